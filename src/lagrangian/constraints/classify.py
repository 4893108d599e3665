"""classify(system) -> ConstraintReport: what each constraint is, and what is left to move.

Goldstein, Classical Mechanics, 3rd ed., §1.3: a constraint is *holonomic* when it is an
equation h(q, t) = 0 between the coordinates (and time); velocity constraints that integrate
to such an equation are holonomic too (:mod:`lagrangian.constraints.integrability`), the
others and inequalities g >= 0 are *non-holonomic*; a constraint with explicit t is
*rheonomic*, else *scleronomic*.  Counting, with n coordinates, r_h the rank of the holonomic
constraints' Jacobian and r the rank of all equality constraints' Jacobian (at a generic point
of the constraint set):

    degrees of freedom       dof = n - r_h
    independent velocities   n - r       (dof minus the independent non-holonomic constraints)

and for N particles in d dimensions (the textbook 3N - k) k = d N - dof, the constraints built
into the coordinates plus the independent holonomic ones.  Unilateral constraints remove no
freedom (they are inequalities).

>>> import lagrangian as lg, sympy as sp
>>> x, y, phi = sp.symbols("x y phi")
>>> x_dot, y_dot = sp.symbols("x_dot y_dot")
>>> skate = lg.System(coordinates=[x, y, phi],
...     constraints=[lg.VelocityConstraint(x_dot*sp.sin(phi) - y_dot*sp.cos(phi))])
>>> report = classify(skate)
>>> report.constraints[0].holonomic, report.dof, report.independent_velocities
(False, 3, 2)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import sympy as sp

from lagrangian.constraints.dependence import Dependence, dependence
from lagrangian.constraints.forms import one_form
from lagrangian.constraints.integrability import Integrability, frobenius, integrate_form
from lagrangian.constraints.pfaffian import pfaffian_form
from lagrangian.constraints.projection import numeric_state
from lagrangian.model import System, t
from lagrangian.model.system import require_system
from lagrangian.symbolic.probe import PointFunction, numeric_rank


@dataclass(frozen=True)
class ConstraintClass:
    """The classification of one constraint.

    ``integrated`` is, for a velocity constraint found integrable, h(q, t) with the constraint
    equivalent to h(q, t) = h(q(0), 0) (the constant is fixed by the initial state)."""

    index: int
    name: str
    kind: str
    expression: sp.Expr
    holonomic: bool
    rheonomic: bool
    redundant: bool
    reason: str
    integrated: sp.Expr | None = None
    integrating_factor: sp.Expr | None = None

    @property
    def label(self) -> str:
        return (
            f"{self.name!r} (constraints[{self.index}])"
            if self.name
            else (f"constraints[{self.index}]")
        )

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON: expressions as strings SymPy can parse."""
        found: dict[str, Any] = {
            "name": self.name,
            "kind": self.kind,
            "expression": str(self.expression),
            "holonomic": self.holonomic,
            "rheonomic": self.rheonomic,
            "redundant": self.redundant,
            "reason": self.reason,
        }
        if self.integrated is not None:
            found["integrated"] = str(self.integrated)
        return found


@dataclass(frozen=True)
class ParticleCount:
    """The textbook count for N particles in d dimensions: dof = d N - k."""

    particles: int
    dimension: int
    constraints: int
    dof: int

    def __str__(self) -> str:
        d, n, k = self.dimension, self.particles, self.constraints
        return f"{d}N - k = {d}*{n} - {k} = {self.dof}"


@dataclass(frozen=True)
class ConstraintReport:
    """Every constraint classified, the ranks, and the freedom left.

    ``constraint_jacobian`` has a row per constraint (dh/dq, a, or dg/dq for a unilateral
    one).  ``generic_rank`` is the rank of the equality constraints' Jacobian at a generic
    point, ``holonomic_rank`` that of the holonomic ones (velocity constraints found
    integrable included).  With a ``state``: ``state_rank`` there (lower at a singular
    configuration) and ``state_residuals``, each constraint's value (h, g, or a.q_dot + b when
    the state has the velocities)."""

    coordinates: tuple[sp.Symbol, ...]
    constraints: tuple[ConstraintClass, ...]
    constraint_jacobian: sp.ImmutableMatrix
    generic_rank: int
    holonomic_rank: int
    dof: int
    independent_velocities: int
    integrable_set: bool | None
    set_reason: str
    particle_count: ParticleCount | None
    state_rank: int | None = None
    state_residuals: tuple[float | None, ...] | None = None

    @property
    def redundant(self) -> tuple[str, ...]:
        return tuple(c.label for c in self.constraints if c.redundant)

    @property
    def configuration_dimension(self) -> int:
        """n minus the rank of the holonomic constraints: the dimension of the configuration
        manifold (``dof`` here; the analysis report's ``dof`` is the independent velocities,
        which non-holonomic constraints make fewer)."""
        return self.dof


def classify(system: System, state: Mapping[Any, float] | None = None) -> ConstraintReport:
    """Classify the constraints of ``system`` (see the module docstring).

    ``state`` (coordinate, velocity, parameter names or symbols, and ``t``, to values) adds
    the rank of the Jacobian and the constraints' residuals there.  Raises ConstraintError
    when the constraints are inconsistent.
    """
    require_system(system, "classify(system)")
    coordinates = tuple(system.coordinates)
    forms = [pfaffian_form(c, coordinates) for c in system.constraints]
    found = dependence(system)
    classes = [_classify_one(system, i, found) for i in range(len(forms))]
    integrable_set, set_reason = _frobenius_for_the_set(system, classes, found)
    if integrable_set:
        classes = [_holonomic_as_a_set(c, set_reason) for c in classes]
    holonomic_rows = [i for i in found.rows if classes[i].holonomic]
    dof = len(coordinates) - found.rank_of(holonomic_rows)
    report = ConstraintReport(
        coordinates=coordinates,
        constraints=tuple(classes),
        constraint_jacobian=sp.ImmutableMatrix(
            len(forms), len(coordinates), [a for f in forms for a in f.coefficients]
        ),
        generic_rank=found.rank_of(found.rows),
        holonomic_rank=found.rank_of(holonomic_rows),
        dof=dof,
        independent_velocities=len(coordinates) - found.rank_of(found.rows),
        integrable_set=integrable_set,
        set_reason=set_reason,
        particle_count=_particle_count(system, dof, found),
    )
    return report if state is None else _at_state(system, report, state)


def _classify_one(system: System, index: int, found: Dependence) -> ConstraintClass:
    constraint = system.constraints[index]
    rheonomic = t in constraint.expression.free_symbols
    timing = "rheonomic (explicit t)" if rheonomic else "scleronomic"
    redundant = index in found.redundant
    note = "; redundant: its Jacobian row is a combination of earlier ones" if redundant else ""
    verdict = Integrability(True, None, None, "")
    if constraint.kind == "holonomic":
        reason = f"holonomic: an equation h(q, t) = 0 between the coordinates; {timing}"
    elif constraint.kind == "unilateral":
        verdict = Integrability(False, None, None, "")
        reason = (
            "unilateral: the inequality g(q, t) >= 0 is non-holonomic; while active "
            f"(g = 0) it acts like the holonomic constraint g = 0; {timing}"
        )
    else:
        verdict = _integrability(system, index)
        if verdict.integrated is not None:
            reason = (
                f"holonomic in velocity form: {verdict.reason}, so the constraint is "
                f"{verdict.integrated} = const (the constant is fixed by the initial state)"
            )
        elif verdict.integrable:
            reason = f"holonomic in velocity form: {verdict.reason}"
        else:
            reason = f"non-holonomic: {verdict.reason}"
        reason += f"; {timing}"
    return ConstraintClass(
        index=index,
        name=constraint.name,
        kind=constraint.kind,
        expression=constraint.expression,
        holonomic=verdict.integrable,
        rheonomic=rheonomic,
        redundant=redundant,
        reason=reason + note,
        integrated=verdict.integrated,
        integrating_factor=verdict.factor,
    )


def _variables(system: System) -> tuple[sp.Symbol, ...]:
    """(q, t) when some constraint depends on time, else q."""
    forms = [pfaffian_form(c, system.coordinates) for c in system.constraints]
    timed = any(f.depends_on_time() for f in forms)
    return (*system.coordinates, t) if timed else tuple(system.coordinates)


def _integrability(system: System, index: int) -> Integrability:
    form = pfaffian_form(system.constraints[index], system.coordinates)
    variables = _variables(system)
    coefficients = list(form.coefficients)
    if len(variables) > len(coefficients):
        coefficients.append(form.time_coefficient)
    return integrate_form(coefficients, variables)


def _frobenius_for_the_set(
    system: System, classes: list[ConstraintClass], found: Dependence
) -> tuple[bool | None, str]:
    """Frobenius for the independent equality constraints together, when some velocity
    constraint is not integrable alone (None when there is nothing to decide)."""
    if not any(c.kind == "velocity" and not c.holonomic for c in classes):
        return None, ""
    variables = _variables(system)
    forms = []
    for i in found.rows:
        if not classes[i].redundant:
            form = pfaffian_form(system.constraints[i], system.coordinates)
            coefficients = list(form.coefficients)
            if len(variables) > len(coefficients):
                coefficients.append(form.time_coefficient)
            forms.append(one_form(coefficients))
    holds, reason = frobenius(forms, variables)
    return holds, ("the constraints together are integrable: " if holds else "") + reason


def _holonomic_as_a_set(c: ConstraintClass, why: str) -> ConstraintClass:
    if c.kind != "velocity" or c.holonomic:
        return c
    return replace(c, holonomic=True, reason=f"holonomic together with the others: {why}")


def _particle_count(system: System, dof: int, found: Dependence) -> ParticleCount | None:
    """d N - k when the coordinates are exactly the particles' freedoms (no bodies, no
    circuit, and the positions determine every coordinate)."""
    if not system.particles or system.rigid_bodies or system.circuit:
        return None
    positions = sp.Matrix([x for p in system.particles for x in p.position])
    values = PointFunction(
        positions.jacobian(list(system.coordinates)), sorted(found.point, key=str)
    )
    jacobian = values(found.point)
    if jacobian is None or numeric_rank(jacobian) < len(system.coordinates):
        return None
    d, n = system.dimension, len(system.particles)
    return ParticleCount(n, d, d * n - dof, dof)


def _at_state(
    system: System, report: ConstraintReport, state: Mapping[Any, float]
) -> ConstraintReport:
    values = numeric_state(system, state)
    symbols = sorted(values, key=str)
    equality = [i for i, c in enumerate(system.constraints) if c.kind != "unilateral"]
    jacobian = report.constraint_jacobian.extract(equality, list(range(len(system.coordinates))))
    at_state = PointFunction(jacobian, symbols)(values) if equality else None
    residuals = []
    for constraint in system.constraints:
        residual = PointFunction(sp.Matrix([constraint.expression]), symbols)
        used = constraint.expression.free_symbols
        known = all(s in values for s in used)
        number = residual(values) if known else None
        residuals.append(None if number is None else float(number[0, 0]))
    return replace(
        report,
        state_rank=numeric_rank(at_state) if at_state is not None else 0,
        state_residuals=tuple(residuals),
    )
