"""The numba backend against independent references: the harmonic oscillator's closed form,
RK4's convergence order, energy conservation, SciPy's solve_ivp on the same equations, and the
NumPy backend; plus its refusals of what it does not do.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.fast import compiled_rates as fast
from lagrangian.numerics.fast.source import values_source

SPRING = {"x": 0.1, "x_dot": 0.0}


def spring_exact(t: np.ndarray, m: float = 1.0, k: float = 10.0) -> np.ndarray:
    """x(t) = x0 cos(sqrt(k/m) t) for m x_ddot = -k x released at rest."""
    return 0.1 * np.cos(np.sqrt(k / m) * t)


# --- without numba ----------------------------------------------------------------------------


def test_a_missing_numba_names_the_extra_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(fast, "numba_available", lambda: False)
    with pytest.raises(lg.SimulationError, match=r"pip install lagrangian\[fast\]"):
        lg.simulate(lg.examples.mass_on_spring(), SPRING, 1.0, backend="numba")


def test_the_generated_source_refuses_a_function_without_numeric_form() -> None:
    x = sp.Symbol("x")
    with pytest.raises(lg.SimulationError, match=r"besselj.*backend='numpy'"):
        values_source([x], [sp.besselj(0, x)])


def test_unknown_backends_and_unsupported_features_are_refused_by_name() -> None:
    spring = lg.examples.mass_on_spring()
    with pytest.raises(lg.SimulationError, match="unknown backend 'cuda'"):
        lg.simulate(spring, SPRING, 1.0, backend="cuda")
    with pytest.raises(lg.SimulationError, match="no method 'Radau'"):
        lg.simulate(spring, SPRING, 1.0, method="Radau", backend="numba")
    with pytest.raises(lg.SimulationError, match="events: the numba backend does not locate"):
        lg.simulate(spring, SPRING, 1.0, events=[lambda t, q, v: q[0]], backend="numba")
    x, y, l = sp.symbols("x y l")
    pendulum = lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        particles=[lg.Particle("bob", 1, (x, y))],
        gravity=(0, -9.81),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
    )
    with pytest.raises(lg.SimulationError, match="constraints: the numba backend"):
        lg.simulate(pendulum, {"x": 1.0, "y": 0.0}, 1.0, backend="numba")


# --- with numba -------------------------------------------------------------------------------

numba = pytest.importorskip("numba")

from lagrangian.numerics.fast.loops import single_loop  # noqa: E402  (needs numba)


def test_rk4_converges_with_order_four_on_the_harmonic_oscillator() -> None:
    errors = []
    for dt in (0.04, 0.02, 0.01):
        run = lg.simulate(
            lg.examples.mass_on_spring(), SPRING, 4.0, method="RK4", dt=dt, backend="numba"
        )
        errors.append(np.max(np.abs(run["x"] - spring_exact(run.t))))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 4) < 0.15), orders


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_adaptive_methods_meet_the_closed_form(method: str) -> None:
    run = lg.simulate(
        lg.examples.mass_on_spring(),
        SPRING,
        5.0,
        method=method,
        rtol=1e-11,
        atol=1e-12,
        samples=51,
        backend="numba",
    )
    assert np.max(np.abs(run["x"] - spring_exact(run.t))) < 1e-9
    assert run["x_dot"][10] == pytest.approx(-0.1 * np.sqrt(10) * np.sin(np.sqrt(10) * 1.0))


def test_dop853_conserves_the_pendulum_energy() -> None:
    run = lg.simulate(
        lg.examples.simple_pendulum(),
        {"theta": 2.5, "theta_dot": 0.0},
        20.0,
        method="DOP853",
        rtol=1e-11,
        atol=1e-11,
        backend="numba",
    )
    assert run.drift()["energy_relative"] < 1e-9


@pytest.mark.parametrize("links", [2, 4])
def test_dop853_agrees_with_solve_ivp_on_n_link_pendulums(links: int) -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(links))
    compiled = compile_equations(eom)
    x0 = np.array([0.5 + 0.3 * i for i in range(links)] + [0.1] * links)
    p = np.array([1.0] * (2 * links) + [9.81])
    times = np.linspace(0.0, 5.0, 11)
    reference = solve_ivp(
        lambda t, x: compiled.rhs(t, x, p),
        (0.0, 5.0),
        x0,
        method="DOP853",
        rtol=1e-10,
        atol=1e-10,
        t_eval=times,
    )
    names = compiled.state_names
    run = lg.simulate(
        eom,
        dict(zip(names, x0)),
        5.0,
        method="DOP853",
        rtol=1e-10,
        atol=1e-10,
        t_eval=times,
        backend="numba",
    )
    state = np.hstack([run.q, run.q_dot])
    assert np.max(np.abs(state - reference.y.T)) < 1e-7


def test_every_step_output_takes_solve_ivps_steps() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    start = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
    compiled = compile_equations(eom)
    p = np.array([1.0, 1.0, 1.0, 1.0, 9.81])
    reference = solve_ivp(
        lambda t, x: compiled.rhs(t, x, p),
        (0.0, 3.0),
        [1.0, 0.5, 0.0, 0.0],
        method="RK45",
        rtol=1e-9,
        atol=1e-9,
    )
    run = lg.simulate(eom, start, 3.0, method="RK45", rtol=1e-9, atol=1e-9, backend="numba")
    # the same steps, up to the rounding of the error estimates that size them
    assert len(run.t) == len(reference.t)
    assert np.allclose(run.t, reference.t, rtol=1e-6, atol=0)


def test_new_parameters_need_no_new_compilation() -> None:
    eom = lg.derive(lg.examples.simple_pendulum())
    first = lg.simulate(eom, {"theta": 0.3, "theta_dot": 0.0}, 2.0, samples=5, backend="numba")
    compiled = fast.fast_equations(eom)
    second = lg.simulate(
        eom,
        {"theta": 0.3, "theta_dot": 0.0},
        2.0,
        samples=5,
        parameters={"l": 2.0},
        backend="numba",
    )
    assert fast.fast_equations(eom) is compiled
    # the loop is compiled for one signature, the same for every system and parameter set
    assert len(single_loop("adaptive").signatures) == 1
    reference = lg.simulate(
        eom, {"theta": 0.3, "theta_dot": 0.0}, 2.0, samples=5, parameters={"l": 2.0}
    )
    assert np.allclose(second.q, reference.q, atol=1e-10)
    assert not np.allclose(first.q, second.q, atol=1e-3)


def test_first_order_coordinates_match_the_numpy_backend() -> None:
    system = lg.examples.rc_rl_circuit()
    numpy_run = lg.simulate(system, t_span=0.05, method="DOP853", samples=21)
    numba_run = lg.simulate(system, t_span=0.05, method="DOP853", samples=21, backend="numba")
    assert np.allclose(numba_run.q, numpy_run.q, rtol=1e-9, atol=1e-12)
    assert np.allclose(numba_run.q_dot, numpy_run.q_dot, rtol=1e-9, atol=1e-12)


def test_a_singular_mass_matrix_fails_with_the_trajectory_so_far() -> None:
    theta, r = sp.symbols("theta r")
    theta_dot = sp.Symbol("theta_dot")
    # M = r^2 vanishes at r = 0: a coordinate singularity the numba solve reports
    system = lg.System(coordinates=[theta], parameters={r: 0.0}, kinetic=r**2 * theta_dot**2 / 2)
    run = lg.simulate(
        system, {"theta": 0.0, "theta_dot": 1.0}, 1.0, backend="numba", raise_on_failure=False
    )
    assert run.status == "failed"
    assert "singular" in run.message
    with pytest.raises(lg.SimulationError, match="singular"):
        lg.simulate(system, {"theta": 0.0, "theta_dot": 1.0}, 1.0, backend="numba")
