"""The kinetic energy in matrix form: T = 1/2 q_dot^T M q_dot + T1 + T0 (or a general T).

For particles and bodies the mass matrix is built from Jacobians, M = sum m J^T J
(+ I g^T g for a planar body's angle, + J_w^T I J_w for a 3-D body whose body angular velocity
is omega_b = J_w q_dot + omega_t), so T is never expanded as a whole; trigonometric products
are combined entry by entry (:mod:`lagrangian.derivation.trig`).  The Coriolis/centripetal vector
C(q, q_dot) q_dot comes from the Christoffel symbols of M:

    (C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l,

computed as d(M q_dot)/dq . q_dot - grad_q(1/2 q_dot^T M q_dot).  The rest of
d/dt dT/dq_dot - dT/dq (explicit time dependence, terms of degree 0 and 1 in the velocities)
is kept apart as the time terms.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass

import symengine as se

from lagrangian.derivation.assemble import Assembly, Rotation
from lagrangian.derivation.backend import Backend
from lagrangian.derivation.trig import combine_trig
from lagrangian.derivation.trig_polynomial import (
    Key,
    Poly,
    PolynomialTooLarge,
    TrigAlgebra,
    algebra_for,
)

Matrix = list[list[Backend]]


@dataclass(frozen=True)
class KineticForm:
    """M(q, t) (or M(q, q_dot, t) for a T that is not quadratic), C q_dot, time terms and T."""

    mass_matrix: Matrix
    coriolis: list[Backend]
    time_terms: list[Backend]
    kinetic_energy: Backend
    quadratic: bool
    #: True when M and C q_dot were built as polynomials grouped by monomial, or kept nested
    #: (3-D bodies): :func:`lagrangian.derivation.trig.combine_and_collect` tidies what is
    #: made of them at once (it knows their monomials, or that they stay nested).
    grouped: bool = False


def _hessian(expr: Backend, symbols: tuple[Backend, ...]) -> Matrix:
    first = [expr.diff(s) for s in symbols]
    return [[first[i].diff(s) for s in symbols] for i in range(len(symbols))]


def _point_terms(asm: Assembly) -> tuple[Matrix, Backend, set[tuple[int, int]]]:
    """sum m J^T J (+ I g^T g), the kinetic terms of degree 0 and 1 in the velocities, and the
    entries that are one combined product times a sum of weights.

    The weights of each combined column product are summed before they multiply it: a chain's
    entry is l_j l_k (m_k + ... + m_n) cos(theta_j - theta_k), never grown term by term; a
    column that recurs (link j's in every point beyond it) is met by number, not compared."""
    n = len(asm.q)
    weights: dict[tuple[int, int], dict[Backend, list[Backend]]] = defaultdict(dict)
    low_degree = se.Integer(0)
    columns_seen: dict[tuple[Backend, ...], int] = {}
    combined: dict[Backend, Backend] = {}  # the same column pairs recur for every point below
    pairs: dict[tuple[int, int], Backend | None] = {}  # column numbers -> product (None: 0)
    polar: dict[int, tuple[Backend, Backend] | None] = {}  # column number -> (r, a) or None
    for point in asm.points:
        columns = [(point.mass, point.position)]
        if point.angle is not None and point.inertia != 0:
            columns.append((point.inertia, (point.angle,)))
        for weight, coordinates in columns:
            jac = [_gradient(x, asm.q) for x in coordinates]
            drift = [x.diff(asm.t) for x in coordinates]
            ids = []
            for j in range(n):
                column = tuple(row[j] for row in jac)
                ids.append(
                    -1
                    if all(c == 0 for c in column)
                    else columns_seen.setdefault(column, len(columns_seen))
                )
            moving_columns = [j for j in range(n) if ids[j] >= 0]
            for j in moving_columns:
                if ids[j] not in polar:
                    polar[ids[j]] = _polar_column([row[j] for row in jac])
            for a, j in enumerate(moving_columns):
                id_j = ids[j]
                for k in moving_columns[a:]:
                    key = (id_j, ids[k])
                    product = pairs.get(key, _UNKNOWN)
                    if product is _UNKNOWN:
                        product = pairs[key] = _column_product(jac, j, k, polar, key, combined)
                    if product is not None:
                        weights[j, k].setdefault(product, []).append(weight)
            if any(d != 0 for d in drift):
                moving = [se.Add(*[row[k] * asm.q_dot[k] for k in range(n)]) for row in jac]
                low_degree += weight * se.Add(*[v * d for v, d in zip(moving, drift)])
                low_degree += weight * se.Add(*[d**2 for d in drift]) / 2
    mass = [[se.Integer(0)] * n for _ in range(n)]
    single = set()
    for (j, k), groups in weights.items():
        mass[j][k] = se.Add(*[se.Add(*w) * c for c, w in groups.items()])
        if len(groups) == 1 and not next(iter(groups)).is_Add:
            single.add((j, k))
    for rotation in asm.rotations:
        low_degree += _rotation_terms(rotation, asm, mass, combined)
        single.clear()
    return mass, low_degree, single


#: A column product not computed yet (None stands for a product that is zero).
_UNKNOWN = object()


def _column_product(
    jac: list[list[Backend]],
    j: int,
    k: int,
    polar: dict[int, tuple[Backend, Backend] | None],
    key: tuple[int, int],
    combined: dict[Backend, Backend],
) -> Backend | None:
    """The product of columns j and k of ``jac``, trigonometry combined; None when it is 0.

    Two planar columns (r cos a, r sin a) and (s cos b, s sin b) give r s cos(a - b) at once,
    which is what :func:`combine_trig` makes of r s (cos a cos b + sin a sin b): a chain has
    n^2/2 of them."""
    first, second = polar[key[0]], polar[key[1]]
    if first is not None and second is not None:
        (r, angle_a), (s, angle_b) = first, second
        return r * s * se.cos(angle_a - angle_b)
    term = se.Add(*[row[j] * row[k] for row in jac])
    if term not in combined:
        combined[term] = combine_trig(term) if term != 0 else term
    product = combined[term]
    return None if product == 0 else product


def _polar_column(column: list[Backend]) -> tuple[Backend, Backend] | None:
    """(r, a) when ``column`` is (r cos a, r sin a) with a a symbol and r a product of
    symbols, numbers and their powers (no sine, no cosine, no sum); else None."""
    if len(column) != 2:
        return None
    x, y = (_times_function(entry) for entry in column)
    if x is None or y is None or x[2] is not se.cos or y[2] is not se.sin or x[:2] != y[:2]:
        return None
    return x[0], x[1]


def _times_function(entry: Backend) -> tuple[Backend, Backend, type] | None:
    """(r, a, f) when ``entry`` is r f(a), f sin or cos, a a symbol, r a plain product."""
    factors = entry.args if entry.is_Mul else (entry,)
    trig = [i for i, f in enumerate(factors) if isinstance(f, (se.sin, se.cos))]
    if len(trig) != 1 or not factors[trig[0]].args[0].is_Symbol:
        return None
    rest = [f for i, f in enumerate(factors) if i != trig[0]]
    plain = all(
        f.is_Symbol or f.is_Number or (f.is_Pow and f.args[0].is_Symbol and f.args[1].is_Number)
        for f in rest
    )
    function = factors[trig[0]]
    return (se.Mul(*rest), function.args[0], type(function)) if plain else None


def _gradient(expr: Backend, symbols: tuple[Backend, ...]) -> list[Backend]:
    """[d expr/ds for s in symbols], a sum differentiated term by term by the symbols each
    term has (a chain's position has one term per link)."""
    terms = expr.args if expr.is_Add else (expr,)
    index = {s: i for i, s in enumerate(symbols)}
    parts: list[list[Backend]] = [[] for _ in symbols]
    for term in terms:
        for s in term.free_symbols:
            i = index.get(s)
            if i is not None:
                parts[i].append(term.diff(s))
    return [se.Add(*p) for p in parts]


def _rotation_terms(
    rotation: Rotation, asm: Assembly, mass: Matrix, combined: dict[Backend, Backend]
) -> Backend:
    """Add J_w^T I J_w to the upper triangle of ``mass`` (omega_b = J_w q_dot + d, I symmetric)
    and return T's terms of degree 0 and 1: (J_w q_dot)^T I d + 1/2 d^T I d."""
    n, inertia = len(asm.q), rotation.inertia
    at_rest = {v: 0 for v in asm.q_dot}
    jac = [[w.diff(v) for v in asm.q_dot] for w in rotation.angular_velocity]
    drift = [w.subs(at_rest) for w in rotation.angular_velocity]
    for a in range(3):
        for b in range(a, 3):
            if inertia[a][b] == 0:
                continue
            for j in range(n):
                for k in range(j, n):
                    # 1/2 I_ab w_a w_b summed over a, b: I_ab (J_aj J_bk + J_bj J_ak) for a < b
                    term = jac[a][j] * jac[b][k] + (jac[b][j] * jac[a][k] if a != b else 0)
                    if term != 0:
                        if term not in combined:
                            combined[term] = combine_trig(term)
                        mass[j][k] += inertia[a][b] * combined[term]
    if all(d == 0 for d in drift):
        return se.Integer(0)
    moving = [se.Add(*[row[k] * asm.q_dot[k] for k in range(n)]) for row in jac]
    return se.Add(
        *[
            inertia[a][b] * (moving[a] * drift[b] + drift[a] * drift[b] / 2)
            for a in range(3)
            for b in range(3)
        ]
    )


def _linear_part(expr: Backend, asm: Assembly) -> Backend:
    """Terms of degree 0 and 1 in the velocities of an expression at most quadratic in them."""
    at_rest = {v: 0 for v in asm.q_dot}
    return expr.subs(at_rest) + se.Add(*[v * expr.diff(v).subs(at_rest) for v in asm.q_dot])


def _coriolis(mass: Matrix, asm: Assembly) -> list[Backend]:
    """(C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l, each entry of the
    upper triangle differentiated only by the coordinates it has."""
    n = len(asm.q)
    index = {q: ell for ell, q in enumerate(asm.q)}
    rows: list[list[Backend]] = [[] for _ in range(n)]
    v = asm.q_dot
    known: dict[Backend, set[Backend]] = {}
    for j in range(n):
        for k in range(j, n):
            entry = mass[j][k]
            factors = entry.args if entry.is_Mul else (entry,)
            for q in set().union(*[_symbols(f, known) for f in factors]):
                ell = index.get(q)
                if ell is None:
                    continue
                slope = entry.diff(q)
                rows[j].append(slope * v[k] * v[ell])
                if j != k:
                    rows[k].append(slope * v[j] * v[ell])
                rows[ell].append(-slope * v[j] * v[k] * (1 if j != k else se.Rational(1, 2)))
    return [se.Add(*row) for row in rows]  # expanded and tidied by the caller


def _symbols(factor: Backend, known: dict[Backend, set[Backend]]) -> set[Backend]:
    """The free symbols of ``factor``, remembered in ``known`` (sums of masses recur)."""
    if factor not in known:
        known[factor] = factor.free_symbols
    return known[factor]


def kinetic_form(asm: Assembly) -> KineticForm:
    """Mass matrix, Coriolis vector, time terms and T of an assembled system."""
    n = len(asm.q)
    explicit = _hessian(asm.explicit_kinetic, asm.q_dot)
    velocities = set(asm.q_dot)
    quadratic = all(velocities.isdisjoint(e.free_symbols) for row in explicit for e in row)
    if not quadratic:
        return _general_form(asm)
    # 3-D bodies: grouped trigonometric polynomials; planar points and bodies (a chain of
    # links) are summed per combined column product, each sum of weights once
    structured = _structured_form(asm, explicit) if asm.rotations else None
    if structured is not None:
        return structured
    point_mass, point_low, single = _point_terms(asm)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            if explicit[j][k] == 0 and (j, k) in single:  # combined already
                mass[j][k] = point_mass[j][k]
            else:
                mass[j][k] = combine_trig(explicit[j][k] + point_mass[j][k])
            mass[k][j] = mass[j][k]
    low = _linear_part(asm.explicit_kinetic, asm) + point_low
    quadratic_t = se.Add(
        *[mass[j][k] * asm.q_dot[j] * asm.q_dot[k] / 2 for j in range(n) for k in range(n)]
    )
    time_terms = []
    for j in range(n):
        explicit_time = se.Add(*[mass[j][k].diff(asm.t) * asm.q_dot[k] for k in range(n)])
        low_terms = asm.time_derivative(low.diff(asm.q_dot[j])) - low.diff(asm.q[j])
        time_terms.append(se.expand(explicit_time + low_terms))
    return KineticForm(mass, _coriolis(mass, asm), time_terms, quadratic_t + low, True)


def _general_form(asm: Assembly) -> KineticForm:
    """T not quadratic in the velocities (e.g. L = m^2 x_dot^4/12 + ...): M = d2T/dq_dot2
    depends on the velocities, and C q_dot is sum_k d2T/dq_dot_j dq_k q_dot_k - dT/dq_j."""
    kinetic = asm.explicit_kinetic
    for point in asm.points:
        velocity = asm.point_velocity(point.position)
        kinetic += point.mass * se.Add(*[v**2 for v in velocity]) / 2
        if point.angle is not None:
            kinetic += point.inertia * asm.time_derivative(point.angle) ** 2 / 2
    for rotation in asm.rotations:
        omega, inertia = rotation.angular_velocity, rotation.inertia
        kinetic += (
            se.Add(*[inertia[a][b] * omega[a] * omega[b] for a in range(3) for b in range(3)]) / 2
        )
    mass = [[se.expand(e) for e in row] for row in _hessian(kinetic, asm.q_dot)]
    momentum = [kinetic.diff(v) for v in asm.q_dot]
    coriolis = [
        se.expand(se.Add(*[p.diff(q) * qd for q, qd in zip(asm.q, asm.q_dot)]) - kinetic.diff(q))
        for p, q in zip(momentum, asm.q)
    ]
    time_terms = [se.expand(p.diff(asm.t)) for p in momentum]
    return KineticForm(mass, coriolis, time_terms, kinetic, False)


#: Products of Jacobian monomials (sum over the points and axes of the squared number of
#: monomials of a row of the Jacobian) beyond which M is built as grouped polynomials.
STRUCTURED_PRODUCTS = 2000
#: Monomials a polynomial of the reduced form may have; beyond, M and C q_dot stay nested.
CANONICAL_MONOMIALS = 1500
#: Products (as :data:`STRUCTURED_PRODUCTS`) beyond which M and C q_dot stay nested at once.
NESTED_PRODUCTS = 30000


def _structured_form(asm: Assembly, explicit: Matrix) -> KineticForm | None:
    """M = sum m J^T J + J_w^T I J_w and C q_dot (Christoffel symbols) of a large system
    whose T has no explicit time dependence, as polynomials grouped by monomial
    (:mod:`lagrangian.derivation.trig_polynomial`); None for a small or time-dependent one,
    or one without 3-D bodies (planar chains read best in angle differences, which the
    entry-by-entry :func:`combine_trig` finds)."""
    if (
        not asm.rotations
        or any(x.diff(asm.t) != 0 for point in asm.points for x in point.position)
        or any(
            w.diff(asm.t) != 0 or w.subs({v: 0 for v in asm.q_dot}) != 0
            for rotation in asm.rotations
            for w in rotation.angular_velocity
        )
    ):
        return None
    algebra = algebra_for([*asm.q, *asm.q_dot, *asm.q_ddot, asm.t])
    algebra.limit = CANONICAL_MONOMIALS
    try:
        return _canonical_form(asm, explicit, algebra)
    except PolynomialTooLarge:
        nested = _nested_form(asm, explicit)
    finally:
        algebra.limit = None
    for expr in [*nested.coriolis, *(e for row in nested.mass_matrix for e in row)]:
        algebra.keep_nested(expr)
    return nested


def _canonical_form(asm: Assembly, explicit: Matrix, algebra: TrigAlgebra) -> KineticForm | None:
    """M and C q_dot as reduced polynomials grouped by monomial; None for a small system
    (the entry-by-entry :func:`combine_trig` is cheap there, and reads best)."""
    n = len(asm.q)
    weighted = []  # (weight, rows of the Jacobian) whose J^T J enter M
    for point in asm.points:
        coordinates = point.position
        if point.angle is not None and point.inertia != 0:
            weighted.append((point.inertia, [_jacobian_row(algebra, point.angle, asm.q)]))
        weighted.append((point.mass, [_jacobian_row(algebra, x, asm.q) for x in coordinates]))
    products = sum(sum(len(p) for p in row) ** 2 for _, rows in weighted for row in rows)
    if products <= STRUCTURED_PRODUCTS:
        return None
    if products > NESTED_PRODUCTS:
        raise PolynomialTooLarge(f"{products} products of Jacobian monomials")
    weighted = [(w, _turned(algebra, rows) if len(rows) == 3 else rows) for w, rows in weighted]
    spins = [_rotation_parts(algebra, rotation, asm) for rotation in asm.rotations]
    mass_poly: list[list[Poly]] = [[{} for _ in range(n)] for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            parts = [algebra.convert(explicit[j][k])]
            for weight, rows in weighted:
                terms = [algebra.multiply(r[j], r[k]) for r in rows if r[j] and r[k]]
                if terms:
                    parts.append(algebra.multiply(algebra.convert(weight), algebra.add(terms)))
            for spin in spins:
                parts += spin.get((j, k), ())
            mass_poly[j][k] = algebra.add(parts)  # once: the sum of every body's share
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            mass_poly[j][k] = mass_poly[k][j] = algebra.finish(mass_poly[j][k])
            mass[j][k] = mass[k][j] = algebra.grouped(algebra.shortest(mass_poly[j][k]))
    quadratic_t = se.Add(
        *[mass[j][k] * asm.q_dot[j] * asm.q_dot[k] / 2 for j in range(n) for k in range(n)]
    )
    coriolis = [algebra.expression(c) for c in _christoffel(algebra, mass_poly, asm)]
    return KineticForm(mass, coriolis, [se.Integer(0)] * n, quadratic_t, True, grouped=True)


def _nested_form(asm: Assembly, explicit: Matrix) -> KineticForm:
    """M and C q_dot of a system whose reduced polynomials would be too large (a chain of
    bodies turned relative to each other: products of the sines and cosines of all the
    joint angles), kept nested as the positions and angular velocities are given, as
    Kane's method keeps them.  C q_dot is projected from the accelerations (Kane's
    generalized inertia forces, equal to Lagrange's for T with no explicit time):

        M = sum m J^T J + J_w^T I J_w,
        C q_dot = sum m J^T (J_dot q_dot) + J_w^T (I (J_w_dot q_dot) + omega x I omega),

    J_dot q_dot = sum_l d(J q_dot)/dq_l q_dot_l, omega = omega_b = J_w q_dot."""
    n = len(asm.q)
    mass = [[explicit[j][k] for k in range(n)] for j in range(n)]
    coriolis = [se.Integer(0)] * n
    for point in asm.points:
        columns = [(point.mass, point.position)]
        if point.angle is not None and point.inertia != 0:
            columns.append((point.inertia, (point.angle,)))
        for weight, coordinates in columns:
            jac = [[x.diff(q) for q in asm.q] for x in coordinates]
            bias = [_rate_change(_dot(row, asm.q_dot), asm) for row in jac]
            _project(mass, coriolis, weight, jac, bias)
    for rotation in asm.rotations:
        omega, inertia = rotation.angular_velocity, rotation.inertia
        jac = [[w.diff(v) for v in asm.q_dot] for w in omega]
        spin = [_dot(row, omega) for row in inertia]
        gyro = [
            omega[1] * spin[2] - omega[2] * spin[1],
            omega[2] * spin[0] - omega[0] * spin[2],
            omega[0] * spin[1] - omega[1] * spin[0],
        ]
        change = [_rate_change(w, asm) for w in omega]
        bias = [_dot(inertia[a], change) + gyro[a] for a in range(3)]
        for j in range(n):
            for k in range(j, n):
                mass[j][k] += se.Add(
                    *[
                        inertia[a][b] * jac[a][j] * jac[b][k]
                        for a in range(3)
                        for b in range(3)
                        if inertia[a][b] != 0
                    ]
                )
            coriolis[j] += _dot([row[j] for row in jac], bias)
    for j in range(n):
        for k in range(j + 1, n):
            mass[k][j] = mass[j][k]
    quadratic_t = se.Add(
        *[mass[j][k] * asm.q_dot[j] * asm.q_dot[k] / 2 for j in range(n) for k in range(n)]
    )
    return KineticForm(mass, coriolis, [se.Integer(0)] * n, quadratic_t, True, grouped=True)


def _dot(a: list[Backend] | tuple[Backend, ...], b: list[Backend] | tuple[Backend, ...]) -> Backend:
    return se.Add(*[x * y for x, y in zip(a, b) if x != 0 and y != 0])


def _rate_change(expr: Backend, asm: Assembly) -> Backend:
    """sum_l d(expr)/dq_l q_dot_l: the rate of ``expr`` (linear in q_dot) without q_ddot."""
    return se.Add(*[expr.diff(q) * v for q, v in zip(asm.q, asm.q_dot)])


def _project(
    mass: Matrix, coriolis: list[Backend], weight: Backend, jac: Matrix, bias: list[Backend]
) -> None:
    """Add weight J^T J to the upper triangle of ``mass`` and weight J^T bias to C q_dot."""
    n = len(coriolis)
    for j in range(n):
        column = [row[j] for row in jac]
        for k in range(j, n):
            term = _dot(column, [row[k] for row in jac])
            if term != 0:
                mass[j][k] += weight * term
        term = _dot(column, bias)
        if term != 0:
            coriolis[j] += weight * term


def _turned(algebra: TrigAlgebra, rows: list[list[Poly]]) -> list[list[Poly]]:
    """The rows of a point's Jacobian in axes turned about the vertical by the angle that
    makes them shortest, (R_z(u)^T J)^T R_z(u)^T J = J^T J: a body's centre moves with the
    heading of the frames it hangs from, and in axes turned with the heading its velocity
    has half the monomials (fewer products to form and reduce).  The angles tried are those
    the height does not depend on (a heading: turning about the vertical leaves the height
    alone), or all when there is none; J^T J is the same polynomial whichever is taken."""
    size = sum(len(p) for row in rows for p in row)
    angles = _angles(algebra, rows[0])
    best = rows
    for angle in (angles - _angles(algebra, rows[2])) or angles:
        x_row, y_row = _turn(algebra, rows[0], rows[1], angle, 1)
        turned_size = sum(len(p) for row in (x_row, y_row, rows[2]) for p in row)
        if turned_size < size:
            best, size = [x_row, y_row, rows[2]], turned_size
    return best


def _spun_back(
    algebra: TrigAlgebra, jac: list[list[Poly]], inertia: tuple[tuple[Backend, ...], ...]
) -> list[list[Poly]]:
    """The rows of J_w (omega_b = J_w q_dot) turned about an axis of symmetry of I by the
    angle (either way) that makes them shortest, (R J_w)^T I (R J_w) = J_w^T I J_w as
    R^T I R = I: a wheel's spin about its axle puts its sine and cosine into every monomial
    of the other two rows, which turned back by the spin have half as many.  The angles
    tried are those the axis' own row does not depend on (the spin leaves it alone)."""
    best, size = jac, sum(len(p) for row in jac for p in row)
    for i in range(3):
        j, k = (i + 1) % 3, (i + 2) % 3
        if inertia[j][j] != inertia[k][k] or any(
            inertia[a][b] != 0 for a, b in ((i, j), (i, k), (j, k))
        ):
            continue  # I is not symmetric about axis i
        for angle in (_angles(algebra, jac[j]) | _angles(algebra, jac[k])) - _angles(
            algebra, jac[i]
        ):
            for sign in (1, -1):
                row_j, row_k = _turn(algebra, jac[j], jac[k], angle, sign)
                turned_size = sum(len(p) for row in (jac[i], row_j, row_k) for p in row)
                if turned_size < size:
                    best, size = [[], [], []], turned_size
                    best[i], best[j], best[k] = jac[i], row_j, row_k
    return best


def _turn(
    algebra: TrigAlgebra, first: list[Poly], second: list[Poly], angle: Backend, sign: int
) -> tuple[list[Poly], list[Poly]]:
    """Two rows turned in their plane by ``sign`` * ``angle``: (c a + s b, -s a + c b)."""
    c, s = algebra.convert(se.cos(angle)), algebra.convert(sign * se.sin(angle))
    minus_s = algebra.scale(s, se.Integer(-1))
    one = [
        algebra.add([algebra.multiply(c, a), algebra.multiply(s, b)]) for a, b in zip(first, second)
    ]
    other = [
        algebra.add([algebra.multiply(minus_s, a), algebra.multiply(c, b)])
        for a, b in zip(first, second)
    ]
    return [algebra.finish(p) for p in one], [algebra.finish(p) for p in other]


def _angles(algebra: TrigAlgebra, row: list[Poly]) -> set[Backend]:
    """The moving angles whose sines or cosines appear in a row of polynomials."""
    return {
        algebra.gens[i].args[0]
        for p in row
        for key in p
        for i in key[::2]
        if algebra.moving[i] and (algebra.sine[i] or algebra.cosine[i])
    }


def _jacobian_row(algebra: TrigAlgebra, x: Backend, q: tuple[Backend, ...]) -> list[Poly]:
    converted = algebra.convert(x)
    return [algebra.finish(algebra.derivative(converted, s)) for s in q]


def _rotation_parts(
    algebra: TrigAlgebra, rotation: Rotation, asm: Assembly
) -> dict[tuple[int, int], list[Poly]]:
    """The parts of J_w^T I J_w (omega_b = J_w q_dot) for the upper triangle of M, by entry:
    I_ab (J_aj J_bk + J_bj J_ak) for a < b, I_aa J_aj J_ak."""
    n, inertia = len(asm.q), rotation.inertia
    jac = [
        [algebra.finish(algebra.convert(se.expand(w.diff(v)))) for v in asm.q_dot]
        for w in rotation.angular_velocity
    ]
    jac = _spun_back(algebra, jac, inertia)
    parts: dict[tuple[int, int], list[Poly]] = defaultdict(list)
    for a in range(3):
        for b in range(a, 3):
            if inertia[a][b] == 0:
                continue
            weight = algebra.convert(inertia[a][b])
            for j in range(n):
                for k in range(j, n):
                    terms = [algebra.multiply(jac[a][j], jac[b][k])]
                    if a != b:
                        terms.append(algebra.multiply(jac[b][j], jac[a][k]))
                    term = algebra.add(terms)
                    if term:
                        parts[j, k].append(algebra.multiply(weight, term))
    return parts


def _christoffel(algebra: TrigAlgebra, mass: list[list[Poly]], asm: Assembly) -> list[Poly]:
    """(C q_dot)_j = sum_k (dM_jk/dq_k - dM_kk/dq_j / 2) q_dot_k^2
    + sum_(k<l) (dM_jk/dq_l + dM_jl/dq_k - dM_kl/dq_j) q_dot_k q_dot_l."""
    n = len(asm.q)
    slope: dict[tuple[int, int, int], Poly] = {}
    # an entry of M has a few of the coordinates (a bicycle's, 3 of 8): the rest give zero
    used = {(j, k): algebra.symbols(mass[j][k]) for j in range(n) for k in range(j, n)}

    def d(j: int, k: int, ell: int) -> Poly:
        key = (min(j, k), max(j, k), ell)
        if key not in slope:
            q = asm.q[ell]
            slope[key] = algebra.derivative(mass[j][k], q) if q in used[key[:2]] else {}
        return slope[key]

    rates = [next(iter(algebra.convert(v))) for v in asm.q_dot]
    half = se.Rational(-1, 2)
    result = []
    for j in range(n):
        parts: dict[Key, list[Backend]] = defaultdict(list)
        for k in range(n):
            for ell in range(k, n):
                pair = algebra.multiply_keys(rates[k], rates[ell])
                if k == ell:
                    algebra.accumulate(parts, d(j, k, k), pair)
                    algebra.accumulate(parts, d(k, k, j), pair, half)
                else:
                    algebra.accumulate(parts, d(j, k, ell), pair)
                    algebra.accumulate(parts, d(j, ell, k), pair)
                    algebra.accumulate(parts, d(k, ell, j), pair, -1)
        result.append(algebra.gather(parts))
    return result
