"""The sine powers a wheel's no-slip coefficients can hold, bounded from the wheel's inputs
(lagrangian.model.contact._sine_powers): every power the walk of each expanded coefficient
finds is in the table, so each coefficient is tidied as by the walk; and inputs that are not
polynomials in sines and cosines of plain angles leave the walk to find them.  The turns the
wheels' angular velocities are composed of (lagrangian.model.rotation._backend_about) are
Rodrigues' formula entry by entry."""

from __future__ import annotations

import random
from typing import Any

import pytest
import symengine as se
import sympy as sp

from lagrangian.examples import BENCHMARKS, CATALOG
from lagrangian.model import RigidBody, RollingDisc, System, contact, rotation, shape
from lagrangian.model.contact import (
    _found_sine_powers,
    _HorizontalLength,
    _shorter_counted,
    _sine_powers,
    _trig_degrees,
    _WheelGeometry,
)

lean, steer, pitch, rF, c = se.symbols("lean steer pitch rF c")
S = _HorizontalLength.SYMBOL


def _random_trig_polynomial(rng: random.Random, angles: list[Any], terms: int) -> Any:
    """A sum of products of sines and cosines of ``angles`` (some of sums of them), symbols
    and small integers, with nested sums: the kind of tree a position or a rotation makes."""
    atoms = [rF, c, *(f(u) for u in angles for f in (se.sin, se.cos))]
    atoms += [se.sin(angles[0] + angles[1]), se.cos(2 * angles[1])]
    parts = []
    for _ in range(terms):
        factors = rng.choices(atoms, k=rng.randint(1, 4))
        if rng.random() < 0.3:
            factors.append(se.Add(*rng.choices(atoms, k=2)) ** rng.randint(1, 3))
        parts.append(rng.randint(-3, 3) * se.Mul(*factors))
    return se.Add(*parts)


@pytest.mark.parametrize("seed", range(12))
def test_every_sine_power_of_a_coefficient_is_in_the_bounded_table(seed: int) -> None:
    rng = random.Random(seed)
    angles = [lean, steer, pitch]
    position = [_random_trig_polynomial(rng, angles, 5) for _ in range(2)]
    omega = [_random_trig_polynomial(rng, angles, 3) for _ in range(3)]
    products = [_random_trig_polynomial(rng, angles, 3) / S for _ in range(3)]
    offset = [se.expand(product) for product in products]
    a_z = se.sin(lean) * se.cos(steer) + se.cos(lean) * se.sin(steer) * se.sin(pitch)
    length = _HorizontalLength(S, se.sqrt(1 - a_z**2), a_z)
    # the offset's degrees read off the products it was expanded from, and off itself
    geometry = _WheelGeometry(tuple(offset), length, products=tuple(products))
    table = _sine_powers(position, omega, geometry)
    assert table is not None
    expanded = _sine_powers(position, omega, _WheelGeometry(tuple(offset), length))
    assert expanded is not None and set(expanded) <= set(table)
    for k, (i, j) in enumerate(((1, 2), (2, 0))):
        for variable in angles:
            part = se.diff(position[k], variable) + omega[i] * offset[j] - omega[j] * offset[i]
            plain = se.expand(part)
            numerator = se.expand(se.expand(plain * S).xreplace({S**2: 1 - a_z**2}))
            for expr in (plain, numerator):
                assert set(_found_sine_powers(expr)) <= set(table)
                assert str(_shorter_counted(expr, table)[0]) == str(_shorter_counted(expr, None)[0])


@pytest.mark.parametrize(
    "expr",
    [
        se.sqrt(se.sin(lean)),  # a sine under a root
        1 / (1 + se.cos(lean)),  # in a denominator
        se.sin(se.sin(lean)),  # an angle that is not free of functions
        se.exp(lean) * se.sin(lean),  # another function
        se.sin(lean) ** steer,  # an exponent that varies
    ],
)
def test_what_is_not_a_polynomial_in_sines_has_no_degree(expr: Any) -> None:
    assert _trig_degrees(expr, {}) is None


def test_degrees_are_those_of_the_expansion() -> None:
    expr = (se.sin(lean) * se.cos(steer) + rF) ** 2 * se.cos(lean) / rF + se.sin(steer) ** 3
    assert _trig_degrees(expr, {}) == {lean: 3, steer: 3}


def _constraints_of(system: System) -> list[str]:
    return [sp.srepr(c.expression) for c in system.constraints]


@pytest.mark.parametrize("name", ["whipple_bicycle", "rolling_disc", "rolling_coin"])
def test_the_models_rolling_constraints_are_those_the_walk_tidies(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    build = BENCHMARKS[name] if name in BENCHMARKS else CATALOG[name]
    bounded = _constraints_of(build.__wrapped__())  # type: ignore[attr-defined]
    monkeypatch.setattr(contact, "_sine_powers", lambda *_: None)
    assert _constraints_of(build.__wrapped__()) == bounded  # type: ignore[attr-defined]


def test_a_wheel_on_a_body_with_other_functions_is_tidied_by_the_walk(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    x, y, psi, theta, m, r, k = sp.symbols("x y psi theta m r k")
    bounded = contact._sine_powers
    tables: list[Any] = []
    monkeypatch.setattr(contact, "_sine_powers", lambda *a: tables.append(bounded(*a)))
    wheel = RigidBody(
        "wheel",
        m,
        shape("disc", radius=r, axis="y"),
        (x + sp.exp(k * theta), y, r * sp.cos(theta)),
        rotations=[("z", psi), ("x", theta)],
    )
    system = System(
        coordinates=[x, y, psi, theta],
        parameters={m: 1.0, r: 0.3, k: 0.5},
        rigid_bodies=[wheel],
        rolling=[RollingDisc("wheel", r)],
    )
    assert tables == [None]
    slip_x = system.constraints[0].expression
    theta_dot = sp.Symbol("theta_dot")
    assert sp.expand(slip_x.coeff(theta_dot) - k * sp.exp(k * theta)) != 0  # the wheel's roll
    assert slip_x.coeff(theta_dot).has(sp.exp)


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 3, 4), (1, 1, 1)])
def test_a_turn_about_an_axis_is_rodrigues_formula(axis: tuple[int, int, int]) -> None:
    # about a coordinate axis the entries are written out; each is the formula's own
    angle = -lean
    n = [se.sympify(e) for e in rotation.unit_axis(axis)]
    cosine, sine = se.cos(angle), se.sin(angle)
    skew = [[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]]
    formula = [
        [
            (cosine if i == j else 0) + sine * skew[i][j] + (1 - cosine) * n[i] * n[j]
            for j in range(3)
        ]
        for i in range(3)
    ]
    made = rotation._backend_about(n, angle)
    assert [[str(e) for e in row] for row in made] == [[str(e) for e in row] for row in formula]
    assert made == formula


def test_a_radius_zero_by_its_symbols_assumptions_makes_a_ball() -> None:
    """log(a b) - log(a) - log(b) is zero for positive a and b only: the radius is decided
    on the user's expression, whose symbols keep their assumptions, so the wheel is a ball
    of the tyre's radius (its contact right below the centre), not a disc of that radius."""
    x, y, psi, theta, m, r = sp.symbols("x y psi theta m r")
    a, b = sp.symbols("a b", positive=True)
    ball = RigidBody(
        "ball",
        m,
        shape("solid_sphere", radius=r),
        (x, y, r),
        rotations=[("z", psi), ("x", theta)],
    )
    system = System(
        coordinates=[x, y, psi, theta],
        parameters={m: 1.0, r: 0.3, a: 2.0, b: 3.0},
        rigid_bodies=[ball],
        rolling=[RollingDisc("ball", sp.log(a * b) - sp.log(a) - sp.log(b), tyre_radius=r)],
    )
    assert system.constraints
    assert not any(c.expression.has(sp.log) for c in system.constraints)
