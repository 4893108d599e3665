"""lagrangian — analytical mechanics, from energies to motion.

Describe a system by its generalized coordinates, energies, elements and forces; get its
Euler–Lagrange equations with every step, the matrix form M q_ddot = forcing, and more.

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> eom.equations[0]
g*l*m*sin(theta) + l**2*m*theta_ddot
"""

from lagrangian import examples, io, render
from lagrangian.analysis import analyze
from lagrangian.derivation import (
    CoordinateSteps,
    EquationsOfMotion,
    check_newton_euler,
    derive,
    newton_euler,
    nielsen_equations,
)
from lagrangian.errors import (
    AnalysisError,
    ConstraintError,
    DerivationError,
    ExpressionError,
    LagrangianError,
    ModelError,
    SimulationError,
)
from lagrangian.io import load
from lagrangian.model import (
    Capacitor,
    Damper,
    Force,
    Holonomic,
    Inductor,
    MutualInductance,
    Particle,
    Resistor,
    RigidBody,
    Spring,
    System,
    Torque,
    Unilateral,
    VelocityConstraint,
    VoltageSource,
    acceleration,
    coordinates,
    t,
    velocity,
)
from lagrangian.simulation import Batch, Trajectory, simulate, simulate_batch

__version__ = "0.1.0"

if "IPython" in __import__("sys").modules:  # inside IPython/Jupyter: typeset results
    render.register()

__all__ = [
    "AnalysisError",
    "Batch",
    "Capacitor",
    "ConstraintError",
    "CoordinateSteps",
    "Damper",
    "DerivationError",
    "EquationsOfMotion",
    "ExpressionError",
    "Force",
    "Holonomic",
    "Inductor",
    "LagrangianError",
    "ModelError",
    "MutualInductance",
    "Particle",
    "Resistor",
    "RigidBody",
    "SimulationError",
    "Spring",
    "System",
    "Torque",
    "Trajectory",
    "Unilateral",
    "VelocityConstraint",
    "VoltageSource",
    "acceleration",
    "analyze",
    "check_newton_euler",
    "coordinates",
    "derive",
    "examples",
    "io",
    "load",
    "newton_euler",
    "nielsen_equations",
    "render",
    "simulate",
    "simulate_batch",
    "t",
    "velocity",
]
