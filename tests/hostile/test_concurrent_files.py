"""Processes running at once never leave a file half-written or mixed: four writers of one
output file leave exactly one writer's whole content; four commands writing one CSV leave
one whole run; four processes building the same on-disk cache (the C loop's library, numba's
compiled loops) from nothing all succeed and leave one whole cache.  Each process is killed
past the test's own timeout."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

TIMEOUT = 300
WRITERS = 4

# Each writer waits for the gate file, so that all write at the same moment.
WRITER = textwrap.dedent(
    """
    import os, sys, time
    from lagrangian.simulation.files import written_atomically
    target, gate, mark = sys.argv[1], sys.argv[2], sys.argv[3]
    while not os.path.exists(gate):
        time.sleep(0.001)
    with written_atomically(target) as temporary, open(temporary, "w") as stream:
        for _ in range(2000):  # 2 MB in small pieces, flushed: the writes overlap
            stream.write(mark * 1000 + "\\n")
            stream.flush()
    """
)


def start_together(commands: list[list[str]], gate: Path, **options) -> list[subprocess.Popen]:
    processes = [
        subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **options)
        for command in commands
    ]
    time.sleep(0.5)  # let each interpreter start and reach the gate
    gate.touch()
    return processes


def finish(processes: list[subprocess.Popen]) -> list[tuple[int, str, str]]:
    results = []
    for process in processes:
        try:
            out, err = process.communicate(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            out, err = process.communicate()
        results.append((process.returncode, out.decode(), err.decode()))
    return results


def test_writers_of_one_file_leave_one_whole_content(tmp_path):
    target = tmp_path / "out.csv"
    target.write_text("old\n")
    marks = "ABCD"
    commands = [
        [sys.executable, "-c", WRITER, str(target), str(tmp_path / "go"), mark] for mark in marks
    ]
    results = finish(start_together(commands, tmp_path / "go"))
    assert [code for code, _, _ in results] == [0] * WRITERS, results
    text = target.read_text()
    assert any(text == (mark * 1000 + "\n") * 2000 for mark in marks)  # one writer's, whole
    assert sorted(p.name for p in tmp_path.iterdir()) == ["go", "out.csv"]  # no temporaries


def test_a_writer_that_fails_leaves_the_old_file(tmp_path):
    from lagrangian.simulation.files import written_atomically

    target = tmp_path / "out.csv"
    target.write_text("old\n")
    with pytest.raises(KeyboardInterrupt), written_atomically(target) as temporary:
        temporary.write_text("half")
        raise KeyboardInterrupt  # Ctrl-C in the middle
    assert target.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]


def test_a_target_with_a_very_long_name_still_gets_its_temporary(tmp_path):
    from lagrangian.simulation.files import written_atomically

    target = tmp_path / ("n" * 240 + ".csv")  # 244 characters: the limit is 255
    with written_atomically(target) as temporary:
        temporary.write_text("t\n0\n")
    assert target.read_text() == "t\n0\n"


MODEL = (
    "coordinates: [x]\nparameters: {m: 1, k: 1}\nkinetic: m*x_dot**2/2\npotential: k*x**2/2\n"
    "initial: {x: 0.5, x_dot: 0}\nsimulate: {t_end: 5}\n"
)


def simulate_commands(folder: Path, out: Path, method: str) -> list[list[str]]:
    model = folder / "model.yaml"
    model.write_text(MODEL)
    gate = folder / "go"
    # the command starts only once the gate exists (the interpreter's start is not the test)
    wait = f"import os,time\nwhile not os.path.exists({str(gate)!r}): time.sleep(0.001)\n"
    run = "from lagrangian.cli.main import main; raise SystemExit(main())"
    return [
        [
            sys.executable,
            "-c",
            wait + "import sys; sys.argv[0] = 'lagrangian'\n" + run,
            "simulate",
            str(model),
            "--set",
            f"x={0.1 * (i + 1):.1f}",
            "--samples",
            "2001",
            "--method",
            method,
            *(["--dt", "0.0025"] if method == "variational" else []),
            "--out",
            str(out),
        ]
        for i in range(WRITERS)
    ]


def whole_runs(out: Path) -> None:
    """``out`` is one whole run: its header, 2001 rows of equal length, one start value."""
    rows = out.read_text().splitlines()
    assert rows[0].split(",")[:3] == ["t", "x", "x_dot"]
    assert len(rows) == 2002
    assert {len(row.split(",")) for row in rows} == {len(rows[0].split(","))}
    assert float(rows[1].split(",")[1]) in (0.1, 0.2, 0.3, 0.4)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["RK45", "variational"])
def test_four_commands_building_the_caches_and_writing_one_csv_at_once(tmp_path, method):
    # From empty caches: the C loop's library (XDG_CACHE_HOME) for RK45, numba's compiled
    # loops (NUMBA_CACHE_DIR) for the variational integrator; all four build them at the same
    # moment.
    cache = tmp_path / "cache"
    cache.mkdir()
    env = {**os.environ, "XDG_CACHE_HOME": str(cache), "NUMBA_CACHE_DIR": str(cache / "numba")}
    out = tmp_path / "trajectory.csv"
    commands = simulate_commands(tmp_path, out, method)
    results = finish(start_together(commands, tmp_path / "go", env=env))
    assert [code for code, _, _ in results] == [0] * WRITERS, results
    whole_runs(out)
    leftovers = [p for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert leftovers == []
    built = [p for p in cache.rglob("*") if p.is_file()]
    assert built, "nothing was cached"
    assert not [p for p in built if ".tmp" in p.name or p.name.startswith(".")], built
    # a fifth run finds the cache whole and uses it
    again = subprocess.run(commands[0], env=env, capture_output=True, timeout=TIMEOUT)
    assert again.returncode == 0, again.stderr.decode()
