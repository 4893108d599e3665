"""The on-disk cache of numba's variational marches: a cache file cut short (a full disk, a
killed process) is rebuilt, never a failure of every later run; an unwritable cache folder
falls back to compiling in the process."""

import os
import subprocess
import sys

import pytest

pytest.importorskip("numba")

RUN = (
    "import lagrangian as lg; "
    "t = lg.simulate(lg.examples.simple_pendulum(), {'theta': 0.1}, 1.0, "
    "method='variational', dt=0.01); print(t.success)"
)


def _simulate(cache: str) -> subprocess.CompletedProcess[str]:
    environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
    return subprocess.run(
        [sys.executable, "-c", RUN], capture_output=True, text=True, env=environment, timeout=600
    )


@pytest.mark.slow
def test_a_truncated_cache_file_is_rebuilt(tmp_path):
    first = _simulate(str(tmp_path))
    assert first.returncode == 0 and first.stdout.strip() == "True", first.stderr
    files = [p for p in tmp_path.rglob("*") if p.suffix in (".nbi", ".nbc")]
    assert files
    for path in files:
        path.write_bytes(path.read_bytes()[: len(path.read_bytes()) // 3])
    second = _simulate(str(tmp_path))
    assert second.returncode == 0 and second.stdout.strip() == "True", second.stderr
    third = _simulate(str(tmp_path))  # and the rebuilt cache is whole again
    assert third.returncode == 0 and third.stdout.strip() == "True", third.stderr


@pytest.mark.slow
def test_an_unwritable_cache_folder_still_runs(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")  # no folder can be made below a file, even by root
    result = _simulate(str(blocker / "cache"))
    assert result.returncode == 0 and result.stdout.strip() == "True", result.stderr
