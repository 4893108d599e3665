"""The wrench the constraints exert on each body: the reactions at pins, rods and joints
(the Newton–Euler equations give the constraint forces that Lagrange's eliminate; Murray, Li
& Sastry 1994, ch. 4).

With the constraints enforced by multipliers the generalized constraint force is A^T lambda
(:mod:`lagrangian.constraints.multipliers`).  When every body moves by coordinates of its own
(maximal coordinates: a particle at (x, y[, z]), a planar body at its centre and angle, a 3-D
body at its centre and three angles) the virtual work of the constraint wrench F_b on the
body's virtual twist J_b dq is the part of (A^T lambda) . dq on its coordinates, so

    J_b^T F_b = (A^T lambda)_b,    F_b = J_b^-T (A^T lambda)_b,

J_b = dV_b/dq_dot the body twist Jacobian on the body's coordinates (square,
:mod:`lagrangian.derivation.body_frames`).  F_b = (f_b, tau_b) is in body axes about the centre of
mass; in world axes the force is f = R f_b and the moment about the centre tau = R tau_b.  This
extends :func:`lagrangian.constraints.particle_constraint_forces` (Cartesian particles, where
J_b = 1) to bodies.

A rod pinned at the origin, its centre at (x, y) = (l/2)(sin th, -cos th):

>>> import lagrangian as lg, sympy as sp
>>> x, y, th, m, l = sp.symbols("x y theta m l")
>>> rod = lg.RigidBody("rod", m, m * l**2 / 12, (x, y), th)
>>> pinned = lg.System(coordinates=[x, y, th], parameters={m: 1.0, l: 1.0}, rigid_bodies=[rod],
...     constraints=[lg.Holonomic(x - l * sp.sin(th) / 2), lg.Holonomic(y + l * sp.cos(th) / 2)])
>>> state = {"x": 0, "y": -0.5, "theta": 0, "x_dot": 1, "y_dot": 0, "theta_dot": 2}
>>> reaction_wrenches(pinned, state)["rod"].force.round(6)  # m (l/2) theta_dot^2 up the rod
array([0., 2.])
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.constraints.multipliers import ConstrainedEquations, constrained_equations
from lagrangian.derivation.body_frames import BodyFrame, body_frames
from lagrangian.errors import ConstraintError, Problem, raise_if_problems
from lagrangian.model import System
from lagrangian.model.rotation import evaluate_matrix
from lagrangian.model.system import require_system
from lagrangian.symbolic.symbols import name_of, t


@dataclass(frozen=True)
class ReactionWrench:
    """The constraint wrench on one body, at one state (1-D arrays) or along a trajectory
    (one row per output time).

    ``wrench`` is F_b = (f_b, tau_b) in body axes about the centre of mass (a particle's is
    its force); ``force`` the force in world axes; ``torque`` the moment about the centre in
    world axes (a number per row in the plane, None for a particle).
    """

    body: str
    kind: str
    wrench: np.ndarray
    force: np.ndarray
    torque: np.ndarray | None


def reaction_wrenches(
    system: System, state: Any, *, parameters: Mapping[Any, float] | None = None
) -> dict[str, ReactionWrench]:
    """Body name -> the wrench the constraints of ``system`` exert on it.

    ``state`` is one state — coordinates, ``NAME_dot``, optionally ``t``, parameters and the
    multipliers ``lambda_j``, by name or symbol — or a Trajectory of a constrained simulation
    (its recorded multipliers are used).  Multipliers not given are solved from
    [[M, -A^T], [A, 0]] [q_ddot; lambda] = [forcing; gamma] at the state.  ``parameters``
    override the defaults.

    Raises ConstraintError when a body does not move by coordinates of its own.
    """
    require_system(system, "reaction_wrenches(system, state)")
    frames = body_frames(system)
    columns = _own_columns(system, frames)
    equations = constrained_equations(system)
    rows = _rows(state)
    base = {s: v for s, v in system.parameters.items() if v is not None}
    base.update(_by_symbol(parameters or {}, system))
    per_body: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray | None]]] = {
        f.name: [] for f in frames
    }
    augmented = (equations.augmented_matrix, equations.augmented_rhs)
    for row in rows:
        values = {**base, **_by_symbol(row, system, equations)}
        values.setdefault(t, 0.0)
        generalized = _generalized_constraint_force(equations, augmented, values)
        for frame in frames:
            per_body[frame.name].append(_wrench(frame, columns[frame.name], generalized, values))
    single = not _is_trajectory(state)
    return {f.name: _stack(f, per_body[f.name], single) for f in frames}


def _own_columns(system: System, frames: tuple[BodyFrame, ...]) -> dict[str, list[int]]:
    """Body name -> the indices of the coordinates that move it, checked to be its own and
    as many as its twist has components."""
    used = {
        f.name: [k for k in range(f.jacobian.cols) if any(e != 0 for e in f.jacobian[:, k])]
        for f in frames
    }
    kinds = {"particle": "particle", "planar": "planar body", "rigid": "3-D body"}
    problems = []
    for i, f in enumerate(frames):
        shared = [
            system.coordinates[k].name
            for k in used[f.name]
            if any(k in used[g.name] for g in frames if g is not f)
        ]
        if not shared and len(used[f.name]) == len(f.twist):
            continue
        have = ", ".join(system.coordinates[k].name for k in used[f.name]) or "none"
        why = f"moves by {len(used[f.name])} coordinates ({have}), not {len(f.twist)}"
        if shared:
            why = f"shares {', '.join(shared)} with other bodies"
        problems.append(
            Problem(
                _field(system, i),
                f"{kinds[f.kind]} {f.name!r} {why}",
                "give every body coordinates of its own (its centre's position and its "
                "angles: maximal coordinates) and tie them with constraints",
            )
        )
    raise_if_problems(problems, "The reaction wrenches are not defined", ConstraintError)
    return used


def _field(system: System, index: int) -> str:
    """The field of the ``index``-th frame of :func:`body_frames` (particles, then bodies)."""
    count = len(system.particles)
    return f"particles[{index}]" if index < count else f"rigid_bodies[{index - count}]"


def _is_trajectory(state: Any) -> bool:
    return all(hasattr(state, name) for name in ("t", "q", "q_dot", "coordinates"))


def _rows(state: Any) -> list[dict[str, float]]:
    """One mapping name -> value per state."""
    if not _is_trajectory(state):
        return [{name_of(k): float(v) for k, v in dict(state).items()}]
    names = list(state.coordinates)
    multipliers = tuple(getattr(state, "multiplier_names", ()))
    lam = getattr(state, "multipliers", None)
    rows = []
    for i, time in enumerate(state.t):
        row = {"t": float(time), **dict(getattr(state, "parameters", {}))}
        row.update(zip(names, map(float, state.q[i])))
        row.update((n + "_dot", float(v)) for n, v in zip(names, state.q_dot[i]))
        if lam is not None:
            row.update(zip(multipliers, map(float, lam[i])))
        rows.append(row)
    return rows


def _by_symbol(
    values: Mapping[Any, Any], system: System, equations: ConstrainedEquations | None = None
) -> dict[sp.Symbol, float]:
    """Values by the system's symbols (coordinates, velocities, parameters, t, multipliers);
    unknown names are refused."""
    known = {s.name: s for s in (*system.coordinates, *system.velocities, *system.parameters)}
    known["t"] = t
    if equations is not None:
        known.update((s.name, s) for s in equations.multipliers)
    unknown = sorted(name_of(k) for k in values if name_of(k) not in known)
    if unknown:
        raise ConstraintError(
            f"The state names {', '.join(unknown)}, which are not coordinates, velocities, "
            "parameters, t or multipliers of this system."
        )
    return {known[name_of(k)]: float(v) for k, v in values.items()}


def _generalized_constraint_force(
    equations: ConstrainedEquations,
    augmented: tuple[sp.ImmutableMatrix, sp.ImmutableMatrix],
    values: dict[sp.Symbol, float],
) -> np.ndarray:
    """A^T lambda at ``values``; lambda solved from the augmented system when not given."""
    missing = [s for s in (*equations.coordinates, *equations.velocities) if s not in values]
    if missing:
        names = ", ".join(s.name for s in missing)
        raise ConstraintError(
            f"The state has no value for {names}: give every coordinate and velocity (NAME_dot)."
        )
    A = _numbers(equations.constraint_jacobian, values, "the constraint Jacobian")
    if all(lam in values for lam in equations.multipliers):
        lam = np.array([values[s] for s in equations.multipliers])
    else:
        matrix = _numbers(augmented[0], values, "the mass matrix")
        rhs = _numbers(augmented[1], values, "the forcing")
        try:
            solution = np.linalg.solve(matrix, rhs[:, 0])
        except np.linalg.LinAlgError:
            raise ConstraintError(
                "The multipliers are not determined at this state: [[M, -A^T], [A, 0]] is "
                "singular there (a singular configuration of the coordinates)."
            ) from None
        lam = solution[len(equations.coordinates) :]
    return A.T @ lam


def _numbers(matrix: sp.MatrixBase, values: dict[sp.Symbol, float], what: str) -> np.ndarray:
    result = evaluate_matrix(matrix, values)
    if result is None:
        unknown = sorted(s.name for s in matrix.free_symbols if s not in values)
        detail = f"no value for {', '.join(unknown)}" if unknown else "not finite there"
        raise ConstraintError(f"Cannot evaluate {what} at the state: {detail}.")
    return result


def _wrench(
    frame: BodyFrame, columns: list[int], generalized: np.ndarray, values: dict[sp.Symbol, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(F_b, f in world axes, moment about the centre in world axes) of one body."""
    J = _numbers(frame.jacobian[:, columns], values, f"the twist of {frame.name}")
    R = _numbers(frame.rotation, values, f"the orientation of {frame.name}")
    try:
        wrench = np.linalg.solve(J.T, generalized[columns])
    except np.linalg.LinAlgError:
        raise ConstraintError(
            f"The twist Jacobian of {frame.name!r} is singular at this state (its angles are "
            "at a singular configuration, such as gimbal lock)."
        ) from None
    d = R.shape[0]
    if frame.kind == "particle":
        return wrench, wrench, None
    torque = wrench[d:] if frame.kind == "rigid" else wrench[d]
    return wrench, R @ wrench[:d], (R @ torque if frame.kind == "rigid" else np.asarray(torque))


def _stack(
    frame: BodyFrame,
    rows: list[tuple[np.ndarray, np.ndarray, np.ndarray | None]],
    single: bool,
) -> ReactionWrench:
    """The rows of one body as arrays (the first row alone for a single state)."""
    wrench, force = (np.array([r[i] for r in rows]) for i in range(2))
    torque = None if frame.kind == "particle" else np.array([r[2] for r in rows])
    if single:
        wrench, force = wrench[0], force[0]
        torque = None if torque is None else torque[0]
    return ReactionWrench(frame.name, frame.kind, wrench, force, torque)
