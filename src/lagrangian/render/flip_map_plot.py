"""The flip-time map of the double pendulum as an image (log-scaled colours).

Each pixel is a start at rest (theta, phi); its colour the time until either arm flips over
(:func:`lagrangian.simulation.flip_map.flip_times`), on a logarithmic scale, in units of
sqrt(l/g); starts that do not flip within the time span are left white.

>>> import numpy as np
>>> figure = flip_map_figure(np.array([[np.nan, 1.0], [2.0, np.nan]]), (-3, 3), (-3, 3), 10.0)
>>> figure.axes[0].get_xlabel()
'theta (rad)'
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def flip_map_figure(
    times: np.ndarray,
    theta_range: tuple[float, float],
    phi_range: tuple[float, float],
    t_end: float,
    unit: float = 1.0,
) -> Figure:
    """The map ``times`` (rows: phi, columns: theta; NaN: no flip) as a figure; times are
    shown divided by ``unit`` (sqrt(l/g) for dimensionless times)."""
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    scaled = np.asarray(times, dtype=float) / unit
    finite = scaled[np.isfinite(scaled)]
    low = float(np.min(finite)) if finite.size else 1e-3
    figure = Figure(figsize=(6.4, 5.4), layout="constrained")
    ax = figure.add_subplot()
    image = ax.imshow(
        np.ma.masked_invalid(scaled),
        origin="lower",
        extent=(*theta_range, *phi_range),
        cmap="viridis",
        norm=LogNorm(vmin=max(low, 1e-3), vmax=t_end / unit),
        interpolation="nearest",
    )
    ax.set_facecolor("white")
    ax.set_xlabel("theta (rad)")
    ax.set_ylabel("phi (rad)")
    ax.set_title(f"Double pendulum: time until an arm flips (white: none by {t_end / unit:g})")
    label = "flip time" if unit == 1.0 else "flip time / sqrt(l/g)"
    figure.colorbar(image, ax=ax, label=label)
    return figure


def save_flip_map(path: str | os.PathLike[str], figure: Figure, dpi: int = 100) -> None:
    """Write the figure as a PNG."""
    figure.savefig(path, dpi=dpi)
