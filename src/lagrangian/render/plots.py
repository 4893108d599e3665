"""Plots of a Trajectory with matplotlib: time series, phase portraits, energy drift.

matplotlib is imported only when a plot is made (it keeps ``import lagrangian`` fast).  Without an
``ax`` each function draws on a new :class:`matplotlib.figure.Figure` (no pyplot state);
every function returns the Axes it drew on.  Names are shown as letters (``θ``, ``θ̇``), with
their units when ``units`` gives them (a model's ``units:`` section, ``System.units``; a
rate's unit is the unit over the time's, ``rad/s``).  The energy drift is

    (E(t) - E(t_0)) / |E(t_0)|      (E(t) - E(t_0) when E(t_0) = 0)

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=50)
>>> plot_phase_portrait(trajectory, "theta", units={"theta": "rad"}).get_ylabel()
'θ̇ [rad/s]'
"""

from __future__ import annotations

import io
import os
import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from lagrangian.model import System
from lagrangian.render.text import DOT, label
from lagrangian.simulation.trajectory import Trajectory
from lagrangian.symbolic.symbols import DOT_SUFFIX

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def column_label(name: str, units: Mapping[str, str] | None = None) -> str:
    """How a plot names the column ``name``: Greek words as letters, a rate with its dot, and
    the unit in brackets when ``units`` gives it (a rate's: the unit per unit of time).

    >>> column_label("theta_dot", {"theta": "rad"}), column_label("x", {"x": "m"})
    ('θ̇ [rad/s]', 'x [m]')
    >>> column_label("v_dot", {"v": "m/s", "t": "ms"}), column_label("energy")
    ('v̇ [(m/s)/ms]', 'energy')
    """
    unit = column_unit(name, units)
    return f"{_letters(name)} [{unit}]" if unit is not None else _letters(name)


def column_unit(name: str, units: Mapping[str, str] | None = None) -> str | None:
    """The unit of column ``name`` from ``units`` (``NAME_dot``: NAME's per the time's), or
    None when it has none."""
    units = units or {}
    base = name.removesuffix(DOT_SUFFIX)
    if base == name:
        return units.get(name)
    unit = units.get(base)
    return None if unit is None else per_time(unit, units.get("t", "s"))


def _letters(name: str) -> str:
    base = name.removesuffix(DOT_SUFFIX)
    return label(sp.Symbol(base), DOT) if base != name else label(sp.Symbol(name))


def per_time(unit: str, time: str = "s") -> str:
    """``unit`` per ``time``: ``rad/s``; a compound unit in parentheses, ``(m/s)/s``."""

    def grouped(text: str) -> str:
        return f"({text})" if any(c in text for c in " /*·") else text

    return f"{grouped(unit)}/{grouped(time)}"


def time_label(units: Mapping[str, str] | None = None) -> str:
    """The time axis: ``t``, or ``t [s]`` when the model gives units (the unit of ``t`` if it
    names one; the model's values are SI otherwise)."""
    return f"t [{units.get('t', 's')}]" if units else "t"


def plot_time_series(
    trajectory: Trajectory,
    names: Sequence[str] | None = None,
    ax: Axes | None = None,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Columns ``names`` (default: every coordinate) against t, labelled with ``units``."""
    ax = ax if ax is not None else new_axes()
    shown = list(names if names is not None else trajectory.coordinates)
    for name in shown:
        ax.plot(trajectory.t, trajectory[name], label=column_label(name, units))
    ax.set_xlabel(time_label(units))
    given = {column_unit(name, units) for name in shown}
    if len(given) == 1 and None not in given:  # one unit: say it once, on the axis
        ax.set_ylabel(f"{', '.join(_letters(name) for name in shown)} [{given.pop()}]")
    ax.set_title("Time series")
    mark_impacts(ax, trajectory)
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


#: At most this many impacts are marked one by one; the bounces of a ball coming to rest
#: crowd into a band, so later ones are left out (the impacts table lists them all).
MARKED_IMPACTS = 200


def mark_impacts(ax: Axes, trajectory: Trajectory) -> None:
    """A thin dashed line at the time of each impact or transition of the run (one legend
    entry, "impacts"); nothing for a run without them."""
    times = [impact.t for impact in trajectory.impacts[:MARKED_IMPACTS]]
    for k, t in enumerate(times):
        ax.axvline(
            t, color="0.5", linestyle="--", linewidth=0.6, label="impacts" if k == 0 else None
        )


def plot_phase_portrait(
    trajectory: Trajectory,
    coordinate: str,
    ax: Axes | None = None,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """``coordinate_dot`` against ``coordinate``, the start marked, labelled with ``units``."""
    ax = ax if ax is not None else new_axes()
    rate = coordinate + DOT_SUFFIX
    q, q_dot = trajectory[coordinate], trajectory[rate]
    ax.plot(q, q_dot, linewidth=1.0)
    if len(q):
        ax.plot(q[:1], q_dot[:1], "o", label="start")
        ax.legend(loc="best")
    ax.set_xlabel(column_label(coordinate, units))
    ax.set_ylabel(column_label(rate, units))
    ax.set_title(f"Phase portrait of {label(sp.Symbol(coordinate))}")
    ax.grid(True, alpha=0.3)
    return ax


def plot_energy_drift(
    trajectory: Trajectory,
    ax: Axes | None = None,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Relative drift of E = T + V (and of h when it differs) against t, titled as the drift
    report says it (:meth:`Trajectory.drift`): a drift where the energy is conserved, a change
    "not conserved: dissipation" (or forcing, ...) where it is not."""
    ax = ax if ax is not None else new_axes()
    series = {"E = T + V": trajectory.energy}
    if trajectory.energy_function is not None:
        series["h"] = trajectory.energy_function
    relative = True
    for name, values in series.items():
        change, scaled = _drift(values)
        relative = relative and scaled
        ax.plot(trajectory.t, change, label=name)
    ax.set_xlabel(time_label(units))
    ax.set_ylabel("(E - E0) / |E0|" if relative else "E - E0")
    ax.set_title(energy_title(trajectory))
    mark_impacts(ax, trajectory)  # where the energy jumps (e < 1)
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


#: The most multipliers a legend names (a gas's dozens of contacts would bury the curves).
LEGEND_ENTRIES = 10


def acting_multipliers(trajectory: Trajectory) -> list[int]:
    """The multipliers that act somewhere in the run: a unilateral contact that never
    closes has no force (NaN throughout) and no curve."""
    if trajectory.multipliers is None:
        return []
    finite = np.isfinite(trajectory.multipliers)
    return [j for j in range(len(trajectory.multiplier_names)) if finite[:, j].any()]


def plot_constraint_forces(
    trajectory: Trajectory,
    ax: Axes | None = None,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Each Lagrange multiplier that acts against t: the force of its constraint
    (lambda_j dh_j/dq); the title counts the contacts that never closed."""
    ax = ax if ax is not None else new_axes()
    assert trajectory.multipliers is not None, "a trajectory of a constrained system"
    acting = acting_multipliers(trajectory)
    for j in acting:
        name = trajectory.multiplier_names[j]
        ax.plot(trajectory.t, trajectory.multipliers[:, j], label=label(sp.Symbol(name)))
    if len(trajectory.t):  # a contact that closes late still spans the run's time axis
        ax.set_xlim(trajectory.t[0], trajectory.t[-1])
    ax.set_xlabel(time_label(units))
    ax.set_ylabel("multiplier")
    idle = len(trajectory.multiplier_names) - len(acting)
    ax.set_title("Constraint forces" + (f" ({idle} never in contact)" if idle else ""))
    if 0 < len(acting) <= LEGEND_ENTRIES:
        ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


def overview(
    trajectory: Trajectory, coordinate: str | None = None, system: System | None = None
) -> Figure:
    """One figure with the time series, the phase portrait of ``coordinate`` (default: the
    first) and the energy drift, side by side, and the constraint forces below the time series
    of a constrained system; titled with the name of ``system`` and labelled with its units
    (when it is not given: the ones the trajectory keeps)."""
    from matplotlib.figure import Figure

    units = dict(system.units) if system is not None else dict(trajectory.units) or None
    groups = scale_groups(trajectory)
    forces = bool(acting_multipliers(trajectory))  # a gas whose contacts never hold: none
    rows = len(groups) + forces
    figure = Figure(figsize=(15, 4.5 if rows == 1 else 2.6 * rows), layout="constrained")
    grid = figure.add_gridspec(rows, 3)
    for row, names in enumerate(groups):  # one panel per scale: 95 rad of spin hides a nutation
        plot_time_series(trajectory, names, ax=figure.add_subplot(grid[row, 0]), units=units)
    if forces:  # in a panel of their own: forces are not on the coordinates' scale
        plot_constraint_forces(trajectory, ax=figure.add_subplot(grid[len(groups), 0]), units=units)
    middle = figure.add_subplot(grid[:, 1])
    right = figure.add_subplot(grid[:, 2])
    chosen = coordinate or trajectory.coordinates[0]
    plot_phase_portrait(trajectory, chosen, ax=middle, units=units)
    plot_energy_drift(trajectory, ax=right, units=units)
    figure.suptitle(overview_title(trajectory, system))
    for axes in figure.axes:
        fit_title(axes)
    return figure


def fit_title(axes: Axes) -> None:
    """Wrap the panel's title onto lines no wider than the panel (a long reason the energy
    is not conserved would run off the figure): the width in characters is the panel's
    width over an average glyph, 0.6 of the font size."""
    from matplotlib.figure import Figure

    text = axes.get_title()
    figure = axes.get_figure()
    if not text or not isinstance(figure, Figure):
        return
    width_inches = axes.get_position().width * figure.get_figwidth()
    size = float(axes.title.get_fontsize())
    columns = max(int(width_inches * 72 / (0.6 * size)), 10)
    lines = [textwrap.fill(line, columns) for line in text.splitlines()]
    axes.set_title("\n".join(lines))


def overview_title(trajectory: Trajectory, system: System | None = None) -> str:
    """The system's name and the method: ``double_pendulum (RK45)`` (the name the trajectory
    keeps when no system is given); ``Simulation (RK45)`` without a name.

    >>> import lagrangian as lg
    >>> from lagrangian.simulation import simulate
    >>> system = lg.examples.simple_pendulum()
    >>> overview_title(simulate(system, t_span=0.1, samples=3), system)
    'simple_pendulum (RK45)'
    """
    name = (system.name if system is not None else trajectory.system_name) or "Simulation"
    return f"{name} ({trajectory.method})" if trajectory.method else name


#: Coordinates whose ranges differ by more than this factor are drawn in panels of their own.
SCALE_RATIO = 10.0


def scale_groups(trajectory: Trajectory) -> list[list[str]]:
    """The coordinates grouped by the size of their excursions, each group within a factor
    ``SCALE_RATIO`` (largest first): a spin angle growing to 95 rad gets its own panel, so the
    nutation of the tilt stays visible.

    >>> import lagrangian as lg
    >>> from lagrangian.simulation import simulate
    >>> scale_groups(simulate(lg.examples.double_pendulum(), t_span=1.0, samples=20))
    [['theta', 'phi']]
    """
    import numpy as np

    sizes = {}
    for name in trajectory.coordinates:
        values = np.asarray(trajectory[name], dtype=float)
        finite = values[np.isfinite(values)]
        sizes[name] = float(np.max(np.abs(finite))) if finite.size else 0.0
    largest = max(sizes.values(), default=0.0)
    groups: list[list[str]] = []
    for name in sorted(sizes, key=lambda n: -sizes[n]):
        at_rest = sizes[name] <= 1e-9 * largest  # a coordinate that stays put: no panel of its own
        if groups and (at_rest or sizes[groups[-1][0]] <= SCALE_RATIO * sizes[name]):
            groups[-1].append(name)
        else:
            groups.append([name])
    order = {name: i for i, name in enumerate(trajectory.coordinates)}
    return [sorted(group, key=order.__getitem__) for group in groups]


def save_plots(
    trajectory: Trajectory,
    path: str | os.PathLike[str],
    coordinate: str | None = None,
    system: System | None = None,
) -> Path:
    """:func:`overview` as a picture in the format of the file's suffix (one of
    :data:`PLOT_FORMATS`: PNG, or the vector formats PDF and SVG for papers), titled and
    labelled from ``system`` when given; returns the path written."""
    return save_figure(overview(trajectory, coordinate, system), path)


def save_figure(figure: Figure, path: str | os.PathLike[str]) -> Path:
    """``figure`` as a picture in the format of the file's suffix (one of
    :data:`PLOT_FORMATS`); returns the path written."""
    target = Path(path)
    picture = target.suffix.lower().lstrip(".")
    if picture not in PLOT_FORMATS:
        known = ", ".join("." + f for f in PLOT_FORMATS)
        raise ValueError(f"{str(target)!r}: plots are written as {known}, not {target.suffix!r}")
    figure.savefig(target, format=picture, dpi=100)
    return target


#: The picture formats of :func:`save_plots`.
PLOT_FORMATS = ("png", "pdf", "svg")


def overview_png(trajectory: Trajectory) -> bytes:
    """:func:`overview` as PNG bytes (for Jupyter)."""
    buffer = io.BytesIO()
    overview(trajectory).savefig(buffer, format="png", dpi=80)
    return buffer.getvalue()


def energy_title(trajectory: Trajectory) -> str:
    """The energy plot's title: "Energy drift" where the energy is conserved (or nothing is
    known), else the change and why, as :meth:`Trajectory.drift_summary` says it.

    >>> import lagrangian as lg
    >>> from lagrangian.simulation import simulate
    >>> energy_title(simulate(lg.examples.mass_spring_damper(), t_span=0.1, samples=3))
    'Energy change (not conserved: dissipation)'
    """
    reasons = trajectory.not_conserved or {}
    if "energy" not in reasons:
        return "Energy drift"
    if trajectory.energy_function is not None and "energy_function" not in reasons:
        return f"Drift of h, the conserved energy\n(T + V not conserved: {reasons['energy']})"
    return f"Energy change (not conserved: {reasons['energy']})"


def new_axes() -> Axes:
    """A new figure's one Axes, the size and layout of every plot of the package."""
    from matplotlib.figure import Figure

    figure: Figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    return figure.add_subplot()


def _drift(values: np.ndarray) -> tuple[Any, bool]:
    """(values - v0) / |v0|, or values - v0 when v0 = 0; and whether it is relative."""
    if len(values) == 0:
        return values, True
    initial = float(values[0])
    change = values - initial
    return (change / abs(initial), True) if initial != 0 else (change, False)
