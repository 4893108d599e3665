"""Plots of a Trajectory with matplotlib: time series, phase portraits, energy drift.

matplotlib is imported only when a plot is made (it keeps ``import lagrangian`` fast).  Without an
``ax`` each function draws on a new :class:`matplotlib.figure.Figure` (no pyplot state);
every function returns the Axes it drew on.  The energy drift is

    (E(t) - E(t_0)) / |E(t_0)|      (E(t) - E(t_0) when E(t_0) = 0)

>>> import lagrangian as lg
>>> from lagrangian.simulation import simulate
>>> trajectory = simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=50)
>>> plot_phase_portrait(trajectory, "theta").get_xlabel()
'theta'
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from lagrangian.simulation.trajectory import Trajectory

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


def plot_time_series(
    trajectory: Trajectory, names: Sequence[str] | None = None, ax: Axes | None = None
) -> Axes:
    """Columns ``names`` (default: every coordinate) against t."""
    ax = ax if ax is not None else _new_axes()
    for name in names if names is not None else trajectory.coordinates:
        ax.plot(trajectory.t, trajectory[name], label=name)
    ax.set_xlabel("t")
    ax.set_title("Time series")
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


def plot_phase_portrait(trajectory: Trajectory, coordinate: str, ax: Axes | None = None) -> Axes:
    """``coordinate_dot`` against ``coordinate``, the start marked."""
    ax = ax if ax is not None else _new_axes()
    q, q_dot = trajectory[coordinate], trajectory[coordinate + "_dot"]
    ax.plot(q, q_dot, linewidth=1.0)
    if len(q):
        ax.plot(q[:1], q_dot[:1], "o", label="start")
        ax.legend(loc="best")
    ax.set_xlabel(coordinate)
    ax.set_ylabel(coordinate + "_dot")
    ax.set_title(f"Phase portrait of {coordinate}")
    ax.grid(True, alpha=0.3)
    return ax


def plot_energy_drift(trajectory: Trajectory, ax: Axes | None = None) -> Axes:
    """Relative drift of E = T + V (and of h when it differs) against t, titled as the drift
    report says it (:meth:`Trajectory.drift`): a drift where the energy is conserved, a change
    "not conserved: dissipation" (or forcing, ...) where it is not."""
    ax = ax if ax is not None else _new_axes()
    series = {"E = T + V": trajectory.energy}
    if trajectory.energy_function is not None:
        series["h"] = trajectory.energy_function
    relative = True
    for label, values in series.items():
        change, scaled = _drift(values)
        relative = relative and scaled
        ax.plot(trajectory.t, change, label=label)
    ax.set_xlabel("t")
    ax.set_ylabel("(E - E0) / |E0|" if relative else "E - E0")
    ax.set_title(energy_title(trajectory))
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax


def overview(trajectory: Trajectory, coordinate: str | None = None) -> Figure:
    """One figure with the time series, the phase portrait of ``coordinate`` (default: the
    first) and the energy drift, side by side."""
    from matplotlib.figure import Figure

    groups = scale_groups(trajectory)
    figure = Figure(
        figsize=(15, 4.5 if len(groups) == 1 else 2.6 * len(groups)), layout="constrained"
    )
    grid = figure.add_gridspec(len(groups), 3)
    for row, names in enumerate(groups):  # one panel per scale: 95 rad of spin hides a nutation
        plot_time_series(trajectory, names, ax=figure.add_subplot(grid[row, 0]))
    middle = figure.add_subplot(grid[:, 1])
    right = figure.add_subplot(grid[:, 2])
    plot_phase_portrait(trajectory, coordinate or trajectory.coordinates[0], ax=middle)
    plot_energy_drift(trajectory, ax=right)
    if trajectory.method:
        figure.suptitle(f"{', '.join(trajectory.coordinates)} ({trajectory.method})")
    return figure


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
    trajectory: Trajectory, path: str | os.PathLike[str], coordinate: str | None = None
) -> Path:
    """:func:`overview` as a picture in the format of the file's suffix (one of
    :data:`PLOT_FORMATS`: PNG, or the vector formats PDF and SVG for papers); returns the path
    written."""
    target = Path(path)
    picture = target.suffix.lower().lstrip(".")
    if picture not in PLOT_FORMATS:
        known = ", ".join("." + f for f in PLOT_FORMATS)
        raise ValueError(f"{str(target)!r}: plots are written as {known}, not {target.suffix!r}")
    overview(trajectory, coordinate).savefig(target, format=picture, dpi=100)
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


def _new_axes() -> Axes:
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
