"""The kinetic form of planar systems of points and bodies (chains with absolute or relative
angles, shared columns, moving pivots) against its definition and against the general
route, and the facts about SymEngine's products its shortcuts rest on:

- M = sum m J^T J + I g^T g, by value at random points;
- C q_dot exactly as the Christoffel sum built entry by entry with ``entry.diff(q)``;
- T exactly as the double sum of 1/2 M_jk q_dot_j q_dot_k over all j and k;
- d(c f r)/dq = (c r) f' as SymEngine writes it, when only the factor f has q."""

from __future__ import annotations

import random

import symengine as se
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import lagrangian as lg
from lagrangian.derivation.assemble import Assembly, assemble
from lagrangian.derivation.kinetic import (
    collected_entry,
    coriolis_vector,
    kinetic_form,
    one_trigonometric_factor,
)
from lagrangian.derivation.trig import combine_trig

t = sp.Symbol("t")


@st.composite
def planar_systems(draw: st.DrawFn) -> lg.System:
    """Points and bodies hung from links: each link turns by its own angle (absolute) or by
    the sum of the angles so far (relative), some links share a length, the pivot may move."""
    n = draw(st.integers(1, 5))
    angles = sp.symbols(f"a1:{n + 1}")
    lengths = sp.symbols(f"l1:{n + 1}")
    masses = sp.symbols(f"m1:{n + 1}")
    inertias = sp.symbols(f"I1:{n + 1}")
    relative = draw(st.booleans())
    moving = draw(st.booleans())
    x0, omega = sp.symbols("x0 omega")
    x, y, turn = (x0 * sp.cos(omega * t) if moving else sp.Integer(0)), sp.Integer(0), 0
    particles, bodies = [], []
    for i in range(n):
        turn = turn + angles[i] if relative else angles[i]
        length = lengths[draw(st.integers(0, i))]  # a length of this link or one before
        x, y = x + length * sp.sin(turn), y - length * sp.cos(turn)
        mass = masses[draw(st.integers(0, i))]
        if draw(st.booleans()):
            bodies.append(lg.RigidBody(f"b{i}", mass, inertias[i], (x, y), angle=turn))
        else:
            particles.append(lg.Particle(f"p{i}", mass, (x, y)))
    return lg.System(
        coordinates=angles,
        parameters=dict.fromkeys([*lengths, *masses, *inertias, x0, omega], 1.0),
        particles=particles,
        rigid_bodies=bodies,
    )


def _identical(fast: se.Basic, slow: se.Basic) -> None:
    assert fast == slow
    assert type(fast) is type(slow)
    assert fast.args == slow.args
    assert str(fast) == str(slow)


def _mass_by_definition(asm: Assembly) -> list[list[se.Basic]]:
    n = len(asm.q)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for point in asm.points:
        parts = [(point.mass, point.position)]
        if point.angle is not None:
            parts.append((point.inertia, (point.angle,)))
        for weight, coordinates in parts:
            jac = [[c.diff(q) for q in asm.q] for c in coordinates]
            for j in range(n):
                for k in range(n):
                    mass[j][k] += weight * se.Add(*[row[j] * row[k] for row in jac])
    return mass


def _polar(column: tuple[se.Basic, ...]) -> tuple[se.Basic, se.Basic] | None:
    """(r, a) for a column (r cos a, r sin a), r a product of symbols and numbers."""
    found = []
    for entry, function in zip(column, (se.cos, se.sin)):
        factors = entry.args if entry.is_Mul else (entry,)
        trig = [f for f in factors if isinstance(f, (se.sin, se.cos))]
        if len(trig) != 1 or type(trig[0]) is not function or not trig[0].args[0].is_Symbol:
            return None
        rest = [f for f in factors if f is not trig[0]]
        if not all(f.is_Symbol or f.is_Number or f.is_Pow for f in rest):
            return None
        found.append((se.Mul(*rest), trig[0].args[0]))
    return found[0] if len(column) == 2 and found[0] == found[1] else None


def _mass_point_by_point(asm: Assembly) -> list[list[se.Basic]]:
    """The upper triangle of sum m J^T J + I g^T g as the points come: each entry's column
    products (combined, or r s cos(a - b) for two planar columns), each times the weights of
    the points that have it summed in their order; an entry of more than one product
    combined once more."""
    n = len(asm.q)
    weights: dict[tuple[int, int], dict[se.Basic, list[se.Basic]]] = {}
    for point in asm.points:
        parts = [(point.mass, point.position)]
        if point.angle is not None and point.inertia != 0:
            parts.append((point.inertia, (point.angle,)))
        for weight, coordinates in parts:
            jac = [[c.diff(q) for q in asm.q] for c in coordinates]
            columns = [tuple(row[j] for row in jac) for j in range(n)]
            moving = [j for j in range(n) if any(c != 0 for c in columns[j])]
            for a, j in enumerate(moving):
                for k in moving[a:]:
                    first, second = _polar(columns[j]), _polar(columns[k])
                    if first is not None and second is not None:
                        product = first[0] * second[0] * se.cos(first[1] - second[1])
                    else:
                        product = combine_trig(
                            se.Add(*[c * d for c, d in zip(columns[j], columns[k])])
                        )
                    if product != 0:
                        weights.setdefault((j, k), {}).setdefault(product, []).append(weight)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            groups = weights.get((j, k), {})
            entry = se.Add(*[se.Add(*w) * c for c, w in groups.items()])
            single = len(groups) == 1 and not next(iter(groups)).is_Add
            if single:
                mass[j][k] = entry
            elif one_trigonometric_factor(list(groups)):  # one product once collected
                mass[j][k] = collected_entry(entry, {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t})
            else:
                mass[j][k] = combine_trig(se.Integer(0) + entry)
    return mass


def _coriolis_entry_by_entry(mass: list[list[se.Basic]], asm: Assembly) -> list[se.Basic]:
    """(C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l, each entry of the
    upper triangle differentiated by each coordinate it has, in the order of its symbols."""
    n, v = len(asm.q), asm.q_dot
    index = {q: ell for ell, q in enumerate(asm.q)}
    rows: list[list[se.Basic]] = [[] for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            entry = mass[j][k]
            factors = entry.args if entry.is_Mul else (entry,)
            for q in set().union(*[f.free_symbols for f in factors]):
                if q not in index:
                    continue
                ell, slope = index[q], entry.diff(q)
                rows[j].append(slope * v[k] * v[ell])
                if j != k:
                    rows[k].append(slope * v[j] * v[ell])
                rows[ell].append(-slope * v[j] * v[k] * (1 if j != k else se.Rational(1, 2)))
    return [se.Add(*row) for row in rows]


@settings(deadline=None, max_examples=40)
@given(planar_systems(), st.integers(0, 2**32 - 1))
def test_the_kinetic_form_of_a_planar_system_is_its_definition(
    system: lg.System, seed: int
) -> None:
    asm = assemble(system)
    form = kinetic_form(asm)
    n = len(asm.q)
    rng = random.Random(seed)
    values: dict[se.Basic, se.Basic] = {}
    for point in asm.points:
        for expr in (point.mass, point.inertia, *point.position):
            values.update({s: se.RealDouble(rng.uniform(0.5, 2.0)) for s in expr.free_symbols})
    reference = _mass_by_definition(asm)
    summed = _mass_point_by_point(asm)
    for j in range(n):
        for k in range(n):
            fast, slow = form.mass_matrix[j][k].subs(values), reference[j][k].subs(values)
            assert abs(float(fast) - float(slow)) <= 1e-9 * (1 + abs(float(slow)))
            if k >= j:
                _identical(form.mass_matrix[j][k], summed[j][k])
    for fast, slow in zip(coriolis_vector(form), _coriolis_entry_by_entry(form.mass_matrix, asm)):
        _identical(fast, slow)
    v = asm.q_dot
    double_sum = se.Add(
        *[form.mass_matrix[j][k] * v[j] * v[k] / 2 for j in range(n) for k in range(n)]
    )
    if not any(c.has(asm.t) for point in asm.points for c in point.position):  # fixed pivot
        assert all(term == 0 for term in form.time_terms)
        _identical(form.kinetic_energy, double_sum + 0)  # T is the double sum (+ no T1, T0)
    else:
        assert se.expand(form.kinetic_energy - double_sum).has(asm.t)


x, y, z, m, l = se.symbols("x y z m l")
#: factors with x (a chain's cos(theta_j - theta_k)) and factors without it
WITH_X = [se.sin(x), se.cos(x - y), se.cos(2 * x + z), se.exp(x), se.Add(x, m), se.sin(x * y)]
FREE = [m, l, se.Add(m, l, z), se.sin(y), se.cos(y - z), se.Pow(y, 2), se.sqrt(l), se.exp(z)]
NUMBERS = [se.Integer(-3), se.Integer(2), se.Rational(-3, 4), se.RealDouble(0.5)]
NUMBERS += [se.RealDouble(1.0), se.RealDouble(-2.5)]


@settings(deadline=None, max_examples=150)
@given(
    st.sampled_from(WITH_X),
    st.lists(st.sampled_from(FREE), max_size=3, unique=True),
    st.lists(st.sampled_from(NUMBERS), max_size=2),
)
def test_a_product_with_one_factor_in_q_is_differentiated_as_the_rest_times_its_derivative(
    held: se.Basic, others: list[se.Basic], numbers: list[se.Basic]
) -> None:
    product = se.Mul(*numbers, held, *others)
    assume(product.is_Mul)
    parts = product.args
    (i,) = [i for i, f in enumerate(parts) if x in f.free_symbols]
    rest, change = se.Mul(*parts[:i], *parts[i + 1 :]), parts[i].diff(x)
    assume(rest.is_Mul and not parts[i].is_Pow and not change.is_Number)
    _identical(rest * change, product.diff(x))
