"""The System: everything a user says about a mechanical or electromechanical system.

A System is an immutable value (its mappings are read-only :class:`~lagrangian.symbolic.frozen.
FrozenMapping` s).  Its contributions add up (docs/architecture.md, "The model file"):
explicit energies T, V (or L directly), a velocity-dependent potential U, a Rayleigh
dissipation function F, generalized forces Q, particles and rigid bodies (planar or 3-D) under
uniform gravity, springs, dampers, applied forces and torques, circuit elements, and constraints.

Example:

>>> import sympy as sp
>>> from lagrangian.model import System, Particle
>>> m, g, l = sp.symbols("m g l")
>>> theta = sp.Symbol("theta")
>>> pendulum = System(
...     coordinates=[theta],
...     parameters={m: 1.0, g: 9.81, l: 1.0},
...     particles=[Particle("bob", m, (l * sp.sin(theta), -l * sp.cos(theta)))],
...     gravity=(0, -g),
... )
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, fields
from typing import Any

import sympy as sp

from lagrangian.errors import ModelError, Problem, raise_if_problems, require
from lagrangian.model.circuit import CircuitElement
from lagrangian.model.constraints import Constraint
from lagrangian.model.contact import RollingDisc
from lagrangian.model.elements import Damper, Force, Particle, RigidBody, Spring, Torque, as_tuple
from lagrangian.model.frames import Frame
from lagrangian.model.normalize import ELEMENT_FIELDS, normalize_system
from lagrangian.model.transitions import Transition
from lagrangian.symbolic.expressions import closest_name
from lagrangian.symbolic.frozen import FrozenMapping
from lagrangian.symbolic.symbols import acceleration, t, velocity
from lagrangian.symbolic.sympy_view import cycle_collection_paused


@dataclass(frozen=True)
class System:
    """A mechanical or electromechanical system described by energies and elements.

    Every field accepts what is convenient (lists, names, numbers); after construction the
    fields hold canonical values: tuples of SymPy Symbols and expressions, read-only mappings
    (parameter symbols to defaults, coordinates to forces, initial values, settings).  A
    System never changes: :meth:`replace` and :meth:`with_parameters` make new ones.

    Parameters
    ----------
    coordinates:
        Generalized coordinates: names, Symbols or time functions ``x(t)``.
    parameters:
        Parameter symbols (or names) with default values (``None`` for no default); a plain
        sequence of names declares parameters without values.
    kinetic, potential, lagrangian, velocity_potential, dissipation:
        Scalar expressions T(q, q_dot, t), V(q, t), L, U(q, q_dot, t) and F(q, q_dot, t).
        All given pieces add up: L = T - V - U + lagrangian.
    generalized_forces:
        Coordinate -> Q_j(q, q_dot, t), forces not derivable from a potential.
    gravity:
        Uniform field (components) acting on every particle and body.
    particles, rigid_bodies, springs, dampers, forces, torques, circuit:
        Elements, see :mod:`lagrangian.model.elements` and :mod:`lagrangian.model.circuit`.
    constraints:
        Holonomic h(q, t) = 0, velocity a(q, t).q_dot + b(q, t) = 0 and unilateral
        g(q, t) >= 0 constraints (:mod:`lagrangian.model.constraints`).  They are declarations:
        :func:`lagrangian.derive` gives the unconstrained equations, and
        :mod:`lagrangian.constraints` classifies, enforces and eliminates the constraints.
        The constraints of the ``rolling`` discs are added after them.
    frames:
        Massless reference frames (:class:`~lagrangian.model.frames.Frame`) that bodies and
        other frames may be oriented relative to (their ``parent``).
    rolling:
        Discs rolling without slipping on the plane z = 0
        (:class:`~lagrangian.model.contact.RollingDisc`): each adds its contact constraints.
    transitions:
        Jumps of the state where a guard crosses zero (a walker's heel strike,
        :class:`~lagrangian.model.transitions.Transition`), applied by the simulation.
    initial:
        Initial values of coordinates and velocities (``theta``, ``theta_dot``), for simulation.
    simulation:
        Default simulation settings (``t_end``, ``method``, ``rtol``, ``atol``, ``samples``).
    units:
        The unit of a parameter, a coordinate or the time ``t`` as free text (``{"l": "m",
        "theta": "rad"}``), shown on plot axes; at most :data:`UNIT_LENGTH` characters from
        :data:`UNIT_CHARACTERS`.  Nothing is converted: values stay as given.
    """

    coordinates: Sequence[Any]
    parameters: Mapping[Any, float | None] = field(default_factory=dict)
    kinetic: Any = sp.Integer(0)
    potential: Any = sp.Integer(0)
    lagrangian: Any = sp.Integer(0)
    velocity_potential: Any = sp.Integer(0)
    dissipation: Any = sp.Integer(0)
    generalized_forces: Mapping[Any, Any] = field(default_factory=dict)
    gravity: Sequence[Any] | None = None
    particles: Sequence[Particle] = ()
    rigid_bodies: Sequence[RigidBody] = ()
    springs: Sequence[Spring] = ()
    dampers: Sequence[Damper] = ()
    forces: Sequence[Force] = ()
    torques: Sequence[Torque] = ()
    circuit: Sequence[CircuitElement] = ()
    constraints: Sequence[Constraint] = ()
    frames: Sequence[Frame] = ()
    rolling: Sequence[RollingDisc] = ()
    transitions: Sequence[Transition] = ()
    initial: Mapping[Any, float] = field(default_factory=dict)
    simulation: Mapping[str, Any] = field(default_factory=dict)
    name: str = ""
    description: str = ""
    units: Mapping[Any, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name in ELEMENT_FIELDS:
                object.__setattr__(self, f.name, as_tuple(getattr(self, f.name)))
        # the checks and the rolling contacts make expressions by the thousand and free
        # none in cycles: Python's collector would walk everything SymPy made at import
        with cycle_collection_paused():
            normalized = normalize_system(self)
        for name, value in normalized.items():
            object.__setattr__(self, name, value)
        named = [*self.coordinates, *self.parameters, t]
        object.__setattr__(self, "units", checked_units(self.units, [s.name for s in named]))

    # -- vocabulary derived from the description (cheap, pure) --------------------------
    @property
    def velocities(self) -> tuple[sp.Symbol, ...]:
        """The generalized velocity symbols, ``theta_dot`` for ``theta``."""
        return tuple(velocity(q) for q in self.coordinates)

    @property
    def accelerations(self) -> tuple[sp.Symbol, ...]:
        """The generalized acceleration symbols, ``theta_ddot`` for ``theta``."""
        return tuple(acceleration(q) for q in self.coordinates)

    @property
    def time(self) -> sp.Symbol:
        """The time symbol ``t``."""
        return t

    @property
    def dimension(self) -> int:
        """Number of spatial components of positions (0 when there are no points)."""
        bodies: tuple[Particle | RigidBody, ...] = (*self.particles, *self.rigid_bodies)
        for item in bodies:
            return len(item.position)
        return len(self.gravity) if self.gravity else 0

    def points(self) -> dict[str, tuple[sp.Expr, ...]]:
        """Named points: particles, body centres of mass and the origin."""
        bodies: tuple[Particle | RigidBody, ...] = (*self.particles, *self.rigid_bodies)
        named = {p.name: tuple(p.position) for p in bodies}
        named.setdefault("origin", tuple(sp.Integer(0) for _ in range(self.dimension)))
        return named

    def replace(self, **changes: Any) -> System:
        """A copy with some fields changed (the System itself never changes); units of names
        the copy no longer has are dropped, unless ``units`` is given."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(changes)
        if "units" not in changes:
            kept = {str(s) for s in (*values["coordinates"], *_names(values["parameters"]), t)}
            values["units"] = {name: unit for name, unit in self.units.items() if name in kept}
        return System(**values)

    def with_parameters(self, values: Mapping[Any, float]) -> System:
        """A copy with new default values for some parameters (names or symbols)."""
        by_name = {p.name: p for p in self.parameters}
        new = dict(self.parameters)
        for key, value in values.items():
            new[by_name[str(key)]] = value
        return self.replace(parameters=new)


#: The longest unit text, and the characters a unit may use (letters of any alphabet, digits,
#: spaces and ``/ * ^ . · - + ( ) % °``): enough for "m/s^2" or "kg·m²", nothing that a plot,
#: a terminal or a web page would read as markup.
UNIT_LENGTH = 32
UNIT_CHARACTERS = re.compile(r"[^\W_]|[ /*^.·\-+()%°²³⁻¹µΩ]")


def checked_units(units: Any, names: Sequence[str]) -> FrozenMapping[str, str]:
    """``units`` (name or Symbol -> unit text) keyed by name and frozen; a ModelError naming
    every unknown name and every unit that is not short text of :data:`UNIT_CHARACTERS`.

    >>> dict(checked_units({sp.Symbol("l"): "m"}, ["l", "t"]))
    {'l': 'm'}
    >>> checked_units({"lenght": "m"}, ["length", "t"])
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: The units are not valid (1 problem):
      - units.lenght: 'lenght' is not a coordinate, parameter or t — did you mean 'length'?
    """
    if not isinstance(units, Mapping):
        fix = "give {'l': 'm', 'theta': 'rad'}"
        raise_if_problems(
            [Problem("units", f"{units!r} is not a mapping", fix)],
            "The units are not valid",
            ModelError,
        )
    problems, result = [], {}
    for key, unit in units.items():
        name = key.name if isinstance(key, sp.Symbol) else str(key)
        message = unit_problem(unit)
        if name not in names:
            close = closest_name(name, names)
            fix = f"did you mean {close!r}?" if close else "give units of: " + ", ".join(names)
            problems.append(
                Problem(f"units.{name}", f"{name!r} is not a coordinate, parameter or t", fix)
            )
        elif message is not None:
            problems.append(Problem(f"units.{name}", message, "write it as m, rad or m/s^2"))
        else:
            result[name] = unit
    raise_if_problems(problems, "The units are not valid", ModelError)
    return FrozenMapping(result)


def unit_problem(unit: Any) -> str | None:
    """What is wrong with ``unit`` as the text of a unit, or None.

    >>> unit_problem("m/s^2") is None, unit_problem("<b>")
    (True, "'<b>' has characters a unit does not use: <>")
    """
    if not isinstance(unit, str) or not unit.strip():
        return f"{unit!r} is not the text of a unit"
    if len(unit) > UNIT_LENGTH:
        return f"{unit[:UNIT_LENGTH]!r}... is longer than {UNIT_LENGTH} characters"
    odd = sorted({c for c in unit if not UNIT_CHARACTERS.fullmatch(c)})
    if odd:
        shown = "".join(odd).encode("unicode_escape").decode("ascii")  # a newline shown as \n
        return f"{unit!r} has characters a unit does not use: {shown}"
    return None


def _names(parameters: Any) -> list[Any]:
    return list(parameters) if isinstance(parameters, (Mapping, list, tuple)) else []


def require_system(value: Any, argument: str) -> System:
    """``value`` when it is a System; else an ArgumentError naming ``argument`` (as
    ``"classify(system)"``) and how to make one."""
    require(
        value,
        System,
        argument,
        "build one with lagrangian.System(...), lagrangian.load(path) or lagrangian.examples",
    )
    return value


def sequence_of_names(items: Iterable[Any] | str) -> Sequence[Any]:
    """A space/comma separated string or an iterable, as a list."""
    if isinstance(items, str):
        return items.replace(",", " ").split()
    return list(items)
