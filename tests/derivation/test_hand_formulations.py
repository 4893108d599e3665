"""Systems written by hand the way sympy.physics.mechanics users write them (orientations as
products of rotation matrices, contact points composed by hand, no-slip conditions written
out as velocity constraints), derived through the same kinematics as the element-based
models and checked against sympy.physics.mechanics' KanesMethod on the same system, and the
bicycle against the eigenvalues published by Meijaard, Papadopoulos, Ruina and Schwab,
Proc. R. Soc. A 463 (2007), Table 2.  The formulations live in benchmarks/, which times them."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bicycle
import multibody
import rolling_disc


@pytest.mark.parametrize("formulation", rolling_disc.METHODS[:-1])
def test_every_formulation_of_the_rolling_disc_matches_kanes_method(formulation: str) -> None:
    """The element, the example, and the matrix product, the expanded matrix and the
    quaternions written by hand: psi'', theta'' and phi'' at a rolling state."""
    ours = rolling_disc.accelerations(formulation, rolling_disc.derive(formulation))
    theirs = rolling_disc.accelerations("kane", rolling_disc.derive("kane"))
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-9)


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
