"""RK4 in the C loop (numerics/fast/c_loop.c): the order 4 of the classical method on a closed
form, the steps and Hermite dense output of the Python loop over
:class:`lagrangian.simulation.integrators.rk4.RK4` (the C loop switched off), its events, and
a batch whose members are each ``simulate`` alone."""

from __future__ import annotations

import numpy as np
import pytest
from c_loop_setup import scipy_path

import lagrangian as lg
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.settings import Settings
from lagrangian.simulation.integrators.compiled import NativeIntegrator
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler")

SPRING = {"x": 0.1, "x_dot": 0.0}
DOUBLE_START = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}


def spring_exact(t: np.ndarray, m: float = 1.0, k: float = 10.0) -> np.ndarray:
    """x(t) = x0 cos(sqrt(k/m) t) for m x_ddot = -k x released at rest."""
    return 0.1 * np.cos(np.sqrt(k / m) * t)


def test_rk4_runs_in_the_c_loop() -> None:
    setup = prepare(lg.examples.mass_on_spring(), SPRING, 1.0, {"method": "RK4", "dt": 0.1})
    _, integrator = plan(setup)
    assert isinstance(integrator, NativeIntegrator)


def test_rk4_in_the_c_loop_converges_with_order_four() -> None:
    errors = []
    for dt in (0.04, 0.02, 0.01):
        run = lg.simulate(lg.examples.mass_on_spring(), SPRING, 4.0, method="RK4", dt=dt)
        errors.append(np.max(np.abs(run["x"] - spring_exact(run.t))))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 4) < 0.15), orders


def test_the_output_between_steps_is_the_hermite_interpolant_of_order_four() -> None:
    # samples between the steps (dt = 0.03 does not divide 0.1): the cubic Hermite
    # interpolant's error O(h^4) keeps the order of the method
    errors = []
    for dt in (0.03, 0.015):
        run = lg.simulate(
            lg.examples.mass_on_spring(), SPRING, 4.0, method="RK4", dt=dt, samples=41
        )
        errors.append(np.max(np.abs(run["x"] - spring_exact(run.t))))
    assert 3.5 < np.log2(errors[0] / errors[1]) < 4.5, errors


@pytest.mark.parametrize("samples", [None, 37])
def test_rk4_takes_the_python_loops_steps(samples: int | None) -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    options = {"method": "RK4", "dt": 0.01, "samples": samples}
    native = lg.simulate(eom, DOUBLE_START, 3.0, **options)
    python = scipy_path(eom, DOUBLE_START, 3.0, **options)
    np.testing.assert_array_equal(native.t, python.t)  # steps land on t0 + i h exactly
    np.testing.assert_allclose(native.q, python.q, rtol=0, atol=1e-13)
    np.testing.assert_allclose(native.q_dot, python.q_dot, rtol=0, atol=1e-12)


def test_the_last_step_lands_on_the_end_of_the_span() -> None:
    fast = c_loop.native_equations(lg.derive(lg.examples.simple_pendulum()))
    assert fast is not None
    settings = Settings("RK4", (0.0, 1.0), np.zeros(0), dt=0.3)  # 4 steps of 0.25
    run = c_loop.integrate(fast, settings, np.array([0.1, 0.0]), np.array([1.0, 9.81, 1.0]))
    np.testing.assert_array_equal(run.t, [0.0, 0.25, 0.5, 0.75, 1.0])
    assert run.steps == 4


def test_rk4_events_are_located_as_the_python_loop_locates_them() -> None:
    eom = lg.derive(lg.examples.double_pendulum())

    def crossing(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return q[0]

    options = {"method": "RK4", "dt": 0.01, "events": [crossing]}
    native = lg.simulate(eom, DOUBLE_START, 5.0, **options)
    python = scipy_path(eom, DOUBLE_START, 5.0, **options)
    assert len(native.events) == len(python.events) > 1
    for ours, theirs in zip(native.events, python.events):
        assert ours.t == pytest.approx(theirs.t, abs=1e-12)


def test_an_rk4_batch_is_each_member_alone() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    angles = [0.3, 1.0, 2.0]
    batch = lg.simulate_batch(
        eom, {**DOUBLE_START, "theta": angles}, 2.0, method="RK4", dt=0.01, samples=11
    )
    assert batch.status == ("success",) * 3
    for i, angle in enumerate(angles):
        alone = scipy_path(eom, {**DOUBLE_START, "theta": angle}, 2.0, method="RK4", dt=0.01,
                           samples=11)  # fmt: skip
        np.testing.assert_allclose(batch.q[i], alone.q, rtol=0, atol=1e-12)


def test_a_singular_mass_matrix_fails_with_the_trajectory_so_far() -> None:
    import sympy as sp

    theta, r = sp.symbols("theta r")
    theta_dot = sp.Symbol("theta_dot")
    # M = r^2 vanishes at r = 0: a coordinate singularity the C loop's solve reports
    system = lg.System(coordinates=[theta], parameters={r: 0.0}, kinetic=r**2 * theta_dot**2 / 2)
    start = {"theta": 0.0, "theta_dot": 1.0}
    run = lg.simulate(system, start, 1.0, method="RK4", dt=0.1, raise_on_failure=False)
    assert run.status == "failed"
    assert "singular" in run.message
    with pytest.raises(lg.SimulationError, match="singular"):
        lg.simulate(system, start, 1.0, method="RK4", dt=0.1)
