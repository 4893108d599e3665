"""Right-hand sides that jump: sign and Heaviside of the state, integrated mode by mode.

Coulomb friction (``-mu N sign(x_dot)``), a V-shaped well (``-k sign(x)``) or a force switched
on at a time (``f0 Heaviside(t - t1)``) make the equations of motion discontinuous across the
*switching surfaces* u_k(t, q, q_dot) = 0, the arguments of their sign and Heaviside functions.
An adaptive integrator stepping across such a surface loses its order, and where both sides
push towards the surface (a block stuck by friction) it chatters with ever smaller steps and
never ends.  So the motion is integrated as Filippov's theory of discontinuous systems has it
(A. F. Filippov, *Differential Equations with Discontinuous Righthand Sides*, 1988, §2; for
friction: D. Karnopp, *J. Dyn. Syst. Meas. Control* 107, 1985):

* in a **mode** every sign(u_k) is a constant s_k = +-1 (Heaviside(u_k) = (1 + s_k)/2), the
  field f_s is smooth and integrated as usual, and each u_k is an event;
* at an event on u_k the fields on both sides, f+ and f-, tell what happens: the motion
  **crosses** to the other side when both carry it the same way (s_k flips), and **slides**
  on the surface when both push towards it, du/dt|+ < 0 < du/dt|-.  Sliding follows the
  convex combination

      f = (1 + lam)/2 f+ + (1 - lam)/2 f-,      lam = -(u'+ + u'-) / (u'+ - u'-),

  which keeps du/dt = 0 (for friction: the block sticks, held by the static friction
  lam mu N); it ends when |lam| reaches 1 (the applied forces exceed what friction can hold)
  and the motion leaves on that side.

The surfaces are found in the equations of motion (:func:`switching_functions`); one slides
at a time (a second sliding surface is refused by name).  Between the switches any solve_ivp
method steps; the rows of the modes are joined into one Trajectory.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulation.dynamics import WithoutConstraints
from lagrangian.simulation.inputs import Inputs
from lagrangian.simulation.integrators.events import EventFunction, EventWatch
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.integrators.piecewise import continued_from, joined
from lagrangian.simulation.integrators.protocol import Integration, Progress
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.frozen import FrozenMapping

#: |du/dt| below this (relative to the field's size) counts as zero when deciding a switch.
DECISION_TOLERANCE = 1e-12


def switching_functions(eom: EquationsOfMotion) -> tuple[sp.Expr, ...]:
    """The arguments u_k of sign and Heaviside in the equations of motion that depend on the
    state or on time (their zeros are where the right-hand side jumps), in a fixed order;
    found once per equations (every run asks)."""
    return _SURFACES.get(eom, _surfaces)


_SURFACES: IdentityCache[EquationsOfMotion, tuple[sp.Expr, ...]] = IdentityCache()


def _surfaces(eom: EquationsOfMotion) -> tuple[sp.Expr, ...]:
    state = {*eom.coordinates, *eom.velocities, eom.time}
    found: dict[sp.Expr, None] = {}
    for expr in (*eom.mass_matrix, *eom.forcing):
        for f in expr.atoms(sp.sign, sp.Heaviside):
            if f.args[0].free_symbols & state:
                found[f.args[0]] = None
    return tuple(sorted(found, key=sp.default_sort_key))


def has_switching(eom: EquationsOfMotion) -> bool:
    """True when the right-hand side jumps across a surface of the state or of time."""
    return bool(switching_functions(eom))


@dataclasses.dataclass
class SwitchedDynamics(WithoutConstraints):
    """The equations with each sign(u_k) replaced by a parameter s_k (the mode), and the
    switching functions u_k with their rates du_k/dt along a field."""

    eom: EquationsOfMotion
    p: np.ndarray
    multiplier_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        eom = self.eom
        if any(eom.coordinate_orders[q] != 2 for q in eom.coordinates):
            raise SimulationError(
                "sign or Heaviside of the state in equations with first-order coordinates: "
                "switching is located for coordinates with inertia only"
            )
        self.surfaces = switching_functions(eom)
        modes = sp.symbols(f"_mode0:{len(self.surfaces)}")
        rule = dict(zip(self.surfaces, modes, strict=True))
        moded = dataclasses.replace(
            eom,
            mass_matrix=_replaced(eom.mass_matrix, rule),
            forcing=_replaced(eom.forcing, rule),
            parameters=FrozenMapping({**eom.parameters, **dict.fromkeys(modes)}),
        )
        self.compiled: CompiledEquations = compile_equations(moded)
        q, qd, t = list(eom.coordinates), list(eom.velocities), eom.time
        groups = (q, qd, t, list(eom.parameters))
        self._u = NumericFunction(groups, list(self.surfaces), (len(self.surfaces),))
        gradient = [u.diff(v) for u in self.surfaces for v in (*q, *qd, t)]
        self._gradient = NumericFunction(groups, gradient, (len(self.surfaces), 2 * len(q) + 1))
        self.n = len(q)
        self.mode = np.ones(len(self.surfaces))
        self.sliding: int | None = None

    # -- the Motion protocol ------------------------------------------------------------
    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[: self.n], x[self.n :]

    # -- the modes ----------------------------------------------------------------------
    def values(self, t: float, x: np.ndarray) -> np.ndarray:
        """u_k at (t, x)."""
        return np.asarray(self._u(x[: self.n], x[self.n :], t, self.p), dtype=float)

    def field_in(self, mode: np.ndarray, t: float, x: np.ndarray) -> np.ndarray:
        return self.compiled.rhs(t, x, np.concatenate([self.p, mode]))

    def sides(self, k: int, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The fields f+ and f- (s_k = +1, -1, the others as in the mode) and the gradient of
        u_k in (q, q_dot, t): everything a switch or a slide on surface k needs, two field
        evaluations."""
        grad = np.asarray(self._gradient(x[: self.n], x[self.n :], t, self.p))[k]
        plus, minus = self.mode.copy(), self.mode.copy()
        plus[k], minus[k] = 1.0, -1.0
        return self.field_in(plus, t, x), self.field_in(minus, t, x), grad

    def rates(self, k: int, t: float, x: np.ndarray) -> tuple[float, float, float]:
        """du_k/dt along f+ and f-, and the size of the terms (for the tolerance of a
        decision)."""
        up, down, scale, _, _ = self._rates_and_fields(k, t, x)
        return up, down, scale

    def sliding_share(self, k: int, t: float, x: np.ndarray) -> tuple[float, np.ndarray]:
        """lam and the Filippov field on the surface u_k = 0."""
        up, down, _, f_plus, f_minus = self._rates_and_fields(k, t, x)
        lam = -(up + down) / (up - down) if up != down else 0.0
        return lam, (1 + lam) / 2 * f_plus + (1 - lam) / 2 * f_minus

    def _rates_and_fields(
        self, k: int, t: float, x: np.ndarray
    ) -> tuple[float, float, float, np.ndarray, np.ndarray]:
        f_plus, f_minus, grad = self.sides(k, t, x)
        up = float(grad[:-1] @ f_plus + grad[-1])
        down = float(grad[:-1] @ f_minus + grad[-1])
        largest = max(np.abs(f_plus).max(), np.abs(f_minus).max())
        scale = float(np.abs(grad[:-1]).sum() * largest) + abs(grad[-1]) + 1e-300
        return up, down, scale, f_plus, f_minus

    def decide(self, k: int, t: float, x: np.ndarray, moving: float) -> str:
        """At u_k = 0: set the mode of surface k and say "slide", "plus" or "minus";
        ``moving`` is the side the motion arrives from (its old s_k)."""
        up, down, scale = self.rates(k, t, x)
        tolerance = DECISION_TOLERANCE * scale
        if up <= tolerance and down >= -tolerance and (up < -tolerance or down > tolerance):
            if self.sliding is not None and self.sliding != k:
                raise SimulationError(
                    f"the motion slides on two switching surfaces at once, {self.surfaces[k]} "
                    f"= 0 and {self.surfaces[self.sliding]} = 0, at t = {t:.6g}: not supported"
                )
            self.sliding = k
            return "slide"
        if up > tolerance and down > tolerance:
            side = 1.0
        elif up < -tolerance and down < -tolerance:
            side = -1.0
        else:  # both fields leave the surface (or the surface is touched): keep going
            side = -moving
        return self.leave(k, side)

    def leave(self, k: int, side: float) -> str:
        """Continue on the side ``side`` (+1, -1) of surface k (ending a slide on it)."""
        self.mode[k] = side
        if self.sliding == k:
            self.sliding = None
        return "plus" if side > 0 else "minus"


@dataclasses.dataclass(frozen=True)
class _Piece(WithoutConstraints):
    """One mode of a SwitchedDynamics as a Dynamics (the field of its mode, or the Filippov
    field while it slides)."""

    switched: SwitchedDynamics
    mode: np.ndarray
    sliding: int | None
    multiplier_names: tuple[str, ...] = ()

    def field(self, t: float, x: np.ndarray) -> np.ndarray:
        if self.sliding is None:
            return self.switched.field_in(self.mode, t, x)
        return self.switched.sliding_share(self.sliding, t, x)[1]

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.switched.unpack(t, x)


class _Surface:
    """The event of a surface: u_k crossing zero in a mode, or |lam| reaching 1 in a slide.

    Its value is positive inside the piece (u_k s_k, 1 - |lam|) and the event fires only where
    it turns negative, so the zero a piece starts from is not found again."""

    terminal = True
    direction = -1.0

    def __init__(self, switched: SwitchedDynamics, k: int, sliding: bool) -> None:
        self.switched, self.k, self.sliding = switched, k, sliding
        self.__name__ = f"switch {switched.surfaces[k]}"

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        x = np.concatenate([q, q_dot])
        if self.sliding:
            lam, _ = self.switched.sliding_share(self.k, t, x)
            return 1.0 - abs(lam)
        return float(self.switched.values(t, x)[self.k]) * self.switched.mode[self.k]


@dataclasses.dataclass(frozen=True)
class SwitchedIntegrator:
    """Integrates mode by mode with a SciPy solver, deciding at every switch (module
    docstring); the caller's events are watched throughout."""

    inner: SolverIntegrator = SolverIntegrator()

    def run(
        self,
        dynamics: SwitchedDynamics,
        inputs: Inputs,
        watch: EventWatch | None,
        progress: Progress | None,
    ) -> Integration:
        own: Sequence[EventFunction] = watch.functions if watch is not None else ()
        counts = np.zeros(len(own), dtype=int)
        t0, t1 = inputs.t_span
        switches = _first_mode(dynamics, t0, inputs.x0)
        pieces: list[Integration] = []
        current = inputs
        while True:
            piece = _Piece(dynamics, dynamics.mode.copy(), dynamics.sliding)
            surfaces = [
                _Surface(dynamics, k, sliding=k == dynamics.sliding)
                for k in range(len(dynamics.surfaces))
            ]
            piece_watch = EventWatch([*own, *surfaces], piece.unpack)
            piece_watch.counts[: len(own)] = counts
            run = self.inner.run(piece, current, piece_watch, progress)
            counts = piece_watch.counts[: len(own)].copy()
            surface = next((s for s in surfaces if s.__name__ == run.stopped_by), None)
            mine = {s.__name__ for s in surfaces}
            events = tuple(e for e in run.events if e[0] not in mine)
            pieces.append(_on_output_times(run, current, (*switches, *events)))
            if run.status != "success" or surface is None:
                break
            _, t_switch, x_switch = run.events[-1]
            if surface.sliding:  # leaves the surface on the side lam reached
                lam, _ = dynamics.sliding_share(surface.k, t_switch, x_switch)
                outcome = dynamics.leave(surface.k, 1.0 if lam > 0 else -1.0)
            else:
                arriving = dynamics.mode[surface.k]
                outcome = dynamics.decide(surface.k, t_switch, x_switch, arriving)
            switches = [(f"{surface.__name__}: {outcome}", t_switch, x_switch)]
            pieces[-1] = dataclasses.replace(pieces[-1], stopped_by=None)
            if t_switch >= t1:
                break
            current = continued_from(current, t_switch, x_switch)
        return joined(pieces)


def _on_output_times(
    run: Integration, inputs: Inputs, events: tuple[tuple[str, float, np.ndarray], ...]
) -> Integration:
    """A piece with ``events`` and, when output times are given, only their rows (not the
    row of the switch that ends it)."""
    run = dataclasses.replace(run, events=events)
    if inputs.t_out is None:
        return run
    keep = np.isin(run.t, inputs.t_out)
    return dataclasses.replace(run, t=run.t[keep], x=run.x[keep])


def _first_mode(
    dynamics: SwitchedDynamics, t: float, x: np.ndarray
) -> list[tuple[str, float, np.ndarray]]:
    """The mode at the start: the sign of each u_k, decided as at a switch where u_k = 0
    (those decisions are the first events: a block at rest starts stuck)."""
    u = dynamics.values(t, x)
    dynamics.mode = np.where(u < 0, -1.0, 1.0)
    dynamics.sliding = None
    decided = []
    for k in np.flatnonzero(u == 0):
        outcome = dynamics.decide(int(k), t, x, moving=-1.0)
        decided.append((f"switch {dynamics.surfaces[k]}: {outcome}", t, np.array(x)))
    return decided


def _replaced(matrix: sp.MatrixBase, modes: dict[sp.Expr, sp.Symbol]) -> sp.ImmutableMatrix:
    """The entries with sign(u_k) -> s_k and Heaviside(u_k) -> (1 + s_k)/2 (the classes of
    :mod:`lagrangian.symbolic.nonsmooth` and SymPy's alike)."""

    def swap(f: sp.Basic) -> sp.Expr:
        s = modes.get(f.args[0])
        if s is None:
            return f
        return s if isinstance(f, sp.sign) else (1 + s) / 2

    def swapped(e: sp.Expr) -> sp.Expr:
        return e.replace(lambda f: isinstance(f, (sp.sign, sp.Heaviside)), swap)

    return sp.ImmutableMatrix(matrix.applyfunc(swapped))
