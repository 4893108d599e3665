"""The derivation of each equation, step by step, as one writes it by hand:

dL/dq_dot_j,  d/dt (dL/dq_dot_j),  dL/dq_j,  dF/dq_dot_j,  Q_j,
and the equation  d/dt (dL/dq_dot_j) - dL/dq_j + dF/dq_dot_j - Q_j = 0.

L itself is differentiated here (not the matrix form), so the steps are an independent route
to the equations; they are computed on first request and once per System object.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.model import System
from lagrangian.model.identity_cache import IdentityCache
from lagrangian.model.symbols import velocity


@dataclass(frozen=True)
class CoordinateSteps:
    """The Euler–Lagrange derivation for one coordinate."""

    coordinate: sp.Symbol
    velocity: sp.Symbol
    dL_dvelocity: sp.Expr
    ddt_dL_dvelocity: sp.Expr
    dL_dcoordinate: sp.Expr
    dF_dvelocity: sp.Expr
    generalized_force: sp.Expr
    equation: sp.Expr

    @property
    def momentum(self) -> sp.Expr:
        """The conjugate momentum p_j = dL/dq_dot_j."""
        return self.dL_dvelocity


class Steps(tuple[CoordinateSteps, ...]):
    """The steps of every coordinate, in order: a tuple (after ``lg.render.register()``,
    or ``%load_ext lagrangian``, Jupyter typesets it)."""

    __slots__ = ()


_STEPS: IdentityCache[System, Steps] = IdentityCache()


def coordinate_steps(system: System) -> Steps:
    """The steps of every coordinate of ``system``, in order (computed once per System).

    >>> import lagrangian as lg
    >>> (step,) = coordinate_steps(lg.examples.simple_pendulum())
    >>> step.dL_dvelocity
    l**2*m*theta_dot
    """
    return _STEPS.get(system, _differentiate_lagrangian)


def _differentiate_lagrangian(system: System) -> Steps:
    terms = euler_lagrange_terms(system)
    asm, sympy = terms.assembly, terms.sympy
    lagrangian = terms.kinetic.kinetic_energy - asm.potential - asm.velocity_potential
    result = []
    for j, (q, v) in enumerate(zip(asm.q, asm.q_dot)):
        momentum = lagrangian.diff(v)
        rate = asm.time_derivative(momentum)
        slope = lagrangian.diff(q)
        friction = asm.dissipation.diff(v)
        coordinate = terms.coordinates[j]
        result.append(
            CoordinateSteps(
                coordinate=coordinate,
                velocity=velocity(coordinate),
                dL_dvelocity=sympy(momentum),
                ddt_dL_dvelocity=sympy(rate),
                dL_dcoordinate=sympy(slope),
                dF_dvelocity=sympy(friction),
                generalized_force=terms.view(asm.applied[j]),
                equation=sympy(rate - slope + friction - asm.applied[j]),
            )
        )
    return Steps(result)
