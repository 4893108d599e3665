"""The variational integrators as steppers: one step per call, driven by the one Python loop.

A stepper has the shape of SciPy's ``OdeSolver`` (``t``, ``y``, ``t_bound``, ``status``,
``step()``, ``dense_output()``; :class:`lagrangian.simulation.integrators.protocol.Stepper`),
so the loop of :mod:`lagrangian.simulation.integrators.loop` that steps SciPy's solvers and
RK4 steps these too, with the output rows, the step and wall-time budget, the progress and
Ctrl-C handled there, once.  Each step goes from one node of a fixed grid to the next:

* :class:`MidpointStepper`: the midpoint rule, (q_k, p_k) -> (q_{k+1}, p_{k+1}) by the
  equations of :mod:`lagrangian.simulation.variational.step`;
* :class:`CollocationStepper`: a symplectic collocation method of
  :mod:`lagrangian.simulation.variational.collocation`, by the stage equations of
  :mod:`lagrangian.simulation.variational.collocation_step`.

The state is y = [q; q_dot].  The velocity is the inverse Legendre map of p at the nodes that
need it — the output nodes, and every node with constraints (it fixes p there) — and elsewhere
the step's mean slope (q_{k+1} - q_k)/dt, which no result uses: it only keeps y finite.
Between two nodes ``dense_output`` interpolates linearly (exact at both nodes: the loop asks
for output rows at nodes only).

>>> import numpy as np, lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> grid = np.linspace(0.0, 1.0, 101)
>>> stepper = MidpointStepper(mechanics, np.array([0.1, 0.0]), np.array([1.0, 9.81, 1.0]), grid,
...                           np.ones(101, dtype=bool))
>>> while stepper.status == "running":
...     _ = stepper.step()
>>> bool(abs(stepper.y[0] - 0.1 * np.cos(np.sqrt(9.81))) < 2e-4)  # the small-angle solution
True
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.numerics.stage_prediction import (
    HISTORY,
    corrected_guess,
    forget,
    remember,
    step_ratio,
)
from lagrangian.simulation.variational.collocation import Tableau
from lagrangian.simulation.variational.collocation_step import stage_step
from lagrangian.simulation.variational.step import position_step, velocity_step


class NodeStepper:
    """What every stepper over the nodes of a grid shares: the state at the current node, the
    step counter, the dense output between the last two nodes, and the constraint residual
    max(|h|, |A q_dot + dh/dt|) at each node where the velocity was solved (NaN elsewhere).

    ``velocity_nodes[k]``: whether node k needs the velocity of the Legendre map.
    """

    def __init__(
        self,
        mechanics: DiscreteMechanics,
        x0: np.ndarray,
        parameters: np.ndarray,
        grid: np.ndarray,
        velocity_nodes: np.ndarray,
    ) -> None:
        n = len(mechanics.coordinates)
        self.mechanics, self.p, self.grid = mechanics, parameters, grid
        self.velocity_nodes = velocity_nodes | (mechanics.constraint_count > 0)
        self.q, self.v = x0[:n].astype(float), x0[n:].astype(float)
        self.momentum = mechanics.legendre(self.q, self.v, grid[0], parameters)[0]
        self.h, self.jacobian, self.rate = mechanics.constraints(self.q, grid[0], parameters)
        self.k, self.evaluations = 0, 1
        self.t, self.t_bound = float(grid[0]), float(grid[-1])
        self.status = "running" if len(grid) > 1 else "finished"
        self.residuals = np.full(len(grid), np.nan)
        self.residuals[0] = self.residual()
        self.previous: tuple[float, np.ndarray] | None = None
        self.y = np.concatenate((self.q, self.v))  # the state [q; q_dot] at the current node

    def residual(self) -> float:
        """The largest constraint residual at the current node (0 without constraints)."""
        values = (*self.h, *(self.jacobian @ self.v + self.rate))
        return float(np.max(np.abs(values), initial=0.0))

    def step(self) -> str | None:
        """Advance to the next node (a SimulationError if Newton's method fails there)."""
        k, t0 = self.k, float(self.grid[self.k])
        before = (self.t, self.y)
        self.advance(k, t0, float(self.grid[k + 1]) - t0)
        self.previous = before
        self.y = np.concatenate((self.q, self.v))
        self.k, self.t = k + 1, float(self.grid[k + 1])
        if self.velocity_nodes[self.k]:
            self.residuals[self.k] = self.residual()
        if self.k == len(self.grid) - 1:
            self.status = "finished"
        return None

    def advance(self, k: int, t0: float, dt: float) -> None:
        """The step from node k at t0 to node k + 1 (each method's own)."""
        raise NotImplementedError

    def dense_output(self) -> Callable[[Any], np.ndarray]:
        """The state between the last two nodes, interpolated linearly (exact at both)."""
        assert self.previous is not None  # dense output exists only after a step
        (t_old, y_old), t_new, y_new = self.previous, self.t, self.y

        def at(s: Any) -> np.ndarray:
            w = (np.asarray(s, dtype=float) - t_old) / (t_new - t_old)
            if np.ndim(w) == 0:
                return y_old * (1 - w) + y_new * w
            return np.outer(y_old, 1 - w) + np.outer(y_new, w)

        return at


class MidpointStepper(NodeStepper):
    """The midpoint rule (:mod:`lagrangian.simulation.variational.midpoint`): each step solves
    for (q_{k+1}, lambda_k), then, where the node needs it, for (q_dot_{k+1}, mu_k) and
    p_{k+1}; ``lam`` and ``mu`` keep the two halves of every step's constraint impulse
    (:func:`lagrangian.simulation.variational.march.node_multipliers` combines them)."""

    def __init__(
        self,
        mechanics: DiscreteMechanics,
        x0: np.ndarray,
        parameters: np.ndarray,
        grid: np.ndarray,
        velocity_nodes: np.ndarray,
    ) -> None:
        super().__init__(mechanics, x0, parameters, grid, velocity_nodes)
        m = mechanics.constraint_count
        self.lam = np.full((len(grid) - 1, m), np.nan)
        self.mu = np.full((len(grid) - 1, m), np.nan)
        self.multipliers = np.zeros(m)
        self.history: tuple[np.ndarray, ...] = ()

    def advance(self, k: int, t0: float, dt: float) -> None:
        mechanics, p = self.mechanics, self.p
        guess = self.extrapolated(k)
        position = position_step(
            mechanics, self.q, self.momentum, t0, dt, p, self.jacobian, guess, self.multipliers
        )
        self.momentum = position.momentum
        self.evaluations += position.evaluations
        slope = (position.q - self.q) / dt
        if self.velocity_nodes[k + 1]:
            self.jacobian, self.rate, self.h = position.jacobian, position.rate, position.h
            velocity = velocity_step(
                mechanics, position.q, self.momentum, t0 + dt, dt / 2, p, self.jacobian,
                self.rate, slope,
            )  # fmt: skip
            self.v, self.mu[k], self.momentum = velocity.v, velocity.multipliers, velocity.momentum
            self.evaluations += velocity.evaluations
        else:
            self.v = slope
        self.history = (self.q, *self.history[:1])
        self.q, self.multipliers = position.q, position.multipliers
        self.lam[k] = self.multipliers

    def extrapolated(self, k: int) -> np.ndarray:
        """q_{k+1} extrapolated by the polynomial through q_k and the q_{k-1}, q_{k-2} known:
        an error O(dt^3) that Newton's method removes in two corrections."""
        grid, q, history = self.grid, self.q, self.history
        if not history:
            return q.copy()
        s1 = (q - history[0]) / (grid[k] - grid[k - 1])
        if len(history) < 2:
            return q + (grid[k + 1] - grid[k]) * s1
        s0 = (history[0] - history[1]) / (grid[k - 1] - grid[k - 2])
        curvature = (s1 - s0) / (grid[k] - grid[k - 2])
        return q + (grid[k + 1] - grid[k]) * (s1 + (grid[k + 1] - grid[k - 1]) * curvature)


class CollocationStepper(NodeStepper):
    """A collocation method ``tableau``: each step solves the stage equations from the stage
    velocities of the step before, extrapolated (and corrected by the extrapolated errors of
    the predictions before: :mod:`lagrangian.numerics.stage_prediction`), then, where the
    node needs it, the velocity equations of the step's end (the Legendre map, with the
    multiplier Lambda_s of the Lobatto pair:
    :func:`~lagrangian.simulation.variational.step.velocity_step` with the weight dt b_s)."""

    def __init__(
        self,
        mechanics: DiscreteMechanics,
        tableau: Tableau,
        x0: np.ndarray,
        parameters: np.ndarray,
        grid: np.ndarray,
        velocity_nodes: np.ndarray,
    ) -> None:
        super().__init__(mechanics, x0, parameters, grid, velocity_nodes)
        m, s = mechanics.constraint_count, tableau.stages
        self.tableau = tableau
        self.stage_velocities = np.tile(self.v, (s, 1))
        self.stage_multipliers = np.zeros((s - 1 if m else 0, m))
        self.last_dt: float | None = None
        # the prediction errors of the last steps (lagrangian.numerics.stage_prediction)
        self.history = np.zeros((HISTORY, s * len(self.q)))
        self.counters = np.zeros(1, dtype=np.int64)

    def advance(self, k: int, t0: float, dt: float) -> None:
        mechanics, tableau, p = self.mechanics, self.tableau, self.p
        V = plain = self.stage_velocities
        if self.last_dt is not None:
            ratio = step_ratio(dt, self.last_dt)
            if ratio != 1.0:  # another size of step
                forget(self.counters)
            plain = tableau.extrapolation(ratio) @ self.stage_velocities
            V = np.empty_like(plain)
            corrected_guess(plain, self.history, self.counters, V)
        stage = stage_step(mechanics, tableau, self.q, self.momentum, t0, dt, p, V,
                           self.stage_multipliers)  # fmt: skip
        if self.last_dt is not None:
            remember(stage.V, plain, V, self.history, self.counters)
        self.momentum = stage.momentum
        self.evaluations += stage.evaluations
        if self.velocity_nodes[k + 1]:
            self.h, self.jacobian, self.rate = stage.h, stage.jacobian, stage.rate
            end = velocity_step(
                mechanics, stage.q, self.momentum, t0 + dt, dt * float(tableau.b[-1]), p,
                self.jacobian, self.rate, stage.V[-1],
            )  # fmt: skip
            self.v, self.momentum = end.v, end.momentum
            self.evaluations += end.evaluations
        else:
            self.v = (stage.q - self.q) / dt
        self.q, self.stage_velocities = stage.q, stage.V
        self.stage_multipliers, self.last_dt = stage.multipliers, dt
