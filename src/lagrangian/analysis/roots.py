"""Roots of static equations: numeric search, angles, and when a symbolic branch is real.

An *angle* is a coordinate that the equations contain only as sin(k q), cos(k q) with an
integer k: its values are taken in (-pi, pi].  A symbolic root such as acos(g/(R omega^2))
is real only when |g/(R omega^2)| <= 1; :func:`branch_condition` collects such conditions
(acos/asin arguments in [-1, 1], square roots of non-negative numbers, logarithms of
positive ones).

>>> x = sp.Symbol("x")
>>> numeric_roots(sp.Matrix([x**2 - 2]), [x], [])
[{x: -1.41421356237310}, {x: 1.41421356237310}]
"""

from __future__ import annotations

import math
import random
import time
from collections.abc import Mapping, Sequence

import sympy as sp

from lagrangian.analysis.arguments import assuming_positive, evaluate
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import TimeLimitError
from lagrangian.limits import time_limit
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import NONSMOOTH

STARTS = 24
TOLERANCE = 1e-8
#: Seconds the numeric search may take; the starting points not tried by then are reported.
SEARCH_SECONDS = 5.0


def _only_in_trig(expr: sp.Basic, q: sp.Symbol) -> bool:
    if q not in expr.free_symbols:
        return True
    if isinstance(expr, (sp.sin, sp.cos)):
        argument = expr.args[0]
        slope = argument.diff(q)
        return bool(
            slope.is_Integer and slope != 0 and q not in (argument - slope * q).free_symbols
        )
    if expr == q:
        return False
    return all(_only_in_trig(a, q) for a in expr.args)


def periodic_coordinates(coordinates: Sequence[sp.Symbol], exprs) -> list[sp.Symbol]:
    """The coordinates that every expression contains only through sin/cos of k q."""
    outside: set[sp.Basic] = set()
    seen: set[sp.Basic] = set()
    for expr in exprs:
        outside |= _outside_trig(to_sympy(expr), set(coordinates) - outside, seen)
    return [q for q in coordinates if q not in outside]


def _outside_trig(expr: sp.Basic, coordinates: set[sp.Basic], seen: set[sp.Basic]) -> set:
    """The ``coordinates`` that ``expr`` contains other than through sin/cos of k q
    (:func:`_only_in_trig` for all of them in one walk, each shared subexpression once)."""
    outside: set[sp.Basic] = set()
    stack = [expr]
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        if node.is_Symbol:
            if node in coordinates:
                outside.add(node)
        elif isinstance(node, (sp.sin, sp.cos)) or not (
            node.is_Add or node.is_Mul or node.is_Pow or isinstance(node, sp.Function)
        ):
            free = node.free_symbols  # a trig argument, or bound variables (Subs, Derivative)
            outside.update(q for q in coordinates if q in free and not _only_in_trig(node, q))
        else:
            stack.extend(node.args)
    return outside


def _occurrences(expr: sp.Basic, q: sp.Symbol, inside: bool, found: set[bool]) -> None:
    if expr == q:
        found.add(inside)
    elif q in expr.free_symbols:
        wraps = isinstance(expr, sp.Function) or (expr.is_Pow and q in expr.exp.free_symbols)
        for argument in expr.args:
            _occurrences(argument, q, inside or wraps, found)


def mixes_functions(exprs, unknowns: Sequence[sp.Symbol]) -> bool:
    """True when some unknown appears both bare and inside a function (k q = sin q): such
    equations have no closed-form solution and sympy.solve spends seconds saying so."""
    for q in unknowns:
        found: set[bool] = set()
        for e in exprs:
            _occurrences(to_sympy(e), q, False, found)
        if found == {True, False}:
            return True
    return False


def branch_condition(values: Sequence[sp.Expr], eom: EquationsOfMotion) -> sp.Basic:
    """When every value is real (positive parameters assumed positive)."""
    parts = []
    for value in values:
        for atom in value.atoms(sp.acos, sp.asin):
            argument = atom.args[0]
            parts += [argument >= -1, argument <= 1]
        for power in value.atoms(sp.Pow):
            if power.exp.is_Rational and not power.exp.is_Integer and power.exp.q % 2 == 0:
                parts.append(power.base >= 0)
        for log in value.atoms(sp.log):
            parts.append(log.args[0] > 0)
    if not parts:
        return sp.true
    return assuming_positive(sp.And(*parts), eom)


def _reduce_angle(value: sp.Expr, number: float) -> sp.Expr:
    """``value`` shifted by a multiple of 2 pi into (-pi, pi] (``number`` is its value)."""
    turns = math.ceil((number - math.pi) / (2 * math.pi) - 1e-12)
    return value - 2 * sp.pi * turns if turns else value


def normalize_angles(
    solutions: list[dict], angles: Sequence[sp.Symbol], numbers: Mapping[sp.Symbol, sp.Expr]
) -> list[dict]:
    """Angles brought into (-pi, pi] and duplicate solutions dropped."""
    result: list[dict] = []
    seen: list[tuple[dict, dict]] = []
    for solution in solutions:
        reduced = dict(solution)
        numeric = {}
        for q, value in solution.items():
            number = evaluate(value, numbers)
            if q in angles and not number.free_symbols and number.is_real:
                reduced[q] = _reduce_angle(value, float(number))
                number = evaluate(reduced[q], numbers)
            numeric[q] = number
        if any(_same(numeric, other) for other, _ in seen):
            continue
        seen.append((numeric, reduced))
        result.append(reduced)
    return result


def _same(a: Mapping, b: Mapping) -> bool:
    if set(a) != set(b):
        return False
    for q in a:
        difference = to_sympy(a[q] - b[q])
        if difference.free_symbols:
            if sp.simplify(difference) != 0:
                return False
        elif abs(complex(difference)) > TOLERANCE * max(1.0, abs(complex(a[q]))):
            return False
    return True


def _starts(unknowns: Sequence[sp.Symbol], angles: Sequence[sp.Symbol]) -> list[list[float]]:
    rng = random.Random(1729)
    starts = [[0.0] * len(unknowns)]
    for i in range(STARTS - 1):
        scale = (0.5, 2.0, 8.0)[i % 3]
        starts.append(
            [
                rng.uniform(-math.pi, math.pi) if q in angles else rng.uniform(-scale, scale)
                for q in unknowns
            ]
        )
    return starts


def numeric_roots(
    equations: sp.MatrixBase,
    unknowns: Sequence[sp.Symbol],
    angles: Sequence[sp.Symbol],
    starts: Sequence[Sequence[float]] | None = None,
    seconds: float = SEARCH_SECONDS,
    tried: list[int] | None = None,
) -> list[dict]:
    """Distinct roots found by sympy.nsolve from several starting points (``starts``, or
    random ones), angles wrapped into (-pi, pi], round-off below 1e-12 of the largest
    entry set to 0, sorted.  No new start is tried after ``seconds``; ``tried``, when
    given, receives (starts tried, starts there were)."""
    system = [e for e in equations if e != 0]
    if len(system) != len(unknowns) or set().union(*[e.free_symbols for e in system]) - set(
        unknowns
    ):
        return []
    if any(e.has(*NONSMOOTH) for e in system):  # Newton's method needs the derivatives
        return []
    found: list[dict] = []
    points = list(starts) if starts is not None else _starts(unknowns, angles)
    deadline = time.monotonic() + seconds
    # one Newton iteration of a long system (a bicycle's) can take longer than the whole
    # search: the search's time bounds each call too
    spent = f"the numeric search for roots ran past its {seconds:g} s"
    count = 0
    for start in points:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        count += 1
        try:
            with time_limit(left, message=spent):
                root = sp.nsolve(system, list(unknowns), list(start), prec=20)
        except TimeLimitError as error:
            if str(error) != spent:
                raise  # a limit outside the search
            count -= 1  # not finished
            break
        except (ValueError, ZeroDivisionError, TypeError):
            continue
        values = {}
        scale = max(1.0, *(abs(float(x)) for x in root))
        for q, value in zip(unknowns, root):
            number = float(value)
            number = 0.0 if abs(number) < 1e-12 * scale else number
            if q in angles:
                number = number - 2 * math.pi * math.ceil((number - math.pi) / (2 * math.pi))
            values[q] = sp.Float(number, 15)
        if not any(_same(values, other) for other in found):
            found.append(values)
    if tried is not None:
        tried.extend((count, len(points)))
    return sorted(found, key=lambda s: [float(s[q]) for q in unknowns])
