"""Plot of Hamilton's principle: the action A(eps) of the varied paths q + eps eta.

On the true path A is stationary, dA/deps = 0 at eps = 0, so the curve is flat there (a
parabola's vertex); on any other path it crosses eps = 0 with a slope.  matplotlib is imported
only when a plot is made; without an ``ax`` the plot goes on a new
:class:`matplotlib.figure.Figure` (no pyplot state).

>>> import numpy as np
>>> eps = np.linspace(-1.0, 1.0, 5)
>>> plot_action_variation(eps, 2.0 + eps**2).get_xlabel()
'eps'
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.axes import Axes


def plot_action_variation(
    amplitudes: ArrayLike, actions: ArrayLike, ax: Axes | None = None
) -> Axes:
    """A(eps) - A(0) against eps (the output of :func:`lagrangian.simulation.action_variation`).

    The action at eps = 0 (or at the smallest |eps|) is subtracted, so that the small
    variation stays visible next to a large action.  Returns the Axes drawn on.
    """
    eps = np.asarray(amplitudes, dtype=float)
    values = np.asarray(actions, dtype=float)
    if ax is None:
        from lagrangian.render.plots import new_axes

        ax = new_axes()
    reference = float(values[np.argmin(np.abs(eps))]) if len(values) else 0.0
    ax.plot(eps, values - reference, "o-", label="A(eps) - A(0)")
    ax.axvline(0.0, color="gray", linewidth=0.8)
    ax.set_xlabel("eps")
    ax.set_ylabel("A(q + eps eta) - A(q)")
    ax.set_title("Variation of the action")
    ax.legend(loc="best")
    ax.grid(True, alpha=0.3)
    return ax
