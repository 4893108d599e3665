"""Equivalent descriptions of the same motion (L + dF/dt: Landau & Lifshitz, Mechanics, §2).

* L and L + dF(q, t)/dt give identical Euler–Lagrange equations: the Euler–Lagrange
  operator of dF/dt = sum dF/dq q_dot + dF/dt vanishes identically.  (A gauge change
  A -> A + grad psi, phi -> phi - dpsi/dt of a charge adds q dpsi/dt to L.)
* A point transformation q = q(s, t) with an invertible Jacobian J = dq/ds carries L into
  L'(s, s_dot, t) = L(q(s, t), J s_dot + dq/dt, t), and the new equations are the old ones
  times J^T:  E'(s) = J^T E(q(s, t)).  Applied forces transform as Q' = J^T Q.

>>> import lagrangian as lg
>>> x = sp.Symbol("x")
>>> equivalent_under_total_derivative(lg.examples.mass_on_spring(), x**2 * lg.t).equivalent
True
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import Subject, equations_of
from lagrangian.derivation import EquationsOfMotion, derive
from lagrangian.errors import AnalysisError, Problem, raise_if_problems
from lagrangian.model import System, velocity
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import all_zero, depends_on, is_zero
from lagrangian.symbolic.symbols import name_of, t, time_derivative


@dataclass(frozen=True)
class TotalDerivativeEquivalence:
    """The equations of L + dF/dt minus those of L (identically zero), with the reason."""

    gauge_function: sp.Expr
    added_term: sp.Expr
    difference: sp.ImmutableMatrix
    equivalent: bool
    reason: str


def _euler_lagrange(expr: sp.Expr, eom: EquationsOfMotion) -> sp.Matrix:
    """d/dt d(expr)/dq_dot - d(expr)/dq for every coordinate."""
    return sp.Matrix(
        [
            time_derivative(expr.diff(v), eom.coordinates) - expr.diff(q)
            for q, v in zip(eom.coordinates, eom.velocities)
        ]
    )


def equivalent_under_total_derivative(subject: Subject, gauge: Any) -> TotalDerivativeEquivalence:
    """Compare the equations of L and L + dF/dt for F = ``gauge``(q, t).

    Given a System, both Lagrangians go through :func:`lagrangian.derive`; given equations
    of motion, the Euler–Lagrange operator is applied to dF/dt here.
    """
    eom = equations_of(subject)
    f = to_sympy(gauge)
    if depends_on(f, (*eom.velocities, *eom.accelerations)):
        raise AnalysisError(
            f"F = {f} depends on velocities: L + dF/dt would contain accelerations. "
            "Give F as a function of the coordinates and t only."
        )
    added = time_derivative(f, eom.coordinates)
    if isinstance(subject, System):
        other = derive(subject.replace(lagrangian=subject.lagrangian + added))
        difference = sp.Matrix(other.equations) - sp.Matrix(eom.equations)
    else:
        difference = _euler_lagrange(added, eom)
    difference = difference.applyfunc(sp.expand)
    equal = all_zero(difference)
    reason = (
        "the Euler–Lagrange operator of dF/dt vanishes: d/dt dF/dq - d/dq dF/dt = 0"
        if equal
        else "the equations differ (F should depend on the coordinates and t only)"
    )
    return TotalDerivativeEquivalence(
        f, added, sp.ImmutableMatrix(difference.applyfunc(sp.simplify)), equal, reason
    )


def _plain(symbol: Any) -> sp.Symbol:
    """The symbol of the same name, without assumptions (``s`` for a positive ``s``)."""
    return sp.Symbol(name_of(symbol))


def _validate(eom, mapping, new) -> dict[sp.Symbol, sp.Expr]:
    """The mapping keyed by the old coordinates; every problem collected, raised once."""
    by_name = {q.name: q for q in eom.coordinates}
    allowed = {*new, *eom.parameters, t}
    problems, resolved = [], {}
    for key, value in mapping.items():
        name = name_of(key)
        expr = to_sympy(value)
        if name not in by_name:
            problems.append(Problem(f"mapping.{name}", "is not a coordinate", "map each old one"))
        else:
            resolved[by_name[name]] = expr
        stray = sorted(s.name for s in expr.free_symbols if _plain(s) not in allowed)
        if stray:
            problems.append(
                Problem(
                    f"mapping.{name}",
                    f"uses unknown names {', '.join(stray)}",
                    "write q with the new coordinates, parameters and t",
                )
            )
    problems += [
        Problem(f"mapping.{q.name}", "is missing", "give q = q(s, t)")
        for q in eom.coordinates
        if q not in resolved
    ]
    if len(new) != len(eom.coordinates):
        problems.append(
            Problem(
                "new_coordinates",
                f"{len(new)} given for {len(eom.coordinates)} coordinates",
                "give as many new coordinates as old ones",
            )
        )
    raise_if_problems(problems, "Invalid point transformation", AnalysisError)
    return resolved


def _simplified(expr: sp.Expr, assumed: Mapping[sp.Symbol, sp.Symbol]) -> sp.Expr:
    """trigsimp with the user's assumptions on the new coordinates, then plain symbols."""
    expr = sp.expand(expr)
    if sp.count_ops(expr) <= 400:
        expr = sp.trigsimp(expr)
    return expr.xreplace(assumed)


def point_transformation(
    system: System, mapping: Mapping[Any, Any], new_coordinates: Sequence[Any]
) -> System:
    """The System in new coordinates s, with q = ``mapping``[q](s, t).

    T, V, U and F are expressed in s (velocities by q_dot = J s_dot + dq/dt) and the applied
    forces become Q' = J^T Q.  New coordinates may carry assumptions (``Symbol("r",
    positive=True)``) used to simplify; the result has plain symbols.  A Jacobian that
    vanishes identically is refused (AnalysisError).

    >>> import lagrangian as lg
    >>> r, th = sp.symbols("r theta")
    >>> polar = point_transformation(lg.examples.particle_plane_cartesian(),
    ...                              {"x": r * sp.cos(th), "y": r * sp.sin(th)}, [r, th])
    >>> lg.derive(polar).mass_matrix
    Matrix([
    [m,      0],
    [0, m*r**2]])
    """
    eom = equations_of(system)
    new = [sp.Symbol(s) if isinstance(s, str) else s for s in new_coordinates]
    plain = [_plain(s) for s in new]
    resolved = _validate(eom, mapping, plain)
    to_assumed = {p: s for p, s in zip(plain, new)}
    q_of_s = {q: resolved[q].xreplace(to_assumed) for q in eom.coordinates}
    jacobian = sp.Matrix([[q_of_s[q].diff(s) for s in new] for q in eom.coordinates])
    if is_zero(jacobian.det()):
        raise AnalysisError(
            f"The point transformation is not invertible: the Jacobian determinant "
            f"d(q)/d(s) of {jacobian.tolist()} is identically zero."
        )
    rates = jacobian * sp.Matrix([velocity(p) for p in plain])
    substitution = {q: q_of_s[q] for q in eom.coordinates}
    substitution.update(
        {
            v: rates[j] + q_of_s[q].diff(t)
            for j, (q, v) in enumerate(zip(eom.coordinates, eom.velocities))
        }
    )
    back = {s: p for s, p in zip(new, plain)}

    def carry(expr: sp.Expr) -> sp.Expr:
        return _simplified(expr.xreplace(substitution), back)

    forces = jacobian.T * sp.Matrix(eom.generalized_forces).xreplace(substitution)
    return System(
        coordinates=plain,
        parameters=dict(eom.parameters),
        kinetic=carry(eom.kinetic_energy),
        potential=carry(eom.potential_energy),
        velocity_potential=carry(eom.velocity_potential),
        dissipation=carry(eom.dissipation_function),
        generalized_forces={
            p: _simplified(f, back) for p, f in zip(plain, forces) if not is_zero(f)
        },
        name=f"{system.name} in ({', '.join(p.name for p in plain)})",
        description=getattr(system, "description", ""),
    )
