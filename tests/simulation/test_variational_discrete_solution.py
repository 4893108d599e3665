"""The compiled variational marches solve the discrete equations to Newton's tolerance, whatever
their starting guesses: every node of the midpoint rule's march satisfies the discrete
Euler-Lagrange equations, evaluated here in NumPy from the compiled discrete Lagrangian's terms
(not by the march), to rounding; and the energy error of a double pendulum stays bounded over
10^6 steps with 101 output samples (the run the speed benchmark measures)."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
from lagrangian.simulation import simulate

pytest.importorskip("numba")

DT = 0.01


def discrete_euler_lagrange_residual(
    mechanics: object, q: np.ndarray, t: np.ndarray, p: np.ndarray
) -> np.ndarray:
    """|D2 L_d(q_{k-1}, q_k) + D1 L_d(q_k, q_{k+1})| at every interior node over the size of
    its terms, with D1 L_d = dt/2 L_q - L_v, D2 L_d = dt/2 L_q + L_v at each step's midpoint
    (Marsden & West 2001, section 3.2)."""
    d1, d2 = [], []
    for k in range(len(q) - 1):
        dt = t[k + 1] - t[k]
        L_q, L_v, *_ = mechanics.midpoint(  # type: ignore[attr-defined]
            (q[k] + q[k + 1]) / 2, (q[k + 1] - q[k]) / dt, t[k] + dt / 2, p
        )
        d1.append(dt / 2 * L_q - L_v)
        d2.append(dt / 2 * L_q + L_v)
    before, after = np.array(d2[:-1]), np.array(d1[1:])
    scale = np.maximum(np.abs(before), np.abs(after)).max(axis=1)
    return np.abs(before + after).max(axis=1) / scale


@pytest.mark.parametrize(
    "start",
    [
        {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0},
        {"theta": 2.5, "phi": -2.0, "theta_dot": 1.0, "phi_dot": -3.0},
    ],
)
def test_every_node_of_the_compiled_march_solves_the_discrete_equations(
    start: dict[str, float],
) -> None:
    pendulum = lg.examples.double_pendulum()
    eom = lg.derive(pendulum)
    run = simulate(eom, start, 20.0, method="variational", dt=DT)  # every node an output
    assert run.success and len(run.t) == 2001
    mechanics = compile_discrete_mechanics(eom)
    p = np.array([float(pendulum.parameters[s]) for s in eom.parameters])
    residual = discrete_euler_lagrange_residual(mechanics, run.q, run.t, p)
    # Newton's method stops at a correction below 1e-8 relative (its error is the square);
    # the residual moves by L_vv/dt (100 times its terms) per unit of q, so the rounding of q
    # shows as ~1e-14, at most a few 1e-12; the predictor alone (an O(dt^3) error in q) would
    # leave ~1e-4, and a step stopped one correction early ~1e-8
    assert np.median(residual) < 1e-13 and residual.max() < 1e-10, residual.max()


def test_the_energy_error_stays_bounded_over_a_million_steps_with_101_samples() -> None:
    pendulum = lg.examples.double_pendulum()
    eom = lg.derive(pendulum)
    run = simulate(eom, pendulum.initial, 10**6 * DT, method="variational", dt=DT, samples=101)
    assert run.success and len(run.t) == 101
    error = np.abs(run.energy / run.energy[0] - 1)
    # O(dt^2) and no drift: the samples of the last half of t = 10^4 s are within the bound
    # of the whole run of every step (3.5e-5 at this dt), as those of the first half are
    assert error.max() < 5e-5, error.max()
    assert error[51:].max() < 5e-5 and error[1:51].max() > 1e-7
