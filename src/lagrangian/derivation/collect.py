"""Collect an expanded expression by its state-dependent monomials and factor the parameter
coefficients:  -g l1 m1 sin(theta1) - g l1 m2 sin(theta1)  ->  -g l1 (m1 + m2) sin(theta1).

This is the form a textbook writes (masses summed, lengths factored out) and it keeps the
output small: each state monomial appears once per equation.  Three or more monomials that
share a coefficient (up to sign; 3-D bodies have many) are summed under it as well:
l1 l2 (m2/2 + m3) (sin a1 sin a2 + cos a1 cos a2 cos b1 + ...).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from functools import lru_cache
from typing import Any

import symengine as se

ONE = se.Integer(1)  # the one object SymEngine gives for every integer 1
ZERO = se.Integer(0)
#: How many monomials must share a coefficient for :func:`collect_state` to sum them under it.
SHARED = 3
#: How many terms :func:`term_powers` remembers (a bicycle's coefficients have about 1,200).
TERM_POWERS = 8192


def product_powers(factors: Sequence[Any]) -> tuple[Any, dict[Any, Any]]:
    """(numeric coefficient, {base: exponent}) of a product of parameters, given as the
    list of its factors."""
    number = ONE
    powers: dict[Any, Any] = {}
    for factor in factors:
        if factor.is_Number:
            number = factor if number is ONE else number * factor  # 1 x is x
            continue
        base, exponent = factor.args if factor.is_Pow else (factor, ONE)
        powers[base] = powers[base] + exponent if base in powers else exponent
    return number, powers


def factor_common(terms: list[Any]) -> Any:
    """Sum of ``terms`` (products of parameters) with their common factors pulled out."""
    if len(terms) == 1:
        return terms[0]
    return _factored([term_powers(term) for term in terms], terms)


@lru_cache(maxsize=TERM_POWERS)
def term_powers(term: Any) -> tuple[Any, dict[Any, Any]]:
    """:func:`product_powers` of a term (a product of parameters, or one factor),
    remembered: the terms of the coefficients :func:`factor_common` factors recur across
    the entries of M and the rows of the forcing (the bicycle's 2,182 are 1,150 distinct),
    and reading a SymEngine product's factors and powers costs more than looking it up.
    The powers are shared: read them, never change them."""
    return product_powers(term.args if term.is_Mul else (term,))


def factor_products(split: list[tuple[Any, dict[Any, Any]]], products: list[Any]) -> Any:
    """:func:`factor_common` of the terms made as the products of the factors in
    ``products``, their (number, powers) given as ``split`` (as :func:`product_powers` of
    each term's factors would find them): a term is multiplied out only if nothing is
    common to pull out of the sum.

    >>> import symengine as se
    >>> a, b, c = se.symbols("a b c")
    >>> split = [(se.Integer(2), {a: ONE, b: ONE}), (ONE, {a: ONE, c: ONE})]
    >>> factor_products(split, [(2 * a, b), (a, c)]) == factor_common([2 * a * b, a * c])
    True
    """
    if len(products) == 1:
        return se.Mul(*products[0])
    return _factored(split, None, products)


def _factor_common(products: list[Any]) -> Any:
    """:func:`factor_common` of products given as the sequences of their factors."""
    if len(products) == 1:
        return se.Mul(*products[0])
    return _factored([product_powers(factors) for factors in products], None, products)


def _factored(
    split: list[tuple[Any, dict[Any, Any]]],
    terms: list[Any] | None,
    products: list[Any] | None = None,
) -> Any:
    """The factored sum of the products whose (number, powers) are ``split``: the
    ``terms`` themselves, or the ``products`` of factors (a sum with nothing common is
    summed from the terms, not multiplied out again)."""
    common = dict(split[0][1])
    for _, powers in split[1:]:
        for base, least in list(common.items()):
            exponent = powers.get(base)
            if exponent is None or not (least.is_Number and exponent.is_Number):
                del common[base]
            elif not (least is ONE and exponent is ONE):  # min(1, 1) is the 1 there already
                common[base] = min(least, exponent)
        if not common:  # nothing left to compare with the other products
            break
    numbers = {number for number, _ in split}  # a few, most of them 1 and -1
    magnitudes = {abs(number) for number in numbers}
    scale = magnitudes.pop() if len(magnitudes) == 1 else ONE
    if all(is_negative_number(number) for number in numbers):
        scale = -scale
    if not common and scale == 1:
        return se.Add(*(terms or [se.Mul(*factors) for factors in products or ()]))
    outside = scale * se.Mul(*[b**e for b, e in common.items()])
    quotients: dict[Any, Any] = {}  # number / scale, once per number (most are -1 or 1)
    parts = []
    for number, powers in split:
        quotient = quotients.get(number)
        if quotient is None:
            quotient = quotients[number] = number / scale
        parts.append(_divided(quotient, powers, common))
    return outside * se.Add(*parts)


def is_negative_number(number: Any) -> bool:
    """``number < 0``, read off an integer or a fraction (the comparison costs 20 times more)."""
    if number.is_Rational:  # an integer or a fraction
        return bool(number.is_negative)
    return bool(number < ZERO)


def _divided(number: Any, powers: dict[Any, Any], common: dict[Any, Any]) -> Any:
    """``number`` times the product of base ** (exponent - common exponent) over
    ``powers``, made as one product.

    A base outside ``common`` is raised to its own exponent (e - 0 is e) and, when that
    is the 1 :func:`product_powers` gives a factor that is no power, left as it is (b ** 1 is b);
    a base whose exponent and common exponent are both that 1 is left out (b ** 0 is 1,
    which a product leaves out): the same product, without two operations per factor.  The
    integer 1 (always the object ONE) is left out as well."""
    factors = [] if number is ONE else [number]
    for base, exponent in powers.items():
        least = common.get(base)
        if least is None:
            factors.append(base if exponent is ONE else base**exponent)
        elif not (exponent is ONE and least is ONE):
            factors.append(base ** (exponent - least))
    # a product of one factor is that factor
    return factors[0] if len(factors) == 1 else se.Mul(*factors)


def collect_state(
    expr: Any,
    state: Iterable[Any],
    sums: Mapping[Any, tuple[Any, Any]] | None = None,
    factors: dict[Any, Any] | None = None,
) -> Any:
    """Group the terms of expanded ``expr`` by their factors that depend on ``state``.

    ``sums`` maps symbols that stand for sums of parameters in ``expr`` to (the sum, the sum
    with its common factors pulled out): the result has the sums back, as though ``expr`` had
    been expanded with them (a coefficient that is one product takes the factored sum, several
    that hold such symbols are expanded together and factored as one).

    ``factors``, when given, remembers across calls with the same ``state`` and ``sums`` (a
    mapping that may grow, never change) how each factor is sorted: the same factors recur
    in every equation of a system."""
    terms = expr.args if expr.is_Add else (expr,)
    groups = _groups(terms, set(state), sums or {}, {} if factors is None else factors)
    if sums:
        return _collected_with_sums(groups, sums)
    if len(groups) < SHARED and all(len(v[0]) == 1 for v in groups.values()):
        return expr
    pairs = [(key, _factor_common(group[0])) for key, group in groups.items()]
    if len(pairs) < SHARED:
        return se.Add(*[key * coefficient for key, coefficient in pairs])
    single = all(len(group[0]) == 1 for group in groups.values())
    return _sum_by_coefficient(pairs, expr if single else None)


def collect_pairs(expr: Any, pairs: list[tuple[Any, Any]]) -> Any:
    """:func:`collect_state` of a sum whose terms are known as (state monomial, coefficient)
    pairs, a monomial in one term only, in the order of the sum's terms (the sign a shared
    coefficient takes is that of the first): the terms are not walked factor by factor.

    >>> import symengine as se
    >>> q, a, b = se.symbols("q a b")
    >>> pairs = [(se.sin(q), a * b), (se.cos(q), -a * b), (q, a * b)]
    >>> expr = se.Add(*[k * c for k, c in pairs])
    >>> collected = collect_pairs(expr, [p for t in expr.args for p in pairs if p[0] * p[1] == t])
    >>> collected == collect_state(expr, [q]), collected.is_Mul
    (True, True)
    """
    if len(pairs) < SHARED:
        return expr
    return _sum_by_coefficient(pairs, expr)


def collect_state_with(
    expr: Any,
    monomials: list[tuple[Any, Any, Any]],
    state: set[Any],
    sums: Mapping[Any, tuple[Any, Any]],
    factors: dict[Any, Any],
) -> Any | None:
    """:func:`collect_state` (with ``sums``) of ``expr`` plus sum(c m for (m, c, _) in
    ``monomials``), whose terms come collected already: each m a state monomial, each c its
    coefficient as :func:`collect_state` makes it (:func:`collected_coefficient`), with
    :func:`numberless` of c.  None when an m is a monomial of ``expr``
    too (its terms would join the group of ``expr``'s); the caller makes sure no two m are
    equal.  A chain's C q_dot has n^2 such terms, known by monomial when they are made
    (:mod:`lagrangian.derivation.coriolis`): grouping them again would walk every factor.
    A coefficient that is a sum (which the sharing of :func:`_sum_by_coefficient` could
    write as either sign, by the order the monomials come in) also gives None."""
    terms = expr.args if expr.is_Add else (expr,)
    groups = _groups(terms, state, sums, factors)
    if any(monomial in groups for monomial, _, _ in monomials):
        return None
    return _collected_with_sums(groups, sums, monomials)


def numberless(coefficient: Any) -> Any | None:
    """``coefficient`` without its number (c for 2 c, -c and c alike); None for a number.
    Two coefficients equal up to their sign have the same."""
    if coefficient.is_Number:
        return None
    if coefficient.is_Mul:
        args = coefficient.args
        if args[0].is_Number:
            return args[1] if len(args) == 2 else se.Mul(*args[1:])
    return coefficient


def collected_coefficient(
    coefficient: Any, state: set[Any], sums: Mapping[Any, tuple[Any, Any]], sorts: dict[Any, Any]
) -> Any:
    """The coefficient :func:`collect_state` (with ``sums``, remembering factors in ``sorts``)
    gives a monomial whose terms' coefficients are the terms of ``coefficient`` (expanded,
    free of the state, its sums of ``sums`` written as their symbols)."""
    products, holds, factored = _coefficient_group(coefficient, state, sums, sorts)
    return _with_sums(products, sums, holds, factored)


def _coefficient_group(
    coefficient: Any, state: set[Any], sums: Mapping[Any, tuple[Any, Any]], sorts: dict[Any, Any]
) -> Group:
    """The :data:`Group` :func:`_grouped` makes of the terms of ``coefficient`` (expanded,
    free of the state) times one monomial."""
    products: list[list[Any]] = []
    holds = False
    factored: list[Any] | None = None
    for term in coefficient.args if coefficient.is_Add else (coefficient,):
        product: list[Any] = []
        first: list[Any] = []
        for factor in term.args if term.is_Mul else (term,):
            sort = sorts.get(factor)
            if sort is None:
                sort = sorts[factor] = _sort(factor, state, sums)
            product.append(factor)
            back = sort[1]
            if back is None:
                first.append(factor)
            else:
                first.append(back)
                holds = True
        products.append(product)
        if factored is None:
            factored = first
    return products, holds, factored or []


def _collected_with_sums(
    groups: dict[Any, Group],
    sums: Mapping[Any, tuple[Any, Any]],
    collected: list[tuple[Any, Any, Any]] | None = None,
) -> Any:
    """The collected sum of ``groups`` (:func:`collect_state` with ``sums``) and of the
    monomials ``collected`` with their coefficients (and those without their numbers);
    with ``collected``, None when a coefficient is a sum."""
    pairs = [
        (key, _with_sums(products, sums, holds, factored))
        for key, (products, holds, factored) in groups.items()
    ]
    if collected is not None:
        if any(coefficient.is_Add for _, coefficient in pairs) or any(
            coefficient.is_Add for _, coefficient, _ in collected
        ):
            return None
        if _none_shared(pairs, collected):
            return se.Add(
                *[key * coefficient for key, coefficient in pairs],
                *[key * coefficient for key, coefficient, _ in collected],
            )
        pairs += [(key, coefficient) for key, coefficient, _ in collected]
    if len(pairs) < SHARED:
        return se.Add(*[key * coefficient for key, coefficient in pairs])
    return _sum_by_coefficient(pairs, None)


def _none_shared(pairs: list[tuple[Any, Any]], collected: list[tuple[Any, Any, Any]]) -> bool:
    """Whether no two coefficients of ``pairs`` and ``collected`` are equal up to their
    sign, told by their :func:`numberless` parts all differing (numbers are never summed
    under): :func:`_sum_by_coefficient` would then give each term as it came.  A chain's row
    of C q_dot has a coefficient of its own for each monomial, l_j l_k (m_k + ... + m_n)."""
    seen = set()
    for part in [numberless(coefficient) for _, coefficient in pairs] + [
        part for _, _, part in collected
    ]:
        if part is not None:
            if part in seen:
                return False
            seen.add(part)
    return True


def _sort(factor: Any, state: set[Any], sums: Mapping[Any, tuple[Any, Any]]) -> tuple[Any, Any]:
    """(``factor`` as it goes into a key, with the sums of ``sums`` put back, or None for a
    factor free of the state; for a factor free of the state that is a symbol of ``sums``
    or its power, that factor with the factored sum put back, else None)."""
    symbols = factor.free_symbols
    if state.isdisjoint(symbols):
        # _put_back changes exactly the factors whose base is in ``sums``
        return None, _put_back(factor, sums, 1) if _base(factor) in sums else None
    if sums and not symbols.isdisjoint(sums):
        return factor.xreplace({s: sums[s][0] for s in sums}), None
    return factor, None


#: A group of terms: the coefficient factors of each term, whether one of them holds a symbol
#: of the sums, and the first term's coefficient factors with the factored sums put back.
Group = tuple[list[list[Any]], bool, list[Any]]


def _groups(
    terms: Iterable[Any],
    state: set[Any],
    sums: Mapping[Any, tuple[Any, Any]],
    sorts: dict[Any, Any],
) -> dict[Any, Group]:
    """{state monomial: its :data:`Group`}, monomials in the order they first come.

    ``sorts`` remembers :func:`_sort` of each factor.  Terms are grouped by the tuple of their
    key factors first: a tuple is cheaper to hash than a product is to build, and one product
    is then built per monomial, not per term.  Equal tuples give equal products; should two
    different tuples give the same product, the terms are grouped again by the product, so
    the groups are always those (and in the order) of grouping by the product."""
    by_factors = _grouped(terms, state, sums, sorts, False)
    keys = [se.Mul(*key) for key in by_factors]
    if len(set(keys)) < len(keys):
        return _grouped(terms, state, sums, sorts, True)
    return dict(zip(keys, by_factors.values()))


def _grouped(
    terms: Iterable[Any],
    state: set[Any],
    sums: Mapping[Any, tuple[Any, Any]],
    sorts: dict[Any, Any],
    by_product: bool,
) -> dict[Any, Group]:
    """The groups of :func:`_groups`, keyed by the tuple of key factors (or their product
    when ``by_product``).

    A symbol whose hash is none of the state's or the sums' is neither (equal objects have
    equal hashes): a parameter, a coefficient with no sum to put back, as :func:`_sort`
    would find; told apart by integers, without the comparisons of SymEngine objects that
    finding it in ``sorts`` costs (most factors are such)."""
    watched = {hash(s) for s in state} | {hash(s) for s in sums}
    groups: dict[Any, Group] = {}
    for term in terms:
        key: list[Any] = []
        coefficient: list[Any] = []
        factored: list[Any] = []  # _put_back(f, sums, 1) of each coefficient factor f
        holds = False
        for factor in term.args if term.is_Mul else (term,):
            if type(factor) is se.Symbol and hash(factor) not in watched:
                coefficient.append(factor)
                factored.append(factor)
                continue
            sort = sorts.get(factor)
            if sort is None:
                sort = sorts[factor] = _sort(factor, state, sums)
            moving, back = sort
            if moving is not None:
                key.append(moving)
                continue
            coefficient.append(factor)
            if back is None:
                factored.append(factor)
            else:
                factored.append(back)
                holds = True
        name = se.Mul(*key) if by_product else tuple(key)
        group = groups.get(name)
        if group is None:
            groups[name] = ([coefficient], holds, factored)
        else:
            group[0].append(coefficient)
            if holds and not group[1]:
                groups[name] = (group[0], True, group[2])
    return groups


def _with_sums(
    products: list[list[Any]],
    sums: Mapping[Any, tuple[Any, Any]],
    holding: bool,
    factored: list[Any],
) -> Any:
    """:func:`_factor_common` of ``products`` whose symbols in ``sums`` stand for sums;
    ``holding``: whether a factor of the products is such a symbol or its power;
    ``factored``: the factors of the first product with the factored sums put back."""
    if not holding:
        return _factor_common(products)
    if len(products) == 1:  # c S -> c (S factored), the form the expanded c S collects to
        return se.Mul(*factored)
    expanded = se.expand(se.Add(*[se.Mul(*[_put_back(f, sums, 0) for f in p]) for p in products]))
    if expanded.is_Number:
        return expanded
    terms = expanded.args if expanded.is_Add else (expanded,)
    return _factor_common([term.args if term.is_Mul else (term,) for term in terms])


def _base(factor: Any) -> Any:
    return factor.args[0] if factor.is_Pow else factor


def _put_back(factor: Any, sums: Mapping[Any, tuple[Any, Any]], form: int) -> Any:
    """``factor`` with a symbol of ``sums`` (or its power) replaced by form 0 (the sum) or
    1 (the factored sum)."""
    if factor in sums:
        return sums[factor][form]
    if factor.is_Pow and factor.args[0] in sums:
        return sums[factor.args[0]][form] ** factor.args[1]
    return factor


def _leads_negative(product: Any) -> bool:
    """Whether a product starts with a negative number."""
    first = product.args[0]
    return bool(first.is_Number) and is_negative_number(first)


def _sum_by_coefficient(pairs: list[tuple[Any, Any]], unchanged: Any) -> Any:
    """sum key * coefficient with the keys of a coefficient (or of its negative) shared by
    :data:`SHARED` or more summed first: c k1 - c k2 + c k3 -> c (k1 - k2 + k3), c without
    a negative number in front; numbers are not factored out.  ``unchanged`` (when not
    None) is returned if nothing is shared."""
    # coefficient without a negative number in front -> [(key, coefficient, its sign flipped)]
    shared: dict[Any, list[tuple[Any, Any, bool]]] = {}
    for key, coefficient in pairs:
        if coefficient.is_Number:
            shared.setdefault(coefficient, []).append((key, coefficient, False))
        elif coefficient.is_Mul and _leads_negative(coefficient):
            # c k1 - c k2 + c k3 whichever sign comes first: the same form for the same sum
            shared.setdefault(-coefficient, []).append((key, coefficient, True))
        else:
            # the negative of a product, a symbol or a power is a product with a negative
            # number in front, never a key: only other coefficients (sums) are looked up
            simple = coefficient.is_Mul or coefficient.is_Symbol or coefficient.is_Pow
            members = None if simple else shared.get(-coefficient)
            if members is not None:  # never None for a coefficient in ``shared``
                members.append((key, coefficient, True))
            else:
                shared.setdefault(coefficient, []).append((key, coefficient, False))
    if unchanged is not None and all(len(members) < SHARED for members in shared.values()):
        return unchanged
    terms = []
    for common, members in shared.items():
        if common.is_Number or len(members) < SHARED:
            # (-c) (-k) is c k: each term as it came
            terms += [coefficient * key for key, coefficient, _ in members]
        else:
            terms.append(common * se.Add(*[-key if flip else key for key, _, flip in members]))
    return se.Add(*terms)
