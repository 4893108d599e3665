"""The multiplier form in the C loop (numerics/fast/c_constrained.py): a pendulum in Cartesian
coordinates against the polar one and its tension, a knife edge (a velocity constraint)
against its closed form, Baumgarte's stabilization, the same rows, multipliers and events as
SciPy's path, and SciPy's path where the loop does not apply (projection after every step)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from c_loop_setup import scipy_path
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.io.load import loads
from lagrangian.numerics.fast import c_loop
from lagrangian.simulation.integrators.compiled import NativeIntegrator
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler")

TOL = {"rtol": 1e-10, "atol": 1e-10}
THETA0 = 1.0
CARTESIAN_START = {"x": math.sin(THETA0), "y": -math.cos(THETA0), "x_dot": 0.0, "y_dot": 0.0}
KNIFE_EDGE = """
name: knife edge on an incline
coordinates: [x, y, phi]
parameters: {m: 1.0, J: 0.3, g: 9.81, a: 0.5}
kinetic: m*(x_dot**2 + y_dot**2)/2 + J*phi_dot**2/2
potential: m*g*sin(a)*x
constraints:
  - {velocity: "x_dot*sin(phi) - y_dot*cos(phi)"}
"""


def cartesian_pendulum() -> lg.System:
    x, y = sp.symbols("x y")
    m, g, l = sp.symbols("m g l", positive=True)
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        gravity=(0, -g),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
        particles=[lg.Particle("bob", m, (x, y))],
    )


def integrator_of(eom, initial, t_end, options, **keywords):
    return plan(prepare(eom, initial, t_end, options, **keywords))[1]


def same_run(native: lg.Trajectory, scipy: lg.Trajectory) -> None:
    assert native.message == scipy.message and len(native.t) == len(scipy.t)
    np.testing.assert_allclose(native.t, scipy.t, rtol=0, atol=1e-12)
    for mine, theirs in [(native.q, scipy.q), (native.q_dot, scipy.q_dot)]:
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.multipliers, scipy.multipliers, rtol=0, atol=1e-9)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_the_cartesian_pendulum_is_the_polar_one(method: str) -> None:
    """x = l sin(theta), y = -l cos(theta); the multiplier of h = x^2 + y^2 - l^2 is
    lambda = -T / (2 l) with the tension T = m g cos(theta) + m l theta_dot^2."""
    eom = lg.derive(cartesian_pendulum())
    options = {"method": method, "samples": 101, **TOL}
    assert isinstance(integrator_of(eom, CARTESIAN_START, 5.0, options), NativeIntegrator)
    native = lg.simulate(eom, CARTESIAN_START, 5.0, **options)
    polar = lg.simulate(lg.examples.simple_pendulum(), {"theta": THETA0}, 5.0, **options)
    theta, omega = polar.q[:, 0], polar.q_dot[:, 0]
    np.testing.assert_allclose(native.q[:, 0], np.sin(theta), rtol=0, atol=1e-7)
    np.testing.assert_allclose(native.q[:, 1], -np.cos(theta), rtol=0, atol=1e-7)
    tension = 9.81 * np.cos(theta) + omega**2
    np.testing.assert_allclose(native.multipliers[:, 0], -tension / 2, rtol=0, atol=1e-6)
    assert np.max(native.constraint_residual) < 1e-7
    same_run(native, scipy_path(eom, CARTESIAN_START, 5.0, **options))


def test_baumgarte_holds_the_constraint_as_on_scipys_path() -> None:
    eom = lg.derive(cartesian_pendulum())
    options = {"method": "DOP853", "samples": 201, "rtol": 1e-6, "atol": 1e-8}
    keywords = {"baumgarte": (10.0, 10.0)}
    integrator = integrator_of(eom, CARTESIAN_START, 40.0, options, **keywords)
    assert isinstance(integrator, NativeIntegrator)
    assert integrator.extra_parameters == (10.0, 10.0)
    native = lg.simulate(eom, CARTESIAN_START, 40.0, **options, **keywords)
    loose = lg.simulate(eom, CARTESIAN_START, 40.0, **options)
    # without stabilization the residual drifts (1.8e-4 at t = 40); with it, it stays bounded
    assert np.max(native.constraint_residual) < 5e-6
    assert np.max(native.constraint_residual) < np.max(loose.constraint_residual) / 30
    same_run(native, scipy_path(eom, CARTESIAN_START, 40.0, **options, **keywords))


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_a_knife_edge_on_an_incline_meets_its_closed_form(method: str) -> None:
    """phi = w t, v along the blade: v' = -g sin(a) cos(phi), so from rest
    x = -(g sin a / (2 w^2)) sin^2(w t), y = -(g sin a / w)(t/2 - sin(2 w t) / (4 w))."""
    eom = lg.derive(loads(KNIFE_EDGE))
    start = {"x": 0.0, "y": 0.0, "phi": 0.0, "x_dot": 0.0, "y_dot": 0.0, "phi_dot": 1.5}
    options = {"method": method, "samples": 61, **TOL}
    assert isinstance(integrator_of(eom, start, 6.0, options), NativeIntegrator)
    native = lg.simulate(eom, start, 6.0, **options)
    t, w, push = native.t, 1.5, 9.81 * math.sin(0.5)
    np.testing.assert_allclose(native.q[:, 2], w * t, rtol=0, atol=1e-8)
    np.testing.assert_allclose(native.q[:, 0], -push / (2 * w**2) * np.sin(w * t) ** 2, atol=1e-8)
    y = -push / w * (t / 2 - np.sin(2 * w * t) / (4 * w))
    np.testing.assert_allclose(native.q[:, 1], y, rtol=0, atol=1e-8)
    assert np.max(native.constraint_residual) < 1e-8
    same_run(native, scipy_path(eom, start, 6.0, **options))


def test_events_on_the_constrained_pendulum_are_at_the_quarter_periods() -> None:
    eom = lg.derive(cartesian_pendulum())

    def bottom(t, q, q_dot):
        return q[0]

    options = {"method": "DOP853", **TOL}
    assert isinstance(
        integrator_of(eom, CARTESIAN_START, 4.0, options, events=[bottom]), NativeIntegrator
    )
    native = lg.simulate(eom, CARTESIAN_START, 4.0, events=[bottom], **options)
    period = 4 * math.sqrt(1.0 / 9.81) * ellipk(math.sin(THETA0 / 2) ** 2)
    times = [e.t for e in native.events]
    np.testing.assert_allclose(times, period / 4 + period / 2 * np.arange(len(times)), atol=1e-8)
    scipy = scipy_path(eom, CARTESIAN_START, 4.0, events=[bottom], **options)
    np.testing.assert_allclose(times, [e.t for e in scipy.events], rtol=0, atol=1e-9)


def test_projection_after_every_step_stays_on_scipys_path() -> None:
    eom = lg.derive(cartesian_pendulum())
    options = {"method": "DOP853", **TOL}
    projected = integrator_of(eom, CARTESIAN_START, 1.0, options, project_steps=True)
    assert isinstance(projected, SolverIntegrator)
    assert isinstance(
        integrator_of(eom, CARTESIAN_START, 1.0, {"method": "Radau"}), SolverIntegrator
    )


def test_every_step_rows_have_the_multipliers_and_residuals_of_numpys_multiplier_form() -> None:
    """The rows' multipliers and residuals computed at once from the compiled function are
    those of the NumPy multiplier form (MultiplierDynamics.constraint_rows) row by row."""
    eom = lg.derive(cartesian_pendulum())
    keywords = {"baumgarte": (2.0, 3.0)}
    options = {"method": "RK45", **TOL}
    setup = prepare(eom, CARTESIAN_START, 2.0, options, **keywords)
    dynamics, integrator = plan(setup)
    assert isinstance(integrator, NativeIntegrator)
    run = lg.simulate(eom, CARTESIAN_START, 2.0, **options, **keywords)
    assert len(run.t) > 50
    multipliers, residual = dynamics.constraint_rows(run.t, run.q, run.q_dot)
    np.testing.assert_allclose(run.multipliers, multipliers, rtol=0, atol=1e-11)
    np.testing.assert_allclose(run.constraint_residual, residual, rtol=0, atol=1e-13)
