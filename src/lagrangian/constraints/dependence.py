"""Redundant and inconsistent constraints, from the rank of the constraint Jacobian.

At a generic point of the constraint set (a random configuration projected onto the holonomic
constraints, :func:`lagrangian.constraints.projection.project`) the rows a_j of the Jacobian are
taken in order, holonomic constraints first:

- a row that does not raise the rank of A is *redundant* (a combination of earlier rows:
  two identical constraints, or x = 0 with 2x = 0);
- a row that raises the rank of [A | b] but not of A is *inconsistent* at velocity level
  (x_dot = 0 with x_dot = 1);
- holonomic constraints that no configuration satisfies (x = 0 with x = 1; least squares
  leaves a residual from every start) are inconsistent at position level.

Inconsistency raises :class:`~lagrangian.errors.ConstraintError` naming the constraints.

Unilateral constraints g(q, t) >= 0 are inequalities: a gas's walls and disk contacts cannot
all be closed at once, and need not be.  :func:`contact_dependence` takes each on its own with
the equality constraints: a contact that can never close (no configuration on the equality
constraints has g = 0) is inconsistent, one whose Jacobian row at a closed configuration is a
combination of the equality rows is redundant (its multiplier would not be determined).

>>> import sympy as sp
>>> from lagrangian.model import System, Holonomic
>>> x, y = sp.symbols("x y")
>>> system = System(coordinates=[x, y], constraints=[Holonomic(x - y), Holonomic(2*x - 2*y)])
>>> dependence(system).redundant
(1,)
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.constraints.pfaffian import PfaffianForm, pfaffian_form
from lagrangian.constraints.projection import SATISFIED, Projection, project
from lagrangian.errors import ConstraintError, Problem, raise_if_problems
from lagrangian.model import Holonomic, System, Unilateral, t
from lagrangian.model.constraints import label, statement
from lagrangian.symbolic.probe import SEED, PointFunction, numeric_rank, random_values, values_at


@dataclass(frozen=True)
class Dependence:
    """Where the constraints were probed, and which of the equality constraints (holonomic and
    velocity; unilateral ones are inequalities) are redundant.

    ``rows`` are the indices of the equality constraints in probing order (holonomic first);
    ``jacobian`` and ``rates`` are A and b at ``point`` for every constraint."""

    point: dict[sp.Symbol, float]
    rows: tuple[int, ...]
    redundant: tuple[int, ...]
    jacobian: np.ndarray
    rates: np.ndarray

    def rank_of(self, indices: list[int] | tuple[int, ...]) -> int:
        """Rank of the Jacobian rows of the constraints ``indices`` at the generic point."""
        return numeric_rank(self.jacobian[list(indices)]) if indices else 0


def equality_rows(system: System, active: bool = False) -> tuple[int, ...]:
    """Indices of the equality constraints, holonomic ones first (unilateral ones among them
    when ``active``)."""
    positional = ("holonomic", "unilateral") if active else ("holonomic",)
    kinds = [c.kind for c in system.constraints]
    holonomic = [i for i, k in enumerate(kinds) if k in positional]
    return (*holonomic, *(i for i, k in enumerate(kinds) if k == "velocity"))


def generic_point(system: System, active: bool = False) -> dict[sp.Symbol, float]:
    """Parameters at their defaults (random without one), t random, and the coordinates
    projected onto the holonomic constraints (and unilateral ones as g = 0 when ``active``);
    ConstraintError when no configuration fits."""
    return _generic_projection(system, active)[1].values


def _generic_projection(system: System, active: bool) -> tuple[list[int], Projection]:
    """:func:`generic_point` as the projection found, and the indices of the constraints
    projected onto (its rows)."""
    rng = random.Random(SEED)
    point = random_values([*system.coordinates, *system.parameters, t], rng)
    point.update({p: v for p, v in system.parameters.items() if v is not None})
    kinds = (Holonomic, Unilateral) if active else (Holonomic,)
    holonomic = [(i, c) for i, c in enumerate(system.constraints) if isinstance(c, kinds)]
    found = project([c.expression for _, c in holonomic], system.coordinates, point)
    if not found.satisfied:
        _raise_inconsistent(system, holonomic, found.residuals)
    return [i for i, _ in holonomic], found


def _raise_inconsistent(
    system: System, holonomic: list[tuple[int, Any]], residuals: tuple[float, ...]
) -> None:
    n, m = len(system.coordinates), len(system.constraints)
    problems = [
        Problem(
            f"constraints[{i}]",
            f"{statement(c)} cannot hold together with the others (least-squares residual {r:.3g})",
            "remove or correct one of the contradicting constraints",
        )
        for (i, c), r in zip(holonomic, residuals)
        if not abs(r) < SATISFIED
    ]
    count = f"more constraints ({m}) than coordinates ({n}) and " if m > n else ""
    raise_if_problems(
        problems,
        f"The constraints are inconsistent: {count}no configuration satisfies them",
        ConstraintError,
    )


def dependence(system: System, active: bool = False) -> Dependence:
    """Redundant equality constraints at a generic point; ConstraintError if inconsistent.
    With ``active`` the unilateral constraints count as equalities g = 0 (the multiplier form
    treats them as active)."""
    projected, found = _generic_projection(system, active)
    point = found.values
    coordinates = system.coordinates
    forms: list[PfaffianForm] = [pfaffian_form(c, coordinates) for c in system.constraints]
    # the rows a_j = dh_j/dq of the constraints projected onto were evaluated there last
    known = {} if found.jacobian is None else dict(zip(projected, found.jacobian))
    a, b = _jacobian_at(forms, coordinates, point, known)
    if a is None or b is None:
        raise ConstraintError(
            "The constraint Jacobian is not defined at a generic configuration; check the "
            "constraints for divisions by zero or square roots of negative numbers."
        )
    rows = equality_rows(system, active)
    redundant, inconsistent = [], []
    kept: list[int] = []
    # independent rows: every subset of them is (its singular values lie within the whole's),
    # so each row raises the rank, and one decomposition decides for all
    for i in rows if numeric_rank(a[list(rows)]) < len(rows) else ():
        if numeric_rank(a[[*kept, i]]) > len(kept):
            kept.append(i)
        elif numeric_rank(np.column_stack([a[[*kept, i]], b[[*kept, i]]])) > len(kept):
            inconsistent.append(i)
        else:
            redundant.append(i)
    if inconsistent:
        _raise_velocity_inconsistent(system, inconsistent, kept)
    return Dependence(point, rows, tuple(sorted(redundant)), a, b.ravel())


def contact_dependence(system: System, found: Dependence) -> tuple[int, ...]:
    """The unilateral constraints redundant in contact, each taken on its own with the
    equality constraints (``found``, their :func:`dependence`): g = 0 is projected onto from
    the equality constraints' generic point, and the contact is redundant when its Jacobian
    row there is a combination of the equality rows kept.  ConstraintError names the contacts
    that can never close (no configuration on the holonomic constraints has g = 0)."""
    coordinates = system.coordinates
    constraints = system.constraints
    if not any(isinstance(c, Unilateral) for c in constraints):
        return ()
    holonomic = [c.expression for c in constraints if isinstance(c, Holonomic)]
    kept = [i for i in found.rows if i not in found.redundant]
    kept_forms = [pfaffian_form(constraints[i], coordinates) for i in kept]
    redundant, unreachable = [], []
    for i, contact in enumerate(constraints):
        if not isinstance(contact, Unilateral):
            continue
        closed = project([*holonomic, contact.expression], coordinates, found.point)
        if not closed.satisfied:
            unreachable.append((i, closed.residuals[-1]))
            continue
        forms = [*kept_forms, pfaffian_form(contact, coordinates)]
        a, _ = _jacobian_at(forms, coordinates, closed.values)
        if a is not None and numeric_rank(a) <= len(kept):
            redundant.append(i)
    problems = [
        Problem(
            f"constraints[{i}]",
            f"{statement(constraints[i])} can never be in contact: no configuration "
            f"{'on the holonomic constraints ' if holonomic else ''}has it = 0 "
            f"(least-squares residual {r:.3g})",
            "correct the inequality, or remove it (it never acts)",
        )
        for i, r in unreachable
    ]
    raise_if_problems(problems, "A unilateral constraint can never close", ConstraintError)
    return tuple(redundant)


def _jacobian_at(
    forms: list[PfaffianForm],
    coordinates: Sequence[sp.Symbol],
    point: dict[sp.Symbol, float],
    known: Mapping[int, np.ndarray] | None = None,
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """A and b at ``point`` (None where not finite and real), each form's a_j and b_j
    evaluated in SymEngine (the images the form was converted from), but the rows a_j
    ``known`` at ``point`` (by form index).  What SymEngine cannot evaluate (the derivative
    of |u| SymPy leaves unevaluated) goes through
    :class:`~lagrangian.symbolic.probe.PointFunction`."""
    n = len(coordinates)
    known = known or {}
    # only the entries that can be non-zero are evaluated: a chain's rod involves four of
    # its 2n speeds, and the entries' substitution costs as much for a zero as for a term
    places, entries = [], []
    for j, form in enumerate(forms):
        fast = form.fast
        if j not in known:
            places += [j * (n + 1) + k for k, _ in fast.coefficients]
            entries += [a for _, a in fast.coefficients]
        places.append(j * (n + 1) + n)
        entries.append(fast.time_coefficient)
    try:
        found = values_at(entries, point)
    except ValueError:
        symbols = sorted(point, key=str)
        a = PointFunction(sp.Matrix([list(f.coefficients) for f in forms]), symbols)(point)
        b = PointFunction(sp.Matrix([f.time_coefficient for f in forms]), symbols)(point)
        return a, b
    if found is None:
        return None, None
    numbers = np.zeros((len(forms), n + 1))
    numbers.flat[places] = found
    for j, row in known.items():
        numbers[j, :-1] = row
    return numbers[:, :-1], numbers[:, -1:]


def _raise_velocity_inconsistent(system: System, bad: list[int], kept: list[int]) -> None:
    n, m = len(system.coordinates), len(system.constraints)
    others = ", ".join(label(i, system.constraints[i]) for i in kept)
    problems = [
        Problem(
            f"constraints[{i}]",
            f"{statement(system.constraints[i])} contradicts {others}: the velocities "
            "cannot satisfy them all",
            "remove or correct one of the contradicting constraints",
        )
        for i in bad
    ]
    count = f"more constraints ({m}) than coordinates ({n}) and " if m > n else ""
    raise_if_problems(
        problems,
        f"The constraints are inconsistent: {count}no velocity satisfies them",
        ConstraintError,
    )
