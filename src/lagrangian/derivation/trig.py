"""Combine trigonometric products early (issue: "structure, not brute force").

Mass-matrix entries built as sums of m J^T J contain products such as
cos a cos b + sin a sin b.  Writing every product of sines and cosines as a sum of single
sines and cosines of combined angles (product-to-sum, the "Fourier form") is canonical for
trigonometric polynomials, so identities such as sin^2 + cos^2 = 1 or
cos a cos b + sin a sin b = cos(a - b) collapse by ordinary term collection, without a
general-purpose simplify.  :func:`combine_trig` keeps whichever form is shortest; it is the
one trigonometric tidying of the package, on backend expressions (:func:`combine_and_collect`
also groups the terms by state monomial) or on SymPy ones (:func:`combine_trig_sympy`).

The Fourier form of a product of d sines and cosines has 2**(d-1) terms, which 3-D bodies
turned by chains of rotations reach quickly (d = 6 to 12).  Beyond a budget of product-to-sum
terms the Fourier form is not tried; the products stay as they are and only
sin^2 + cos^2 = 1 is applied, as the polynomial reduction modulo s^2 + c^2 - 1 of every angle
(:func:`pythagorean_forms`): linear in the number of terms, and canonical for polynomials in
the sines and cosines of independent angles, so identities such as R^T R = 1 still cancel.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.derivation.backend import SympyView, to_backend
from lagrangian.derivation.collect import collect_pairs, collect_state
from lagrangian.derivation.trig_polynomial import (
    FACTORED_TERMS,
    PolynomialTooLarge,
    algebra_for,
    expanded_terms,
    pairs,
)
from lagrangian.symbolic.conversion import to_sympy

MAX_TRIG_DEGREE = 8  # beyond this a term is left as it is (2**(d-1) Fourier terms)
#: Product-to-sum terms (sum of 2**(d-1) over the terms of degree d >= 2) beyond which
#: :func:`combine_trig` does not try the Fourier form (see the module docstring) ...
FOURIER_BUDGET = 256
#: ... nor when a term has more sines and cosines than this: the angle sums of such products
#: (cos(a + b - c) ...) read worse than the products, which sin^2 + cos^2 = 1 shortens as well.
FOURIER_DEGREE = 3
#: Terms beyond which :func:`combine_trig` weighs no forms: it writes cos^2 as 1 - sin^2 and
#: stops (weighing costs more than the reduction on the equations of long chains).
LONG_EXPRESSION = 2000
#: Terms beyond which :func:`combine_and_collect` reduces an expression as a polynomial
#: grouped by monomial (the Fourier form, whose budget is far smaller, is out of reach).
LARGE_POLYNOMIAL = 400
#: Monomials beyond which :func:`combine_and_collect` leaves an expression nested as it is
#: (the equations of long chains of bodies turned relative to each other).
NESTED_MONOMIALS = 1500
#: Terms of the expanded form (an upper bound counted on the tree) beyond which
#: :func:`combine_trig` leaves an expression nested.
NESTED_TERMS = 200_000
#: Operations (SymEngine's count, cheap) from which :func:`combine_trig` counts those terms.
NESTED_CHECK_OPS = 2000


def _trig_factors(term: Any) -> list[Any] | None:
    """The sine and cosine factors of a product, each repeated by its power; None when a
    trig power is not a small positive integer or there are too many."""
    trig: list[Any] = []
    for factor in term.args if term.is_Mul else (term,):
        base, power = factor.args if factor.is_Pow else (factor, None)
        if isinstance(base, (se.sin, se.cos)):
            count = 1 if power is None else int(power) if power.is_Integer else 0
            if not 0 < count <= MAX_TRIG_DEGREE:
                return None
            trig.extend([base] * count)
    return trig if len(trig) <= MAX_TRIG_DEGREE else None


def _coefficient(term: Any) -> Any:
    """The product of the factors of ``term`` that are not powers of sines and cosines."""
    factors = term.args if term.is_Mul else (term,)
    return se.Mul(
        *[f for f in factors if not isinstance(f.args[0] if f.is_Pow else f, (se.sin, se.cos))]
    )


def _product_to_sum(a: Any, b: Any) -> list[tuple[Any, Any]]:
    """(coefficient, trig) pairs with a*b = sum(coefficient * trig)."""
    x, y = a.args[0], b.args[0]
    # SymEngine keeps theta - (psi - theta) nested: expanded, equal angles meet and collect
    difference, total = se.expand(x - y), se.expand(x + y)
    half = se.Rational(1, 2)
    if isinstance(a, se.cos) and isinstance(b, se.cos):
        return [(half, se.cos(difference)), (half, se.cos(total))]
    if isinstance(a, se.sin) and isinstance(b, se.sin):
        return [(half, se.cos(difference)), (-half, se.cos(total))]
    if isinstance(a, se.cos):  # sin y cos x = (sin(y + x) + sin(y - x)) / 2
        return [(half, se.sin(total)), (-half, se.sin(difference))]
    return [(half, se.sin(total)), (half, se.sin(difference))]


def _linearize(trig: list[Any]) -> list[tuple[Any, Any]]:
    """Product of trig factors as a list of (coefficient, single trig or 1)."""
    if not trig:
        return [(se.Integer(1), se.Integer(1))]
    terms = [(se.Integer(1), trig[0])]
    for factor in trig[1:]:
        new = []
        for coefficient, current in terms:
            if current == 1:
                new.append((coefficient, factor))
                continue
            for c, f in _product_to_sum(current, factor):
                number, single = _as_single(f)
                if number != 0:
                    new.append((coefficient * c * number, single))
        terms = new
    return terms


def _as_single(value: Any) -> tuple[Any, Any]:
    """(number, sin/cos or 1) from what a product-to-sum step gives: SymEngine evaluates
    sin(0) to 0, cos(0) to 1 and sin(-x) to -sin(x)."""
    if value.is_Number:
        return value, se.Integer(1)
    if value.is_Mul:
        number = se.Mul(*[a for a in value.args if a.is_Number])
        rest = se.Mul(*[a for a in value.args if not a.is_Number])
        return number, rest
    return se.Integer(1), value


def fourier_form(expr: Any) -> Any:
    """Every product of sines and cosines rewritten as a sum of single sines and cosines
    (``expr`` expanded when it has no such product)."""
    return _fourier_of_expanded(se.expand(expr))


def _fourier_of_expanded(expanded: Any) -> Any:
    """:func:`fourier_form` of an expanded expression: ``expanded`` itself (the same object)
    when no term has two or more trig factors."""
    terms = expanded.args if expanded.is_Add else (expanded,)
    factors = [_trig_factors(term) for term in terms]
    if all(trig is None or len(trig) < 2 for trig in factors):
        return expanded
    collected: dict[Any, Any] = defaultdict(lambda: se.Integer(0))
    for term, trig in zip(terms, factors):
        if trig is None or len(trig) < 2:
            collected[se.Integer(1)] += term
            continue
        coefficient = _coefficient(term)
        for c, f in _linearize(trig):
            collected[f] += coefficient * c
    return se.Add(*[se.expand(c) * f for f, c in collected.items()])


def _multiple_angles(expr: Any) -> bool:
    """True when some sin/cos argument contains a symbol with a coefficient other than +-1."""
    return any(_multiple_angle(atom) for atom in _trig_atoms(expr))


def _multiple_angle(atom: Any) -> bool:
    """True when the argument of the sin/cos ``atom`` itself (not a trig function inside it)
    has a term with a coefficient other than +-1."""
    argument = se.expand(atom.args[0])
    for term in argument.args if argument.is_Add else (argument,):
        if term.is_Mul and term.args[0].is_Number and abs(term.args[0]) != 1:
            return True
    return False


def _trig_atoms(expr: Any) -> set[Any]:
    return set(expr.atoms(se.sin, se.cos))


def size(expr: Any) -> int:
    """The number of operations in ``expr`` (SymEngine's count_ops)."""
    return int(se.count_ops(expr))


def combine_and_collect(expr: Any, state: Any, factors: dict[Any, Any] | None = None) -> Any:
    """:func:`combine_trig`, then the terms grouped by their monomial in ``state`` with the
    parameter coefficients factored (:func:`lagrangian.derivation.collect.collect_state`;
    ``factors`` remembers how it sorted each factor across the calls with the same
    ``state``, as its own ``factors`` does: the equations of a system share their factors).

    An expression of more than :data:`LARGE_POLYNOMIAL` terms (the equations of 3-D
    multibody systems) is reduced modulo sin^2 + cos^2 = 1 as a polynomial grouped by
    monomial (:mod:`lagrangian.derivation.trig_polynomial`), never expanded as a whole: the
    shorter of its two canonical forms, which is what :func:`combine_trig` chooses between
    for such expressions, too (the Fourier form is not tried beyond its budget).

    A sum with nothing to combine (:func:`_single_trig_expansion`) is collected at once."""
    state = state if isinstance(state, (set, frozenset)) else set(state)
    expanded = _single_trig_expansion(expr, state)
    if expanded is not None:
        return collect_state(expanded, state, factors=factors)
    algebra = algebra_for(state)
    algebra.limit = NESTED_MONOMIALS
    try:
        polynomial = algebra.finish(algebra.convert(expr))
    except PolynomialTooLarge:
        return expr  # kept nested: expanded, it would be larger still
    finally:
        algebra.limit = None
    if algebra.terms(polynomial) <= LARGE_POLYNOMIAL:
        return collect_state(combine_trig(expr), state, factors=factors)
    grouped, pairs = algebra.grouped_terms(algebra.shortest(polynomial))
    if pairs is None:
        return collect_state(grouped, state, factors=factors)
    return collect_pairs(grouped, pairs)


def _single_trig_expansion(expr: Any, state: set[Any] | frozenset[Any]) -> Any | None:
    """The expansion of ``expr`` when it is a sum with nothing to combine
    (:func:`_single_trig_monomials`), else None.  Only a shallow ``expr`` is expanded: terms
    each with at most one sum among their factors, itself of terms with no sum among theirs
    (-(C q_dot) and the like), so the expansion grows no longer than the tree; the general
    route keeps an expression nested when its expansion would reach ``NESTED_TERMS`` terms,
    and so does this one."""
    terms = expr.args if expr.is_Add else (expr,)
    spread, nested = 0, False
    for term in terms:
        sums = [f for f in term.args if f.is_Add] if term.is_Mul else []
        if not sums:
            spread += 1
            continue
        if len(sums) > 1 or any(g.is_Mul and any(h.is_Add for h in g.args) for g in sums[0].args):
            return None
        spread += len(sums[0].args)
        nested = True
    if spread >= NESTED_TERMS:
        return None
    expanded = se.expand(expr) if nested else expr
    return expanded if _single_trig_monomials(expanded, state) else None


def _single_trig_monomials(expr: Any, state: set[Any] | frozenset[Any]) -> bool:
    """True when ``expr`` is a sum of products of numbers, parameters, positive integer
    powers of state symbols and at most one sine or cosine (to the power 1) of a plain angle
    (symbols with coefficients +-1), with at most :data:`NESTED_MONOMIALS` monomials and, past
    :data:`LARGE_POLYNOMIAL` terms, at most ``FACTORED_TERMS`` terms under each state
    monomial: the equations of a chain of particles.

    For such a sum :func:`combine_and_collect` is :func:`collect_state` of ``expr`` itself,
    and finding that out by converting it to a trigonometric polynomial costs the most of its
    tidying.  Why: ``expr`` is expanded already (SymEngine's sum of such products combines
    like terms as it forms), no term has a product or a square of sines and cosines, and no
    angle is a multiple, so :func:`combine_trig` has no Fourier, Pythagorean or half-angle
    form to weigh and returns ``expr``; the polynomial has a monomial per distinct product of
    state symbols and sines and cosines, and none of its partial sums cancels (the terms of a
    canonical sum differ), so it outgrows no limit that the whole does not; past
    ``LARGE_POLYNOMIAL`` terms its two Pythagorean forms are itself, and
    :meth:`~lagrangian.derivation.trig_polynomial.TrigAlgebra.grouped` factors each state
    monomial's coefficient as collect_state does when it has at most ``FACTORED_TERMS``
    terms."""
    terms = expr.args if expr.is_Add else (expr,)
    monomials: set[Any] = set()
    per_state_monomial: dict[Any, int] = defaultdict(int)
    for term in terms:
        moving: list[Any] = []
        trig = None
        for factor in term.args if term.is_Mul else (term,):
            if factor.is_Number:
                continue
            if factor.is_Symbol:
                if factor in state:
                    moving.append(factor)
                continue
            if factor.is_Pow:
                base, exponent = factor.args
                if not base.is_Symbol:
                    return False
                if base in state:
                    if not (exponent.is_Integer and exponent > 0):
                        return False
                    moving.append(factor)
                continue
            if trig is not None or not isinstance(factor, (se.sin, se.cos)):
                return False
            if not plain_angle(factor.args[0]):
                return False
            trig = factor
        key = se.Mul(*moving)
        monomials.add((key, trig))
        if trig is not None and not state.isdisjoint(trig.args[0].free_symbols):
            key = key * trig
        per_state_monomial[key] += 1
    if len(monomials) > NESTED_MONOMIALS:
        return False
    return len(terms) <= LARGE_POLYNOMIAL or max(per_state_monomial.values()) <= FACTORED_TERMS


_UNITS = (se.Integer(1), se.Integer(-1))


def plain_angle(angle: Any) -> bool:
    """A symbol, or a sum of symbols each with coefficient +-1 (no multiple angle)."""
    for term in angle.args if angle.is_Add else (angle,):
        if term.is_Symbol:
            continue
        args: tuple[Any, ...] = term.args if term.is_Mul else ()
        if not (len(args) == 2 and args[1].is_Symbol and args[0] in _UNITS):
            return False
    return True


def combine_trig_sympy(expr: Any, budget: int | None = None) -> sp.Expr:
    """:func:`combine_trig` of a SymPy expression, back in SymPy with its own symbols.

    The Fourier form is canonical for trigonometric polynomials, so a difference that is
    identically zero becomes 0 (with the default ``budget`` None the Fourier form is always
    tried: this is the zero test of the Newton–Euler checks).

    >>> a, b = sp.symbols("a b")
    >>> combine_trig_sympy(sp.sin(a) ** 2 * sp.cos(b) + sp.cos(a) ** 2 * sp.cos(b))
    cos(b)
    """
    expr = to_sympy(expr)
    return SympyView(expr.free_symbols)(combine_trig(to_backend(expr), budget))


def combine_trig_matrix(matrix: sp.MatrixBase, budget: int | None = None) -> sp.ImmutableMatrix:
    """:func:`combine_trig_sympy` applied to every entry."""
    return sp.ImmutableMatrix(
        sp.Matrix(matrix).applyfunc(lambda entry: combine_trig_sympy(entry, budget))
    )


def combine_trig(expr: Any, budget: int | None = FOURIER_BUDGET) -> Any:
    """The shortest of: the expanded expression, its Fourier form, the Fourier form with
    double angles written back as squares (cos 2x = 1 - 2 sin^2 x = 2 cos^2 x - 1, which gives
    the textbook r^2 sin^2(theta) rather than r^2/2 - r^2 cos(2 theta)/2), and its
    :func:`pythagorean_forms`.  The Fourier forms are tried only when they cost at most
    ``budget`` product-to-sum terms and no term has more than ``FOURIER_DEGREE`` sines and
    cosines (always when ``budget`` is None).  Beyond them, an expression of more than
    ``LARGE_POLYNOMIAL`` terms is reduced as a polynomial grouped by its products of sines
    and cosines (:mod:`lagrangian.derivation.trig_polynomial`: the shorter pythagorean form,
    without weighing the expanded one), and one that would expand to ``NESTED_TERMS`` terms
    or more is returned as it is.  No general simplify."""
    if (
        budget is not None
        and size(expr) > NESTED_CHECK_OPS
        and expanded_terms(expr, NESTED_TERMS) >= NESTED_TERMS
    ):
        return expr  # kept nested: expanded, it would be far longer
    expanded = se.expand(expr)
    terms = expanded.args if expanded.is_Add else (expanded,)
    if budget is not None and len(terms) > LARGE_POLYNOMIAL:
        reduced_polynomial = _reduced_polynomial(expanded, budget)
        if reduced_polynomial is not None:
            return reduced_polynomial
    degrees = [len(trig) for trig in map(_trig_factors, terms) if trig is not None]
    cost = sum(2 ** (d - 1) for d in degrees if d > 1)
    if cost == 0:  # no product of sines and cosines: only double angles to weigh
        halves = _half_angle_forms(expanded)
        return min((expanded, *halves), key=_textbook_size) if halves else expanded
    if budget is not None and len(terms) > LONG_EXPRESSION:
        return _reduce_squares(expanded, se.cos, se.sin)
    reduced = pythagorean_forms(expanded)
    if budget is not None and (cost > budget or max(degrees) > FOURIER_DEGREE):
        return min((expanded, *reduced), key=collected_size)
    fourier = _fourier_of_expanded(expanded)
    halves = _half_angle_forms(fourier)
    if not halves:  # no double angles to weigh: the plain size decides
        return min((expanded, fourier, *reduced), key=collected_size)
    return min((expanded, fourier, *halves, *reduced), key=_textbook_size)


def _reduced_polynomial(expanded: Any, budget: int) -> Any:
    """The shorter of the two :func:`pythagorean_forms` of a long expanded expression,
    reduced as a polynomial in its sines and cosines (:mod:`trig_polynomial`), expanded;
    None when the Fourier form is within ``budget`` or there is no product to reduce."""
    algebra = algebra_for(())
    polynomial = algebra.finish(algebra.convert(expanded))
    cost, degree = 0, 0
    for key, coefficient in polynomial.items():
        d = sum(e for i, e in pairs(key) if algebra.sine[i] or algebra.cosine[i])
        degree = max(degree, d)
        if d > 1:
            cost += 2 ** (d - 1) * len(coefficient)
    if cost == 0 or (cost <= budget and degree <= FOURIER_DEGREE):
        return None
    return se.expand(algebra.expression(algebra.shortest(polynomial)))


def collected_size(expr: Any) -> int:
    """The :func:`size` of ``expr`` with its terms grouped by their product of sines and
    cosines (the coefficients of one product summed): the size of the form the equations
    are shown in, so K (cos a sin b) is not counted as often as K has terms.

    >>> x, p, r = se.symbols("x p r")
    >>> collected_size(se.expand((p + r) * se.sin(x))), size(se.expand((p + r) * se.sin(x)))
    (3, 5)
    """
    terms = expr.args if expr.is_Add else (expr,)
    groups: dict[Any, list[Any]] = defaultdict(list)
    for term in terms:
        trig: list[Any] = []
        rest: list[Any] = []
        for factor in term.args if term.is_Mul else (term,):
            base = factor.args[0] if factor.is_Pow else factor
            (trig if isinstance(base, (se.sin, se.cos)) else rest).append(factor)
        groups[se.Mul(*trig)].append(se.Mul(*rest))
    if len(groups) == len(terms):
        return size(expr)
    products = [key * se.Add(*coefficients) for key, coefficients in groups.items()]
    return sum(size(p) for p in products) + len(products) - 1


def pythagorean_forms(expanded: Any) -> list[Any]:
    """``expanded`` (an expanded expression) reduced modulo sin^2 x + cos^2 x - 1 for every
    angle x, once writing each cos^2 x as 1 - sin^2 x, once each sin^2 x as 1 - cos^2 x;
    the forms that differ from ``expanded``.

    >>> x, m = se.symbols("x m")
    >>> pythagorean_forms(se.expand(m * se.cos(x) ** 2 * se.sin(x) + m * se.sin(x) ** 3))
    [m*sin(x)]
    """
    forms: list[Any] = []
    for square, other in ((se.cos, se.sin), (se.sin, se.cos)):
        reduced = _reduce_squares(expanded, square, other)
        if reduced is not expanded and all(reduced != f for f in forms):
            forms.append(reduced)
    return forms


def _reduce_squares(expanded: Any, square: Any, other: Any) -> Any:
    """Every power f(x)**k (k >= 2, f = ``square``) of ``expanded`` written as
    f(x)**(k mod 2) (1 - g(x)**2)**(k // 2), g = ``other``; ``expanded`` itself when there
    is none."""
    terms = expanded.args if expanded.is_Add else (expanded,)
    result, changed = [], False
    for term in terms:
        kept, swapped = [], []
        for factor in term.args if term.is_Mul else (term,):
            base, power = factor.args if factor.is_Pow else (factor, None)
            if isinstance(base, square) and power is not None and power.is_Integer:
                count = int(power)
                if count >= 2:
                    swapped.append((1 - other(base.args[0]) ** 2) ** (count // 2))
                    kept.extend([base] * (count % 2))
                    continue
            kept.append(factor)
        if swapped:
            changed = True
            result.append(se.expand(se.Mul(*kept) * se.Mul(*swapped)))
        else:
            result.append(term)
    return se.Add(*result) if changed else expanded


def _textbook_size(expr: Any) -> int:
    """Size, with multiple angles counted dearer: sin(x) cos(x) reads better than sin(2x)/2."""
    multiple = sum(1 for atom in _trig_atoms(expr) if _multiple_angles(atom))
    return collected_size(expr) + 3 * multiple


def _half_angle_forms(expr: Any) -> list[Any]:
    """``expr`` with every cos(2x) written as 1 - 2 sin^2 x, and as 2 cos^2 x - 1
    (sin(2x) as 2 sin x cos x in both)."""
    doubled = {}
    for atom in _trig_atoms(expr):
        if not _multiple_angle(atom):  # a trig function inside is one of the atoms too
            continue
        half = se.expand(atom.args[0] / 2)
        if not _multiple_angles(se.sin(half)):
            doubled[atom] = half
    if not doubled:
        return []
    forms = []
    for cosine in (lambda x: 1 - 2 * se.sin(x) ** 2, lambda x: 2 * se.cos(x) ** 2 - 1):
        swap = {
            atom: (cosine(half) if isinstance(atom, se.cos) else 2 * se.sin(half) * se.cos(half))
            for atom, half in doubled.items()
        }
        forms.append(se.expand(expr.xreplace(swap)))
    return forms
