"""The derivation layer: Euler–Lagrange equations from a System (matrix form, steps, Nielsen),
and the Newton–Euler equations of its bodies checked against them.  :func:`derive` remembers
the equations of the Systems it derived last (:func:`forget_derivations` drops them)."""

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.derivation.lagrange import derive, equations_of, forget_derivations
from lagrangian.derivation.newton_euler import (
    BodyEquations,
    NewtonEuler,
    NewtonEulerCheck,
    check_newton_euler,
    newton_euler,
)
from lagrangian.derivation.nielsen import nielsen_equations
from lagrangian.derivation.steps import CoordinateSteps

__all__ = [
    "BodyEquations",
    "CoordinateSteps",
    "EquationsOfMotion",
    "NewtonEuler",
    "NewtonEulerCheck",
    "check_newton_euler",
    "derive",
    "equations_of",
    "forget_derivations",
    "newton_euler",
    "nielsen_equations",
]
