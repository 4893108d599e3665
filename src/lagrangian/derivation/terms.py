"""The Euler–Lagrange terms of a System in the fast backend (SymEngine), computed once per
System object and shared by :func:`lagrangian.derive` and the views it offers on demand (the
steps, the Christoffel form of C).

    M = d2T/dq_dot2 - d2U/dq_dot2,    G = dV/dq,    -dF/dq_dot,
    velocity-potential forces = d/dt dU/dq_dot - dU/dq  (without their q_ddot part),
    forcing = Q - dF/dq_dot + (U forces) - C q_dot - time terms - G.

Every expression is tidied once (:func:`lagrangian.derivation.trig.combine_and_collect`) and
converted to SymPy through one :class:`~lagrangian.derivation.backend.SympyView`, whose memo
makes the shared subexpressions of M, the forcing and the steps one SymPy object each.

A sum of parameters that multiplies a term (the m_k + ... + m_n of a chain's link k) is tidied
and differentiated as one symbol (:meth:`EulerLagrangeTerms.compress`), so the work on the
equations of an n-link chain grows with their n^2 terms, not with the n^3 masses inside them.

``derive`` converts M and the forcing; the pieces the forcing is the sum of (C q_dot, G, the
time terms, ...) and the energies are converted when first read (:func:`matrix_piece`,
each once per System): a simulation reads none of them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.derivation.assemble import Assembly, assemble, gravity_potential
from lagrangian.derivation.backend import Backend, SympyView, vector_to_backend
from lagrangian.derivation.collect import (
    collect_state,
    collect_state_with,
    collected_coefficient,
    factor_common,
    numberless,
)
from lagrangian.derivation.coriolis import VelocityProduct
from lagrangian.derivation.kinetic import KineticForm, coriolis_vector, kinetic_form
from lagrangian.derivation.trig import (
    NESTED_CHECK_OPS,
    NESTED_TERMS,
    combine_and_collect,
    combine_trig,
    plain_angle,
    size,
)
from lagrangian.derivation.trig_polynomial import expanded_terms
from lagrangian.model import System
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.probe import depends_on
from lagrangian.symbolic.symbols import t

#: The fewest terms of a sum of parameters that :meth:`EulerLagrangeTerms.compress` keeps
#: whole: shorter ones are expanded with the rest, so a small system's equations read as the
#: expansion and collection write them (the order of their terms included).
LONG_SUM = 8

#: How many times its operations a potential's expansion may have terms for
#: :meth:`EulerLagrangeTerms.potential_gradient` to differentiate it expanded.
SPREAD = 4

#: What :meth:`EulerLagrangeTerms.compress` remembers of a sum that is not one of parameters.
_MOVING = se.Integer(0)

#: Kept while their System lives; they hold backend expressions, never the System itself.
_TERMS: IdentityCache[System, EulerLagrangeTerms] = IdentityCache()


def euler_lagrange_terms(system: System) -> EulerLagrangeTerms:
    """The backend terms of ``system``, computed once per System object."""
    return _TERMS.get(system, EulerLagrangeTerms)


class EulerLagrangeTerms:
    """M, the force vectors, the forcing and the coordinate orders of one System, in backend
    form and tidied; :meth:`sympy` converts any of them for the user."""

    def __init__(self, system: System) -> None:
        self.coordinates: tuple[sp.Symbol, ...] = tuple(system.coordinates)
        self.assembly: Assembly = assemble(system)
        self.kinetic: KineticForm = kinetic_form(self.assembly)
        self.view = SympyView([*system.coordinates, *system.parameters, t])
        asm = self.assembly
        self.state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
        self.rates = {asm.t: se.Integer(1), **dict(zip(asm.q, asm.q_dot))}
        self.rates.update(zip(asm.q_dot, asm.q_ddot))
        self._symbol_of_sum: dict[Backend, Backend] = {}
        self._sum_of_symbol: dict[Backend, Backend] = {}
        self._sums: dict[Backend, tuple[Backend, Backend]] = {}  # symbol -> (sum, factored)
        self._refactored = False  # whether a sum's factored form differs from it
        self._compressed: dict[Backend, Backend] = {}
        self._factors: dict[Backend, Backend] = {}  # collect_state's sorting of factors
        # the same for the expressions collected with no sums (none of their symbols in them)
        self._plain_factors: dict[Backend, Backend] = {}
        # of C q_dot's terms (:meth:`_product_collection`)
        self._coefficients: dict[Backend, tuple[int, Backend | None, Backend | None]] = {}
        self.velocity_potential_forces = self._velocity_potential_forces()
        self.mass = self._mass_matrix()
        # sums kept whole in M (a chain's m_k + ... + m_n) recur in C q_dot and G: keep them
        # whole there too; with none, looking for them would only cost time
        kept = any(
            f.is_Add for row in self.kinetic.mass_matrix for e in row if e.is_Mul for f in e.args
        )
        gravity = self._gravity_forces(system) if kept else None
        self.gravity = self.potential_gradient(asm.potential) if gravity is None else gravity
        self.dissipation_forces = [se.expand(-asm.dissipation.diff(v)) for v in asm.q_dot]
        tidy = self.tidy if kept else self._tidy_expanded
        products = self.kinetic.coriolis_products if kept else None
        self.forcing = []
        coriolis: list[Backend] | None = None  # summed when a row is tidied whole
        for j in range(len(asm.q)):
            rest = (
                asm.applied[j]
                + self.dissipation_forces[j]
                + self.velocity_potential_forces[j]
                - self.kinetic.time_terms[j]
                - self.gravity[j]
            )
            tidied = None if products is None else self._tidy_with(rest, products[j])
            if tidied is None:
                coriolis = coriolis or coriolis_vector(self.kinetic)
                tidied = tidy(rest - coriolis[j])
            self.forcing.append(tidied)
        self.orders = self._orders()

    def _tidy_with(self, rest: Backend, coriolis: tuple[VelocityProduct, ...]) -> Backend | None:
        """:meth:`tidy` of rest - C q_dot for the terms of C q_dot known by monomial
        (:func:`lagrangian.derivation.coriolis.coriolis_products`): the same expression,
        with the n terms of a chain's row taken as they are made (each coefficient collected
        once, :meth:`_collected_coefficient`) instead of expanded and collected with the
        rest; None when :meth:`tidy` would not expand the whole (a factor it cannot vouch
        for, or too many terms), or a monomial of C q_dot is also one of ``rest``'s."""
        monomials = []
        bound = 0
        for monomial, coefficient, number in coriolis:
            count, collected, part = self._collected_coefficient(-number, coefficient)
            bound += count
            monomials.append((monomial, collected, part))
        compact = self.compress(rest)
        if not self._sums:
            return None
        rest_bound = _plain_bound(compact, NESTED_TERMS)
        if rest_bound is None or rest_bound + bound >= NESTED_TERMS:
            return None
        return collect_state_with(
            se.expand(compact), monomials, self.state, self._sums, self._factors
        )

    def _collected_coefficient(
        self, number: Backend, coefficient: Backend
    ) -> tuple[int, Backend, Backend | None]:
        """(the terms of the expansion of number * ``coefficient`` with its long sums kept
        whole, counted as :func:`_plain_bound` counts them; the coefficient collect_state
        makes of those terms; that without its number, :func:`numberless`).  A product with
        no short sum to expand collects to number times what the product collects to, found
        once per coefficient (a chain's w_jk is in two rows of C q_dot)."""
        known = self._coefficients.get(coefficient)
        if known is None:
            known = self._coefficients[coefficient] = self._product_collection(coefficient)
        count, collected, numberless_part = known
        if collected is not None:
            return count, number * collected, numberless_part
        general = self._collected(se.expand(self.compress(number * coefficient)))
        return count, general, numberless(general)

    def _product_collection(
        self, coefficient: Backend
    ) -> tuple[int, Backend | None, Backend | None]:
        """(the count of :meth:`_collected_coefficient`; what ``coefficient`` collects to
        when it is one product once its long sums are symbols (:meth:`compress`), else None;
        that without its number).  The factors' sums are looked up, not compressed: a long
        sum is one symbol (a factor counted once), a short one is expanded with the rest."""
        if coefficient.is_Add:
            return len(self.compress(coefficient).args), None, None
        count = 1
        for factor in coefficient.args if coefficient.is_Mul else (coefficient,):
            if factor.is_Add and self._symbol_for(factor) is None:
                count *= len(factor.args)
        if count != 1:
            return count, None, None
        # one product collects to itself with its sums put back factored: the coefficient
        # as it came when no sum has a common factor to pull out
        collected = self._collected(self.compress(coefficient)) if self._refactored else coefficient
        return count, collected, numberless(collected)

    def _collected(self, coefficient: Backend) -> Backend:
        return collected_coefficient(coefficient, self.state, self._sums, self._factors)

    def _gravity_forces(self, system: System) -> list[Backend] | None:
        """G = dV/dq read off M's columns
        (:meth:`~lagrangian.derivation.kinetic.PointColumns.gravity_forces`) when V is a
        uniform gravity's alone and M was summed from the points' columns, of a chain of
        planar links (C q_dot held by monomial); else None."""
        asm, columns = self.assembly, self.kinetic.point_columns
        if system.gravity is None or columns is None or self.kinetic.coriolis_products is None:
            return None
        gravity = vector_to_backend(system.gravity)
        if asm.potential != gravity_potential(gravity, asm.points):  # springs, a potential
            return None
        return columns.gravity_forces(gravity)

    def _velocity_potential_forces(self) -> list[Backend]:
        """d/dt dU/dq_dot - dU/dq of each coordinate, without its q_ddot part; each 0 when U
        is a number (every derivative of it is 0, which the general path finds out by
        differentiating a zero 3n times per coordinate)."""
        asm = self.assembly
        u = asm.velocity_potential
        if u.is_Number:
            return [se.Integer(0) for _ in asm.q]
        at_rest = {a: 0 for a in asm.q_ddot}
        return [
            se.expand((asm.time_derivative(u.diff(v)) - u.diff(q)).subs(at_rest))
            for q, v in zip(asm.q, asm.q_dot)
        ]

    def tidy(self, expr: Backend) -> Backend:
        """Trigonometric products combined, terms grouped by state monomial (a single term,
        which neither can shorten, as it is: most entries of a mass matrix); sums of
        parameters that multiply a term are kept whole (:meth:`compress`)."""
        if not expr.is_Add and not any(arg.is_Add for arg in expr.args):
            if self._sums and not self._sums.keys().isdisjoint(expr.free_symbols):
                return collect_state(expr, self.state, self._sums, self._factors)  # sum back
            return expr
        if self.kinetic.grouped:  # 3-D bodies: reduced trigonometric polynomials, no long sums
            # (a compressed step, dL/dq_dot of a Lagrangian with long sums, has its sums back)
            return combine_and_collect(self.expand_sums(expr), self.state, self._plain_factors)
        return self.tidy_compressed(self.compress(expr))

    def _tidy_expanded(self, expr: Backend) -> Backend:
        """:meth:`tidy` of an expression with no sum to keep whole."""
        if not expr.is_Add and not any(arg.is_Add for arg in expr.args):
            return expr
        return combine_and_collect(expr, self.state, self._plain_factors)

    def tidy_compressed(self, compact: Backend) -> Backend:
        """:meth:`tidy` of an expression whose sums :meth:`compress` has written as symbols
        already (derivatives of a compressed one), with the sums put back."""
        if not self._sums:
            return combine_and_collect(compact, self.state, self._plain_factors)
        return collect_state(combined_trig(compact), self.state, self._sums, self._factors)

    def compress(self, expr: Backend) -> Backend:
        """``expr`` with every sum of parameters that multiplies one of its terms (of it, or
        of a sum it multiplies) written as one symbol, the same symbol for the same sum;
        ``expr`` itself when there is none.  :meth:`expand_sums` puts the sums back.

        A chain's m_k + ... + m_n is then one factor to expand, collect and differentiate,
        however many masses it holds."""
        known = self._compressed.get(expr)  # nested expressions share their subexpressions
        if known is not None:
            return known
        if expr.is_Mul:
            result = self._compress_product(expr)
        elif not expr.is_Add:
            result = expr
        else:
            args = expr.args  # the terms of a sum are never sums
            parts = [self._compress_product(a) if a.is_Mul else a for a in args]
            result = expr if all(n is o for n, o in zip(parts, args)) else se.Add(*parts)
        self._compressed[expr] = result
        return result

    def _compress_product(self, product: Backend) -> Backend:
        args = product.args
        parts: list[Backend] | None = None  # made when a factor changes (one pass over them)
        for i, factor in enumerate(args):
            if factor.is_Add:
                new = self._compress_factor(factor)
                if new is not factor:
                    parts = parts or list(args)
                    parts[i] = new
        return product if parts is None else se.Mul(*parts)

    def _compress_factor(self, factor: Backend) -> Backend:
        symbol = self._symbol_for(factor)
        return self.compress(factor) if symbol is None else symbol

    def _symbol_for(self, factor: Backend) -> Backend | None:
        """The symbol standing for ``factor`` when it is a long sum of parameters, else None."""
        symbol = self._symbol_of_sum.get(factor)
        if symbol is not None:
            return symbol if symbol is not _MOVING else None
        terms = factor.args
        # the cheap test first: the same answer as the free symbols' when it says moving
        if len(terms) < LONG_SUM or self._moving(terms) or not self._parameters(factor):
            self._symbol_of_sum[factor] = _MOVING
            return None
        symbol = se.Dummy("sum")
        self._symbol_of_sum[factor] = symbol
        whole = self.expand_sums(factor)
        self._sum_of_symbol[symbol] = whole
        factored = factor_common(list(whole.args)) if whole.is_Add else whole
        self._sums[symbol] = (whole, factored)
        self._refactored = self._refactored or factored != whole
        return symbol

    def _moving(self, terms: tuple[Backend, ...]) -> bool:
        """True when one of the first two terms of a sum (the first may be its number) has
        a state symbol (or its power) as a factor; False says nothing.  A sum of C q_dot,
        whose free symbols (the masses of every sum inside included) cost far more to
        gather than two terms' factors to look at."""
        for term in terms[:2]:
            for factor in term.args if term.is_Mul else (term,):
                base = factor.args[0] if factor.is_Pow else factor
                if base.is_Symbol and base in self.state:
                    return True
        return False

    def _parameters(self, factor: Backend) -> bool:
        """True when ``factor`` has no state symbol at all."""
        return self.state.isdisjoint(factor.free_symbols)

    def expand_sums(self, expr: Backend) -> Backend:
        """``expr`` with the symbols of :meth:`compress` replaced by their sums."""
        return expr.xreplace(self._sum_of_symbol) if self._sum_of_symbol else expr

    def gradient(self, expr: Backend, symbols: list[Backend]) -> list[Backend]:
        """[d expr/ds for s in symbols], a sum differentiated term by term, each term by the
        symbols it has only (a term of an n-link chain's L has four of the 2n).

        A number times a sum (the -V of L = T - V, whose n^2/2 terms of a chain hold every
        angle) is differentiated term by term as well, not whole by each of its symbols:
        the derivatives are the same sums, written out (every caller expands them)."""
        return _term_gradient(_distributed_terms(expr), symbols)

    def potential_gradient(self, potential: Backend) -> list[Backend]:
        """G = dV/dq.  A potential whose expansion has at most :data:`SPREAD` times as many
        terms as it has operations is expanded and differentiated term by term
        (:meth:`gradient`): a chain's V = -sum_i m_i g . r_i holds each link's height in the
        n - k points below link k, and differentiating it whole by each coordinate walks all
        n^2/2 of its terms n times (the tidying of the forcing expands each G_j anyway)."""
        q = list(self.assembly.q)
        ops = size(potential)
        if ops > NESTED_CHECK_OPS and expanded_terms(potential, SPREAD * ops) < SPREAD * ops:
            expanded = se.expand(potential)  # no term a number times a sum: none to distribute
            return _term_gradient(expanded.args if expanded.is_Add else (expanded,), q)
        return [potential.diff(s) for s in q]

    def time_derivative(self, expr: Backend) -> Backend:
        """d/dt by the chain rule, sum(de/dq q_dot + de/dq_dot q_ddot) + de/dt, term by term
        over the state symbols each term has."""
        parts = []
        for term in expr.args if expr.is_Add else (expr,):
            for s in term.free_symbols:
                rate = self.rates.get(s)
                if rate is not None:
                    parts.append(term.diff(s) * rate)
        return se.Add(*parts)

    def collect(self, expr: Backend) -> Backend:
        """The terms of an expression whose trigonometric products are combined already
        grouped by state monomial."""
        return collect_state(expr, self.state, factors=self._plain_factors) if expr.is_Add else expr

    def sympy(self, expr: Backend) -> sp.Expr:
        """``expr`` tidied and in SymPy, with the System's own symbols."""
        return self.view(self.tidy(expr))

    def sympy_expanded(self, expr: Backend) -> sp.Expr:
        """``sympy.expand`` of ``expr`` in SymPy (its sums put back), expanded first in the
        backend: the n^3 terms of a chain's expanded energy cost microseconds each there,
        milliseconds in SymPy.  SymPy's expand is then run only when a term has what
        SymEngine's leaves (functions of sums to expand, powers of sums, exponentials of
        sums): on a sum of plain terms it would rebuild each to find it unchanged."""
        converted = self.view(se.expand(self.expand_sums(expr)))
        terms = converted.args if converted.is_Add else (converted,)
        return converted if all(map(_plain_sympy_term, terms)) else sp.expand(converted)

    def sympy_vector(self, values: list[Backend]) -> sp.ImmutableMatrix:
        """Every entry tidied, as a SymPy column."""
        return self.view.vector([self.tidy(v) for v in values])

    def _mass_matrix(self) -> list[list[Backend]]:
        """M = d2T/dq_dot2 - d2U/dq_dot2 (symmetric: each entry tidied once)."""
        asm, kinetic, n = self.assembly, self.kinetic.mass_matrix, len(self.assembly.q)
        u_momentum = [asm.velocity_potential.diff(v) for v in asm.q_dot]
        mass = [[se.Integer(0)] * n for _ in range(n)]
        zero = se.Integer(0)
        for j in range(n):
            constant = u_momentum[j].is_Number  # no q_dot in dU/dq_dot_j (a chain has no U)
            for k in range(j, n):
                u_part = zero if constant else u_momentum[j].diff(asm.q_dot[k])
                if (constant or u_part == 0) and self.kinetic.quadratic:  # combined already
                    mass[j][k] = mass[k][j] = self.collect(kinetic[j][k])
                else:
                    mass[j][k] = mass[k][j] = self.tidy(kinetic[j][k] - u_part)
        return mass

    def _orders(self) -> dict[sp.Symbol, int]:
        """2 with inertia; without, 1 if the equation has velocities of such coordinates."""
        n = len(self.coordinates)
        inert = [j for j in range(n) if all(self.mass[j][k] == 0 for k in range(n))]
        inert_velocities = [self.assembly.q_dot[j] for j in inert]
        orders = {}
        for j, q in enumerate(self.coordinates):
            if j not in inert:
                orders[q] = 2
            else:
                orders[q] = 1 if depends_on(self.forcing[j], inert_velocities) else 0
        return orders


def _term_gradient(terms: Iterable[Backend], symbols: list[Backend]) -> list[Backend]:
    """[d(sum of ``terms``)/ds for s in symbols], each term differentiated by the symbols it
    has only."""
    index = {s: i for i, s in enumerate(symbols)}
    parts: list[list[Backend]] = [[] for _ in symbols]
    for term in terms:
        for s in term.free_symbols:
            i = index.get(s)
            if i is not None:
                parts[i].append(term.diff(s))
    return [se.Add(*p) for p in parts]


def _distributed_terms(expr: Backend) -> list[Backend]:
    """The terms of ``expr``, a number times a sum written as the number times each term."""
    terms = []
    for term in expr.args if expr.is_Add else (expr,):
        args: tuple[Backend, ...] = term.args if term.is_Mul else ()
        if len(args) == 2 and args[0].is_Number and args[1].is_Add:
            terms += [args[0] * inner for inner in args[1].args]
        else:
            terms.append(term)
    return terms


def combined_trig(expr: Backend) -> Backend:
    """:func:`~lagrangian.derivation.trig.combine_trig` of ``expr``, which is its expansion
    when no term of that has more than one sine or cosine (to the power 1) nor a multiple
    angle: the equations of a chain, whose every term has one sin(theta_j - theta_k) or
    cos(theta_j - theta_k).  combine_trig has no product of sines and cosines to combine,
    no square to reduce and no double angle to weigh in such a sum, and would only find
    that out (at a cost that grows with the terms, and more so beyond
    :data:`~lagrangian.derivation.trig.LARGE_POLYNOMIAL` of them).  As in combine_trig, an
    expression that would expand to :data:`~lagrangian.derivation.trig.NESTED_TERMS` terms
    or more is kept nested.

    Both questions are answered by one walk over ``expr`` when it can (:func:`_plain_bound`);
    the expansion is checked term by term only when the walk cannot tell."""
    bound = _plain_bound(expr, NESTED_TERMS)
    if bound is not None:
        if bound >= NESTED_TERMS and size(expr) > NESTED_CHECK_OPS:
            return expr
        return se.expand(expr)
    expanded = se.expand(expr)
    terms = expanded.args if expanded.is_Add else (expanded,)
    if not all(map(_at_most_one_plain_trig, terms)):
        return combine_trig(expr)
    if size(expr) > NESTED_CHECK_OPS and expanded_terms(expr, NESTED_TERMS) >= NESTED_TERMS:
        return expr
    return expanded


_TRIG = (se.sin, se.cos)


class _NotPlain(Exception):
    """Raised by :func:`_plain_bound`'s walk at a factor it cannot vouch for."""


def _plain_bound(expr: Backend, cap: int) -> int | None:
    """``expanded_terms(expr, cap)`` when every term of ``se.expand(expr)`` is one that
    :func:`_at_most_one_plain_trig` accepts, proven on the tree of ``expr``; None when the
    walk cannot prove it (the expansion is then checked).

    The proof: the leaves of ``expr`` (outside its sines and cosines, which expansion keeps
    as they are) are numbers, symbols, symbols to integer powers and sines and cosines of
    plain angles, and no product of ``expr`` multiplies more than one sine or cosine (a sum
    counts as its term with the most, a product as the total of its factors).  Every term
    of the expansion is a product of one term of each factor, down the tree: numbers,
    symbols and their integer powers (merged into the same kinds) and at most one sine or
    cosine, which is what the check accepts.  The bound is counted as expanded_terms counts
    it (a sum adds its terms' counts, a product multiplies its factors', a leaf counts 1,
    each capped at ``cap``), so the two are equal."""
    try:
        return _PlainWalk(cap).walk(expr)[0]
    except _NotPlain:
        return None


class _PlainWalk:
    """The walk of :func:`_plain_bound` (methods, not closures of each other: closures
    that call each other are a reference cycle, left to the collector at every call)."""

    def __init__(self, cap: int) -> None:
        self.cap = cap
        self.sums: dict[Backend, tuple[int, int]] = {}  # a sum shared by several terms once
        self.angles: dict[Backend, bool] = {}  # whether a sine or cosine is of a plain angle

    def total(self, e: Backend) -> tuple[int, int]:
        """(terms counted, most sines/cosines in a term) of a sum."""
        known = self.sums.get(e)
        if known is None:
            parts = [self.product(a) if a.is_Mul else self.walk(a) for a in e.args]
            known = (min(self.cap, sum(p[0] for p in parts)), max(p[1] for p in parts))
            self.sums[e] = known
        return known

    def product(self, e: Backend) -> tuple[int, int]:
        count, trig = 1, 0
        for factor in e.args:  # the leaves inline: a chain's terms are products of them
            if factor.is_Symbol or factor.is_Number:
                continue
            if factor.is_Add:
                terms, inner = self.total(factor)
                count, trig = min(self.cap, count * terms), trig + inner
            elif isinstance(factor, _TRIG):
                trig += self.plain_trig(factor)
            elif not _symbol_power(factor):
                raise _NotPlain
        if trig > 1:
            raise _NotPlain
        return count, trig

    def plain_trig(self, e: Backend) -> int:
        """1 for a sine or cosine of a plain angle."""
        plain = self.angles.get(e)
        if plain is None:
            plain = self.angles[e] = plain_angle(e.args[0])
        if not plain:
            raise _NotPlain
        return 1

    def walk(self, e: Backend) -> tuple[int, int]:
        if e.is_Add:
            return self.total(e)
        if e.is_Mul:
            return self.product(e)
        if e.is_Symbol or e.is_Number or _symbol_power(e):
            return 1, 0
        if isinstance(e, _TRIG):
            return 1, self.plain_trig(e)
        raise _NotPlain


def _symbol_power(factor: Backend) -> bool:
    """A symbol to an integer power."""
    if not factor.is_Pow:
        return False
    base, exponent = factor.args
    return bool(base.is_Symbol and exponent.is_Integer)


def _plain_sympy_term(term: sp.Expr) -> bool:
    """A SymPy product of numbers, symbols, symbols to integer powers and sines and cosines
    of plain sums (symbols times numbers, numbers): ``sympy.expand`` leaves it as it is."""
    return _plain_product(term, (sp.sin, sp.cos), _plain_sympy_angle, None)


def _plain_sympy_angle(angle: sp.Expr) -> bool:
    """A symbol, a number times a symbol, or a sum of such and numbers."""
    for term in angle.args if angle.is_Add else (angle,):
        if term.is_Number or term.is_Symbol:
            continue
        if not (term.is_Mul and len(term.args) == 2 and term.args[0].is_Number):
            return False
        if not term.args[1].is_Symbol:
            return False
    return True


def _at_most_one_plain_trig(term: Backend) -> bool:
    """A product of numbers, symbols, integer powers of symbols and at most one sine or
    cosine of a sum of symbols each with coefficient +-1."""
    return _plain_product(term, (se.sin, se.cos), plain_angle, 1)


def _plain_product(
    term: Any, trig: tuple[Any, ...], angle: Callable[[Any], bool], most: int | None
) -> bool:
    """A product (SymPy's or SymEngine's: both name their kinds alike) of numbers, symbols,
    integer powers of symbols and sines and cosines (the types ``trig``) whose arguments
    ``angle`` accepts, at most ``most`` of those (None: any number, and integer powers of
    them too)."""
    count = 0
    for factor in term.args if term.is_Mul else (term,):
        if factor.is_Number or factor.is_Symbol:
            continue
        if factor.is_Pow:
            base, exponent = factor.args
            if not exponent.is_Integer:
                return False
            # a power of a sine or cosine (cos(pitch)**2 of a body's inertia) is left as it
            # is by expand too, when the trigonometric factors are not counted
            trig_power = most is None and isinstance(base, trig) and angle(base.args[0])
            if not (base.is_Symbol or trig_power):
                return False
        elif isinstance(factor, trig) and angle(factor.args[0]):
            count += 1
            if most is not None and count > most:
                return False
        else:
            return False
    return True


#: How each piece of :func:`matrix_piece` is made from the backend terms.
PIECES: dict[str, Callable[[EulerLagrangeTerms], sp.Basic]] = {
    "kinetic_energy": lambda terms: terms.sympy(terms.kinetic.kinetic_energy),
    "potential_energy": lambda terms: terms.sympy(terms.assembly.potential),
    "velocity_potential": lambda terms: terms.sympy(terms.assembly.velocity_potential),
    "dissipation_function": lambda terms: terms.sympy(terms.assembly.dissipation),
    "coriolis": lambda terms: terms.sympy_vector(coriolis_vector(terms.kinetic)),
    "time_terms": lambda terms: terms.sympy_vector(terms.kinetic.time_terms),
    "gravity": lambda terms: terms.sympy_vector(terms.gravity),
    "generalized_forces": lambda terms: terms.sympy_vector(list(terms.assembly.applied)),
    "dissipation_forces": lambda terms: terms.sympy_vector(terms.dissipation_forces),
    "velocity_potential_forces": lambda terms: terms.sympy_vector(terms.velocity_potential_forces),
}

_PIECES: IdentityCache[System, dict[str, sp.Basic]] = IdentityCache()


def matrix_piece(system: System, name: str) -> Any:
    """One of T, V, U, F (``"kinetic_energy"``, ...) or of the vectors whose sum is the
    forcing (``"coriolis"``, ``"gravity"``, ...; the keys of :data:`PIECES`) of ``system``
    in SymPy, tidied; each computed once per System, when first asked for."""
    pieces = _PIECES.get(system, lambda _: {})
    if name not in pieces:
        pieces[name] = PIECES[name](euler_lagrange_terms(system))
    return pieces[name]


_CORIOLIS_MATRICES: IdentityCache[System, sp.ImmutableMatrix] = IdentityCache()


def coriolis_matrix(system: System) -> sp.ImmutableMatrix:
    """C with C_jk = sum_l Gamma_jkl q_dot_l, Gamma_jkl = (dM_jk/dq_l + dM_jl/dq_k -
    dM_kl/dq_j) / 2 the Christoffel symbols of the kinetic M; computed once per System."""
    return _CORIOLIS_MATRICES.get(system, _christoffel_form)


def _christoffel_form(system: System) -> sp.ImmutableMatrix:
    terms = euler_lagrange_terms(system)
    asm, mass, n = terms.assembly, terms.kinetic.mass_matrix, len(terms.coordinates)
    rows = []
    for j in range(n):
        row = []
        for k in range(n):
            entry = se.Integer(0)
            for ell in range(n):
                gamma = (
                    mass[j][k].diff(asm.q[ell])
                    + mass[j][ell].diff(asm.q[k])
                    - mass[k][ell].diff(asm.q[j])
                ) / 2
                entry += gamma * asm.q_dot[ell]
            row.append(terms.tidy(entry))
        rows.append(row)
    return terms.view.matrix(rows)
