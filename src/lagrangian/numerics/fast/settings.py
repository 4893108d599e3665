"""How to integrate, for every batch and compiled run: the method and its tolerances or step,
the time span and the output times.

One value for the C loop (:mod:`lagrangian.numerics.fast.c_loop`) and the vectorized batch
(:mod:`lagrangian.simulation.batch.vectorized`).

>>> import numpy as np
>>> Settings("RK4", (0.0, 1.0), np.linspace(0, 1, 5), dt=0.01).rtol
1e-08
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Settings:
    """Method, time span, output times (empty: every step), tolerances (adaptive methods)
    or step ``dt`` (RK4)."""

    method: str
    span: tuple[float, float]
    t_out: np.ndarray
    rtol: float = 1e-8
    atol: float = 1e-10
    max_step: float = math.inf
    dt: float | None = None
    #: Steps a member may take (None: no limit).
    max_steps: int | None = None
