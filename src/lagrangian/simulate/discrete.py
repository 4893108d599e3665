"""The midpoint discrete Lagrangian shared by Hamilton's principle (:mod:`.action`) and the
variational integrator (:mod:`.variational`): L, dL/dq and dL/dq_dot compiled as NumPy
functions of (q, q_dot, t, p), and the convergence test of the discrete Euler–Lagrange
equations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagrangian.derive import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.model import System
from lagrangian.numerics.cache import IdentityCache
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulate.run import _description


@dataclass(frozen=True)
class LagrangianFunctions:
    """L, dL/dq and dL/dq_dot of one system as NumPy functions of (q, q_dot, t, p)."""

    lagrangian: NumericFunction
    dL_dq: NumericFunction
    dL_dq_dot: NumericFunction


_CACHE: IdentityCache[EquationsOfMotion, LagrangianFunctions] = IdentityCache()


def prepare(
    system_or_eom: System | EquationsOfMotion,
) -> tuple[CompiledEquations, LagrangianFunctions]:
    """The compiled equations (names, defaults, energy) and the compiled L of a system."""
    eom, _, _, system = _description(system_or_eom)
    if system is not None and system.constraints:
        # The action of the unconstrained L would be silently wrong.
        raise SimulationError(
            "The discrete action of a constrained system is not implemented yet: eliminate the "
            "holonomic constraints first (lagrangian.constraints.eliminate)."
        )
    return compile_equations(eom), _CACHE.get(eom, compile_lagrangian)


def compile_lagrangian(eom: EquationsOfMotion) -> LagrangianFunctions:
    q, qd, t, p = list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)
    lagrangian = eom.lagrangian
    unknown = sorted(s.name for s in lagrangian.free_symbols - {*q, *qd, t, *p})
    if unknown:
        raise SimulationError(
            f"The Lagrangian uses {', '.join(unknown)}, which are neither coordinates nor "
            "parameters: declare them as parameters of the System to give them values."
        )
    groups, n = (q, qd, t, p), len(q)
    return LagrangianFunctions(
        lagrangian=NumericFunction(groups, [lagrangian], ()),
        dL_dq=NumericFunction(groups, [sp.diff(lagrangian, s) for s in q], (n,)),
        dL_dq_dot=NumericFunction(groups, [sp.diff(lagrangian, s) for s in qd], (n,)),
    )


def residual_converged(terms: tuple[np.ndarray, np.ndarray]) -> tuple[bool, float]:
    """Whether the residual is at rounding level against its terms, and its largest value.

    hybr may report slow progress when the start is already the solution (a straight line
    for a free particle); the residual itself decides then.
    """
    worst = float(np.max(np.abs(terms[0] + terms[1]), initial=0.0))
    size = float(np.max(np.abs(np.concatenate(terms)), initial=0.0))
    return bool(np.isfinite(worst) and worst <= 1e-10 * size), worst
