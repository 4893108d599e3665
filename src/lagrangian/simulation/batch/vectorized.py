"""A batch of integrations vectorized with NumPy: every member keeps its own adaptive step.

Each iteration makes one trial step for every running member at once (one call of the
right-hand side per stage on a (members, state) array), each with its own step h_i and time
t_i, and accepts or rejects each member by its own error norm with SciPy's rules
(SciPy's ``RungeKutta``, as the C loop).  Per-member control rather than one shared step:
members of a chaotic ensemble need very different steps, a shared step would be the smallest
for all, and with its own steps member i of a batch is the run of member i alone (the same
steps as solve_ivp).  Members that finished, stopped or failed leave the arrays, so the work
shrinks with them.  RK4 (fixed step) uses the same loop without rejections.

Output rows come from each step's dense output at the shared output times; a stop condition
g(t, q, q_dot) (vectorized: arrays (members,) and (members, n)) ends a member where g turns
negative, its time found on the dense output by the Illinois method, vectorized too.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.numerics.fast.settings import Settings
from lagrangian.numerics.fast.tableaus import Tableau, fixed_steps, tableau_of
from lagrangian.numerics.status import Status
from lagrangian.simulation.batch.dense import DOP853, HERMITE, RK45, Dense, locate_stops

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
ULP = float(np.finfo(float).eps)


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
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Integrate every row of X0 (parameters: the same row of P).

    Returns (out (members, times, state) with NaN after a stop or failure, status, t_final,
    x_final): status codes of :class:`~lagrangian.numerics.status.Status`, the time and state
    each member ended at (the end, its stop, or its last accepted step).  ``progress`` gets
    the smallest time reached by a running member after each iteration.
    """
    run = _Run(compiled, settings, X0, P, stop_when)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        run.start()
        while len(run.active):
            run.iterate()
            if progress is not None and len(run.active):
                progress(float(np.min(run.t[run.active])))
    if progress is not None:
        progress(settings.span[1])
    return run.out, run.status, run.t_final, run.x_final


class _Run:
    """The state of a batch run: per member t, x, f, h, status, next output row."""

    def __init__(
        self,
        compiled: CompiledEquations,
        settings: Settings,
        X0: np.ndarray,
        P: np.ndarray,
        stop_when: Callable[..., Any] | None,
    ) -> None:
        k, nx = X0.shape
        self.compiled, self.settings, self.stop_when = compiled, settings, stop_when
        self.n = len(compiled.coordinates)
        self.field = _Field(compiled, P)
        self.tableau = tableau_of(settings.method)
        self.fixed = self.tableau.fixed
        self.t, self.x = np.full(k, settings.span[0]), X0.astype(float).copy()
        self.f, self.h = np.zeros((k, nx)), np.zeros(k)
        self.rejected = np.zeros(k, dtype=bool)
        self.trials = np.zeros(k, dtype=np.int64)  # trial steps per member, for max_steps
        self.g = np.ones(k)
        self.status = np.full(k, Status.FINISHED)
        self.t_final, self.x_final = np.full(k, settings.span[1]), self.x.copy()
        t_out = settings.t_out
        self.out = np.full((k, len(t_out), nx), np.nan)
        first = int(np.searchsorted(t_out, settings.span[0], side="right"))
        self.out[:, :first] = X0[:, None, :]
        self.row = np.full(k, first)
        self.active = np.arange(k)

    # ----------------------------------------------------------------- start and end

    def start(self) -> None:
        rows = self.active
        self.f[rows], bad = self.field(self.t[rows], self.x[rows], rows)
        self.end(rows[bad], Status.SINGULAR)
        rows = self.active
        if self.stop_when is not None:
            self.g[rows] = self.condition(self.t[rows], self.x[rows], self.f[rows])
            stopped = rows[~(self.g[rows] >= 0)]
            self.t_final[stopped], self.x_final[stopped] = self.t[stopped], self.x[stopped]
            self.end(stopped, Status.STOPPED)
        rows = self.active
        if self.fixed:
            t0, t1 = self.settings.span
            self.steps = fixed_steps(t0, t1, float(self.settings.dt or 1.0))
            self.h[:] = (t1 - t0) / self.steps
            self.taken = 0
        else:
            self.h[rows] = self.initial_step(rows)

    def end(self, rows: np.ndarray, status: int) -> None:
        """Members ``rows`` leave the run with ``status`` (their final state set already,
        except after a failure: the last accepted step)."""
        if len(rows) == 0:
            return
        self.status[rows] = status
        if status not in (Status.FINISHED, Status.STOPPED):
            self.t_final[rows], self.x_final[rows] = self.t[rows], self.x[rows]
        self.active = np.setdiff1d(self.active, rows, assume_unique=True)

    def condition(self, t: np.ndarray, x: np.ndarray, f: np.ndarray) -> np.ndarray:
        assert self.stop_when is not None
        n = self.n
        values = np.asarray(self.stop_when(t, x[:, :n], f[:, :n]), dtype=float)
        return np.broadcast_to(values, t.shape).astype(float)

    # ----------------------------------------------------------------- steps

    def initial_step(self, rows: np.ndarray) -> np.ndarray:
        """SciPy's select_initial_step, member by member (vectorized)."""
        s = self.settings
        t0, y0, f0 = self.t[rows], self.x[rows], self.f[rows]
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
        self.end(rows[bad], Status.SINGULAR)
        return np.minimum(np.minimum(100 * h0, h1), min(interval, s.max_step))

    def iterate(self) -> None:
        """One trial step of every running member; accepted ones advance."""
        if self.fixed:
            self.iterate_fixed()
            return
        s, tableau = self.settings, self.tableau
        rows = self.active
        if s.max_steps is not None:
            self.trials[rows] += 1
            self.end(rows[self.trials[rows] > s.max_steps], Status.STEP_BUDGET)
            rows = self.active
        t, y, f = self.t[rows], self.x[rows], self.f[rows]
        min_step = 10 * np.abs(np.nextafter(t, np.inf) - t)
        h_abs = self.h[rows]
        fresh = ~self.rejected[rows]  # a new step: clamp as SciPy does before its loop
        h_abs = np.where(fresh & (h_abs > s.max_step), s.max_step, h_abs)
        h_abs = np.where(fresh & (h_abs < min_step), min_step, h_abs)
        small = h_abs < min_step
        self.end(rows[small], Status.STEP_TOO_SMALL)
        rows, t, y, f, h_abs = rows[~small], t[~small], y[~small], f[~small], h_abs[~small]
        t_new = np.minimum(t + h_abs, s.span[1])
        h = t_new - t
        K, y_new, bad = self.stages(rows, t, y, f, h)
        err = _error_norm(K, h, y, y_new, s.rtol, s.atol, tableau)
        exponent = -1 / (tableau.error_order + 1)
        accept = (err < 1) & ~bad
        with np.errstate(divide="ignore"):
            grow = np.where(err == 0, MAX_FACTOR, np.minimum(MAX_FACTOR, SAFETY * err**exponent))
            shrink = SAFETY * err**exponent
        grow = np.where(self.rejected[rows], np.minimum(1.0, grow), grow)
        shrink = np.where(shrink > MIN_FACTOR, shrink, MIN_FACTOR)  # NaN error: shrink by 0.2
        self.h[rows] = np.abs(h) * np.where(accept, grow, shrink)
        self.rejected[rows] = ~accept
        self.end(rows[bad], Status.SINGULAR)
        a = accept
        self.advance(rows[a], t[a], y[a], f[a], t_new[a], y_new[a], K[:, a], h[a])

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

    def iterate_fixed(self) -> None:
        """One RK4 step of every running member (all share the step index)."""
        rows = self.active
        t0, t1 = self.settings.span
        self.taken += 1
        h = self.h[rows]
        t, y, f = self.t[rows], self.x[rows], self.f[rows]
        bad = np.zeros(len(rows), dtype=bool)
        k = [f]
        for c in (0.5, 0.5, 1.0):
            value, singular = self.field(t + c * h, y + (c * h)[:, None] * k[-1], rows)
            k.append(value)
            bad |= singular
        y_new = y + (h / 6)[:, None] * (k[0] + 2 * k[1] + 2 * k[2] + k[3])
        t_new = np.full(len(rows), t1 if self.taken == self.steps else t0 + self.taken * h[0])
        f_new, singular = self.field(t_new, y_new, rows)
        bad |= singular
        self.end(rows[bad], Status.SINGULAR)
        ok = ~bad
        K = np.stack([y[ok], y_new[ok], f[ok], f_new[ok]])
        self.advance(rows[ok], t[ok], y[ok], f[ok], t_new[ok], y_new[ok], K, h[ok], f_new[ok])

    # ----------------------------------------------------------------- after a step

    def advance(
        self,
        rows: np.ndarray,
        t_old: np.ndarray,
        y_old: np.ndarray,
        f_old: np.ndarray,
        t_new: np.ndarray,
        y_new: np.ndarray,
        K: np.ndarray,
        h: np.ndarray,
        f_new: np.ndarray | None = None,
    ) -> None:
        """Accept a step of members ``rows``: output rows, stop condition, the end."""
        finite = np.all(np.isfinite(y_new), axis=1)
        self.end(rows[~finite], Status.NOT_FINITE)
        rows, t_old, y_old, f_old = rows[finite], t_old[finite], y_old[finite], f_old[finite]
        t_new, y_new, K, h = t_new[finite], y_new[finite], K[:, finite], h[finite]
        f_new = K[len(self.tableau.B)] if f_new is None else f_new[finite]
        self.t[rows], self.x[rows], self.f[rows] = t_new, y_new, f_new
        stopped = np.zeros(len(rows), dtype=bool)
        if self.stop_when is not None:
            g_new = self.condition(t_new, y_new, f_new)
            stopped = ~(g_new >= 0)
        t_out, row = self.settings.t_out, self.row[rows]
        sampled = (row < len(t_out)) & (t_out[np.minimum(row, len(t_out) - 1)] <= t_new)
        local = np.flatnonzero(sampled | stopped)
        if len(local):
            dense = self.dense(
                rows[local],
                t_old[local],
                y_old[local],
                y_new[local],
                f_new[local],
                K[:, local],
                h[local],
            )
            t_end = t_new[local].copy()
            ends = np.flatnonzero(stopped[local])
            if len(ends):
                t_end[ends] = locate_stops(
                    dense,
                    ends,
                    self.g[rows[local][ends]],
                    t_new[local][ends],
                    g_new[local][ends],
                    lambda c, x, m: self.condition_at(c, x, rows[local][m]),
                )
                members = rows[local][ends]
                self.t_final[members] = t_end[ends]
                self.x_final[members] = dense.value(t_end[ends], ends)
            self.sample(rows[local], dense, t_end)
        if self.stop_when is not None:
            self.g[rows] = g_new
        self.end(rows[stopped], Status.STOPPED)
        done = ~stopped & (t_new >= self.settings.span[1])
        self.t_final[rows[done]], self.x_final[rows[done]] = t_new[done], y_new[done]
        self.end(rows[done], Status.FINISHED)

    def sample(self, rows: np.ndarray, dense: Dense, t_end: np.ndarray) -> None:
        """Output rows of members ``rows`` at the output times up to t_end (per member)."""
        t_out = self.settings.t_out
        while True:
            row = self.row[rows]
            pending = np.flatnonzero(
                (row < len(t_out)) & (t_out[np.minimum(row, len(t_out) - 1)] <= t_end)
            )
            if len(pending) == 0:
                return
            times = t_out[row[pending]]
            self.out[rows[pending], row[pending]] = dense.value(times, pending)
            self.row[rows[pending]] += 1

    def dense(
        self,
        rows: np.ndarray,
        t_old: np.ndarray,
        y_old: np.ndarray,
        y_new: np.ndarray,
        f_new: np.ndarray,
        K: np.ndarray,
        h: np.ndarray,
    ) -> Dense:
        """The step's interpolant for members ``rows`` (DOP853: its three extra stages)."""
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
            K[s], _ = self.field(t_old + C_extra[e] * h, y_old + dy, rows)
        delta = y_new - y_old
        f_old = K[0]
        F = np.empty((7, *y_old.shape))
        F[0], F[1] = delta, h[:, None] * f_old - delta
        F[2] = 2 * delta - h[:, None] * (f_new + f_old)
        F[3:] = h[None, :, None] * np.einsum("rs,sai->rai", D, K)
        return Dense(DOP853, t_old, h, y_old, F)

    def condition_at(self, t: np.ndarray, x: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """g at states x of members ``rows`` (q_dot from the right-hand side)."""
        f, bad = self.field(t, x, rows)
        return np.where(bad, np.nan, self.condition(t, x, f))


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
