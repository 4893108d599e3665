"""The output rows of the lanes of a run: at shared output times, or at every step.

With output times (a batch's, or ``t_eval``/``samples`` of a single run) each lane fills the
rows (k, T, n) of the times its steps covered, read on the step's interpolant, one call for
every (lane, time) pair of a step; rows a lane never reached stay NaN.  Without (a single
run keeping every step) each lane keeps the time and state of every step.

>>> import numpy as np
>>> rows = Rows(np.array([0.0, 0.5, 1.0]), 0.0, np.zeros((2, 1)))
>>> rows.filled.tolist(), rows.pending(np.array([0, 1]), np.array([0.7, 0.2]))
([1, 1], array([ True, False]))
"""

from __future__ import annotations

import numpy as np

from lagrangian.simulation.integrators.lanes import LaneDense

_ONE = np.ones(1, dtype=bool)


class Rows:
    """Collects output rows of k lanes: at ``times`` (None: every step) as they are reached."""

    def __init__(self, times: np.ndarray | None, t0: float, X0: np.ndarray) -> None:
        k, n = X0.shape
        self.times = times
        if times is None:
            self.steps_t: list[list[float]] = [[t0] for _ in range(k)]
            self.steps_x: list[list[np.ndarray]] = [[x] for x in X0]
            self.filled = np.ones(k, dtype=np.intp)
            return
        first = int(np.searchsorted(times, t0, side="right"))
        self.x = np.full((k, len(times), n), np.nan)
        self.x[:, :first] = X0[:, None, :]
        self.filled = np.full(k, first, dtype=np.intp)

    def pending(self, lanes: np.ndarray, t: np.ndarray) -> np.ndarray | None:
        """Whether each of ``lanes`` has an output time at or before its t (its step needs
        the interpolant); None when none has (and always without output times: a step's
        end is its row)."""
        times = self.times
        if times is None:
            return None
        if len(lanes) == 1:  # a single run: most steps of a fine output hold no time
            r = self.filled[lanes[0]]
            return _ONE if r < len(times) and times[r] <= t[0] else None
        row = self.filled[lanes]
        inside = row < len(times)
        pending = inside & (times[np.where(inside, row, 0)] <= t)
        return pending if pending.any() else None

    def reach(
        self,
        lanes: np.ndarray,
        t: np.ndarray,
        x: np.ndarray | None,
        dense: LaneDense | None,
        which: np.ndarray,
    ) -> None:
        """Record the output of ``lanes`` up to their times t (states x at t, needed when
        every step is kept): the rows at the output times in their step, read on ``dense``
        (entry ``which[j]`` for lane j)."""
        if self.times is None:
            assert x is not None  # the loop reads the states when every step is kept
            if len(lanes) == 1:
                self.steps_x[lanes[0]].append(x[0])
                self.steps_t[lanes[0]].append(float(t[0]))
                return
            for lane, s, state in zip(lanes.tolist(), t.tolist(), x):
                # the state is kept before its time: a Ctrl-C in between leaves no time alone
                self.steps_x[lane].append(state)
                self.steps_t[lane].append(s)
            return
        if dense is None:
            return
        if len(lanes) == 1:  # a single run: its block of rows in one call
            lane = lanes[0]
            first = self.filled[lane]
            last = int(np.searchsorted(self.times, t[0], side="right"))
            if last > first:
                block = self.times[first:last]
                self.x[lane, first:last] = dense.value(block, np.full(len(block), which[0]))
                self.filled[lane] = last
            return
        start = self.filled[lanes]
        end = np.searchsorted(self.times, t, side="right")
        counts = np.maximum(end - start, 0)
        if not counts.any():
            return
        entry = np.repeat(np.arange(len(lanes)), counts)
        row = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
        row += np.repeat(start, counts)
        states = dense.value(self.times[row], which[entry])
        self.x[lanes[entry], row] = states
        self.filled[lanes] = np.maximum(start, end)

    def lane(self, lane: int) -> tuple[np.ndarray, np.ndarray]:
        """The times and states of lane ``lane``'s rows."""
        if self.times is None:
            times, states = self.steps_t[lane], self.steps_x[lane]
            rows = min(len(times), len(states))
            x = np.array(states[:rows], dtype=float).reshape(rows, -1)
            return np.array(times[:rows], dtype=float), x
        rows = int(self.filled[lane])
        return self.times[:rows].astype(float), self.x[lane, :rows]
