"""The flip-time map of the double pendulum: how long until either arm flips over.

Two equal point masses on rods of equal length l (as the ``double_pendulum`` example, with
its angles theta and phi from the downward vertical) start at rest at (theta, phi) on a grid;
a member stops when |theta| or |phi| passes pi,

    g(t, q, q_dot) = pi - max(|theta|, |phi|)      (negative: flipped),

and its flip time is recorded; members that do not flip before t_end get NaN.  Energy alone
forbids a flip of a start at rest with 2 cos theta + cos phi > 1: the energy
E = -m g l (2 cos theta + cos phi) is conserved and a flip needs E >= -m g l (at theta = pi
the lowest potential is m g l, at phi = pi it is -m g l).

>>> import numpy as np, lagrangian as lg
>>> times = flip_times(lg.examples.double_pendulum(), [0.5, 3.0], [3.0], t_end=2.0)
>>> bool(np.isnan(times[0, 0])), bool(times[0, 1] < 2.0)
(True, True)
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from lagrangian.derivation import EquationsOfMotion
from lagrangian.model import System
from lagrangian.simulation.batch import simulate_batch


def flipped(t: float, q: np.ndarray, q_dot: np.ndarray) -> np.ndarray:
    """pi - max(|theta|, |phi|): negative once either arm has flipped over."""
    return np.pi - np.maximum(np.abs(q[..., 0]), np.abs(q[..., 1]))


def flip_times(
    double_pendulum: System | EquationsOfMotion,
    theta: ArrayLike,
    phi: ArrayLike,
    t_end: float,
    *,
    length: float = 1.0,
    gravity: float = 9.81,
    rtol: float = 1e-9,
    atol: float = 1e-9,
    backend: str = "numpy",
    progress: bool | Callable[[float], None] = False,
    workers: int = 1,
) -> np.ndarray:
    """Flip times of starts at rest on the grid ``theta`` x ``phi``, shape (len(phi),
    len(theta)) (rows: phi, as an image), NaN where no arm flips before ``t_end``.

    ``double_pendulum``: ``lagrangian.examples.double_pendulum()`` or its equations (angles
    theta, phi; parameters m1, m2, l1, l2, g).  DOP853 with rtol and atol; both masses 1 (the
    times do not depend on them when equal).
    """
    grid_theta, grid_phi = np.meshgrid(np.asarray(theta, float), np.asarray(phi, float))
    at_rest = {"theta_dot": 0.0, "phi_dot": 0.0}
    batch = simulate_batch(
        double_pendulum,
        {"theta": grid_theta.ravel(), "phi": grid_phi.ravel(), **at_rest},
        t_end,
        parameters={"l1": length, "l2": length, "g": gravity, "m1": 1.0, "m2": 1.0},
        method="DOP853",
        rtol=rtol,
        atol=atol,
        stop_when=flipped,
        backend=backend,
        progress=progress,
        workers=workers,
    )
    return batch.stop_time.reshape(grid_theta.shape)
