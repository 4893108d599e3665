"""The animation of a system with nothing to draw in space — a circuit, or coordinates that
are not positions of particles or bodies: each coordinate and its rate as a bar (a gauge),
scaled to the largest value it reaches, so charges and currents of an RLC circuit swing as
they would on the dials of a meter.

>>> import lagrangian as lg
>>> system = lg.examples.series_rlc()
>>> trajectory = lg.simulate(system, t_span=1.0, samples=11)
>>> figure, draw, shown = gauge_scene(system, trajectory, shown=[0, 5, 10])
>>> len(draw(1))  # the bars and the clock
3
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from lagrangian.model import System
from lagrangian.simulation.trajectory import Trajectory

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def gauge_columns(system: System, trajectory: Trajectory) -> dict[str, np.ndarray]:
    """The columns shown: every coordinate, then every velocity (for a circuit: the charges,
    then the currents)."""
    names = [q.name for q in system.coordinates]
    return {
        **{n: trajectory[n] for n in names},
        **{n + "_dot": trajectory[n + "_dot"] for n in names},
    }


def gauge_scene(
    system: System, trajectory: Trajectory, shown: Sequence[int] | np.ndarray
) -> tuple[Figure, Callable[[int], list[Any]], np.ndarray]:
    """The figure of the gauges, a function drawing frame ``index`` of ``shown`` (rows of the
    trajectory), and those rows."""
    from matplotlib.figure import Figure

    columns = gauge_columns(system, trajectory)
    labels = list(columns)
    values = np.array([columns[name] for name in labels])  # (gauges, rows)
    scale = np.nanmax(np.abs(values), axis=1)
    scale[~(scale > 0)] = 1.0
    figure = Figure(figsize=(5, 0.6 * len(labels) + 1.2))
    axes = figure.add_subplot()
    bars = axes.barh(range(len(labels)), np.zeros(len(labels)), color="C0")
    axes.set_yticks(range(len(labels)), labels)
    axes.invert_yaxis()
    axes.set_xlim(-1.05, 1.05)
    axes.axvline(0.0, color="0.3", lw=1)
    axes.set_xlabel("value / largest |value| of the run")
    axes.set_title(system.name or "system")
    clock = axes.text(0.02, 1.02, "", transform=axes.transAxes)
    rows = np.asarray(shown)
    figure.tight_layout()

    def draw(index: int) -> list[Any]:
        row = rows[index]
        for bar, value, largest in zip(bars, values[:, row], scale):
            bar.set_width(value / largest)
            bar.set_color("C0" if value >= 0 else "C3")
        clock.set_text(f"t = {trajectory.t[row]:.3g}")
        return [*bars, clock]

    return figure, draw, rows
