"""simulate_batch against independent references: single simulate runs of each member, the
harmonic oscillator's closed form for a batch of masses, and the flip-time map's energy bound,
its symmetry and solve_ivp-located events; plus the bad-input contract.
"""

from __future__ import annotations

import dataclasses
import importlib.util
from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg


def _flip_map_application():
    """benchmarks/flip_map.py, the application that draws the map (not part of the package)."""
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "flip_map.py"
    spec = importlib.util.spec_from_file_location("flip_map_application", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_APPLICATION = _flip_map_application()
flip_times, flipped = _APPLICATION.flip_times, _APPLICATION.flipped

ANGLES = np.array([-1.2, -0.4, 0.3, 1.1])
REST = {"theta_dot": 0.0, "phi_dot": 0.0}
#: "numba" is another name of the default backend for one release: both must give the same.
BACKENDS = ["numpy", "numba"]


@pytest.fixture(scope="module")
def double_pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.double_pendulum())


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("method", ["DOP853", "RK45", "RK4"])
def test_each_member_is_the_single_simulation_of_its_start(
    double_pendulum: lg.EquationsOfMotion, method: str, backend: str
) -> None:
    settings = {"dt": 0.01} if method == "RK4" else {"rtol": 1e-10, "atol": 1e-10}
    batch = lg.simulate_batch(
        double_pendulum,
        {"theta": ANGLES, "phi": 0.5, **REST},
        3.0,
        method=method,
        samples=7,
        backend=backend,
        **settings,
    )
    assert batch.status == ("success",) * len(ANGLES)
    for i, theta in enumerate(ANGLES):
        single = lg.simulate(
            double_pendulum,
            {"theta": theta, "phi": 0.5, **REST},
            3.0,
            method=method,
            samples=7,
            **settings,
        )
        assert np.allclose(batch.q[i], single.q, rtol=0, atol=1e-12)
        assert np.allclose(batch.q_dot[i], single.q_dot, rtol=0, atol=1e-11)
        assert np.allclose(batch.energy[i], single.energy, rtol=1e-12)
        member = batch.trajectory(i)
        assert np.allclose(member.q, single.q, atol=1e-12)
        assert member.parameters == single.parameters
    assert np.allclose(batch.final["theta"], batch.q[:, -1, 0])


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_batch_of_masses_oscillates_at_sqrt_k_over_m(backend: str) -> None:
    masses = np.array([0.5, 1.0, 2.0, 4.0])
    batch = lg.simulate_batch(
        lg.examples.mass_on_spring(),
        {"x": 0.1, "x_dot": 0.0},
        2.0,
        parameters={"m": masses},
        method="DOP853",
        rtol=1e-11,
        atol=1e-12,
        samples=9,
        backend=backend,
    )
    exact = 0.1 * np.cos(np.sqrt(10.0 / masses)[:, None] * batch.t[None, :])
    assert np.max(np.abs(batch.q[:, :, 0] - exact)) < 1e-9
    assert np.array_equal(batch.parameters["m"], masses)
    assert np.allclose(batch.energy, 0.5 * 10.0 * 0.1**2, rtol=1e-9)


def test_the_default_output_is_enough_times_to_plot_and_agrees_with_simulate(
    double_pendulum,
) -> None:
    initial = {"theta": ANGLES, "phi": 0.0, **REST}
    batch = lg.simulate_batch(double_pendulum, initial, 1.5, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(batch.t, np.linspace(0.0, 1.5, 1000))
    assert np.array_equal(batch.final_t, [1.5] * len(ANGLES))
    alone = lg.simulate(
        double_pendulum, {"theta": ANGLES[1], "phi": 0.0, **REST}, 1.5, t_eval=batch.t
    )
    np.testing.assert_allclose(batch.q[1], alone.q, atol=1e-7)


def test_the_default_output_of_a_huge_batch_keeps_fewer_times(double_pendulum) -> None:
    many = np.linspace(0.1, 0.2, 20_000)  # 20,000 members x 4 states: 209 times fit 2**24
    batch = lg.simulate_batch(double_pendulum, {"theta": many, "phi": 0.0, **REST}, 0.01)
    assert len(batch.t) == 2**24 // (20_000 * 4)
    assert batch.q.shape == (20_000, len(batch.t), 2)


def test_the_systems_own_samples_are_the_batch_default() -> None:
    system = dataclasses.replace(lg.examples.double_pendulum(), simulation={"samples": 7})
    batch = lg.simulate_batch(system, {"theta": ANGLES, "phi": 0.0, **REST}, 1.5)
    np.testing.assert_allclose(batch.t, np.linspace(0.0, 1.5, 7))


def test_progress_reaches_the_end(double_pendulum) -> None:
    seen: list[float] = []
    lg.simulate_batch(
        double_pendulum, {"theta": ANGLES, "phi": 0.0, **REST}, 1.0, progress=seen.append
    )
    assert seen[-1] == 1.0 and seen == sorted(seen)


def test_bad_input_names_every_field(double_pendulum) -> None:
    with pytest.raises(
        lg.SimulationError,
        match=r"parameters\['m1'\]: has 3 values, but "
        r"initial\['theta'\] has 4",
    ):
        lg.simulate_batch(
            double_pendulum,
            {"theta": ANGLES, "phi": 0.0, **REST},
            1.0,
            parameters={"m1": [1.0, 2.0, 3.0]},
        )
    with pytest.raises(lg.SimulationError, match="no initial value for the coordinate phi"):
        lg.simulate_batch(double_pendulum, {"theta": ANGLES, **REST}, 1.0)
    with pytest.raises(lg.SimulationError, match=r"initial\['phi'\]: has shape \(2, 2\)"):
        lg.simulate_batch(double_pendulum, {"theta": 0.1, "phi": np.ones((2, 2)), **REST}, 1.0)
    with pytest.raises(lg.SimulationError, match="did you mean 'theta'"):
        lg.simulate_batch(double_pendulum, {"thetta": 0.1, "theta": 0.1, "phi": 0.1, **REST}, 1)


# --- the flip-time map ------------------------------------------------------------------------

GRID = np.linspace(-3.0, 3.0, 24)
T_END = 10 * np.sqrt(1 / 9.81)


@pytest.fixture(scope="module")
def flip_map() -> np.ndarray:
    return flip_times(lg.examples.double_pendulum(), GRID, GRID, T_END)


def test_energy_forbids_a_flip_where_2_cos_theta_plus_cos_phi_exceeds_1(flip_map) -> None:
    theta, phi = np.meshgrid(GRID, GRID)
    forbidden = 2 * np.cos(theta) + np.cos(phi) > 1
    assert forbidden.sum() > 100
    assert np.all(np.isnan(flip_map[forbidden]))
    assert np.any(np.isfinite(flip_map[~forbidden]))
    # the rod pendulum's bound 3 cos theta + cos phi > 2 is inside this one
    assert np.all(np.isnan(flip_map[3 * np.cos(theta) + np.cos(phi) > 2]))


def test_the_map_is_symmetric_under_reversing_both_angles(flip_map) -> None:
    mirrored = flip_map[::-1, ::-1]
    assert np.array_equal(np.isnan(flip_map), np.isnan(mirrored))
    finite = np.isfinite(flip_map)
    assert np.allclose(flip_map[finite], mirrored[finite], rtol=1e-9)


def test_flip_times_agree_with_single_runs_and_their_events(flip_map) -> None:
    system = lg.examples.double_pendulum()

    def flip(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(flipped(t, q, q_dot))

    flip.terminal = True  # type: ignore[attr-defined]
    checked = 0
    for row, col in [(0, 0), (2, 21), (5, 23), (23, 1), (12, 12)]:
        run = lg.simulate(
            system,
            {"theta": GRID[col], "phi": GRID[row], **REST},
            T_END,
            method="DOP853",
            rtol=1e-9,
            atol=1e-9,
            events=[flip],
        )
        if run.events:
            assert flip_map[row, col] == pytest.approx(run.events[0].t, rel=1e-7)
            checked += 1
        else:
            assert np.isnan(flip_map[row, col])
    assert checked >= 3


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_stopped_member_ends_at_its_stop(double_pendulum, backend: str) -> None:
    batch = lg.simulate_batch(
        double_pendulum,
        {"theta": [3.0, 0.2], "phi": [3.0, 0.1], **REST},
        2.0,
        method="DOP853",
        samples=5,
        stop_when=flipped,
        backend=backend,
    )
    assert batch.status == ("stopped", "success")
    stop = batch.stop_time[0]
    assert 0 < stop < 2.0 and np.isnan(batch.stop_time[1])
    assert max(abs(batch.final_q[0])) == pytest.approx(np.pi, abs=1e-8)
    member = batch.trajectory(0)
    assert member.t[-1] == stop and member.events[0].name == "stop_when"
    assert np.all(np.isnan(batch.q[0][batch.t > stop]))
