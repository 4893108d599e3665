"""Systems written by hand the way sympy.physics.mechanics users write them (orientations as
products of rotation matrices, contact points composed by hand, no-slip conditions written
out as velocity constraints), derived through the same kinematics as the element-based
models and checked against sympy.physics.mechanics' KanesMethod on the same system, and the
bicycle against the eigenvalues published by Meijaard, Papadopoulos, Ruina and Schwab,
Proc. R. Soc. A 463 (2007), Table 2.  The formulations live in benchmarks/, which times them."""

from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.symbolic.symbols import t

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bicycle
import multibody


def _numbers(expr: sp.Basic, values: dict) -> np.ndarray:
    return np.array(sp.Matrix(expr).xreplace(values).evalf(30), dtype=float)


@pytest.mark.parametrize("orientation", multibody.DISC_ORIENTATIONS)
def test_the_rolling_disc_written_by_hand_matches_kanes_method(orientation: str) -> None:
    system = multibody.hand_rolling_disc(orientation)
    kane = multibody.kane_rolling_disc()
    plain = {qi: sp.Symbol(qi.func.__name__) for qi in kane["q"]}
    plain.update({ui: sp.Symbol(ui.func.__name__) for ui in kane["u"]})
    equations = lg.constrained_equations(system)
    x_dot, y_dot = system.velocities[:2]
    slip = [s.xreplace(plain) for s in kane["slip"]]
    rng = random.Random(17)
    for _ in range(3):
        values: dict = {p: rng.uniform(0.5, 1.5) for p in system.parameters}
        values.update({s: rng.uniform(-1.0, 1.0) for s in system.coordinates})
        values.update({s: rng.uniform(-2.0, 2.0) for s in system.velocities})
        values[t] = 0.0
        # x_dot, y_dot from Kane's own constraints (each holds x_dot or y_dot alone)
        values[x_dot] -= float(slip[0].xreplace(values))
        values[y_dot] -= float(slip[1].xreplace(values))
        ours = np.linalg.solve(
            _numbers(equations.augmented_matrix, values), _numbers(equations.augmented_rhs, values)
        ).ravel()[:5]
        method = kane["method"]
        mass = _numbers(method.mass_matrix_full.xreplace(plain), values)
        forcing = _numbers(method.forcing_full.xreplace(plain), values).ravel()
        theirs = np.linalg.solve(mass, forcing)[5:]  # after q_dot; independent speeds first
        np.testing.assert_allclose(ours[[2, 3, 4, 0, 1]], theirs, rtol=1e-9, atol=1e-9)


def test_the_chain_written_by_hand_matches_kanes_method_and_the_euler_angle_chain() -> None:
    result = multibody.derive_hand(2)
    assert multibody.check("hand", 2, result) == "ok"
    values = multibody.random_values(2)
    euler = multibody.derive_euler(2)
    for matrix in ("mass_matrix", "forcing"):
        np.testing.assert_allclose(
            multibody.numbers(result[matrix], values),
            multibody.numbers(euler[matrix], values),
            rtol=1e-10,
            atol=1e-10,
        )


@pytest.mark.slow
def test_the_bicycle_written_by_hand_agrees_with_kanes_method() -> None:
    ours = bicycle.lagrangian_accelerations(bicycle.hand_bicycle())
    theirs = bicycle.kane_accelerations(bicycle.derive_kane())
    np.testing.assert_allclose(ours, theirs, rtol=1e-9)


#: Table 2 of the paper: the eigenvalues of the lean/steer equations at 4 and 5 m/s.
TABLE_2 = {
    4.0: [-12.15861426576447, -1.42944427361326, 0.41325331521125 - 3.07910818603206j],
    5.0: [-14.07838969279822, -0.32286642900409, -0.77534188219585 - 4.46486771378823j],
}


@pytest.mark.slow
@pytest.mark.parametrize("speed", list(TABLE_2))
def test_the_bicycle_written_by_hand_has_the_published_eigenvalues(speed: float) -> None:
    system = bicycle.hand_bicycle()
    eom = lg.derive(system)
    values = {p.name: v for p, v in eom.parameters.items() if p.name not in ("Tlean", "Tsteer")}
    about = {"x_dot": speed, "thetaR_dot": speed / 0.3, "thetaF_dot": speed / 0.35}
    kept = ["x", "y", "yaw", "lean", "steer", "thetaR", "thetaF"]
    kept += ["lean_dot", "steer_dot", "thetaR_dot"]
    linear = lg.analysis.linearize(
        eom, about, inputs=["Tlean", "Tsteer"], parameters=values, independent=kept
    )
    eigenvalues = np.linalg.eigvals(np.array(sp.Matrix(linear.A).evalf(30), dtype=float))
    moving = sorted((e for e in eigenvalues if abs(e) > 1e-8), key=lambda e: (e.real, e.imag))
    expected = TABLE_2[speed]
    expected = sorted([*expected, np.conj(expected[-1])], key=lambda e: (e.real, e.imag))
    np.testing.assert_allclose(moving, expected, atol=1e-9)
