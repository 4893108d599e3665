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
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.canonical import (
    EXPR,
    Builder,
    CanonicalOrder,
    Part,
    Unorderable,
    sympy_product,
    sympy_sum,
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
        self._memo: dict[Backend, Part] = {}
        self._builder = Builder()
        # a backend angle -> (the angle converted, its canonical difference or None, flipped)
        self._angles: dict[Backend, tuple[Part, Part | None, bool]] = {}
        self._negatives: dict[sp.Symbol, Part] = {}  # symbol -> -symbol

    def __call__(self, expr: Backend) -> sp.Expr:
        known = self._memo.get(expr)
        return (self._part(expr) if known is None else known)[EXPR]

    def _part(self, expr: Backend) -> Part:
        """The :data:`~lagrangian.symbolic.canonical.Part` of ``expr`` converted."""
        known = self._memo.get(expr)
        if known is not None:
            return known
        build = self._builder
        if isinstance(expr, se.Symbol):
            result = build.part(self.by_name.get(expr.name) or sp.Symbol(expr.name))
        elif expr.is_Add:
            result = build.sum(self._arguments(expr))
        elif expr.is_Mul:
            result = build.product(self._arguments(expr))
        elif expr.is_Pow:
            base, exponent = expr.args
            if base.is_Add and exponent.is_Number and not exponent.is_Integer:
                result = build.part(sympy_root(self(base), self(exponent), base.has(se.I)))
            else:
                result = build.part(sp.Pow(self(base), self(exponent)))
        elif type(expr) in _TRIG:
            result = self._trig(_TRIG[type(expr)], expr.args[0])
        elif expr.is_Number:
            result = build.part(to_sympy(expr))
        else:
            result = build.part(self._fallback(expr))
        self._memo[expr] = result
        return result

    def _all(self, entries: list[Backend]) -> list[sp.Expr]:
        """Every entry converted."""
        with _cycle_collection_paused():
            return [self(v) for v in entries]

    def _arguments(self, expr: Backend) -> list[Part]:
        """The arguments of ``expr`` converted (most are met before: looked up directly)."""
        get = self._memo.get
        return [known if (known := get(a)) is not None else self._part(a) for a in expr.args]

    def _fallback(self, expr: Backend) -> sp.Expr:
        # SymEngine knows only SymPy's complex Abs and sign, and Heaviside by a stand-in
        result = piecewise_smooth(to_sympy(expr))
        swap = {
            s: self.by_name[s.name]
            for s in result.free_symbols
            if s.name in self.by_name and self.by_name[s.name] is not s
        }
        return result.xreplace(swap) if swap else result

    def _trig(self, function: Callable[..., sp.Expr], angle: Backend) -> Part:
        """``function`` of the backend ``angle``; a difference of two symbols in SymPy's
        canonical order (the first symbol positive), made from the two symbols directly: the
        angle as SymEngine orders it is then never converted (an n-link chain has n^2/2 such
        angles, each in a cosine of M and a sine of the forcing)."""
        build = self._builder
        known = self._angles.get(angle)  # the sine and the cosine of an angle share it
        if known is None:
            pair = _backend_difference(angle)
            x, y = (None, None) if pair is None else (self(pair[0]), self(pair[1]))
            if not (x is not None and x.is_Symbol and y is not None and y.is_Symbol):
                known = (self._part(angle), None, False)
            else:
                first, second, flipped = _ordered(x, y)
                difference = build.sum([build.part(first), self._negative(second)])
                known = (difference, difference, flipped)
            self._angles[angle] = known
        argument, canonical, flipped = known
        if canonical is None:
            return build.part(function(argument[EXPR]))
        value = build.function_value(unevaluated_trig(function, canonical[EXPR]), canonical)
        if flipped and function is sp.sin:
            return build.product([build.part(sp.S.NegativeOne), value])
        return value

    def _negative(self, symbol: sp.Symbol) -> Part:
        """-symbol, made once per symbol."""
        known = self._negatives.get(symbol)
        if known is None:
            known = self._negatives[symbol] = self._builder.part(-symbol)
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


__all__ = [
    "Backend",
    "CanonicalOrder",
    "SympyView",
    "Unorderable",
    "backend_entries",
    "cycle_collection_paused",
    "sympy_product",
    "sympy_root",
    "sympy_sum",
    "unevaluated_trig",
]
