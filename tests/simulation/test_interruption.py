"""A run stopped by Ctrl-C (KeyboardInterrupt) keeps what it computed, on every path; output
files are replaced atomically, never left half written."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.simulation.files import written_atomically
from lagrangian.simulation.outcome import SimulationInterrupted

STOP_AT = 0.5


def ctrl_c_after(time: float):
    """A progress callback that raises KeyboardInterrupt once the run passes ``time``, as
    Ctrl-C would."""

    def progress(t: float) -> None:
        if t > time:
            raise KeyboardInterrupt

    return progress


def cartesian_pendulum(*extra: lg.Constraint) -> lg.System:
    x, y, l = sp.symbols("x y l")
    return lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        particles=[lg.Particle("bob", 1, (x, y))],
        gravity=(0, -9.81),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2), *extra],
    )


ON_THE_CIRCLE = {"x": 0.6, "y": -0.8, "x_dot": 0.0, "y_dot": 0.0}
SPRING = {"x": 0.1, "x_dot": 0.0}


def _floor() -> lg.System:
    y = sp.Symbol("y")
    return cartesian_pendulum(lg.Unilateral(y + 2.0, name="floor"))


PATHS = {
    "free": (lg.examples.mass_on_spring, SPRING, {}),
    "free, every step": (lg.examples.mass_on_spring, SPRING, {"samples": None}),
    "RK4": (lg.examples.mass_on_spring, SPRING, {"method": "RK4", "dt": 0.001}),
    "multiplier form": (cartesian_pendulum, ON_THE_CIRCLE, {"baumgarte": (5.0, 5.0)}),
    "active sets": (_floor, ON_THE_CIRCLE, {}),
    "variational": (lg.examples.mass_on_spring, SPRING, {"method": "variational", "dt": 1e-3}),
}


@pytest.mark.parametrize("path", list(PATHS))
def test_an_interrupted_run_keeps_the_rows_computed_before(path: str) -> None:
    build, start, options = PATHS[path]
    options = {"samples": 201, **options}
    if options["samples"] is None:
        del options["samples"]
    run = lg.simulate(
        build(), start, 2.0, progress=ctrl_c_after(STOP_AT), raise_on_failure=False, **options
    )
    assert run.status == "interrupted" and not run.success
    assert run.message.startswith("Interrupted (Ctrl-C) at t = ")
    assert run.t[-1] == pytest.approx(STOP_AT, abs=0.05)
    assert np.all(np.isfinite(run.q)) and np.all(np.isfinite(run.energy))
    whole = lg.simulate(build(), start, 2.0, **options)
    np.testing.assert_allclose(run.q, whole.q[: len(run.t)], rtol=1e-12, atol=1e-12)


def test_raising_on_failure_an_interruption_is_still_a_keyboard_interrupt() -> None:
    with pytest.raises(KeyboardInterrupt) as caught:
        lg.simulate(
            lg.examples.mass_on_spring(), SPRING, 2.0, samples=21, progress=ctrl_c_after(STOP_AT)
        )
    error = caught.value
    assert isinstance(error, SimulationInterrupted) and not isinstance(error, Exception)
    assert error.trajectory.status == "interrupted" and len(error.trajectory.t) > 1
    assert "Interrupted (Ctrl-C)" in str(error)


def test_an_event_function_interrupted_keeps_the_rows_too() -> None:
    def watched(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        if t > STOP_AT:
            raise KeyboardInterrupt
        return 1.0

    run = lg.simulate(
        lg.examples.mass_on_spring(),
        SPRING,
        2.0,
        samples=21,
        events=[watched],
        raise_on_failure=False,
    )
    assert run.status == "interrupted" and run.t[-1] <= STOP_AT + 0.1


def test_an_atomic_write_that_fails_leaves_the_old_file(tmp_path: Path) -> None:
    target = tmp_path / "run.csv"
    target.write_text("old\n")
    with pytest.raises(RuntimeError, match="disk full"), written_atomically(target) as temporary:
        temporary.write_text("half a fi")
        raise RuntimeError("disk full")
    assert target.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["run.csv"]
    with written_atomically(target) as temporary:
        assert temporary.parent == tmp_path and temporary.suffix == ".csv"
        temporary.write_text("new\n")
    assert target.read_text() == "new\n" and [p.name for p in tmp_path.iterdir()] == ["run.csv"]


def test_to_csv_writes_atomically_and_names_a_missing_folder(tmp_path: Path) -> None:
    run = lg.simulate(lg.examples.mass_on_spring(), SPRING, 1.0, samples=5)
    run.to_csv(tmp_path / "run.csv")
    assert [p.name for p in tmp_path.iterdir()] == ["run.csv"]
    missing = tmp_path / "nowhere" / "run.csv"
    with pytest.raises(FileNotFoundError) as caught:
        run.to_csv(missing)
    assert caught.value.filename == str(missing)
