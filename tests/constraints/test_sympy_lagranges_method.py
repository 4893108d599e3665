"""Cross-check the multiplier form against sympy.physics.mechanics.LagrangesMethod with
``hol_coneqs`` (holonomic) and ``nonhol_coneqs`` (velocity constraints) on the same systems,
built there independently (dynamicsymbols, its own Lagrangian, points and loads).

Both solve the same augmented system: the accelerations must agree, and the multipliers too,
with a caveat on LagrangesMethod's sign.  Its ``lam_coeffs`` are -A (A the Jacobian of the
velocity-level constraints), and its ``mass_matrix`` = [m_d, lam_coeffs^T] makes the solved
system m_d q_ddot - A^T lam = f_d: the same as lagrangian's M q_ddot - A^T lambda = forcing,
so lam = lambda when solving ``mass_matrix_full`` / ``forcing_full`` (as here).  Its ``eom``
expression, however, carries + A^T lam, i.e. the opposite sign (sympy issue #30215,
"LagrangesMethod stores the negative of the Jacobian of the constraints")."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from constraint_systems import (
    dumbbell,
    hoop_state,
    knife_edge,
    numeric,
    pendulum,
    pendulum_state,
    rolling_disc,
    rotating_hoop,
)

import lagrangian as lg
from lagrangian.constraints import constrained_equations

TIME = me.dynamicsymbols._t


def _reference(
    names: str,
    lagrangian: Callable[[list, list], sp.Expr],
    hol: Callable[[list], list] | None = None,
    nonhol: Callable[[list, list], list] | None = None,
    loads: Callable[[me.ReferenceFrame, list, list], list] | None = None,
) -> tuple[me.LagrangesMethod, list, list]:
    q = me.dynamicsymbols(names)
    u = [qi.diff(TIME) for qi in q]
    frame = me.ReferenceFrame("N")
    method = me.LagrangesMethod(
        lagrangian(q, u),
        q,
        forcelist=loads(frame, q, u) if loads else None,
        frame=frame,
        hol_coneqs=hol(q) if hol else None,
        nonhol_coneqs=nonhol(q, u) if nonhol else None,
    )
    method.form_lagranges_equations()
    return method, q, u


def _solve_reference(method: me.LagrangesMethod, q: list, u: list, state: dict) -> np.ndarray:
    """[q_dot, q_ddot, lam] from LagrangesMethod's full system at ``state`` (names -> values)."""
    values = {}
    for qi, ui in zip(q, u):
        name = qi.func.__name__
        values[ui] = state[f"{name}_dot"]
        values[qi] = state[name]
    values.update({sp.Symbol(k): v for k, v in state.items()})
    values[TIME] = state.get("t", 0.0)
    mass = np.array(me.msubs(method.mass_matrix_full, values).evalf(), dtype=float)
    forcing = np.array(me.msubs(method.forcing_full, values).evalf(), dtype=float).ravel()
    return np.linalg.solve(mass, forcing)


def _compare(system: lg.System, reference: tuple, states: list[dict]) -> None:
    method, q, u = reference
    equations = constrained_equations(system)
    parameters = {p.name: v for p, v in system.parameters.items()}
    n, m = len(q), len(equations.multipliers)
    for state in states:
        full = {**parameters, "t": 0.0, **state}
        solution = _solve_reference(method, q, u, full)
        ours_acc = [numeric(equations.explicit[a], full) for a in equations.accelerations]
        ours_lam = [numeric(equations.explicit[lam], full) for lam in equations.multipliers]
        assert ours_acc == pytest.approx(list(solution[n : 2 * n]), rel=1e-9, abs=1e-9)
        assert ours_lam == pytest.approx(list(solution[2 * n : 2 * n + m]), rel=1e-9, abs=1e-9)


def test_pendulum_in_cartesian_coordinates() -> None:
    m, g, l = sp.symbols("m g l")
    reference = _reference(
        "x y",
        lambda q, u: m * (u[0] ** 2 + u[1] ** 2) / 2 - m * g * q[1],
        hol=lambda q: [q[0] ** 2 + q[1] ** 2 - l**2],
    )
    _compare(pendulum(), reference, [pendulum_state(0.5, 1.5), pendulum_state(-2.5, -0.3)])


def test_dumbbell_with_forces() -> None:
    m1, m2, h, g = sp.symbols("m1 m2 h g")
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")

    def loads(frame: me.ReferenceFrame, q: list, u: list) -> list:
        p1, p2 = me.Point("P1"), me.Point("P2")
        p1.set_vel(frame, u[0] * frame.x + u[1] * frame.y)
        p2.set_vel(frame, u[2] * frame.x + u[3] * frame.y)
        return [(p1, f1x * frame.x + f1y * frame.y), (p2, f2x * frame.x + f2y * frame.y)]

    reference = _reference(
        "x1 y1 x2 y2",
        lambda q, u: (
            m1 * (u[0] ** 2 + u[1] ** 2) / 2
            + m2 * (u[2] ** 2 + u[3] ** 2) / 2
            - m1 * g * q[1]
            - m2 * g * q[3]
        ),
        hol=lambda q: [(q[0] - q[2]) ** 2 + (q[1] - q[3]) ** 2 - h**2],
        loads=loads,
    )
    length = 0.9
    states = []
    for angle, rate in [(0.3, 2.0), (2.4, -1.0)]:
        c, s = math.cos(angle), math.sin(angle)
        states.append(
            {
                "x1": 0.2,
                "y1": -0.4,
                "x2": 0.2 + length * c,
                "y2": -0.4 + length * s,
                "x1_dot": 1.0,
                "y1_dot": 0.5,
                "x2_dot": 1.0 - length * s * rate,
                "y2_dot": 0.5 + length * c * rate,
            }
        )
    _compare(dumbbell(), reference, states)


def test_bead_on_a_rotating_hoop_rheonomic() -> None:
    m, g, R, w = sp.symbols("m g R omega")
    reference = _reference(
        "x y z",
        lambda q, u: m * (u[0] ** 2 + u[1] ** 2 + u[2] ** 2) / 2 - m * g * q[2],
        hol=lambda q: [
            q[0] * sp.sin(w * TIME) - q[1] * sp.cos(w * TIME),
            q[0] ** 2 + q[1] ** 2 + q[2] ** 2 - R**2,
        ],
    )
    _compare(rotating_hoop(), reference, [hoop_state(0.6, 0.4, 0.3), hoop_state(2.2, -1.1, 1.7)])


def test_knife_edge_with_nonhol_coneqs() -> None:
    m, inertia, g, alpha = sp.symbols("m I g alpha")
    reference = _reference(
        "x y phi",
        lambda q, u: (
            m * (u[0] ** 2 + u[1] ** 2) / 2 + inertia * u[2] ** 2 / 2 - m * g * sp.sin(alpha) * q[0]
        ),
        nonhol=lambda q, u: [u[0] * sp.sin(q[2]) - u[1] * sp.cos(q[2])],
    )
    states = []
    for heading, speed, turn in [(0.3, 1.2, 0.7), (2.2, -0.4, -1.5)]:
        states.append(
            {
                "x": 0.5,
                "y": -1.0,
                "phi": heading,
                "x_dot": speed * math.cos(heading),
                "y_dot": speed * math.sin(heading),
                "phi_dot": turn,
            }
        )
    _compare(knife_edge(), reference, states)


def test_rolling_disc_with_nonhol_coneqs() -> None:
    m, r, heading, spin, tau = sp.symbols("m r J_heading J_spin tau")
    reference = _reference(
        "x y theta phi",
        # the torque tau on the spin enters as the potential -tau phi
        lambda q, u: (
            m * (u[0] ** 2 + u[1] ** 2) / 2
            + heading * u[2] ** 2 / 2
            + spin * u[3] ** 2 / 2
            + tau * q[3]
        ),
        nonhol=lambda q, u: [u[0] - r * u[3] * sp.cos(q[2]), u[1] - r * u[3] * sp.sin(q[2])],
    )
    states = []
    for angle, turn, rate in [(0.9, 0.4, 2.0), (-2.0, -1.3, 0.5)]:
        states.append(
            {
                "x": 0.1,
                "y": 0.2,
                "theta": angle,
                "phi": 1.0,
                "theta_dot": turn,
                "phi_dot": rate,
                "x_dot": 0.3 * rate * math.cos(angle),
                "y_dot": 0.3 * rate * math.sin(angle),
            }
        )
    _compare(rolling_disc(), reference, states)
