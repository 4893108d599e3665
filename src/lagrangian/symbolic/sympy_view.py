"""SymEngine results back as SymPy, with the user's own symbol objects: the one conversion
that the derivation, the constraints and the model's rolling contacts share.

The SymPy expressions are built as SymPy's constructors build them (the same arguments in the
same order, so ``srepr`` is equal), with SymPy's general evaluation skipped where the
arguments are canonical already (:func:`sympy_sum`, :func:`sympy_product`), which is most of
the time of converting large equations.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from functools import cmp_to_key
from typing import Any

import symengine as se
import sympy as sp
from sympy.core.basic import ordering_of_classes

from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import piecewise_smooth

Backend = Any  # a symengine expression

_TRIG: dict[type, Callable[..., sp.Expr]] = {se.sin: sp.sin, se.cos: sp.cos}


class SympyView:
    """Converts SymEngine results back to SymPy, with the user's symbol objects.

    Sines and cosines of a difference of two symbols, which pendulum-like systems have by
    the hundred, are built directly in SymPy's canonical form (the first symbol in SymPy's
    order positive) instead of through SymPy's general evaluation; sums and products of
    terms that are canonical already skip most of it (:func:`sympy_sum`,
    :func:`sympy_product`); everything else goes through SymPy's own constructors.
    """

    def __init__(
        self, symbols: Iterable[sp.Symbol], names: dict[str, sp.Expr] | None = None
    ) -> None:
        """``symbols`` are the SymPy objects of the backend symbols of the same names;
        ``names`` maps further names to any SymPy expression the symbol stands for."""
        self.by_name: dict[str, sp.Expr] = {s.name: s for s in symbols}
        self.by_name.update(names or {})
        self._memo: dict[Backend, sp.Expr] = {}
        self._order = CanonicalOrder()
        # a backend angle -> (the angle converted, its canonical difference or None, flipped)
        self._angles: dict[Backend, tuple[sp.Expr, sp.Expr | None, bool]] = {}
        self._negatives: dict[sp.Symbol, sp.Expr] = {}  # symbol -> -symbol

    def __call__(self, expr: Backend) -> sp.Expr:
        known = self._memo.get(expr)
        if known is not None:
            return known
        if isinstance(expr, se.Symbol):
            result = self.by_name.get(expr.name) or sp.Symbol(expr.name)
        elif expr.is_Add:
            result = sympy_sum(self._arguments(expr), self._order)
        elif expr.is_Mul:
            result = sympy_product(self._arguments(expr), self._order)
        elif expr.is_Pow:
            base, exponent = expr.args
            if base.is_Add and exponent.is_Number and not exponent.is_Integer:
                result = sympy_root(self(base), self(exponent), base.has(se.I))
            else:
                result = sp.Pow(self(base), self(exponent))
        elif type(expr) in _TRIG:
            result = self._trig(_TRIG[type(expr)], expr.args[0])
        elif expr.is_Number:
            result = to_sympy(expr)
        else:
            result = self._fallback(expr)
        self._memo[expr] = result
        return result

    def _all(self, entries: list[Backend]) -> list[sp.Expr]:
        """Every entry converted; then the sort keys remembered meanwhile are let go (a
        200-link chain's equations have hundreds of thousands; the few that other entries
        share are quickly made again)."""
        try:
            with _cycle_collection_paused():
                return [self(v) for v in entries]
        finally:
            self._order = CanonicalOrder()

    def _arguments(self, expr: Backend) -> list[sp.Expr]:
        """The arguments of ``expr`` converted (most are met before: looked up directly)."""
        get = self._memo.get
        return [known if (known := get(a)) is not None else self(a) for a in expr.args]

    def _fallback(self, expr: Backend) -> sp.Expr:
        # SymEngine knows only SymPy's complex Abs and sign, and Heaviside by a stand-in
        result = piecewise_smooth(to_sympy(expr))
        swap = {
            s: self.by_name[s.name]
            for s in result.free_symbols
            if s.name in self.by_name and self.by_name[s.name] is not s
        }
        return result.xreplace(swap) if swap else result

    def _trig(self, function: Callable[..., sp.Expr], angle: Backend) -> sp.Expr:
        """``function`` of the backend ``angle``; a difference of two symbols in SymPy's
        canonical order (the first symbol positive), made from the two symbols directly: the
        angle as SymEngine orders it is then never converted (an n-link chain has n^2/2 such
        angles, each in a cosine of M and a sine of the forcing)."""
        known = self._angles.get(angle)  # the sine and the cosine of an angle share it
        if known is None:
            pair = _backend_difference(angle)
            x, y = (None, None) if pair is None else (self(pair[0]), self(pair[1]))
            if not (x is not None and x.is_Symbol and y is not None and y.is_Symbol):
                known = (self(angle), None, False)
            else:
                first, second, flipped = _ordered(x, y)
                canonical = sympy_sum([first, self._negative(second)], self._order)
                known = (canonical, canonical, flipped)
            self._angles[angle] = known
        argument, canonical, flipped = known
        if canonical is None:
            return function(argument)
        value = unevaluated_trig(function, canonical)
        return sympy_product([sp.S.NegativeOne, value]) if flipped and function is sp.sin else value

    def _negative(self, symbol: sp.Symbol) -> sp.Expr:
        """-symbol, made once per symbol."""
        known = self._negatives.get(symbol)
        if known is None:
            known = self._negatives[symbol] = -symbol
        return known

    def vector(self, values: Iterable[Backend]) -> sp.ImmutableMatrix:
        entries = list(values)
        return _remember(_immutable(len(entries), 1, self._all(entries)), entries)

    def matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        entries = [v for row in rows for v in row]
        columns = len(rows[0]) if rows else 0
        return _remember(_immutable(len(rows), columns, self._all(entries)), entries)

    def symmetric_matrix(self, rows: Sequence[Sequence[Backend]]) -> sp.ImmutableMatrix:
        """Convert the upper triangle only and mirror it."""
        n = len(rows)
        pairs = [(j, k) for j in range(n) for k in range(j, n)]
        upper = dict(zip(pairs, self._all([rows[j][k] for j, k in pairs])))
        mirrored = [(min(j, k), max(j, k)) for j in range(n) for k in range(n)]
        converted = _immutable(n, n, [upper[pair] for pair in mirrored])
        return _remember(converted, [rows[j][k] for j, k in mirrored])


def sympy_root(base: sp.Expr, exponent: sp.Expr, imaginary: bool = True) -> sp.Expr:
    """``sp.Pow(base, exponent)``, the same expression, for a sum ``base`` and a rational
    ``exponent`` that is not an integer (a square root), built without SymPy's evaluation
    when the sum has symbols and no imaginary unit (``imaginary`` False): then
    ``Add._eval_power`` returns nothing (it changes only a number, or a sum with an
    imaginary term and an infinite one), but first asks whether either of two terms is
    infinite, which walks SymPy's assumptions through the whole sum (a steered wheel's
    tilt: a tenth of the time of making its constraints).

    >>> x, y = sp.symbols("x y")
    >>> root = sympy_root(1 - (x * y + x) ** 2, sp.Rational(1, 2), imaginary=False)
    >>> sp.srepr(root) == sp.srepr(sp.sqrt(1 - (x * y + x) ** 2))
    True
    """
    if (
        imaginary
        or type(base) is not sp.Add
        or not exponent.is_Rational
        or exponent.is_Integer
        or base.is_number is not False
    ):
        return sp.Pow(base, exponent)
    root = sp.Expr.__new__(sp.Pow, base, exponent)
    root.is_commutative = base.is_commutative and exponent.is_commutative
    return root


def _immutable(rows: int, columns: int, entries: list[sp.Expr]) -> sp.ImmutableMatrix:
    """The matrix of SymPy ``entries`` (row by row), made without sympifying each again (a
    SymPy expression is itself; a 200-link chain's M has 40,000 entries)."""
    return sp.ImmutableMatrix._new(rows, columns, entries, copy=False)


class _CollectorPause:
    """Python's cycle collector paused while any conversion runs (in any thread), and put
    back as it was when the last one ends.  A conversion makes expressions by the hundred
    thousand, and each of the collector's passes walks them all, a fifth of the time of
    converting a 200-link chain's equations, to find nothing: expressions, their sort keys
    and the memos refer only to their parts, never back.  Any cycle made meanwhile elsewhere
    is collected once the collector runs again.  Counted under a lock, so two threads that
    convert at once never leave the collector off."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._running = 0
        self._resume = False

    @contextmanager
    def __call__(self) -> Iterator[None]:
        with self._lock:
            if self._running == 0:
                self._resume = gc.isenabled()
                gc.disable()
            self._running += 1
        try:
            yield
        finally:
            with self._lock:
                self._running -= 1
                if self._running == 0 and self._resume:
                    gc.enable()


_cycle_collection_paused = _CollectorPause()
#: The same pause for a whole derivation and the multiplier form: a bicycle's derivation
#: otherwise sets off a full collection (of everything SymPy made at import), a tenth of its
#: time, that finds nothing to free.
cycle_collection_paused = _cycle_collection_paused


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


def _backend_difference(angle: Backend) -> tuple[Backend, Backend] | None:
    """(x, y) for a backend angle x - y with x, y symbols; else None."""
    if not (angle.is_Add and len(angle.args) == 2):
        return None
    positive, negative = None, None
    for term in angle.args:
        if term.is_Symbol:
            positive = term
        elif term.is_Mul:
            args = term.args
            if len(args) == 2 and args[0] == -1 and args[1].is_Symbol:
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


#: SymPy's canonical order of the arguments of a sum or a product (what ``Add`` and ``Mul``
#: sort them by).
_CANONICAL_ORDER = cmp_to_key(sp.Basic.compare)


def sympy_sum(terms: list[sp.Expr], order: CanonicalOrder | None = None) -> sp.Expr:
    """``sp.Add(*terms)``, the same expression (equal arguments in the same order), built
    without SymPy's general evaluation when the terms are canonical SymPy terms with nothing
    to combine: rational numbers, and symbols, powers, products and function values whose
    parts without their numeric coefficients all differ.  Then ``Add.flatten`` would only
    sum the numbers, sort the rest (by :meth:`sympy.Basic.compare`) and put the number first,
    which is all this does; anything else goes through ``sp.Add``.

    >>> x, y = sp.symbols("x y")
    >>> sympy_sum([sp.Integer(2), 3 * y, x**2]) == sp.Add(2, 3 * y, x**2)
    True
    """
    return _sum(terms, terms, order)


def _sum(flat: list[sp.Expr], terms: list[sp.Expr], order: CanonicalOrder | None) -> sp.Expr:
    """:func:`sympy_sum` of ``terms``, whose sums are flattened in ``flat`` (``terms`` until
    one is met)."""
    coefficient: sp.Expr = sp.S.Zero
    parts: list[sp.Expr] = []
    seen: set[Any] = set()
    for term in flat:
        if term.is_Rational:
            # 0 + a rational number is that number (SymPy makes the same canonical one)
            coefficient = term if coefficient is sp.S.Zero else coefficient + term
            continue
        kind = type(term)
        if kind is sp.Add:
            if flat is not terms:  # a sum among a sum's arguments: SymPy never makes one
                return sp.Add(*terms)
            return _sum(_flat(terms, sp.Add), terms, order)
        if kind is sp.Mul:
            args = term.args
            key: Any = (args[1:] if len(args) > 2 else args[1]) if args[0].is_Number else args
        elif _is_plain(term) or (kind is sp.Pow and not term.args[0].is_Number):
            key = term
        else:
            return sp.Add(*terms)
        if key in seen or term.is_commutative is not True:
            return sp.Add(*terms)
        seen.add(key)
        parts.append(term)
    _sort(parts, order)
    if coefficient is not sp.S.Zero:
        parts.insert(0, coefficient)
    return sp.Add._from_args(parts, True)  # what sp.Add does with the flattened terms


def sympy_product(factors: list[sp.Expr], order: CanonicalOrder | None = None) -> sp.Expr:
    """``sp.Mul(*factors)``, the same expression, built without SymPy's general evaluation
    when the factors are canonical SymPy factors with nothing to combine: rational numbers,
    and symbols, sums, function values and powers of them with rational exponents, of bases
    that all differ.  Then ``Mul.flatten`` would only multiply the numbers, sort the rest
    (by :meth:`sympy.Basic.compare`) and put the number first, which is all this does; a
    number times one sum (which SymPy distributes) and anything else go through ``sp.Mul``.

    >>> x, y = sp.symbols("x y")
    >>> sympy_product([sp.Integer(-2), sp.sin(y), x**2]) == sp.Mul(-2, sp.sin(y), x**2)
    True
    """
    if (
        len(factors) == 2
        and any(f.is_Rational for f in factors)
        and any(type(f) in (sp.Add, sp.Mul) for f in factors)
    ):
        return sp.Mul(*factors)  # SymPy's two-argument rules (a number times a sum)
    # a product among the factors (a flipped sine) flattened at once, not met midway
    return _product(_flat(factors, sp.Mul), factors, order)


def _product(flat: list[sp.Expr], factors: list[sp.Expr], order: CanonicalOrder | None) -> sp.Expr:
    """:func:`sympy_product` of ``factors``, whose products are flattened in ``flat``
    (``factors`` until one is met)."""
    coefficient: sp.Expr = sp.S.One
    parts: list[sp.Expr] = []
    bases: set[sp.Expr] = set()
    for factor in flat:
        if factor.is_Rational:
            # 1 * a rational number is that number (SymPy makes the same canonical one)
            coefficient = factor if coefficient is sp.S.One else coefficient * factor
            continue
        kind = type(factor)
        if kind is sp.Mul:
            if flat is not factors:  # a product among a product's arguments: SymPy never makes one
                return sp.Mul(*factors)
            return _product(_flat(factors, sp.Mul), factors, order)
        if kind is sp.Pow:
            base, exponent = factor.args
            if base.is_Number or not exponent.is_Rational:
                return sp.Mul(*factors)
        elif kind is sp.Add or _is_plain(factor):
            base = factor
        else:
            return sp.Mul(*factors)
        if base in bases or factor.is_commutative is not True:
            return sp.Mul(*factors)
        bases.add(base)
        parts.append(factor)
    if coefficient is sp.S.Zero or (
        coefficient is not sp.S.One and len(parts) == 1 and parts[0].is_Add
    ):
        return sp.Mul(*factors)
    keys = _sort(parts, order)
    if coefficient is not sp.S.One:
        parts.insert(0, coefficient)
    product = sp.Mul._from_args(parts, True)  # what sp.Mul does with the flattened factors
    if keys is not None and order is not None:
        # its key from its factors' (a sum of such products sorts them by it next)
        if coefficient is not sp.S.One:
            keys.insert(0, order(coefficient))
        order.remember(product, keys)
    return product


def _sort(parts: list[sp.Expr], order: CanonicalOrder | None) -> list[tuple[Any, ...]] | None:
    """Sort ``parts`` in SymPy's canonical order, by the keys of ``order`` where it has them
    (keys of unlike content, which no canonical expression has, cannot be compared); the
    keys in the sorted order when they were used."""
    if order is not None and len(parts) > 1:
        try:
            keys = [order(part) for part in parts]
            ranks = sorted(range(len(parts)), key=keys.__getitem__)
        except (Unorderable, TypeError):
            pass
        else:
            parts[:] = [parts[i] for i in ranks]
            return [keys[i] for i in ranks]
    parts.sort(key=_CANONICAL_ORDER)
    return None


class Unorderable(Exception):
    """An expression :class:`CanonicalOrder` has no key for."""


#: Where a class's name stands in SymPy's order of classes; the rest come after, by name.
_CLASS_RANK = {name: i for i, name in enumerate(ordering_of_classes)}
_UNRANKED = len(ordering_of_classes) + 1
_MUL_RANK = _CLASS_RANK.get("Mul", _UNRANKED)
#: How SymPy's classes give the content that ``Basic.compare`` compares after the class.
_ARGS_CONTENT = (sp.Basic._hashable_content, sp.Expr._hashable_content)
_NAMED = (sp.Symbol, sp.Dummy)


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

    def remember(self, product: sp.Mul, keys: list[tuple[Any, ...]]) -> None:
        """Remember the key of ``product`` from the keys of its arguments (in their order),
        the key :meth:`__call__` would make of them."""
        self._keys[id(product)] = (product, (_MUL_RANK, "Mul", len(keys), *keys))


def _flat(items: list[sp.Expr], kind: type) -> list[sp.Expr]:
    """``items`` with the arguments of each ``kind`` (Add or Mul) in place of it."""
    if not any(type(item) is kind for item in items):
        return items
    flat: list[sp.Expr] = []
    for item in items:
        args: tuple[sp.Expr, ...] = item.args
        flat.extend(args if type(item) is kind else (item,))
    return flat


def _is_plain(expr: sp.Expr) -> bool:
    """A symbol, or the value of a function that SymPy's products take as a base to the
    power 1 (every function but exp): neither has SymPy constructor postprocessors (only
    matrix, vector, tensor and quantum expressions do)."""
    kind = type(expr)
    return kind in _NAMED or (
        isinstance(expr, sp.Function) and kind.as_base_exp is sp.Expr.as_base_exp
    )
