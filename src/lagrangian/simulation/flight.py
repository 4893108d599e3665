"""Closed-form flight between impacts: where the motion of a mode is polynomial in t, its
contacts are found as roots of polynomials, not by stepping.

A mode of unilateral contacts whose mass matrix and forces are constant (and whose active
contacts are affine in q) has a constant acceleration a: between events

    q(t0 + s) = q0 + v0 s + a s^2 / 2,        q_dot(t0 + s) = v0 + a s,

free flight (a = 0) or flight under a constant force.  A contact g(q) >= 0 that is a
polynomial of degree <= 2 in q,

    g(q) = c + l . q + q^T H q,

is then a polynomial of degree <= 4 in s along the flight (degree 2 in free flight: the
squared distance of two disks is a quadratic in s), and the contact is met at its first root
where g turns negative.  Each gap holds its few coordinates (a wall one, a pair of disks four),
so every gap's polynomial is a handful of products, all gaps at once in NumPy.

The first contact of a run is the earliest of these roots.  After an impact only the
coordinates whose velocity jumped start a new flight; the gaps that involve none of them keep
their root (their polynomial is the same), so a :class:`Calendar` (the state of one run, like
an event watch) keeps every gap's next contact time and, after each impact, finds again only
those of the gaps whose coordinates moved: the bookkeeping of event-driven molecular dynamics
(Alder & Wainwright, *J. Chem. Phys.* 31, 459, 1959; Rapaport, *The Art of Molecular
Dynamics Simulation*, 2nd ed., 2004, ch. 14), here for any model whose contacts are such
polynomials.

Where the mode has no active contact and a C compiler is at hand, the flights and the lone
impacts between them run in one compiled step (:mod:`lagrangian.numerics.fast.c_flight`,
:func:`_flights`): the same calendar, the same roots, the impulse of a lone contact in the
closed form of :mod:`lagrangian.simulation.impacts`, from the model's own numbers (each gap's
form matrix, its coordinates, M^-1, each contact's restitution), impact after impact; a
contact that needs more (several at once, one without restitution, one coming to rest) goes
back to the piecewise loop, which resolves it as it resolves every impact without a compiler.

>>> import numpy as np
>>> first_crossings(np.array([1.0]), np.array([-2.0]), np.array([0.5]))  # (s - 2)^2/2 - 1
array([0.58578644])
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Sequence
from typing import Any, Protocol

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.numerics.fast import c_flight
from lagrangian.simulation.impacts import SIGN_TOLERANCE, ImpactRecord
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.budget import Budget
from lagrangian.simulation.integrators.events import EventWatch
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.integrators.protocol import Dynamics, Integration, Progress
from lagrangian.symbolic.caches import IdentityCache

#: Most coordinates one gap may involve (its polynomial is kept as a dense block that size).
MOST_COORDINATES = 8
#: Most lone impacts one compiled step resolves before it hands a contact to the piecewise
#: loop (a return to Python for the budget's wall time, progress and Ctrl-C).
IMPACTS_PER_CALL = 4096

#: The compiled flights' numbers of each run's lone impacts, per mode acceleration.
_MODELS: IdentityCache[LoneImpacts, dict[bytes, c_flight.FlightModel]] = IdentityCache()


@dataclasses.dataclass(frozen=True)
class QuadraticGaps:
    """Gaps g_k(q) = c_k + l_k . q_k + q_k^T H_k q_k, each in its own coordinates q_k =
    q[index[k]] (padded with the index n of a coordinate held at 0).

    ``rows`` are the constraint indices of the gaps in the System's list."""

    rows: tuple[int, ...]
    index: np.ndarray
    constant: np.ndarray
    linear: np.ndarray
    quadratic: np.ndarray
    n: int

    @functools.cached_property
    def affine(self) -> np.ndarray:
        """Per gap, whether it is affine in q (no quadratic part)."""
        return ~np.any(self.quadratic != 0, axis=(1, 2))

    def local(self, gaps: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The point (x, 1) at the coordinates of each of the ``gaps`` (0 at the padding)."""
        return np.concatenate((x, (0.0, 1.0)))[self.augmented_index[gaps]]

    def values(self, gaps: np.ndarray, q: np.ndarray) -> np.ndarray:
        """g of the ``gaps`` at q: (q, 1)^T K (q, 1) (``along``)."""
        return self.values_and_gradients(gaps, q, rows=False)[0]

    def gradients(self, gaps: np.ndarray, q: np.ndarray) -> np.ndarray:
        """The rows dg/dq = l + 2 H q of the ``gaps`` at q (one row of length n each)."""
        return self.values_and_gradients(gaps, q)[1]

    def values_and_gradients(
        self, gaps: np.ndarray, q: np.ndarray, rows: bool = True
    ) -> tuple[np.ndarray, np.ndarray]:
        """g and the rows dg/dq of the ``gaps`` at q (the rows empty unless ``rows``): with
        K (q, 1) = (H q + l/2, l.q/2 + c), g = (q, 1) . K (q, 1) and dg/dq twice the first
        entries of K (q, 1), scattered to the gap's coordinates."""
        ql = self.local(gaps, q)
        pushed = np.matmul(self.forms[gaps], ql[..., None])[..., 0]
        values = np.einsum("ki,ki->k", ql, pushed)
        if not rows:
            return values, np.zeros((len(gaps), 0))
        gradients = np.zeros((len(gaps), self.n + 1))
        # a gap's coordinates are distinct but for the padding, where the entry is 0
        gradients[np.arange(len(gaps))[:, None], self.index[gaps]] = 2 * pushed[:, :-1]
        return values, gradients[:, : self.n]

    def along(
        self, gaps: np.ndarray, q: np.ndarray, v: np.ndarray, a: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        """The coefficients (c0, ..., c4) of g(q + v s + a s^2/2) = sum c_j s^j.

        Each gap's form is the symmetric matrix K = [[H, l/2], [l^T/2, c]] of the point
        (x, 1), so that with q~ = (q, 1), v~ = (v, 0), a~ = (a, 0) and the bilinear form
        <x, y> = x^T K y: c0 = <q~, q~>, c1 = 2 <q~, v~>, c2 = <v~, v~> + <q~, a~>,
        c3 = <v~, a~>, c4 = <a~, a~>/4.  The nine forms of every gap are two batched
        products of its small matrices (a gas finds ~200 gaps' roots per collision)."""
        columns = np.zeros((self.n + 2, 3))  # (q, v, a); row n the padding, n + 1 the (1, 0, 0)
        columns[: self.n, 0], columns[: self.n, 1], columns[: self.n, 2] = q, v, a
        columns[self.n + 1, 0] = 1.0
        local = columns[self.augmented_index[gaps]]  # (gaps, width + 1, 3)
        forms = np.matmul(local.transpose(0, 2, 1), np.matmul(self.forms[gaps], local))
        return (
            forms[:, 0, 0],
            2 * forms[:, 0, 1],
            forms[:, 1, 1] + forms[:, 0, 2],
            forms[:, 1, 2],
            forms[:, 2, 2] / 4,
        )

    @functools.cached_property
    def augmented_index(self) -> np.ndarray:
        """Each gap's coordinates, then the index n + 1 of the point's constant 1."""
        return np.hstack((self.index, np.full((len(self.index), 1), self.n + 1)))

    @functools.cached_property
    def forms(self) -> np.ndarray:
        """Each gap's matrix K = [[H, l/2], [l^T/2, c]] (``along``)."""
        k, width = self.linear.shape
        forms = np.zeros((k, width + 1, width + 1))
        forms[:, :width, :width] = self.quadratic
        forms[:, :width, width] = forms[:, width, :width] = self.linear / 2
        forms[:, width, width] = self.constant
        return forms

    @functools.cached_property
    def incidence(self) -> list[np.ndarray]:
        """Per coordinate, the gaps that involve it."""
        return _incidence(self.index, self.n)


def _incidence(index: np.ndarray, n: int) -> list[np.ndarray]:
    gap, slot = np.nonzero(index < n)
    coordinate = index[gap, slot]
    order = np.argsort(coordinate, kind="stable")
    cuts = np.searchsorted(coordinate[order], np.arange(n + 1))
    return [np.unique(gap[order][cuts[i] : cuts[i + 1]]) for i in range(n)]


def quadratic_gaps(
    expressions: Sequence[sp.Expr],
    rows: Sequence[int],
    coordinates: Sequence[sp.Symbol],
    values: dict[sp.Symbol, float],
) -> QuadraticGaps | None:
    """The gaps of ``expressions`` (constraint ``rows``) at the parameter ``values``, or None
    when one is not a polynomial of degree <= 2 in the coordinates alone (it has t or a
    velocity, a function, or more than MOST_COORDINATES coordinates)."""
    n = len(coordinates)
    place = {se.sympify(q): i for i, q in enumerate(coordinates)}
    numbers = {se.sympify(s): float(v) for s, v in values.items()}
    size = len(expressions)
    index = np.full((size, MOST_COORDINATES), n, dtype=np.intp)
    constant, linear = np.zeros(size), np.zeros((size, MOST_COORDINATES))
    quadratic = np.zeros((size, MOST_COORDINATES, MOST_COORDINATES))
    for k, expression in enumerate(expressions):
        found = _taylor(expression, numbers, place)
        if found is None:
            return None
        own, constant[k], gradient, hessian = found
        width = len(own)
        index[k, :width] = [place[s] for s in own]
        linear[k, :width], quadratic[k, :width, :width] = gradient, hessian / 2
    width = max(1, int(np.max(np.sum(index < n, axis=1), initial=1)))  # the widest gap's
    return QuadraticGaps(
        tuple(rows), index[:, :width], constant, linear[:, :width],
        quadratic[:, :width, :width], n,
    )  # fmt: skip


def _taylor(
    expression: sp.Expr, numbers: dict[Any, float], place: dict[Any, int]
) -> tuple[list[Any], float, np.ndarray, np.ndarray] | None:
    """(its coordinates, g, dg/dq, d2g/dq2 at q = 0) of a gap g whose second derivatives are
    numbers: then g is exactly c + l.q + q^T H q / 2 (its Taylor polynomial); None when they
    are not (g is not a polynomial of degree <= 2 in the coordinates alone), when g has
    another symbol or more than MOST_COORDINATES coordinates, or cannot be read.  Found
    with SymEngine (a gas of a hundred disks has 5,350 gaps)."""
    try:
        g = se.sympify(expression).subs(numbers)
        own = sorted(g.free_symbols, key=lambda s: place.get(s, -1))
        if len(own) > MOST_COORDINATES or any(s not in place for s in own):
            return None
        origin = dict.fromkeys(own, 0.0)
        first = [g.diff(s) for s in own]
        second = [[d.diff(s) for s in own] for d in first]
        if any(h.free_symbols for row in second for h in row):
            return None
        value = float(g.subs(origin))
        gradient = np.array([float(d.subs(origin)) for d in first])
        hessian = np.array([[float(h) for h in row] for row in second]).reshape(len(own), -1)
    except (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError):
        return None  # SymEngine cannot read or evaluate it: not a polynomial gap
    numbers_found = np.concatenate(([value], gradient, hessian.ravel()))
    return (own, value, gradient, hessian) if np.all(np.isfinite(numbers_found)) else None


def first_crossings(
    c0: np.ndarray,
    c1: np.ndarray,
    c2: np.ndarray,
    c3: np.ndarray | None = None,
    c4: np.ndarray | None = None,
) -> np.ndarray:
    """Per gap, the first s > 0 where c0 + c1 s + ... + c4 s^4 turns negative (0 when it is
    closing now at g <= 0, inf when never): the quadratics in closed form (the root of the
    stable pair -(c1 + sign(c1) sqrt(D))/2 / c2, c0 / that), the others by their roots."""
    if c3 is None or c4 is None or not (c3.any() or c4.any()):  # every gap a quadratic
        return _quadratic_crossings(c0, c1, c2)
    s = np.full(len(c0), np.inf)
    higher = (c3 != 0) | (c4 != 0)
    low = ~higher
    s[low] = _quadratic_crossings(c0[low], c1[low], c2[low])
    for k in np.flatnonzero(higher):
        s[k] = _polynomial_crossing(np.array([c0[k], c1[k], c2[k], c3[k], c4[k]]))
    return s


def _quadratic_crossings(c0: np.ndarray, c1: np.ndarray, c2: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(c1 * c1 - 4 * c2 * c0, 0.0))
        half = -(c1 + np.where(c1 >= 0, root, -root)) / 2
        r1, r2 = half / c2, c0 / half
        low, high = np.minimum(r1, r2), np.maximum(r1, r2)
        # g turns negative at the smaller root of an upward parabola, the larger of a downward
        down = np.where(c2 > 0, low, high)
        down = np.where(c2 == 0, -c0 / c1, down)
        real = (c1 * c1 - 4 * c2 * c0 >= 0) & np.isfinite(down)
        closing = np.where(c2 == 0, c1 < 0, True)
        s = np.where(real & closing & (down > 0), down, np.inf)
    return np.where((c0 <= 0) & (c1 < 0), 0.0, s)


def _polynomial_crossing(coefficients: np.ndarray) -> float:
    """The first s > 0 where the polynomial (ascending coefficients) turns negative."""
    roots = np.roots(coefficients[::-1])
    real = np.sort(roots[np.abs(roots.imag) <= 1e-12 * (1 + np.abs(roots.real))].real)
    slope = np.polynomial.polynomial.polyder(coefficients)
    if coefficients[0] <= 0 and coefficients[1] < 0:
        return 0.0
    for s in real[real > 0]:
        if np.polynomial.polynomial.polyval(s, slope) < 0:
            return float(s)
    return float("inf")


class Calendar:
    """The next contact time of every gap along the flight of a run (the state of one run):
    after a jump only the gaps whose coordinates moved are found again (module docstring)."""

    def __init__(self, gaps: QuadraticGaps) -> None:
        self.gaps = gaps
        self.incidence = gaps.incidence
        self.times = np.full(len(gaps.rows), np.inf)
        self.origin: tuple[float, np.ndarray, np.ndarray, np.ndarray] | None = None
        self.excluded = np.zeros(len(gaps.rows), dtype=bool)
        #: The time and gap of the latest contact found.
        self.hit: tuple[float, int] = (np.inf, -1)

    def state_at(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(q, q_dot) at t along the flight from the origin."""
        assert self.origin is not None
        t0, q, v, a = self.origin
        s = t - t0
        return q + v * s + a * (s * s / 2), v + a * s

    def next(
        self, t: float, q: np.ndarray, v: np.ndarray, a: np.ndarray, excluded: np.ndarray
    ) -> tuple[float, int]:
        """The first contact (time, gap) of the flight from (t, q, v) with acceleration a,
        the ``excluded`` gaps (active contacts) aside; (inf, -1) for none."""
        stale = self._stale(t, q, v, a, excluded)
        self.origin = (t, q.copy(), v.copy(), a.copy())
        self.excluded = excluded  # a guard's, fixed with its mode
        if stale is None:
            stale = np.arange(len(self.times))
        if len(stale):
            coefficients = self.gaps.along(stale, q, v, a)
            self.times[stale] = t + first_crossings(*coefficients)
        candidates = np.where(excluded, np.inf, self.times) if excluded.any() else self.times
        k = int(np.argmin(candidates))
        self.hit = (float(candidates[k]), k if np.isfinite(candidates[k]) else -1)
        return self.hit

    def _stale(
        self, t: float, q: np.ndarray, v: np.ndarray, a: np.ndarray, excluded: np.ndarray
    ) -> np.ndarray | None:
        """The gaps whose next contact must be found again for the flight from (t, q, v):
        those of the coordinates that left the calendar's flight (a jump) and those whose
        exclusion changed; None for every gap (a new acceleration, or most coordinates
        moved)."""
        if self.origin is None or not np.array_equal(a, self.origin[3]):
            return None
        qp, vp = self.state_at(t)
        moved = np.flatnonzero((qp != q) | (vp != v))
        if len(moved) > len(q) // 2:
            return None
        mark = excluded != self.excluded
        for i in moved.tolist():
            mark[self.incidence[i]] = True
        return np.flatnonzero(mark)


@dataclasses.dataclass(frozen=True)
class LoneImpacts:
    """What a flight needs to resolve a lone contact's impact itself (:func:`_flights`): M^-1
    (constant), each gap's coefficient of restitution (NaN: none) and ``labels`` (its name),
    and the tolerances of the impact rule: contacts within ``simultaneous`` (relative to
    1 + |t|) of another meet it together, a bounce lower than ``contact_tolerance`` rests."""

    inverse_mass: np.ndarray
    restitution: np.ndarray
    labels: tuple[str, ...]
    simultaneous: float
    contact_tolerance: float


class FlightGuard(Protocol):
    """The contact guard of a mode that may move in closed form: its calendar, the gaps its
    mode leaves aside (the active contacts), the mode's constant acceleration at a piece's
    start (None when the mode's motion is not polynomial in t), and what resolves a lone
    impact (None: every impact goes back to the piecewise loop)."""

    __name__: str
    calendar: Calendar
    excluded: np.ndarray
    lone_impacts: LoneImpacts | None

    def acceleration(self, piece: Dynamics, t: float, x: np.ndarray) -> np.ndarray | None: ...


@dataclasses.dataclass(frozen=True)
class FlightIntegrator:
    """The Integrator of a piece of hybrid motion: in closed form up to the first contact
    (module docstring) where the piece's only guard that can fire is a :class:`FlightGuard`
    of a mode with constant acceleration; by ``stepping`` otherwise (the caller's events, a
    transition's guard, a mode whose motion is not polynomial)."""

    stepping: SolverIntegrator

    def run(
        self,
        dynamics: Dynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
        budget: Budget | None = None,
    ) -> Integration:
        """One piece: a flight in closed form where it can be, else stepped; ``budget`` is
        the run's (a flight counts as one step of it, so max_steps bounds the impacts)."""
        functions: tuple[Any, ...] = watch.functions if watch is not None else ()
        guards = [f for f in functions if isinstance(getattr(f, "calendar", None), Calendar)]
        rest = [f for f in functions if f not in guards and not _constant_in_flight(f)]
        t0, x0 = inputs.t_span[0], inputs.x0
        a = guards[0].acceleration(dynamics, t0, x0) if len(guards) == 1 and not rest else None
        if a is None:
            return self.stepping.run(dynamics, inputs, watch, progress, budget)
        guard = guards[0]
        lone = guard.lone_impacts
        alone = lone is not None and not guard.excluded.any()  # no active contact
        if alone and inputs.t_out is not None and c_flight.available():
            assert lone is not None
            return _flights(guard, lone, a, inputs, progress, budget)
        if budget is not None:
            budget.steps += 1
        return _flight(guard, a, inputs, progress)


def _constant_in_flight(function: Any) -> bool:
    """A guard that cannot fire during a flight (an active contact's multiplier, constant
    where the acceleration is)."""
    return bool(getattr(function, "constant_in_flight", False))


def _flight(
    guard: FlightGuard, a: np.ndarray, inputs: Inputs, progress: Progress | None
) -> Integration:
    """The rows of a flight from ``inputs``' start to its first contact or the span's end."""
    (t0, t1), x0 = inputs.t_span, inputs.x0
    n = len(x0) // 2
    calendar = guard.calendar
    t_hit, _ = calendar.next(t0, x0[:n], x0[n:], a, guard.excluded)
    hit = t_hit <= t1
    t_stop = t_hit if hit else t1
    if inputs.t_out is None:
        times = np.array([t0, t_stop]) if t_stop > t0 else np.array([t0])
    else:  # the output times in the flight, then its end at a contact
        t_out = inputs.t_out  # sorted
        times = t_out[np.searchsorted(t_out, t0) : np.searchsorted(t_out, t_stop, "right")]
        if hit and (len(times) == 0 or times[-1] < t_hit):
            times = np.append(times, t_hit)
    q, v = calendar.state_at(np.append(times, t_stop)[:, None])  # type: ignore[arg-type]
    rows = np.hstack((q, v))
    x_stop = rows[-1].copy()
    if progress is not None:
        progress(t_stop)
    events = ((guard.__name__, t_hit, x_stop),) if hit else ()
    return Integration(
        times,
        rows[:-1],
        t_stop,
        x_stop,
        events=events,
        stopped_by=guard.__name__ if hit else None,
    )


def _flights(
    guard: FlightGuard,
    lone: LoneImpacts,
    a: np.ndarray,
    inputs: Inputs,
    progress: Progress | None,
    budget: Budget | None,
) -> Integration:
    """Flights and the lone impacts between them in one compiled step
    (:mod:`lagrangian.numerics.fast.c_flight`), from ``inputs``' start to the span's end or
    the first contact that the piecewise loop resolves (several contacts at once, one without
    restitution or coming to rest, and every ``IMPACTS_PER_CALL``-th): the impacts that
    :func:`_flight` and the piecewise loop would make, one flight a step of the ``budget``."""
    (t0, t1), x0 = inputs.t_span, inputs.x0
    n = len(x0) // 2
    calendar, gaps = guard.calendar, guard.calendar.gaps
    calendar.next(t0, x0[:n], x0[n:], a, guard.excluded)
    models = _MODELS.get(lone, lambda _: {})
    model = models.get(a.tobytes())
    if model is None:  # once per run and mode (a gas of a hundred disks: milliseconds)
        model = c_flight.FlightModel(gaps.augmented_index, gaps.forms, calendar.incidence,
                                     lone.inverse_mass, lone.restitution, a)  # fmt: skip
        models[a.tobytes()] = model
    room = max(64, min(IMPACTS_PER_CALL, 2**21 // (4 * n)))
    if budget is not None:  # the last flight, to the contact left to the loop, is a step
        room = min(room, budget.max_steps - budget.steps - 1)
    t_out = inputs.t_out
    assert t_out is not None
    t_out = t_out[np.searchsorted(t_out, t0) : np.searchsorted(t_out, t1, "right")]
    tolerances = (lone.simultaneous, SIGN_TOLERANCE, lone.contact_tolerance)
    flown = c_flight.fly(model, calendar.times, t0, x0, t1, t_out, room, tolerances)
    if budget is not None:
        budget.steps += len(flown.impact_t) + 1
    hit = flown.code == c_flight.CONTACT
    q, v = flown.x[:n], flown.x[n:]
    calendar.origin = (flown.t, q.copy(), v.copy(), a.copy())
    k = int(np.argmin(calendar.times))
    calendar.hit = (flown.t, flown.hit) if hit else (float(calendar.times[k]), k)
    impacts, events = _impacts(lone.labels, flown)
    if hit:
        events.append((guard.__name__, flown.t, flown.x.copy()))
    if progress is not None:
        progress(flown.t)
    return Integration(
        t_out[: len(flown.rows)],
        flown.rows,
        flown.t,
        flown.x,
        events=tuple(events),
        stopped_by=guard.__name__ if hit else None,
        impacts=impacts,
    )


def _impacts(
    labels: tuple[str, ...], flown: c_flight.Flown
) -> tuple[tuple[ImpactRecord, ...], list[tuple[str, float, np.ndarray]]]:
    """The impacts of a compiled flight as the piecewise loop records them: each an
    ImpactRecord and its event ``impact NAME`` at the state after it."""
    names = [labels[gap] for gap in flown.impact_gap.tolist()]
    befores, afters = list(flown.states[:, 0]), list(flown.states[:, 1])
    times, impulses = flown.impact_t.tolist(), flown.impulses.tolist()
    records = [
        ImpactRecord(t, (name,), (impulse,), before, after)
        for t, name, impulse, before, after in zip(times, names, impulses, befores, afters)
    ]
    events = [(f"impact {name}", t, after) for t, name, after in zip(times, names, afters)]
    return tuple(records), events
