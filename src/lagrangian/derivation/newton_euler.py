"""The Newton–Euler equations of every body of a System, and their agreement with the
Euler–Lagrange equations (Murray, Li & Sastry 1994, ch. 4).

For each particle and rigid body, in the body frame at its centre of mass and in the spatial
frame (twists (v, omega), wrenches F = (f, tau), :mod:`lagrangian.derivation.body_frames`):

    d/dt (M^s V^s) = M^s V^s_dot - ad_{V^s}^T M^s V^s = F^s,
    M^b V^b_dot - ad_{V^b}^T M^b V^b = F^b     (m (v_dot + omega x v) = f,
                                                I omega_dot + omega x I omega = tau).

The applied wrench of a body gathers gravity, the forces applied at points that move with it
(F^s = (f, r x f) about the world origin, F^b = Ad^T F^s), its torques, and the forces of the
springs and dampers at its points.  Each equation is kept as its residual
M V_dot - ad_V^T M V - F, an expression of q, q_dot, q_ddot and t.

Projected on the coordinates with the twist Jacobians J_b = dV_b/dq_dot, the residuals give
the Euler–Lagrange equations: since dV/dq - d/dt dV/dq_dot = ad_V J (MLS94 ch. 4),

    sum_b J_b^T (M_b V_b_dot - ad^T M_b V_b - F_b) - Q_rest
        = d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q,

where Q_rest = Q - dV/dq - dF/dq_dot collects what the System gives on the coordinates
themselves (a potential, a dissipation function, generalized forces) rather than on a body.
:func:`check_newton_euler` shows this row by row.  Constraint forces are not in these
equations (as in :func:`lagrangian.derive`); :func:`lagrangian.constraints.reaction_wrenches`
gives them.

>>> import lagrangian as lg
>>> check_newton_euler(lg.examples.compound_pendulum()).agree
True
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.derivation.backend import to_backend
from lagrangian.derivation.body_frames import (
    BodyFrame,
    ad_twist,
    body_frames,
    fixed_in,
    point_wrench,
)
from lagrangian.derivation.lagrange import derive
from lagrangian.derivation.trig import combine_trig_matrix, combine_trig_sympy
from lagrangian.errors import DerivationError, Problem, raise_if_problems
from lagrangian.model import System
from lagrangian.model.elements import Damper, Spring
from lagrangian.model.system import require_system
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t, time_derivative, velocity

#: Size (operations) up to which a difference that trigonometric collection leaves is put
#: over one denominator, whose numerator is collected, before falling back to numbers.
SIMPLIFY_LIMIT = 400
#: Relative size of a numeric difference still counted as zero.
NUMERIC_TOLERANCE = 1e-9


@dataclass(frozen=True)
class BodyEquations:
    """The Newton–Euler equation of one body: its frame (twists, inertia, adjoint, twist
    Jacobians), its applied wrench F^b and F^s, and the residuals
    M^b V^b_dot - ad^T M^b V^b - F^b (``residual``) and the same in the spatial frame."""

    frame: BodyFrame
    wrench: sp.ImmutableMatrix
    spatial_wrench: sp.ImmutableMatrix
    residual: sp.ImmutableMatrix
    spatial_residual: sp.ImmutableMatrix

    @property
    def name(self) -> str:
        return self.frame.name


@dataclass(frozen=True)
class NewtonEuler:
    """The Newton–Euler equations of a System's bodies (see the module docstring).

    ``generalized_forces`` is Q_rest = Q - dV/dq - dF/dq_dot: what the System gives on the
    coordinates rather than on a body (zero when every force acts on a body).
    """

    coordinates: tuple[sp.Symbol, ...]
    velocities: tuple[sp.Symbol, ...]
    accelerations: tuple[sp.Symbol, ...]
    bodies: tuple[BodyEquations, ...]
    generalized_forces: sp.ImmutableMatrix

    def body(self, name: str) -> BodyEquations:
        """The equations of the body or particle ``name``."""
        for body in self.bodies:
            if body.name == name:
                return body
        known = ", ".join(b.name for b in self.bodies)
        raise KeyError(f"No body named {name!r}; the bodies are {known}.")

    def projected(self, spatial: bool = False) -> sp.ImmutableMatrix:
        """sum_b J_b^T residual_b - Q_rest, one row per coordinate (body frame, or spatial)."""
        total = -sp.Matrix(self.generalized_forces)
        for body in self.bodies:
            frame = body.frame
            J = frame.spatial_jacobian if spatial else frame.jacobian
            total += J.T * (body.spatial_residual if spatial else body.residual)
        return sp.ImmutableMatrix(total)


def newton_euler(system: System) -> NewtonEuler:
    """The Newton–Euler equation of every particle and rigid body of ``system``.

    Every inertia must sit in a particle or a rigid body: a kinetic energy, velocity-dependent
    potential or Lagrangian with velocities given as an expression, or a circuit, cannot be
    split among bodies, and DerivationError says so.  So does a force applied at a moving
    point that moves with no body.
    """
    require_system(system, "newton_euler(system)")
    _refuse_unsplittable(system)
    q = tuple(system.coordinates)
    frames = body_frames(system)
    loads = _spatial_loads(system, frames)
    bodies = tuple(_equations(frame, loads[frame.name], q) for frame in frames)
    return NewtonEuler(
        q, system.velocities, system.accelerations, bodies, _generalized_rest(system)
    )


def _equations(frame: BodyFrame, load: sp.MatrixBase, q: tuple[sp.Symbol, ...]) -> BodyEquations:
    """M V_dot - ad_V^T M V - F in the body and the spatial frame."""
    spatial_wrench = combine_trig_matrix(load)
    wrench = combine_trig_matrix(frame.adjoint.T * spatial_wrench)

    def residual(M: sp.MatrixBase, V: sp.MatrixBase, F: sp.MatrixBase) -> sp.ImmutableMatrix:
        V_dot = sp.Matrix(V).applyfunc(lambda e: time_derivative(e, q))
        return combine_trig_matrix(M * V_dot - ad_twist(frame.kind, V).T * M * V - F)

    return BodyEquations(
        frame,
        wrench,
        spatial_wrench,
        residual(frame.inertia, frame.twist, wrench),
        residual(frame.spatial_inertia, frame.spatial_twist, spatial_wrench),
    )


def _refuse_unsplittable(system: System) -> None:
    problems = []
    why = "the Newton–Euler equations need every inertia in a particle or a rigid body"
    if system.kinetic != 0:
        problems.append(Problem("kinetic", f"T is given as an expression; {why}", _BODIES))
    if system.velocity_potential != 0:
        fix = "give the velocity-dependent forces as forces at points"
        problems.append(Problem("velocity_potential", f"U cannot act on a body; {why}", fix))
    if _velocity_part(system) != 0:
        problems.append(Problem("lagrangian", f"L has velocity terms; {why}", _BODIES))
    if system.circuit:
        fix = "a circuit has no bodies; compare its equations with derive() alone"
        problems.append(Problem("circuit", "circuit elements are not bodies", fix))
    raise_if_problems(problems, "No Newton–Euler equations for this System", DerivationError)


_BODIES = "describe the masses as particles and rigid bodies"


def _velocity_part(system: System) -> sp.Expr:
    L = to_sympy(system.lagrangian)
    return sp.expand(L - L.xreplace({v: 0 for v in system.velocities}))


def _generalized_rest(system: System) -> sp.ImmutableMatrix:
    """Q_j - dV/dq_j - dF/dq_dot_j of the potential, dissipation and generalized forces given
    on the coordinates (L without velocities acts as -V)."""
    potential = to_sympy(system.potential) - to_sympy(system.lagrangian)
    rows = []
    for q in system.coordinates:
        given = to_sympy(system.generalized_forces.get(q, 0))
        rows.append(given - potential.diff(q) - to_sympy(system.dissipation).diff(velocity(q)))
    return sp.ImmutableMatrix([combine_trig_sympy(r) for r in rows])


# -- the applied wrenches ---------------------------------------------------------------------


def _spatial_loads(system: System, frames: Sequence[BodyFrame]) -> dict[str, sp.Matrix]:
    """Body name -> the sum of its applied spatial wrenches F^s."""
    q = tuple(system.coordinates)
    loads = {f.name: sp.zeros(len(f.twist), 1) for f in frames}
    by_name = {f.name: f for f in frames}
    named = system.points()
    problems: list[Problem] = []

    def push(field: str, ref: Any, force: Sequence[Any]) -> None:
        frame, point = _carrier(ref, by_name, named, q)
        if frame is not None:
            loads[frame.name] += point_wrench(frame.kind, point, force)
        elif any(to_sympy(x).free_symbols & {*q, t} for x in point):
            problems.append(_unattached(field, point))

    for frame in frames:
        if system.gravity is not None:
            push("gravity", frame.name, [frame.mass * g for g in system.gravity])
    for i, applied in enumerate(system.forces):
        push(f"forces[{i}].at", applied.at, applied.force)
    for field, ends in _pair_forces(system):
        for ref, pull in ends:
            push(field, ref, pull)
    for torque in system.torques:
        frame = by_name[torque.body]
        couple = [torque.torque] if frame.kind == "planar" else list(torque.torque)
        loads[frame.name] += sp.Matrix([0] * (len(frame.twist) - len(couple)) + couple)
    raise_if_problems(problems, "Some forces act on no body", DerivationError)
    return loads


def _carrier(
    ref: Any,
    frames: Mapping[str, BodyFrame],
    named: Mapping[str, tuple[sp.Expr, ...]],
    q: tuple[sp.Symbol, ...],
) -> tuple[BodyFrame | None, tuple[Any, ...]]:
    """The body a point belongs to (None: the ground) and the point's position."""
    if isinstance(ref, str):
        return frames.get(ref), named[ref]
    point = tuple(ref)
    for frame in frames.values():
        if len(frame.position) == len(point) and fixed_in(frame, point, q):
            return frame, point
    return None, point


def _unattached(field: str, point: Sequence[Any]) -> Problem:
    return Problem(
        field,
        f"the point {list(point)} moves but is fixed in no body, so its force acts on nothing "
        "the Newton–Euler equations know",
        "apply the force at a body's or particle's name, or at a point that moves with one body",
    )


def _pair_forces(system: System) -> list[tuple[str, list[tuple[Any, list[sp.Expr]]]]]:
    """(field, the forces on its two ends) of each spring and damper: f_b = -f_a along b - a,
    the gradients of 1/2 k (d - d0)^2 and of the Rayleigh function 1/2 c d_dot^2."""
    named = system.points()
    pairs = []
    elements: list[tuple[str, Spring | Damper]] = [
        (f"springs[{i}]", s) for i, s in enumerate(system.springs)
    ]
    elements += [(f"dampers[{i}]", d) for i, d in enumerate(system.dampers)]
    for field, element in elements:
        a, b = element.between
        ra, rb = (sp.Matrix(list(named[r] if isinstance(r, str) else r)) for r in (a, b))
        on_b = _pull(element, rb - ra, tuple(system.coordinates))
        pairs.append((f"{field}.between", [(a, list(-on_b)), (b, list(on_b))]))
    return pairs


def _pull(element: Spring | Damper, delta: sp.Matrix, q: tuple[sp.Symbol, ...]) -> sp.Matrix:
    """The force of a spring or damper on its end b, delta = r_b - r_a (signed in 1-D)."""
    if isinstance(element, Spring):
        k, rest = element.stiffness, element.rest_length
        if len(delta) == 1:
            return -k * (delta - sp.Matrix([rest]))
        length = sp.sqrt(delta.dot(delta))
        return -k * delta if rest == 0 else -k * (length - rest) * delta / length
    rate = delta.applyfunc(lambda e: time_derivative(e, q))
    c = element.coefficient
    return -c * rate if len(delta) == 1 else -c * delta.dot(rate) * delta / delta.dot(delta)


# -- the check against the Euler–Lagrange equations -------------------------------------------


@dataclass(frozen=True)
class NewtonEulerCheck:
    """Row by row: the Euler–Lagrange residual of each coordinate against the projected
    Newton–Euler residuals.

    ``difference`` is lagrange - newton_euler after trigonometric collection (zero where
    they agree symbolically); ``methods`` says how each row was decided: ``"symbolic"``
    (the difference collects to 0) or ``"numeric"`` (it does not: compared at
    ``samples`` random points of q, q_dot, q_ddot, t and the parameters, to 1e-9 relative).
    """

    coordinates: tuple[sp.Symbol, ...]
    lagrange: sp.ImmutableMatrix
    newton_euler: sp.ImmutableMatrix
    difference: sp.ImmutableMatrix
    agrees: tuple[bool, ...]
    methods: tuple[str, ...]
    frame: str
    samples: int

    @property
    def agree(self) -> bool:
        """True when every row agrees."""
        return all(self.agrees)

    def summary(self) -> str:
        """One line per coordinate: agrees (and how) or the difference."""
        lines = []
        for q, ok, how, d in zip(self.coordinates, self.agrees, self.methods, self.difference):
            verdict = f"agree ({how})" if ok else f"differ by {d}"
            lines.append(f"{q}: Euler–Lagrange and Newton–Euler ({self.frame} frame) {verdict}")
        return "\n".join(lines)


def check_newton_euler(
    system: System, *, frame: str = "body", samples: int = 5, seed: int = 0
) -> NewtonEulerCheck:
    """Project the Newton–Euler residuals of ``system`` on its coordinates and compare them
    with its Euler–Lagrange residuals (:attr:`lagrangian.EquationsOfMotion.equations`).

    ``frame`` is ``"body"`` or ``"spatial"`` (the same result: J^s = Ad J^b and
    F^s = Ad^-T F^b).  A row whose difference trigonometric collection (and, when small,
    cancelling over one denominator) does not bring to 0 is compared numerically at
    ``samples`` random points; :attr:`NewtonEulerCheck.methods` says which rows were.
    """
    if frame not in ("body", "spatial"):
        raise ValueError(f"frame must be 'body' or 'spatial', not {frame!r}")
    projected = newton_euler(system).projected(spatial=frame == "spatial")
    lagrange = derive(system).equations
    return compare_residuals(system, lagrange, projected, frame=frame, samples=samples, seed=seed)


def compare_residuals(
    system: System,
    lagrange: Sequence[sp.Expr],
    projected: Sequence[sp.Expr],
    *,
    frame: str = "body",
    samples: int = 5,
    seed: int = 0,
) -> NewtonEulerCheck:
    """Row by row, whether two residual vectors of ``system``'s coordinates are equal:
    symbolically when their difference collects to 0, else at ``samples`` random points
    (what :func:`check_newton_euler` does with the Euler–Lagrange and the projected
    Newton–Euler residuals)."""
    rows = [_compare(a, b, system, samples, seed) for a, b in zip(lagrange, projected)]
    return NewtonEulerCheck(
        tuple(system.coordinates),
        sp.ImmutableMatrix(list(lagrange)),
        sp.ImmutableMatrix(list(projected)),
        sp.ImmutableMatrix([d for d, _, _ in rows]),
        tuple(ok for _, ok, _ in rows),
        tuple(how for _, _, how in rows),
        frame,
        samples,
    )


def _compare(
    lagrange: sp.Expr, projected: sp.Expr, system: System, samples: int, seed: int
) -> tuple[sp.Expr, bool, str]:
    difference = combine_trig_sympy(lagrange - projected)
    if difference == 0:
        return difference, True, "symbolic"
    if sp.count_ops(difference) <= SIMPLIFY_LIMIT:
        numerator, _ = sp.fraction(sp.together(difference))
        if combine_trig_sympy(numerator) == 0:
            return sp.Integer(0), True, "symbolic"
    rng = random.Random(seed)
    rows = [to_backend(e) for e in (difference, lagrange, projected)]
    compared = 0
    for _ in range(samples):
        values = _at(rows, _random_point(system, rng))
        if values is None:
            continue
        compared += 1
        scale = max(1.0, float(np.max(np.abs(values[1:]))))
        if abs(values[0]) > NUMERIC_TOLERANCE * scale:
            return difference, False, "numeric"
    return difference, compared > 0, "numeric"


def _at(rows: Sequence[Any], point: Mapping[sp.Symbol, float]) -> np.ndarray | None:
    """The values of backend expressions at ``point`` (None when one is not a finite real)."""
    swap = {to_backend(s): v for s, v in point.items()}
    try:
        values = np.array([complex(e.subs(swap)) for e in rows])
    except (TypeError, ValueError, RuntimeError, ZeroDivisionError):
        return None
    if not np.all(np.isfinite(values)) or np.max(np.abs(values.imag)) > 1e-12:
        return None
    return values.real


def _random_point(system: System, rng: random.Random) -> dict[sp.Symbol, float]:
    point: dict[sp.Symbol, float] = {s: rng.uniform(0.5, 1.5) for s in system.parameters}
    point.update({q: rng.uniform(-1.2, 1.2) for q in system.coordinates})
    rates = (*system.velocities, *system.accelerations)
    point.update({v: rng.uniform(-2.0, 2.0) for v in rates})
    point[t] = rng.uniform(0.0, 2.0)
    return point
