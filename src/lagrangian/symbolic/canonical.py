"""SymPy sums and products built in their canonical form without SymPy's general evaluation,
from what is already known of their parts.

``sp.Add(*terms)`` and ``sp.Mul(*factors)`` flatten, combine like parts, sort the rest by
:meth:`sympy.Basic.compare` and put the number first.  When the parts are canonical and
nothing combines, only the sorting and the number are left to do, and that is what
:class:`Builder` does, from a :data:`Part` of each argument: the SymPy expression with its
sort key, what kind of argument it is and the hashes that tell whether two parts could
combine.  A converted 200-link chain has 60,000 products of five or six factors each (M's
entries and the forcing's terms), each sorted and checked once, so none of this is asked
of SymPy again for each product: a part's key and hashes are computed once, when it is
made, and a product's and a sum's from their parts'.

Two parts combine only if their hashes are equal, so parts whose hashes all differ combine
in no way, and a clash of hashes (rare) only sends the arguments to SymPy's own
constructors: the result is SymPy's in every case.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> sympy_product([sp.Integer(-2), sp.sin(y), x**2]) == sp.Mul(-2, sp.sin(y), x**2)
True
>>> sympy_sum([sp.Integer(2), 3 * y, x**2]) == sp.Add(2, 3 * y, x**2)
True
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from functools import cmp_to_key
from operator import itemgetter
from typing import Any, NamedTuple

import sympy as sp
from sympy.core.basic import ordering_of_classes
from sympy.core.parameters import global_parameters

from lagrangian.symbolic.objects import sympy_object

#: The fields of a Part, a tuple (the fastest record to read in the conversion's loops):
#: the expression, its sort key (:data:`UNORDERABLE` when it has none), its kind,
#: its hash (None for a sum or a product made here: asked of SymPy when needed), the hash
#: of its base as a commutative factor that SymPy's products combine with another of the
#: same base (PLAIN, POWER_RATIONAL, SUM; else None, and None for a sum made here until
#: asked), the hash of what remains of it without a numeric coefficient as a term (None for
#: a SUM, and for a product of a sum made here until it is met as a term), whether it is
#: commutative, and the Parts of a sum's or a product's arguments (None until asked for).
EXPR, KEY, KIND, HASH, BASE_HASH, REST_HASH, COMMUTATIVE, ARGS = range(8)
Part = tuple[Any, ...]

#: The kinds of parts: a rational number; a symbol or the value of a function that SymPy's
#: products take as a base to the power 1; a power of a base that is not a number (to a
#: rational exponent or not); a sum; a product; anything else (SymPy's constructors).
RATIONAL, PLAIN, POWER_RATIONAL, POWER, SUM, PRODUCT, OTHER = range(7)


class Unorderable(Exception):
    """An expression :class:`CanonicalOrder` has no key for."""


#: The key of a Part without one (its expression is sorted by ``Basic.compare``): None,
#: which no key compares with, so sorting by keys raises TypeError when one is missing.
UNORDERABLE = None


#: Where a class's name stands in SymPy's order of classes; the rest come after, by name.
_CLASS_RANK = {name: i for i, name in enumerate(ordering_of_classes)}
_UNRANKED = len(ordering_of_classes) + 1
_MUL_RANK = _CLASS_RANK.get("Mul", _UNRANKED)
_ADD_RANK = _CLASS_RANK.get("Add", _UNRANKED)
#: How SymPy's classes give the content that ``Basic.compare`` compares after the class.
_ARGS_CONTENT = (sp.Basic._hashable_content, sp.Expr._hashable_content)
_NAMED = (sp.Symbol, sp.Dummy)

#: SymPy's canonical order of the arguments of a sum or a product (what ``Add`` and ``Mul``
#: sort them by).
_CANONICAL_ORDER = cmp_to_key(sp.Basic.compare)
_KEY_OF = itemgetter(KEY)
#: SymPy's 0 and 1 and its sum and product classes, read once (each ``sp.S.One`` is two
#: attribute lookups in the conversion's loops).
_ZERO, _ONE = sp.S.Zero, sp.S.One
_ADD, _MUL = sp.Add, sp.Mul
#: A sum or a product of two or more commutative arguments in SymPy's order made as
#: ``AssocOp._from_args(args, True)`` makes it (SymPy 1.12 to 1.14): ``Basic.__new__`` of the
#: class and the arguments, then ``is_commutative`` set, which the caller does.  Called
#: directly, the classmethod's own steps (its call, the count of the arguments, ``super()``)
#: are left out: a third of the making of each of a bicycle's 3,000 products (2.5 -> 1.5 us).
_NEW = sp.Basic.__new__


class CanonicalOrder:
    """Sort keys that order expressions as :meth:`sympy.Basic.compare` does, remembered per
    expression: a key is compared in C, where ``compare`` runs in Python on every
    comparison (the arguments of the sums of a 200-link chain's equations are sorted by
    the hundred thousand).

    ``compare`` orders by class (its place in SymPy's ``ordering_of_classes``, else its
    name), then by the length of the hashable content, then by its items one by one (other
    expressions recursively, anything else by ``<``); the key is that tuple.  Symbols,
    rational numbers and the expressions whose content is their arguments have keys; any
    other expression raises :class:`Unorderable`.

    >>> x, y = sp.symbols("x y")
    >>> order = CanonicalOrder()
    >>> sorted([y, sp.sin(x), x**2, x], key=order)
    [x, y, x**2, sin(x)]
    """

    def __init__(self) -> None:
        # by id, which hashes faster than an expression; the expression is kept with its key,
        # so its id is not reused while the key is remembered
        self._keys: dict[int, tuple[sp.Basic, tuple[Any, ...]]] = {}

    def __call__(self, expr: sp.Basic) -> tuple[Any, ...]:
        known = self._keys.get(id(expr))
        if known is not None:
            return known[1]
        kind = type(expr)
        name = kind.__name__
        if kind._hashable_content in _ARGS_CONTENT:
            content: tuple[Any, ...] = tuple(map(self, expr.args))
        elif kind in _NAMED or expr.is_Rational:
            content = expr._hashable_content()
        else:
            raise Unorderable(name)
        key = (_CLASS_RANK.get(name, _UNRANKED), name, len(content), *content)
        self._keys[id(expr)] = (expr, key)
        return key


class Monomial(NamedTuple):
    """The factors of a product without its number (:meth:`Builder.monomial`): as given,
    and, when SymPy's Mul would only sort them, in SymPy's order (else None), their
    expressions and keys in that order (the keys None when one is missing) and the
    REST_HASH of their product."""

    factors: tuple[Part, ...]
    ordered: tuple[Part, ...] | None
    expressions: tuple[sp.Expr, ...]
    keys: tuple[Any, ...] | None
    rest_hash: int | None


class Builder:
    """Makes the :data:`Part` of SymPy expressions (:meth:`part`, remembered per object),
    and sums and products of Parts in SymPy's canonical form (:meth:`sum`,
    :meth:`product`), each with its Part."""

    def __init__(self) -> None:
        self.order = CanonicalOrder()
        self._parts: dict[int, Part] = {}  # by id; the Part holds its expression

    def part(self, expr: sp.Expr) -> Part:
        """The Part of any SymPy expression."""
        known = self._parts.get(id(expr))
        if known is None:
            known = self._parts[id(expr)] = _describe(expr, self._key(expr))
        return known

    def function_value(self, value: sp.Expr, argument: Part) -> Part:
        """The Part of ``value``, a sine or a cosine of the expression of ``argument`` made
        without SymPy's constructor (:func:`lagrangian.symbolic.sympy_view.unevaluated_trig`),
        without asking SymPy what it is."""
        value_hash = hash(value)
        key = argument[KEY]
        if key is not UNORDERABLE:
            name = type(value).__name__
            key = (_CLASS_RANK.get(name, _UNRANKED), name, 1, key)
        commutative = argument[COMMUTATIVE]
        base_hash = value_hash if commutative else None
        return (value, key, PLAIN, value_hash, base_hash, hash((value_hash,)), commutative, None)

    def _key(self, expr: sp.Expr) -> tuple[Any, ...] | None:
        try:
            return self.order(expr)
        except Unorderable:
            return UNORDERABLE

    def sum(self, parts: Sequence[Part]) -> Part:
        """The Part of ``sp.Add`` of the parts' expressions (:func:`sympy_sum`)."""
        return self._sum(parts, parts)

    def product(self, parts: Sequence[Part]) -> Part:
        """The Part of ``sp.Mul`` of the parts' expressions (:func:`sympy_product`)."""
        made = self._canonical_product(parts)
        return self._general(_MUL, parts) if made is None else made

    def monomial(self, factors: Sequence[Part]) -> Monomial:
        """The factors of a product without its number, read once for all the numbers it is
        scaled by (:meth:`scaled`): in SymPy's order with their keys and the product's
        REST_HASH when they are commutative symbols, function values, rational powers or
        given sums of distinct bases (what SymPy's Mul only sorts), else as given.  A
        bicycle's sums share their monomials of sines, cosines and lengths, each term with
        its own number."""
        bases = [p[BASE_HASH] for p in factors]
        if (
            None in bases
            or len(set(bases)) < len(bases)
            or (len(factors) == 1 and factors[0][KIND] == SUM)  # SymPy distributes a number
        ):
            return Monomial(tuple(factors), None, (), (), None)
        ordered = tuple(_sorted(factors))
        keys = tuple([p[KEY] for p in ordered])
        return Monomial(
            tuple(factors),
            ordered,
            tuple([p[EXPR] for p in ordered]),
            None if None in keys else keys,
            hash(tuple([p[HASH] for p in ordered])),
        )

    def unscaled(self, monomial: Monomial) -> Part:
        """The Part of ``sp.Mul`` of the factors of ``monomial`` (:meth:`product`), in the
        order :meth:`monomial` found, where SymPy's Mul would only sort them."""
        if monomial.ordered is None:
            return self.product(monomial.factors)
        return self._made_product(None, list(monomial.ordered))

    def scaled(self, number: Part, monomial: Monomial) -> Part:
        """The Part of ``sp.Mul`` of the number of ``number`` and the factors of
        ``monomial`` (:meth:`product`): the number first, then the ordered factors, when the
        number is a rational other than 0 and 1."""
        value = number[EXPR]
        if monomial.ordered is None or number[KIND] != RATIONAL or value is _ONE or value is _ZERO:
            return self.product([number, *monomial.factors])
        made = _NEW(_MUL, value, *monomial.expressions)
        made.is_commutative = True
        keys, key = monomial.keys, number[KEY]
        if keys is not None and key is not UNORDERABLE:
            key = (_MUL_RANK, "Mul", len(keys) + 1, key, *keys)
        else:
            key = UNORDERABLE
        return (
            made,
            key,
            PRODUCT,
            None,
            None,
            monomial.rest_hash,
            True,
            (number, *monomial.ordered),
        )

    def _canonical_product(self, parts: Sequence[Part]) -> Part | None:
        """:meth:`product`, or None where it needs SymPy's own rules."""
        if len(parts) == 2:
            kinds = (parts[0][KIND], parts[1][KIND])
            if kinds == (RATIONAL, PLAIN) and parts[1][COMMUTATIVE]:
                return self._scaled(parts[0], parts[1])
            if RATIONAL in kinds and SUM in kinds:
                number, total = parts if kinds[0] == RATIONAL else parts[::-1]
                return self._distributed(number, total)
        return self._product(parts, parts)

    def _scaled(self, number: Part, factor: Part) -> Part | None:
        """:meth:`product` of a rational number and a commutative symbol or function value
        (a sine whose angle was flipped): the number first, unless it is 0 or 1."""
        value = number[EXPR]
        if value is _ONE:
            return factor
        if value is _ZERO:
            return None
        made = _NEW(_MUL, value, factor[EXPR])
        made.is_commutative = True
        keys = (number[KEY], factor[KEY])
        key = None if None in keys else (_MUL_RANK, "Mul", 2, *keys)
        rest_hash = hash((factor[HASH],))
        return (made, key, PRODUCT, None, None, rest_hash, True, (number, factor))

    def _distributed(self, number: Part, total: Part) -> Part | None:
        """:meth:`product` of a rational number and a sum, which SymPy's Mul of the two
        distributes: the sum of the number times each term (``_keep_coeff``: a product's
        coefficient multiplied, a number times any other term as ``Mul`` makes it).  Each
        such product and the sum are made as :meth:`product` and :meth:`sum` make them, so
        what is skipped is SymPy's evaluation of each new term and of their sum (a
        bicycle's forcing has sums of forty terms negated)."""
        value = number[EXPR]
        if value is _ZERO or value is _ONE or not total[COMMUTATIVE]:
            return None
        if not global_parameters.distribute:
            return None
        terms: list[Part] = []
        for term in self._arguments(total):
            kind = term[KIND]
            if kind == RATIONAL:
                made: Part | None = self.part(value * term[EXPR])
            elif kind in (PLAIN, POWER_RATIONAL, PRODUCT):
                pair = (number, term)
                made = self._product(pair, pair)
            else:
                return None
            if made is None:
                return None
            terms.append(made)
        return self.sum(terms)

    def _general(self, constructor: Any, parts: Sequence[Part]) -> Part:
        return self.part(constructor(*[p[EXPR] for p in parts]))

    def _flat(self, parts: Sequence[Part], kind: int) -> list[Part]:
        """``parts`` with the Parts of the arguments of each of ``kind`` (SUM or PRODUCT) in
        place of it."""
        flat: list[Part] = []
        for p in parts:
            flat.extend(self._arguments(p) if p[KIND] == kind else (p,))
        return flat

    def _arguments(self, part: Part) -> tuple[Part, ...]:
        args = part[ARGS]
        return tuple(map(self.part, part[EXPR].args)) if args is None else args

    def _sum(self, flat: Sequence[Part], parts: Sequence[Part]) -> Part:
        """:meth:`sum` of ``parts``, whose sums are flattened in ``flat`` (``parts`` until
        one is met).  Add.flatten would sum the numbers, sort the rest and put the number
        first, which is all this does when no two terms have the same part without their
        numeric coefficients (their REST_HASHes all differ; the products of a sum made here
        are compared apart, :func:`_apart`)."""
        coefficient: Any = _ZERO
        terms: list[Part] = []
        seen: set[int] = set()
        of_sums: list[Part] = []
        for p in flat:
            expr, _, kind, _, _, rest, commutative, _ = p
            if kind == RATIONAL:
                # 0 + a rational number is that number (SymPy makes the same canonical one)
                coefficient = expr if coefficient is _ZERO else coefficient + expr
                continue
            if kind == SUM:
                if flat is not parts:  # a sum among a sum's arguments: SymPy never makes one
                    return self._general(_ADD, parts)
                return self._sum(self._flat(parts, SUM), parts)
            if rest is None and kind == PRODUCT and commutative:  # a product of a sum, made here
                of_sums.append(p)
            elif kind == OTHER or rest in seen or not commutative:
                return self._general(_ADD, parts)
            else:
                seen.add(rest)
            terms.append(p)
        if of_sums and not _apart(of_sums, terms, seen):
            return self._general(_ADD, parts)
        number = None if coefficient is _ZERO else self.part(coefficient)
        ordered = _sorted(terms)
        args = ordered if number is None else [number, *ordered]
        if len(args) < 2:
            return args[0] if args else self.part(_ZERO)
        made = _NEW(_ADD, *[p[EXPR] for p in args])
        made.is_commutative = True
        key = _made_key(_ADD_RANK, "Add", args)
        return (made, key, SUM, None, None, None, True, tuple(args))

    def _product(self, flat: Sequence[Part], parts: Sequence[Part]) -> Part | None:
        """:meth:`product` of ``parts``, whose products are flattened in ``flat``
        (``parts`` until one is met).  Mul.flatten would multiply the numbers, sort the rest
        and put the number first, which is all this does when the factors' bases all differ
        (their BASE_HASHes); None when SymPy's own rules are needed."""
        coefficient: Any = _ONE
        factors: list[Part] = []
        bases: list[int] = []
        # the commutative sums made here among the factors: a sum's base is itself, so it can
        # be another factor's base only if that is a sum or a power of a sum; else its SymPy
        # hash (Python-level, over the whole sum) is not needed to tell the bases apart
        sums: list[Part] = []
        for p in flat:
            base = p[BASE_HASH]
            if base is None:  # not a commutative symbol, function value or rational power
                kind = p[KIND]
                if kind == RATIONAL:
                    # 1 * a rational number is that number (SymPy makes the same one)
                    coefficient = p[EXPR] if coefficient is _ONE else coefficient * p[EXPR]
                    continue
                if kind == PRODUCT and flat is parts:
                    # a product among the factors (a flipped sine) flattened at once
                    return self._product(self._flat(parts, PRODUCT), parts)
                if kind == SUM and p[COMMUTATIVE]:
                    sums.append(p)  # its base compared below, if it can meet another
                    factors.append(p)
                    continue
                return None  # a power to another exponent, a product's product, ...
            factors.append(p)
            bases.append(base)
        if sums and _sum_bases(factors) > 1:
            bases.extend(map(_hash, sums))
        if len(set(bases)) < len(bases) or coefficient is _ZERO:
            return None
        if coefficient is not _ONE and len(factors) == 1 and factors[0][KIND] == SUM:
            return None  # SymPy distributes the number
        number = None if coefficient is _ONE else self.part(coefficient)
        return self._made_product(number, _sorted(factors))

    def _made_product(self, number: Part | None, ordered: list[Part]) -> Part:
        """The Part of the product of the factors ``ordered`` (in SymPy's order) and
        ``number`` (if any) first, as SymPy puts it; its key and REST_HASH from theirs."""
        args = ordered if number is None else [number, *ordered]
        if len(args) < 2:
            return args[0] if args else self.part(_ONE)
        made = _NEW(_MUL, *[p[EXPR] for p in args])
        made.is_commutative = True
        key = _made_key(_MUL_RANK, "Mul", args)
        # the REST_HASH now if it is the hash of known hashes; with a sum among the factors
        # (whose hash SymPy computes), when the product is met as a term (:func:`_rest_hash`),
        # which most such are not (a chain's M: each entry a product of a sum of masses)
        hashes = [p[HASH] for p in ordered]
        rest_hash = None if None in hashes else hash(tuple(hashes))
        return (made, key, PRODUCT, None, None, rest_hash, True, tuple(args))


def _made_key(rank: int, name: str, args: Sequence[Part]) -> tuple[Any, ...] | None:
    """The key of the sum or product (``name``) of ``args`` in SymPy's order, from theirs."""
    keys = [p[KEY] for p in args]
    return None if None in keys else (rank, name, len(keys), *keys)


def _rest_hash(product: Part) -> int:
    """The hash of what a product made here is without its number, as a term of a sum (what
    SymPy's Add compares to combine terms): the hash of the tuple of its other factors, as
    :func:`_describe` reads it off a SymPy product."""
    args = product[ARGS]
    rest = args[1:] if args[0][KIND] == RATIONAL else args
    return hash(tuple([_hash(p) for p in rest]))


def _sum_bases(factors: list[Part]) -> int:
    """How many of ``factors`` are sums or powers of sums (whose bases SymPy's Mul compares
    with the other factors')."""
    count = 0
    for p in factors:
        kind = p[KIND]
        if kind == SUM or (kind == POWER_RATIONAL and isinstance(p[EXPR].base, _ADD)):
            count += 1
    return count


def _apart(of_sums: list[Part], terms: list[Part], seen: set[int]) -> bool:
    """Whether no product of a sum made here among ``of_sums`` (whose REST_HASH is not known)
    has the part without its number of another of ``terms`` (SymPy's Add would combine
    them); ``seen`` holds the REST_HASHes of the other terms.

    Two such parts are equal only if both have a sum among their factors and equal factors
    elsewhere.  So when no other term has a sum among its factors, a product of ``of_sums``
    whose other factors differ from those of the rest of ``of_sums`` combines with none,
    and the SymPy hash of its sums (a Python-level walk over each whole sum) is not needed:
    the REST_HASHes are computed and compared only for the products that meet others."""
    others = [p for p in terms if p[REST_HASH] is not None]
    meeting = of_sums
    if not any(map(_has_sum_factor, others)):
        partial = list(map(_rest_without_sums, of_sums))
        counts = Counter(partial)
        meeting = [p for p, h in zip(of_sums, partial) if counts[h] > 1]
    for p in meeting:
        rest = _rest_hash(p)
        if rest in seen:
            return False
        seen.add(rest)
    return True


def _has_sum_factor(term: Part) -> bool:
    """Whether the term ``term`` is a product with a sum among its factors."""
    if term[KIND] != PRODUCT:
        return False
    args = term[ARGS]
    if args is None:
        return any(isinstance(a, _ADD) for a in term[EXPR].args)
    return any(a[KIND] == SUM for a in args)


def _rest_without_sums(product: Part) -> int:
    """The hash of the factors of a product made here, its number and its sums left out:
    equal for two products whose parts without their numbers are equal."""
    args = product[ARGS]
    rest = args[1:] if args[0][KIND] == RATIONAL else args
    return hash(tuple([None if p[KIND] == SUM else p[HASH] for p in rest]))


def _hash(part: Part) -> int:
    known = part[HASH]
    return hash(part[EXPR]) if known is None else known


def _sorted(parts: Sequence[Part]) -> list[Part]:
    """``parts`` in SymPy's canonical order: sorted by their keys (compared in C), or by
    ``Basic.compare`` when one has none (with two or more parts sorting by keys then raises
    TypeError: every part is compared, and a missing key compares with nothing) or two are
    of unlike content."""
    try:
        return sorted(parts, key=_KEY_OF)
    except TypeError:
        return sorted(parts, key=lambda p: _CANONICAL_ORDER(p[EXPR]))


def _describe(expr: sp.Expr, key: tuple[Any, ...] | None) -> Part:
    """The Part of ``expr`` read from the expression itself, its sort key ``key``."""
    kind = type(expr)
    commutative = expr.is_commutative is True
    value_hash = hash(expr)
    if expr.is_Rational:
        return (expr, key, RATIONAL, value_hash, None, None, commutative, None)
    if kind is sp.Add:
        base_hash = value_hash if commutative else None
        return (expr, key, SUM, value_hash, base_hash, None, commutative, None)
    if kind is sp.Mul:
        args = expr.args
        rest = args[1:] if args[0].is_Number else args
        rest_hash = hash(tuple(map(hash, rest)))
        return (expr, key, PRODUCT, value_hash, None, rest_hash, commutative, None)
    rest_hash = hash((value_hash,))
    if _is_plain(expr):
        base_hash = value_hash if commutative else None
        return (expr, key, PLAIN, value_hash, base_hash, rest_hash, commutative, None)
    if kind is sp.Pow and not expr.args[0].is_Number:
        base, exponent = expr.args
        tag = POWER_RATIONAL if exponent.is_Rational else POWER
        base_hash = hash(base) if commutative and tag == POWER_RATIONAL else None
        return (expr, key, tag, value_hash, base_hash, rest_hash, commutative, None)
    return (expr, key, OTHER, value_hash, None, None, commutative, None)


def _is_plain(expr: sp.Expr) -> bool:
    """A symbol, or the value of a function that SymPy's products take as a base to the
    power 1 (every function but exp): neither has SymPy constructor postprocessors (only
    matrix, vector, tensor and quantum expressions do)."""
    kind = type(expr)
    return kind in _NAMED or (
        isinstance(expr, sp.Function) and kind.as_base_exp is sp.Expr.as_base_exp
    )


def sympy_sum(terms: list[sp.Expr], builder: Builder | None = None) -> sp.Expr:
    """``sp.Add(*terms)``, the same expression (equal arguments in the same order), built
    without SymPy's general evaluation when the terms are canonical SymPy terms with nothing
    to combine (:class:`Builder`); anything else goes through ``sp.Add``.

    >>> x, y = sp.symbols("x y")
    >>> sympy_sum([sp.Integer(2), 3 * y, x**2]) == sp.Add(2, 3 * y, x**2)
    True
    """
    builder = builder or Builder()
    return builder.sum([builder.part(sympy_object(term)) for term in terms])[EXPR]


def sympy_product(factors: list[sp.Expr], builder: Builder | None = None) -> sp.Expr:
    """``sp.Mul(*factors)``, the same expression, built without SymPy's general evaluation
    when the factors are canonical SymPy factors with nothing to combine (:class:`Builder`);
    a number times one sum (which SymPy distributes) and anything else go through ``sp.Mul``.

    >>> x, y = sp.symbols("x y")
    >>> sympy_product([sp.Integer(-2), sp.sin(y), x**2]) == sp.Mul(-2, sp.sin(y), x**2)
    True
    """
    builder = builder or Builder()
    return builder.product([builder.part(sympy_object(f)) for f in factors])[EXPR]
