"""simulate and Trajectory against independent references: closed-form solutions, the small-
amplitude pendulum period, SciPy's solve_ivp on equations written by hand from the seed notes,
energy conservation, RK4's convergence order, and the bad-input contract of issue 6.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import sys

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad, solve_ivp

import lagrangian as lg
from lagrangian.numerics.compile import compile_equations
from lagrangian.simulation import Event, Trajectory, simulate
from lagrangian.simulation.methods import METHODS


@pytest.fixture(scope="module")
def double_pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.double_pendulum())


DOUBLE_START = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}


def _upward_zero(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
    return float(q[0])


_upward_zero.direction = 1  # type: ignore[attr-defined]


# --- references -----------------------------------------------------------------------------


def test_small_amplitude_pendulum_period_is_2_pi_sqrt_l_over_g() -> None:
    # theta0 = 0.01: the amplitude correction theta0^2/16 = 6e-6 is below the 1e-4 asked for.
    trajectory = simulate(
        lg.examples.simple_pendulum(),
        {"theta": 0.01},
        12.0,
        parameters={"l": 1.5},
        events=[_upward_zero],
    )
    crossings = np.array([event.t for event in trajectory.events])
    assert len(crossings) == 5
    period = np.mean(np.diff(crossings))
    assert period == pytest.approx(2 * np.pi * np.sqrt(1.5 / 9.81), rel=1e-4)
    assert all(event.name == "_upward_zero" for event in trajectory.events)
    assert abs(trajectory.events[0].state["theta"]) < 1e-9
    assert trajectory.events[0].state["theta_dot"] > 0


def test_mass_spring_damper_matches_the_damped_closed_form() -> None:
    # m x'' + B x' + K x + m g = 0 from rest at x = 0: x = x_eq + exp(-z w0 t)(A cos wd t +
    # B' sin wd t), x_eq = -m g / K, A = -x_eq, B' = z w0 A / wd.
    m, K, B, g = 2.0, 30.0, 1.5, 9.81
    trajectory = simulate(
        lg.examples.mass_spring_damper(),
        t_span=5.0,
        parameters={"m": m, "K": K, "B": B},
        samples=201,
        rtol=1e-10,
        atol=1e-12,
    )
    w0, zeta = np.sqrt(K / m), B / (2 * np.sqrt(K * m))
    wd, x_eq = w0 * np.sqrt(1 - zeta**2), -m * g / K
    t = trajectory.t
    a, b = -x_eq, zeta * w0 * -x_eq / wd
    decay = np.exp(-zeta * w0 * t)
    x = x_eq + decay * (a * np.cos(wd * t) + b * np.sin(wd * t))
    v = decay * (
        (b * wd - zeta * w0 * a) * np.cos(wd * t) - (a * wd + zeta * w0 * b) * np.sin(wd * t)
    )
    np.testing.assert_allclose(trajectory["x"], x, atol=1e-8)
    np.testing.assert_allclose(trajectory["x_dot"], v, atol=1e-8)


def test_series_rlc_step_response_matches_the_closed_form() -> None:
    # L q'' + R q' + q/C = u, q(0) = i(0) = 0: q = C u (1 - exp(-a t)(cos wd t + a/wd sin wd t)),
    # i = C u (w0^2 / wd) exp(-a t) sin wd t, a = R / 2L, w0^2 = 1/LC.
    L, C, R, u = 0.1, 1e-3, 1.0, 1.0
    trajectory = simulate(lg.examples.series_rlc(), t_span=0.3, samples=301, rtol=1e-10, atol=1e-14)
    a, w0 = R / (2 * L), 1 / np.sqrt(L * C)
    wd = np.sqrt(w0**2 - a**2)
    t = trajectory.t
    q = C * u * (1 - np.exp(-a * t) * (np.cos(wd * t) + a / wd * np.sin(wd * t)))
    i = C * u * w0**2 / wd * np.exp(-a * t) * np.sin(wd * t)
    np.testing.assert_allclose(trajectory["q"], q, rtol=0, atol=1e-9 * C * u)
    np.testing.assert_allclose(trajectory["q_dot"], i, rtol=0, atol=1e-8 * np.max(np.abs(i)))


def test_double_pendulum_conserves_energy(double_pendulum: lg.EquationsOfMotion) -> None:
    trajectory = simulate(
        double_pendulum, DOUBLE_START, 10.0, method="DOP853", rtol=1e-10, atol=1e-10
    )
    drift = trajectory.drift()
    assert drift["energy_relative"] is not None and drift["energy_relative"] < 1e-7
    assert trajectory.status == "success" and trajectory.method == "DOP853"


def test_rk4_converges_with_order_four(double_pendulum: lg.EquationsOfMotion) -> None:
    reference = simulate(
        double_pendulum, DOUBLE_START, 3.0, method="DOP853", rtol=1e-13, atol=1e-13
    )
    end = np.concatenate((reference.q[-1], reference.q_dot[-1]))
    errors = []
    for dt in (0.01, 0.005):
        trajectory = simulate(double_pendulum, DOUBLE_START, 3.0, method="RK4", dt=dt)
        assert len(trajectory.t) == round(3.0 / dt) + 1 and trajectory.t[-1] == 3.0
        errors.append(
            np.max(np.abs(np.concatenate((trajectory.q[-1], trajectory.q_dot[-1])) - end))
        )
    assert 10 < errors[0] / errors[1] < 22


def test_rk4_samples_give_the_step() -> None:
    trajectory = simulate(lg.examples.simple_pendulum(), t_span=2.0, method="RK4", samples=401)
    np.testing.assert_allclose(trajectory.t, np.linspace(0, 2, 401), atol=1e-15)
    reference = simulate(lg.examples.simple_pendulum(), t_span=2.0, samples=401)
    np.testing.assert_allclose(trajectory.q, reference.q, atol=1e-7)


def test_rc_rl_circuit_matches_the_notes_state_equations() -> None:
    # Seed 001 "Another Example": du_C/dt = (-u_C/R - i_L + u_a/R)/C, di_L/dt = (u_C - R_L i_L)/L,
    # with u_C = (q1 - q2)/C, i_L = q2_dot, and the source current i_a = q1_dot = (u_a - u_C)/R.
    L, C, R, R_L, u_a = 0.1, 1e-3, 10.0, 1.0, 1.0

    def notes(t: float, state: np.ndarray) -> list[float]:
        u_c, i_l = state
        return [(-u_c / R - i_l + u_a / R) / C, (u_c - R_L * i_l) / L]

    times = np.linspace(0, 0.5, 101)
    expected = solve_ivp(notes, (0, 0.5), [0.0, 0.0], t_eval=times, rtol=1e-11, atol=1e-13).y
    for method in ("DOP853", "Radau"):
        trajectory = simulate(
            lg.examples.rc_rl_circuit(),
            t_span=0.5,
            method=method,
            t_eval=times,
            rtol=1e-11,
            atol=1e-13,
        )
        u_c = (trajectory["q1"] - trajectory["q2"]) / C
        np.testing.assert_allclose(u_c, expected[0], atol=1e-6 * u_a)
        np.testing.assert_allclose(trajectory["q2_dot"], expected[1], atol=1e-6)
        np.testing.assert_allclose(trajectory["q1_dot"], (u_a - expected[0]) / R, atol=1e-6)


def test_moving_pivot_pendulum_matches_the_hand_written_equation() -> None:
    # Seed 000: m l^2 th'' - m l x0 w^2 cos(w t) cos(th) + m g l sin(th) = 0.
    g, l, x0, w = 9.81, 0.7, 0.15, 3.0

    def hand(t: float, state: np.ndarray) -> list[float]:
        th, th_d = state
        return [th_d, (x0 * w**2 * np.cos(w * t) * np.cos(th) - g * np.sin(th)) / l]

    times = np.linspace(0, 5, 51)
    expected = solve_ivp(hand, (0, 5), [0.2, 0.0], t_eval=times, rtol=1e-11, atol=1e-12).y
    trajectory = simulate(
        lg.examples.moving_pivot_pendulum(),
        t_span=5.0,
        parameters={"l": l, "x0": x0, "omega": w},
        t_eval=times,
        rtol=1e-11,
        atol=1e-12,
    )
    np.testing.assert_allclose(trajectory["theta"], expected[0], atol=1e-8)
    np.testing.assert_allclose(trajectory["theta_dot"], expected[1], atol=1e-8)
    assert trajectory.energy_function is not None  # h differs from T + V here


@pytest.mark.parametrize("method", METHODS)
def test_every_method_agrees_on_the_pendulum(method: str) -> None:
    options = {"dt": 0.005} if method == "RK4" else {}
    trajectory = simulate(
        lg.examples.simple_pendulum(), t_span=1.0, method=method, samples=11, **options
    )
    reference = simulate(
        lg.examples.simple_pendulum(), t_span=1.0, method="DOP853", samples=11, rtol=1e-12
    )
    assert trajectory.method == method and trajectory.t.shape == (11,)
    np.testing.assert_allclose(trajectory.q, reference.q, atol=1e-5)


# --- events and settings ----------------------------------------------------------------------


@pytest.mark.parametrize("options", [{}, {"method": "RK4", "dt": 1e-3}], ids=["RK45", "RK4"])
def test_terminal_event_stops_the_run_at_the_zero(options: dict) -> None:
    def bottom(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(q[0])

    bottom.terminal = True  # type: ignore[attr-defined]
    trajectory = simulate(
        lg.examples.simple_pendulum(), {"theta": 0.01}, 5.0, events=[bottom], **options
    )
    quarter = np.pi / 2 * np.sqrt(1.0 / 9.81)
    assert trajectory.t[-1] == pytest.approx(quarter, rel=1e-4)
    assert trajectory.events[-1].t == trajectory.t[-1]
    assert trajectory.status == "success" and "terminal event bottom" in trajectory.message


def test_terminal_count_and_direction() -> None:
    def crossing(t: float, q: np.ndarray, q_dot: np.ndarray) -> float:
        return float(q[0])

    crossing.terminal = 3  # type: ignore[attr-defined]
    crossing.direction = -1  # type: ignore[attr-defined]
    trajectory = simulate(lg.examples.simple_pendulum(), {"theta": 0.01}, 20.0, events=[crossing])
    assert len(trajectory.events) == 3
    assert all(event.state["theta_dot"] < 0 for event in trajectory.events)
    period = 2 * np.pi * np.sqrt(1.0 / 9.81)
    assert trajectory.t[-1] == pytest.approx(period / 4 + 2 * period, rel=1e-4)


def test_settings_fall_back_to_the_system() -> None:
    system = lg.examples.simple_pendulum().replace(
        simulation={"t_end": 2.0, "samples": 11, "method": "DOP853"}
    )
    trajectory = simulate(system, initial={sp.Symbol("theta"): 0.2})
    np.testing.assert_allclose(trajectory.t, np.linspace(0, 2, 11))
    assert trajectory.method == "DOP853"
    assert trajectory.q[0, 0] == 0.2 and trajectory.q_dot[0, 0] == 0.0
    assert dict(trajectory.parameters) == {"m": 1.0, "g": 9.81, "l": 1.0}
    # t_eval wins over the System's samples, and may start after t0
    later = simulate(system, {"theta": 0.2}, t_eval=[0.5, 1.25])
    np.testing.assert_array_equal(later.t, [0.5, 1.25])
    every_quarter = simulate(system, {"theta": 0.2}, 1.25, samples=6)
    np.testing.assert_allclose(later.q, every_quarter.q[[2, 5]], atol=1e-7)


def test_changing_a_parameter_does_not_recompile() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())
    compiled = compile_equations(eom)
    start = {"theta": 0.01, "theta_dot": 0.0}
    short = simulate(eom, start, 3.0, events=[_upward_zero])
    long = simulate(eom, start, 6.0, parameters={"l": 4.0}, events=[_upward_zero])
    assert compile_equations(eom) is compiled
    assert long.events[0].t == pytest.approx(2 * short.events[0].t, rel=1e-6)
    assert long.parameters["l"] == 4.0


# --- bad input ----------------------------------------------------------------------------------


def test_missing_initial_velocity_is_named(double_pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(lg.SimulationError, match="no initial value for the velocity phi_dot"):
        simulate(double_pendulum, {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0}, 1.0)


def test_missing_initial_coordinate_is_named(double_pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(lg.SimulationError, match="no initial value for the coordinate phi"):
        simulate(double_pendulum, {"theta": 1.0, "theta_dot": 0.0, "phi_dot": 0.0}, 1.0)


def test_parameter_without_value_is_named() -> None:
    q, q_dot, k = sp.symbols("q q_dot k")
    system = lg.System(
        coordinates=[q], parameters=[k], kinetic=q_dot**2 / 2, potential=k * q**2 / 2
    )
    with pytest.raises(
        lg.SimulationError, match=r"parameter k has no value — pass parameters=\{'k': \.\.\.\}"
    ):
        simulate(system, {"q": 1.0, "q_dot": 0.0}, 1.0)
    trajectory = simulate(system, {"q": 1.0, "q_dot": 0.0}, np.pi, parameters={"k": 1.0})
    assert trajectory["q"][-1] == pytest.approx(-1.0, abs=1e-7)  # half a period of cos t


def test_unknown_names_get_the_closest_suggestion(double_pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(lg.SimulationError, match=r"'thetta' is not a coordinate.*'theta'\?"):
        simulate(double_pendulum, {**DOUBLE_START, "thetta": 1.0}, 1.0)
    with pytest.raises(lg.SimulationError, match=r"'l3' is not a parameter.*did you mean 'l[12]'"):
        simulate(double_pendulum, DOUBLE_START, 1.0, parameters={"l3": 2.0})
    with pytest.raises(lg.SimulationError, match=r"unknown method 'rk45'.*'RK45'"):
        simulate(double_pendulum, DOUBLE_START, 1.0, method="rk45")


def test_every_problem_is_reported_at_once(double_pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(lg.SimulationError, match=r"Cannot simulate \(5 problems\)") as caught:
        simulate(double_pendulum, {"theta": 1.0}, parameters={"g": "strong"})
    fields = sorted(problem.field for problem in caught.value.problems)
    assert fields == ["initial", "initial", "initial", "parameters['g']", "t_span"]
    assert "'strong' is not a number" in str(caught.value)


@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"t_span": (1.0, 0.5)}, "the end time 0.5 is not after the start 1"),
        ({"t_span": 1.0, "method": "RK4"}, "the fixed-step method RK4 needs a step"),
        ({"t_span": 1.0, "dt": 0.1}, "dt is the step of the fixed-step RK4, not of RK45"),
        ({"t_span": 1.0, "samples": 5, "t_eval": [0.5]}, "both samples and t_eval given"),
        ({"t_span": 1.0, "samples": 1}, "1 is not an integer >= 2"),
        ({"t_span": 1.0, "t_eval": [0.5, 2.0]}, "must increase and lie within t_span"),
        ({"t_span": 1.0, "rtol": -1.0}, "rtol must be positive"),
        ({"t_span": 1.0, "max_step": 0.0}, "max_step must be a positive number"),
        ({}, "no end time"),
    ],
)
def test_bad_settings(double_pendulum: lg.EquationsOfMotion, options: dict, match: str) -> None:
    with pytest.raises(lg.SimulationError, match=match):
        simulate(double_pendulum, DOUBLE_START, **options)


def test_only_systems_and_equations_are_simulated() -> None:
    with pytest.raises(lg.SimulationError, match="needs a System or the EquationsOfMotion"):
        simulate("simple_pendulum", {}, 1.0)  # type: ignore[arg-type]


def _runaway() -> lg.System:
    # x_ddot = x^2 (V = -x^3/3) from x = 1 at rest reaches infinity at
    # t* = integral_1^inf dx / sqrt(2 (x^3 - 1) / 3), by energy conservation.
    x, x_dot = sp.symbols("x x_dot")
    return lg.System(
        coordinates=[x], kinetic=x_dot**2 / 2, potential=-(x**3) / 3, initial={x: 1.0, x_dot: 0.0}
    )


def _blow_up_time() -> float:
    # x = 1 + u^2 removes the integrable 1/sqrt singularity at x = 1
    def integrand(u: float) -> float:
        return 2 * u / np.sqrt(2 * ((1 + u * u) ** 3 - 1) / 3) if u > 0 else np.sqrt(2.0)

    return float(quad(integrand, 0, np.inf, limit=200)[0])


def test_integration_failure_raises_with_time_and_state() -> None:
    with pytest.raises(
        lg.SimulationError, match=r"Integration failed at t = 2\.97\d* \(x="
    ) as caught:
        simulate(_runaway(), t_span=10.0)
    assert "raise_on_failure=False" in str(caught.value)
    assert isinstance(caught.value, lg.LagrangianError) and isinstance(caught.value, RuntimeError)


def test_failed_trajectory_holds_everything_up_to_the_failure() -> None:
    trajectory = simulate(_runaway(), t_span=10.0, raise_on_failure=False)
    assert trajectory.status == "failed" and not trajectory.success
    assert "t = 2.97" in trajectory.message and "step size" in trajectory.message
    assert trajectory.t[-1] == pytest.approx(_blow_up_time(), abs=1e-4)
    assert len(trajectory.t) > 50 and np.all(np.diff(trajectory["x"]) > 0)
    assert np.all(np.isfinite(trajectory.q)) and np.all(np.isfinite(trajectory.energy))
    # energy stays -1/3 on the way (T - x^3/3 with x = 1 at rest)
    early = trajectory.t < 1.5
    np.testing.assert_allclose(trajectory.energy[early], -1 / 3, rtol=1e-6)
    sampled = simulate(_runaway(), t_span=10.0, samples=101, raise_on_failure=False)
    np.testing.assert_allclose(sampled.t, np.linspace(0, 10, 101)[:30])


def test_singular_configuration_fails_with_time_and_state() -> None:
    arm = lg.examples.robot_arm()
    with pytest.raises(lg.SimulationError, match=r"mass matrix is singular at t = 0, theta=0, r=0"):
        simulate(arm, {"r": 0.0}, 1.0)
    trajectory = simulate(arm, {"r": 0.0}, 1.0, raise_on_failure=False)
    assert trajectory.status == "failed" and len(trajectory.t) == 1


# --- Trajectory -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def swing(double_pendulum: lg.EquationsOfMotion) -> Trajectory:
    return simulate(double_pendulum, DOUBLE_START, 1.0, samples=21)


def test_csv_has_the_documented_columns_and_round_trips(swing: Trajectory, tmp_path) -> None:
    path = tmp_path / "swing.csv"
    swing.to_csv(path)
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    assert rows[0] == ["t", "theta", "phi", "theta_dot", "phi_dot", "energy"]
    assert len(rows) == 22 and float(rows[5][1]) == swing["theta"][4]
    back = Trajectory.from_csv(path)
    assert back.coordinates == swing.coordinates
    for name in swing.names:
        np.testing.assert_array_equal(back[name], swing[name])
    buffer = io.StringIO()
    swing.to_csv(buffer)
    assert buffer.getvalue() == path.read_text()


def test_trajectory_is_immutable(swing: Trajectory) -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        swing.t = np.zeros(3)  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        swing.q[0, 0] = 5.0
    with pytest.raises(TypeError, match="does not support item assignment"):
        swing.parameters["g"] = 1.0  # type: ignore[index]


def test_columns_by_name(swing: Trajectory) -> None:
    assert swing.q.shape == swing.q_dot.shape == (21, 2) and swing.energy.shape == (21,)
    np.testing.assert_array_equal(swing["phi_dot"], swing.q_dot[:, 1])
    np.testing.assert_array_equal(swing["t"], np.linspace(0, 1, 21))
    with pytest.raises(KeyError, match="did you mean 'theta_dot'"):
        swing["theta_dott"]


def test_drift_report() -> None:
    trajectory = Trajectory(
        t=[0, 1, 2],
        q=[[0], [1], [2]],
        q_dot=[[0], [0], [0]],
        coordinates=("x",),
        energy=[2.0, 2.5, 1.0],
        energy_function=[0.0, 0.1, -0.2],
    )
    drift = trajectory.drift()
    assert drift["energy_absolute"] == 1.0 and drift["energy_relative"] == 0.5
    assert drift["energy_function_absolute"] == pytest.approx(0.2)
    assert drift["energy_function_relative"] is None  # h0 = 0: only the absolute drift


def test_events_are_named_tuples(swing: Trajectory) -> None:
    event = Event("hit", 0.5, {"x": 1.0})
    name, time, state = event
    assert (name, time, state["x"]) == ("hit", 0.5, 1.0)
    assert swing.events == ()


def test_to_pandas_explains_a_missing_pandas(swing: Trajectory, monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match=r"to_pandas needs pandas.*pip install pandas"):
        swing.to_pandas()


def test_to_pandas(swing: Trajectory) -> None:
    pd = pytest.importorskip("pandas")
    frame = swing.to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame.columns) == list(swing.names)
