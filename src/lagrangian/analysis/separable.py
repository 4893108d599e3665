"""Static equations that separate: each static force depends on one coordinate of its own.

An n-link pendulum at rest has the static forces -g l_i (m_i + ... + m_n) sin(theta_i): each
equation holds its own coordinate alone, so the equilibria are every combination of the
roots of the n one-coordinate equations (theta_i = 0 or pi: 2^n of them), found by n small
solves instead of a search in n unknowns, and

    K = -d(static forces)/dq    is diagonal,  K_ii = -d f_i/dq_i at q_i's root,

so at a combination K has one negative eigenvalue for each coordinate at a root where its
entry is negative: the combinations of roots with positive entries are the minima of the
potential, those with negative ones the maxima, every other one a saddle.  Up to
:data:`LISTED` equilibria are listed; beyond, the minima and the maxima, and the reason says
how many there are and what the others are.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> [(r.coordinate, r.roots) for r in separate_roots(sp.Matrix([-sp.sin(x), 2 - y]), [x, y], {})]
[(x, (0, pi)), (y, (2,))]
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import evaluate
from lagrangian.analysis.evaluation import names_text
from lagrangian.analysis.rest import symbolic_solutions
from lagrangian.analysis.roots import normalize_angles, periodic_coordinates
from lagrangian.symbolic.nonsmooth import derivative

#: The unknown each coordinate's equation is solved in (one solve per form of equation).
_X = sp.Dummy("x")
#: Equilibria listed one by one; beyond, the minima and maxima (up to this many in all).
LISTED = 64


@dataclass(frozen=True)
class CoordinateRoots:
    """The roots of one coordinate's static equation and, at each, K's diagonal entry
    -d f/dq at the parameter values (None where it is not a number)."""

    coordinate: sp.Symbol
    roots: tuple[sp.Expr, ...]
    stiffness: tuple[float | None, ...]


def separate_equations(
    static: sp.MatrixBase, unknowns: Sequence[sp.Symbol]
) -> dict[sp.Symbol, sp.Expr] | None:
    """Each unknown with the one static equation that holds it alone; None unless every
    non-zero equation holds exactly one unknown, each a different one (at least two)."""
    wanted, found = set(unknowns), {}
    for equation in static:
        if equation == 0:
            continue
        own = equation.free_symbols & wanted
        if len(own) != 1:
            return None
        (q,) = own
        if q in found:
            return None
        found[q] = equation
    return found if len(found) >= 2 and len(found) == len(wanted) else None


def _number(expr: sp.Expr, numbers: Mapping[sp.Symbol, sp.Expr]) -> float | None:
    value = evaluate(expr, numbers)
    if value.free_symbols:
        return None
    real = complex(value)
    return real.real if abs(real.imag) <= 1e-12 * max(1.0, abs(real.real)) else None


def _one_coordinate(
    equation: sp.Expr,
    q: sp.Symbol,
    numbers: Mapping[sp.Symbol, sp.Expr],
    solved: dict[sp.Expr, list[sp.Expr] | None],
) -> tuple[sp.Expr, ...] | None:
    """The roots of ``equation`` = 0 in ``q``: its factor free of q dropped when the values
    make it non-zero (none of them: every q would be at rest, a family; None), the rest
    solved by sympy.solve once per form (a chain's sin(theta_i) is sin(x) once)."""
    coefficient, dependent = equation.as_independent(q, as_Add=False)
    size = _number(coefficient, numbers)
    if size is None or abs(size) < 1e-12:
        return None
    form = dependent.xreplace({q: _X})
    if form not in solved:
        solutions = symbolic_solutions(sp.Matrix([form]), [_X])
        solved[form] = None if solutions is None else [s[_X] for s in solutions if _X in s]
    roots = solved[form]
    return None if roots is None else tuple(roots)


def separate_roots(
    static: sp.MatrixBase, unknowns: Sequence[sp.Symbol], numbers: Mapping[sp.Symbol, sp.Expr]
) -> list[CoordinateRoots] | None:
    """The roots of each coordinate's own static equation (angles in (-pi, pi]) and K's
    entry at each, or None when the equations do not separate or a root is not found
    symbolically (the system is then solved whole)."""
    equations = separate_equations(static, unknowns)
    if equations is None:
        return None
    angles = periodic_coordinates(list(equations), list(equations.values()))
    solved: dict[sp.Expr, list[sp.Expr] | None] = {}
    found = []
    for q in unknowns:
        equation = equations[q]
        roots = _one_coordinate(equation, q, numbers, solved)
        if roots is None:
            return None
        kept = normalize_angles([{q: r} for r in roots], angles, numbers)
        values = tuple(s[q] for s in kept)
        slope = -derivative(equation, q)
        stiffness = tuple(_number(slope.xreplace({q: r}), numbers) for r in values)
        found.append(CoordinateRoots(q, values, stiffness))
    return found


def equilibrium_count(found: Sequence[CoordinateRoots]) -> int:
    """Every combination of the coordinates' roots."""
    return math.prod(len(r.roots) for r in found)


def _combinations(found: Sequence[CoordinateRoots], sign: int) -> Iterator[dict]:
    """The combinations of roots whose K entries all have ``sign``."""
    choices = [
        [root for root, k in zip(r.roots, r.stiffness) if k is not None and k * sign > 0]
        for r in found
    ]
    for values in itertools.product(*choices):
        yield {r.coordinate: v for r, v in zip(found, values)}


def listed_solutions(found: Sequence[CoordinateRoots]) -> tuple[list[dict], str]:
    """The combinations of roots to list, and which they are: all of them up to
    :data:`LISTED`; beyond, the minima (every K entry positive) and the maxima (every one
    negative), up to :data:`LISTED` in all."""
    count = equilibrium_count(found)
    if count <= LISTED:
        every = itertools.product(*[r.roots for r in found])
        return [{r.coordinate: v for r, v in zip(found, values)} for values in every], "all"
    if any(k is None or k == 0 for r in found for k in r.stiffness):
        first = itertools.islice(itertools.product(*[r.roots for r in found]), LISTED)
        listed = [{r.coordinate: v for r, v in zip(found, values)} for values in first]
        return listed, f"the first {len(listed)} in the order of the roots"
    minima = list(itertools.islice(_combinations(found, 1), LISTED // 2))
    maxima = list(itertools.islice(_combinations(found, -1), LISTED - len(minima)))
    return minima + maxima, (
        f"{_counted(minima, 'combination')} whose K entries are all positive (minima of the "
        f"potential) and {_counted(maxima, 'combination')} whose entries are all negative "
        "(maxima); at every other combination K has both signs: a saddle of the potential"
    )


def _counted(items: Sequence, noun: str) -> str:
    return f"the {len(items)} {noun}{'' if len(items) == 1 else 's'}"


def separable_reason(found: Sequence[CoordinateRoots], listed: str, gyroscopic: bool) -> str:
    """How the equilibria were found and, when not all are listed, how many there are."""
    if listed == "all":
        return (
            "every branch sympy.solve finds for the static equations, which separate: each "
            "holds one coordinate of its own, solved one by one"
        )
    groups: dict[tuple[str, ...], list[str]] = {}
    for r in found:
        groups.setdefault(tuple(str(v) for v in r.roots), []).append(r.coordinate.name)
    roots = "; ".join(
        f"{names_text(names, 'more coordinates')}: {' or '.join(values)}"
        for values, names in groups.items()
    )
    unstable = "" if gyroscopic else " (unstable: no force linear in the velocities acts at rest)"
    return (
        "the static equations separate, each holding one coordinate of its own, solved one by "
        f"one by sympy.solve ({roots}): {equilibrium_count(found):,} equilibria, every "
        "combination of the roots; K = -d(static forces)/dq is diagonal there, with one "
        "negative eigenvalue for each coordinate at a root where its entry is negative; "
        f"listed: {listed}" + (unstable if "saddle" in listed else "")
    )
