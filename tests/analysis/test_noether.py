"""Point symmetries and Noether charges against textbook results.

References (written here by hand, not taken from the code under test; e.g. Goldstone,
Classical Mechanics, sections 2.6 and 13.7):
- Kepler problem in Cartesian (x, y), V = -k / sqrt(x^2 + y^2): invariant under rotations
  xi = (-y, x) only, conserved angular momentum m (x y_dot - y x_dot);
- free particle in the plane: translations along x and y and the rotation, conserved
  m x_dot, m y_dot and m (x y_dot - y x_dot);
- planet in polar coordinates: theta -> theta + eps, conserved p_theta = m r^2 theta_dot;
- two masses on a line joined by a spring, V = k/2 (x2 - x1 - l)^2: only the common
  translation xi = (1, 1), conserved total momentum m1 x1_dot + m2 x2_dot;
- with a dissipation function nothing is reported.
"""

from __future__ import annotations

import sympy as sp

import lagrangian as lg
from lagrangian.analysis import Symmetry, point_symmetries

m, k, m1, m2, l, B = sp.symbols("m k m1 m2 l B")
x, y, x1, x2 = sp.symbols("x y x1 x2")
x_dot, y_dot, x1_dot, x2_dot = sp.symbols("x_dot y_dot x1_dot x2_dot")
r, r_dot, theta_dot = sp.symbols("r r_dot theta_dot")

ANGULAR_MOMENTUM = m * (x * y_dot - y * x_dot)


def proportional(found: sp.Expr, expected: sp.Expr) -> bool:
    """``found`` is a nonzero constant multiple of ``expected`` (generators have no scale)."""
    ratio = sp.simplify(found / expected)
    return ratio != 0 and not ratio.free_symbols


def charges_match(symmetries: tuple[Symmetry, ...], expected: list[sp.Expr]) -> bool:
    """Every expected charge is found (up to scale), and nothing else."""
    unmatched = [s.conserved for s in symmetries]
    for charge in expected:
        match = next((c for c in unmatched if proportional(c, charge)), None)
        if match is None:
            return False
        unmatched.remove(match)
    return not unmatched


def plane_particle(potential: sp.Expr = sp.S.Zero, dissipation: sp.Expr = sp.S.Zero) -> lg.System:
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, k: 2.0, B: 0.5},
        kinetic=m / 2 * (x_dot**2 + y_dot**2),
        potential=potential,
        dissipation=dissipation,
    )


def test_central_potential_has_the_rotation_only() -> None:
    symmetries = point_symmetries(plane_particle(-k / sp.sqrt(x**2 + y**2)))
    assert charges_match(symmetries, [ANGULAR_MOMENTUM])
    assert symmetries[0].description == "rotation in the (x, y) plane"
    assert proportional(symmetries[0].generator[0], -y)
    assert proportional(symmetries[0].generator[1], x)


def test_free_particle_has_two_translations_and_the_rotation() -> None:
    symmetries = point_symmetries(plane_particle())
    assert charges_match(symmetries, [m * x_dot, m * y_dot, ANGULAR_MOMENTUM])
    descriptions = {s.description for s in symmetries}
    assert descriptions == {
        "translation along x",
        "translation along y",
        "rotation in the (x, y) plane",
    }


def test_planet_in_polar_coordinates_conserves_p_theta() -> None:
    symmetries = point_symmetries(lg.examples.planet())
    assert charges_match(symmetries, [m * r**2 * theta_dot])
    assert symmetries[0].description == "translation along theta"


def test_two_masses_on_a_spring_conserve_total_momentum() -> None:
    system = lg.System(
        coordinates=[x1, x2],
        parameters={m1: 1.0, m2: 3.0, k: 2.0, l: 1.0},
        kinetic=m1 / 2 * x1_dot**2 + m2 / 2 * x2_dot**2,
        potential=k / 2 * (x2 - x1 - l) ** 2,
    )
    symmetries = point_symmetries(system)
    assert charges_match(symmetries, [m1 * x1_dot + m2 * x2_dot])
    assert proportional(symmetries[0].generator[0], symmetries[0].generator[1])


def test_parameters_are_substituted_first() -> None:
    symmetries = point_symmetries(plane_particle(), parameters={"m": 2})
    assert charges_match(symmetries, [2 * x_dot, 2 * y_dot, 2 * (x * y_dot - y * x_dot)])


def test_dissipation_gives_no_symmetries() -> None:
    assert point_symmetries(plane_particle(dissipation=B / 2 * (x_dot**2 + y_dot**2))) == ()


def test_applied_force_gives_no_symmetries() -> None:
    assert point_symmetries(lg.examples.mass_spring_damper()) == ()


def test_analyze_reports_the_angular_momentum_of_a_central_field_in_cartesian() -> None:
    x, y, m, k = sp.symbols("x y m k")
    x_dot, y_dot = sp.symbols("x_dot y_dot")
    kepler = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, k: 1.0},
        kinetic=m * (x_dot**2 + y_dot**2) / 2,
        potential=-k / sp.sqrt(x**2 + y**2),
    )
    conserved = {c.name: c.expression for c in lg.analyze(kepler).conserved}
    assert sp.simplify(conserved["noether_1"] - m * (x * y_dot - y * x_dot)) == 0
    assert "h" in conserved
