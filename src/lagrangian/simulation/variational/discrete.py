"""The midpoint discrete Lagrangian of Hamilton's principle (:mod:`.action`): L, dL/dq and
dL/dq_dot compiled as NumPy functions of (q, q_dot, t, p)
(:func:`lagrangian.numerics.discrete_lagrangian.compile_lagrangian`, which also compiles what
the variational integrator of :mod:`.variational` needs), and the convergence test of the
discrete Euler–Lagrange equations.
"""

from __future__ import annotations

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.model import System
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.discrete_lagrangian import LagrangianFunctions, compile_lagrangian
from lagrangian.simulation.setup import describe_system


def prepare(
    system_or_eom: System | EquationsOfMotion,
) -> tuple[CompiledEquations, LagrangianFunctions]:
    """The compiled equations (names, defaults, energy) and the compiled L of a system."""
    eom, system, _ = describe_system(system_or_eom)
    if system.constraints:
        # The action of the unconstrained L would be silently wrong.
        raise SimulationInputError(
            "The discrete action of a constrained system is not implemented yet: eliminate the "
            "holonomic constraints first (lagrangian.constraints.eliminate)."
        )
    return compile_equations(eom), compile_lagrangian(eom)


def residual_converged(terms: tuple[np.ndarray, np.ndarray]) -> tuple[bool, float]:
    """Whether the residual is at rounding level against its terms, and its largest value.

    hybr may report slow progress when the start is already the solution (a straight line
    for a free particle); the residual itself decides then.
    """
    worst = float(np.max(np.abs(terms[0] + terms[1]), initial=0.0))
    size = float(np.max(np.abs(np.concatenate(terms)), initial=0.0))
    return bool(np.isfinite(worst) and worst <= 1e-10 * size), worst
