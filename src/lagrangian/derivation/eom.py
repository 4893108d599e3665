"""EquationsOfMotion: the immutable result of :func:`lagrangian.derive`.

Vocabulary (docs/architecture.md; the matrix form of a manipulator's equations, Murray, Li &
Sastry 1994, ch. 4):

    M(q,t) q_ddot + C(q,q_dot) q_dot + time_terms + G(q) = Q + dissipation_forces
                                                          + velocity_potential_forces
    M q_ddot = forcing

and the residual form of every equation, d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q = 0.

Every field is computed by :func:`lagrangian.derive`; the views that cost more (the pieces of
the forcing and the energies, the steps, the residuals, the Christoffel form of C, the solved
form, the regularity of M) are properties that call pure functions cached per object, so an
EquationsOfMotion never changes once made.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.derivation.solved import explicit_solution, mass_matrix_is_regular
from lagrangian.derivation.steps import Steps, coordinate_steps, equation_residuals
from lagrangian.derivation.terms import coriolis_matrix, matrix_piece
from lagrangian.errors import DerivationError
from lagrangian.model import System
from lagrangian.symbolic.caches import IdentityCache

_LAGRANGIANS: IdentityCache[System, sp.Expr] = IdentityCache()


@dataclass(frozen=True)
class EquationsOfMotion:
    """Euler–Lagrange equations of a System, in residual, matrix and step-by-step form.

    Attributes
    ----------
    coordinates, velocities, accelerations:
        Symbols q, q_dot, q_ddot.
    parameters:
        Parameter symbol -> default value (None for none), read-only.
    mass_matrix:
        M = d2T/dq_dot dq_dot^T (minus d2U/dq_dot2 when U is quadratic in the velocities).
    forcing:
        Q + dissipation_forces + velocity_potential_forces - coriolis - time_terms - gravity.
    coordinate_orders:
        2 for a coordinate with inertia, 1 for one with none whose equation holds its velocity
        (a charge through a resistor only), 0 for an algebraic one (read-only).
    system:
        The System these equations were derived from (its constraints, initial values and
        simulation settings are there).

    Properties (of :attr:`system`, computed once per System when first read)
    -----------------------------------------------------------------------
    kinetic_energy:
        T = 1/2 q_dot^T M q_dot + T1 + T0 (or the general T).
    potential_energy:
        V, every potential contribution (given V, gravity, springs, capacitors).
    velocity_potential:
        U(q, q_dot, t), the velocity-dependent potential.
    dissipation_function:
        F, the Rayleigh dissipation function (given F, dampers, resistors).
    coriolis:
        The vector C(q, q_dot) q_dot, C from the Christoffel symbols of M
        (:attr:`coriolis_matrix`, with dM/dt - 2C skew-symmetric).
    time_terms:
        What d/dt dT/dq_dot - dT/dq has besides M q_ddot + C q_dot: explicit time dependence
        (moving constraints) and the parts of T of degree 0 and 1 in the velocities.
    gravity:
        G = dV/dq (every potential force, not only gravity).
    generalized_forces:
        Applied Q_j (given, from forces at points by virtual work, torques, sources).
    dissipation_forces:
        -dF/dq_dot, the forces of the Rayleigh dissipation function.
    velocity_potential_forces:
        d/dt dU/dq_dot - dU/dq without its q_ddot part (which is in M).
    """

    coordinates: tuple[sp.Symbol, ...]
    velocities: tuple[sp.Symbol, ...]
    accelerations: tuple[sp.Symbol, ...]
    parameters: Mapping[sp.Symbol, float | None]
    time: sp.Symbol
    mass_matrix: sp.ImmutableMatrix
    forcing: sp.ImmutableMatrix
    coordinate_orders: Mapping[sp.Symbol, int]
    system: System
    name: str = ""

    @property
    def kinetic_energy(self) -> sp.Expr:
        """T = 1/2 q_dot^T M q_dot + T1 + T0 (or the general T)."""
        return matrix_piece(self.system, "kinetic_energy")

    @property
    def potential_energy(self) -> sp.Expr:
        """V, every potential contribution (given V, gravity, springs, capacitors)."""
        return matrix_piece(self.system, "potential_energy")

    @property
    def velocity_potential(self) -> sp.Expr:
        """U(q, q_dot, t), the velocity-dependent potential."""
        return matrix_piece(self.system, "velocity_potential")

    @property
    def dissipation_function(self) -> sp.Expr:
        """F, the Rayleigh dissipation function (given F, dampers, resistors)."""
        return matrix_piece(self.system, "dissipation_function")

    @property
    def coriolis(self) -> sp.ImmutableMatrix:
        """The vector C(q, q_dot) q_dot."""
        return matrix_piece(self.system, "coriolis")

    @property
    def time_terms(self) -> sp.ImmutableMatrix:
        """What d/dt dT/dq_dot - dT/dq has besides M q_ddot + C q_dot."""
        return matrix_piece(self.system, "time_terms")

    @property
    def gravity(self) -> sp.ImmutableMatrix:
        """G = dV/dq."""
        return matrix_piece(self.system, "gravity")

    @property
    def generalized_forces(self) -> sp.ImmutableMatrix:
        """Applied Q_j (given, from forces at points, torques, sources)."""
        return matrix_piece(self.system, "generalized_forces")

    @property
    def dissipation_forces(self) -> sp.ImmutableMatrix:
        """-dF/dq_dot."""
        return matrix_piece(self.system, "dissipation_forces")

    @property
    def velocity_potential_forces(self) -> sp.ImmutableMatrix:
        """d/dt dU/dq_dot - dU/dq without its q_ddot part."""
        return matrix_piece(self.system, "velocity_potential_forces")

    @property
    def lagrangian(self) -> sp.Expr:
        """L = T - V - U (made once per System: a long chain's has n^2 terms)."""
        return _LAGRANGIANS.get(self.system, lambda _: self._lagrangian())

    def _lagrangian(self) -> sp.Expr:
        return self.kinetic_energy - self.potential_energy - self.velocity_potential

    @property
    def mass_matrix_is_regular(self) -> bool:
        """True when every coordinate has inertia and M is generically invertible."""
        return mass_matrix_is_regular(self)

    @property
    def steps(self) -> Steps:
        """The derivation for each coordinate of :attr:`system`, step by step as by hand."""
        return coordinate_steps(self.system)

    @property
    def equations(self) -> sp.ImmutableMatrix:
        """Residuals d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q, each = 0 (from the steps)."""
        return equation_residuals(self.system)

    @property
    def coriolis_matrix(self) -> sp.ImmutableMatrix:
        """C with C_jk = sum_l Gamma_jkl q_dot_l, Gamma the Christoffel symbols of M."""
        return coriolis_matrix(self.system)

    @property
    def explicit(self) -> Mapping[sp.Symbol, sp.Expr]:
        """Solved form: q_ddot for second-order coordinates, q_dot for first-order ones."""
        return explicit_solution(self)

    @property
    def explicit_accelerations(self) -> sp.ImmutableMatrix:
        """q_ddot = M^-1 forcing (only when M is regular)."""
        if not self.mass_matrix_is_regular:
            raise DerivationError(
                "The mass matrix is singular, so there are no explicit accelerations: "
                f"coordinate orders {self.orders_by_name()}. Use .explicit for the solved "
                "first-order and second-order equations."
            )
        return sp.ImmutableMatrix([self.explicit[a] for a in self.accelerations])

    @property
    def algebraic_equations(self) -> tuple[sp.Expr, ...]:
        """Equations (= 0) of coordinates with neither inertia nor dissipation."""
        return tuple(
            self.forcing[j]
            for j, q in enumerate(self.coordinates)
            if self.coordinate_orders[q] == 0
        )

    def orders_by_name(self) -> dict[str, int]:
        """Coordinate name -> order (2 with inertia, 1 or 0 without)."""
        return {q.name: order for q, order in self.coordinate_orders.items()}

    def __repr__(self) -> str:
        names = ", ".join(q.name for q in self.coordinates)
        label = f"{self.name!r}, " if self.name else ""
        return f"EquationsOfMotion({label}coordinates=({names}))"
