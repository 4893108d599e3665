"""The derive layer: Euler–Lagrange equations from a System (matrix form, steps, Nielsen)."""

from lagrangian.derive.eom import EquationsOfMotion
from lagrangian.derive.lagrange import derive
from lagrangian.derive.nielsen import nielsen_equations
from lagrangian.derive.steps import CoordinateSteps

__all__ = ["CoordinateSteps", "EquationsOfMotion", "derive", "nielsen_equations"]
