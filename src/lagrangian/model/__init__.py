"""The model layer: what a user says about a system (coordinates, parameters, energies,
elements) as immutable values, validated at the boundary.

3-D rigid bodies: :mod:`lagrangian.model.rotation` (orientations, angular velocities),
:mod:`lagrangian.model.twist` (poses, twists, the adjoint) and :mod:`lagrangian.model.inertia`
(shapes, parallel axes, combination, the 6x6 generalized inertia); the names most used are
exported here.
"""

from lagrangian.model import inertia, rotation, twist
from lagrangian.model.circuit import (
    Capacitor,
    Inductor,
    MutualInductance,
    Resistor,
    VoltageSource,
)
from lagrangian.model.constraints import Holonomic, Unilateral, VelocityConstraint
from lagrangian.model.contact import RollingDisc, rolling_sphere
from lagrangian.model.elements import Damper, Force, Particle, RigidBody, Spring, Torque
from lagrangian.model.frames import Frame
from lagrangian.model.inertia import Shape, shape
from lagrangian.model.rotation import (
    Orientation,
    axis_angle,
    body_angular_velocity,
    euler_rotation,
    quaternion_rotation,
    rotation_sequence,
    spatial_angular_velocity,
)
from lagrangian.model.system import System
from lagrangian.model.transitions import Transition
from lagrangian.symbolic.symbols import acceleration, coordinates, from_time_functions, t, velocity

__all__ = [
    "Capacitor",
    "Damper",
    "Force",
    "Frame",
    "Holonomic",
    "Inductor",
    "MutualInductance",
    "Orientation",
    "Particle",
    "Resistor",
    "RigidBody",
    "RollingDisc",
    "Shape",
    "Spring",
    "System",
    "Torque",
    "Transition",
    "Unilateral",
    "VelocityConstraint",
    "VoltageSource",
    "acceleration",
    "axis_angle",
    "body_angular_velocity",
    "coordinates",
    "euler_rotation",
    "from_time_functions",
    "inertia",
    "quaternion_rotation",
    "rolling_sphere",
    "rotation",
    "rotation_sequence",
    "shape",
    "spatial_angular_velocity",
    "t",
    "twist",
    "velocity",
]
