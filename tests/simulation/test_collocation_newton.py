"""The Newton iteration of the collocation steps: it stops at a small correction whose residual
was small and takes the forces at the corrected stages from their Jacobian, so the solution it
returns must be that of the stage equations to rounding.  Checked against the same equations
evaluated afresh at the returned stages, against SciPy's root finder at a tight tolerance, on
the Lobatto pair's constraints, and by the count of evaluations a step (two per stage on a
smooth motion)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import root

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics, compile_discrete_mechanics
from lagrangian.simulation.variational.collocation import Tableau, gauss, lobatto
from lagrangian.simulation.variational.collocation_march import collocation_march
from lagrangian.simulation.variational.collocation_step import stage_step

DT = 0.01


def forced_double_pendulum() -> lg.System:
    """The double pendulum with Rayleigh dissipation and a time-dependent torque (forces that
    depend on q, v and t enter every block of the Jacobian)."""
    theta_dot, phi_dot, c, tau, t = sp.symbols("theta_dot phi_dot c tau t")
    pendulum = lg.examples.double_pendulum()
    return pendulum.replace(
        parameters={**pendulum.parameters, c: 0.3, tau: 0.5},
        dissipation=c * (theta_dot**2 + theta_dot * phi_dot + phi_dot**2),
        generalized_forces={sp.Symbol("theta"): tau * sp.cos(t) * sp.Symbol("phi")},
    )


def setup(system: lg.System) -> tuple[DiscreteMechanics, np.ndarray]:
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, [c.expression for c in system.constraints])
    return mechanics, np.array([float(eom.system.parameters[s]) for s in eom.parameters])


def stage_residual(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    q0: np.ndarray,
    p0: np.ndarray,
    t0: float,
    p: np.ndarray,
    V: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The stage equations L_v(Q_i, V_i) - p0 - dt sum_j a_ij F_j (no constraints) evaluated
    afresh at V, and the momentum p0 + dt sum_i b_i F_i."""
    Q = q0 + DT * tableau.a @ V
    terms = [mechanics.midpoint(Qi, Vi, t0 + ci * DT, p) for Qi, Vi, ci in zip(Q, V, tableau.c)]
    F = np.array([L_q + Q_f for L_q, _, Q_f, *_ in terms])
    L_v = np.array([term[1] for term in terms])
    return L_v - p0 - DT * tableau.a @ F, p0 + DT * tableau.b @ F


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_a_gauss_step_solves_its_stage_equations_to_rounding(tableau: Tableau) -> None:
    mechanics, p = setup(forced_double_pendulum())
    q0, v0, t0 = np.array([1.0, 0.5]), np.array([0.7, -1.3]), 0.4
    p0 = np.array(mechanics.legendre(q0, v0, t0, p)[0], dtype=float)
    guess = np.tile(v0, (tableau.stages, 1))
    step = stage_step(mechanics, tableau, q0, p0, t0, DT, p, guess, np.zeros((0, 0)))
    rows, momentum = stage_residual(mechanics, tableau, q0, p0, t0, p, step.V)
    # the equations hold at the returned stages to rounding of their terms (about 10)
    assert np.abs(rows).max() < 1e-13
    # the momentum taken from the Jacobian is the one evaluated at the stages
    np.testing.assert_allclose(step.momentum, momentum, rtol=0, atol=1e-13)
    np.testing.assert_allclose(step.q, q0 + DT * tableau.b @ step.V, rtol=0, atol=1e-15)
    # SciPy's root finder on the same equations (no Jacobian given), at a tight tolerance
    found = root(
        lambda x: stage_residual(mechanics, tableau, q0, p0, t0, p, x.reshape(-1, 2))[0].ravel(),
        guess.ravel(),
        method="hybr",
        options={"xtol": 1e-13},
    )
    assert found.success and np.abs(found.fun).max() < 1e-12
    np.testing.assert_allclose(step.V.ravel(), found.x, rtol=0, atol=1e-11)
    # a guess this far off takes more corrections; every one is counted
    assert step.evaluations % tableau.stages == 0 and step.evaluations >= 2 * tableau.stages


@pytest.mark.parametrize("tableau", [lobatto(3), lobatto(4)], ids=lambda t: t.name)
def test_a_lobatto_step_ends_on_the_constraints_with_their_values_there(tableau: Tableau) -> None:
    x1, y1, m1, l1, g = sp.symbols("x1 y1 m1 l1 g")
    pendulum = lg.System(
        coordinates=[x1, y1],
        parameters={m1: 1.0, l1: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m1, (x1, y1))],
        constraints=[lg.Holonomic(x1**2 + y1**2 - l1**2, name="rod")],
    )
    mechanics, p = setup(pendulum)
    angle, speed = 0.8, 1.1
    q0 = np.array([np.sin(angle), -np.cos(angle)])
    v0 = speed * np.array([np.cos(angle), np.sin(angle)])
    p0 = np.array(mechanics.legendre(q0, v0, 0.0, p)[0], dtype=float)
    guess = np.tile(v0, (tableau.stages, 1))
    multipliers = np.zeros((tableau.stages - 1, 1))
    step = stage_step(mechanics, tableau, q0, p0, 0.0, DT, p, guess, multipliers)
    # every stage after the first on the circle, q1 among them
    Q = q0 + DT * tableau.a @ step.V
    assert np.abs((Q[1:] ** 2).sum(axis=1) - 1).max() < 1e-14
    np.testing.assert_allclose(step.q, Q[-1], rtol=0, atol=1e-15)
    # h, A and dh/dt returned are those at the corrected q1
    for returned, fresh in zip(
        (step.h, step.jacobian, step.rate), mechanics.constraints(step.q, DT, p)
    ):
        np.testing.assert_allclose(returned, fresh, rtol=0, atol=1e-15)


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_a_smooth_motion_evaluates_each_stage_about_twice_a_step(tableau: Tableau) -> None:
    # the extrapolated guess is corrected once, the correction after it is small: two
    # evaluations of every stage (the first steps, started from v0 at every stage, take more)
    mechanics, p = setup(lg.examples.double_pendulum())
    x0, steps = np.array([1.0, 0.5, 0.0, 0.0]), 1000
    grid = np.linspace(0.0, steps * DT, steps + 1)
    run = collocation_march(mechanics, tableau, x0, p, grid, np.array([0, steps]))
    assert run.failure is None
    per_step = (run.evaluations - 2) / steps / tableau.stages  # less the Legendre maps
    assert 2.0 <= per_step < 2.3, per_step
