"""Symbolic questions answered by numbers: is an expression identically zero, what is the rank
of a matrix of expressions at a generic point, what is an expression worth at a point.

Every layer asks these (the derivation for the rank of M, the constraints for the rank of their
Jacobian, the analysis for zero tests), so they live here, at the bottom, once.  They are
decisions, not simulations: a few evaluations at random points in high precision, never a
general ``simplify`` of a large expression.

Tolerances, all documented here and nowhere else:

- values are drawn uniformly in (0.3, 1.3): away from 0, where factors 1/q blow up, and of
  order one, so that a sum of order-one terms that cancels is told from one that does not;
- expressions are evaluated at ``DIGITS`` = 30 significant digits, so an identically zero
  expression comes out below 1e-25 and ``ZERO`` = 1e-15 separates it from a genuine value with
  a margin of ten orders of magnitude either way;
- a matrix is evaluated at the same precision and its rank counts the singular values above
  ``RANK_TOLERANCE`` = 1e-9 of the largest (the constraint Jacobians of closed chains have
  singular values of order one, their redundant rows give 1e-15 in double precision).

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> is_zero(sp.sin(x)**2 + sp.cos(x)**2 - 1), is_zero(x - 1)
(True, False)
>>> generic_rank(sp.Matrix([[x, y], [2 * x, 2 * y]]))
1
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.symbolic.native import to_symengine
from lagrangian.symbolic.nonsmooth import piecewise_smooth
from lagrangian.symbolic.objects import sympy_object

SEED = 20240605
PROBES = 3
DIGITS = 30
ZERO = 1e-15
#: ``DIGITS`` in bits, for SymEngine's evaluation
BITS = math.ceil(DIGITS * math.log2(10))
RANK_TOLERANCE = 1e-9
#: count_ops up to which sympy.simplify is cheap enough to confirm a zero found by probes
SMALL = 60
MODULES = ["math", "mpmath", "sympy"]


def random_values(symbols: Iterable[sp.Symbol], rng: random.Random) -> dict[sp.Symbol, float]:
    """Values in (0.3, 1.3) for ``symbols``, drawn in a fixed (sorted) order."""
    return {s: rng.uniform(0.3, 1.3) for s in sorted(symbols, key=_printed)}


def _printed(symbol: sp.Basic) -> str:
    """``str(symbol)``: a plain Symbol's name without SymPy's printer (a Dummy prints with
    a leading underscore, so anything else is printed)."""
    return symbol.name if type(symbol) is sp.Symbol else str(symbol)


def evaluate(expr: Any, values: Mapping[sp.Symbol, float]) -> float | None:
    """The real value of ``expr`` at ``values`` to ``DIGITS`` digits; None if it is not finite
    or not real there."""
    try:
        exact = {s: sp.Float(v, DIGITS) for s, v in values.items()}
        number = complex(sympy_object(expr).xreplace(exact).evalf(DIGITS))
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    if not np.isfinite(number) or abs(number.imag) > 1e-12 * max(1.0, abs(number.real)):
        return None
    return number.real


def is_small(expr: sp.Basic, limit: int = SMALL) -> bool:
    """At most ``limit`` operations, found without walking all of a large expression."""
    for nodes, _ in enumerate(sp.preorder_traversal(expr)):
        if nodes > 4 * limit:
            return False
    return bool(sp.count_ops(expr) <= limit)


def is_zero(expr: Any) -> bool:
    """True when ``expr`` vanishes identically.

    A value above ``ZERO`` at a random point proves it does not; zeros at ``PROBES`` points
    are confirmed by ``sympy.simplify`` when the expression is small, and accepted otherwise
    (a non-zero analytic expression vanishes on a set of measure zero).  A SymEngine
    expression is evaluated at the first point by SymEngine, to the same ``DIGITS``: a value
    there settles "not zero" without converting it to SymPy (a rolling wheel's contact
    height, hundreds of operations, is asked whether it holds identically).
    """
    if isinstance(expr, se.Basic) and _nonzero_at_first_point(expr):
        return False
    expr = sympy_object(expr)
    if expr == 0 or (expr.is_Number and expr.is_zero):  # 0.0 == 0 is False in SymPy
        return True
    if not expr.free_symbols:
        return bool(sp.simplify(expr) == 0)
    rng = random.Random(SEED)
    for _ in range(PROBES):
        value = evaluate(expr, random_values(expr.free_symbols, rng))
        if value is not None and abs(value) > ZERO:
            return False
    if is_small(expr):
        return bool(sp.simplify(expr) == 0)
    return True


def _nonzero_at_first_point(expr: se.Basic) -> bool:
    """True when the SymEngine ``expr`` at the first point :func:`is_zero` probes, evaluated
    by SymEngine to ``DIGITS`` digits, is real and above ``ZERO``; False when it is not or
    cannot be evaluated there (a function SymEngine does not know)."""
    values = random_values(expr.free_symbols, random.Random(SEED))
    point = {s: se.RealMPFR(repr(v), BITS) for s, v in values.items()}
    try:
        number = complex(expr.xreplace(point))
    except (TypeError, ValueError, RuntimeError):
        return False
    real = np.isfinite(number) and abs(number.imag) <= 1e-12 * max(1.0, abs(number.real))
    return bool(real and abs(number.real) > ZERO)


def all_zero(exprs: Iterable[Any]) -> bool:
    """True when every expression vanishes identically (:func:`is_zero`)."""
    return all(is_zero(e) for e in exprs)


def depends_on(expr: Any, symbols: Iterable[Any]) -> bool:
    """True when any of ``symbols`` is free in ``expr`` (SymPy or SymEngine)."""
    free = expr.free_symbols if hasattr(expr, "free_symbols") else sympy_object(expr).free_symbols
    return any(s in free for s in symbols)


def numeric_rank(matrix: np.ndarray) -> int:
    """Number of singular values above ``RANK_TOLERANCE`` times the largest (at least 1)."""
    if matrix.size == 0:
        return 0
    singular = np.linalg.svd(np.asarray(matrix, dtype=float), compute_uv=False)
    return int(np.sum(singular > RANK_TOLERANCE * max(1.0, singular[0])))


def generic_rank(matrix: Any, values: Mapping[sp.Symbol, float] | None = None) -> int:
    """Rank of a matrix of expressions (SymPy or SymEngine) at a generic point: its symbols
    drawn at random (``values`` fixes some of them).

    The entries are evaluated in double precision by SymEngine (a chain's 100 x 100 mass
    matrix in milliseconds; SymPy's evaluation of its 10,000 entries at ``DIGITS`` digits
    took seconds), and to ``DIGITS`` digits by SymPy where that is not finite and real.  The
    verdict is the same either way: the singular values are computed in double precision,
    and an entry's rounding error (1e-16 of its terms) lies seven orders of magnitude below
    ``RANK_TOLERANCE``.
    """
    matrix = sp.Matrix(matrix) if not isinstance(matrix, sp.MatrixBase) else matrix
    if 0 in matrix.shape:
        return 0
    symbols = set(matrix.free_symbols) - set(values or {})
    point = {**random_values(symbols, random.Random(SEED)), **(values or {})}
    numbers = _double_values(matrix, point)
    if numbers is None:
        exact = {s: sp.Float(v, DIGITS) for s, v in point.items()}
        numbers = np.array(matrix.xreplace(exact).evalf(DIGITS).tolist(), dtype=complex).real
    return numeric_rank(numbers)


def _double_values(matrix: sp.MatrixBase, point: Mapping[sp.Symbol, Any]) -> np.ndarray | None:
    """``matrix`` at ``point`` in double precision, substituted in SymEngine (no code
    compiled: each entry is evaluated once), from the SymEngine entries it was converted
    from where a derivation remembers them (a 100-link chain's M: no conversion back); None
    when a value given is not a real number, or a value is not finite and real there, or
    not a number (a function SymEngine does not evaluate)."""
    # sympy_view imports the conversion, which imports this module: imported when used
    from lagrangian.symbolic.sympy_view import backend_entries

    try:
        numbers = {se.sympify(s): se.RealDouble(float(v)) for s, v in point.items()}
    except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
        return None
    kept = backend_entries(matrix)
    values = None if kept is None else _evaluated(kept, numbers)
    if values is None:  # a symbol of the kept entries that stands for an expression
        try:
            values = _evaluated([se.sympify(e) for e in _entries(matrix)], numbers)
        except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
            return None
    return None if values is None else values.reshape(matrix.shape)


def _evaluated(entries: Sequence[Any], numbers: Mapping[Any, Any]) -> np.ndarray | None:
    """SymEngine ``entries`` with ``numbers`` put in, as real doubles; None where one is not
    a finite real number."""
    try:
        values = np.array([complex(e) for e in substituted(entries, numbers)], dtype=complex)
    except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
        return None
    return real_values(values)


#: The undefined function whose application holds expressions substituted together
#: (SymEngine's substitution leaves an undefined function's arguments in place and in order).
_TOGETHER = se.Function("together")


def together(entries: Sequence[Any]) -> Any:
    """SymEngine ``entries`` as the arguments of one application of an undefined function:
    one expression to substitute into or walk (its free symbols) in one call, the parts the
    entries share met once."""
    return _TOGETHER(*entries)


def substituted(entries: Sequence[Any], mapping: Mapping[Any, Any]) -> tuple[Any, ...]:
    """SymEngine ``entries`` with ``mapping`` put in, all in one substitution, as the
    arguments of one function application: each substitution copies its whole mapping first
    (SymEngine keeps it as the start of its memo), so a matrix's entry-by-entry substitution
    paid the mapping once per entry (a 200-link Cartesian chain's 998 Jacobian entries over
    its 802 symbols: 48 ms against 2.3); in one call the entries also share the memo (a
    rolling wheel's coefficients share its axle's tilt)."""
    return together(entries).xreplace(dict(mapping)).args if entries else ()


class Substitution:
    """SymEngine expressions as a numerical function of a point given by ``symbols``, by
    one :func:`substitution <substituted>` per point (nothing compiled: for the few points a
    probe or a projection needs, compiling costs more than it saves: a bicycle's contact
    height and its three slopes take 1.2 ms to compile, and its generic point 8
    evaluations); the complex values, ValueError where SymEngine cannot evaluate one."""

    def __init__(self, exprs: Sequence[Any], symbols: Sequence[sp.Symbol]) -> None:
        self.symbols = tuple(symbols)
        self.images = [se.sympify(s) for s in self.symbols]
        self.together = together(exprs)

    def __call__(self, values: Mapping[sp.Symbol, float]) -> np.ndarray:
        point = {i: se.RealDouble(values[s]) for s, i in zip(self.symbols, self.images)}
        try:
            found = self.together.xreplace(point).args
            return np.array([complex(e) for e in found], dtype=complex)
        except (RuntimeError, TypeError) as error:
            raise ValueError(f"SymEngine cannot evaluate an expression: {error}") from error


def values_at(exprs: Sequence[Any], point: Mapping[sp.Symbol, float]) -> np.ndarray | None:
    """The values of SymEngine expressions at ``point`` (:class:`Substitution`); None where
    one is not finite or not real, ValueError where SymEngine cannot evaluate one.  An entry
    in SymEngine already is taken as it is (converting it again walks its tree: a rolling
    wheel's coefficients have thousands of operations)."""
    if not exprs:
        return np.zeros(0)
    entries = [e if isinstance(e, se.Basic) else to_symengine(e) for e in exprs]
    return real_values(Substitution(entries, list(point))(point))


def real_values(numbers: np.ndarray) -> np.ndarray | None:
    """``numbers`` as reals; None where one is not finite or not real."""
    if not np.all(np.isfinite(numbers)) or np.any(np.abs(numbers.imag) > 1e-12):
        return None
    return numbers.real


def _entries(matrix: Any) -> list[Any]:
    """The entries of a SymPy or SymEngine matrix, row by row."""
    rows, cols = matrix.shape
    return [matrix[i, j] for i in range(rows) for j in range(cols)]


class PointFunction:
    """Expressions as a numerical function of a point given by name (a mapping from symbols
    to floats), vector or matrix valued; None where any value is not finite or not real.

    For probing and for the small Newton iterations of the lower layers; the compiled,
    vectorised functions of a simulation are :class:`lagrangian.numerics.NumericFunction`.
    """

    def __init__(self, exprs: Any, symbols: Sequence[sp.Symbol]) -> None:
        """``exprs``: a SymPy or SymEngine matrix."""
        self.shape = tuple(exprs.shape)
        self.symbols = tuple(symbols)
        self._function: Callable[..., Any] = list
        if 0 in self.shape:
            return
        try:  # SymEngine compiles in milliseconds what SymPy's printer takes seconds over
            # SymEngine's CSE names its temporaries x0, x1, ...: a user's x1 would be taken
            # for one, so every argument gets a name no model can have
            renamed = {se.sympify(s): se.Symbol(f"_arg{i}_") for i, s in enumerate(self.symbols)}
            # renamed in one substitution: a chain of n bodies has n (2n + 1) entries over
            # 4n + 1 symbols
            entries = [se.sympify(e) for e in _entries(exprs)]
            column = list(substituted(entries, renamed))
            compiled = se.Lambdify(list(renamed.values()), column, real=False, cse=True)
            self._function = lambda *values: compiled(values)
        except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
            # a derivative of |u| SymPy left unevaluated: SymPy prints it piecewise smooth
            smooth = sp.Matrix(
                self.shape[0], self.shape[1], [sympy_object(e) for e in _entries(exprs)]
            )
            self._function = sp.lambdify(
                self.symbols, smooth.applyfunc(piecewise_smooth), modules=MODULES
            )

    def __call__(self, values: Mapping[sp.Symbol, float]) -> np.ndarray | None:
        if 0 in self.shape:
            return np.zeros(self.shape)
        try:
            result = np.array(self._function(*[values[s] for s in self.symbols]), dtype=complex)
        except (TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None
        real = real_values(result)
        return None if real is None else real.reshape(self.shape)
