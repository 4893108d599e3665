"""The C integration loop (``c_loop.c``), compiled once per machine and kept on disk.

The system C compiler (``cc``, else Python's own ``CC``, ``gcc`` or ``clang``) compiles
``c_loop.c`` beside this file into a shared library, once: the library is kept in the user's
cache folder, ``$XDG_CACHE_HOME/lagrangian`` (``~/.cache/lagrangian``), under a name keyed by
a hash of the C source, the compiler (its path, size and time stamp) and the flags, so an
edited source or another compiler gets a library of its own.  Every later process loads it
with ctypes in a fraction of a millisecond.

- A library is written atomically: compiled to a temporary file in the cache folder, then
  moved onto its name with ``os.replace``; its SHA-256 is kept beside it (``.sha256``), written
  the same way.  A library whose digest does not match (a file cut short, or garbled), that
  does not load or that is of another layout is compiled again.
- Where the cache folder cannot be written, the library goes to a folder of this user's in
  the temporary folder (``lagrangian-<uid>``, private to the user), or, failing that, to a new
  temporary folder of this process (compiled in every process).
- Without a C compiler, or when compiling fails, :func:`loop_library` is None and the callers
  use SciPy's solvers instead (:mod:`lagrangian.simulation.integrators.compiled`).

Compiling takes about a second; loading, under a millisecond (and the check of the digest).
The compiled flights of polynomial motion (``c_flight.c``, :mod:`~lagrangian.numerics.fast.
c_flight`) are built and kept the same way (:func:`compiled_library`), a library of their own.

>>> library = loop_library()
>>> library is None or library.lg_abi() == ABI_VERSION
True
"""

from __future__ import annotations

import contextlib
import ctypes
import hashlib
import os
import platform
import shlex
import shutil
import stat
import subprocess
import sys
import sysconfig
import tempfile
from collections.abc import Iterator
from functools import cache
from pathlib import Path

#: The C source of the loop.
SOURCE = Path(__file__).with_name("c_loop.c")
#: LG_ABI_VERSION of the source: a library answering another number is compiled again.
ABI_VERSION = 3
#: No contraction to fused multiply-adds and no fast math: the loop rounds as SciPy does.
FLAGS = ("-O2", "-shared", "-fPIC", "-ffp-contract=off", "-fno-fast-math")
#: Seconds a compilation may take.
COMPILE_TIMEOUT = 300.0


def find_compiler() -> str | None:
    """The path of the system C compiler, or None: ``cc``, else the compiler Python was built
    with (sysconfig's ``CC``), else ``gcc`` or ``clang``."""
    configured = sysconfig.get_config_var("CC") or ""
    words = shlex.split(configured) if configured else []
    for name in ("cc", *words[:1], "gcc", "clang"):
        found = shutil.which(name)
        if found:
            return found
    return None


def cache_folder() -> Path | None:
    """The user's cache folder of lagrangian: ``$XDG_CACHE_HOME/lagrangian``, by default
    ``~/.cache/lagrangian``; None without a home folder (a relative XDG_CACHE_HOME is
    ignored, as the XDG specification says)."""
    base = os.environ.get("XDG_CACHE_HOME", "")
    if not os.path.isabs(base):
        home = os.path.expanduser("~")
        if not os.path.isabs(home):
            return None
        base = os.path.join(home, ".cache")
    return Path(base) / "lagrangian"


def library_name(compiler: str, source: Path = SOURCE) -> str:
    """The file name of the library of ``source`` for this compiler and platform."""
    status = os.stat(compiler)
    key = hashlib.sha256()
    for part in (
        source.read_bytes(),
        os.path.realpath(compiler).encode(),
        f"{status.st_size} {status.st_mtime_ns}".encode(),
        " ".join(FLAGS).encode(),
        f"{sys.platform} {platform.machine()} {ctypes.sizeof(ctypes.c_void_p)}".encode(),
    ):
        key.update(part)
        key.update(b"\0")
    suffix = ".dll" if sys.platform == "win32" else ".so"
    return f"{source.stem}-{key.hexdigest()[:20]}{suffix}"


@cache
def loop_library() -> ctypes.CDLL | None:
    """The loaded library of ``c_loop.c`` (module docstring), compiled on the first call on
    this machine; None without a C compiler or when it cannot be built."""
    return compiled_library(SOURCE, "lg_abi", ABI_VERSION)


def compiled_library(source: Path, abi: str, version: int) -> ctypes.CDLL | None:
    """The loaded library of the C ``source`` beside this file, compiled on the first call
    on this machine and kept as ``c_loop.c``'s is (module docstring); its function ``abi``
    must answer ``version``.  None without a C compiler or when it cannot be built."""
    compiler = find_compiler()
    if compiler is None:
        return None
    try:
        name = library_name(compiler, source)
    except OSError:
        return None
    for folder in _folders():
        path = folder / name
        library = _open(path, abi, version)
        if library is not None:
            return library
        try:
            if not _build(compiler, path, source):
                return None  # the compiler fails: it would fail in every folder
        except OSError:  # the folder cannot be written: the next one
            continue
        library = _open(path, abi, version)
        if library is not None:  # else a folder that cannot run code (noexec): the next one
            return library
    return None


def _folders() -> Iterator[Path]:
    """Where a library may be kept: the user's cache folder, then a private folder in the
    temporary folder, then a new temporary folder of this process (made only when reached)."""
    user = cache_folder()
    if user is not None:
        yield user
    private = _private_temporary()
    if private is not None:
        yield private
    try:
        temporary = tempfile.mkdtemp(prefix="lagrangian-")
    except OSError:
        return
    yield Path(temporary)


def _private_temporary() -> Path | None:
    """``<temp>/lagrangian-<uid>``, made for this user alone; None where it is not (another
    user's, a link, open to others) or where there are no user ids."""
    getuid = getattr(os, "getuid", None)
    if getuid is None:
        return None
    try:  # gettempdir raises when no temporary folder is writable
        folder = Path(tempfile.gettempdir()) / f"lagrangian-{getuid()}"
        folder.mkdir(mode=0o700, exist_ok=True)
        status = os.lstat(folder)
    except OSError:
        return None
    private = stat.S_ISDIR(status.st_mode) and status.st_uid == getuid()
    return folder if private and not status.st_mode & 0o077 else None


def _open(path: Path, abi: str, version: int) -> ctypes.CDLL | None:
    """The library at ``path`` when it is whole (its digest matches) and its function
    ``abi`` answers ``version`` (this layout); None otherwise."""
    try:
        expected = path.with_name(path.name + ".sha256").read_text().strip()
        content = path.read_bytes()
    except OSError:
        return None
    if hashlib.sha256(content).hexdigest() != expected:
        return None
    try:
        library = ctypes.CDLL(str(path))
        answer = getattr(library, abi)
        answer.restype = ctypes.c_int64
        if answer() != version:
            return None
    except (OSError, AttributeError):
        return None
    return library


def _build(compiler: str, path: Path, source: Path) -> bool:
    """Compile ``source`` into ``path`` atomically, with its digest beside it; False when
    the compiler fails, OSError when the folder cannot be written."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    os.close(handle)
    try:
        command = [compiler, *FLAGS, "-o", temporary, str(source), "-lm"]
        try:
            done = subprocess.run(command, capture_output=True, timeout=COMPILE_TIMEOUT)
        except (OSError, subprocess.SubprocessError):
            return False
        if done.returncode != 0:
            return False
        digest = hashlib.sha256(Path(temporary).read_bytes()).hexdigest()
        os.replace(temporary, path)
        write_atomically(path.with_name(path.name + ".sha256"), (digest + "\n").encode())
        return True
    finally:
        with contextlib.suppress(OSError):
            os.unlink(temporary)


def write_atomically(path: Path, content: bytes) -> None:
    """``content`` into ``path`` whole or not at all: a temporary file of the same folder,
    moved onto the name (a reader sees the old file or the new one, never half of one)."""
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".", suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(content)
        os.replace(temporary, path)
    finally:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
