"""Numerical probes for the symbolic questions of this layer: is an expression identically
zero, what is the rank of the constraint Jacobian "generically", is there a configuration at
all that satisfies the holonomic constraints.

These are decisions, not simulations, so they are made here with a few evaluations at random
points (parameters and time drawn at random too) instead of through :mod:`lagrangian.numerics`,
which sits above this layer.  A generic point is a random configuration *projected onto* the
holonomic constraints by Gauss–Newton least squares,

    q <- q - A(q)^+ h(q),          A = dh/dq, ^+ the pseudo-inverse,

so ranks are those on the constraint set, and a least-squares minimum with h != 0 from every
start means the constraints are inconsistent.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> is_zero(sp.sin(x)**2 + sp.cos(x)**2 - 1), is_zero(x - 1)
(True, False)
"""

from __future__ import annotations

import random
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

SEED = 20240605
PROBES = 3
TOLERANCE = 1e-9
MODULES = ["math", "mpmath", "sympy"]


def random_values(symbols: Sequence[sp.Symbol], rng: random.Random) -> dict[sp.Symbol, float]:
    """Values in (0.3, 1.3): away from 0 (where factors 1/q blow up) and of order one."""
    return {s: rng.uniform(0.3, 1.3) for s in sorted(symbols, key=str)}


def evaluate(expr: Any, values: Mapping[sp.Symbol, float]) -> float | None:
    """The real value of ``expr`` at ``values``; None if it is not finite or not real."""
    try:
        exact = {s: sp.Float(v, 30) for s, v in values.items()}
        number = complex(sp.sympify(expr).xreplace(exact).evalf(30))
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    if not np.isfinite(number) or abs(number.imag) > 1e-12 * max(1.0, abs(number.real)):
        return None
    return number.real


def is_zero(expr: Any) -> bool:
    """True when ``expr`` vanishes identically: a non-zero value at a random point proves it
    does not; zeros at several points are confirmed by simplify when that is cheap."""
    expr = sp.sympify(expr)
    if expr == 0:
        return True
    rng = random.Random(SEED)
    symbols = list(expr.free_symbols)
    for _ in range(PROBES):
        value = evaluate(expr, random_values(symbols, rng))
        if value is not None and abs(value) > 1e-12:
            return False
    if sp.count_ops(expr) <= 80:
        return bool(sp.simplify(expr) == 0)
    return True


def rank(matrix: np.ndarray) -> int:
    """Numerical rank (singular values above a relative tolerance)."""
    if matrix.size == 0:
        return 0
    singular = np.linalg.svd(matrix, compute_uv=False)
    return int(np.sum(singular > TOLERANCE * max(1.0, singular[0])))


class NumericFunction:
    """``exprs`` as a fast numerical function of ``symbols`` (vector or matrix valued)."""

    def __init__(self, exprs: sp.MatrixBase, symbols: Sequence[sp.Symbol]) -> None:
        self.shape = exprs.shape
        self.symbols = tuple(symbols)
        self._function: Callable[..., Any] = (
            sp.lambdify(self.symbols, exprs, modules=MODULES) if 0 not in self.shape else list
        )

    def __call__(self, values: Mapping[sp.Symbol, float]) -> np.ndarray | None:
        if 0 in self.shape:
            return np.zeros(self.shape)
        try:
            result = np.array(self._function(*[values[s] for s in self.symbols]), dtype=complex)
        except (TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None
        if not np.all(np.isfinite(result)) or np.any(np.abs(result.imag) > 1e-12):
            return None
        return result.real.reshape(self.shape)


@dataclass(frozen=True)
class Projection:
    """The best configuration found and the constraints' values (residuals) there."""

    values: dict[sp.Symbol, float]
    residuals: tuple[float, ...]

    @property
    def satisfied(self) -> bool:
        return all(abs(r) < 1e-8 for r in self.residuals)


def project(
    equations: Sequence[sp.Expr],
    unknowns: Sequence[sp.Symbol],
    start: Mapping[sp.Symbol, float],
    starts: int = 4,
) -> Projection:
    """Least squares h(q) = 0 over ``unknowns`` by damped Gauss–Newton, from ``start`` and
    from further random starts until one satisfies every equation."""
    if not equations:
        return Projection(dict(start), ())
    symbols = sorted(set(start) | set(unknowns), key=str)
    residual = NumericFunction(sp.Matrix(equations), symbols)
    slope = NumericFunction(sp.Matrix(equations).jacobian(list(unknowns)), symbols)
    rng = random.Random(SEED + 1)
    best: Projection | None = None
    for attempt in range(starts):
        values = dict(start)
        if attempt:
            values.update(random_values(unknowns, rng))
        found = _gauss_newton(residual, slope, unknowns, values)
        if found is not None and (best is None or _norm(found) < _norm(best)):
            best = found
        if best is not None and best.satisfied:
            break
    return best or Projection(dict(start), tuple(float("nan") for _ in equations))


def _norm(projection: Projection) -> float:
    return float(np.linalg.norm(projection.residuals))


def _gauss_newton(
    residual: NumericFunction,
    slope: NumericFunction,
    unknowns: Sequence[sp.Symbol],
    values: dict[sp.Symbol, float],
) -> Projection | None:
    h = residual(values)
    if h is None:
        return None
    h = h.ravel()
    for _ in range(60):
        jac = slope(values)
        if jac is None or np.linalg.norm(h) < 1e-13:
            break
        step = np.linalg.lstsq(jac, -h, rcond=None)[0]
        for damping in (1.0, 0.5, 0.25, 0.1, 0.01):  # accept the first step that helps
            trial = dict(values)
            for s, ds in zip(unknowns, step):
                trial[s] += damping * ds
            h_trial = residual(trial)
            if h_trial is not None and np.linalg.norm(h_trial) < np.linalg.norm(h):
                values, h = trial, h_trial.ravel()
                break
        else:
            break  # no step reduces |h|: a least-squares minimum
    return Projection({s: float(v) for s, v in values.items()}, tuple(float(v) for v in h))
