"""The shortcuts that let a large system (the Whipple bicycle) be analyzed, against the
slower definitions they replace.

References (independent of the code under test):
- the degrees of a polynomial in the velocities are those of ``sympy.Poly`` of its
  expansion (the definition :func:`homogeneous_parts` uses), and a quadratic form obeys
  T(q, s v) = s^2 T(q, v) at every point (checked numerically at random points);
- a coordinate is an angle when every occurrence is inside sin/cos(k q + c) with integer
  k != 0: written out here as a direct recursion over the expression;
- the energy of a bicycle whose rolling constraints do not move is conserved (Meijaard et
  al. 2007 check their integrations by it).

The numeric equilibrium search on a manifold, whose starting points are now computed from
one compiled function, is checked against its hand results in test_manifold_statics (the
four-bar linkage).
"""

from __future__ import annotations

import random

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.energy import energy_conservation, homogeneous_parts, velocity_degrees
from lagrangian.analysis.roots import periodic_coordinates

x, y, z, t = sp.symbols("x y z t")
v, w = sp.symbols("v w")


def _poly_degrees(expr: sp.Expr, velocities: list[sp.Symbol]) -> set[int]:
    expanded = sp.expand(expr)
    if expanded == 0:
        return set()
    return {sum(m) for m in sp.Poly(expanded, *velocities).monoms()}


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        (x * v**2 + v * w, {2}),
        ((x + 1) * (v * w + x * v**2) + 3, {0, 2}),
        ((v + x) ** 2, {0, 1, 2}),
        (v**3 * sp.cos(x) + w, {1, 3}),
        (sp.sin(x) * (v + w) * (v - w), {2}),
    ],
)
def test_velocity_degrees_contain_the_polynomial_degrees(expr: sp.Expr, expected: set) -> None:
    found = velocity_degrees(expr, [v, w])
    assert found == expected
    assert _poly_degrees(expr, [v, w]) <= found  # a degree may cancel, never appear


def test_velocity_degrees_refuse_non_polynomials() -> None:
    for expr in (sp.cos(v), sp.sqrt(v) * x, x / v, sp.exp(v + w)):
        assert velocity_degrees(expr, [v, w]) is None
        assert homogeneous_parts(expr, [v, w]) is None


@pytest.mark.parametrize(
    "name", ["double_pendulum", "moving_pivot_pendulum", "charged_particle_em", "rolling_disc"]
)
def test_velocity_degrees_of_example_energies(name: str) -> None:
    eom = lg.derive(lg.examples.get(name)())
    for expr in (eom.kinetic_energy, eom.velocity_potential):
        parts = homogeneous_parts(expr, eom.velocities)
        degrees = velocity_degrees(expr, eom.velocities)
        assert parts is not None and degrees is not None
        assert set(parts) <= degrees


def _only_in_trig(expr: sp.Basic, q: sp.Symbol) -> bool:
    if q not in expr.free_symbols:
        return True
    if isinstance(expr, (sp.sin, sp.cos)):
        slope = sp.diff(expr.args[0], q)
        rest = expr.args[0] - slope * q
        return bool(slope.is_Integer and slope != 0 and q not in rest.free_symbols)
    if expr == q:
        return False
    return all(_only_in_trig(a, q) for a in expr.args)


@pytest.mark.parametrize(
    "exprs",
    [
        [sp.sin(x) + y],
        [sp.sin(2 * x + y) * sp.cos(z)],
        [sp.sin(x / 2)],
        [sp.sin(sp.sin(x))],
        [sp.exp(sp.cos(x)) * y**2, x],
        [sp.cos(3 * x) * sp.sin(x), z * sp.sin(z)],
        [sp.cos(x) ** 2 * sp.sin(x - 2 * y) + sp.sin(x) * sp.cos(x)],
    ],
)
def test_periodic_coordinates_match_the_definition(exprs: list) -> None:
    expected = [q for q in (x, y, z) if all(_only_in_trig(e, q) for e in exprs)]
    assert periodic_coordinates([x, y, z], exprs) == expected


@pytest.fixture(scope="module")
def bicycle() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.whipple_bicycle())


def test_bicycle_kinetic_energy_is_a_quadratic_form(bicycle: lg.EquationsOfMotion) -> None:
    eom = bicycle
    assert velocity_degrees(eom.kinetic_energy, eom.velocities) == {2}
    rng = random.Random(7)
    symbols = sorted(eom.kinetic_energy.free_symbols, key=str)
    point = {s: rng.uniform(0.3, 1.3) for s in symbols}
    kinetic = sp.lambdify(symbols, eom.kinetic_energy)
    scaled = dict(point)
    scaled.update({s: 1.7 * point[s] for s in eom.velocities if s in point})
    at = kinetic(*point.values())
    assert kinetic(*[scaled[s] for s in symbols]) == pytest.approx(1.7**2 * at, rel=1e-12)


@pytest.mark.slow
def test_bicycle_energy_is_conserved(bicycle: lg.EquationsOfMotion) -> None:
    """Rolling constraints that do not move do no work, and the lean and steer torques
    vanish on the manifold: dh/dt = 0."""
    verdict = energy_conservation(bicycle)
    assert verdict.conserved and verdict.rate == 0
    assert "T has terms of degree" not in verdict.total_energy_reason
