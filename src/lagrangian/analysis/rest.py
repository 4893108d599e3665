"""States of rest and how they are found: the Equilibrium values, the solution of the static
equations (symbolic, else numeric), and the test of each solution (is the branch real, is it
stable) shared by free systems (:mod:`lagrangian.analysis.equilibria`) and constrained ones
(:mod:`lagrangian.analysis.manifold.statics`).

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> solve_static(sp.Matrix([x**2 - 4]), [x], {})[0]
[{x: -2}, {x: 2}]
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import assuming_positive, evaluate, frozen
from lagrangian.analysis.roots import (
    SEARCH_SECONDS,
    branch_condition,
    mixes_functions,
    numeric_roots,
    periodic_coordinates,
)
from lagrangian.analysis.stability import sylvester_condition
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError

SYMBOLIC_LIMIT = 400  # count_ops of the static equations beyond which solve is not tried
UNWIELDY = 80  # count_ops of a root beyond which it is reported as a number
BEZOUT_LIMIT = 16  # roots (Bezout's bound) of a polynomial system beyond which solve is not tried


@dataclass(frozen=True)
class Equilibrium:
    """One state of rest: coordinate values (a ``free`` coordinate maps to itself), whether
    it is stable at the parameter values (None: undetermined) and why, the condition for
    the branch to exist, K there, and the symbolic condition for K > 0.

    On a constraint manifold also the ``multipliers`` there (lambda_j a_j is the force of
    constraint j that holds the system at rest), and K is the stiffness on the manifold,
    written in the independent coordinates ``stiffness_coordinates``."""

    state: Mapping[sp.Symbol, sp.Expr]
    stable: bool | None
    reason: str
    stiffness: sp.ImmutableMatrix
    condition: sp.Basic = sp.true
    exists: bool | None = True
    stability_condition: sp.Basic | None = None
    free: tuple[sp.Symbol, ...] = ()
    exact: bool = True
    multipliers: Mapping[sp.Symbol, sp.Expr] = frozen({})
    stiffness_coordinates: tuple[sp.Symbol, ...] = ()


@dataclass(frozen=True)
class Equilibria:
    """Every equilibrium found, the static equations (each = 0), the effective potential
    when there is one, and how they were found ("symbolic", "numeric" or "none");
    ``general`` says what holds for other parameter values where that differs from the
    values given ("for F ≠ 0: no rest"), empty otherwise; ``count`` is the number of
    equilibria when it is known and more than those listed (the 2^n of an n-link chain,
    whose static equations separate: the reason says which are listed), else None."""

    equilibria: tuple[Equilibrium, ...]
    static_equations: sp.ImmutableMatrix
    effective_potential: sp.Expr | None
    method: str
    reason: str
    general: str = ""
    count: int | None = None

    def __iter__(self):
        return iter(self.equilibria)

    def __len__(self) -> int:
        return len(self.equilibria)

    def stable(self) -> tuple[Equilibrium, ...]:
        return tuple(e for e in self.equilibria if e.stable)


def symbolic_solutions(
    static: sp.MatrixBase, unknowns: list[sp.Symbol], most: int = 3
) -> list[dict] | None:
    """Every branch sympy.solve finds for static = 0 (factored first), or None when the
    system is too large or of a kind it takes too long on (then solved numerically)."""
    equations = [e for e in static if e != 0]
    if len(unknowns) > most or sum(sp.count_ops(e) for e in equations) > SYMBOLIC_LIMIT:
        return None
    if mixes_functions(equations, unknowns) or _many_roots(equations, unknowns):
        return None
    # Factored first, so sympy.solve sees each branch (sin(theta) (R omega^2 cos(theta) - g)).
    equations = [sp.factor(e) for e in equations]
    try:
        solutions = sp.solve(equations, unknowns, dict=True)
    except (NotImplementedError, ValueError, TypeError):
        return None
    return solutions


def _many_roots(equations: list[sp.Expr], unknowns: list[sp.Symbol]) -> bool:
    """A polynomial system in several unknowns with more than ``BEZOUT_LIMIT`` roots by
    Bezout's bound (the product of the degrees): sympy.solve's Groebner bases take minutes to
    hours there (degree 6 in three unknowns), the numeric search seconds."""
    if len(unknowns) < 2:
        return False
    bound = 1
    for e in equations:
        try:
            bound *= max(1, sp.Poly(e, *unknowns).total_degree())
        except sp.PolynomialError:
            return False
    return bound > BEZOUT_LIMIT


def _unwieldy(solution: Mapping[sp.Symbol, sp.Expr]) -> bool:
    """Roots written with I or longer than a line (Cardano's formulas) read better as numbers."""
    return any(v.has(sp.I) or sp.count_ops(v) > UNWIELDY for v in solution.values())


def _complex(values: Mapping[sp.Symbol, sp.Expr]) -> bool:
    return any(abs(sp.im(v)) > 1e-9 * max(1.0, abs(v)) for v in values.values())


#: (state, free coordinates, multipliers, exact) -> (stable, reason, K, condition for K > 0,
#: the coordinates K is written in; () for all).
StabilityTest = Callable[
    [Mapping[sp.Symbol, sp.Expr], tuple[sp.Symbol, ...], Mapping[sp.Symbol, sp.Expr], bool],
    tuple[bool | None, str, sp.ImmutableMatrix, sp.Basic | None, tuple[sp.Symbol, ...]],
]


def build_equilibrium(
    eom: EquationsOfMotion,
    solution: Mapping[sp.Symbol, sp.Expr],
    numbers: Mapping[sp.Symbol, sp.Expr],
    exact: bool,
    stability: StabilityTest,
) -> Equilibrium:
    """The Equilibrium of one solution of the static equations (coordinates, and multipliers
    on a constraint manifold): the branch's condition to be real, whether the parameter
    values meet it, and ``stability`` there."""
    numeric = {q: evaluate(v, numbers) for q, v in solution.items()}
    known = not any(v.free_symbols for v in numeric.values())
    if known and _unwieldy(solution) and not _complex(numeric):
        solution, exact = {q: sp.Float(sp.re(v), 15) for q, v in numeric.items()}, False
    free = tuple(q for q in eom.coordinates if q not in solution)
    state = frozen({q: solution.get(q, q) for q in eom.coordinates})
    multipliers = frozen({k: v for k, v in solution.items() if k not in eom.coordinates})
    condition = branch_condition(list(solution.values()), eom) if exact else sp.true
    if known and _complex(numeric):
        exists: bool | None = False
        reason = "this branch is complex at the parameter values"
    else:
        exists = _holds(condition, numbers)
        reason = f"this branch needs {condition}, which the parameter values do not satisfy"
    if exists is False:
        stiffness = sp.ImmutableMatrix.zeros(len(eom.coordinates))
        return Equilibrium(
            state, None, reason, stiffness, condition, False, None, free, exact, multipliers
        )
    stable, reason, stiffness, sylvester, written_in = stability(state, free, multipliers, exact)
    return Equilibrium(
        state,
        stable,
        reason,
        stiffness,
        condition,
        exists,
        sylvester,
        free,
        exact,
        multipliers,
        written_in,
    )


def positivity_condition(
    reduced: sp.MatrixBase, eom: EquationsOfMotion, exact: bool
) -> sp.Basic | None:
    """Sylvester's condition for the stiffness ``reduced`` to be positive definite, the
    parameters taken positive, when it is short enough to state (exact, at most 3 x 3)."""
    if exact and 0 < reduced.rows <= 3:
        return assuming_positive(sylvester_condition(reduced), eom)
    return None


def _holds(condition: sp.Basic, numbers: Mapping) -> bool | None:
    verdict = evaluate(condition, numbers)
    return bool(verdict) if verdict in (sp.true, sp.false) else None


def solve_static(
    static: sp.MatrixBase,
    unknowns: list[sp.Symbol],
    numbers: Mapping[sp.Symbol, sp.Expr],
    most: int = 3,
    starts: Callable[[], list[list[float]]] | None = None,
) -> tuple[list[dict] | None, str, str]:
    """(solutions, method, reason) of static = 0: sympy.solve when there are at most
    ``most`` unknowns and the equations are short, else sympy.nsolve at the parameter
    values from several starts (``starts()`` when given, else random; square systems
    only)."""
    solutions = symbolic_solutions(static, unknowns, most)
    if solutions == []:
        return [], "symbolic", "sympy.solve finds no solution of the static equations"
    if solutions is not None:
        return solutions, "symbolic", "every branch sympy.solve finds for the static equations"
    numeric = evaluate(static, numbers)
    missing = numeric.free_symbols - set(unknowns)
    if missing:
        names = ", ".join(sorted(s.name for s in missing))
        return None, "none", f"sympy.solve failed and {names} have no values to search with"
    angles = periodic_coordinates(unknowns, static)
    tried: list[int] = []
    roots = numeric_roots(numeric, unknowns, angles, starts() if starts else None, tried=tried)
    reason = "sympy.nsolve from several starting points at the parameter values"
    if tried and tried[0] < tried[1]:
        reason += (
            f" (the search's {SEARCH_SECONDS:g} s ran out after {tried[0]} of {tried[1]} "
            "starting points: equilibria near the others were not searched)"
        )
    return roots, "numeric", reason


def no_rest(static: sp.ImmutableMatrix, reason: str) -> Equilibria:
    """No state of rest, and why."""
    return Equilibria((), static, None, "none", reason)


def first_stable(found: Equilibria) -> Equilibrium:
    """The first stable equilibrium, or AnalysisError listing why none is."""
    stable = found.stable()
    if stable:
        return stable[0]
    summary = "; ".join(f"{dict(e.state)}: {e.reason}" for e in found) or found.reason
    raise AnalysisError(f"No stable equilibrium to oscillate about ({summary}).")
