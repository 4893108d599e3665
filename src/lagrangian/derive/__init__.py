"""The derive layer: Euler–Lagrange equations from a System (matrix form, steps, Nielsen), and
the Newton–Euler equations of its bodies checked against them."""

from lagrangian.derive.eom import EquationsOfMotion
from lagrangian.derive.lagrange import derive
from lagrangian.derive.newton_euler import (
    BodyEquations,
    NewtonEuler,
    NewtonEulerCheck,
    check_newton_euler,
    newton_euler,
)
from lagrangian.derive.nielsen import nielsen_equations
from lagrangian.derive.steps import CoordinateSteps

__all__ = [
    "BodyEquations",
    "CoordinateSteps",
    "EquationsOfMotion",
    "NewtonEuler",
    "NewtonEulerCheck",
    "check_newton_euler",
    "derive",
    "newton_euler",
    "nielsen_equations",
]
