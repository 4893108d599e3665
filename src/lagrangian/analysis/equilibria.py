"""Equilibria: every solution of the static equations, and its stability.

At rest (q_dot = q_ddot = 0) the equations M q_ddot = forcing reduce to

    forcing(q, 0, t) = 0,

which for a steady rheonomic system (T = T2 + T0, a bead on a hoop spinning at omega) is
grad V_eff = 0 with the effective potential V_eff = -L(q, 0) = V - T0.  Solved symbolically
with sympy.solve when possible (every branch, each with the condition for it to be real),
otherwise numerically with sympy.nsolve from several starting points at the parameter
values.  Stability from K = -d forcing/dq at rest (:mod:`lagrangian.analysis.stability`).

>>> import lagrangian as lg
>>> [dict(e.state) for e in equilibria(lg.examples.simple_pendulum())]
[{theta: 0}, {theta: pi}]
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    assuming_positive,
    equations_of,
    evaluate,
    frozen,
    numeric_values,
    substitutions,
)
from lagrangian.analysis.roots import (
    branch_condition,
    mixes_functions,
    normalize_angles,
    numeric_roots,
    periodic_coordinates,
)
from lagrangian.analysis.simplification import simplify_small_matrix
from lagrangian.analysis.stability import stability_of, stiffness_matrix, sylvester_condition
from lagrangian.derivation import EquationsOfMotion
from lagrangian.model.probe import depends_on, is_zero

SYMBOLIC_LIMIT = 400  # count_ops of the static equations beyond which solve is not tried
UNWIELDY = 80  # count_ops of a root beyond which it is reported as a number


@dataclass(frozen=True)
class Equilibrium:
    """One state of rest: coordinate values (a ``free`` coordinate maps to itself), whether
    it is stable at the parameter values (None: undetermined) and why, the condition for
    the branch to exist, K there, and the symbolic condition for K > 0."""

    state: Mapping[sp.Symbol, sp.Expr]
    stable: bool | None
    reason: str
    stiffness: sp.ImmutableMatrix
    condition: sp.Basic = sp.true
    exists: bool | None = True
    stability_condition: sp.Basic | None = None
    free: tuple[sp.Symbol, ...] = ()
    exact: bool = True


@dataclass(frozen=True)
class Equilibria:
    """Every equilibrium found, the static equations (each = 0), the effective potential
    when there is one, and how they were found ("symbolic", "numeric" or "none")."""

    equilibria: tuple[Equilibrium, ...]
    static_equations: sp.ImmutableMatrix
    effective_potential: sp.Expr | None
    method: str
    reason: str

    def __iter__(self):
        return iter(self.equilibria)

    def __len__(self) -> int:
        return len(self.equilibria)

    def stable(self) -> tuple[Equilibrium, ...]:
        return tuple(e for e in self.equilibria if e.stable)


def static_forces(eom: EquationsOfMotion, subs: Mapping[sp.Symbol, sp.Expr]) -> sp.ImmutableMatrix:
    """forcing(q, 0, t) with the parameter substitutions: zero at an equilibrium."""
    at_rest = {v: 0 for v in eom.velocities}
    return sp.ImmutableMatrix([f.xreplace(at_rest).xreplace(dict(subs)) for f in eom.forcing])


def _symbolic(static: sp.MatrixBase, unknowns: list[sp.Symbol]) -> list[dict] | None:
    equations = [e for e in static if e != 0]
    if len(unknowns) > 3 or sum(sp.count_ops(e) for e in equations) > SYMBOLIC_LIMIT:
        return None
    if mixes_functions(equations, unknowns):
        return None
    # Factored first, so sympy.solve sees each branch (sin(theta) (R omega^2 cos(theta) - g)).
    equations = [sp.factor(e) for e in equations]
    try:
        solutions = sp.solve(equations, unknowns, dict=True)
    except (NotImplementedError, ValueError, TypeError):
        return None
    return solutions


def _stability(
    eom: EquationsOfMotion,
    state: Mapping[sp.Symbol, sp.Expr],
    free: tuple[sp.Symbol, ...],
    numbers: Mapping[sp.Symbol, sp.Expr],
    subs: Mapping[sp.Symbol, sp.Expr],
    exact: bool,
) -> tuple[bool | None, str, sp.ImmutableMatrix, sp.Basic | None]:
    static = static_forces(eom, subs)
    point = {**state, **{v: 0 for v in eom.velocities}}
    stiffness = simplify_small_matrix(stiffness_matrix(static, eom.coordinates).xreplace(point))
    kept = [j for j, q in enumerate(eom.coordinates) if q not in free]
    reduced = stiffness.extract(kept, kept)
    condition = None
    if exact and 0 < reduced.rows <= 3:
        condition = assuming_positive(sylvester_condition(reduced), eom)
    numeric = evaluate(reduced, numbers)
    if numeric.free_symbols:
        verdict = condition if condition in (sp.true, sp.false) else None
        stable = None if verdict is None else bool(verdict)
        missing = ", ".join(sorted(s.name for s in numeric.free_symbols))
        return stable, f"stable when {condition} (no values for {missing})", stiffness, condition
    forcing = sp.Matrix(eom.forcing).xreplace(dict(subs))
    velocity_jacobian = forcing.jacobian(list(eom.velocities)).xreplace(point)
    gyroscopic = evaluate(velocity_jacobian.extract(kept, kept), numbers)
    if gyroscopic.free_symbols:
        gyroscopic = None
    stable, reason = stability_of(numeric, gyroscopic, [q.name for q in free])
    return stable, reason, stiffness, condition


def _unwieldy(solution: Mapping[sp.Symbol, sp.Expr]) -> bool:
    """Roots written with I or longer than a line (Cardano's formulas) read better as numbers."""
    return any(v.has(sp.I) or sp.count_ops(v) > UNWIELDY for v in solution.values())


def _complex(values: Mapping[sp.Symbol, sp.Expr]) -> bool:
    return any(abs(sp.im(v)) > 1e-9 * max(1.0, abs(v)) for v in values.values())


def _build(eom, solution, numbers, subs, exact) -> Equilibrium:
    numeric = {q: evaluate(v, numbers) for q, v in solution.items()}
    known = not any(v.free_symbols for v in numeric.values())
    if known and _unwieldy(solution) and not _complex(numeric):
        solution, exact = {q: sp.Float(sp.re(v), 15) for q, v in numeric.items()}, False
    free = tuple(q for q in eom.coordinates if q not in solution)
    state = frozen({q: solution.get(q, q) for q in eom.coordinates})
    condition = branch_condition(list(solution.values()), eom) if exact else sp.true
    if known and _complex(numeric):
        exists: bool | None = False
        reason = "this branch is complex at the parameter values"
    else:
        exists = _holds(condition, numbers)
        reason = f"this branch needs {condition}, which the parameter values do not satisfy"
    if exists is False:
        stiffness = sp.ImmutableMatrix.zeros(len(eom.coordinates))
        return Equilibrium(state, None, reason, stiffness, condition, False, None, free, exact)
    stable, reason, stiffness, sylvester = _stability(eom, state, free, numbers, subs, exact)
    return Equilibrium(state, stable, reason, stiffness, condition, exists, sylvester, free, exact)


def _holds(condition: sp.Basic, numbers: Mapping) -> bool | None:
    verdict = evaluate(condition, numbers)
    return bool(verdict) if verdict in (sp.true, sp.false) else None


def _solve(static, unknowns, numbers) -> tuple[list[dict] | None, str, str]:
    """(solutions, method, reason): sympy.solve, else nsolve at the parameter values."""
    solutions = _symbolic(static, unknowns)
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
    roots = numeric_roots(numeric, unknowns, angles)
    return roots, "numeric", "sympy.nsolve from several starting points at the parameter values"


def _no_rest(static: sp.ImmutableMatrix, reason: str) -> Equilibria:
    return Equilibria((), static, None, "none", reason)


def equilibria(subject: Subject, parameters: Values | None = None) -> Equilibria:
    """Every equilibrium: symbolic when sympy.solve manages (each branch with its condition),
    otherwise numeric at the parameter values; each with its stability.

    >>> import lagrangian as lg
    >>> [e.stable for e in equilibria(lg.examples.simple_pendulum())]
    [True, False]
    """
    eom = equations_of(subject)
    subs = substitutions(eom, parameters)
    numbers = numeric_values(eom, parameters)
    static = static_forces(eom, subs)
    if depends_on(static, [eom.time]):
        return _no_rest(static, "the static forces depend on time (driven or rheonomic): no rest")
    at_rest = {v: 0 for v in eom.velocities}
    potential = sp.expand(-eom.lagrangian.xreplace(at_rest).xreplace(dict(subs)))
    unknowns = [q for q in eom.coordinates if depends_on(static, [q])]
    nonzero = [e for e in static if not is_zero(e)]
    if not nonzero:
        everywhere = (_build(eom, {}, numbers, subs, True),)
        return Equilibria(everywhere, static, potential, "symbolic", "the static forces vanish")
    constant = [e for e in nonzero if not depends_on(e, unknowns)]
    if constant:
        return _no_rest(
            static, f"the static forces {constant} do not depend on the coordinates: no rest"
        )
    solutions, method, reason = _solve(static, unknowns, numbers)
    if solutions is None:
        return _no_rest(static, reason)
    solutions = normalize_angles(solutions, periodic_coordinates(unknowns, static), numbers)
    found = tuple(_build(eom, s, numbers, subs, method == "symbolic") for s in solutions)
    return Equilibria(found, static, potential, method, reason)
