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
* a surface of the configuration alone, u_k(q, t) (a kink of the potential: ``Abs(x)``,
  ``x*sign(x)``), is met with du/dt the same on both sides: the fields differ in the
  accelerations only.  Where the motion reaches it with du/dt = 0 (at rest at the bottom of
  a V-shaped well) the second derivatives decide, as the first ones do above: both pushing
  towards the surface, d2u/dt2|+ < 0 < d2u/dt2|-, the motion **rests on the kink** (sliding
  of the second order: u = 0 and du/dt = 0 kept by the same convex combination, lam now
  making d2u/dt2 = 0; Filippov, §19), until |lam| reaches 1.

The surfaces are found in the equations of motion (:func:`switching_functions`); one slides
at a time (a second sliding surface is refused by name).  A mode is a value
(:class:`SwitchMode`); the piecewise loop (:mod:`lagrangian.simulation.integrators.piecewise`)
integrates mode by mode with any solve_ivp method and joins the rows into one Trajectory.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import sympy as sp

from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.compile import CompiledEquations, compile_equations
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.simulation.dynamics import WithoutConstraints
from lagrangian.simulation.integrators.piecewise import Guard, Jump, Record
from lagrangian.simulation.integrators.protocol import Dynamics, Integration
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


class SwitchMode(NamedTuple):
    """A mode of a switched right-hand side: s_k = +-1 for every surface (``signs``), the
    surface the motion slides on, or None, and the ``order`` of that slide (1: u = 0 kept
    by du/dt = 0; 2: resting on a kink, u = du/dt = 0 kept by d2u/dt2 = 0)."""

    signs: tuple[float, ...]
    sliding: int | None = None
    order: int = 1

    def leaving(self, k: int, side: float) -> SwitchMode:
        """The mode on the side ``side`` (+1, -1) of surface k (ending a slide on it)."""
        signs = list(self.signs)
        signs[k] = side
        if self.sliding == k:
            return SwitchMode(tuple(signs))
        return SwitchMode(tuple(signs), self.sliding, self.order)

    def sliding_on(self, k: int, order: int = 1) -> SwitchMode:
        """The mode sliding on surface k (resting on it with ``order`` 2)."""
        return SwitchMode(self.signs, k, order)


@dataclasses.dataclass(frozen=True)
class SwitchedDynamics(WithoutConstraints):
    """The equations with each sign(u_k) replaced by a parameter s_k (the mode), and the
    switching functions u_k with their rates du_k/dt along a field: the
    :class:`~lagrangian.simulation.integrators.piecewise.Hybrid` of a switched right-hand side
    (module docstring), its modes :class:`SwitchMode` values."""

    eom: EquationsOfMotion
    p: np.ndarray
    multiplier_names: tuple[str, ...] = ()
    compiled: CompiledEquations = dataclasses.field(init=False, repr=False)
    surfaces: tuple[sp.Expr, ...] = dataclasses.field(init=False, repr=False)
    functions: tuple[NumericFunction, NumericFunction, NumericFunction] = dataclasses.field(
        init=False, repr=False
    )
    #: Whether each surface is one of the configuration alone (u_k(q, t): a kink to rest on).
    kinks: tuple[bool, ...] = dataclasses.field(init=False, repr=False)

    def __post_init__(self) -> None:
        eom = self.eom
        if any(eom.coordinate_orders[q] != 2 for q in eom.coordinates):
            raise SimulationError(
                "sign or Heaviside of the state in equations with first-order coordinates: "
                "switching is located for coordinates with inertia only"
            )
        surfaces = switching_functions(eom)
        q, qd, t = list(eom.coordinates), list(eom.velocities), eom.time
        groups = (q, qd, t, list(eom.parameters))
        values = NumericFunction(groups, list(surfaces), (len(surfaces),))
        gradient = [u.diff(v) for u in surfaces for v in (*q, *qd, t)]
        rates = NumericFunction(groups, gradient, (len(surfaces), 2 * len(q) + 1))
        # du/dt of a surface u(q, t), whose gradient gives d2u/dt2 along a field (the rest on
        # a kink); zero for a surface of the velocities, never rested on
        kinks = tuple(not (u.free_symbols & set(qd)) for u in surfaces)
        first = [_rate(u, q, qd, t) if kink else sp.S.Zero for u, kink in zip(surfaces, kinks)]
        second = [w.diff(v) for w in first for v in (*q, *qd, t)]
        second_rates = NumericFunction(groups, second, (len(surfaces), 2 * len(q) + 1))
        # a frozen value filled once, here: the compiled forms of the same equations
        object.__setattr__(self, "surfaces", surfaces)
        object.__setattr__(self, "kinks", kinks)
        object.__setattr__(self, "compiled", _moded_equations(eom))
        object.__setattr__(self, "functions", (values, rates, second_rates))

    @property
    def n(self) -> int:
        return len(self.eom.coordinates)

    # -- the Motion protocol ------------------------------------------------------------
    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return x[: self.n], x[self.n :]

    # -- the modes ----------------------------------------------------------------------
    def values(self, t: float, x: np.ndarray) -> np.ndarray:
        """u_k at (t, x)."""
        return np.asarray(self.functions[0](x[: self.n], x[self.n :], t, self.p), dtype=float)

    def field_in(self, signs: Sequence[float], t: float, x: np.ndarray) -> np.ndarray:
        return self.compiled.rhs(t, x, np.concatenate([self.p, signs]))

    def sides(
        self, mode: SwitchMode, k: int, t: float, x: np.ndarray, order: int = 1
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The fields f+ and f- (s_k = +1, -1, the others as in the mode) and the gradient of
        u_k in (q, q_dot, t) (``order`` 2: of du_k/dt): everything a switch or a slide on
        surface k needs, two field evaluations."""
        gradients = self.functions[order]
        grad = np.asarray(gradients(x[: self.n], x[self.n :], t, self.p))[k]
        plus, minus = mode.leaving(k, 1.0).signs, mode.leaving(k, -1.0).signs
        return self.field_in(plus, t, x), self.field_in(minus, t, x), grad

    def rates(
        self, mode: SwitchMode, k: int, t: float, x: np.ndarray, order: int = 1
    ) -> tuple[float, float, float]:
        """du_k/dt (``order`` 2: d2u_k/dt2) along f+ and f-, and the size of the terms (for
        the tolerance of a decision)."""
        up, down, scale, _, _ = self._rates_and_fields(mode, k, t, x, order)
        return up, down, scale

    def sliding_share(
        self, mode: SwitchMode, k: int, t: float, x: np.ndarray
    ) -> tuple[float, np.ndarray]:
        """lam and the Filippov field on the surface u_k = 0 (resting on it: on u_k = 0 and
        du_k/dt = 0, the order of the mode)."""
        order = mode.order if mode.sliding == k else 1
        up, down, _, f_plus, f_minus = self._rates_and_fields(mode, k, t, x, order)
        lam = -(up + down) / (up - down) if up != down else 0.0
        return lam, (1 + lam) / 2 * f_plus + (1 - lam) / 2 * f_minus

    def _rates_and_fields(
        self, mode: SwitchMode, k: int, t: float, x: np.ndarray, order: int = 1
    ) -> tuple[float, float, float, np.ndarray, np.ndarray]:
        f_plus, f_minus, grad = self.sides(mode, k, t, x, order)
        up = float(grad[:-1] @ f_plus + grad[-1])
        down = float(grad[:-1] @ f_minus + grad[-1])
        largest = max(np.abs(f_plus).max(), np.abs(f_minus).max())
        scale = float(np.abs(grad[:-1]).sum() * largest) + abs(grad[-1]) + 1e-300
        return up, down, scale, f_plus, f_minus

    def decide(
        self, mode: SwitchMode, k: int, t: float, x: np.ndarray, moving: float
    ) -> tuple[SwitchMode, str]:
        """At u_k = 0: the mode after surface k, and "slide", "plus" or "minus"; ``moving``
        is the side the motion arrives from (its old s_k)."""
        up, down, scale = self.rates(mode, k, t, x)
        tolerance = DECISION_TOLERANCE * scale
        order, outcome = 1, "slide"
        if self.kinks[k] and abs(up) <= tolerance and abs(down) <= tolerance:
            # on a kink with du/dt = 0 on both sides: the accelerations decide
            order, outcome = 2, "rest"
            up, down, scale = self.rates(mode, k, t, x, order=2)
            tolerance = DECISION_TOLERANCE * scale
        if up <= tolerance and down >= -tolerance and (up < -tolerance or down > tolerance):
            if mode.sliding is not None and mode.sliding != k:
                raise SimulationError(
                    f"the motion slides on two switching surfaces at once, {self.surfaces[k]} "
                    f"= 0 and {self.surfaces[mode.sliding]} = 0, at t = {t:.6g}: not supported"
                )
            return mode.sliding_on(k, order), outcome
        if up > tolerance and down > tolerance:
            side = 1.0
        elif up < -tolerance and down < -tolerance:
            side = -1.0
        else:  # both fields leave the surface (or the surface is touched): keep going
            side = -moving
        return mode.leaving(k, side), "plus" if side > 0 else "minus"

    # -- the Hybrid protocol of the piecewise loop ----------------------------------------
    def initial_mode(self, t: float, x: np.ndarray) -> tuple[SwitchMode, list[Record]]:
        """The sign of each u_k, decided as at a switch where u_k = 0 (those decisions are
        the first events: a block at rest starts stuck)."""
        u = self.values(t, x)
        mode = SwitchMode(tuple(np.where(u < 0, -1.0, 1.0).tolist()))
        decided: list[Record] = []
        for k in np.flatnonzero(u == 0):
            mode, outcome = self.decide(mode, int(k), t, x, moving=-1.0)
            decided.append((f"switch {self.surfaces[k]}: {outcome}", t, np.array(x)))
        return mode, decided

    def settle(self, mode: SwitchMode, t: float, x: np.ndarray) -> tuple[SwitchMode, list[Record]]:
        return mode, []

    def piece(self, mode: SwitchMode) -> Dynamics:
        return _Piece(self, mode)

    def guards(self, mode: SwitchMode, piece: Dynamics) -> list[_Surface]:
        return [_Surface(self, mode, k) for k in range(len(self.surfaces))]

    def transition(self, mode: SwitchMode, guard: Guard, t: float, x: np.ndarray) -> Jump:
        """A slide ends on the side lam reached; a crossing is decided by the two fields."""
        k = guard.k  # type: ignore[attr-defined]
        if mode.sliding == k:
            lam, _ = self.sliding_share(mode, k, t, x)
            after = mode.leaving(k, 1.0 if lam > 0 else -1.0)
            outcome = "plus" if lam > 0 else "minus"
        else:
            after, outcome = self.decide(mode, k, t, x, mode.signs[k])
        return Jump(after, x, f"{guard.__name__}: {outcome}")

    def completed(self, mode: SwitchMode, piece: Dynamics, run: Integration) -> Integration:
        return run


@dataclasses.dataclass(frozen=True)
class _Piece(WithoutConstraints):
    """One mode of a SwitchedDynamics as a Dynamics (the field of its mode, or the Filippov
    field while it slides)."""

    switched: SwitchedDynamics
    mode: SwitchMode
    multiplier_names: tuple[str, ...] = ()

    def field(self, t: float, x: np.ndarray) -> np.ndarray:
        if self.mode.sliding is None:
            return self.switched.field_in(self.mode.signs, t, x)
        return self.switched.sliding_share(self.mode, self.mode.sliding, t, x)[1]

    def unpack(self, t: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.switched.unpack(t, x)


class _Surface:
    """The guard of a surface: u_k crossing zero in a mode, or |lam| reaching 1 in a slide.

    Its value is positive inside the piece (u_k s_k, 1 - |lam|) and the event fires only where
    it turns negative, so the zero a piece starts from is not found again."""

    terminal = True
    direction = -1.0

    def __init__(self, switched: SwitchedDynamics, mode: SwitchMode, k: int) -> None:
        self.switched, self.mode, self.k = switched, mode, k
        self.__name__ = f"switch {switched.surfaces[k]}"

    def __call__(self, t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        x = np.concatenate([q, q_dot])
        if self.mode.sliding == self.k:
            lam, _ = self.switched.sliding_share(self.mode, self.k, t, x)
            return 1.0 - abs(lam)
        return float(self.switched.values(t, x)[self.k]) * self.mode.signs[self.k]


def _rate(u: sp.Expr, q: list[sp.Symbol], q_dot: list[sp.Symbol], t: sp.Symbol) -> sp.Expr:
    """du/dt = sum_i du/dq_i q_dot_i + du/dt of a surface u(q, t)."""
    return sum((u.diff(qi) * vi for qi, vi in zip(q, q_dot)), u.diff(t))


def _moded_equations(eom: EquationsOfMotion) -> CompiledEquations:
    """The equations with sign(u_k) -> s_k, compiled once per equations; the s_k follow the
    parameters in the parameter vector."""
    return _MODED.get(eom, _compile_moded)


_MODED: IdentityCache[EquationsOfMotion, CompiledEquations] = IdentityCache()


def _compile_moded(eom: EquationsOfMotion) -> CompiledEquations:
    surfaces = switching_functions(eom)
    modes = sp.symbols(f"_mode0:{len(surfaces)}")
    rule = dict(zip(surfaces, modes, strict=True))
    moded = dataclasses.replace(
        eom,
        mass_matrix=_replaced(eom.mass_matrix, rule),
        forcing=_replaced(eom.forcing, rule),
        parameters=FrozenMapping({**eom.parameters, **dict.fromkeys(modes)}),
    )
    return compile_equations(moded)


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
