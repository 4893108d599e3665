"""Unilateral constraints: a particle sliding from the top of a smooth circle (vertical
plane) leaves it at cos(theta) = 2/3 (energy: v^2 = 2 g R (1 - cos), normal force
m g cos - m v^2 / R = 0), then flies on a free parabola."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationError
from lagrangian.simulation.trajectory import Trajectory

R, G, M, TH0 = 1.0, 9.81, 1.0, 1e-4
TIGHT = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}


def on_circle(expression_sign: int = 1) -> lg.System:
    x, y, m, g, r = sp.symbols("x y m g r")
    return lg.System(
        coordinates=[x, y],
        parameters={m: M, g: G, r: R},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Unilateral(expression_sign * (x**2 + y**2 - r**2), name="dome")],
    )


@pytest.fixture(scope="module")
def run() -> Trajectory:
    top = {"x": R * np.sin(TH0), "y": R * np.cos(TH0), "x_dot": 0.0, "y_dot": 0.0}
    return lg.simulate(on_circle(), top, 4.0, samples=401, **TIGHT)


def test_the_particle_leaves_the_circle_at_two_thirds_of_the_radius(run: Trajectory) -> None:
    assert run.success, run.message
    releases = [e for e in run.events if e.name == "release dome"]
    assert len(releases) == 1
    state = releases[0].state
    assert abs(state["y"] / R - 2 / 3) < 2e-3
    assert abs(np.hypot(state["x"], state["y"]) - R) < 1e-8
    before = run.t <= releases[0].t  # the release row itself has lambda = 0
    # the multiplier pushes (>= 0) while in contact, NaN once released
    assert np.all(run["lambda_1"][before] >= -1e-9)
    assert np.all(np.isnan(run["lambda_1"][~before]))


def test_after_the_release_the_motion_is_a_free_parabola(run: Trajectory) -> None:
    drift = run.drift()["energy_absolute"]
    assert drift is not None and drift < 1e-8
    t_release = run.events[0].t
    after = run.t > t_release + 0.05
    assert after.sum() > 10
    assert np.all(run["x"][after] ** 2 + run["y"][after] ** 2 > R**2)
    t, y_dot, x_dot = run.t[after], run["y_dot"][after], run["x_dot"][after]
    assert np.allclose(np.gradient(y_dot, t), -G, atol=1e-6)
    assert np.allclose(x_dot, x_dot[0], atol=1e-9)
    assert np.allclose(y_dot, y_dot[0] - G * (t - t[0]), atol=1e-8)


def test_a_re_contact_without_restitution_stops_the_run_at_the_impact() -> None:
    # inside a circular bowl, released from the side at rest above the bottom: the constraint
    # (x^2 + y^2 - R^2 <= 0) is inactive until the bead reaches the wall; with no coefficient
    # of restitution the impact cannot be resolved (tests/simulation/test_impacts.py has them)
    start = {"x": 0.5, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
    failed = lg.simulate(on_circle(-1), start, 2.0, raise_on_failure=False, **TIGHT)
    assert failed.status == "failed" and "no coefficient of restitution" in failed.message
    assert np.all(np.isnan(failed["lambda_1"]))
    with pytest.raises(SimulationError, match="an impact, and it has no coefficient"):
        lg.simulate(on_circle(-1), start, 2.0, **TIGHT)
