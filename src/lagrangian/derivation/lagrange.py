"""derive(system) -> EquationsOfMotion: the Euler–Lagrange equations of a System.

    d/dt dL/dq_dot_j - dL/dq_j + dF/dq_dot_j = Q_j,    L = T - V - U    (seed 000, 001)

The matrix form is built from structure (Jacobians, Christoffel symbols) in SymEngine; the
step-by-step form differentiates L itself, lazily, when asked for.
"""

from __future__ import annotations

import random
from functools import cached_property

import symengine as se
import sympy as sp

from lagrangian.derivation.assemble import assemble
from lagrangian.derivation.backend import Backend, SympyView, depends_on
from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.derivation.kinetic import KineticForm, kinetic_form
from lagrangian.derivation.steps import CoordinateSteps
from lagrangian.derivation.trig import tidy
from lagrangian.model import System
from lagrangian.model.symbols import acceleration, t, velocity


def derive(system: System) -> EquationsOfMotion:
    """The equations of motion of ``system``.

    >>> import sympy as sp
    >>> from lagrangian.model import System
    >>> x, x_dot = sp.symbols("x x_dot"); m, k = sp.symbols("m k")
    >>> eom = derive(System(coordinates=[x], parameters=[m, k],
    ...                     kinetic=m * x_dot**2 / 2, potential=k * x**2 / 2))
    >>> eom.mass_matrix, eom.forcing
    (Matrix([[m]]), Matrix([[-k*x]]))
    """
    work = _Derivation(system)
    return EquationsOfMotion(
        coordinates=tuple(system.coordinates),
        velocities=system.velocities,
        accelerations=system.accelerations,
        parameters=dict(system.parameters),
        time=t,
        mass_matrix=work.view.symmetric_matrix(work.mass),
        forcing=work.view.vector(work.forcing),
        coordinate_orders=work.orders,
        name=system.name,
        _work=work,
    )


class _Derivation:
    """The backend pieces of one derivation, and what an EquationsOfMotion computes from them
    on demand (conversion to SymPy, steps, Christoffel matrix, solved form)."""

    def __init__(self, system: System) -> None:
        self.system = system
        self.asm = asm = assemble(system)
        self.kinetic: KineticForm = kinetic_form(asm)
        self.view = SympyView([*system.coordinates, *system.parameters, t])
        self.state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
        n = len(asm.q)
        u = asm.velocity_potential
        at_rest = {a: 0 for a in asm.q_ddot}
        self.velocity_potential_forces = [
            se.expand((asm.time_derivative(u.diff(v)) - u.diff(q)).subs(at_rest))
            for q, v in zip(asm.q, asm.q_dot)
        ]
        self.mass = self._mass_matrix()
        self.gravity = [asm.potential.diff(q) for q in asm.q]
        self.dissipation_forces = [se.expand(-asm.dissipation.diff(v)) for v in asm.q_dot]
        self.forcing = [
            self.tidy(
                asm.applied[j]
                + self.dissipation_forces[j]
                + self.velocity_potential_forces[j]
                - self.kinetic.coriolis[j]
                - self.kinetic.time_terms[j]
                - self.gravity[j]
            )
            for j in range(n)
        ]
        self.orders = self._orders()

    def _mass_matrix(self) -> list[list[Backend]]:
        """M = d2T/dq_dot2 - d2U/dq_dot2 (symmetric: each entry tidied once)."""
        asm, kinetic, n = self.asm, self.kinetic.mass_matrix, len(self.asm.q)
        u_momentum = [asm.velocity_potential.diff(v) for v in asm.q_dot]
        mass = [[se.Integer(0)] * n for _ in range(n)]
        for j in range(n):
            for k in range(j, n):
                entry = kinetic[j][k] - u_momentum[j].diff(asm.q_dot[k])
                mass[j][k] = mass[k][j] = self.tidy(entry)
        return mass

    def tidy(self, expr: Backend) -> Backend:
        return tidy(expr, self.state)

    def scalar(self, name: str) -> sp.Expr:
        expr = {
            "kinetic_energy": self.kinetic.kinetic_energy,
            "potential_energy": self.asm.potential,
            "velocity_potential": self.asm.velocity_potential,
            "dissipation_function": self.asm.dissipation,
        }[name]
        return self.view(self.tidy(expr))

    def vector(self, name: str) -> sp.ImmutableMatrix:
        values = {
            "coriolis": self.kinetic.coriolis,
            "time_terms": self.kinetic.time_terms,
            "gravity": self.gravity,
            "generalized_forces": self.asm.applied,
            "dissipation_forces": self.dissipation_forces,
            "velocity_potential_forces": self.velocity_potential_forces,
        }[name]
        return self.view.vector([self.tidy(v) for v in values])

    def _orders(self) -> dict[sp.Symbol, int]:
        """2 with inertia; without, 1 if the equation has velocities of such coordinates."""
        n = len(self.asm.q)
        inert = [j for j in range(n) if all(self.mass[j][k] == 0 for k in range(n))]
        inert_velocities = [self.asm.q_dot[j] for j in inert]
        orders = {}
        for j, q in enumerate(self.system.coordinates):
            if j not in inert:
                orders[q] = 2
            else:
                orders[q] = 1 if depends_on(self.forcing[j], inert_velocities) else 0
        return orders

    @cached_property
    def generic_rank(self) -> int:
        """Rank of M at a random point (parameters and state drawn at random)."""
        rng = random.Random(12345)
        symbols: set[Backend] = set()
        for row in self.mass:
            for e in row:
                symbols |= e.free_symbols
        values = {s: rng.uniform(0.5, 1.5) for s in symbols}
        numeric = sp.Matrix([[float(e.subs(values)) for e in row] for row in self.mass])
        return int(numeric.rank(iszerofunc=lambda x: abs(x) < 1e-10))

    def steps(self) -> tuple[CoordinateSteps, ...]:
        asm, view = self.asm, self.view
        lagrangian = self.kinetic.kinetic_energy - asm.potential - asm.velocity_potential
        result = []
        for j, (q, v) in enumerate(zip(asm.q, asm.q_dot)):
            momentum = lagrangian.diff(v)
            rate = asm.time_derivative(momentum)
            slope = lagrangian.diff(q)
            friction = asm.dissipation.diff(v)
            result.append(
                CoordinateSteps(
                    coordinate=self.system.coordinates[j],
                    velocity=velocity(self.system.coordinates[j]),
                    dL_dvelocity=view(self.tidy(momentum)),
                    ddt_dL_dvelocity=view(self.tidy(rate)),
                    dL_dcoordinate=view(self.tidy(slope)),
                    dF_dvelocity=view(self.tidy(friction)),
                    generalized_force=view(asm.applied[j]),
                    equation=view(self.tidy(rate - slope + friction - asm.applied[j])),
                )
            )
        return tuple(result)

    def coriolis_matrix(self) -> sp.ImmutableMatrix:
        asm, mass, n = self.asm, self.kinetic.mass_matrix, len(self.asm.q)
        rows = []
        for j in range(n):
            row = []
            for k in range(n):
                entry = se.Integer(0)
                for ell in range(n):
                    gamma = (
                        mass[j][k].diff(asm.q[ell])
                        + mass[j][ell].diff(asm.q[k])
                        - mass[k][ell].diff(asm.q[j])
                    ) / 2
                    entry += gamma * asm.q_dot[ell]
                row.append(self.tidy(entry))
            rows.append(row)
        return self.view.matrix(rows)

    def explicit(self) -> dict[sp.Symbol, sp.Expr]:
        """Solve M q_ddot = forcing (second order) and forcing = 0 for first-order velocities."""
        coords = self.system.coordinates
        second = [j for j, q in enumerate(coords) if self.orders[q] == 2]
        first = [j for j, q in enumerate(coords) if self.orders[q] == 1]
        forcing = [self.view(f) for f in self.forcing]
        solved: dict[sp.Symbol, sp.Expr] = {}
        if first:
            unknowns = [velocity(coords[j]) for j in first]
            a, b = sp.linear_eq_to_matrix([forcing[j] for j in first], unknowns)
            solved.update({u: sp.simplify(v) for u, v in zip(unknowns, a.LUsolve(b))})
            forcing = [f.xreplace(solved) for f in forcing]
        if second:
            mass = sp.Matrix([[self.view(self.mass[j][k]) for k in second] for j in second])
            values = _solve_linear(mass, sp.Matrix([forcing[j] for j in second]))
            solved.update({acceleration(coords[j]): v for j, v in zip(second, values)})
        return solved


def _solve_linear(mass: sp.Matrix, rhs: sp.Matrix) -> list[sp.Expr]:
    """M x = rhs; a diagonal M is divided directly, small ones solved by LU and simplified."""
    if mass.is_diagonal():
        return [sp.expand(rhs[i] / mass[i, i]) for i in range(mass.rows)]
    return [sp.simplify(v) if mass.rows <= 3 else v for v in mass.LUsolve(rhs)]
