"""The Euler–Lagrange terms of a System in the fast backend (SymEngine), computed once per
System object and shared by :func:`lagrangian.derive` and the views it offers on demand (the
steps, the Christoffel form of C).

    M = d2T/dq_dot2 - d2U/dq_dot2,    G = dV/dq,    -dF/dq_dot,
    velocity-potential forces = d/dt dU/dq_dot - dU/dq  (without their q_ddot part),
    forcing = Q - dF/dq_dot + (U forces) - C q_dot - time terms - G.

Every expression is tidied once (:func:`lagrangian.derivation.trig.combine_and_collect`) and
converted to SymPy through one :class:`~lagrangian.derivation.backend.SympyView`, whose memo
makes the shared subexpressions of M, the forcing and the steps one SymPy object each.

``derive`` converts M and the forcing; the pieces the forcing is the sum of (C q_dot, G, the
time terms, ...) and the energies are converted when first read (:func:`matrix_piece`,
each once per System): a simulation reads none of them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import symengine as se
import sympy as sp

from lagrangian.derivation.assemble import Assembly, assemble
from lagrangian.derivation.backend import Backend, SympyView
from lagrangian.derivation.collect import collect_state
from lagrangian.derivation.kinetic import KineticForm, kinetic_form
from lagrangian.derivation.trig import combine_and_collect
from lagrangian.model import System
from lagrangian.model.identity_cache import IdentityCache
from lagrangian.model.probe import depends_on
from lagrangian.model.symbols import t

#: Kept while their System lives; they hold backend expressions, never the System itself.
_TERMS: IdentityCache[System, EulerLagrangeTerms] = IdentityCache()


def euler_lagrange_terms(system: System) -> EulerLagrangeTerms:
    """The backend terms of ``system``, computed once per System object."""
    return _TERMS.get(system, EulerLagrangeTerms)


class EulerLagrangeTerms:
    """M, the force vectors, the forcing and the coordinate orders of one System, in backend
    form and tidied; :meth:`sympy` converts any of them for the user."""

    def __init__(self, system: System) -> None:
        self.coordinates: tuple[sp.Symbol, ...] = tuple(system.coordinates)
        self.assembly: Assembly = assemble(system)
        self.kinetic: KineticForm = kinetic_form(self.assembly)
        self.view = SympyView([*system.coordinates, *system.parameters, t])
        asm = self.assembly
        self.state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
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
            for j in range(len(asm.q))
        ]
        self.orders = self._orders()

    def tidy(self, expr: Backend) -> Backend:
        """Trigonometric products combined, terms grouped by state monomial (a single term,
        which neither can shorten, as it is: most entries of a mass matrix)."""
        if not expr.is_Add and not any(arg.is_Add for arg in expr.args):
            return expr
        return combine_and_collect(expr, self.state)

    def collect(self, expr: Backend) -> Backend:
        """The terms of an expression whose trigonometric products are combined already
        grouped by state monomial."""
        return collect_state(expr, self.state) if expr.is_Add else expr

    def sympy(self, expr: Backend) -> sp.Expr:
        """``expr`` tidied and in SymPy, with the System's own symbols."""
        return self.view(self.tidy(expr))

    def sympy_vector(self, values: list[Backend]) -> sp.ImmutableMatrix:
        """Every entry tidied, as a SymPy column."""
        return self.view.vector([self.tidy(v) for v in values])

    def _mass_matrix(self) -> list[list[Backend]]:
        """M = d2T/dq_dot2 - d2U/dq_dot2 (symmetric: each entry tidied once)."""
        asm, kinetic, n = self.assembly, self.kinetic.mass_matrix, len(self.assembly.q)
        u_momentum = [asm.velocity_potential.diff(v) for v in asm.q_dot]
        mass = [[se.Integer(0)] * n for _ in range(n)]
        for j in range(n):
            for k in range(j, n):
                u_part = u_momentum[j].diff(asm.q_dot[k])
                if u_part == 0 and self.kinetic.quadratic:  # combined already (kinetic_form)
                    mass[j][k] = mass[k][j] = self.collect(kinetic[j][k])
                else:
                    mass[j][k] = mass[k][j] = self.tidy(kinetic[j][k] - u_part)
        return mass

    def _orders(self) -> dict[sp.Symbol, int]:
        """2 with inertia; without, 1 if the equation has velocities of such coordinates."""
        n = len(self.coordinates)
        inert = [j for j in range(n) if all(self.mass[j][k] == 0 for k in range(n))]
        inert_velocities = [self.assembly.q_dot[j] for j in inert]
        orders = {}
        for j, q in enumerate(self.coordinates):
            if j not in inert:
                orders[q] = 2
            else:
                orders[q] = 1 if depends_on(self.forcing[j], inert_velocities) else 0
        return orders


#: How each piece of :func:`matrix_piece` is made from the backend terms.
PIECES: dict[str, Callable[[EulerLagrangeTerms], sp.Basic]] = {
    "kinetic_energy": lambda terms: terms.sympy(terms.kinetic.kinetic_energy),
    "potential_energy": lambda terms: terms.sympy(terms.assembly.potential),
    "velocity_potential": lambda terms: terms.sympy(terms.assembly.velocity_potential),
    "dissipation_function": lambda terms: terms.sympy(terms.assembly.dissipation),
    "coriolis": lambda terms: terms.sympy_vector(terms.kinetic.coriolis),
    "time_terms": lambda terms: terms.sympy_vector(terms.kinetic.time_terms),
    "gravity": lambda terms: terms.sympy_vector(terms.gravity),
    "generalized_forces": lambda terms: terms.sympy_vector(list(terms.assembly.applied)),
    "dissipation_forces": lambda terms: terms.sympy_vector(terms.dissipation_forces),
    "velocity_potential_forces": lambda terms: terms.sympy_vector(terms.velocity_potential_forces),
}

_PIECES: IdentityCache[System, dict[str, sp.Basic]] = IdentityCache()


def matrix_piece(system: System, name: str) -> Any:
    """One of T, V, U, F (``"kinetic_energy"``, ...) or of the vectors whose sum is the
    forcing (``"coriolis"``, ``"gravity"``, ...; the keys of :data:`PIECES`) of ``system``
    in SymPy, tidied; each computed once per System, when first asked for."""
    pieces = _PIECES.get(system, lambda _: {})
    if name not in pieces:
        pieces[name] = PIECES[name](euler_lagrange_terms(system))
    return pieces[name]


_CORIOLIS_MATRICES: IdentityCache[System, sp.ImmutableMatrix] = IdentityCache()


def coriolis_matrix(system: System) -> sp.ImmutableMatrix:
    """C with C_jk = sum_l Gamma_jkl q_dot_l, Gamma_jkl = (dM_jk/dq_l + dM_jl/dq_k -
    dM_kl/dq_j) / 2 the Christoffel symbols of the kinetic M; computed once per System."""
    return _CORIOLIS_MATRICES.get(system, _christoffel_form)


def _christoffel_form(system: System) -> sp.ImmutableMatrix:
    terms = euler_lagrange_terms(system)
    asm, mass, n = terms.assembly, terms.kinetic.mass_matrix, len(terms.coordinates)
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
            row.append(terms.tidy(entry))
        rows.append(row)
    return terms.view.matrix(rows)
