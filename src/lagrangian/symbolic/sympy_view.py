"""SymEngine results back as SymPy, with the user's own symbol objects: the one conversion
that the derivation, the constraints and the model's rolling contacts share.

The SymPy expressions are built as SymPy's constructors build them (the same arguments in the
same order, so ``srepr`` is equal), with SymPy's general evaluation skipped where the
arguments are canonical already (:func:`~lagrangian.symbolic.canonical.sympy_sum`,
:func:`~lagrangian.symbolic.canonical.sympy_product`), which is most of
the time of converting large equations.
"""

from __future__ import annotations

import gc
import math
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, NamedTuple

import symengine as se
import sympy as sp
from sympy.core.parameters import global_parameters

from lagrangian.size_limits import active_operations, check_operations
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.canonical import (
    ARGS,
    EXPR,
    KIND,
    PLAIN,
    PRODUCT,
    RATIONAL,
    Builder,
    Monomial,
    Part,
)
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import piecewise_smooth

Backend = Any  # a symengine expression

_TRIG: dict[type, Callable[..., sp.Expr]] = {se.sin: sp.sin, se.cos: sp.cos}


class SympyView:
    """Converts SymEngine results back to SymPy, with the user's symbol objects.

    Sines and cosines of a difference of two symbols, which pendulum-like systems have by
    the hundred, are built directly in SymPy's canonical form (the first symbol in SymPy's
    order positive) instead of through SymPy's general evaluation; sums and products of
    terms that are canonical already skip most of it, each made from what is known of its
    converted arguments (:class:`lagrangian.symbolic.canonical.Builder`); everything else
    goes through SymPy's own constructors.
    """

    def __init__(
        self, symbols: Iterable[sp.Symbol], names: dict[str, sp.Expr] | None = None
    ) -> None:
        """``symbols`` are the SymPy objects of the backend symbols of the same names;
        ``names`` maps further names to any SymPy expression the symbol stands for."""
        self.by_name: dict[str, sp.Expr] = {s.name: s for s in symbols}
        self.by_name.update(names or {})
        # a backend expression's hash -> (its Part converted, its operations counted over its
        # tree, the expression): SymEngine gives a new wrapper of the same expression on each
        # ``args``, and a dict keyed by expressions tests the one it finds for equality
        # through two Python-level ``_sympify`` calls (0.4 us), where comparing the two
        # directly (:data:`_EQUAL`) takes a third of that; expressions of the same hash that
        # differ (rare) are kept in ``_clashes``
        self._memo: dict[int, tuple[Part, int, Backend]] = {}
        self._clashes: dict[Backend, tuple[Part, int, Backend]] = {}
        # the operations past which a sized conversion stops, per thread (as the size limits
        # themselves: one thread's limit never stops another's conversion of the same view)
        self._sizing = _Sizing()
        # counts what is not converted part by part: a function handed to SymPy whole, or an
        # entry past the size limit (for the message)
        self._tree_operations = TreeOperations()
        self._builder = Builder()
        # a backend angle -> (the angle converted, its canonical form if SymPy's sine and
        # cosine leave it as it is (else None), flipped, its operations)
        self._angles: dict[Backend, tuple[Part, _Angle | None, bool, int]] = {}
        # (first, second) symbols -> first - second; shared by the angles x - y and y - x
        self._differences: dict[tuple[sp.Symbol, sp.Symbol], _Angle] = {}
        self._negatives: dict[sp.Symbol, Part] = {}  # symbol -> -symbol
        # a backend term of a sum's hash -> its factors converted (itself if not a product),
        # its operations, and the term
        self._factors: dict[int, tuple[Monomial, int, Backend]] = {}
        # the terms whose hash another term has in _factors (rare), by the terms themselves
        self._clashing_factors: dict[Backend, tuple[Monomial, int, Backend]] = {}
        # (id of a number's Part, id of a term's Monomial) -> their product converted, its
        # operations, and the Part and the term's entry of _factors (kept alive with the ids)
        self._products: dict[tuple[int, int], tuple[Part, int, Part, Any]] = {}

    def __call__(self, expr: Backend) -> sp.Expr:
        return self._converted(expr)[0][EXPR]

    def operations(self, expr: Backend) -> int:
        """The operations of ``expr`` counted over its tree as SymEngine's ``count_ops``
        counts them (:func:`lagrangian.size_limits.operations`), read off its conversion:
        each distinct subexpression is counted once and its count remembered with its
        converted Part (a chain's mass sums m_k + ... + m_n recur in n entries of M each)."""
        return self._converted(expr)[1]

    def _converted(self, expr: Backend) -> tuple[Part, int, Backend]:
        """The :data:`~lagrangian.symbolic.canonical.Part` of ``expr`` converted, and its
        operations; :class:`_PastLimit` before converting a sum, product, power or function
        of more operations than the limit of a sized conversion."""
        known = self._memo.get(hash(expr))
        if known is None:
            return self._convert(expr)
        if known[2] is not expr and not _EQUAL(known[2], expr, _EQ):
            return self._clashing(expr)
        return known

    def _clashing(self, expr: Backend) -> tuple[Part, int, Backend]:
        """:meth:`_converted` of an expression whose hash is in the memo for another
        expression."""
        return self._clashes.get(expr) or self._convert(expr)

    def _convert(self, expr: Backend) -> tuple[Part, int, Backend]:
        """:meth:`_converted` of an expression not converted yet."""
        build = self._builder
        kind = type(expr)  # read once: SymEngine's ``is_Add``... are properties
        if kind is _ADD:
            terms, count = self._terms(expr)
            result = build.sum(terms)
        elif kind is _MUL:
            term = self._factors.get(hash(expr))  # met before as a term of a sum
            if term is not None and _EQUAL(term[2], expr, _EQ):
                result, count = build.unscaled(term[0]), self._within(term[1])
            else:
                result, count = self._product(expr.args)
        elif kind is _POW:
            base, exponent = arguments = expr.args
            (power, base_count, _), (root, exponent_count, _) = map(self._converted, arguments)
            count = self._within(1 + base_count + exponent_count)
            if type(base) is _ADD and exponent.is_Rational:
                result = build.part(sympy_sum_power(power[EXPR], root[EXPR], base.has(se.I)))
            elif power[KIND] == PLAIN and root[KIND] == RATIONAL:
                result = build.part(plain_power(power[EXPR], root[EXPR]))
            else:
                result = build.part(sp.Pow(power[EXPR], root[EXPR]))
        elif isinstance(expr, se.Symbol):
            count, result = 0, build.part(self.by_name.get(expr.name) or sp.Symbol(expr.name))
        elif kind in _TRIG:
            result, count = self._trig(_TRIG[kind], expr.args[0])
        elif expr.is_Rational:
            count, result = 0, build.part(_sympy_rational(expr))
        elif expr.is_Number:
            count, result = 0, build.part(to_sympy(expr))
        else:
            count = self._within(self._tree_operations(expr))
            result = build.part(self._fallback(expr))
        known = (result, count, expr)
        if self._memo.setdefault(hash(expr), known) is not known:
            self._clashes[expr] = known
        return known

    def _product(self, factors: tuple[Backend, ...]) -> tuple[Part, int]:
        """The product of the backend ``factors`` converted, and its operations."""
        if len(factors) == 2 and type(factors[1]) is _ADD and factors[0].is_Rational:
            distributed = self._distributed(*factors)
            if distributed is not None:
                return distributed
        parts, count = self._arguments(factors)
        return self._builder.product(parts), count

    def _within(self, count: int) -> int:
        """``count``, checked against the limit of a sized conversion."""
        if count > self._sizing.limit:
            raise _PastLimit
        return count

    def _all(self, entries: list[Backend], named: Callable[[int], str] | None) -> list[sp.Expr]:
        """Every entry converted; with ``named`` (the entry at an index, named for a
        message), each within the size limit that applies
        (:func:`lagrangian.size_limits.active_operations`): SizeLimitError naming the first
        entry past it, raised before the subexpression past the limit is converted.  Every
        subexpression of an entry has at most the entry's operations, so this is the entry
        that counting every entry first would name."""
        with cycle_collection_paused():
            if named is None:
                return [self(v) for v in entries]
            self._sizing.limit = active_operations()
            try:
                return [self._sized(v, i, named) for i, v in enumerate(entries)]
            finally:
                self._sizing.limit = math.inf

    def _sized(self, entry: Backend, index: int, named: Callable[[int], str]) -> sp.Expr:
        try:
            part, count, _ = self._converted(entry)
        except _PastLimit:
            # the message gives the whole entry's operations
            check_operations(self._tree_operations(entry), named(index))
            raise  # not reached: the entry holds the subexpression past the limit
        if count > self._sizing.limit:  # converted before, by a conversion without a limit
            check_operations(count, named(index))
        return part[EXPR]

    def _arguments(self, arguments: tuple[Backend, ...]) -> tuple[tuple[Part, ...], int]:
        """The ``arguments`` of a product converted (most are met before: looked up
        directly), and the operations of the product."""
        get, convert, clashing = self._memo.get, self._convert, self._clashing
        parts, counts = [], 0
        for a in arguments:  # _converted, inline: a product's factors are most lookups
            known = get(hash(a))
            if known is None:
                known = convert(a)
            elif known[2] is not a and not _EQUAL(known[2], a, _EQ):
                known = clashing(a)
            parts.append(known[0])
            counts += known[1]
        return tuple(parts), self._within(len(parts) - 1 + counts)

    def _terms(self, expr: Backend) -> tuple[list[Part], int]:
        """The arguments of the sum ``expr`` converted, and the operations of ``expr``.

        SymEngine keeps a sum as its constant and a table of terms without their
        coefficients, and makes each argument that has a coefficient anew for each call of
        ``expr.args`` (a product of the coefficient and the term's factors), which is then
        hashed, looked up and converted afresh.  So the terms are read with their
        coefficients apart (:meth:`_scaled`): a bicycle's sums share the same monomials of
        inertias and lengths, each with its own number."""
        get, convert, clashing = self._memo.get, self._convert, self._clashing
        items = iter(expr.as_coefficients_dict().items())
        _, constant = next(items)  # the constant comes first, under the key 1
        parts = [] if constant is _ZERO else [self._converted(constant)[0]]
        count = len(parts) - 1
        for term, coefficient in items:
            # _converted, inline, of the coefficient or the term
            looked_up = term if coefficient is _ONE else coefficient
            known = get(hash(looked_up))
            if known is None:
                known = convert(looked_up)
            elif known[2] is not looked_up and not _EQUAL(known[2], looked_up, _EQ):
                known = clashing(looked_up)
            part, operations, _ = known
            if coefficient is not _ONE:
                part, operations = self._scaled(part, term)
            parts.append(part)
            count += 1 + operations
        return parts, self._within(count)

    def _distributed(self, number: Backend, total: Backend) -> tuple[Part, int] | None:
        """The rational ``number`` times the sum ``total`` converted, with its operations:
        SymPy's Mul distributes the number (``_keep_coeff`` of each term), SymEngine keeps
        the product (a gamma's -(rate)).  Each term is made once, as the number times its
        coefficient (multiplied in SymEngine) times its factors (:meth:`_scaled`), where
        converting the sum first made each of its terms and then each again times the
        number.  None (converted as a product) when a coefficient is not rational, or
        SymPy's products do not distribute."""
        coefficients = total.as_coefficients_dict()
        if not global_parameters.distribute or not all(
            c.is_Rational for c in coefficients.values()
        ):
            return None
        items = iter(coefficients.items())
        _, constant = next(items)  # the constant comes first, under the key 1
        parts = [] if constant is _ZERO else [self._converted(number * constant)[0]]
        # the operations of number * total as written: one for the product, one between
        # each two of the sum's arguments, and each term's, with one for its coefficient
        # unless that is 1 (_scaled counts one for every number)
        count = len(parts)
        for term, coefficient in items:
            part, operations = self._scaled(self._converted(number * coefficient)[0], term)
            parts.append(part)
            count += 1 + operations - (coefficient is _ONE)
        return self._builder.sum(parts), self._within(count)

    def _scaled(self, number: Part, term: Backend) -> tuple[Part, int]:
        """The product of a number and a term converted, with its operations: the product
        SymEngine makes of the two (the number and the term's factors, in its order), made
        from the term's factors converted and ordered once for all its coefficients
        (:meth:`~lagrangian.symbolic.canonical.Builder.monomial`), and once per number and
        term."""
        term_hash = hash(term)  # looked up as in the memo (a term recurs as a new wrapper)
        factors = self._factors.get(term_hash)
        if factors is None:
            factors = self._factors[term_hash] = self._monomial(term)
        elif not _EQUAL(factors[2], term, _EQ):  # a term of another term's hash (rare)
            factors = self._clashing_factors.get(term) or self._clashing_factors.setdefault(
                term, self._monomial(term)
            )
        pair = (id(number), id(factors[0]))
        scaled = self._products.get(pair)
        if scaled is None:
            made = self._builder.scaled(number, factors[0])
            # the entry holds the two objects its key names, so their ids cannot be reused
            # while it lives (another thread may have replaced them in the memos meanwhile)
            scaled = self._products[pair] = (made, self._within(1 + factors[1]), number, factors)
        return scaled[0], scaled[1]

    def _monomial(self, term: Backend) -> tuple[Monomial, int, Backend]:
        """The factors of the term of a sum (itself if it is not a product) converted and
        read for scaling, the term's operations, and the term."""
        if type(term) is _MUL:
            parts, count = self._factors_of(term)
        else:
            part, count, _ = self._converted(term)
            parts = (part,)
        return self._builder.monomial(parts), count, term

    def _factors_of(self, product: Backend) -> tuple[tuple[Part, ...], int]:
        """The factors of a product without a number converted, and its operations: the
        arguments of its Part if it was converted before as a product of them in SymPy's
        order (a term of one sum recurs with a coefficient in another), else read off
        SymEngine (whose ``args`` makes each factor anew, as a new Python object)."""
        known = self._memo.get(hash(product))
        if known is not None and _EQUAL(known[2], product, _EQ):
            part, count, _ = known
            args = part[ARGS]
            if part[KIND] == PRODUCT and args is not None and args[0][KIND] != RATIONAL:
                return args, self._within(count)
        return self._arguments(product.args)

    def _fallback(self, expr: Backend) -> sp.Expr:
        # SymEngine knows only SymPy's complex Abs and sign, and Heaviside by a stand-in
        result = piecewise_smooth(to_sympy(expr))
        swap = {
            s: self.by_name[s.name]
            for s in result.free_symbols
            if s.name in self.by_name and self.by_name[s.name] is not s
        }
        return result.xreplace(swap) if swap else result

    def _trig(self, function: Callable[..., sp.Expr], angle: Backend) -> tuple[Part, int]:
        """``function`` of the backend ``angle`` and its operations; a difference of two
        symbols in SymPy's canonical order (the first symbol positive), made from the two
        symbols directly: the angle as SymEngine orders it is then never converted (an
        n-link chain has n^2/2 such angles, each in a cosine of M and a sine of the
        forcing).  Of a symbol and of such a difference the value is made without SymPy's
        evaluation (:func:`unevaluated_trig`), which changes neither."""
        build = self._builder
        known = self._angles.get(angle)  # the sine and the cosine of an angle share it
        if known is None:
            pair = _backend_difference(angle)
            x, y = (None, None) if pair is None else (self(pair[0]), self(pair[1]))
            if not (x is not None and x.is_Symbol and y is not None and y.is_Symbol):
                argument, count, _ = self._converted(angle)
                known = (argument, _symbol_angle(argument), False, count)
            else:
                first, second, flipped = _ordered(x, y)
                difference = self._difference(first, second)
                # x + (-1)*y as SymEngine has it: a sum of two terms, one a product of two
                known = (difference.part, difference, flipped, 2)
            self._angles[angle] = known
        argument, canonical, flipped, count = known
        count = self._within(1 + count)
        if canonical is None:
            return build.part(function(argument[EXPR])), count
        value = canonical.values.get(function)
        if value is None:
            made = unevaluated_trig(function, canonical.part[EXPR])
            value = canonical.values[function] = build.function_value(made, canonical.part)
        if flipped and function is sp.sin:
            return build.product([build.part(sp.S.NegativeOne), value]), count
        return value, count

    def _difference(self, first: sp.Symbol, second: sp.Symbol) -> _Angle:
        """first - second (first before second in SymPy's order), made once for both
        orientations of the angle (a chain's forcing has the sines of both)."""
        known = self._differences.get((first, second))
        if known is None:
            made = self._builder.sum([self._builder.part(first), self._negative(second)])
            known = self._differences[(first, second)] = _Angle(made, {})
        return known

    def _negative(self, symbol: sp.Symbol) -> Part:
        """-symbol, made once per symbol."""
        known = self._negatives.get(symbol)
        if known is None:
            known = self._negatives[symbol] = self._builder.part(-symbol)
        return known

    def vector(
        self, values: Iterable[Backend], named: Callable[[int], str] | None = None
    ) -> sp.ImmutableMatrix:
        """The column of ``values`` converted; with ``named`` (an entry's index -> its name in
        a message), each entry within the active size limit (SizeLimitError naming the first
        past it, before it is converted)."""
        entries = list(values)
        return _remember(_immutable(len(entries), 1, self._all(entries, named)), entries)

    def matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        entries = [v for row in rows for v in row]
        columns = len(rows[0]) if rows else 0
        return _remember(_immutable(len(rows), columns, self._all(entries, None)), entries)

    def symmetric_matrix(
        self, rows: Sequence[Sequence[Backend]], named: Callable[[int, int], str] | None = None
    ) -> sp.ImmutableMatrix:
        """Convert the upper triangle only (row by row) and mirror it; with ``named`` (row,
        column -> the entry's name), each entry of the upper triangle within the size limit
        as :meth:`vector`."""
        n = len(rows)
        pairs = [(j, k) for j in range(n) for k in range(j, n)]
        upper_named = None if named is None else (lambda i: named(*pairs[i]))
        upper = dict(zip(pairs, self._all([rows[j][k] for j, k in pairs], upper_named)))
        mirrored = [(min(j, k), max(j, k)) for j in range(n) for k in range(n)]
        converted = _immutable(n, n, [upper[pair] for pair in mirrored])
        return _remember(converted, [rows[j][k] for j, k in mirrored])


class _Angle(NamedTuple):
    """An angle that SymPy's sine and cosine leave as it is: a symbol, or the difference of
    two symbols in SymPy's canonical form; and the sine and the cosine of it made so far
    (by SymPy function)."""

    part: Part
    values: dict[Callable[..., sp.Expr], Part]


def _symbol_angle(argument: Part) -> _Angle | None:
    """The angle ``argument`` as an :class:`_Angle` if it is a plain symbol not known to be
    zero: ``sin.eval`` and ``cos.eval`` (SymPy 1.12 to 1.14) return None for it (they change
    numbers, sums with a multiple of pi, a sign that can be taken out, a multiple of the
    imaginary unit or of pi, an inverse function's value, and an argument that is zero)."""
    symbol = argument[EXPR]
    if type(symbol) is sp.Symbol and symbol.is_zero is not True:
        return _Angle(argument, {})
    return None


class _Sizing(threading.local):
    """The operations past which a sized conversion stops, in this thread (none unless
    set)."""

    limit: float = math.inf


class _PastLimit(Exception):
    """A subexpression of more operations than the limit of a sized conversion."""


class TreeOperations:
    """The operations of SymEngine expressions counted over their trees as SymEngine's
    ``count_ops`` counts them (n - 1 for a sum or product of n arguments, one for a power or
    a function, none for an atom), each distinct subexpression counted once across calls and
    its count remembered (atoms too): a chain's mass sums m_k + ... + m_n recur in n entries
    of M each, and counting every entry afresh would walk n^3/6 masses.  What a
    :class:`SympyView` converts is counted as it is converted (:meth:`SympyView.operations`);
    this counts what it hands to SymPy whole."""

    def __init__(self) -> None:
        self._known: dict[Backend, int] = {}

    def __call__(self, expr: Backend) -> int:
        known = self._known
        count = known.get(expr)
        if count is not None:
            return count
        args = expr.args
        if not args:
            known[expr] = 0
            return 0
        count = len(args) - 1 if (expr.is_Add or expr.is_Mul) else 1
        get = known.get
        for arg in args:
            inner = get(arg)
            count += self(arg) if inner is None else inner
        known[expr] = count
        return count


def sympy_sum_power(base: sp.Expr, exponent: sp.Expr, imaginary: bool = True) -> sp.Expr:
    """``sp.Pow(base, exponent)``, the same expression, for a sum ``base`` and a rational
    ``exponent`` (a square root, a square, a reciprocal), built without SymPy's evaluation
    when the sum has symbols and no imaginary unit (``imaginary`` False) and the exponent
    is neither 0 nor 1: then ``Add._eval_power`` returns nothing (it changes only a number,
    or a sum with an imaginary term and an infinite one), but first asks whether either of
    two terms is infinite, which walks SymPy's assumptions through the whole sum (a steered
    wheel's tilt: a tenth of the time of making its constraints).  A sum with a Float
    coefficient goes through ``sp.Pow``: SymPy before 1.14 takes the Float out of such a
    sum raised to a power other than +-1 (``(2.0 + 4 x)**2`` as ``16 (0.5 + x)**2``); a
    term's number is read as its first argument (what ``as_coeff_Mul`` returns, without the
    product of the other factors it makes).

    >>> x, y = sp.symbols("x y")
    >>> root = sympy_sum_power(1 - (x * y + x) ** 2, sp.Rational(1, 2), imaginary=False)
    >>> sp.srepr(root) == sp.srepr(sp.sqrt(1 - (x * y + x) ** 2))
    True
    """
    if (
        imaginary
        or type(base) is not sp.Add
        or not exponent.is_Rational
        or exponent is sp.S.Zero
        or exponent is sp.S.One
        or base.is_number is not False
        or any((term.args[0] if term.is_Mul else term).is_Float for term in base.args)
    ):
        return sp.Pow(base, exponent)
    return _unevaluated_power(base, exponent)


def plain_power(base: sp.Expr, exponent: sp.Rational) -> sp.Expr:
    """``sp.Pow(base, exponent)``, the same expression, for a symbol or a function value
    ``base`` (a sine, a length) and a rational ``exponent``, built without SymPy's
    evaluation when the base's class leaves powers to ``Expr._eval_power`` (which returns
    nothing) and the exponent is neither 0 nor 1: then all that ``Pow.__new__`` does with a
    base that is not a number is ask ``_eval_power`` (the rules before it are for numeric
    bases, infinite, zero or unit exponents and non-atomic ones), after looking the call up
    in SymPy's cache (about 20 us a power, where this takes 2).  The value of any other
    function (exp, Abs, sign, ...) goes through ``sp.Pow``.

    >>> x = sp.Symbol("x")
    >>> square = plain_power(sp.sin(x), sp.Integer(2))
    >>> sp.srepr(square) == sp.srepr(sp.sin(x) ** 2), square.is_commutative
    (True, True)
    """
    if (
        type(base)._eval_power is not _DEFAULT_POWER
        or not exponent.is_Rational
        or exponent is sp.S.Zero
        or exponent is sp.S.One
        or base.is_Number
    ):
        return sp.Pow(base, exponent)
    return _unevaluated_power(base, exponent)


def _unevaluated_power(base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
    """The power as ``Pow.__new__`` would leave it, made without its evaluation."""
    power = sp.Expr.__new__(sp.Pow, base, exponent)
    power.is_commutative = base.is_commutative and exponent.is_commutative
    return power


#: What ``Pow.__new__`` asks of a base whose class does not change its powers.
_DEFAULT_POWER = sp.Expr._eval_power


def _immutable(rows: int, columns: int, entries: list[sp.Expr]) -> sp.ImmutableMatrix:
    """The matrix of SymPy ``entries`` (row by row), made without sympifying each again (a
    SymPy expression is itself; a 200-link chain's M has 40,000 entries)."""
    return sp.ImmutableMatrix._new(rows, columns, entries, copy=False)


class _CollectorPause:
    """Python's cycle collector paused while any conversion runs (in any thread), and put
    back as it was when the last one ends.  A conversion makes expressions by the hundred
    thousand, and each of the collector's passes walks them all, a fifth of the time of
    converting a 200-link chain's equations, to find nothing: expressions, their sort keys
    and the memos refer only to their parts, never back.  The young generations are collected
    first: the pause ages whatever is young when it ends (:func:`_age_unwalked`), and the
    caller's garbage cycles, aged so without being counted, could wait in the oldest
    generation for a full collection that a loop of models never sets off.  Any cycle made
    meanwhile elsewhere is collected by a later full collection.  Counted under a lock, so two
    threads that convert at once never leave the collector off."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._running = 0
        self._resume = False

    @contextmanager
    def __call__(self) -> Iterator[None]:
        with self._lock:
            if self._running == 0:
                self._resume = gc.isenabled()
                if self._resume:
                    gc.collect(1)  # small: at most a few thousand young objects to walk
                gc.disable()
            self._running += 1
        try:
            yield
        finally:
            with self._lock:
                self._running -= 1
                if self._running == 0 and self._resume:
                    _age_unwalked()
                    gc.enable()


def _age_unwalked() -> None:
    """Every object the collector tracks moved to its oldest generation without walking them.

    The objects made while the collector was paused are all in its youngest generation, and
    the first allocation after it is on again would walk them all (a quarter of a second
    for a 200-link chain's million objects), and a collection of the middle generation
    walks them again later.  ``gc.freeze`` moves every generation to the permanent one,
    which no collection walks, and ``gc.unfreeze`` moves that to the oldest: collected by
    the next full collection as any object that lived long, so a cycle among them (or a
    garbage one made meanwhile) is still freed then, never leaked.  CPython starts a full
    collection when the objects that reached the oldest generation by younger collections
    since the last are a quarter of those the last one kept; these are not among them, so
    they bring none sooner, and the full collection that walks them counts them in, so the
    next comes later.  Done only when nothing is frozen: unfreezing would thaw what the
    program froze itself (before a fork).  Another thread may run between the two calls: a
    collection it starts then passes over the frozen objects, which is all it does."""
    if gc.get_freeze_count() == 0:
        gc.freeze()
        gc.unfreeze()


#: The pause of every conversion, and of a whole derivation and the multiplier form: a
#: bicycle's derivation otherwise sets off a full collection (of everything SymPy made at
#: import), a tenth of its time, that finds nothing to free.
cycle_collection_paused = _CollectorPause()


#: The backend entries each matrix a SympyView converted came from, row by row: numeric code
#: compiles those directly instead of converting the SymPy matrix back (a tenth of the
#: compile time of a 10-link pendulum's equations).
_SOURCES: IdentityCache[sp.ImmutableMatrix, tuple[Backend, ...]] = IdentityCache()


def _remember(converted: sp.ImmutableMatrix, entries: Sequence[Backend]) -> sp.ImmutableMatrix:
    _SOURCES.get(converted, lambda _: tuple(entries))
    return converted


def backend_entries(matrix: Any) -> tuple[Backend, ...] | None:
    """The SymEngine entries (row by row) that ``matrix`` was converted from by a
    :class:`SympyView`, or None for a matrix built any other way."""
    return _SOURCES.peek(matrix) if isinstance(matrix, sp.ImmutableMatrix) else None


#: The ``nargs`` that SymPy's ``Application.__new__`` gives every value of a sine or a cosine
#: (``FiniteSet(*cls._nargs)``); a FiniteSet is immutable, so one is shared by all the values.
_NARGS: dict[Callable[..., sp.Expr], sp.FiniteSet] = {
    f: sp.FiniteSet(*f._nargs) for f in (sp.sin, sp.cos)
}


def unevaluated_trig(function: Callable[..., sp.Expr], argument: sp.Expr) -> sp.Expr:
    """``function(argument, evaluate=False)`` for ``sp.sin`` or ``sp.cos`` and a SymPy
    ``argument``, built as SymPy builds it: ``Function.__new__`` checks the number of
    arguments and ``Application.__new__`` sympifies them (a SymPy expression is itself),
    makes the value with ``Basic.__new__`` and sets its ``nargs`` to the function's, which
    is all that is done here.  What is left out is SymPy's cache of the two constructors,
    which only makes a later equal call return the same object, and making a new FiniteSet
    for each value (a third of the time of converting a 200-link chain's M).

    >>> x, y = sp.symbols("x y")
    >>> value = unevaluated_trig(sp.cos, x - y)
    >>> value == sp.cos(x - y, evaluate=False), value.nargs, sp.srepr(value)
    (True, {1}, "cos(Add(Symbol('x'), Mul(Integer(-1), Symbol('y'))))")
    """
    value = sp.Basic.__new__(function, argument)
    value.nargs = _NARGS[function]
    return value


_MINUS_ONE = se.Integer(-1)
#: SymEngine's classes of sums, products and powers (every such expression is of exactly
#: one of them).
_ADD, _MUL, _POW = se.Add, se.Mul, se.Pow
#: Two SymEngine expressions compared in C++ (``_EQUAL(a, b, _EQ)``): what ``a == b`` calls
#: after converting both sides with ``_sympify``, which SymEngine expressions need not.
_EQUAL, _EQ = se.Basic._richcmp_, 2
#: SymEngine's own 0 and 1, which it gives as the same objects every time.
_ZERO, _ONE = se.S.Zero, se.S.One


def _sympy_rational(number: Backend) -> sp.Rational:
    """A SymEngine integer or rational as SymPy, the number ``sympify`` makes of it, made
    directly (``sympify`` asks SymEngine's ``_sympy_`` through SymPy's converters, two
    to five times as long)."""
    if number.is_Integer:
        return sp.Integer(int(number))
    return sp.Rational(int(number.p), int(number.q))


def _backend_difference(angle: Backend) -> tuple[Backend, Backend] | None:
    """(x, y) for a backend angle x - y with x, y symbols; else None."""
    terms = angle.args if angle.is_Add else ()
    if len(terms) != 2:
        return None
    positive, negative = None, None
    for term in terms:
        if term.is_Symbol:
            positive = term
        elif term.is_Mul:
            args = term.args
            if len(args) == 2 and args[1].is_Symbol and args[0] == _MINUS_ONE:
                negative = args[1]
    if positive is None or negative is None:
        return None
    return positive, negative


def _ordered(x: sp.Symbol, y: sp.Symbol) -> tuple[sp.Symbol, sp.Symbol, bool]:
    """(first, second, flipped) for the angle x - y: first before second in SymPy's order,
    ``flipped`` when the angle is second - first."""
    if type(x) is sp.Symbol and type(y) is sp.Symbol:  # SymPy orders plain symbols by name
        first, second = (x, y) if x.name <= y.name else (y, x)
    else:
        first, second = sorted((x, y), key=sp.default_sort_key)
    return first, second, x is not first


__all__ = [
    "Backend",
    "SympyView",
    "TreeOperations",
    "backend_entries",
    "cycle_collection_paused",
    "plain_power",
    "sympy_sum_power",
    "unevaluated_trig",
]
