"""A batch's members as the lanes of one Runge–Kutta stepper vectorized with NumPy.

The members of a batch without the C loop run through the one Python loop
(:func:`lagrangian.simulation.integrators.loop.run_lanes`) as its lanes: each call of
:meth:`RungeKuttaLanes.step` makes one trial step for every running member at once (one call
of the right-hand side per stage on a (members, state) array), each with its own step h_i
and time t_i, and accepts or rejects each member by its own error norm with SciPy's rules
(SciPy's ``RungeKutta``, as the C loop).  Per-member control rather than one shared step:
members of a chaotic ensemble need very different steps, a shared step would be the smallest
for all, and with its own steps member i of a batch is the run of member i alone (the same
steps as solve_ivp).  Members that finished, stopped or failed leave the lanes the loop
steps, so the work shrinks with them.  RK4 (fixed step) takes every member's step together.

The loop reads the output rows on the steps' interpolants (:mod:`~.dense`, SciPy's, with an
axis for the members) and watches the stop condition (:mod:`~.stop`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.fast.tableaus import Tableau, fixed_steps, tableau_of
from lagrangian.numerics.status import Status
from lagrangian.simulation.batch.dense import DOP853, HERMITE, RK45, Dense
from lagrangian.simulation.batch.stop import StopWatch
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.lanes import NOWHERE, Projection, Taken
from lagrangian.simulation.integrators.loop import run_lanes

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
#: The step budget of a member when the settings give none.
UNLIMITED = np.iinfo(np.int64).max


class _Field:
    """dx/dt of the running members, with the members whose matrix was singular."""

    def __init__(self, compiled: CompiledEquations, P: np.ndarray) -> None:
        self.compiled, self.P = compiled, P

    def __call__(
        self, t: np.ndarray, x: np.ndarray, rows: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        p = self.P[rows]
        try:
            return self.compiled.rhs(t, x, p), np.zeros(len(x), dtype=bool)
        except (SimulationError, np.linalg.LinAlgError):
            pass
        dx, bad = np.full_like(x, np.nan), np.zeros(len(x), dtype=bool)
        for i in range(len(x)):  # find the singular members, keep the others
            try:
                dx[i] = self.compiled.rhs(float(t[i]), x[i], p[i])
            except (SimulationError, np.linalg.LinAlgError):
                bad[i] = True
        return dx, bad


def integrate_members(
    compiled: CompiledEquations,
    settings: Settings,
    X0: np.ndarray,
    P: np.ndarray,
    stop_when: Callable[..., Any] | None = None,
    progress: Callable[[float], None] | None = None,
) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], list[str | None]]:
    """Integrate every row of X0 (parameters: the same row of P) as the lanes of the loop.

    Returns (out (members, times, state) with NaN after a stop or failure, status, t_final,
    x_final) — status codes of :class:`~lagrangian.numerics.status.Status`, the time and
    state each member ended at (the end, its stop, or its last accepted step) — and each
    member's message where its code does not say it (an error raised while stepping).
    ``progress`` gets the smallest time reached by a running member after each round.
    Ctrl-C ends the whole batch (KeyboardInterrupt).
    """
    t0, t1 = settings.span
    watch = None if stop_when is None else StopWatch(stop_when, len(compiled.coordinates))
    max_steps = settings.max_steps if settings.max_steps is not None else UNLIMITED
    budget = Budget(settings.method, max_steps=max_steps, start=t0)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        run = run_lanes(
            lambda: RungeKuttaLanes(compiled, settings, X0, P),
            t0,
            X0.astype(float),
            settings.t_out,
            watch,
            progress,
            None,
            budget,
        )
    if run.interrupted:
        raise KeyboardInterrupt  # as the C loop's batch: Ctrl-C ends the whole batch
    if progress is not None:
        progress(t1)
    messages = [
        str(m) if m is not None and code == Status.FAILED else None
        for m, code in zip(run.messages, run.status.tolist())
    ]
    return (run.rows.x, run.status, run.t_final, run.x_final), messages


class RungeKuttaLanes:
    """The members of a batch as lanes (:class:`~lagrangian.simulation.integrators.lanes.
    LaneStepper`): per member t, x, f = dx/dt, step h; one trial step per call."""

    def __init__(
        self, compiled: CompiledEquations, settings: Settings, X0: np.ndarray, P: np.ndarray
    ) -> None:
        k, nx = X0.shape
        self.settings = settings
        self.field = _Field(compiled, P)
        self.tableau = tableau_of(settings.method)
        self.fixed = self.tableau.fixed
        self.t_bound = float(settings.span[1])
        self.t, self.y = np.full(k, float(settings.span[0])), X0.astype(float).copy()
        self.f, self.h = np.zeros((k, nx)), np.zeros(k)
        self.rejected = np.zeros(k, dtype=bool)
        self.fresh = np.ones(k, dtype=bool)  # no step size chosen yet
        self.taken = 0  # RK4: the steps every member took (all share the step index)
        self.last: _Last | None = None

    def rates(self, t: np.ndarray, x: np.ndarray, lanes: np.ndarray) -> tuple[np.ndarray, Any]:
        """dx/dt of the ``lanes`` at (t, x), and which of them were singular."""
        return self.field(t, x, lanes)

    # ----------------------------------------------------------------- start

    def begin(self) -> Taken:
        lanes = np.arange(len(self.t))
        self.f, bad = self.field(self.t, self.y, lanes)
        if self.fixed:
            t0, t1 = self.settings.span
            self.steps = fixed_steps(t0, t1, float(self.settings.dt or 1.0))
            self.h[:] = (t1 - t0) / self.steps
            self.fresh[:] = False
        return _failures((lanes[bad], Status.SINGULAR))

    def initial_step(self, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """SciPy's select_initial_step, member by member (vectorized), and the members
        whose matrix was singular on the way."""
        s = self.settings
        t0, y0, f0 = self.t[rows], self.y[rows], self.f[rows]
        interval = abs(s.span[1] - s.span[0])
        scale = s.atol + np.abs(y0) * s.rtol
        d0, d1 = _rms(y0 / scale), _rms(f0 / scale)
        h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / d1)
        h0 = np.minimum(h0, interval)
        f1, bad = self.field(t0 + h0, y0 + h0[:, None] * f0, rows)
        d2 = _rms((f1 - f0) / scale) / h0
        order = self.tableau.error_order
        h1 = np.where(
            (d1 <= 1e-15) & (d2 <= 1e-15),
            np.maximum(1e-6, h0 * 1e-3),
            (0.01 / np.maximum(d1, d2)) ** (1 / (order + 1)),
        )
        return np.minimum(np.minimum(100 * h0, h1), min(interval, s.max_step)), bad

    # ----------------------------------------------------------------- steps

    def step(self, lanes: np.ndarray) -> Taken:
        """One trial step of every lane in ``lanes``; the accepted ones advance."""
        if self.fixed:
            return self.step_fixed(lanes)
        failed: list[tuple[np.ndarray, int]] = []
        fresh = lanes[self.fresh[lanes]]
        if len(fresh):
            self.h[fresh], bad = self.initial_step(fresh)
            self.fresh[fresh] = False
            failed.append((fresh[bad], Status.SINGULAR))
            lanes = np.setdiff1d(lanes, fresh[bad], assume_unique=True)
        s, tableau = self.settings, self.tableau
        t, y, f = self.t[lanes], self.y[lanes], self.f[lanes]
        min_step = 10 * np.abs(np.nextafter(t, np.inf) - t)
        h_abs = self.h[lanes]
        new = ~self.rejected[lanes]  # a new step: clamp as SciPy does before its loop
        h_abs = np.where(new & (h_abs > s.max_step), s.max_step, h_abs)
        h_abs = np.where(new & (h_abs < min_step), min_step, h_abs)
        small = h_abs < min_step
        failed.append((lanes[small], Status.STEP_TOO_SMALL))
        lanes, t, y, f, h_abs = lanes[~small], t[~small], y[~small], f[~small], h_abs[~small]
        t_new = np.minimum(t + h_abs, s.span[1])
        h = t_new - t
        K, y_new, bad = self.stages(lanes, t, y, f, h)
        err = _error_norm(K, h, y, y_new, s.rtol, s.atol, tableau)
        exponent = -1 / (tableau.error_order + 1)
        accept = (err < 1) & ~bad
        with np.errstate(divide="ignore"):
            grow = np.where(err == 0, MAX_FACTOR, np.minimum(MAX_FACTOR, SAFETY * err**exponent))
            shrink = SAFETY * err**exponent
        grow = np.where(self.rejected[lanes], np.minimum(1.0, grow), grow)
        shrink = np.where(shrink > MIN_FACTOR, shrink, MIN_FACTOR)  # NaN error: shrink by 0.2
        self.h[lanes] = np.abs(h) * np.where(accept, grow, shrink)
        self.rejected[lanes] = ~accept
        failed.append((lanes[bad], Status.SINGULAR))
        a = accept
        last = _Last(lanes[a], t[a], y[a], t_new[a], y_new[a], K[:, a], h[a])
        return self.accepted(last, K[len(tableau.B), a], t_new[a] >= s.span[1], failed)

    def stages(
        self, rows: np.ndarray, t: np.ndarray, y: np.ndarray, f: np.ndarray, h: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """K_0..K_s of one trial step (K_s = f at the new state), the new state, and the
        members whose matrix was singular on the way."""
        A, B, C = self.tableau.A, self.tableau.B, self.tableau.C
        extra = len(self.tableau.C_extra) if self.tableau.dop853 else 0
        K = np.empty((len(B) + 1 + extra, *y.shape))
        K[0] = f
        bad = np.zeros(len(rows), dtype=bool)
        for s in range(1, len(B)):
            dy = np.einsum("sai,s->ai", K[:s], A[s, :s]) * h[:, None]
            K[s], singular = self.field(t + C[s] * h, y + dy, rows)
            bad |= singular
        y_new = y + h[:, None] * np.einsum("sai,s->ai", K[: len(B)], B)
        K[len(B)], singular = self.field(t + h, y_new, rows)
        return K, y_new, bad | singular

    def step_fixed(self, lanes: np.ndarray) -> Taken:
        """One RK4 step of every lane in ``lanes`` (all share the step index)."""
        t0, t1 = self.settings.span
        self.taken += 1
        h = self.h[lanes]
        t, y, f = self.t[lanes], self.y[lanes], self.f[lanes]
        bad = np.zeros(len(lanes), dtype=bool)
        k = [f]
        for c in (0.5, 0.5, 1.0):
            value, singular = self.field(t + c * h, y + (c * h)[:, None] * k[-1], lanes)
            k.append(value)
            bad |= singular
        y_new = y + (h / 6)[:, None] * (k[0] + 2 * k[1] + 2 * k[2] + k[3])
        last_step = self.taken == self.steps
        t_new = np.full(len(lanes), t1 if last_step else t0 + self.taken * h[0])
        f_new, singular = self.field(t_new, y_new, lanes)
        bad |= singular
        ok = ~bad
        K = np.stack([y[ok], y_new[ok], f[ok], f_new[ok]])
        last = _Last(lanes[ok], t[ok], y[ok], t_new[ok], y_new[ok], K, h[ok])
        finished = np.full(int(ok.sum()), last_step)
        return self.accepted(last, f_new[ok], finished, [(lanes[bad], Status.SINGULAR)])

    def accepted(
        self,
        last: _Last,
        f_new: np.ndarray,
        finished: np.ndarray,
        failed: list[tuple[np.ndarray, int]],
    ) -> Taken:
        """Advance the lanes of an accepted step whose state is finite (the others fail)."""
        finite = np.all(np.isfinite(last.y_new), axis=1)
        failed.append((last.lanes[~finite], Status.NOT_FINITE))
        if not finite.all():
            last = last.where(finite)
            f_new, finished = f_new[finite], finished[finite]
        self.t[last.lanes], self.y[last.lanes], self.f[last.lanes] = last.t_new, last.y_new, f_new
        self.last = last
        return Taken(last.lanes, finished, last.t_old, *_failures(*failed)[3:5])

    def project(self, lanes: np.ndarray, project: Projection) -> None:
        for lane in lanes.tolist():
            self.y[lane] = project(float(self.t[lane]), self.y[lane])
        self.f[lanes], _ = self.field(self.t[lanes], self.y[lanes], lanes)

    # ----------------------------------------------------------------- interpolants

    def dense_output(self, lanes: np.ndarray) -> Dense:
        """The last step's interpolant of ``lanes`` (DOP853: its three extra stages)."""
        last = self.last
        assert last is not None  # the loop asks only after a step
        at = np.searchsorted(last.lanes, lanes)
        t_old, y_old, y_new, h = last.t_old[at], last.y_old[at], last.y_new[at], last.h[at]
        K = last.K[:, at]
        if self.fixed:
            return Dense(HERMITE, t_old, h, y_old, K)
        tb = self.tableau
        P, A_extra, C_extra, D, dop853 = tb.P, tb.A_extra, tb.C_extra, tb.D, tb.dop853
        if not dop853:
            return Dense(RK45, t_old, h, y_old, np.einsum("sai,sk->kai", K[: len(P)], P))
        first = len(K) - len(C_extra)
        for e in range(len(C_extra)):
            s = first + e
            dy = np.einsum("sai,s->ai", K[:s], A_extra[e, :s]) * h[:, None]
            K[s], _ = self.field(t_old + C_extra[e] * h, y_old + dy, lanes)
        delta = y_new - y_old
        f_old, f_new = K[0], K[len(tb.B)]
        F = np.empty((7, *y_old.shape))
        F[0], F[1] = delta, h[:, None] * f_old - delta
        F[2] = 2 * delta - h[:, None] * (f_new + f_old)
        F[3:] = h[None, :, None] * np.einsum("rs,sai->rai", D, K)
        return Dense(DOP853, t_old, h, y_old, F)


class _Last(NamedTuple):
    """The last accepted step of some lanes: what their interpolants are built from."""

    lanes: np.ndarray
    t_old: np.ndarray
    y_old: np.ndarray
    t_new: np.ndarray
    y_new: np.ndarray
    K: np.ndarray
    h: np.ndarray

    def where(self, keep: np.ndarray) -> _Last:
        """The lanes ``keep`` (bool) of this step."""
        return _Last(
            *(v[:, keep] if name == "K" else v[keep] for name, v in self._asdict().items())
        )


def _failures(*groups: tuple[np.ndarray, int]) -> Taken:
    """A Taken of failures only: each group's lanes with its code."""
    lanes = [g for g, _ in groups if len(g)]
    if not lanes:
        return Taken(NOWHERE, NOWHERE)
    codes = [np.full(len(g), code) for g, code in groups if len(g)]
    return Taken(NOWHERE, NOWHERE, NOWHERE, np.concatenate(lanes), np.concatenate(codes))


def _rms(values: np.ndarray) -> np.ndarray:
    return np.sqrt(np.mean(values**2, axis=-1))


def _error_norm(
    K: np.ndarray,
    h: np.ndarray,
    y: np.ndarray,
    y_new: np.ndarray,
    rtol: float,
    atol: float,
    tableau: Tableau,
) -> np.ndarray:
    """Each member's error norm, as SciPy's RK45 and DOP853 compute it."""
    E, E3, dop853 = tableau.E, tableau.E3, tableau.dop853
    scale = atol + np.maximum(np.abs(y), np.abs(y_new)) * rtol
    rows = K[: len(E)]
    if not dop853:
        return _rms(np.einsum("sai,s->ai", rows, E) * h[:, None] / scale)
    e5 = np.sum((np.einsum("sai,s->ai", rows, E) / scale) ** 2, axis=-1)
    e3 = np.sum((np.einsum("sai,s->ai", rows, E3) / scale) ** 2, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        norm = np.abs(h) * e5 / np.sqrt((e5 + 0.01 * e3) * y.shape[-1])
    return np.where((e5 == 0) & (e3 == 0), 0.0, norm)
