"""``lagrangian sweep``: bad flags exit 2 naming the flag, each fix in the sweep's own flags
(the Python API keeps its keywords); a sweep killed midway (the whole client, or one worker)
resumes or completes with every member present."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import zarr

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.cli.sweep_command import SWEEP
from lagrangian.errors import Setting, SimulationInputError
from lagrangian.sweeps import sweep


@pytest.mark.parametrize(
    ("flags", "named"),
    [
        (["--vary", "kk=1,2"], r"--vary kk=1,2: 'kk' is not a name"),
        (["--vary", "theta=0:1"], r"--vary theta=0:1: expected NAME=START:STOP:COUNT"),
        (["--vary", "theta=0:1:0"], r"--vary theta=0:1:0"),
        (["--random", "l=2:1:5"], r"--random l=2:1:5: expected NAME=LOW:HIGH:N"),
        (["--vary", "theta=0,1", "--stop-when", "theta + zz"], r"--stop-when: unknown \['zz'\]"),
        (["--vary", "theta=0,1", "--method", "nope"], r"--method: unknown method"),
        (["--vary", "theta=0,1", "--t-end", "-1"], r"--t-end: the end time"),
        (["--vary", "theta=0,1", "--chunk-size", "0"], r"--chunk-size: 0 is not a whole number"),
    ],
)
def test_bad_flags_exit_2_naming_the_flag(flags, named, tmp_path: Path, capsys) -> None:
    out = tmp_path / "r.zarr"
    code = main(["sweep", "examples/simple_pendulum", *flags, "--out", str(out)])
    assert code == 2
    assert __import__("re").search(named, capsys.readouterr().err)
    assert not out.exists()


#: A Python keyword given a value (``project_initial=True``, ``method='RK4'``, ``dt=...``,
#: ``vary={...}``): the command line never says one.
PYTHON_KEYWORD = re.compile(r"\b[a-z_]+=(True|False|'|\.\.\.|\{)")


@pytest.mark.parametrize(
    ("model", "flags", "line"),
    [
        (
            "cylinder_on_incline",
            ["--vary", "x=0.1,0.2"],
            "--set: the initial state violates the constraints: the largest residual is 0.1 "
            "(> 1e-09) — move it onto them: pass --project-initial",
        ),
        (
            "cylinder_on_incline",
            ["--vary", "alpha=0.1", "--method", "variational", "--dt", "0.1", "--stop-when", "x"],
            "--stop-when: the method 'variational' does not locate events yet — use another "
            "--method with --stop-when",
        ),
        (
            "cylinder_on_incline",
            ["--vary", "alpha=0.1", "--method", "gauss4", "--dt", "0.1", "--backend", "numba"],
            "the backend 'numba' is another name of the default backend — remove --backend numba",
        ),
        (
            "simple_pendulum",
            ["--vary", "l=1,2", "--method", "RK4"],
            "--dt: the fixed-step method RK4 needs a step — pass --dt or --samples",
        ),
        (
            "simple_pendulum",
            ["--vary", "l=1,2", "--method", "RK4", "--dt", "1e-9"],
            "--dt: a step of 1e-09 needs 1e+10 steps over the time span, more than the step "
            "budget of 1,000,000 — use a larger --dt, a shorter time span, or pass --max-steps",
        ),
        (
            "simple_pendulum",
            ["--vary", "l=1,2", "--method", "RK4", "--rtol", "1e-6", "--dt", "0.1"],
            "— remove --rtol, or choose an adaptive method such as --method DOP853",
        ),
        (
            "simple_pendulum",
            ["--vary", "l=1,2", "--project-initial"],
            "--project-initial: project_initial moves states onto the constraints, and this "
            "system has none — remove --project-initial",
        ),
        (
            "simple_pendulum",
            [],
            "--vary: nothing to sweep over — give --vary NAME=START:STOP:COUNT or "
            "--random NAME=LOW:HIGH:N",
        ),
    ],
)
def test_messages_say_flags_not_keywords(model, flags, line, tmp_path: Path, capsys) -> None:
    out = tmp_path / "r.zarr"
    assert main(["sweep", f"examples/{model}", *flags, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert line in err, err
    assert not PYTHON_KEYWORD.search(err), err
    assert not out.exists()


def test_a_bad_worker_count_names_the_flag_in_its_fix(tmp_path: Path, capsys) -> None:
    flags = ["--vary", "theta=0,1", "--workers", "0", "--out", str(tmp_path / "r.zarr")]
    assert main(["sweep", "examples/simple_pendulum", *flags]) == 2
    assert "--workers: 0 is not a positive whole number — give --workers >= 1" in (
        capsys.readouterr().err
    )


@pytest.mark.parametrize(
    ("model", "vary", "keywords", "line"),
    [
        (
            "cylinder_on_incline",
            {"x": [0.1, 0.2]},
            {},
            "initial: the initial state violates the constraints: the largest residual is 0.1 "
            "(> 1e-09) — move it onto them: pass project_initial=True",
        ),
        (
            "cylinder_on_incline",
            {"alpha": [0.1]},
            {"method": "variational", "dt": 0.1, "stop_when": "x"},
            "stop_when: the method 'variational' does not locate events yet — use another "
            "method with stop_when",
        ),
        (
            "simple_pendulum",
            {"l": [1.0, 2.0]},
            {"project_initial": True},
            "project_initial: project_initial moves states onto the constraints, and this "
            "system has none — remove project_initial=True",
        ),
        (
            "simple_pendulum",
            {},
            {},
            "vary: nothing to sweep over — give vary={'NAME': ...} or random={'NAME': ...}",
        ),
    ],
)
def test_the_python_api_keeps_its_keywords(model, vary, keywords, line, tmp_path: Path) -> None:
    system = lg.examples.get(model)()
    with pytest.raises(SimulationInputError) as caught:
        sweep(system, vary, 1.0, out=tmp_path / "r.zarr", **keywords)
    assert line in str(caught.value)
    assert "--" not in str(caught.value).replace(" — ", " ")


def test_the_sweeps_wording_is_its_own_flags() -> None:
    # the flags are read from the sweep's parser: --max-steps is one, --max-wall-time not
    assert SWEEP.setting(Setting("max_steps", 10)) == "--max-steps 10"
    assert SWEEP.setting(Setting("max_wall_time")) == "max_wall_time"
    assert SWEEP.setting(Setting("initial", entry="theta")) == "--set theta=VALUE"
    assert SWEEP.setting(Setting("vary", entry="l")) == "--vary l=START:STOP:COUNT"
    assert SWEEP.setting(Setting("resume", True)) == "--resume"
    assert SWEEP.option("t_span") == "--t-end" and SWEEP.option("stop_when") == "--stop-when"


def test_a_constrained_sweep_from_the_command_line(cluster, tmp_path: Path) -> None:
    # a solid cylinder rolling down a slope: x = g sin(alpha) t^2 / 3 and the friction
    # multiplier lambda = -m g sin(alpha) / 3 (the model's comment)
    out = tmp_path / "incline.zarr"
    flags = ["--vary", "alpha=0.2,0.4", "--t-end", "1", "--samples", "3", "--method", "DOP853"]
    flags += ["--stop-when", "0.8 - x", "--scheduler", cluster.scheduler_address]
    assert main(["sweep", "examples/cylinder_on_incline", *flags, "--out", str(out)]) == 0
    data = xr.open_zarr(out)
    alpha = data["alpha"].values
    expected = np.broadcast_to(-9.81 * np.sin(alpha)[:, None] / 3, (2, 3))
    finite = np.isfinite(data["lambda_1"].values)
    np.testing.assert_allclose(data["lambda_1"].values[finite], expected[finite], atol=1e-8)
    stop = np.sqrt(2.4 / (9.81 * np.sin(alpha)))  # x = 0.8 at 1.11 (after t_end) and 0.79
    np.testing.assert_allclose(data["stop_time"], [np.nan, stop[1]], rtol=1e-7)
    assert list(data["status"].values) == ["success", "stopped"]


def test_an_existing_out_needs_resume(tmp_path: Path, capsys) -> None:
    out = tmp_path / "r.zarr"
    out.mkdir()
    assert main(["sweep", "examples/simple_pendulum", "--vary", "theta=0,1", "--out", str(out)])
    err = capsys.readouterr().err
    assert f"--out: {out} already exists — pass --resume to continue it, or choose" in err, err
    with pytest.raises(SimulationInputError, match=r"pass resume=True to continue it"):
        sweep(lg.examples.simple_pendulum(), {"theta": [0.0, 1.0]}, 1.0, out=out)


COMMAND = [
    sys.executable,
    "-m",
    "lagrangian",
    "sweep",
    "examples/double_pendulum",
    "--vary",
    "theta=0.5:2.5:12",
    "--vary",
    "phi=0,1",
    "--t-end",
    "20",
    "--samples",
    "5",
    "--method",
    "DOP853",
    "--rtol",
    "1e-10",
    "--atol",
    "1e-10",
    "--chunk-size",
    "2",
    "--workers",
    "1",
]


def _done(out: Path) -> int:
    try:
        return int(np.sum(zarr.open_group(str(out), mode="r")["done"][...]))
    except Exception:  # not laid out yet, or a chunk being written
        return 0


@pytest.mark.slow
def test_a_sweep_killed_midway_resumes_with_every_member(tmp_path: Path) -> None:
    out, clean = tmp_path / "killed.zarr", tmp_path / "clean.zarr"
    # the client, its scheduler and its workers share a session: SIGKILL them all at once
    process = subprocess.Popen(
        [*COMMAND, "--out", str(out)], start_new_session=True, stderr=subprocess.DEVNULL
    )
    try:
        deadline = time.monotonic() + 120
        while _done(out) < 4 and process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
    finally:
        os.killpg(process.pid, signal.SIGKILL)
        process.wait()
    written = _done(out)
    assert 4 <= written < 24, "the sweep was to be killed midway"
    subprocess.run([*COMMAND, "--out", str(out), "--resume"], check=True, capture_output=True)
    subprocess.run([*COMMAND, "--out", str(clean)], check=True, capture_output=True)
    resumed, reference = xr.open_zarr(out).load(), xr.open_zarr(clean).load()
    assert bool(resumed["done"].all()) and set(resumed["status"].values.ravel()) == {"success"}
    xr.testing.assert_identical(resumed, reference)


@pytest.mark.slow
def test_a_worker_killed_midway_is_replaced_and_the_sweep_completes(
    cluster, tmp_path: Path
) -> None:
    from dask.distributed import Client

    out = tmp_path / "worker.zarr"
    system = lg.examples.double_pendulum()
    vary = {"theta": np.linspace(0.5, 2.5, 16), "phi": [0.0, 1.0]}
    options = {"samples": 3, "method": "DOP853", "rtol": 1e-10, "atol": 1e-10}
    found: dict[str, object] = {}

    def run() -> None:
        found["report"] = sweep(
            system,
            vary,
            20.0,
            out=out,
            chunk_size=2,
            scheduler=cluster.scheduler_address,
            **options,
        )

    thread = threading.Thread(target=run)
    thread.start()
    deadline = time.monotonic() + 120
    while _done(out) < 2 and thread.is_alive() and time.monotonic() < deadline:
        time.sleep(0.02)
    with Client(cluster.scheduler_address) as client:
        # The worker holding the System: losing it must not lose the sweep (scattered
        # data could not be recovered; a task's result is computed again).
        holders = [w for key, w in client.who_has().items() if "sweep-model" in str(key)]
        assert holders, "the System is not held by a worker"
        address = next(iter(holders[0]))
        victim = client.run(os.getpid, workers=[address])[address]
    os.kill(victim, signal.SIGKILL)
    thread.join(timeout=300)
    report = found["report"]
    assert report.status == {"success": 32}  # type: ignore[attr-defined]
    data = xr.open_zarr(out)
    alone = lg.simulate(system, {"theta": 0.5, "phi": 1.0}, 20.0, **options)
    np.testing.assert_allclose(data["theta"][0, -1], alone.q[:, 0], rtol=0, atol=1e-8)


def test_a_missing_numba_names_the_backend_in_each_interface(monkeypatch) -> None:
    from lagrangian.numerics.fast import compiled_rates

    monkeypatch.setattr(compiled_rates, "numba_available", lambda: False)
    with pytest.raises(lg.SimulationError) as caught:
        compiled_rates.require_numba()
    assert str(caught.value).endswith("or use backend='numpy' (the default)")
    assert str(caught.value.worded(SWEEP)).startswith("--backend: the compiled variational")
    assert str(caught.value.worded(SWEEP)).endswith("or use --backend numpy (the default)")
