"""The frames of an animation: how many (from the motion's time scale), at which times, and
the state at each (interpolated between the run's samples), with the frames of its impacts.

The time scale tau of a run is the shortest mean time between turning points of any
coordinate (a sign change of its velocity, counted with a hysteresis of 5 % of its largest
speed, so noise about rest is not motion): an oscillation of period P turns twice per period,
tau = P / 2.  A run lasting D gets :data:`FRAMES_PER_TURN` frames per turning interval,
frames = D / tau * FRAMES_PER_TURN, kept between :data:`MIN_FRAMES` and :data:`MAX_FRAMES`;
a motion that never turns (a rolling disc, a free particle) gets :data:`MIN_FRAMES`.

>>> import lagrangian as lg
>>> system = lg.examples.simple_pendulum()   # period 2.03 s (l = 1 m, swinging 0.5 rad)
>>> frame_count(lg.simulate(system, t_span=20.0, samples=2001))  # 19 turns after rest
190
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lagrangian.simulation.trajectory import Trajectory

#: Frames per second of playback unless one is asked for.
FPS = 25.0
#: Frames between two turning points of the fastest coordinate.
FRAMES_PER_TURN = 10
MIN_FRAMES = 40
MAX_FRAMES = 300


def turning_points(velocity: np.ndarray) -> int:
    """Sign changes of ``velocity``, each counted once it has reached 5 % of the largest
    speed on the new side (hysteresis: a velocity hovering about 0 does not count)."""
    values = np.asarray(velocity, dtype=float)
    values = values[np.isfinite(values)]
    if values.size < 2:
        return 0
    threshold = 0.05 * float(np.max(np.abs(values)))
    if threshold == 0.0:
        return 0
    side, turns = 0, 0
    for value in values:
        now = 1 if value > threshold else -1 if value < -threshold else 0
        if now and side and now != side:
            turns += 1
        side = now or side
    return turns


def frame_count(trajectory: Trajectory) -> int:
    """Frames for the run: :data:`FRAMES_PER_TURN` per turning interval of its fastest
    coordinate, between :data:`MIN_FRAMES` and :data:`MAX_FRAMES`."""
    if len(trajectory.t) < 2:
        return max(len(trajectory.t), 1)
    turns = max((turning_points(trajectory.q_dot[:, j]) for j in range(trajectory.q.shape[1])),
                default=0)  # fmt: skip
    return int(np.clip(round(max(turns, 1) * FRAMES_PER_TURN), MIN_FRAMES, MAX_FRAMES))


@dataclass(frozen=True)
class FrameStates:
    """The state at each frame: times ``t`` (F,), coordinates ``q`` and velocities ``q_dot``
    (F, n), the run's ``parameters`` by name, and the names of the coordinates."""

    t: np.ndarray
    q: np.ndarray
    q_dot: np.ndarray
    parameters: dict[str, float]
    names: tuple[str, ...]

    def column(self, name: str) -> np.ndarray:
        """A coordinate (``x``) or a velocity (``x_dot``) at every frame."""
        if name.endswith("_dot") and name[:-4] in self.names:
            return self.q_dot[:, self.names.index(name[:-4])]
        return self.q[:, self.names.index(name)]


def frame_states(trajectory: Trajectory, count: int) -> FrameStates:
    """``count`` evenly spaced frames over the run (its samples themselves when it has no
    more than that), the state interpolated linearly between samples."""
    t = np.asarray(trajectory.t, dtype=float)
    names = tuple(trajectory.coordinates)
    parameters = {str(k): float(v) for k, v in dict(trajectory.parameters).items()}
    if len(t) <= max(count, 1) or len(t) < 2:
        return FrameStates(t, np.asarray(trajectory.q), np.asarray(trajectory.q_dot),
                           parameters, names)  # fmt: skip
    times = np.linspace(t[0], t[-1], max(count, 2))
    return FrameStates(
        times,
        _interpolated(times, t, trajectory.q),
        _interpolated(times, t, trajectory.q_dot),
        parameters,
        names,
    )


def sample_states(trajectory: Trajectory, rows: Sequence[int] | np.ndarray) -> FrameStates:
    """The run's own samples at ``rows`` (indices into its times, increasing) as the frames:
    no interpolation, so frame k shows the state of sample ``rows[k]`` exactly."""
    picked = np.asarray(rows, dtype=int)
    t = np.asarray(trajectory.t, dtype=float)
    if picked.ndim != 1 or picked.size == 0 or np.any(np.diff(picked) <= 0):
        raise ValueError("rows must be increasing sample indices, at least one")
    if picked[0] < 0 or picked[-1] >= len(t):
        raise ValueError(f"rows must lie in 0..{len(t) - 1}, the run's samples")
    parameters = {str(k): float(v) for k, v in dict(trajectory.parameters).items()}
    return FrameStates(t[picked], np.asarray(trajectory.q)[picked],
                       np.asarray(trajectory.q_dot)[picked], parameters,
                       tuple(trajectory.coordinates))  # fmt: skip


def spread_rows(samples: int, most: int = MAX_FRAMES) -> np.ndarray:
    """At most ``most`` of ``samples`` rows, evenly spread over them, the first and the last
    always among them (every row when there are no more than ``most``).

    >>> spread_rows(5, 3).tolist(), spread_rows(3).tolist()
    ([0, 2, 4], [0, 1, 2])
    """
    if samples <= max(most, 1):
        return np.arange(samples)
    return np.unique(np.round(np.linspace(0, samples - 1, max(most, 2))).astype(int))


def _interpolated(times: np.ndarray, t: np.ndarray, values: Any) -> np.ndarray:
    columns = np.asarray(values, dtype=float)
    return np.stack([np.interp(times, t, columns[:, j]) for j in range(columns.shape[1])], axis=1)


def impact_frames(trajectory: Trajectory, states: FrameStates) -> tuple[tuple[int, str], ...]:
    """The first frame at or after each impact (or transition) of the run, with what struck:
    ``((frame, "impact: floor"), ...)``; one entry per frame, naming every constraint that
    struck since the frame before (a gas has several impacts a frame), the first
    :data:`NAMED_IMPACTS` of them and how many more."""
    struck: dict[int, list[str]] = {}
    count: dict[int, int] = {}
    times = states.t
    for impact in trajectory.impacts:
        frame = int(np.searchsorted(times, impact.t - 1e-12))
        if frame < len(times):
            names = struck.setdefault(frame, [])
            names += [name for name in impact.constraints if name not in names]
            count[frame] = count.get(frame, 0) + 1
    return tuple(
        (frame, _impact_label(names, count[frame])) for frame, names in sorted(struck.items())
    )


#: The constraints an impact's label names before it counts the rest.
NAMED_IMPACTS = 3


def _impact_label(names: list[str], impacts: int) -> str:
    """``impact: floor``; ``3 impacts: a, b, c and 2 more`` for several in one frame."""
    more = len(names) - NAMED_IMPACTS
    shown = ", ".join(names[:NAMED_IMPACTS]) + (f" and {more} more" if more > 0 else "")
    return (f"{impacts} impacts: " if impacts > 1 else "impact: ") + shown
