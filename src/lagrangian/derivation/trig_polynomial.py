"""Trigonometric polynomials kept as {monomial: coefficient}, reduced as they are multiplied.

The equations of 3-D multibody systems (a bicycle, a chain of bodies turned relative to each
other) are polynomials in the sines and cosines of their angles, in the coordinates and in
the velocities.  Expanded, such an expression has thousands of terms, but only a hundred or
so distinct products of sines, cosines and state variables: everything else is the
coefficient (masses, lengths, inertias), a polynomial in the parameters.  A polynomial
here is a dict from a monomial, a flat tuple of generator indices and exponents (i1, e1,
i2, e2, ..., the indices ascending), to its coefficient; the generators are the state
symbols, the sines and cosines (of state angles and of constant ones, such as a head-tube
angle) and any other function of the state, taken as a whole.  A coefficient is a dict
from a parameter monomial, packed into one integer, to a Python number
(:data:`Coefficient`): its products and sums are expanded as they are formed, and
SymEngine expressions are built once, from the finished polynomials
(:meth:`TrigAlgebra.grouped`, :meth:`TrigAlgebra.expression`).

Every product is reduced modulo sin^2 x + cos^2 x = 1 as it is formed (cos^2 x written as
1 - sin^2 x), the canonical form of :func:`lagrangian.derivation.trig.pythagorean_forms`,
so identities such as R^T R = 1 cancel monomial by monomial, without expanding the whole.

>>> import symengine as se
>>> x, m = se.symbols("x m")
>>> algebra = TrigAlgebra([x])
>>> p = algebra.convert(m * se.cos(x) ** 2 + m * se.sin(x) ** 2)
>>> algebra.expression(algebra.finish(p))
m
"""

from __future__ import annotations

import threading
from bisect import bisect
from collections.abc import Iterable, Iterator, Sequence
from fractions import Fraction
from itertools import chain
from math import comb
from operator import eq
from typing import Any

import symengine as se

from lagrangian.derivation.collect import factor_common, factor_products, term_powers

Backend = Any  # a symengine expression
#: A monomial: (index, exponent, index, exponent, ...), the indices ascending.  Flat, not a
#: tuple of pairs: the memos keep tens of thousands of monomials, and the garbage collector
#: stops tracking a tuple of numbers at its first pass over it, where a tuple of tuples stays
#: tracked for a pass per level and so reaches the oldest generation, whose growth sets off
#: full collections (of everything SymPy made at import).
Key = tuple[int, ...]
#: A number of a coefficient: SymEngine's integers and fractions as Python's, its doubles
#: as floats (any other number is a parameter factor).
Number = int | Fraction | float
#: A coefficient: {parameter monomial: number}, the monomial packed into one integer, the
#: exponent of the j-th parameter factor times 2**(BITS j): the packing is linear, so the
#: product of two monomials is the sum of their integers (negative exponents too).
Coefficient = dict[int, Number]
Poly = dict[Key, Coefficient]
BITS = 16  # exponents within +-2**15 stay apart
_FIELD = (1 << BITS) - 1
#: Monomials with their integer factors, flat for the same reason: (key, n, key, n, ...).
Terms = tuple[Any, ...]
#: The product of two monomials: a :data:`Key` when it needs no reduction (its factor 1: the
#: common case, kept as a bare monomial), else the :data:`Terms` of its reduction (their first
#: item a tuple, where a monomial's is a number).
Product = Key | Terms

ONE: Key = ()
#: Terms of a coefficient beyond which :meth:`TrigAlgebra.grouped` does not factor it.
FACTORED_TERMS = 40
_NESTED: Poly = {(): {}}  # the marker of :meth:`TrigAlgebra.keep_nested`
_ZERO = se.Integer(0)
_ONE = se.Integer(1)


def _times(a: Coefficient, b: Coefficient) -> Coefficient:
    """The product of two coefficients."""
    if len(a) > len(b):
        a, b = b, a
    if len(a) == 1:
        for ka, na in a.items():
            if ka == 0:  # a number (a derivative's exponent, a sign): no key to shift
                if na.__class__ is int and na == 1:
                    return b
                return {kb: na * nb for kb, nb in b.items()}
            if len(b) == 1:  # most are (a mass times a length): no comprehension to call
                for kb, nb in b.items():
                    return {ka + kb: na * nb}
            return {ka + kb: na * nb for kb, nb in b.items()}
    out: Coefficient = {}
    for ka, na in a.items():
        for kb, nb in b.items():
            k = ka + kb
            out[k] = out.get(k, 0) + na * nb
    return out


def _scaled(c: Coefficient, n: Number) -> Coefficient:
    if n.__class__ is Fraction:
        top, bottom = n.numerator, n.denominator  # properties: read once, not per term
        return {k: _fraction_times(n, top, bottom, v) for k, v in c.items()}
    if n.__class__ is int and n == -1:  # the sine form's 1 - cos^2: a negation, no product
        return {k: -v for k, v in c.items()}
    return {k: n * v for k, v in c.items()}


def _fraction_times(n: Fraction, top: int, bottom: int, v: Number) -> Number:
    """n * v (n = top / bottom), a whole product as an int: the -1/2 of a Christoffel
    symbol halves even integers, and kept as ints they keep the sums and products made of
    them on integer arithmetic (a Fraction's costs ten times as much)."""
    if v.__class__ is int:
        numerator = top * v
        if numerator % bottom:
            return Fraction(numerator, bottom)
        return numerator // bottom
    product = n * v
    if product.__class__ is Fraction and product.denominator == 1:
        return product.numerator
    return product


def _summed(parts: list[Coefficient]) -> Coefficient:
    out = dict(parts[0])
    for c in parts[1:]:
        for k, v in c.items():
            out[k] = out.get(k, 0) + v
    return out


def _add_into(result: Poly, made: set[Key], key: Key, c: Coefficient, n: int = 1) -> None:
    """Add ``n`` * ``c`` to ``result[key]``: in place when that coefficient was made here
    (its key in ``made``), else into a copy (a coefficient met once is kept as it is, shared
    with the polynomial it came from)."""
    known = result.get(key)
    if known is None:
        if n == 1:
            result[key] = c
        else:
            result[key] = _scaled(c, n)
            made.add(key)
        return
    if key not in made:
        known = result[key] = dict(known)
        made.add(key)
    get = known.get
    if n == 1:
        for k, v in c.items():
            known[k] = get(k, 0) + v
    elif n == -1:  # a + (-1) v is a - v exactly, floats too
        for k, v in c.items():
            known[k] = get(k, 0) - v
    else:
        for k, v in c.items():
            known[k] = get(k, 0) + n * v


class Sum:
    """A polynomial summed in place (:func:`_add_into`): the many products and shares that
    make an entry of M, a row of C q_dot or a derivative go into one result, with no list of
    coefficients per monomial summed at the end."""

    __slots__ = ("made", "poly")

    def __init__(self) -> None:
        self.poly: Poly = {}
        self.made: set[Key] = set()  # the monomials whose coefficients were made here

    def add(self, p: Poly) -> None:
        """Add the polynomial ``p`` (its coefficients met once kept, shared)."""
        poly, made = self.poly, self.made
        for k, c in p.items():
            _add_into(poly, made, k, c)


def _nonzero(c: Coefficient) -> Coefficient:
    """``c`` without its zero terms: ``c`` itself when it has none (the common case, tested
    in C: coefficients are not changed once made)."""
    return c if all(c.values()) else {k: v for k, v in c.items() if v}


def number(expr: Backend) -> Number | None:
    """A SymEngine number as a coefficient's number (None: a parameter factor).

    >>> number(se.Rational(3, 4)), number(se.RealDouble(0.5)), number(se.sqrt(2))
    (Fraction(3, 4), 0.5, None)
    """
    if expr.is_Integer:
        return int(expr)
    if expr.is_Rational:
        numerator, denominator = expr.get_num_den()
        return Fraction(int(numerator), int(denominator))
    if isinstance(expr, se.RealDouble):
        return float(expr)
    return None


def backend_number(value: Number) -> Backend:
    """A coefficient's number as a SymEngine number (a float stays a double, 2.0 too)."""
    if value.__class__ is int:
        return se.Integer(value)
    if isinstance(value, Fraction):
        if value.denominator == 1:
            return se.Integer(value.numerator)
        return se.Rational(value.numerator, value.denominator)
    return se.RealDouble(value)


def pairs(key: Key) -> Iterator[tuple[int, int]]:
    """The (generator index, exponent) pairs of a monomial.

    >>> list(pairs((0, 2, 3, 1)))
    [(0, 2), (3, 1)]
    """
    it = iter(key)
    return zip(it, it)


def _monomials(terms: Sequence[Any]) -> Iterator[tuple[Key, int]]:
    """The (monomial, integer factor) pairs of :data:`Terms` (or of a list of them)."""
    it = iter(terms)
    return zip(it, it)


def _joined(a: Key, b: Key) -> Key:
    """The product of two monomials merged in index order (both are sorted), made without a
    dict and a sort: most are joined end to end (the velocities after the angles)."""
    if not a or not b or a[-2] < b[0]:
        return a + b
    if b[-2] < a[0]:
        return b + a
    out: list[int] = []
    i = j = 0
    la, lb = len(a), len(b)
    while i < la and j < lb:
        ia, ib = a[i], b[j]
        if ia < ib:
            out += a[i : i + 2]
            i += 2
        elif ib < ia:
            out += b[j : j + 2]
            j += 2
        else:
            out += (ia, a[i + 1] + b[j + 1])
            i += 2
            j += 2
    out += a[i:]
    out += b[j:]
    return tuple(out)


def _spliced(others: Key, indices: list[int], part: Key) -> Key:
    """The monomial ``others`` (its generator indices ``indices``) times ``part``, which has
    none of them: each pair of ``part`` put in at its place, found by bisection (the terms of
    a reduction share ``others``: one sort for all, not one per term)."""
    out: Key = ()
    start = 0
    for k in range(0, len(part), 2):
        at = 2 * bisect(indices, part[k])
        out += others[start:at] + part[k : k + 2]
        start = at
    return out + others[start:]


def _key(exponents: Iterable[tuple[int, int]]) -> Key:
    """The monomial of (index, exponent) pairs, sorted by index."""
    return tuple(chain.from_iterable(sorted(exponents)))


class PolynomialTooLarge(ArithmeticError):
    """A polynomial outgrew the :attr:`TrigAlgebra.limit` of monomials: the expression is
    better kept as it is (nested) than expanded."""


class TrigAlgebra:
    """The generators met so far (each sine registered with its cosine) and the memos of
    conversion, products of monomials and derivatives; one per derivation."""

    def __init__(self, state: Iterable[Backend]) -> None:
        self.state = frozenset(state)
        self.gens: list[Backend] = []
        self.index: dict[Backend, int] = {}
        self.partner: dict[int, int] = {}  # sin(u) <-> cos(u)
        self.cosine: list[bool] = []
        self.sine: list[bool] = []
        self.moving: list[bool] = []  # the generator depends on the state
        self._converted: dict[Backend, Poly] = {}
        #: a * b keyed by b, then a: a product by one monomial runs over the many of a
        #: polynomial, each looked up with no key made of both
        self._products: dict[Key, dict[Key, Product]] = {}
        #: derivatives of monomials and of generators (by index, None: not yet taken), by
        #: symbol: a polynomial's terms are looked up with no key made of monomial and symbol
        self._derivatives: dict[Backend, dict[Key, Poly]] = {}
        self._gen_derivatives: dict[Backend, list[Poly | None]] = {}
        self._monomials: dict[Key, Backend] = {}
        self._powers: dict[tuple[int, int], Backend] = {}
        self._factored: dict[frozenset[Backend] | tuple[Backend, ...], Backend] = {}
        self._factored_parts: dict[frozenset[Any] | tuple[Any, ...], Backend] = {}
        self._numbers_in_front: dict[Backend, bool] = {}  # see :meth:`_numbered`
        self._coefficient_terms: dict[Backend, tuple[tuple[Backend, ...], list[Any]]] = {}
        #: the terms (the memo key of :meth:`_built_terms`) each built expression with no
        #: irregular factor was made from
        self._built_from: dict[Backend, frozenset[tuple[Any, ...]]] = {}
        self._parameter_powers: dict[int, dict[Backend, Backend]] = {}
        self._constant_powers: dict[Backend, tuple[Backend, dict[Backend, Backend]]] = {}
        self._sine_reduced: dict[Key, Product] = {}
        self._reductions: dict[tuple[Any, ...], Terms] = {}
        self._splits: dict[Key, tuple[Key, Key]] = {}
        #: The parameter factors (the fields of a packed parameter monomial): symbols, and
        #: factors that are no polynomial taken whole, flagged irregular (SymEngine may
        #: rewrite their powers and products: sqrt(2)**2 is 2).
        self.parameters: list[Backend] = []
        self._parameter_index: dict[Backend, int] = {}
        self._irregular: list[bool] = []
        self._coefficients: dict[Backend, Coefficient] = {}  # parameter expressions
        self._parameter_monomials: dict[int, tuple[Backend, bool]] = {}
        self._built: dict[frozenset[tuple[Any, ...]], tuple[Backend, int]] = {}
        self._integers: dict[int, Backend] = {}  # the coefficients' integers in SymEngine
        #: Whether a float entered a coefficient: 2 and 2.0 are equal keys of a dict, so the
        #: memo of built coefficients then keys each number with its type.
        self._floats = False
        #: Monomials a product or sum may have before :class:`PolynomialTooLarge` (None: any).
        self.limit: int | None = None

    # -- generators -----------------------------------------------------------------------

    def _register(
        self, gen: Backend, moving: bool, sine: bool = False, cosine: bool = False
    ) -> int:
        index = len(self.gens)
        self.gens.append(gen)
        self.index[gen] = index
        self.moving.append(moving)
        self.sine.append(sine)
        self.cosine.append(cosine)
        return index

    def _generator(self, gen: Backend) -> int:
        if gen in self.index:
            return self.index[gen]
        if isinstance(gen, (se.sin, se.cos)):
            argument = gen.args[0]
            moving = not self.state.isdisjoint(argument.free_symbols)
            s = self._register(se.sin(argument), moving, sine=True)
            c = self._register(se.cos(argument), moving, cosine=True)
            self.partner[s], self.partner[c] = c, s
            return self.index[gen]
        return self._register(gen, not self.state.isdisjoint(gen.free_symbols))

    def _monomial(self, gen: Backend, exponent: int = 1) -> Poly:
        index = self._generator(gen)
        return {k: {0: n} for k, n in _monomials(self._reduced({index: exponent}))}

    # -- conversion -----------------------------------------------------------------------

    def convert(self, expr: Backend) -> Poly:
        """``expr`` as a polynomial (zero terms not yet dropped: see :meth:`finish`)."""
        memo = self._converted
        if expr in memo:
            known = memo[expr]
            if known is _NESTED:
                raise PolynomialTooLarge("an expression kept nested")
            return known
        result = self._convert(expr)
        memo[expr] = result
        return result

    def remembered(self) -> int:
        """The number of memo entries (conversions, products, derivatives)."""
        memos: tuple[dict[Any, Any], ...] = (self._converted, self._reductions)
        factored = (self._factored, self._factored_parts, self._coefficient_terms)
        more = (*factored, self._numbers_in_front, self._sine_reduced, self._splits)
        built = (self._coefficients, self._parameter_monomials, self._built, self._integers)
        split = (self._built_from, self._parameter_powers, self._constant_powers)
        by_key = sum(map(len, self._products.values())) + sum(map(len, self._derivatives.values()))
        return by_key + sum(len(memo) for memo in (*memos, *more, *built, *split))

    def keep_nested(self, expr: Backend) -> None:
        """Mark ``expr`` as too large to expand: converting it (or an expression that holds
        it) raises :class:`PolynomialTooLarge` at once."""
        if not expr.is_Number:
            self._converted[expr] = _NESTED

    def _convert(self, expr: Backend) -> Poly:
        if expr.is_Number:
            # a SymEngine zero: comparing with 0 converts it each time
            return {ONE: self.coefficient(expr)} if expr != _ZERO else {}
        if isinstance(expr, se.Symbol):
            if expr in self.state:
                return self._monomial(expr)
            return {ONE: self.coefficient(expr)}
        if isinstance(expr, (se.sin, se.cos)):
            return self._monomial(expr)
        if expr.is_Add:
            parts = [self.convert(a) for a in expr.args]
            if all(_pure(p) for p in parts):
                return {ONE: self.coefficient(expr)}
            return self.add(parts)
        if expr.is_Mul:
            parts = [self.convert(a) for a in expr.args]
            pure = [a for a, p in zip(expr.args, parts) if _pure(p)]
            if len(pure) == len(parts):
                return {ONE: self.coefficient(expr)}
            result: Poly = {ONE: self.coefficient(se.Mul(*pure))}
            for p in parts:
                if not _pure(p):
                    result = self.multiply(result, p)
            return result
        if expr.is_Pow:
            base, exponent = expr.args
            converted = self.convert(base)
            if _pure(converted) and _pure(self.convert(exponent)):
                return {ONE: self.coefficient(expr)}
            if exponent.is_Integer and int(exponent) > 0:
                if isinstance(base, (se.sin, se.cos, se.Symbol)):
                    return self._monomial(base, int(exponent))
                return self.power(converted, int(exponent))
            return self._monomial(expr)
        if all(_pure(self.convert(a)) for a in expr.args):
            return {ONE: self.coefficient(expr)}
        return self._monomial(expr)

    def coefficient(self, expr: Backend) -> Coefficient:
        """A parameter expression as a coefficient (the expansion SymEngine would give)."""
        known = self._coefficients.get(expr)
        if known is None:
            known = self._coefficients[expr] = self._coefficient(expr)
        return known

    def _coefficient(self, expr: Backend) -> Coefficient:
        if expr.is_Number:
            value = number(expr)
            if value is None:
                return self._parameter(expr)
            if value.__class__ is float:
                self._floats = True
            return {0: value}
        if isinstance(expr, se.Symbol):
            return self._parameter(expr)
        if expr.is_Add:
            return _summed([self.coefficient(a) for a in expr.args])
        if expr.is_Mul:
            result: Coefficient = {0: 1}
            for a in expr.args:
                result = _times(result, self.coefficient(a))
            return result
        if expr.is_Pow:
            base, exponent = expr.args
            if exponent.is_Integer and isinstance(base, se.Symbol):
                return self._parameter(base, int(exponent))  # m**2, 1/m
            if exponent.is_Integer and int(exponent) > 0:
                power = self.coefficient(base)
                result = {0: 1}
                for _ in range(int(exponent)):
                    result = _times(result, power)
                return result
            # SymEngine's expansion expands the base of such a power (1/(a + b)**2 is
            # 1/(a**2 + 2 a b + b**2)), and may split it (sqrt(4 m) is 2 sqrt(m))
            expanded = se.expand(expr)
            if expanded != expr:
                return self.coefficient(expanded)
        return self._parameter(expr)  # SymEngine's expansion leaves function arguments alone

    def _parameter(self, factor: Backend, exponent: int = 1) -> Coefficient:
        """A parameter factor (a symbol, or a factor taken whole) to an integer power."""
        index = self._parameter_index.get(factor)
        if index is None:
            index = self._parameter_index[factor] = len(self.parameters)
            self.parameters.append(factor)
            self._irregular.append(not isinstance(factor, se.Symbol))
        return {exponent << (BITS * index): 1}

    # -- arithmetic -----------------------------------------------------------------------

    def add(self, polys: Iterable[Poly]) -> Poly:
        total = Sum()
        for p in polys:
            total.add(p)
        return self.gather(total)

    def _check_size(self, monomials: int) -> None:
        """Raise :class:`PolynomialTooLarge` for more ``monomials`` than :attr:`limit`."""
        if self.limit is not None and monomials > self.limit:
            raise PolynomialTooLarge(f"{monomials} monomials")

    def multiply(self, a: Poly, b: Poly) -> Poly:
        if len(a) == 1 and ONE in a:
            c = a[ONE]
            return {k: _times(c, v) for k, v in b.items()}
        if not b:  # a factor that vanishes (a derivative of a constant)
            return {}
        if len(a) == 1 and len(b) == 1:  # two factors of a product term: no sum to make
            for ka, ca in a.items():
                for kb, cb in b.items():
                    return self._term_product(ka, ca, kb, cb)
        product = Sum()
        self.accumulate_product(product, a, b)
        return self.gather(product)

    def _term_product(self, ka: Key, ca: Coefficient, kb: Key, cb: Coefficient) -> Poly:
        """The product of two terms, as :meth:`accumulate` makes it (a reduction's terms
        are distinct monomials)."""
        value = _times(ca, cb)
        r = self._product(kb, ka)
        if not r or r[0].__class__ is int:
            return {r: value}
        result = {key: value if n == 1 else _scaled(value, n) for key, n in _monomials(r)}
        self._check_size(len(result))
        return result

    def accumulate_product(
        self, target: Sum, a: Poly, b: Poly, weight: Coefficient | None = None
    ) -> None:
        """Add ``weight`` (a coefficient, 1 when None) * ``a`` * ``b`` to ``target``: the
        products of many pairs summed into one, as an entry of M sums every body's share,
        with no polynomial made per pair."""
        for ka, ca in a.items():
            self.accumulate(target, b, ka, ca if weight is None else _times(weight, ca))

    def accumulate(
        self, target: Sum, p: Poly, factor: Key, scale: Coefficient | Number = 1
    ) -> None:
        """Add ``scale`` (a coefficient or a number) * monomial ``factor`` * ``p`` to
        ``target``."""
        known = self._products_by(factor)  # most pairs are known
        coefficient = isinstance(scale, dict)
        plain = not coefficient and scale.__class__ is int and scale == 1
        result, made = target.poly, target.made
        for k, c in p.items():
            if plain:
                value = c
            elif coefficient:
                value = _times(scale, c)  # type: ignore[arg-type]
            else:
                value = _scaled(c, scale)  # type: ignore[arg-type]
            r = known.get(k)
            if r is None:
                r = known[k] = self._made_product(k, factor)
            if not r or r[0].__class__ is int:  # a monomial
                _add_into(result, made, r, value)
                continue
            for key, n in _monomials(r):
                _add_into(result, made, key, value, n)

    def gather(self, target: Sum) -> Poly:
        """The polynomial summed in ``target`` (see :meth:`accumulate`): the sum's own dict,
        so ``target`` is done with once gathered (adding to it again would change the
        polynomial handed out, and what was made of it)."""
        self._check_size(len(target.poly))
        return target.poly

    def power(self, p: Poly, exponent: int) -> Poly:
        result: Poly = {ONE: {0: 1}}
        for _ in range(exponent):
            result = self.multiply(result, p)
        return result

    @staticmethod
    def scale(p: Poly, factor: Coefficient | Number) -> Poly:
        if isinstance(factor, dict):
            return {k: _times(factor, c) for k, c in p.items()}
        return {k: _scaled(c, factor) for k, c in p.items()}

    def multiply_keys(self, a: Key, b: Key) -> Key:
        """The product of two monomials that need no reduction (no cosine squared)."""
        key = self._product(a, b)
        assert not key or key[0].__class__ is int, "a product that needs reduction"
        return key

    def _product(self, a: Key, b: Key) -> Product:
        """The product of two monomials, remembered."""
        known = self._products_by(b)
        product = known.get(a)
        if product is None:
            product = known[a] = self._made_product(a, b)
        return product

    def _products_by(self, b: Key) -> dict[Key, Product]:
        """The remembered products a * b, keyed by a."""
        known = self._products.get(b)
        if known is None:
            known = self._products[b] = {}
        return known

    def _made_product(self, a: Key, b: Key) -> Product:
        """a * b merged, and reduced when it has a cosine squared."""
        reduced = self._stretch_reduced(_joined(a, b), self.cosine)
        if reduced is not None:
            return reduced
        # two angles' cosines squared: the binomials expanded in the order of a's powers,
        # then b's
        exponents = dict(pairs(a))
        for i, e in pairs(b):
            exponents[i] = exponents.get(i, 0) + e
        return self._reduced(exponents)

    def _reduced(self, exponents: dict[int, int], squares: list[bool] | None = None) -> Terms:
        """The monomial of ``exponents`` with every f(x)**k, k >= 2 (f the cosine, or the
        generators flagged in ``squares``) written as f**(k mod 2) (1 - g**2)**(k // 2).

        The terms come in the order of expanding the binomials one after the other in the
        order of ``exponents`` (the last varying fastest).  Only the powers of those f and
        their partners g change: the terms of that part are remembered by it alone (a few
        dozen, where the whole monomials, with their velocities and other factors, are
        thousands), and the other powers are merged into each."""
        squares = self.cosine if squares is None else squares
        partner = self.partner
        touched: list[int] = []  # (i, e, i, e, ...) of every f and g, in exponents' order
        rest: list[tuple[int, int]] = []
        for i, e in exponents.items():
            if not e:
                continue
            reduced = squares[i] and e >= 2  # an f**k, or the g of one:
            if reduced or (exponents.get(partner.get(i, -1), 0) >= 2 and squares[partner[i]]):
                touched += (i, e)
            else:
                rest.append((i, e))
        terms = self._reduced_part(squares, tuple(touched))
        if not rest:
            return terms
        rest.sort()
        others = tuple(chain.from_iterable(rest))
        indices = [i for i, _ in rest]
        flat: list[Any] = []
        for key, n in _monomials(terms):
            flat += (_spliced(others, indices, key), n)
        return tuple(flat)

    def _reduced_part(self, squares: list[bool], touched: Key) -> Terms:
        """:meth:`_reduced` of the powers ``touched`` (i, e, ...): the ones it changes."""
        memo_key = (squares is self.sine, *touched)
        known = self._reductions.get(memo_key)
        if known is not None:
            return known
        base: dict[int, int] = {}  # what every term has: the other powers, f**(k mod 2)
        binomials: list[tuple[int, int]] = []  # (g, k // 2) of each f(x)**k
        partner = self.partner
        for i, e in pairs(touched):
            if e >= 2 and squares[i]:
                half, rest = divmod(e, 2)
                if rest:
                    base[i] = rest
                binomials.append((partner[i], half))
            else:
                base[i] = e
        # (powers, factor) of the terms, multiplied out binomial by binomial
        terms = [(base, 1)]
        for other, half in binomials:
            expanded = []
            for powers, n in terms:
                expanded.append((powers, n))
                for j in range(1, half + 1):  # C(half, j) (-g**2)**j
                    raised = dict(powers)
                    raised[other] = raised.get(other, 0) + 2 * j
                    expanded.append((raised, -n * comb(half, j) if j % 2 else n * comb(half, j)))
            terms = expanded
        flat: list[Any] = []
        for powers, n in terms:
            flat += (_key(powers.items()), n)  # all e > 0
        result = self._reductions[memo_key] = tuple(flat)
        return result

    # -- calculus -------------------------------------------------------------------------

    def derivative(self, p: Poly, symbol: Backend) -> Poly:
        """dp/d``symbol`` (``symbol`` a state symbol)."""
        known = self._derivatives.get(symbol)
        if known is None:
            known = self._derivatives[symbol] = {}
        result: Poly = {}
        made: set[Key] = set()
        for k, c in p.items():
            d = known.get(k)
            if d is None:
                d = known[k] = self._spliced_derivative(k, symbol, known)
            for key, value in d.items():
                _add_into(result, made, key, _times(c, value))
        self._check_size(len(result))
        return result

    def symbols(self, p: Poly) -> set[Backend]:
        """The state symbols ``p`` depends on (through its generators): a derivative by any
        other is zero."""
        gens, moving = self.gens, self.moving
        indices = {i for key in p for i in key[::2] if moving[i]}
        return set().union(*(gens[i].free_symbols for i in indices)) & self.state

    def _spliced_derivative(self, key: Key, symbol: Backend, known: dict[Key, Poly]) -> Poly:
        """The derivative of a monomial as that of its state part times its constant part
        (sines and cosines of constant angles, such as a head-tube angle): M's monomials
        differ mostly there, so the state part's derivative is remembered in ``known`` and
        met again (the product reduced, should the derivative hold the constant angles)."""
        moving, constant = self.split(key)
        if not constant or not moving:
            return self._key_derivative(key, symbol)
        d = known.get(moving)
        if d is None:
            d = known[moving] = self._key_derivative(moving, symbol)
        parts = Sum()
        self.accumulate(parts, d, constant)
        return self.gather(parts)

    def _key_derivative(self, key: Key, symbol: Backend) -> Poly:
        """The derivative of a monomial (remembered by :meth:`derivative`)."""
        rates = self._gen_derivatives.get(symbol)
        if rates is None:
            rates = self._gen_derivatives[symbol] = []
        rates += [None] * (len(self.gens) - len(rates))  # the generators registered since
        parts = Sum()
        moving = self.moving
        for at in range(0, len(key), 2):
            i, e = key[at], key[at + 1]
            if not moving[i]:
                continue
            d = rates[i]
            if d is None:
                d = rates[i] = self._gen_derivative(i, symbol)
            if not d:
                continue
            lowered = (i, e - 1) if e > 1 else ()  # the rest stays in index order
            self.accumulate(parts, d, key[:at] + lowered + key[at + 2 :], e)
        return self.gather(parts)

    def _gen_derivative(self, i: int, symbol: Backend) -> Poly:
        gen = self.gens[i]
        if isinstance(gen, se.Symbol):
            result: Poly = {ONE: {0: 1}} if gen == symbol else {}
        elif self.sine[i] or self.cosine[i]:
            rate = self.convert(se.expand(gen.args[0].diff(symbol)))
            turned: Poly = {(self.partner[i], 1): {0: 1 if self.sine[i] else -1}}
            result = self.multiply(turned, rate) if rate else {}
        else:
            result = self.convert(se.expand(gen.diff(symbol)))
        return result

    # -- results --------------------------------------------------------------------------

    @staticmethod
    def finish(p: Poly) -> Poly:
        """Zero terms and coefficients dropped (the sums are expanded as they are formed)."""
        result = {}
        for k, c in p.items():
            value = _nonzero(c)
            if value:
                result[k] = value
        return result

    def sine_form(self, p: Poly) -> Poly:
        """A finished polynomial with every sin^2 x written as 1 - cos^2 x instead (the other
        canonical form)."""
        memo = self._sine_reduced
        reductions = []
        for k in p:
            r = memo.get(k)
            if r is None:
                r = memo[k] = self._sine_reduction(k)
            reductions.append(r)
        if all(map(eq, reductions, p)):  # no sine squared: the same polynomial
            return p
        result: Poly = {}
        made: set[Key] = set()
        for c, r in zip(p.values(), reductions):
            if not r or r[0].__class__ is int:  # the monomial itself: no sine squared
                _add_into(result, made, r, c)
                continue
            for key, n in _monomials(r):
                _add_into(result, made, key, c, n)
        # only a sum can vanish: p's coefficients, and their integer multiples, are nonzero
        for key in made:
            value = _nonzero(result[key])
            if value:
                result[key] = value
            else:
                del result[key]
        return result

    def _sine_reduction(self, key: Key) -> Product:
        """The monomial ``key`` with every sin^2 x written as 1 - cos^2 x: ``key`` itself when
        it has no sine squared (remembered by :meth:`sine_form`: the same monomials recur in
        every entry)."""
        reduced = self._stretch_reduced(key, self.sine)
        return self._stretches_reduced(key, self.sine) if reduced is None else reduced

    def _stretch_reduced(self, key: Key, squares: list[bool]) -> Product | None:
        """:meth:`_reduced` of a monomial with at most one f(x)**k, k >= 2 (f flagged in
        ``squares``): ``key`` itself when it has none, None when it has more than one.

        An angle's sine and cosine are registered together (neighbouring generator indices,
        see :meth:`_generator`), so the powers that change, f's and its partner's, are one
        stretch of the sorted monomial, and the terms of their reduction go where the
        stretch was: no other generator comes between."""
        at = -1  # the place of f
        for k in range(0, len(key), 2):  # a loop, not any(...): this runs for every monomial
            if key[k + 1] > 1 and squares[key[k]]:
                if at >= 0:
                    return None
                at = k
        if at < 0:
            return key
        start, end = self._stretch(key, at)
        head, tail = key[:start], key[end:]
        flat: list[Any] = []
        for part, n in _monomials(self._reduced_part(squares, key[start:end])):
            flat += (head + part + tail, n)
        return tuple(flat)

    def _stretches_reduced(self, key: Key, squares: list[bool]) -> Terms:
        """:meth:`_reduced` of the powers of ``key`` in its own order (the binomials of its
        f(x)**k expanded in index order, the first varying slowest): each stretch of an f and
        its partner reduced on its own (:meth:`_reduced_part`, remembered by its powers),
        the terms of the whole the products of one term of each stretch, the powers between
        the stretches kept as they are (no dict of powers, no sort, no splice)."""
        terms: list[Any] = [(), 1]  # (the monomial so far, its factor, ...)
        done = 0  # the end of the last stretch
        for at in range(0, len(key), 2):
            if at < done or key[at + 1] < 2 or not squares[key[at]]:
                continue
            start, end = self._stretch(key, at)
            between = key[done:start]
            parts = self._reduced_part(squares, key[start:end])
            grown: list[Any] = []
            for head, n in _monomials(terms):
                head += between
                for part, m in _monomials(parts):
                    grown += (head + part, n * m)
            terms, done = grown, end
        tail = key[done:]
        for k in range(0, len(terms), 2):
            terms[k] += tail
        return tuple(terms)

    def _stretch(self, key: Key, at: int) -> tuple[int, int]:
        """(start, end) of the powers of the f at ``at`` of ``key`` and of its partner, which
        neighbours it when present."""
        start, end = at, at + 2
        partner = self.partner[key[at]]
        if partner > key[at]:
            if end < len(key) and key[end] == partner:
                end += 2
        elif start and key[start - 2] == partner:
            start -= 2
        return start, end

    def monomial_expression(self, key: Key) -> Backend:
        memo = self._monomials.get(key)
        if memo is None:
            powers = self._powers
            factors = []
            for pair in pairs(key):
                power = powers.get(pair)
                if power is None:
                    power = powers[pair] = self.gens[pair[0]] ** pair[1]
                factors.append(power)
            memo = self._monomials[key] = se.Mul(*factors)
        return memo

    def parameter_monomial(self, packed: int) -> tuple[Backend, bool]:
        """(the expression, whether it holds an irregular factor) of a packed parameter
        monomial, remembered."""
        known = self._parameter_monomials.get(packed)
        if known is None:
            factors, irregular, index, rest = [], False, 0, packed
            powers: dict[Backend, Backend] = {}  # base -> exponent, as a product's factors
            while rest:
                exponent = rest & _FIELD
                if exponent > _FIELD >> 1:
                    exponent -= _FIELD + 1
                rest = (rest - exponent) >> BITS
                if exponent:
                    factors.append(self.parameters[index] ** exponent)
                    powers[self.parameters[index]] = se.Integer(exponent)
                    irregular = irregular or self._irregular[index]
                index += 1
            known = self._parameter_monomials[packed] = (se.Mul(*factors), irregular)
            self._parameter_powers[packed] = powers
        return known

    def built(self, coefficient: Coefficient) -> Backend:
        """A coefficient as SymEngine's expanded sum: the canonical sum of number *
        monomial over its terms (expanded by SymEngine, too, when it holds an irregular
        factor), remembered: the same coefficients recur."""
        return self._built_terms(coefficient)[0]

    def _built_terms(self, coefficient: Coefficient) -> tuple[Backend, int]:
        """(:meth:`built`, the number of its terms): counted on the coefficient (each packed
        monomial one term of its own), not on the expression (whose arguments SymEngine
        would make into Python objects), unless SymEngine expanded it."""
        memo_key: frozenset[Any]
        if self._floats:  # {0: 2.0} is built as a double, not as {0: 2}'s integer
            memo_key = frozenset((k, n, n.__class__) for k, n in coefficient.items())
        else:
            memo_key = frozenset(coefficient.items())
        known = self._built.get(memo_key)
        if known is None:
            terms, irregular = [], False
            for k, n in coefficient.items():
                if n:
                    monomial, odd = self.parameter_monomial(k)
                    terms.append(self._number_times(n, monomial))
                    irregular = irregular or odd
            expr = se.Add(*terms)
            if irregular:
                expr = se.expand(expr)
                known = (expr, _count(expr))
            else:
                known = (expr, len(terms) or 1)  # 0 is one term
                if terms:
                    self._built_from[expr] = memo_key  # its (packed, number, ...) terms
            self._built[memo_key] = known
        return known

    def _number_times(self, n: Number, monomial: Backend) -> Backend:
        """``n`` * ``monomial`` as SymEngine forms it: an integer +-1 with no product and no
        number made (a third of a coefficient's terms), any other integer made once."""
        if not isinstance(n, int):
            return backend_number(n) * monomial
        if n == 1:
            return monomial
        if n == -1:
            return -monomial
        number = self._integers.get(n)
        if number is None:
            number = self._integers[n] = se.Integer(n)
        return number * monomial

    def expression(self, p: Poly) -> Backend:
        """sum monomial * coefficient (each coefficient SymEngine's expanded sum); converting
        it back (in this algebra) gives ``p`` at once."""
        built = self.built
        result = se.Add(*[self.monomial_expression(k) * built(c) for k, c in p.items()])
        self._converted.setdefault(result, p)
        return result

    def products_expression(self, parts: list[tuple[Key, Poly]]) -> Backend:
        """sum monomial * :meth:`expression` of its polynomial over ``parts`` (no two
        products with a monomial in common: the pairs of velocities of C q_dot's row times
        their Christoffel symbols), each part's expression made once for all the monomials
        it multiplies; converting the sum back (in this algebra) gives its polynomial at
        once, as for :meth:`expression`."""
        total = Sum()
        for factor, p in parts:
            self.accumulate(total, p, factor)
        expression, monomial = self.expression, self.monomial_expression
        result = se.Add(*[monomial(factor) * expression(p) for factor, p in parts])
        self._converted.setdefault(result, self.gather(total))
        return result

    def split(self, key: Key) -> tuple[Key, Key]:
        """(the state part, the constant part) of a monomial."""
        known = self._splits.get(key)
        if known is None:
            flags = self.moving  # read once, not per power
            moving: list[int] = []
            constant: list[int] = []
            for at in range(0, len(key), 2):
                part = moving if flags[key[at]] else constant
                part.append(key[at])  # no (index, exponent) tuple made per power
                part.append(key[at + 1])
            known = self._splits[key] = (tuple(moving), tuple(constant))
        return known

    def shortest(self, p: Poly) -> Poly:
        """The finished polynomial ``p`` or its :meth:`sine_form`, whichever is shorter."""
        other = self.sine_form(p)
        if other is p:  # no sine squared
            return p
        return other if self.size(other) < self.size(p) else p

    def grouped(self, p: Poly) -> Backend:
        """A finished polynomial as an expression grouped by state monomial, the constant
        coefficient of each with its common factors pulled out
        (:func:`lagrangian.derivation.collect.factor_common`) when it has at most
        :data:`FACTORED_TERMS` terms (a longer one is summed by constant monomial: factoring
        it costs more than the rest of its tidying, and reads no better)."""
        return se.Add(*[k * c for k, c in self._grouped_pairs(p)])

    def grouped_terms(self, p: Poly) -> tuple[Backend, list[tuple[Backend, Backend]] | None]:
        """(:meth:`grouped`, its (state monomial, coefficient) pairs in the order of the
        sum's terms, as collecting the sum by state monomial would find them): collecting
        then reads the pairs instead of walking every factor of every term.  A sum
        coefficient of no state monomial is spread into the sum by SymEngine: its pair
        comes where its first term does, its terms factored as collecting factors them.
        The pairs are None where a monomial holds a number (a power of a function that
        SymEngine writes so): collecting would move the number into the coefficient."""
        pairs = self._grouped_pairs(p)
        terms = [k * c for k, c in pairs]
        result = se.Add(*terms)
        spread = None
        for k, c in pairs:
            if self._numbered(k):
                return result, None
            if spread is None and c.is_Add and k == _ONE:
                spread = c
        if not pairs:
            return result, []
        by_term = dict(zip(terms, pairs))
        in_order = []
        for term in result.args if result.is_Add else (result,):
            pair = by_term.get(term)
            if pair is not None:
                in_order.append(pair)
            elif spread is not None:  # the first term of the spread coefficient
                in_order.append((_ONE, self._factor(spread.args)))
                spread = None
        if len(in_order) != len(pairs):  # a term neither a pair's nor the spread sum's
            return result, None
        return result, in_order

    def _numbered(self, monomial: Backend) -> bool:
        """Whether SymEngine wrote the state monomial ``monomial`` (an expression of
        :meth:`monomial_expression`) with a number in front, remembered: reading a
        product's factors makes a Python object of each, and the same monomials recur in
        every row."""
        known = self._numbers_in_front.get(monomial)
        if known is None:
            known = self._numbers_in_front[monomial] = bool(
                monomial.is_Mul and monomial.args[0].is_Number
            )
        return known

    def _grouped_pairs(self, p: Poly) -> list[tuple[Backend, Backend]]:
        """The (state monomial, coefficient) pairs of :meth:`grouped`, in monomial order."""
        groups: dict[Key, list[Any]] = {}  # state monomial -> [its terms, its parts]
        split, built_terms, monomial = self.split, self._built_terms, self.monomial_expression
        for k, c in p.items():
            moving, constant = split(k)
            built, count = built_terms(c)
            group = groups.get(moving)  # one look-up per monomial, no defaultdict
            if group is None:
                groups[moving] = [count, [(monomial(constant), built)]]
            else:
                group[0] += count
                group[1].append((monomial(constant), built))
        result = []
        for k, (count, parts) in groups.items():
            if count <= FACTORED_TERMS:
                coefficient = self._factor_parts(parts)
            else:
                coefficient = se.Add(*[f * c for f, c in parts])
            result.append((monomial(k), coefficient))
        return result

    def _factor_parts(self, parts: list[tuple[Backend, Backend]]) -> Backend:
        """:meth:`_factor` of the terms of sum f c over ``parts`` (constant monomial f,
        expanded coefficient c), remembered by the parts: the same parts recur in the
        entries of M, in C q_dot and in the forcing, and making their terms (a product per
        term, the terms of each sum) costs more than factoring them."""
        key = _unordered(parts)
        known = self._factored_parts.get(key)
        if known is None:
            known = self._factored_parts[key] = self._factored_products(parts)
        return known

    def _factored_products(self, parts: list[tuple[Backend, Backend]]) -> Backend:
        """:meth:`_factor` of the terms f t (t a term of c) over ``parts``, their numbers
        and powers read off f's and t's, which recur (:meth:`_monomial_powers`,
        :meth:`_term_powers`), instead of off each product made anew: f is a product of
        powers of generators and t of parameters, so the product's powers are the two sets
        side by side.  Where f has a number or a base of t (SymEngine could combine them),
        or c is 0, the products are made and factored as they are."""
        split: list[tuple[Backend, dict[Backend, Backend]]] = []
        products: list[tuple[Backend, Backend]] = []
        for f, c in parts:
            f_number, f_powers = self._monomial_powers(f)
            if f_number is not _ONE or (c.is_Number and c == _ZERO):
                return self._factor([f * t for f, c in parts for t in _terms_of(c)])
            terms, splits = self._term_powers(c)
            for number, powers in splits:
                if not f_powers.keys().isdisjoint(powers):
                    return self._factor([f * t for f, c in parts for t in _terms_of(c)])
                merged = dict(powers)
                merged.update(f_powers)
                split.append((number, merged))
            products += [(f, t) for t in terms]  # the same terms, in SymEngine's order
        return factor_products(split, products)

    def _term_powers(self, coefficient: Backend) -> tuple[tuple[Backend, ...], list[Any]]:
        """(the terms, :func:`collect.term_powers` of each, in their own order) of a built
        coefficient, remembered by the coefficient (one of :meth:`built`'s, met again as the
        same object): its terms are read once, not made anew (SymEngine makes a Python
        object of each, a new product for each with a number) and looked up by value."""
        known = self._coefficient_terms.get(coefficient)
        if known is None:
            terms = _terms_of(coefficient)
            made = self._built_from.get(coefficient)
            if made is None:  # irregular factors: SymEngine's own terms read
                splits = [term_powers(t) for t in terms]
            else:
                splits = [self._term_split(term[0], term[1]) for term in made if term[1]]
            known = self._coefficient_terms[coefficient] = (terms, splits)
        return known

    def _monomial_powers(self, monomial: Backend) -> tuple[Backend, dict[Backend, Backend]]:
        """:func:`collect.term_powers` of a constant monomial's expression, its bases the
        algebra's own generators where they are ones (found by identity while factoring),
        remembered."""
        known = self._constant_powers.get(monomial)
        if known is None:
            number, powers = term_powers(monomial)
            gens, index = self.gens, self.index
            own = {gens[index[b]] if b in index else b: e for b, e in powers.items()}
            known = self._constant_powers[monomial] = (number, own)
        return known

    def _term_split(self, packed: int, n: Number) -> tuple[Backend, dict[Backend, Backend]]:
        """:func:`collect.term_powers` of the term n * (packed parameter monomial) of a
        coefficient with no irregular factor (:meth:`_built_terms` makes it so: the number
        first, each parameter a factor of its own), read off the packed monomial: its bases
        are the algebra's own parameter symbols, so looking them up while factoring finds
        them by identity, without comparing SymEngine objects."""
        number = _ONE if n.__class__ is int and n == 1 else backend_number(n)
        return number, self._parameter_powers[packed]

    def _factor(self, terms: Sequence[Backend]) -> Backend:
        """:func:`factor_common` of ``terms``, remembered: the same coefficient recurs in the
        entries of M, in C q_dot and in the forcing (a bicycle's 510 coefficients are 129),
        its terms in any order (the factored sum does not depend on it)."""
        key = _unordered(terms)
        known = self._factored.get(key)
        if known is None:
            known = self._factored[key] = factor_common(list(terms))
        return known

    def terms(self, p: Poly) -> int:
        """The number of terms of the expanded form of a finished polynomial."""
        return sum(map(len, p.values()))

    def size(self, p: Poly) -> int:
        """A size for choosing between forms: terms of the coefficients plus factors."""
        total = 0
        for k, c in p.items():  # a loop: a generator costs more than its sums here
            total += len(c)
            for at in range(1, len(k), 2):
                total += k[at]
        return total


def _unordered(items: Sequence[Any]) -> frozenset[Any] | tuple[Any, ...]:
    """A memo key of distinct ``items`` in any order: their frozenset (each item hashed
    once, where a tuple sorted by hash hashes each again when looked up); their tuple
    sorted by hash should two be equal (a set would lose one)."""
    key = frozenset(items)
    return key if len(key) == len(items) else tuple(sorted(items, key=hash))


def _terms_of(coefficient: Backend) -> tuple[Backend, ...]:
    """The terms of an expanded SymEngine coefficient (itself when it is no sum)."""
    return coefficient.args if coefficient.is_Add else (coefficient,)


def _count(coefficient: Backend) -> int:
    """The number of terms of an expanded SymEngine coefficient."""
    return len(coefficient.args) if coefficient.is_Add else 1


def expanded_terms(expr: Backend, cap: int) -> int:
    """An upper bound of the number of terms of ``se.expand(expr)``, or ``cap`` when it
    reaches ``cap`` (counted on the tree, each distinct subexpression once)."""
    memo: dict[Backend, int] = {}

    def count(e: Backend) -> int:
        known = memo.get(e)
        if known is not None:
            return known
        if e.is_Add:
            result = min(cap, sum(count(a) for a in e.args))
        elif e.is_Mul:
            result = 1
            for a in e.args:
                result = min(cap, result * count(a))
        elif e.is_Pow and e.args[1].is_Integer and int(e.args[1]) > 1:
            result = min(cap, count(e.args[0]) ** min(int(e.args[1]), 64))
        else:
            result = 1
        memo[e] = result
        return result

    return count(expr)


_ALGEBRAS = threading.local()
#: Algebras (of different states) each thread keeps, the most recently used last.
KEPT_ALGEBRAS = 2
#: Memo entries beyond which :func:`algebra_for` starts a kept algebra afresh.
KEPT_MEMOS = 200_000


def algebra_for(state: Iterable[Backend]) -> TrigAlgebra:
    """The algebra of the state ``state`` of this thread, made when first asked for (only
    the :data:`KEPT_ALGEBRAS` most recently used are kept): the kinetic form and the tidying
    of the equations share its generators and conversions."""
    key = frozenset(state)
    kept: dict[frozenset[Backend], TrigAlgebra] = getattr(_ALGEBRAS, "kept", None) or {}
    algebra = kept.pop(key, None)
    if algebra is None or algebra.remembered() > KEPT_MEMOS:
        algebra = TrigAlgebra(key)  # a long run (a sweep) does not grow the memos for ever
    kept[key] = algebra
    while len(kept) > KEPT_ALGEBRAS:
        del kept[next(iter(kept))]
    _ALGEBRAS.kept = kept
    return algebra


def forget_algebras() -> None:
    """Drop this thread's algebras (and the expressions their memos hold)."""
    _ALGEBRAS.kept = {}


def _pure(p: Poly) -> bool:
    """True when ``p`` is a constant (no generator): a coefficient."""
    return len(p) <= 1 and all(k == ONE for k in p)
