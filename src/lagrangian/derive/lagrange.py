"""derive(system) -> EquationsOfMotion: the Euler–Lagrange equations of a System.

    d/dt dL/dq_dot_j - dL/dq_j + dF/dq_dot_j = Q_j,    L = T - V - U    (seed 000, 001)

The matrix form is built from structure (Jacobians, Christoffel symbols) in SymEngine; the
step-by-step form differentiates L itself, lazily, when asked for.
"""

from __future__ import annotations

import random

import symengine as se
import sympy as sp

from lagrangian.derive.assemble import Assembly, assemble
from lagrangian.derive.backend import Backend, SympyView, depends_on
from lagrangian.derive.eom import EquationsOfMotion
from lagrangian.derive.kinetic import KineticForm, kinetic_form
from lagrangian.derive.steps import CoordinateSteps
from lagrangian.derive.trig import combine_trig
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
    asm = assemble(system)
    kinetic = kinetic_form(asm)
    view = SympyView([*system.coordinates, *system.parameters, t])
    n = len(asm.q)
    rest = {a: 0 for a in asm.q_ddot}
    u_hessian = [[asm.velocity_potential.diff(a).diff(b) for b in asm.q_dot] for a in asm.q_dot]
    u_forces = [
        se.expand((asm.time_derivative(asm.velocity_potential.diff(v))
                   - asm.velocity_potential.diff(q)).subs(rest))
        for q, v in zip(asm.q, asm.q_dot)
    ]
    mass = [[combine_trig(kinetic.mass_matrix[j][k] - u_hessian[j][k]) for k in range(n)]
            for j in range(n)]
    gravity = [combine_trig(asm.potential.diff(q)) for q in asm.q]
    dissipation = [se.expand(-asm.dissipation.diff(v)) for v in asm.q_dot]
    forcing = [
        combine_trig(asm.applied[j] + dissipation[j] + u_forces[j] - kinetic.coriolis[j]
                     - kinetic.time_terms[j] - gravity[j])
        for j in range(n)
    ]
    work = _Derivation(system, asm, kinetic, view, mass, forcing)
    return EquationsOfMotion(
        coordinates=system.coordinates,
        velocities=system.velocities,
        accelerations=system.accelerations,
        parameters=dict(system.parameters),
        time=t,
        kinetic_energy=view(kinetic.kinetic_energy),
        potential_energy=view(asm.potential),
        velocity_potential=view(asm.velocity_potential),
        dissipation_function=view(asm.dissipation),
        mass_matrix=view.matrix(mass),
        coriolis=view.vector(kinetic.coriolis),
        time_terms=view.vector(kinetic.time_terms),
        gravity=view.vector(gravity),
        generalized_forces=view.vector(asm.applied),
        dissipation_forces=view.vector(dissipation),
        velocity_potential_forces=view.vector(u_forces),
        forcing=view.vector(forcing),
        coordinate_orders=work.orders,
        name=system.name,
        _work=work,
    )


class _Derivation:
    """Backend state an EquationsOfMotion keeps for what it computes on demand."""

    def __init__(self, system: System, asm: Assembly, kinetic: KineticForm, view: SympyView,
                 mass: list[list[Backend]], forcing: list[Backend]) -> None:
        self.system, self.asm, self.kinetic, self.view = system, asm, kinetic, view
        self.mass, self.forcing = mass, forcing
        self.orders = self._orders()
        self.generic_rank = self._generic_rank()

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

    def _generic_rank(self) -> int:
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
            equation = combine_trig(rate - slope + friction - asm.applied[j])
            result.append(CoordinateSteps(
                coordinate=self.system.coordinates[j],
                velocity=velocity(self.system.coordinates[j]),
                dL_dvelocity=view(combine_trig(momentum)),
                ddt_dL_dvelocity=view(combine_trig(rate)),
                dL_dcoordinate=view(combine_trig(slope)),
                dF_dvelocity=view(se.expand(friction)),
                generalized_force=view(asm.applied[j]),
                equation=view(equation),
            ))
        return tuple(result)

    def coriolis_matrix(self) -> sp.ImmutableMatrix:
        asm, mass, n = self.asm, self.kinetic.mass_matrix, len(self.asm.q)
        rows = []
        for j in range(n):
            row = []
            for k in range(n):
                entry = se.Integer(0)
                for ell in range(n):
                    gamma = (mass[j][k].diff(asm.q[ell]) + mass[j][ell].diff(asm.q[k])
                             - mass[k][ell].diff(asm.q[j])) / 2
                    entry += gamma * asm.q_dot[ell]
                row.append(combine_trig(entry))
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
            system_ = [forcing[j] for j in first]
            a, b = sp.linear_eq_to_matrix(system_, unknowns)
            values = a.LUsolve(b)
            solved.update({u: sp.simplify(v) for u, v in zip(unknowns, values)})
            forcing = [f.xreplace(solved) for f in forcing]
        if second:
            mass = sp.Matrix([[self.view(self.mass[j][k]) for k in second] for j in second])
            rhs = sp.Matrix([forcing[j] for j in second])
            values = _solve_linear(mass, rhs)
            solved.update({acceleration(coords[j]): v for j, v in zip(second, values)})
        return solved


def _solve_linear(mass: sp.Matrix, rhs: sp.Matrix) -> list[sp.Expr]:
    """M x = rhs; a diagonal M is divided directly, small ones solved by LU."""
    if mass.is_diagonal():
        return [sp.expand(rhs[i] / mass[i, i]) for i in range(mass.rows)]
    return [sp.simplify(v) if mass.rows <= 3 else v for v in mass.LUsolve(rhs)]
