"""The Nielsen form of Lagrange's equations:

    Q_j = dT_dot/dq_dot_j - 2 dT/dq_j,

with T_dot = dT/dt the total time derivative (it contains the accelerations) and Q_j every
generalized force: -dV/dq_j, the applied forces, -dF/dq_dot_j and the forces of a
velocity-dependent potential, d/dt dU/dq_dot_j - dU/dq_j.  It is an independent route to the
same equations, used to check the Euler–Lagrange form.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from lagrangian.derivation.lagrange import equations_of
from lagrangian.symbolic.symbols import time_derivative


def nielsen_equations(subject: Any) -> sp.ImmutableMatrix:
    """Residuals dT_dot/dq_dot_j - 2 dT/dq_j - Q_j (each = 0), Q_j all generalized forces, of
    a System or its EquationsOfMotion.

    >>> import lagrangian as lg
    >>> eom = lg.derive(lg.examples.simple_pendulum())
    >>> nielsen_equations(eom)[0]
    g*l*m*sin(theta) + l**2*m*theta_ddot
    """
    eom = equations_of(subject, "nielsen_equations(subject)")
    kinetic = eom.kinetic_energy
    kinetic_rate = time_derivative(kinetic, eom.coordinates)
    u = eom.velocity_potential
    residuals = []
    for j, (q, v) in enumerate(zip(eom.coordinates, eom.velocities)):
        potential_force = -sp.diff(eom.potential_energy, q)
        u_force = time_derivative(sp.diff(u, v), eom.coordinates) - sp.diff(u, q)
        forces = potential_force + eom.generalized_forces[j] + eom.dissipation_forces[j] + u_force
        residuals.append(sp.expand(sp.diff(kinetic_rate, v) - 2 * sp.diff(kinetic, q) - forces))
    return sp.ImmutableMatrix(residuals)
