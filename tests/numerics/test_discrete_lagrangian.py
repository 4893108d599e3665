"""The compiled derivatives for the variational integrator equal SymPy's derivatives of L, of
the forces and of the constraints evaluated by substitution (no lambdify), and the Hessian
blocks equal central differences of the compiled first derivatives."""

from __future__ import annotations

import numpy as np
import sympy as sp

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics

RNG = np.random.default_rng(7)


def _forced_double_pendulum() -> lg.System:
    theta_dot, phi_dot, c, tau, t = sp.symbols("theta_dot phi_dot c tau t")
    pendulum = lg.examples.double_pendulum()
    return pendulum.replace(
        parameters={**pendulum.parameters, c: 0.3, tau: 0.5},
        dissipation=c * (theta_dot**2 + theta_dot * phi_dot + phi_dot**2),
        generalized_forces={sp.Symbol("theta"): tau * sp.cos(t) * sp.Symbol("phi")},
    )


def _point(eom: lg.EquationsOfMotion) -> tuple[dict, np.ndarray, np.ndarray, float, np.ndarray]:
    n = len(eom.coordinates)
    q, v = RNG.uniform(-1.5, 1.5, n), RNG.uniform(-1.5, 1.5, n)
    t = float(RNG.uniform(0.0, 2.0))
    p = np.array([float(value) for value in eom.parameters.values()])
    subs = dict(zip(eom.coordinates, q)) | dict(zip(eom.velocities, v))
    subs |= dict(zip(eom.parameters, p)) | {eom.time: t}
    return subs, q, v, t, p


def _value(expression: sp.Expr, subs: dict) -> float:
    return float(sp.sympify(expression).subs(subs).evalf())


def test_midpoint_terms_equal_the_symbolic_derivatives() -> None:
    eom = lg.derive(_forced_double_pendulum())
    mechanics = compile_discrete_mechanics(eom)
    assert mechanics.forced and mechanics.legendre_linear
    q_sym, v_sym = eom.coordinates, eom.velocities
    lagrangian = eom.lagrangian
    forces = list(eom.generalized_forces + eom.dissipation_forces)
    for _ in range(3):
        subs, q, v, t, p = _point(eom)
        L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v = mechanics.midpoint(q, v, t, p)
        expected = {
            "L_q": [_value(lagrangian.diff(a), subs) for a in q_sym],
            "L_v": [_value(lagrangian.diff(a), subs) for a in v_sym],
            "Q": [_value(f, subs) for f in forces],
            "L_qq": [[_value(lagrangian.diff(a, b), subs) for b in q_sym] for a in q_sym],
            "L_qv": [[_value(lagrangian.diff(a, b), subs) for b in v_sym] for a in q_sym],
            "L_vv": [[_value(lagrangian.diff(a, b), subs) for b in v_sym] for a in v_sym],
            "Q_q": [[_value(f.diff(b), subs) for b in q_sym] for f in forces],
            "Q_v": [[_value(f.diff(b), subs) for b in v_sym] for f in forces],
        }
        found = dict(zip(expected, (L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v)))
        for name, values in expected.items():
            np.testing.assert_allclose(found[name], values, rtol=1e-12, atol=1e-12, err_msg=name)


def test_the_hessian_blocks_are_derivatives_of_the_first_derivatives() -> None:
    eom = lg.derive(_forced_double_pendulum())
    mechanics = compile_discrete_mechanics(eom)
    _, q, v, t, p = _point(eom)
    step = 1e-6
    _, _, _, L_qq, L_qv, L_vv, Q_q, Q_v = mechanics.midpoint(q, v, t, p)
    for j in range(len(q)):
        dq, dv = np.eye(len(q))[j] * step, np.eye(len(q))[j] * step
        plus_q, minus_q = mechanics.midpoint(q + dq, v, t, p), mechanics.midpoint(q - dq, v, t, p)
        plus_v, minus_v = mechanics.midpoint(q, v + dv, t, p), mechanics.midpoint(q, v - dv, t, p)
        np.testing.assert_allclose((plus_q[0] - minus_q[0]) / (2 * step), L_qq[:, j], atol=1e-7)
        np.testing.assert_allclose((plus_v[0] - minus_v[0]) / (2 * step), L_qv[:, j], atol=1e-7)
        np.testing.assert_allclose((plus_v[1] - minus_v[1]) / (2 * step), L_vv[:, j], atol=1e-7)
        np.testing.assert_allclose((plus_q[2] - minus_q[2]) / (2 * step), Q_q[:, j], atol=1e-7)
        np.testing.assert_allclose((plus_v[2] - minus_v[2]) / (2 * step), Q_v[:, j], atol=1e-7)


def test_constraint_terms_of_a_moving_constraint() -> None:
    x, y, a, w, t = sp.symbols("x y a w t")
    h = (x - a * sp.cos(w * t)) ** 2 + y**2 - 1
    system = lg.System(
        coordinates=[x, y],
        parameters={a: 0.2, w: 3.0},
        particles=[lg.Particle("bead", 1, (x, y))],
        constraints=[lg.Holonomic(h)],
    )
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, [h])
    subs, q, v, time, p = _point(eom)
    values, jacobian, rate = mechanics.constraints(q, time, p)
    np.testing.assert_allclose(values, [_value(h, subs)], rtol=1e-13)
    np.testing.assert_allclose(jacobian, [[_value(h.diff(x), subs), _value(h.diff(y), subs)]])
    np.testing.assert_allclose(rate, [_value(h.diff(t), subs)], rtol=1e-13)
    position_residual, velocity_residual = mechanics.residuals(q, v, time, p)
    np.testing.assert_allclose(position_residual, values)
    np.testing.assert_allclose(velocity_residual, jacobian @ v + rate)
    assert compile_discrete_mechanics(eom, [h]) is mechanics  # compiled once


def test_a_lagrangian_not_quadratic_in_the_velocities_is_flagged() -> None:
    x, x_dot, m, c = sp.symbols("x x_dot m c")
    relativistic = lg.System(
        coordinates=[x],
        parameters={m: 1.0, c: 2.0},
        lagrangian=-m * c**2 * sp.sqrt(1 - x_dot**2 / c**2) - x**2 / 2,
    )
    mechanics = compile_discrete_mechanics(lg.derive(relativistic))
    assert not mechanics.legendre_linear and not mechanics.forced
