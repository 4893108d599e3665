"""NumericFunction: SymPy expressions as one NumPy function, for one state or a batch of states.

The expressions are compiled once to machine code by SymEngine's LLVM backend
(``symengine.Lambdify(..., backend="llvm", cse=True)``: common subexpressions computed once,
a few milliseconds to compile, a few microseconds a call; Heaviside, which SymEngine does not
know, is compiled written with sign); where SymEngine cannot (a function it does not know, or
a SymEngine built without LLVM) they fall back to
``sympy.lambdify(..., modules="numpy", cse=True)``, which gives the same numbers.

Compilation is tiered, as in a JIT: the first call compiles without LLVM's optimization passes
(a third of the time; each state costs a few times more), and once OPTIMIZE_AFTER_ROWS states
have been evaluated the function is compiled again with them.  A function evaluated once over
a trajectory's output rows (its energy) never pays for the optimizer; one called inside an
integration loop pays for it after a few thousand steps.  The two tiers give the same numbers
(LLVM's optimizer does not reassociate floating-point arithmetic without fast-math).

The arguments come in groups, each a list of symbols (q, q_dot, p) or a single symbol (t).
A group is given as an array of shape (len,) for one state, or (k, len) for a batch of k
states; a scalar group as a float or an array (k,).  The result has shape ``shape`` for one
state and (k, *shape) for a batch.

>>> import sympy as sp
>>> x, v, t = sp.symbols("x v t")
>>> f = NumericFunction(([x, v], t), [x * v, sp.sin(t)], shape=(2,))
>>> f([2.0, 3.0], 0.0)
array([6., 0.])
>>> f([[2.0, 3.0], [1.0, 1.0]], 0.0).shape
(2, 2)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cached_property
from typing import Any, TypeAlias

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.numerics.fast.llvm import llvm_lambdify
from lagrangian.symbolic.nonsmooth import piecewise_smooth

#: Whether to compile with SymEngine's LLVM backend (False: always sympy.lambdify; tests
#: compare the two).
NATIVE = True

#: States evaluated by the quick compilation before the optimized one replaces it: about where
#: the optimizer's compile time (~30 ms on a 10-link pendulum's energy) equals the per-state
#: time it saves (~6 us).
OPTIMIZE_AFTER_ROWS = 5000

#: An argument group: a list of symbols (an array argument) or one symbol (a scalar argument).
Group: TypeAlias = "Sequence[sp.Symbol] | sp.Symbol"


def with_signs(expr: Any) -> Any:
    """Heaviside(u, h0) written with sign, which SymEngine compiles (SymPy's lambdify would
    run its common-subexpression search over the whole expression instead: minutes for
    Heaviside(x**200)): (1 + sign(u))/2, plus (h0 - 1/2)(1 - sign(u)**2) for a value at 0
    other than 1/2.

    >>> x = sp.Symbol("x")
    >>> with_signs(sp.Heaviside(x - 1))
    sign(x - 1)/2 + 1/2
    """
    if not isinstance(expr, sp.Basic) or not expr.has(sp.Heaviside):
        return expr

    def step(u: sp.Expr, h0: sp.Expr = sp.S.Half) -> sp.Expr:
        jump = (1 + sp.sign(u)) / 2
        return jump if h0 == sp.S.Half else jump + (h0 - sp.S.Half) * (1 - sp.sign(u) ** 2)

    return expr.replace(lambda e: isinstance(e, sp.Heaviside), lambda e: step(*e.args))


def _has_symengine_step(expr: Any) -> bool:
    return isinstance(expr, se.Basic) and any(
        f.get_name() == "Heaviside" for f in expr.atoms(se.FunctionSymbol)
    )


class NumericFunction:
    """``expressions`` as a NumPy function of the argument ``groups``, reshaped to ``shape``.

    The expressions are SymPy's, or SymEngine's with ``sympy_form`` giving the same in SymPy
    (a derivation's own terms: compiled without a conversion, converted only for the fallback).

    ``raw`` is the lambdified function itself (it returns a list of numbers), for callers that
    have already unpacked one state and want no overhead beyond that one call.  It is built on
    first use, so functions nobody calls cost nothing.
    """

    def __init__(
        self,
        groups: Sequence[Group],
        expressions: Sequence[Any],
        shape: tuple[int, ...],
        *,
        sympy_form: Callable[[], Sequence[sp.Expr]] | None = None,
    ) -> None:
        self._args: list[Any] = [list(g) if isinstance(g, Sequence) else g for g in groups]
        # a derivative of |u| SymPy left unevaluated cannot be printed (nor sent to SymEngine)
        self._expressions = [piecewise_smooth(e) for e in expressions]
        # expressions given in SymEngine come with their SymPy form, made only when SymEngine
        # cannot compile them
        self._sympy_form = sympy_form
        self.shape = shape
        # the number of dimensions of each argument when it carries a batch
        self._batch_ndim = tuple(2 if isinstance(g, list) else 1 for g in self._args)
        self._rows = 0  # states evaluated natively, for the tiered compilation
        self._optimized = False
        self._fast: Callable[[np.ndarray], np.ndarray] | None = None

    @cached_property
    def raw(self) -> Callable[..., Any]:
        if self._native is None:
            return self._lambdified

        def call(*arguments: Any) -> np.ndarray:
            return self._run(np.concatenate([np.ravel(a) for a in arguments], dtype=float))

        return call

    @cached_property
    def _lambdified(self) -> Callable[..., list[Any]]:
        expressions = self._expressions
        if self._sympy_form is not None:
            expressions = [piecewise_smooth(e) for e in self._sympy_form()]
        return sp.lambdify(self._args, expressions, modules="numpy", cse=True)

    @cached_property
    def _native(self) -> Callable[[np.ndarray], np.ndarray] | None:
        """The LLVM-compiled function of one flat argument vector (rows of a 2-d array are
        states), quickly compiled, or None where SymEngine cannot compile these expressions."""
        return self._compile(optimize=False)

    def _run(self, flat: np.ndarray) -> Any:
        """The native function on a flat vector or rows of states; the optimized compilation
        replaces the quick one after OPTIMIZE_AFTER_ROWS states."""
        self._rows += 1 if flat.ndim == 1 else len(flat)
        if self._rows > OPTIMIZE_AFTER_ROWS and not self._optimized:
            self._optimized = True
            self._fast = self._compile(optimize=True)
        return (self._fast or self._native)(flat)  # type: ignore[misc]

    def _compile(self, *, optimize: bool) -> Callable[[np.ndarray], np.ndarray] | None:
        if not self._expressions or not NATIVE:
            return None
        symbols = [s for a in self._args for s in (a if isinstance(a, list) else [a])]
        return llvm_lambdify(symbols, self._compilable(), opt_level=3 if optimize else 0)

    def _compilable(self) -> list[Any]:
        """The expressions with Heaviside written with sign (SymEngine's own expressions
        replaced by their SymPy form where they hold one: SymEngine keeps it as a SymPy
        function, which it cannot compile)."""
        expressions = self._expressions
        if self._sympy_form is not None and any(map(_has_symengine_step, expressions)):
            expressions = [piecewise_smooth(e) for e in self._sympy_form()]
        return [with_signs(e) for e in expressions]

    def __call__(self, *arguments: Any) -> np.ndarray:
        if self._native is not None:
            return self._call_native(arguments)
        size: int | None = None
        prepared = []
        for argument, batch_ndim in zip(arguments, self._batch_ndim):
            array = np.asarray(argument, dtype=float)
            if array.ndim == batch_ndim:
                size = array.shape[0]
                array = array.T  # one row per symbol, so lambdify unpacks columns of the batch
            prepared.append(array)
        values = self._lambdified(*prepared)
        if size is None:
            return np.array(values, dtype=float).reshape(self.shape)
        columns = [np.broadcast_to(np.asarray(v, dtype=float), (size,)) for v in values]
        return np.stack(columns, axis=-1).reshape((size, *self.shape))

    def _call_native(self, arguments: tuple[Any, ...]) -> np.ndarray:
        """One flat vector (or one row per state of a batch) into the native function."""
        columns, size = [], None
        for argument, batch_ndim in zip(arguments, self._batch_ndim):
            array = np.asarray(argument, dtype=float)
            if array.ndim == batch_ndim:
                size = array.shape[0]
            columns.append(array)
        if size is None:
            flat = np.concatenate([np.ravel(c) for c in columns])
            return np.asarray(self._run(flat), dtype=float).reshape(self.shape)
        if size == 0:  # no state left to evaluate (every member of a batch has ended)
            return np.zeros((0, *self.shape))
        rows = [
            c.reshape(size, -1) if c.ndim == b else np.broadcast_to(c.ravel(), (size, c.size))
            for c, b in zip(columns, self._batch_ndim)
        ]
        values = self._run(np.concatenate(rows, axis=1))
        return np.asarray(values, dtype=float).reshape((size, *self.shape))
