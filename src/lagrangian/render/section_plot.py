"""The plot of a Poincaré section (:mod:`lagrangian.simulation.poincare`): its points in the
plane of two of its columns, a dot a crossing (a regular orbit draws a closed curve, a
chaotic one fills an area).

>>> import lagrangian as lg
>>> section = lg.poincare_section(lg.examples.henon_heiles(), "x", t_span=30.0)
>>> ax = plot_poincare_section(section)
>>> ax.get_xlabel(), ax.get_ylabel() == column_label("y_dot")
('y', True)
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from lagrangian.model import System
from lagrangian.render.plots import column_label, save_figure
from lagrangian.simulation.poincare import PoincareSection

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: A section is a plane of two like quantities: a square picture.
FIGURE_SIZE = (6.0, 6.0)


def plot_poincare_section(
    section: PoincareSection,
    axes: tuple[str, str] | None = None,
    ax: Axes | None = None,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """The points of ``section`` in the plane of the columns ``axes`` (default: the
    section's own, :attr:`PoincareSection.axes`), labelled with ``units``."""
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=FIGURE_SIZE, layout="constrained").add_subplot()
    horizontal, vertical = axes or section.axes
    ax.plot(section[horizontal], section[vertical], ".", markersize=2.0)
    ax.set_xlabel(column_label(horizontal, units))
    ax.set_ylabel(column_label(vertical, units))
    ax.set_title(f"Poincaré section {section.section} = 0 ({section.direction})")
    ax.grid(True, alpha=0.3)
    return ax


def save_section_plot(
    section: PoincareSection,
    path: str | os.PathLike[str],
    axes: tuple[str, str] | None = None,
    system: System | None = None,
) -> Path:
    """:func:`plot_poincare_section` as a picture in the format of the file's suffix,
    labelled with the units of ``system`` when given; returns the path written."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=FIGURE_SIZE, layout="constrained")
    units = dict(system.units) if system is not None else None
    plot_poincare_section(section, axes, figure.add_subplot(), units=units)
    if system is not None and system.name:
        figure.suptitle(system.name)
    return save_figure(figure, path)
