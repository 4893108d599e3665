"""A sweep's members run one by one call the stop condition as the batch calls it."""

from __future__ import annotations

import numpy as np

import lagrangian as lg
from lagrangian.sweeps.members import simulate_member, stop_time


def crossing(t: np.ndarray, q: np.ndarray, q_dot: np.ndarray) -> np.ndarray:
    """theta, written for a batch: t (members,), q (members, n)."""
    return q[:, 0]


def test_a_batch_stop_condition_stops_a_member_run_by_simulate() -> None:
    system = lg.examples.simple_pendulum()
    stepping = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}
    member = simulate_member(system, {"theta": 0.5}, {}, 5.0, stepping, stop_when=crossing)
    batch = lg.simulate_batch(system, {"theta": [0.5]}, 5.0, stop_when=crossing, **stepping)
    # a quarter period of the pendulum at amplitude 0.5 (l = 1, g = 9.81): K(sin 0.25) sqrt(l/g)
    from scipy.special import ellipk

    quarter = float(ellipk(np.sin(0.25) ** 2)) / np.sqrt(9.81)
    assert abs(stop_time(member) - quarter) < 1e-8
    assert abs(stop_time(member) - float(batch.stop_time[0])) < 1e-8


def test_a_member_negative_at_its_start_stops_there() -> None:
    system = lg.examples.simple_pendulum()
    member = simulate_member(system, {"theta": -0.5}, {}, 1.0, {}, stop_when=crossing)
    assert stop_time(member) == 0.0 and len(member.t) == 1
