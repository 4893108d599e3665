"""Run the ``lagrangian`` command on hostile input in a child process that the test bounds:
a time after which the child is killed (the test's own timeout, not a speed assertion) and an
address-space limit (RLIMIT_AS), so that a probe that hangs or eats memory fails the test
instead of the machine.

The child is forked from the test process (SymPy and lagrangian already imported, so a probe
costs its own work, not an interpreter start) and calls ``lagrangian.cli.main.main`` with
standard input, output and error on files; where the test process has other threads running
(a fork would copy their locks held), it is a fresh ``python -m lagrangian`` instead.
"""

from __future__ import annotations

import contextlib
import gc
import os
import resource
import signal
import subprocess
import sys
import tempfile
import threading
import time
import traceback
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pytest

# Loaded once here rather than in every forked probe: a probe then costs its own work.
import lagrangian.cli.commands
import lagrangian.numerics.compile
import lagrangian.simulation.run  # noqa: F401

GiB = 1 << 30
#: The memory a probe may use beyond what the process had when it started.
MEMORY = GiB
#: Seconds after which a probe is killed: far beyond what any probe needs.
TIMEOUT = 60.0
#: What a child that raised past ``main`` (a bug in the runner or in main) exits with.
CRASHED = 99


@dataclass(frozen=True)
class Outcome:
    """How a command ended: exit code (None when killed at the timeout), its output, and the
    most memory it had resident (bytes)."""

    code: int | None
    out: str
    err: str
    peak_bytes: int

    @property
    def internal(self) -> bool:
        return "internal error" in self.err or "Traceback" in self.err

    def __str__(self) -> str:
        return f"exit {self.code}; stderr: {self.err[-2000:]!r}"

    def assert_refused(self, *words: str) -> None:
        """Exit 2 (bad input), each of ``words`` (the field, the fix) in the message, and no
        internal error."""
        assert self.code == 2, self
        assert not self.internal, self
        for word in words:
            assert word in self.err, (word, self)


def _virtual_bytes() -> int:
    """The address space this process uses now (VmSize), 0 where /proc is missing."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _limit_memory(extra: int) -> None:
    limit = _virtual_bytes() + extra
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def run_cli(
    argv: Sequence[str],
    stdin: str = "",
    *,
    timeout: float = TIMEOUT,
    memory: int = MEMORY,
    cwd: str | os.PathLike[str] | None = None,
    env: dict[str, str] | None = None,
    fresh: bool = False,
) -> Outcome:
    """Run ``lagrangian ARGV`` with ``stdin``, killed after ``timeout`` seconds, with at most
    ``memory`` more bytes of address space; ``fresh``: in a new interpreter."""
    with tempfile.TemporaryDirectory() as folder:
        files = {name: Path(folder) / name for name in ("in", "out", "err")}
        files["in"].write_text(stdin, encoding="utf-8", errors="surrogatepass")
        files["out"].touch()
        files["err"].touch()
        if fresh or env is not None or threading.active_count() > 1:
            code, peak = _run_fresh(argv, files, timeout, memory, cwd, env)
        else:
            code, peak = _run_forked(argv, files, timeout, memory, cwd)
        read = {k: files[k].read_text(errors="replace") for k in ("out", "err")}
    return Outcome(code, read["out"], read["err"], peak)


def _run_fresh(argv, files, timeout, memory, cwd, env) -> tuple[int | None, int]:
    with (
        open(files["in"], "rb") as given,
        open(files["out"], "wb") as out,
        open(files["err"], "wb") as err,
    ):
        process = subprocess.Popen(
            [sys.executable, "-m", "lagrangian", *argv],
            stdin=given,
            stdout=out,
            stderr=err,
            cwd=cwd,
            env={**os.environ, **(env or {})},
            preexec_fn=lambda: _limit_memory(memory + GiB),  # plus the interpreter's own
        )
        code, peak = _wait(process.pid, timeout)
        process.returncode = -signal.SIGKILL if code is None else code  # reaped above
        return code, peak


def _run_forked(argv, files, timeout, memory, cwd) -> tuple[int | None, int]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # fork with threads: checked above
        pid = os.fork()
    if pid == 0:  # the child: never returns
        code = CRASHED
        # the test process's objects are not the probe's: frozen, the collector does not walk
        # (and copy, page by page) the parent's heap on every collection of the probe
        gc.freeze()
        try:
            _limit_memory(memory)
            if cwd is not None:
                os.chdir(cwd)
            for fd, name, mode in ((0, "in", os.O_RDONLY), (1, "out", os.O_WRONLY)):
                os.dup2(os.open(files[name], mode), fd)
            os.dup2(os.open(files["err"], os.O_WRONLY), 2)
            # the child's own streams, open until os._exit ends it
            sys.stdin = open(0, encoding="utf-8", closefd=False)  # noqa: SIM115
            sys.stdout = open(1, "w", encoding="utf-8", closefd=False)  # noqa: SIM115
            sys.stderr = open(2, "w", encoding="utf-8", closefd=False)  # noqa: SIM115
            from lagrangian.cli.main import main

            try:
                code = main(list(argv))
            except SystemExit as exit:  # argparse: --help, usage errors
                code = exit.code if isinstance(exit.code, int) else 2
        except BaseException:
            traceback.print_exc()
        finally:
            for stream in (sys.stdout, sys.stderr):
                with contextlib.suppress(BaseException):
                    stream.flush()
            os._exit(code)
    return _wait(pid, timeout)


def _wait(pid: int, timeout: float) -> tuple[int | None, int]:
    """Exit code (None if it had to be killed at ``timeout``) and peak resident bytes."""
    deadline = time.monotonic() + timeout
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status), usage.ru_maxrss * 1024
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            _, _, usage = os.wait4(pid, 0)
            return None, usage.ru_maxrss * 1024
        time.sleep(0.02)


@pytest.fixture
def cli(tmp_path):
    """``cli(argv, stdin)``: :func:`run_cli` in a fresh temporary folder."""

    def run(argv: Sequence[str], stdin: str = "", **options) -> Outcome:
        options.setdefault("cwd", tmp_path)
        return run_cli(argv, stdin, **options)

    return run
