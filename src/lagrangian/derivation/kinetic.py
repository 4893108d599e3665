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

from collections.abc import Iterator
from dataclasses import dataclass, field
from fractions import Fraction

import symengine as se

from lagrangian.derivation.assemble import Assembly, InertialPoint, Rotation, frames_carried
from lagrangian.derivation.backend import Backend
from lagrangian.derivation.collect import collect_state, is_negative_number, product_powers
from lagrangian.derivation.coriolis import EntrySplit, VelocityProduct, coriolis_products
from lagrangian.derivation.trig import combine_trig, plain_angle
from lagrangian.derivation.trig_polynomial import (
    ONE,
    Coefficient,
    Key,
    Number,
    Poly,
    PolynomialTooLarge,
    Sum,
    TrigAlgebra,
    algebra_for,
)

Matrix = list[list[Backend]]
#: The products of two columns in an entry of M: product -> (the set of holders that have
#: it, the ids of the first pair of columns that made it)
Groups = dict[Backend, tuple[int, tuple[int, int]]]

_ZERO = se.Integer(0)  # compared with as it is (0 would be converted at each comparison)
_UNIT = se.Integer(1)  # the number 1 (ONE is the key of the constant monomial)


@dataclass(frozen=True)
class KineticForm:
    """M(q, t) (or M(q, q_dot, t) for a T that is not quadratic), C q_dot, time terms and T."""

    mass_matrix: Matrix
    #: C q_dot, one sum per row; None when :attr:`coriolis_products` holds it by monomial
    #: (:func:`coriolis_vector` sums them: the forcing of a chain takes them as they are)
    coriolis: list[Backend] | None
    time_terms: list[Backend]
    kinetic_energy: Backend
    quadratic: bool
    #: True when M and C q_dot were built as polynomials grouped by monomial, or kept nested
    #: (3-D bodies): :func:`lagrangian.derivation.trig.combine_and_collect` tidies what is
    #: made of them at once (it knows their monomials, or that they stay nested).
    grouped: bool = False
    #: The terms of each row of C q_dot, each monomial once, when M is a planar chain's
    #: (:func:`lagrangian.derivation.coriolis.coriolis_products`); else None.
    coriolis_products: tuple[tuple[VelocityProduct, ...], ...] | None = None
    #: The Jacobian columns M was summed from, when it was (planar points and bodies): a
    #: uniform gravity's forces are read off them (:meth:`PointColumns.gravity_forces`).
    point_columns: PointColumns | None = None


def _hessian(expr: Backend, symbols: tuple[Backend, ...]) -> Matrix:
    first = [expr.diff(s) for s in symbols]
    # the derivatives of 0 are 0 (T given only through points and bodies)
    return [[f.diff(s) for s in symbols] if f != _ZERO else [f] * len(symbols) for f in first]


def _point_terms(
    asm: Assembly, explicit: Matrix, memo: EntryMemo
) -> tuple[
    Matrix,
    Backend,
    set[tuple[int, int]],
    set[tuple[int, int]],
    _ColumnTable,
    dict[tuple[int, int], EntrySplit],
]:
    """sum m J^T J (+ I g^T g), the kinetic terms of degree 0 and 1 in the velocities, the
    entries that are one combined product times a sum of weights or collected already
    (where T's ``explicit`` Hessian adds nothing, :meth:`_ColumnTable.split`), those
    that are several such products sharing their one sine or cosine
    (:func:`one_trigonometric_factor`), the table of the columns, and the entries made of
    planar columns as (w, cos(a - b), the parts w is the product of): C q_dot's products
    take them as they are made (:func:`~lagrangian.derivation.coriolis.coriolis_products`).

    The weights of each combined column product are summed before they multiply it: a chain's
    entry is l_j l_k (m_k + ... + m_n) cos(theta_j - theta_k), never grown term by term; a
    column that recurs (link j's in every point beyond it) is met by number, not compared."""
    n = len(asm.q)
    low_degree = se.Integer(0)
    table = _ColumnTable(n)
    index = {q: i for i, q in enumerate(asm.q)}
    slopes: dict[Backend, list[tuple[int, Backend]]] = {}
    for point in asm.points:
        columns = [(point.mass, point.position)]
        if point.angle is not None and point.inertia != 0:
            columns.append((point.inertia, (point.angle,)))
        for weight, coordinates in columns:
            jac = [_gradient(x, index, slopes) for x in coordinates]
            table.add(weight, jac, coordinates is point.position)
            drift = [x.diff(asm.t) for x in coordinates]
            if any(d != 0 for d in drift):
                moving = [se.Add(*[row[k] * asm.q_dot[k] for k in range(n)]) for row in jac]
                low_degree += weight * se.Add(*[v * d for v, d in zip(moving, drift)])
                low_degree += weight * se.Add(*[d**2 for d in drift]) / 2
    mass = [[se.Integer(0)] * n for _ in range(n)]
    single: set[tuple[int, int]] = set()
    shared: set[tuple[int, int]] = set()  # products that differ only in their coefficient
    combined: dict[Backend, Backend] = {}  # the same column pairs recur for every point below
    state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
    splits: dict[tuple[int, int], EntrySplit] = {}
    for j in range(n):
        for k in range(j, n):
            groups = table.pair_groups(j, k, combined)
            if not groups:
                continue
            # the products in the order the holders first meet them, each times the sum of
            # its holders' weights in their order: the entry as summed holder by holder
            ordered = sorted(groups.items(), key=lambda group: group[1][0] & -group[1][0])
            if not asm.rotations and explicit[j][k] == _ZERO:  # the entry is M's as made
                split = table.split([group for _, group in ordered], state, memo)
                if split is not None:
                    mass[j][k] = split[1] * split[0]
                    splits[j, k] = split
                    single.add((j, k))
                    continue
            mass[j][k] = se.Add(*[table.weight_sum(group[0]) * c for c, group in ordered])
            if len(groups) == 1 and not ordered[0][0].is_Add:
                single.add((j, k))
            elif one_trigonometric_factor([c for c, _ in ordered]):
                shared.add((j, k))
    for rotation in asm.rotations:
        low_degree += _rotation_terms(rotation, asm, mass, combined)
        single.clear()
        shared.clear()
    return mass, low_degree, single, shared, table, splits


def one_trigonometric_factor(products: list[Backend]) -> bool:
    """Whether every product is a plain product (numbers, symbols and their powers) times the
    same sine or cosine of a plain angle (or all times none): a chain of rods, whose link
    columns differ between a rod's own centre (l_k / 2) and the rods below (l_k), has two
    such products in an entry of M, l_j l_k cos(theta_j - theta_k) / 2 and l_j l_k
    cos(theta_j - theta_k), each times its sum of masses."""
    shared = None
    for index, product in enumerate(products):
        trig = None
        for factor in product.args if product.is_Mul else (product,):
            if isinstance(factor, (se.sin, se.cos)) and trig is None:
                trig = factor
            elif not (factor.is_Symbol or factor.is_Number or _symbol_power(factor)):
                return False
        if index == 0:
            shared = trig
        elif trig != shared:
            return False
    return shared is None or plain_angle(shared.args[0])


def collected_entry(entry: Backend, state: set[Backend], memo: EntryMemo | None = None) -> Backend:
    """An entry of M whose products share one sine or cosine (:func:`one_trigonometric_factor`)
    collected now, as the mass matrix's tidying would collect it, when that makes it one
    product: its sum of masses is then one factor in C q_dot (never n terms each); else
    combined as any other entry.  ``memo`` remembers what :func:`_collected_products` finds
    across the entries of one M (:class:`EntryMemo`)."""
    collected = _collected_products(entry, state, EntryMemo() if memo is None else memo)
    if collected is None:
        collected = collect_state(se.expand(entry), state)
    return collected if collected.is_Mul else combine_trig(entry)


#: What the collection of an expanded sum of masses needs of it: the least exponent of each
#: base in every term, the magnitudes of the terms' numbers, whether all are negative and
#: whether all are positive, and how many terms it has.
_SumPowers = tuple[dict[Backend, Backend], set[Backend], bool, bool, int]


@dataclass
class EntryMemo:
    """What :func:`collected_entry` finds once for all the entries of one M: each sum of
    masses read off (its :data:`_SumPowers`, or None), and each coefficient left inside
    the common factor expanded (or None when its terms combine), by the products it is
    made of: the sums recur in n entries each."""

    sums: dict[Backend, _SumPowers | None] = field(default_factory=dict)
    insides: dict[tuple[tuple[Backend, Backend | None], ...], Backend | None] = field(
        default_factory=dict
    )
    #: the collected sums of (column radius, holders) pairs (:meth:`_ColumnTable.split`)
    columns: dict[tuple[tuple[Backend, int], ...], Backend | None] = field(default_factory=dict)

    def sum_powers(self, factor: Backend, state: set[Backend]) -> _SumPowers | None:
        """:func:`_sum_powers` of ``factor``, read off once."""
        if factor not in self.sums:
            self.sums[factor] = _sum_powers(factor, state)
        return self.sums[factor]


def _sum_powers(factor: Backend, state: set[Backend]) -> _SumPowers | None:
    """The :data:`_SumPowers` of a sum of plain products free of the state, else None."""
    if not state.isdisjoint(factor.free_symbols):
        return None
    split = []
    for term in factor.args if factor.is_Add else (factor,):
        factors = term.args if term.is_Mul else (term,)
        if not all(f.is_Symbol or f.is_Number or _symbol_power(f) for f in factors):
            return None
        split.append(product_powers(list(factors)))
    common = dict(split[0][1])
    for _, powers in split[1:]:
        _keep_least(common, powers)
    magnitudes = {abs(number) for number, _ in split}
    negative = all(is_negative_number(number) for number, _ in split)
    positive = all(not is_negative_number(number) for number, _ in split)
    return common, magnitudes, negative, positive, len(split)


def _keep_least(common: dict[Backend, Backend], powers: dict[Backend, Backend]) -> None:
    """Keep in ``common`` the bases also in ``powers``, each at the lesser exponent."""
    for base, least in list(common.items()):
        exponent = powers.get(base)
        if exponent is None:
            del common[base]
        else:
            common[base] = min(least, exponent)


def _collected_products(entry: Backend, state: set[Backend], memo: EntryMemo) -> Backend | None:
    """``collect_state(se.expand(entry), state)`` for an entry that is a sum of products, each
    a number, parameters, one sine or cosine of the state shared by all (or none in any:
    a rod's diagonal entry l_k^2 (m_k / 3 + m_(k+1) + ... + m_n), one monomial still), and
    at most one sum of parameter products (a sum of masses), whose expanded terms all
    differ; else None.

    Collecting the expanded entry walks its terms in Python, n per entry of a chain of rods
    and n^3/6 in all; here each sum of masses is read once (``memo``), an entry by its few
    products, and the expansion is SymEngine's.  The collection of one monomial is its
    coefficient's common factor (each base's least exponent over the terms, the numbers'
    one magnitude, negative when every number is) times the terms divided by it, which is
    the value built here; SymEngine's sums and products are canonical, so it is the same
    expression."""
    trig = None
    # (the plain factors, their number and powers, the sum or None, the sum's powers or None)
    products = []
    for term in entry.args if entry.is_Add else (entry,):
        plain, sum_factor, summed = [], None, None
        for factor in term.args if term.is_Mul else (term,):
            if isinstance(factor, (se.sin, se.cos)) and (trig is None or factor == trig):
                trig = factor
            elif factor.is_Add and sum_factor is None:
                sum_factor, summed = factor, memo.sum_powers(factor, state)
                if summed is None:
                    return None
            elif factor.is_Symbol or factor.is_Number or _symbol_power(factor):
                plain.append(factor)
            else:
                return None
        number, powers = product_powers(plain)
        if not state.isdisjoint(powers):
            return None
        products.append((plain, number, powers, sum_factor, summed))
    if not products or (trig is not None and state.isdisjoint(trig.free_symbols)):
        return None
    collected = _collected_sum(products, memo)
    if collected is None or trig is None:  # no trigonometry: a rod's diagonal entry
        return collected
    return trig * collected


#: A product of an entry as :func:`_collected_products` reads it: its plain factors, their
#: number and powers, its sum of masses (or None) and that sum's :data:`_SumPowers` (or None).
_Product = tuple[
    list[Backend], Backend, dict[Backend, Backend], Backend | None, "_SumPowers | None"
]


def _collected_sum(products: list[_Product], memo: EntryMemo) -> Backend | None:
    """The sum of ``products`` collected (the common factor times the expanded rest), or None
    when two of its expanded terms combine."""
    common: dict[Backend, Backend] | None = None
    magnitudes: set[Backend] = set()
    negative = True
    for _, number, powers, _, summed in products:
        own = dict(powers)
        if summed is None:
            magnitudes.add(abs(number))
            negative = negative and is_negative_number(number)
        else:
            for base, least in summed[0].items():
                own[base] = own[base] + least if base in own else least
            magnitudes.update(abs(number) * m for m in summed[1])
            negative = negative and (summed[3] if is_negative_number(number) else summed[2])
        if common is None:
            common = own
        else:
            _keep_least(common, own)
    scale = magnitudes.pop() if len(magnitudes) == 1 else se.Integer(1)
    if negative:
        scale = -scale
    outside = scale * se.Mul(*[b**e for b, e in (common or {}).items()])
    # the expanded coefficient divided by its common factor: its terms, one per term of the
    # expanded entry unless two combined (then the entry is collected from its expansion).
    # The same for every entry of a column of a chain of rods (l_j l_k is the common factor,
    # m_k / 2 + m_(k+1) + ... + m_n what is left): expanded once (``insides``), not n times
    parts = tuple((se.Mul(*plain) / outside, sum_factor) for plain, _, _, sum_factor, _ in products)
    if parts not in memo.insides:
        expanded = se.expand(
            se.Add(
                *[
                    part * (_UNIT if sum_factor is None else sum_factor)
                    for part, sum_factor in parts
                ]
            )
        )
        expected = sum(1 if summed is None else summed[4] for *_, summed in products)
        whole = len(expanded.args if expanded.is_Add else (expanded,)) == expected
        memo.insides[parts] = expanded if whole else None
    inside = memo.insides[parts]
    return None if inside is None else outside * inside


def _symbol_power(factor: Backend) -> bool:
    return bool(factor.is_Pow and factor.args[0].is_Symbol and factor.args[1].is_Number)


class _ColumnTable:
    """The columns of the weighted Jacobians (a point's position with its mass, a planar
    body's angle with its inertia: the holders, numbered in the order of the points), each
    distinct column once, and for each coordinate which holders have which column there.

    A set of holders is an int with bit h for holder h, so the holders of a column pair are
    one ``&`` of two such sets: a chain's link j column is held by every point beyond link j,
    and M_jk sums the weights of the n - max(j, k) points that hold both columns, n^3/6
    weights in all if met point by point.  Each distinct set of holders sums its weights once
    (:meth:`weight_sum`), in the holders' order, as the points are met."""

    def __init__(self, n: int) -> None:
        self.weights: list[Backend] = []  # by holder
        self.ids: list[list[int]] = []  # by holder: the column id at each coordinate (-1: 0)
        self.columns: dict[tuple[Backend, ...], int] = {}  # column -> id
        self.by_id: list[tuple[Backend, ...]] = []  # id -> column
        self.polar: list[tuple[Backend, Backend] | None] = []  # by id: (r, a) or None
        self.holders: list[dict[int, int]] = [{} for _ in range(n)]  # coordinate -> id -> set
        self.moving: list[int] = [0] * n  # coordinate -> holders with a column that is not 0
        self.positions = 0  # the holders that are points' positions (weighed by their masses)
        self.products: dict[tuple[int, int], Backend | None] = {}  # (id, id) -> product
        self.sums: dict[int, Backend] = {}  # set of holders -> sum of their weights
        # (a, b) -> cos(a - b): a rod's centre and the joint below it share their angle
        self.cosines: dict[tuple[Backend, Backend], Backend] = {}

    def add(self, weight: Backend, jac: list[list[Backend]], position: bool) -> None:
        """Add a holder of weight ``weight`` whose Jacobian has rows ``jac``; ``position``:
        whether it is a point's position (else a planar body's angle)."""
        bit = 1 << len(self.weights)
        self.weights.append(weight)
        if position:
            self.positions |= bit
        ids = []
        zero = (_ZERO,) * len(jac)
        for j, column in enumerate(zip(*jac)):
            if column == zero:  # the zeros of _gradient are _ZERO itself: told apart at once
                ids.append(-1)
                continue
            id_j = self.columns.setdefault(column, len(self.columns))
            if id_j == len(self.by_id):  # a new column
                self.by_id.append(column)
                self.polar.append(_polar_column(list(column)))
            ids.append(id_j)
            self.holders[j][id_j] = self.holders[j].get(id_j, 0) | bit
            self.moving[j] |= bit
        self.ids.append(ids)

    def pair_groups(self, j: int, k: int, combined: dict[Backend, Backend]) -> Groups:
        """The products of columns j and k of the holders that move with both (0 left out),
        each with the set of holders that have it and the ids of the first pair of columns
        that made it."""
        both = self.moving[j] & self.moving[k]
        groups: Groups = {}
        if not both:
            return groups
        at_j, at_k = self.holders[j], self.holders[k]
        if len(at_j) * len(at_k) <= both.bit_count():  # few distinct columns: pair them
            for id_j, with_j in at_j.items():
                for id_k, with_k in at_k.items():
                    shared = with_j & with_k
                    if shared:
                        self._group(groups, id_j, id_k, shared, combined)
        else:  # a column of its own in most holders (relative angles): holder by holder
            for holder in _members(both):
                ids = self.ids[holder]
                self._group(groups, ids[j], ids[k], 1 << holder, combined)
        return groups

    def _group(
        self,
        groups: Groups,
        id_j: int,
        id_k: int,
        holders: int,
        combined: dict[Backend, Backend],
    ) -> None:
        key = (id_j, id_k)
        if key not in self.products:
            self.products[key] = _column_product(
                self.by_id[id_j],
                self.by_id[id_k],
                self.polar[id_j],
                self.polar[id_k],
                combined,
                self.cosines,
            )
        product = self.products[key]
        if product is not None:
            known = groups.get(product)
            groups[product] = (holders, key) if known is None else (known[0] | holders, known[1])

    def split(
        self, groups: list[tuple[int, tuple[int, int]]], state: set[Backend], memo: EntryMemo
    ) -> EntrySplit | None:
        """The entry of M summed from ``groups`` (holders, column ids) as (w, cos(a - b), the
        parts w is the product of), collected as :func:`collected_entry` collects it, made
        from the columns without reading the entry back; None when its columns are not such.

        When every pair of columns is planar, r_j (cos a, sin a) and s_i (cos b, sin b) with
        the same r_j, a and b, the entry is r_j cos(a - b) sum_i s_i (the masses of holders
        i).  One pair (a chain of particles): w = r_j s_1 (the masses), as summed.  Several
        (with r_j a product of parameters with no number): the sum is collected once for
        all the entries with the same s_i and holders (``memo``), a chain of rods' column k,
        l_k (m_k / 2 + m_(k+1) + ... + m_n), in every entry M_jk with j < k.  The common
        factor of the whole is r_j times the sum's (r_j is in every product, with no number
        to change the numbers' magnitudes), what is left inside is the same: the same
        expression."""
        first, first_k = self.polar[groups[0][1][0]], self.polar[groups[0][1][1]]
        if first is None or first_k is None:
            return None
        radius, angle = first
        sides = []
        for holders, (id_j, id_k) in groups:
            at_k = self.polar[id_k]
            if at_k is None or at_k[1] != first_k[1] or self.polar[id_j] != first:
                return None
            sides.append((at_k[0], holders))
        cosine = self.cosines[angle, first_k[1]]
        if not isinstance(cosine, se.cos):
            return None
        if len(sides) == 1:
            weight = self.weight_sum(sides[0][1])
            return radius * sides[0][0] * weight, cosine, (radius, sides[0][0], weight)
        if not _numberless_parameters(radius, state):
            return None
        key = tuple(sides)
        if key not in memo.columns:
            memo.columns[key] = self._collected_sides(sides, state, memo)
        inner = memo.columns[key]
        return None if inner is None else (radius * inner, cosine, (radius, inner))

    def _collected_sides(
        self, sides: list[tuple[Backend, int]], state: set[Backend], memo: EntryMemo
    ) -> Backend | None:
        """sum_i s_i (the masses of holders i) collected (:func:`_collected_sum`), or None."""
        products: list[_Product] = []
        for radius, holders in sides:
            weight = self.weight_sum(holders)
            plain = list(radius.args if radius.is_Mul else (radius,))
            sum_factor, summed = None, None
            if weight.is_Add:
                sum_factor, summed = weight, memo.sum_powers(weight, state)
                if summed is None:
                    return None
            else:
                plain += weight.args if weight.is_Mul else (weight,)
            if not all(f.is_Symbol or f.is_Number or _symbol_power(f) for f in plain):
                return None
            number, powers = product_powers(plain)
            if not state.isdisjoint(powers):
                return None
            products.append((plain, number, powers, sum_factor, summed))
        return _collected_sum(products, memo)

    def weight_sum(self, holders: int) -> Backend:
        """The sum of the weights of a set of holders, in their order."""
        if holders not in self.sums:
            self.sums[holders] = se.Add(*[self.weights[h] for h in _members(holders)])
        return self.sums[holders]


def _numberless_parameters(product: Backend, state: set[Backend]) -> bool:
    """Whether a plain product has no number among its factors and no state symbol."""
    for factor in product.args if product.is_Mul else (product,):
        if factor.is_Number or (factor.args[0] if factor.is_Pow else factor) in state:
            return False
    return True


def _members(holders: int) -> Iterator[int]:
    """The holders in a set (an int, bit h for holder h), in increasing order."""
    while holders:
        lowest = holders & -holders
        yield lowest.bit_length() - 1
        holders ^= lowest


@dataclass(frozen=True)
class PointColumns:
    """The columns M was summed from (:class:`_ColumnTable`), with what collected its
    entries."""

    table: _ColumnTable
    memo: EntryMemo
    state: set[Backend]

    def gravity_forces(self, gravity: list[Backend]) -> list[Backend]:
        """G = dV/dq of the gravity potential V = -sum_p m_p g . r_p of the points (g the
        vector ``gravity``): G_k = -sum_c (g . c) (the masses of the points whose position
        has the column c at q_k, summed), over the distinct columns c at q_k.

        The sums are those M's entries were made with (a chain's G_k = g l_k (m_k + ... +
        m_n) sin(theta_k), read off the column of link k), where expanding V and
        differentiating it term by term builds its n^2/2 terms; products that share their
        sine or cosine (a rod's centre and the joints below it) are collected as M's entries
        are (:func:`collected_entry`), with the same sums of masses."""
        table = self.table
        forces = []
        for at_k in table.holders:
            products = []
            for id_k, holders in at_k.items():
                masses = holders & table.positions
                if not masses:
                    continue
                slope = se.expand(se.Add(*[g * c for g, c in zip(gravity, table.by_id[id_k])]))
                if slope == _ZERO:
                    continue
                weight = table.weight_sum(masses)
                products += [(-term, weight) for term in (slope.args if slope.is_Add else (slope,))]
            force = se.Add(*[term * weight for term, weight in products])
            if len(products) > 1 and one_trigonometric_factor([term for term, _ in products]):
                force = _collected_products(force, self.state, self.memo) or force
            forces.append(force)
        return forces


def _column_product(
    first: tuple[Backend, ...],
    second: tuple[Backend, ...],
    first_polar: tuple[Backend, Backend] | None,
    second_polar: tuple[Backend, Backend] | None,
    combined: dict[Backend, Backend],
    cosines: dict[tuple[Backend, Backend], Backend],
) -> Backend | None:
    """The product of two Jacobian columns, trigonometry combined; None when it is 0.

    Two planar columns (r cos a, r sin a) and (s cos b, s sin b) give r s cos(a - b) at once,
    which is what :func:`combine_trig` makes of r s (cos a cos b + sin a sin b): a chain has
    n^2/2 of them (``cosines`` keeps each cos(a - b))."""
    if first_polar is not None and second_polar is not None:
        (r, angle_a), (s, angle_b) = first_polar, second_polar
        cosine = cosines.get((angle_a, angle_b))
        if cosine is None:
            cosine = cosines[angle_a, angle_b] = se.cos(angle_a - angle_b)
        return r * s * cosine
    term = se.Add(*[x * y for x, y in zip(first, second)])
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


def _gradient(
    expr: Backend, index: dict[Backend, int], slopes: dict[Backend, list[tuple[int, Backend]]]
) -> list[Backend]:
    """[d expr/ds for s in the symbols numbered by ``index``], a sum differentiated term by
    term by the symbols each term has (a chain's position has one term per link); ``slopes``
    keeps each term's derivatives (point p's position has the terms of those before it)."""
    terms = expr.args if expr.is_Add else (expr,)
    parts: list[list[Backend]] = [[] for _ in index]
    for term in terms:
        if term not in slopes:
            slopes[term] = [(index[s], term.diff(s)) for s in term.free_symbols if s in index]
        for i, slope in slopes[term]:
            parts[i].append(slope)
    return [(p[0] if len(p) == 1 else se.Add(*p)) if p else _ZERO for p in parts]


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
    """Terms of degree 0 and 1 in the velocities of an expression at most quadratic in them
    (a velocity it does not have gives the term 0, which adds nothing to the sum)."""
    at_rest = {v: 0 for v in asm.q_dot}
    present = expr.free_symbols
    return expr.subs(at_rest) + se.Add(
        *[v * expr.diff(v).subs(at_rest) for v in asm.q_dot if v in present]
    )


def _coriolis(mass: Matrix, asm: Assembly) -> list[Backend]:
    """(C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l, each entry of the
    upper triangle differentiated only by the coordinates it has."""
    n = len(asm.q)
    index = {q: ell for ell, q in enumerate(asm.q)}
    rows: list[list[Backend]] = [[] for _ in range(n)]
    v = asm.q_dot
    known = _FreeSymbols()
    half = se.Rational(1, 2)
    for j in range(n):
        for k in range(j, n):
            entry = mass[j][k]
            factors = entry.args if entry.is_Mul else (entry,)
            symbols = [known[f] for f in factors]
            rests: dict[int, Backend] = {}
            # the coordinates in the order of the set of all the entry's symbols
            for q in filter(index.__contains__, set().union(*symbols)):
                ell = index[q]
                slope = _slope(entry, factors, symbols, q, rests)
                rows[j].append(slope * v[k] * v[ell])
                if j != k:
                    rows[k].append(slope * v[j] * v[ell])
                term = -slope * v[j] * v[k]  # times 1 (j != k) would give it back as it is
                rows[ell].append(term if j != k else term * half)
    return [se.Add(*row) for row in rows]  # expanded and tidied by the caller


def _slope(
    entry: Backend,
    factors: tuple[Backend, ...],
    symbols: list[set[Backend]],
    q: Backend,
    rests: dict[int, Backend],
) -> Backend:
    """d entry/dq, ``entry`` the product of ``factors`` (whose free symbols are ``symbols``).

    A product with one factor f in q (a chain's l_j l_k (m_k + ... + m_n) cos(theta_j -
    theta_k)) is (the rest) f': SymEngine differentiates a product factor by factor, and of
    a factor free of q it gets 0 and skips it, so for f it puts f''s coefficient and factors
    into the rest's, as a product rest * f' does (f' not a number), the same expression;
    this way the rest (a sum of n masses) is not differentiated term by term to 0.  The
    rests are kept in ``rests`` by factor (an entry is differentiated by each of its
    coordinates, often held by one factor)."""
    holding = [i for i, s in enumerate(symbols) if q in s]
    if entry.is_Mul and len(holding) == 1:
        i = holding[0]
        if i not in rests:
            rests[i] = se.Mul(*factors[:i], *factors[i + 1 :])
        change = factors[i].diff(q)
        if rests[i].is_Mul and not factors[i].is_Pow and not change.is_Number:
            return rests[i] * change
    return entry.diff(q)


class _FreeSymbols(dict[Backend, set[Backend]]):
    """The free symbols of each factor looked up, each found once (sums of masses recur)."""

    def __missing__(self, factor: Backend) -> set[Backend]:
        self[factor] = symbols = factor.free_symbols
        return symbols


def kinetic_form(asm: Assembly) -> KineticForm:
    """Mass matrix, Coriolis vector, time terms and T of an assembled system."""
    n = len(asm.q)
    explicit = _hessian(asm.explicit_kinetic, asm.q_dot)
    velocities = set(asm.q_dot)
    quadratic = all(
        e == _ZERO or velocities.isdisjoint(e.free_symbols) for row in explicit for e in row
    )
    if not quadratic:
        return _general_form(asm)
    # 3-D bodies: grouped trigonometric polynomials; planar points and bodies (a chain of
    # links) are summed per combined column product, each sum of weights once
    structured = _structured_form(asm, explicit) if asm.rotations else None
    if structured is not None:
        return structured
    memo = EntryMemo()
    point_mass, point_low, single, shared, table, splits = _point_terms(asm, explicit, memo)
    mass = [[se.Integer(0)] * n for _ in range(n)]
    state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
    for j in range(n):
        for k in range(j, n):
            if explicit[j][k] == _ZERO and (j, k) in single:  # combined already
                mass[j][k] = point_mass[j][k]
            elif explicit[j][k] == _ZERO and (j, k) in shared:
                mass[j][k] = collected_entry(point_mass[j][k], state, memo)
            else:
                mass[j][k] = combine_trig(explicit[j][k] + point_mass[j][k])
            mass[k][j] = mass[j][k]
    low = _linear_part(asm.explicit_kinetic, asm) + point_low
    quadratic_t = _quadratic_form(mass, asm.q_dot)
    # an entry without t has no derivative by t (every entry of a chain on a fixed pivot);
    # its term, 0, would add nothing to the sum
    timed = (
        {(j, k) for j in range(n) for k in range(j, n) if mass[j][k].has(asm.t)}
        if _made_with_time(asm)
        else set()
    )
    time_terms = []
    for j in range(n):
        explicit_time = (
            se.Add(
                *[
                    mass[j][k].diff(asm.t) * asm.q_dot[k]
                    for k in range(n)
                    if (min(j, k), max(j, k)) in timed
                ]
            )
            if timed
            else se.Integer(0)
        )
        # no terms of degree 0 and 1 in the velocities (T = 1/2 q_dot^T M q_dot): none of theirs
        low_terms = (
            asm.time_derivative(low.diff(asm.q_dot[j])) - low.diff(asm.q[j])
            if low != 0
            else se.Integer(0)
        )
        time_terms.append(se.expand(explicit_time + low_terms))
    products = coriolis_products(mass, asm, splits)
    coriolis = _coriolis(mass, asm) if products is None else None
    return KineticForm(
        mass,
        coriolis,
        time_terms,
        quadratic_t + low,
        True,
        coriolis_products=products,
        point_columns=PointColumns(table, memo, state),
    )


def coriolis_vector(kinetic: KineticForm) -> list[Backend]:
    """C q_dot of ``kinetic``, one sum per row (summed from its products when it is held by
    monomial)."""
    if kinetic.coriolis is not None:
        return kinetic.coriolis
    if kinetic.coriolis_products is None:
        raise ValueError("a kinetic form without C q_dot")  # never made by kinetic_form
    return [se.Add(*[product.term for product in row]) for row in kinetic.coriolis_products]


def _made_with_time(asm: Assembly) -> bool:
    """Whether t is in what M is made of: T's explicit part, the points' masses, positions,
    angles and inertias, the bodies' inertias and angular velocities (M is made of them, their
    derivatives by the coordinates and velocities and the products of those, and combining
    their trigonometry brings in no symbol).  One look at each, not at each entry of M."""
    parts = [asm.explicit_kinetic]
    for point in asm.points:
        parts += [point.mass, point.inertia, *point.position]
        parts += [] if point.angle is None else [point.angle]
    for rotation in asm.rotations:
        parts += [*rotation.angular_velocity, *(e for row in rotation.inertia for e in row)]
    return any(part.has(asm.t) for part in parts)


def _quadratic_form(mass: Matrix, q_dot: tuple[Backend, ...]) -> Backend:
    """1/2 q_dot^T M q_dot for a symmetric M, the same sum as the double sum over j and k:
    there the terms jk and kj (M_kj is M_jk) are one term, kept where jk (j < k) put it, whose
    coefficient is the sum of the two halves (exactly the whole, in floating point too), so
    here it is taken once whole, in that place."""
    n = len(q_dot)
    return se.Add(
        *[
            mass[j][k] * q_dot[j] * q_dot[k] / 2 if j == k else mass[j][k] * q_dot[j] * q_dot[k]
            for j in range(n)
            for k in range(j, n)
        ]
    )


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
    if not asm.rotations:
        return None
    # compared with SymEngine's zero and substituted by one dict of its zeros: Python's 0,
    # in the comparisons and in a dict made for each component, is converted at each use
    # (half the time of these checks)
    t, at_rest = asm.t, {v: _ZERO for v in asm.q_dot}
    if any(x.diff(t) != _ZERO for point in asm.points for x in point.position) or any(
        w.diff(t) != _ZERO or w.subs(at_rest) != _ZERO
        for rotation in asm.rotations
        for w in rotation.angular_velocity
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
    for expr in [*coriolis_vector(nested), *(e for row in nested.mass_matrix for e in row)]:
        algebra.keep_nested(expr)
    return nested


def _canonical_form(asm: Assembly, explicit: Matrix, algebra: TrigAlgebra) -> KineticForm | None:
    """M and C q_dot as reduced polynomials grouped by monomial; None for a small system
    (the entry-by-entry :func:`combine_trig` is cheap there, and reads best)."""
    n = len(asm.q)
    # (weight, rows of the Jacobian, the point whose centre they move or None for a planar
    # body's angle) whose J^T J enter M
    weighted: list[tuple[Backend, list[list[Poly]], InertialPoint | None]] = []
    for point in asm.points:
        coordinates = point.position
        if point.angle is not None and point.inertia != 0:
            weighted.append((point.inertia, [_jacobian_row(algebra, point.angle, asm.q)], None))
        rows = [_jacobian_row(algebra, x, asm.q) for x in coordinates]
        weighted.append((point.mass, rows, point))
    products = sum(sum(len(p) for p in row) ** 2 for _, rows, _ in weighted for row in rows)
    if products <= STRUCTURED_PRODUCTS:
        return None
    if products > NESTED_PRODUCTS:
        raise PolynomialTooLarge(f"{products} products of Jacobian monomials")
    # every body's share of an entry is summed into one polynomial (:class:`Sum`): no
    # polynomial per body, row or pair of axes
    shares = [[Sum() for _ in range(n)] for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            shares[j][k].add(algebra.convert(explicit[j][k]))
    for weight, rows, centre in weighted:
        frames = [rows] if centre is None else _point_axes(algebra, rows, centre, asm.q)
        for rows, entries in _entries_by_frame(frames):
            _add_gram(algebra, shares, algebra.convert(weight), rows, rows, entries)
    for rotation in asm.rotations:
        _add_rotation_share(algebra, shares, rotation, asm)
    mass_poly: list[list[Poly]] = [[{} for _ in range(n)] for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            mass_poly[j][k] = algebra.gather(shares[j][k])
    mass = [[se.Integer(0)] * n for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            mass_poly[j][k] = mass_poly[k][j] = algebra.finish(mass_poly[j][k])
            mass[j][k] = mass[k][j] = algebra.grouped(algebra.shortest(mass_poly[j][k]))
    quadratic_t = _quadratic_form(mass, asm.q_dot)
    # each row as sum over pairs q_dot_k q_dot_l times its symbol: the symbols' monomials
    # recur across rows and pairs, so their expressions are mostly made already
    symbols = _christoffel_symbols(algebra, mass_poly, asm)
    coriolis = [algebra.products_expression(row) for row in symbols]
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
    quadratic_t = _quadratic_form(mass, asm.q_dot)
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


def _point_axes(
    algebra: TrigAlgebra, rows: list[list[Poly]], point: InertialPoint, q: tuple[Backend, ...]
) -> list[list[list[Poly]]]:
    """The rows of a point's Jacobian in world axes, then in the axes of each frame it hangs
    from when they are known, else in the axes :func:`_turned` finds (a 3-D point), else
    as they are: J^T J is the same in each, and each entry is formed in the axes where it
    has the fewest products (:func:`_entries_by_frame`)."""
    carried = frames_carried(point.orientation, point.position, q)
    if carried:
        return _frames(algebra, rows, carried)
    turned = _turned(algebra, rows) if len(rows) == 3 else rows
    return [rows] if turned is rows else [rows, turned]


def _frames(
    algebra: TrigAlgebra, rows: list[list[Poly]], turns: tuple[tuple[int, Backend], ...]
) -> list[list[list[Poly]]]:
    """The rows of a point's Jacobian in world axes and in the axes of each frame its
    centre hangs from, (R^T J)^T R^T J = J^T J for R = R_1(a_1) ... R_m(a_m) the leading
    rotations of its body's chain (:func:`lagrangian.derivation.assemble.frames_carried`):
    R_i^T turns the two rows across axis i, one rotation after another.  In the last
    frame the centre's velocity has the monomials of its offset there (a bicycle's fork: 72
    in all against 107 in axes turned by the heading alone, 176 in world axes)."""
    frames = [rows]
    for axis, angle in turns:
        j, k = (axis + 1) % 3, (axis + 2) % 3
        rows = list(rows)
        rows[j], rows[k] = _turn(algebra, rows[j], rows[k], angle, 1)
        frames.append(rows)
    return frames


def _entries_by_frame(
    frames: list[list[list[Poly]]],
) -> list[tuple[list[list[Poly]], set[tuple[int, int]]]]:
    """The rows of each of ``frames`` (one point's Jacobian in several axes) with the
    entries (j, k), j <= k, of J^T J to form in them: those whose products of monomials,
    sum_r len(J_rj) len(J_rk), are fewest there (the last frame's when several tie).

    A translation's column is (1, 0, 0) in world axes and R^T (1, 0, 0) in a body's, whose
    products with the other columns cancel by sin^2 + cos^2 = 1 (M_xx = m from 3 rows of
    products): a bicycle's entries in x and y are fewest in world axes, the rest in the
    frames of the heading, the lean or the pitch (12 % fewer products than all in the last
    frame)."""
    n = len(frames[0][0])
    sizes = [[[len(p) for p in row] for row in rows] for rows in frames]
    chosen: list[set[tuple[int, int]]] = [set() for _ in frames]
    for j in range(n):
        for k in range(j, n):
            costs = [sum(row[j] * row[k] for row in rows) for rows in sizes]
            best = len(costs) - 1
            for at in range(best - 1, -1, -1):
                if costs[at] < costs[best]:
                    best = at
            if costs[best]:
                chosen[best].add((j, k))
    return [(rows, entries) for rows, entries in zip(frames, chosen) if entries]


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
    minus_s = algebra.scale(s, -1)
    one = [_combination(algebra, c, a, s, b) for a, b in zip(first, second)]
    other = [_combination(algebra, minus_s, a, c, b) for a, b in zip(first, second)]
    return one, other


def _combination(algebra: TrigAlgebra, f: Poly, a: Poly, g: Poly, b: Poly) -> Poly:
    """f a + g b, finished: both products summed into one polynomial (no polynomial made for
    each product and summed again)."""
    total = Sum()
    algebra.accumulate_product(total, f, a)
    algebra.accumulate_product(total, g, b)
    return algebra.finish(algebra.gather(total))


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
    """dx/dq of each coordinate, differentiated only by the coordinates x has (a bicycle's
    centres have 5 of its 8): by any other every monomial's derivative is 0."""
    converted = algebra.convert(x)
    moving = algebra.symbols(converted)
    return [algebra.finish(algebra.derivative(converted, s)) if s in moving else {} for s in q]


def _add_gram(
    algebra: TrigAlgebra,
    shares: list[list[Sum]],
    weight: Poly,
    first: list[list[Poly]],
    second: list[list[Poly]],
    entries: set[tuple[int, int]] | None = None,
) -> None:
    """Add weight * sum_r (first_rj second_rk + second_rj first_rk) (once when ``first`` is
    ``second``: weight J^T J) to the upper triangle of the entries' sums (those of
    ``entries`` only, when given).

    On the diagonal the two products of a pair of monomials are one product taken twice
    (first_rj second_rj and second_rj first_rj; in a square, x_a x_b and x_b x_a): each is
    formed once, with its weight doubled (:func:`_add_square`); the diagonal holds about half
    of a bicycle's products."""
    n = len(shares)
    if not weight:
        return
    if entries is None:
        entries = {(j, k) for j in range(n) for k in range(j, n)}
    pairs = list(zip(first, second))
    crossed = pairs + ([] if first is second else [(b, a) for a, b in pairs])
    scale = weight.get(ONE) if len(weight) == 1 else None
    if scale is None:  # a weight that moves (never a mass or an inertia)
        _add_moving_gram(algebra, shares, weight, crossed, entries)
        return
    twice = algebra.scale({ONE: scale}, 2)[ONE]
    # each row's monomials times the weight once, not once for every entry they meet
    columns = {j for j, k in entries if j != k}
    weighted = [
        ([algebra.scale(p, scale) if j in columns else p for j, p in enumerate(a)], b)
        for a, b in crossed
    ]
    for j, k in sorted(entries):
        target = shares[j][k]
        if j == k:
            for a, b in pairs:
                if a[j] and b[j]:
                    if first is second:
                        _add_square(algebra, target, a[j], scale, twice)
                    else:
                        algebra.accumulate_product(target, a[j], b[j], twice)
            continue
        for a, b in weighted:
            if a[j] and b[k]:
                algebra.accumulate_product(target, a[j], b[k])


def _add_square(
    algebra: TrigAlgebra, target: Sum, p: Poly, weight: Coefficient, twice: Coefficient
) -> None:
    """Add ``weight`` * p^2 to ``target``: the square of each monomial once, and each product
    of two different monomials once, with ``twice`` the weight (not once each way round)."""
    weighted = list(algebra.scale(p, weight).items())
    doubled = list(algebra.scale(p, twice).items())
    for i, (key, c) in enumerate(p.items()):
        algebra.accumulate(target, dict([weighted[i], *doubled[i + 1 :]]), key, c)


def _add_moving_gram(
    algebra: TrigAlgebra,
    shares: list[list[Sum]],
    weight: Poly,
    crossed: list[tuple[list[Poly], list[Poly]]],
    entries: set[tuple[int, int]],
) -> None:
    """:func:`_add_gram` for a weight that is a polynomial of the state, each product of
    the rows' pairs ``crossed`` (both ways round unless the rows are one) made and
    multiplied by it, in the ``entries`` (j, k)."""
    for j, k in sorted(entries):
        for a, b in crossed:
            if a[j] and b[k]:
                shares[j][k].add(algebra.multiply(weight, algebra.multiply(a[j], b[k])))


def _add_rotation_share(
    algebra: TrigAlgebra,
    shares: list[list[Sum]],
    rotation: Rotation,
    asm: Assembly,
) -> None:
    """Add J_w^T I J_w (omega_b = J_w q_dot) to the upper triangle of the entries' sums:
    I_ab (J_aj J_bk + J_bj J_ak) for a < b, I_aa J_aj J_ak."""
    inertia = rotation.inertia
    jac = [
        [algebra.finish(algebra.convert(se.expand(w.diff(v)))) for v in asm.q_dot]
        for w in rotation.angular_velocity
    ]
    jac = _spun_back(algebra, jac, inertia)
    for a in range(3):
        for b in range(a, 3):
            if inertia[a][b] != 0:
                rows = [jac[a]]
                weight = algebra.convert(inertia[a][b])
                _add_gram(algebra, shares, weight, rows, rows if a == b else [jac[b]])


def _christoffel(algebra: TrigAlgebra, mass: list[list[Poly]], asm: Assembly) -> list[Poly]:
    """The rows of C q_dot (:func:`_christoffel_symbols`) as polynomials."""
    rows = []
    for symbols in _christoffel_symbols(algebra, mass, asm):
        row = Sum()
        for pair, symbol in symbols:
            algebra.accumulate(row, symbol, pair)
        rows.append(algebra.gather(row))
    return rows


def _christoffel_symbols(
    algebra: TrigAlgebra, mass: list[list[Poly]], asm: Assembly
) -> list[list[tuple[Key, Poly]]]:
    """(C q_dot)_j = sum_k (dM_jk/dq_k - dM_kk/dq_j / 2) q_dot_k^2
    + sum_(k<l) (dM_jk/dq_l + dM_jl/dq_k - dM_kl/dq_j) q_dot_k q_dot_l,
    row by row as its (velocity pair, Christoffel symbol) pairs, the symbols not zero.

    Where j is k (or l) the last two derivatives are dM_jl/dq_j twice with opposite signs:
    the symbol is dM_jj/dq_l, taken as it is (2(n - 1) of the n(n + 1)/2 symbols of a row;
    summed out, they left 286 zero monomials in a bicycle's rows).  The symbols are
    finished: no zero coefficient."""
    n = len(asm.q)
    rates = [next(iter(algebra.convert(v))) for v in asm.q_dot]
    # the velocity products q_dot_k q_dot_l, the same in every row
    pairs = [
        (k, ell, algebra.multiply_keys(rates[k], rates[ell]))
        for k in range(n)
        for ell in range(k, n)
    ]
    slopes = _mass_slopes(algebra, mass, asm.q)
    half: Number = Fraction(-1, 2)
    result = []
    for j in range(n):
        at_j = slopes[j]
        row: list[tuple[Key, Poly]] = []
        for k, ell, pair in pairs:
            parts: tuple[tuple[Poly, Number], ...]
            if k == ell:
                parts = ((at_j[k][k], 1), (slopes[k][k][j], half))
            elif j == k:  # dM_jl/dq_j - dM_jl/dq_j cancel: dM_jj/dq_l is left
                parts = ((at_j[j][ell], 1),)
            elif j == ell:
                parts = ((at_j[j][k], 1),)
            else:
                parts = ((at_j[k][ell], 1), (at_j[ell][k], 1), (slopes[k][ell][j], -1))
            nonzero = [part for part in parts if part[0]]
            if not nonzero:  # most pairs of most rows (a bicycle's: 192 of 288)
                continue
            symbol = _symbol(algebra, nonzero)
            if symbol:
                row.append((pair, symbol))
        result.append(row)
    return result


def _mass_slopes(
    algebra: TrigAlgebra, mass: list[list[Poly]], q: tuple[Backend, ...]
) -> list[list[list[Poly]]]:
    """dM_jk/dq_l at [j][k][l] (one list for [j][k] and [k][j]), finished, {} where M_jk
    does not hold q_l (an entry of a bicycle's M has 3 of the 8 coordinates).  Each is a
    part of some Christoffel symbol (dM_jk/dq_l is one of row l's, pair (j, k)): made all
    at once, and read by index in the symbols' loop, not looked up by a key made per read."""
    n = len(q)
    slopes: list[list[list[Poly]]] = [[[] for _ in range(n)] for _ in range(n)]
    for j in range(n):
        for k in range(j, n):
            entry = mass[j][k]
            held = algebra.symbols(entry)
            slopes[j][k] = slopes[k][j] = [
                algebra.finish(algebra.derivative(entry, s)) if s in held else {} for s in q
            ]
    return slopes


def _symbol(algebra: TrigAlgebra, parts: list[tuple[Poly, Number]]) -> Poly:
    """The Christoffel symbol sum scale * dM/dq over ``parts``, summed before it multiplies
    its velocity pair: its monomials have no velocity, so pair times them are monomials of
    no other pair, and what cancels in a row cancels within one symbol (a fifth of a
    bicycle's monomials of C q_dot); so the cancelled monomials are never multiplied by
    the pair, nor written out as zero terms of the row's expression.

    Two parts that are one polynomial are one part with the sum of their scales (0: they
    cancel): a translation's column of M is a gradient, dM_xk/dq_l = dM_xl/dq_k, so the
    symbols of a bicycle's rows for yaw, lean, pitch and steer with the pairs of x or y are
    such differences, and the rows of x and y such sums (24 and 12 of its 51 symbols of two
    parts; one dict comparison, where summing them formed every term and cancelled it)."""
    if len(parts) == 2 and parts[0][0] == parts[1][0]:
        parts = [(parts[0][0], parts[0][1] + parts[1][1])]
    if len(parts) == 1:
        p, scale = parts[0]
        if scale == 0:
            return {}
        return p if scale == 1 else algebra.scale(p, scale)
    symbol = Sum()
    for p, scale in parts:
        symbol.add(p if scale == 1 else algebra.scale(p, scale))
    return algebra.finish(algebra.gather(symbol))
