"""The energy function and the total energy of a System, expanded (Goldstein, Classical
Mechanics, 3rd ed., §2.7):

    h = sum_j q_dot_j dL/dq_dot_j - L,    T + V.

Each is the expansion of the expression written with the steps' momenta and T, V and U as
the equations show them (tidied), expanded in the backend and converted once
(:meth:`~lagrangian.derivation.terms.EulerLagrangeTerms.sympy_expanded`): a chain's h has
n^3/3 terms once its sums of masses are multiplied out, which SymPy's expand of the
products builds at a thousandth of the speed.  Each is computed once per System.
"""

from __future__ import annotations

import symengine as se
import sympy as sp

from lagrangian.derivation.steps import momenta
from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.model import System
from lagrangian.symbolic.caches import IdentityCache

_ENERGY_FUNCTIONS: IdentityCache[System, sp.Expr] = IdentityCache()
_TOTAL_ENERGIES: IdentityCache[System, sp.Expr] = IdentityCache()
_REST_POTENTIALS: IdentityCache[System, sp.Expr] = IdentityCache()


def energy_function(system: System) -> sp.Expr:
    """h = sum_j q_dot_j dL/dq_dot_j - L of ``system``, expanded.

    >>> import lagrangian as lg
    >>> energy_function(lg.examples.simple_pendulum())
    -g*l*m*cos(theta) + l**2*m*theta_dot**2/2
    """
    return _ENERGY_FUNCTIONS.get(system, _energy_function)


def kinetic_plus_potential(system: System) -> sp.Expr:
    """T + V of ``system``, expanded.

    >>> import lagrangian as lg
    >>> kinetic_plus_potential(lg.examples.simple_pendulum())
    -g*l*m*cos(theta) + l**2*m*theta_dot**2/2
    """
    return _TOTAL_ENERGIES.get(system, _kinetic_plus_potential)


def rest_potential(system: System) -> sp.Expr:
    """-L(q, 0, t) = V + U(q, 0, t) - T(q, 0, t) of ``system``, expanded: the potential whose
    stationary points are the equilibria (the pieces tidied, then every velocity 0).

    >>> import lagrangian as lg
    >>> rest_potential(lg.examples.double_pendulum())
    -g*l1*m1*cos(theta) - g*l1*m2*cos(theta) - g*l2*m2*cos(phi)
    """
    return _REST_POTENTIALS.get(system, _rest_potential)


def _energy_function(system: System) -> sp.Expr:
    terms = euler_lagrange_terms(system)
    asm, tidy = terms.assembly, terms.tidy
    lagrangian = (
        tidy(terms.kinetic.kinetic_energy) - tidy(asm.potential) - tidy(asm.velocity_potential)
    )
    work = se.Add(*[v * tidy(p) for v, p in zip(asm.q_dot, momenta(system))])
    return terms.sympy_expanded(work - lagrangian)


def _kinetic_plus_potential(system: System) -> sp.Expr:
    terms = euler_lagrange_terms(system)
    return terms.sympy_expanded(
        terms.tidy(terms.kinetic.kinetic_energy) + terms.tidy(terms.assembly.potential)
    )


def _rest_potential(system: System) -> sp.Expr:
    terms = euler_lagrange_terms(system)
    asm, tidy = terms.assembly, terms.tidy
    at_rest = {v: se.Integer(0) for v in asm.q_dot}
    kinetic, velocity_potential = (
        tidy(e).xreplace(at_rest) for e in (terms.kinetic.kinetic_energy, asm.velocity_potential)
    )
    return terms.sympy_expanded(tidy(asm.potential) + velocity_potential - kinetic)
