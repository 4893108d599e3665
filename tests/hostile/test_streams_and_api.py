"""The rest of the audit's probes (issue 34, item 8): a SIGTERM while the CSV is written
leaves no temporary file; a closed standard output is a message, not a traceback; a cache
folder that cannot be written falls back; the Python API refuses a number beyond a double,
events and progress that are not functions and a CSV that is no trajectory by field, never
with a raw OverflowError, TypeError or KeyError."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

import lagrangian as lg
from lagrangian.cli.main import TERMINATED, main
from lagrangian.numerics.fast import c_build
from lagrangian.simulation import trajectory

SOURCE = str(Path(lg.__file__).resolve().parents[1])
MODEL = (
    "coordinates: [x]\nparameters: {m: 1, k: 1}\nkinetic: m*x_dot**2/2\npotential: k*x**2/2\n"
    "initial: {x: 0.5, x_dot: 0}\nsimulate: {t_end: 1}\n"
)


def test_sigterm_while_the_csv_is_written_removes_the_temporary_file(tmp_path, monkeypatch):
    model = tmp_path / "model.yaml"
    model.write_text(MODEL)
    (tmp_path / "run.csv").write_text("old\n")
    write = trajectory._write_csv

    def killed_midway(stream, names, data):
        write(stream, names, data[:2])
        stream.flush()
        os.kill(os.getpid(), signal.SIGTERM)  # the handler runs at the next instruction
        write(stream, names, data)

    monkeypatch.setattr(trajectory, "_write_csv", killed_midway)
    handler = signal.getsignal(signal.SIGTERM)
    with pytest.raises(SystemExit) as caught:
        main(["simulate", str(model), "--samples", "11", "--out", str(tmp_path / "run.csv")])
    assert caught.value.code == TERMINATED
    assert signal.getsignal(signal.SIGTERM) is handler  # given back
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.yaml", "run.csv"]
    assert (tmp_path / "run.csv").read_text() == "old\n"


def test_a_closed_standard_output_is_a_message_not_a_traceback():
    done = subprocess.run(
        [sys.executable, "-m", "lagrangian", "derive", "examples/simple_pendulum"],
        preexec_fn=lambda: os.close(1),  # as `>&-`: Python starts with sys.stdout None
        stderr=subprocess.PIPE,
        env={**os.environ, "PYTHONPATH": SOURCE},
        timeout=120,
    )
    error = done.stderr.decode()
    assert done.returncode == 1, error
    assert "standard output is closed" in error and "Traceback" not in error


def test_a_cache_folder_that_cannot_be_written_falls_back(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("")  # a folder below a file cannot be made: as one without permission

    def no_temporary_folder(*args, **kwargs):
        raise FileNotFoundError(2, "No usable temporary directory found")

    monkeypatch.setattr(c_build, "cache_folder", lambda: blocker / "cache")
    monkeypatch.setattr(tempfile, "gettempdir", no_temporary_folder)
    monkeypatch.setattr(tempfile, "mkdtemp", no_temporary_folder)
    c_build.loop_library.cache_clear()
    try:
        assert c_build.loop_library() is None  # the callers then use SciPy's solvers
    finally:
        c_build.loop_library.cache_clear()  # the next test finds the real cache


@pytest.mark.parametrize(
    ("keywords", "words"),
    [
        ({"initial": {"theta": 10**400}}, ["initial['theta']", "401 digits", "beyond a double"]),
        ({"parameters": {"m": -(10**400)}}, ["parameters['m']", "beyond a double"]),
        ({"events": [5]}, ["events[0]", "is not a function"]),
        ({"events": 5}, ["events", "is not a list of functions"]),
        ({"progress": 5}, ["progress", "is not a function"]),
    ],
    ids=["initial 10**400", "parameter -10**400", "events=[5]", "events=5", "progress=5"],
)
def test_the_python_api_refuses_wrong_values_by_field(keywords, words):
    with pytest.raises(lg.SimulationInputError, match="Cannot simulate") as caught:
        lg.simulate(lg.examples.simple_pendulum(), t_span=1.0, **keywords)
    for word in words:
        assert word in str(caught.value), (word, caught.value)


def test_an_event_with_a_wrong_direction_is_refused_by_field():
    def ground(t, q, q_dot):
        return q[0]

    ground.direction = "up"  # type: ignore[attr-defined]
    with pytest.raises(lg.SimulationInputError, match=r"events\[0\]\.direction"):
        lg.simulate(lg.examples.simple_pendulum(), t_span=1.0, events=[ground])


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("garbage", ["header (line 1)", "must start with t"]),
        ("t,x,x_dot,energy\n1,2\n", ["row (line 2)", "2 values, and the header names 4"]),
        ("t,x,x_dot,energy\n0,1,0,1\n1,a,0,1\n", ["x (line 3, column 2)", "'a' is not a number"]),
        ("t,x,x_dot,energy\n1,2,3,4,5\n", ["5 values"]),
        ("t,energy\n0,1\n", ["no coordinate column"]),
        ("t,x,x,x_dot,energy\n", ["named more than once"]),
    ],
    ids=["no header", "short row", "not a number", "long row", "no coordinate", "repeated"],
)
def test_a_csv_that_is_no_trajectory_is_refused_by_line(text, words):
    with pytest.raises(lg.SimulationInputError, match="Not a trajectory CSV") as caught:
        lg.Trajectory.from_csv(io.StringIO(text))
    for word in words:
        assert word in str(caught.value), (word, caught.value)


def test_a_csv_file_that_is_not_utf8_names_the_byte(tmp_path):
    path = tmp_path / "run.csv"
    path.write_bytes(b"t,x,x_dot,energy\n0,1,0,\xff\n")
    with pytest.raises(lg.SimulationInputError, match=r"byte 0xff at position 23") as caught:
        lg.Trajectory.from_csv(path)
    assert "line 2, column 7" in str(caught.value)
