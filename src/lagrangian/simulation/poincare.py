"""Poincaré sections: the states where a motion crosses a surface G(q, q_dot, t) = 0.

Every crossing in the direction asked (``rising`` by default: G from negative to positive) is
an event of the run, located on the integrator's dense output to its tolerance
(:mod:`lagrangian.simulation.crossings`), not read off the output rows.  The points of the
section are the states there.  For a conservative system of two degrees of freedom at energy
E, the section x = 0 crossed with x_dot > 0 is a plane (y, y_dot): a regular orbit draws a
closed curve on it, a chaotic one scatters its points over an area (Hénon & Heiles,
*Astron. J.* 69, 1964; Lichtenberg & Lieberman, *Regular and Chaotic Dynamics*, 2nd ed.
1992, §1.2b).

>>> import lagrangian as lg
>>> section = poincare_section(lg.examples.henon_heiles(), "x", t_span=60.0)
>>> section.axes, len(section.t) > 5
(('y', 'y_dot'), True)
>>> bool(abs(section["x"]).max() < 1e-9)                 # every point is on x = 0
True
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, TextIO

import numpy as np

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.numerics.compile import compile_equations
from lagrangian.simulation.crossings import Crossing, section_crossing
from lagrangian.simulation.inputs import parameter_values
from lagrangian.simulation.run import simulate
from lagrangian.simulation.setup import describe_system
from lagrangian.simulation.trajectory import DOT, Trajectory, write_columns

if TYPE_CHECKING:
    from typing_extensions import Unpack

    from lagrangian.simulation.options import StepKeywords

#: The name of the section's events in ``Trajectory.events``.
SECTION_EVENT = "poincare"


@dataclasses.dataclass(frozen=True, eq=False)
class PoincareSection:
    """The crossings of the surface ``section`` = 0 in ``direction``: their times ``t``
    (shape (N,)) and the states there, ``points`` (shape (N, 2n), columns ``names``: the
    coordinates, then each ``NAME_dot``); ``axes``, the two columns a plot shows by default
    (the first coordinate the section does not involve and its velocity); the
    ``trajectory`` of the run, when the section was made by :func:`poincare_section`."""

    section: str
    direction: str
    t: np.ndarray
    points: np.ndarray
    names: tuple[str, ...]
    axes: tuple[str, str]
    trajectory: Trajectory | None = dataclasses.field(default=None, repr=False)

    def __getitem__(self, name: str) -> np.ndarray:
        """The column ``name`` (a coordinate or a ``NAME_dot``) at every point."""
        if name not in self.names:
            raise KeyError(f"{name!r} is not a column of the section; its columns: {self.names}")
        return np.asarray(self.points[:, self.names.index(name)])

    def to_csv(self, destination: str | os.PathLike[str] | TextIO) -> None:
        """Columns t, the coordinates and each ``NAME_dot``, one row a crossing (17
        significant digits); a file is written atomically."""
        data = np.column_stack((self.t, self.points)) if len(self.t) else None
        write_columns(destination, ("t", *self.names), data)

    def summary(self) -> str:
        """One line: how many crossings of which section."""
        plural = "point" if len(self.t) == 1 else "points"
        return f"{len(self.t)} Poincaré section {plural} ({self.section} = 0, {self.direction})"


def section_event(
    system_or_eom: System | EquationsOfMotion,
    section: Any,
    *,
    direction: str = "rising",
    parameters: Mapping[Any, float] | None = None,
    field: str = "section",
) -> Crossing:
    """The event function of the section ``section`` = 0 (text or SymPy: an expression of
    the coordinates, ``NAME_dot``, the parameters and t) for ``simulate(..., events=...)``,
    at the ``parameters`` over the System's; its events are named :data:`SECTION_EVENT`.
    ``field`` names the section in errors."""
    eom, _, _ = describe_system(system_or_eom)
    problems: list[Problem] = []
    values = parameter_values(compile_equations(eom), parameters or {}, problems)
    raise_if_problems(problems, "Cannot simulate", SimulationInputError)
    p = np.array([values[s.name] for s in eom.parameters], dtype=float)
    return section_crossing(eom, section, p, direction, name=SECTION_EVENT, field=field)


def section_of(
    trajectory: Trajectory, event: Crossing, section: Any, direction: str = "rising"
) -> PoincareSection:
    """The section of a run simulated with ``event`` (:func:`section_event`) among its
    events; ``section`` and ``direction`` as the event was made."""
    names = (*trajectory.coordinates, *(name + DOT for name in trajectory.coordinates))
    crossings = [e for e in trajectory.events if e.name == event.__name__]
    t = np.array([e.t for e in crossings], dtype=float)
    points = np.array([[e.state[name] for name in names] for e in crossings], dtype=float)
    return PoincareSection(
        str(section),
        direction,
        t,
        points.reshape(len(crossings), len(names)),
        names,
        default_axes(trajectory.coordinates, event),
    )


def default_axes(coordinates: Sequence[str], event: Crossing) -> tuple[str, str]:
    """The first coordinate the section's expression does not involve (itself or its
    velocity), else the first coordinate; with its velocity."""
    used = {s.name for s in event.traced.free_symbols} if event.traced is not None else set()
    free = [q for q in coordinates if q not in used and q + DOT not in used]
    chosen = (free or list(coordinates))[0]
    return chosen, chosen + DOT


def poincare_section(
    system_or_eom: System | EquationsOfMotion,
    section: Any,
    initial: Mapping[Any, float] | None = None,
    t_span: float | tuple[float, float] | None = None,
    *,
    direction: str = "rising",
    parameters: Mapping[Any, float] | None = None,
    **keywords: Unpack[StepKeywords],
) -> PoincareSection:
    """Simulate (:func:`lagrangian.simulate`, with ``initial``, ``t_span``, ``parameters``
    and the stepping keywords) and return the crossings of ``section`` = 0 in
    ``direction`` (module docstring), with the run's Trajectory.

    Raises ExpressionError or SimulationInputError for a section that is no expression of
    the state, and what simulate raises."""
    event = section_event(system_or_eom, section, direction=direction, parameters=parameters)
    trajectory = simulate(
        system_or_eom, initial, t_span, parameters=parameters, events=[event], **keywords
    )
    return dataclasses.replace(
        section_of(trajectory, event, section, direction), trajectory=trajectory
    )
