"""The generalized eigenproblem of small oscillations, K v = omega^2 M v: symbolic when 2 x 2
(or 1 x 1) and short, numeric at the parameter values otherwise.

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.mass_on_spring())
>>> k, m = sp.Matrix([sp.Symbol("k")]), sp.Matrix([sp.Symbol("m")])
>>> solve_pencil(k, m, k, m, eom, {})[0]
(k/m,)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import assuming_positive, evaluate
from lagrangian.analysis.names import OutputNames
from lagrangian.analysis.simplification import simplify_small
from lagrangian.analysis.spectrum import generalized_modes
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError

SIMPLE = 30  # count_ops of a symbolic omega^2 or mode-shape entry still worth showing


def _magnitude(expr: sp.Expr, numbers: Mapping[sp.Symbol, sp.Expr]) -> float:
    """A number to order symbolic roots by: at the parameter values, other symbols at 1."""
    value = evaluate(expr, numbers)
    return float(sp.re(value.xreplace({s: 1 for s in value.free_symbols})))


def _symbolic_modes(k: sp.Matrix, m: sp.Matrix, eom: EquationsOfMotion, numbers):
    """omega^2 from det(K - lambda M) = 0 and v from the null space, when short enough."""
    lam = sp.Dummy("lambda")
    pencil = k - lam * m
    roots = sp.roots(sp.Poly(pencil.det(), lam))
    if sum(roots.values()) != k.rows:
        return None
    squares = sorted(
        (assuming_positive(r, eom) for r, count in roots.items() for _ in range(count)),
        key=lambda r: _magnitude(r, numbers),
    )
    if any(sp.count_ops(s) > SIMPLE for s in squares):
        return None
    shapes = []
    for square in dict.fromkeys(squares):
        for v in pencil.xreplace({lam: square}).nullspace(simplify=True):
            pivot = next(x for x in v if x != 0)
            shapes.append(sp.ImmutableMatrix([simplify_small(x / pivot) for x in v]))
    if len(shapes) != k.rows or any(sp.count_ops(x) > SIMPLE for v in shapes for x in v):
        return None
    return tuple(squares), tuple(shapes)


def solve_pencil(
    k: sp.MatrixBase,
    m: sp.MatrixBase,
    k_numeric: sp.MatrixBase,
    m_numeric: sp.MatrixBase,
    eom: EquationsOfMotion,
    numbers: Mapping[sp.Symbol, Any],
) -> tuple[tuple, tuple, bool, str]:
    """(omega^2 values, shapes, symbolic?, how): symbolic when exact, 2 x 2 and short."""
    exact = not (k.atoms(sp.Float) or m.atoms(sp.Float))
    omega = OutputNames.of(eom).frequency  # the model may have an omega of its own
    if exact and k.rows <= 2:
        found = _symbolic_modes(sp.Matrix(k), sp.Matrix(m), eom, numbers)
        if found is not None:
            return (*found, True, f"det(K - {omega}^2 M) = 0 solved symbolically")
    missing = k_numeric.free_symbols | m_numeric.free_symbols
    if missing:
        names = ", ".join(sorted(s.name for s in missing))
        raise AnalysisError(f"No numbers for {names} and no short symbolic answer.")
    pairs = generalized_modes(k_numeric, m_numeric)
    squares = tuple(sp.Float(w2, 15) for w2, _ in pairs)
    shapes = tuple(v for _, v in pairs)
    how = f"K v = {omega}^2 M v solved numerically at the parameter values"
    return squares, shapes, False, how
