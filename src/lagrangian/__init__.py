"""lagrangian — analytical mechanics, from energies to motion.

Describe a system by its generalized coordinates, energies, elements and forces; get its
Euler–Lagrange equations with every step, the matrix form M q_ddot = forcing, its constraints
classified and enforced, its conserved quantities, equilibria and modes, and its motion.

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> eom.equations[0]
g*l*m*sin(theta) + l**2*m*theta_ddot
>>> lg.classify(lg.examples.spherical_pendulum()).dof
2

Every name below loads on first use (PEP 562): ``import lagrangian`` itself imports neither
SymPy nor SciPy, so the command line starts at once.  In IPython or Jupyter,
``%load_ext lagrangian`` (or ``lg.render.register()``) typesets results as LaTeX.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from lagrangian import compiled
from lagrangian.errors import (
    AnalysisError,
    ArgumentError,
    ConstraintError,
    DerivationError,
    ExpressionError,
    LagrangianError,
    ModelError,
    OutputError,
    Problem,
    SimulationError,
    SimulationInputError,
    SizeLimitError,
    TimeLimitError,
)
from lagrangian.lazy_names import lazy_attribute

compiled.install()  # the modules compiled at install, while they match their source

if TYPE_CHECKING:
    from lagrangian import examples, io, render
    from lagrangian.analysis import AnalysisReport, analyze
    from lagrangian.constraints import (
        ConstrainedEquations,
        ConstraintReport,
        ReactionWrench,
        classify,
        constrained_equations,
        eliminate,
        particle_constraint_forces,
        project_state,
        reaction_wrenches,
    )
    from lagrangian.derivation import (
        CoordinateSteps,
        EquationsOfMotion,
        NewtonEuler,
        derive,
        newton_euler,
        nielsen_equations,
    )
    from lagrangian.io import load, loads
    from lagrangian.limits import time_limit
    from lagrangian.model import (
        Capacitor,
        Damper,
        Force,
        Frame,
        Holonomic,
        Inductor,
        MutualInductance,
        Particle,
        Resistor,
        RigidBody,
        RollingDisc,
        Spring,
        System,
        Torque,
        Transition,
        Unilateral,
        VelocityConstraint,
        VoltageSource,
        acceleration,
        coordinates,
        t,
        velocity,
    )
    from lagrangian.numerics.export import export
    from lagrangian.simulation import Batch, Event, Trajectory, simulate, simulate_batch
    from lagrangian.simulation.limit_cycle import LimitCycle, limit_cycle
    from lagrangian.simulation.poincare import PoincareSection, poincare_section
    from lagrangian.size_limits import size_limit
    from lagrangian.sweeps import SweepReport, sweep
    from lagrangian.web import serve

    __version__: str

#: The public package each lazily loaded name comes from (the names the TYPE_CHECKING block
#: imports, for type checkers).
_HOMES = {
    **dict.fromkeys(("AnalysisReport", "analyze"), "lagrangian.analysis"),
    **dict.fromkeys(
        (
            "ConstrainedEquations",
            "ConstraintReport",
            "ReactionWrench",
            "classify",
            "constrained_equations",
            "eliminate",
            "particle_constraint_forces",
            "project_state",
            "reaction_wrenches",
        ),
        "lagrangian.constraints",
    ),
    **dict.fromkeys(
        (
            "CoordinateSteps",
            "EquationsOfMotion",
            "NewtonEuler",
            "derive",
            "newton_euler",
            "nielsen_equations",
        ),
        "lagrangian.derivation",
    ),
    "load": "lagrangian.io",
    "loads": "lagrangian.io",
    "time_limit": "lagrangian.limits",
    "size_limit": "lagrangian.size_limits",
    "export": "lagrangian.numerics.export",
    **dict.fromkeys(
        (
            "Capacitor",
            "Damper",
            "Force",
            "Frame",
            "Holonomic",
            "Inductor",
            "MutualInductance",
            "Particle",
            "Resistor",
            "RigidBody",
            "RollingDisc",
            "Spring",
            "System",
            "Torque",
            "Transition",
            "Unilateral",
            "VelocityConstraint",
            "VoltageSource",
            "acceleration",
            "coordinates",
            "t",
            "velocity",
        ),
        "lagrangian.model",
    ),
    **dict.fromkeys(
        ("Batch", "Event", "Trajectory", "simulate", "simulate_batch"), "lagrangian.simulation"
    ),
    **dict.fromkeys(("LimitCycle", "limit_cycle"), "lagrangian.simulation.limit_cycle"),
    **dict.fromkeys(("PoincareSection", "poincare_section"), "lagrangian.simulation.poincare"),
    **dict.fromkeys(("SweepReport", "sweep"), "lagrangian.sweeps"),
    "serve": "lagrangian.web",
}
#: Subpackages reachable as attributes (``lg.examples.double_pendulum()``, ``lg.constraints``).
_SUBPACKAGES = (
    "analysis",
    "constraints",
    "derivation",
    "examples",
    "io",
    "model",
    "numerics",
    "render",
    "simulation",
    "sweeps",
)


def __getattr__(name: str) -> Any:
    if name in _SUBPACKAGES:
        return importlib.import_module(f"{__name__}.{name}")
    if name == "__version__":
        return _installed_version()
    return lazy_attribute(globals(), _HOMES, __name__, name)


def __dir__() -> list[str]:
    return sorted([*__all__, "__version__"])


def _installed_version() -> str:
    """The installed version of lagrangian (package metadata), or ``0+unknown`` when the
    package runs from a source tree that was never installed."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed_version

    try:
        return installed_version("lagrangian")
    except PackageNotFoundError:
        return "0+unknown"


def load_ipython_extension(ipython: Any) -> None:
    """``%load_ext lagrangian``: typeset equations, steps, systems and analyses as LaTeX and
    show trajectories as plots in this IPython session (:func:`lagrangian.render.register`)."""
    from lagrangian.render import register

    register(ipython)


__all__ = [
    "AnalysisError",
    "AnalysisReport",
    "ArgumentError",
    "Batch",
    "Capacitor",
    "ConstrainedEquations",
    "ConstraintError",
    "ConstraintReport",
    "CoordinateSteps",
    "Damper",
    "DerivationError",
    "EquationsOfMotion",
    "Event",
    "ExpressionError",
    "Force",
    "Frame",
    "Holonomic",
    "Inductor",
    "LagrangianError",
    "LimitCycle",
    "ModelError",
    "MutualInductance",
    "NewtonEuler",
    "OutputError",
    "Particle",
    "PoincareSection",
    "Problem",
    "ReactionWrench",
    "Resistor",
    "RigidBody",
    "RollingDisc",
    "SimulationError",
    "SimulationInputError",
    "SizeLimitError",
    "Spring",
    "SweepReport",
    "System",
    "TimeLimitError",
    "Torque",
    "Trajectory",
    "Transition",
    "Unilateral",
    "VelocityConstraint",
    "VoltageSource",
    "acceleration",
    "analyze",
    "classify",
    "constrained_equations",
    "coordinates",
    "derive",
    "eliminate",
    "examples",
    "export",
    "io",
    "limit_cycle",
    "load",
    "loads",
    "newton_euler",
    "nielsen_equations",
    "particle_constraint_forces",
    "poincare_section",
    "project_state",
    "reaction_wrenches",
    "render",
    "serve",
    "simulate",
    "simulate_batch",
    "size_limit",
    "sweep",
    "t",
    "time_limit",
    "velocity",
]
