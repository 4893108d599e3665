"""The derivation of each equation, step by step, as one writes it by hand:

dL/dq_dot_j,  d/dt (dL/dq_dot_j),  dL/dq_j,  dF/dq_dot_j,  Q_j,
and the equation  d/dt (dL/dq_dot_j) - dL/dq_j + dF/dq_dot_j - Q_j = 0.

L itself is differentiated here (not the matrix form), so the steps are an independent route
to the equations; they are computed on first request and once per System object, and shown
(converted to SymPy) only when asked for: the equations alone convert one expression per
coordinate, not six.
"""

from __future__ import annotations

from dataclasses import dataclass

import symengine as se
import sympy as sp

from lagrangian.derivation.backend import Backend
from lagrangian.derivation.terms import EulerLagrangeTerms, euler_lagrange_terms
from lagrangian.model import System
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.symbols import velocity


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
    return _STEPS.get(system, _show_steps)


_RESIDUALS: IdentityCache[System, sp.ImmutableMatrix] = IdentityCache()


def equation_residuals(system: System) -> sp.ImmutableMatrix:
    """The equation of each coordinate, d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q (each = 0),
    as the steps derive it; the steps themselves are shown (converted to SymPy) only when
    asked for (computed once per System).

    >>> import lagrangian as lg
    >>> equation_residuals(lg.examples.simple_pendulum())
    Matrix([[g*l*m*sin(theta) + l**2*m*theta_ddot]])
    """
    return _RESIDUALS.get(system, _convert_residuals)


@dataclass(frozen=True)
class _Derivatives:
    """One coordinate's steps in backend form, the equation tidied."""

    momentum: Backend
    rate: Backend
    slope: Backend
    friction: Backend
    equation: Backend


_DERIVATIVES: IdentityCache[System, list[_Derivatives]] = IdentityCache()


def _convert_residuals(system: System) -> sp.ImmutableMatrix:
    view = euler_lagrange_terms(system).view
    return view.vector([d.equation for d in _DERIVATIVES.get(system, _differentiate_lagrangian)])


_SHOWN_MOMENTA: IdentityCache[System, tuple[sp.Expr, ...]] = IdentityCache()
_SHOWN_SLOPES: IdentityCache[System, tuple[sp.Expr, ...]] = IdentityCache()


def step_momenta(system: System) -> tuple[sp.Expr, ...]:
    """dL/dq_dot_j of every coordinate as the steps show it (the first step), converted
    without the other steps: the analysis reads the momenta and dL/dq alone, and a long
    chain's d/dt dL/dq_dot has n^2 terms per coordinate to convert (once per System).

    >>> import lagrangian as lg
    >>> step_momenta(lg.examples.simple_pendulum())
    (l**2*m*theta_dot,)
    """
    return _SHOWN_MOMENTA.get(system, lambda s: _shown(s, momenta(s)))


def step_slopes(system: System) -> tuple[sp.Expr, ...]:
    """dL/dq_j of every coordinate as the steps show it (see :func:`step_momenta`)."""
    return _SHOWN_SLOPES.get(system, lambda s: _shown(s, slopes(s)))


def _shown(system: System, derivatives: list[Backend]) -> tuple[sp.Expr, ...]:
    sympy = euler_lagrange_terms(system).sympy
    return tuple(sympy(d) for d in derivatives)


def _show_steps(system: System) -> Steps:
    terms = euler_lagrange_terms(system)
    derivatives = _DERIVATIVES.get(system, _differentiate_lagrangian)
    sympy, applied = terms.sympy, terms.assembly.applied
    shown_momenta, shown_slopes = step_momenta(system), step_slopes(system)
    return Steps(
        CoordinateSteps(
            coordinate=coordinate,
            velocity=velocity(coordinate),
            dL_dvelocity=shown_momenta[j],
            ddt_dL_dvelocity=sympy(d.rate),
            dL_dcoordinate=shown_slopes[j],
            dF_dvelocity=sympy(d.friction),
            generalized_force=terms.view(applied[j]),
            equation=terms.view(d.equation),
        )
        for j, (coordinate, d) in enumerate(zip(terms.coordinates, derivatives))
    )


def momenta(system: System) -> list[Backend]:
    """dL/dq_dot_j of every coordinate of ``system`` in backend form, as the steps find it
    (before it is tidied; computed once per System): the steps' own when they are derived
    already, else L differentiated by the velocities alone (the same sums: the gradient
    adds each term's derivative by a symbol in the same order whichever other symbols it
    is asked for), without the equations the steps tidy."""
    return _first_derivatives(system, "momentum")


def slopes(system: System) -> list[Backend]:
    """dL/dq_j of every coordinate of ``system`` in backend form, as the steps find it (see
    :func:`momenta`): neither needs the time derivatives of the momenta, nor the tidied
    equations (n^2 terms each for a chain)."""
    return _first_derivatives(system, "slope")


#: L's gradients by the velocities ("momentum") or the coordinates ("slope") alone, per System.
_GRADIENTS: IdentityCache[System, dict[str, list[Backend]]] = IdentityCache()


def _first_derivatives(system: System, step: str) -> list[Backend]:
    derived = _DERIVATIVES.peek(system)
    if derived is not None:
        return [getattr(d, step) for d in derived]
    known = _GRADIENTS.get(system, lambda _: {})
    if step not in known:
        terms = euler_lagrange_terms(system)
        asm = terms.assembly
        symbols = asm.q_dot if step == "momentum" else asm.q
        known[step] = terms.gradient(_compressed_lagrangian(terms), list(symbols))
    return known[step]


def _compressed_lagrangian(terms: EulerLagrangeTerms) -> Backend:
    """L = T - V - U with its sums of parameters compressed
    (:meth:`~lagrangian.derivation.terms.EulerLagrangeTerms.compress`).

    V expanded: a chain's V = -g sum_i m_i y_i has its y_i = -(l_1 cos theta_1 + ...) as
    one factor, which every theta_k would otherwise differentiate whole."""
    asm = terms.assembly
    return terms.compress(
        terms.kinetic.kinetic_energy - se.expand(asm.potential) - asm.velocity_potential
    )


def _differentiate_lagrangian(system: System) -> list[_Derivatives]:
    terms = euler_lagrange_terms(system)
    asm = terms.assembly
    lagrangian = _compressed_lagrangian(terms)
    n = len(asm.q)
    # every partial derivative of L in one pass over its terms, not one pass per coordinate
    slopes = terms.gradient(lagrangian, [*asm.q, *asm.q_dot])
    frictions = terms.gradient(asm.dissipation, list(asm.q_dot))
    result = []
    for j in range(n):
        momentum, slope, friction = slopes[n + j], slopes[j], frictions[j]
        rate = terms.time_derivative(momentum)
        equation = terms.tidy_compressed(rate - slope + friction - asm.applied[j])
        result.append(_Derivatives(momentum, rate, slope, friction, equation))
    return result
