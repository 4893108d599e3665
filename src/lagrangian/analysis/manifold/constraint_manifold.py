"""The constraint manifold an analysis works on: the equality constraints in the form every
analysis of a constrained system needs (docs/architecture.md; Goldstein, Classical Mechanics,
3rd ed., §1.3).

Each kept constraint j gives a row of the velocity-level form

    a_j(q, t) . q_dot + b_j(q, t) = 0,        A = [a_j],  b = [b_j],

(a holonomic h_j(q, t) = 0 through h_dot: a_j = dh_j/dq, b_j = dh_j/dt) and, differentiated
once more, A q_ddot = gamma.  Holonomic constraints also hold at position level, h_j = 0.
With the multipliers of the sign convention of docs/architecture.md the equations are

    M q_ddot = forcing + A^T lambda,

so lambda_j a_j is the force of constraint j and its power is lambda_j a_j . q_dot =
-lambda_j b_j: a constraint with b = 0 (scleronomic) does no work on the actual motion.

Redundant constraints (a Jacobian row that is a combination of earlier ones) are left out, as
their multipliers are not determined; unilateral constraints g >= 0 are taken as not in
contact (released), and both are said in ``left_out``, once per reason.  The dimensions (Greenwood,
*Advanced Dynamics* §1.3; Bloch, *Nonholonomic Mechanics and Control* §1.2):

    configuration_dimension = n - rank(holonomic rows)       (the manifold of configurations)
    independent_velocities  = n - rank(all rows)             (the degrees of freedom)

>>> import lagrangian as lg
>>> manifold = constraint_manifold(lg.derive(lg.examples.rolling_disc()))
>>> manifold.configuration_dimension, manifold.independent_velocities
(5, 3)
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import evaluate
from lagrangian.analysis.manifold.left_out import REDUNDANT, UNILATERAL, LeftOut, statements
from lagrangian.constraints import ConstraintReport, classify, multiplier_symbols
from lagrangian.constraints.pfaffian import acceleration_terms, pfaffian_form
from lagrangian.constraints.projection import Violation, project_state, violations
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import ConstraintError, Fix, raise_if_problems
from lagrangian.model.constraints import Constraint, label
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import PROBES, SEED, is_zero, random_values
from lagrangian.symbolic.probe import evaluate as value_at


@dataclass(frozen=True)
class ConstraintManifold:
    """The kept equality constraints of a system (see the module docstring).

    ``indices`` are the positions of the kept constraints in ``System.constraints``,
    ``positional`` says which of them are holonomic (h = 0 at position level, ``levels``
    their h), ``jacobian``, ``rates`` and ``gamma`` are A, b and gamma row by row, and
    ``multipliers`` the lambda_j of those rows, named by their constraint's position as in
    ``lagrangian derive``.  ``classification`` is :func:`lagrangian.constraints.classify`.
    """

    coordinates: tuple[sp.Symbol, ...]
    velocities: tuple[sp.Symbol, ...]
    constraints: tuple[Constraint, ...]
    indices: tuple[int, ...]
    labels: tuple[str, ...]
    positional: tuple[bool, ...]
    levels: tuple[sp.Expr | None, ...]
    jacobian: sp.ImmutableMatrix
    rates: sp.ImmutableMatrix
    gamma: sp.ImmutableMatrix
    multipliers: tuple[sp.Symbol, ...]
    left_out: tuple[str, ...]  # one statement per reason (:mod:`.left_out`)
    classification: ConstraintReport

    @property
    def size(self) -> int:
        """The number of kept constraints (rows of A)."""
        return len(self.indices)

    @property
    def configuration_dimension(self) -> int:
        """n minus the rank of the holonomic constraints."""
        return self.classification.dof

    @property
    def independent_velocities(self) -> int:
        """n minus the rank of all equality constraints: the degrees of freedom."""
        return self.classification.independent_velocities

    @property
    def holonomic_rows(self) -> tuple[int, ...]:
        """Rows (of A) of the holonomic constraints."""
        return tuple(i for i, p in enumerate(self.positional) if p)

    @property
    def velocity_rows(self) -> tuple[int, ...]:
        """Rows of the constraints given at velocity level."""
        return tuple(i for i, p in enumerate(self.positional) if not p)

    @property
    def nonholonomic(self) -> tuple[str, ...]:
        """Labels of the kept constraints that classify() finds non-integrable."""
        classes = self.classification.constraints
        return tuple(
            self.labels[row] for row, i in enumerate(self.indices) if not classes[i].holonomic
        )

    @property
    def moving(self) -> tuple[int, ...]:
        """Rows with b != 0: constraints that move with time and do work."""
        return tuple(row for row in range(self.size) if not is_zero(self.rates[row]))

    @property
    def position_equations(self) -> tuple[sp.Expr, ...]:
        """h_j(q, t) of the holonomic rows."""
        return tuple(h for h in self.levels if h is not None)

    def constraint_forces(self) -> sp.ImmutableMatrix:
        """A^T lambda: the generalized force of the constraints on each coordinate."""
        return sp.ImmutableMatrix(self.jacobian.T * sp.Matrix(self.multipliers))


_MANIFOLDS: IdentityCache[EquationsOfMotion, ConstraintManifold | None] = IdentityCache()


def constraint_manifold(eom: EquationsOfMotion) -> ConstraintManifold | None:
    """The constraint manifold of ``eom.system`` (once per equations object), or None when
    the system has no constraints.  Raises ConstraintError for inconsistent constraints."""
    return _MANIFOLDS.get(eom, _build)


def _build(eom: EquationsOfMotion) -> ConstraintManifold | None:
    system = eom.system
    if not system.constraints:
        return None
    report = classify(system)
    coordinates = tuple(system.coordinates)
    names = multiplier_symbols(len(system.constraints))
    kept, left_out = [], []
    for i, constraint in enumerate(system.constraints):
        why = (
            UNILATERAL
            if constraint.kind == "unilateral"
            else REDUNDANT
            if report.constraints[i].redundant
            else None
        )
        if why is not None:
            left_out.append(LeftOut(i, constraint, why))
        else:
            kept.append(i)
    forms = [pfaffian_form(system.constraints[i], coordinates) for i in kept]
    positional = tuple(system.constraints[i].kind == "holonomic" for i in kept)
    return ConstraintManifold(
        coordinates=coordinates,
        velocities=tuple(eom.velocities),
        constraints=tuple(system.constraints[i] for i in kept),
        indices=tuple(kept),
        labels=tuple(label(i, system.constraints[i]) for i in kept),
        positional=positional,
        levels=tuple(
            system.constraints[i].expression if p else None for i, p in zip(kept, positional)
        ),
        jacobian=sp.ImmutableMatrix(
            len(forms), len(coordinates), [a for f in forms for a in f.coefficients]
        ),
        rates=sp.ImmutableMatrix(len(forms), 1, [f.time_coefficient for f in forms]),
        gamma=sp.ImmutableMatrix(len(forms), 1, acceleration_terms(forms, coordinates)),
        multipliers=tuple(names[i] for i in kept),
        left_out=statements(left_out),
        classification=report,
    )


def numeric_point(
    eom: EquationsOfMotion, state: Mapping[sp.Symbol, sp.Expr], numbers: Mapping
) -> dict[sp.Symbol, float]:
    """The state and the parameter values as floats; ConstraintError when a parameter that
    the constraints use has no value."""
    point = {s: float(evaluate(to_sympy(v), numbers)) for s, v in state.items()}
    used = set().union(*(c.expression.free_symbols for c in eom.system.constraints))
    missing = []
    for p in eom.parameters:
        value = evaluate(to_sympy(numbers.get(p, p)), numbers)
        if value.free_symbols:
            if p in used:
                missing.append(p.name)
            continue
        point[p] = float(value)
    if missing:
        raise ConstraintError(
            f"The state cannot be checked against the constraints: {', '.join(missing)} "
            "have no values; give them values."
        )
    return point


def state_violations(
    eom: EquationsOfMotion, state: Mapping[sp.Symbol, sp.Expr], numbers: Mapping
) -> tuple[Violation, ...]:
    """The constraints that ``state`` (every coordinate, velocity and t) misses, at the
    parameter values ``numbers`` (:func:`lagrangian.constraints.projection.violations`)."""
    return violations(eom.system, numeric_point(eom, state, numbers))


def require_on_manifold(
    eom: EquationsOfMotion,
    state: Mapping[sp.Symbol, sp.Expr],
    numbers: Mapping,
    fix: str | Fix,
) -> None:
    """ConstraintError naming every constraint ``state`` misses, each with its residual
    and ``fix`` (the way to project the state, in the caller's words)."""
    if not eom.system.constraints:
        return
    found = state_violations(eom, state, numbers)
    raise_if_problems(
        [v.problem(fix) for v in found],
        "The state is not on the constraints",
        ConstraintError,
    )


#: |value| / (largest term) below which an expression counts as 0 at a state on the manifold.
ON_MANIFOLD = 1e-9


def vanishes_on_manifold(expr: sp.Expr, eom: EquationsOfMotion) -> bool:
    """True when ``expr`` (of q, q_dot, t and the parameters) is 0 wherever the constraints
    hold: identically, or at ``PROBES`` generic states moved onto every equality constraint
    (:func:`lagrangian.constraints.project_state`), parameters at their defaults.  A force
    across a knife edge, F (sin phi, -cos phi) . q_dot, does no work on the manifold."""
    if is_zero(expr):
        return True
    system = eom.system
    terms = sp.Add.make_args(sp.expand(expr))
    rng = random.Random(SEED)
    free = [*system.coordinates, *system.velocities, eom.time]
    free += [p for p, v in system.parameters.items() if v is None]
    for _ in range(PROBES):
        try:
            state = project_state(system, random_values(free, rng))
        except ConstraintError:
            return False
        value = value_at(expr, state)
        sizes = [abs(value_at(term, state) or 0.0) for term in terms]
        if value is None or abs(value) > ON_MANIFOLD * max(1.0, *sizes):
            return False
    return True
