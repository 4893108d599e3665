"""The model layer: what a user says about a system (coordinates, parameters, energies,
elements) as immutable values, validated at the boundary."""

from lagrangian.model.circuit import (
    Capacitor,
    Inductor,
    MutualInductance,
    Resistor,
    VoltageSource,
)
from lagrangian.model.constraints import Holonomic, Unilateral, VelocityConstraint
from lagrangian.model.elements import Damper, Force, Particle, RigidBody, Spring, Torque
from lagrangian.model.symbols import acceleration, coordinates, from_time_functions, t, velocity
from lagrangian.model.system import System

__all__ = [
    "Capacitor",
    "Damper",
    "Force",
    "Holonomic",
    "Inductor",
    "MutualInductance",
    "Particle",
    "Resistor",
    "RigidBody",
    "Spring",
    "System",
    "Torque",
    "Unilateral",
    "VelocityConstraint",
    "VoltageSource",
    "acceleration",
    "coordinates",
    "from_time_functions",
    "t",
    "velocity",
]
