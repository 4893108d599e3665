"""The collocation integrators gauss4 and gauss6: their tableaus (symplectic, of their order,
the textbook's coefficients), convergence at orders 4 and 6 against exact solutions (harmonic
and damped oscillators, a Kepler orbit) and DOP853 at rtol 1e-13 (a pendulum), the Lobatto
IIIA–IIIB pair on constrained systems (a Cartesian pendulum, fixed and moving pivot) at the
same orders with the constraints at rounding, bounded energy errors over long runs, and
refusal of what they do not integrate."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.simulation import Trajectory, simulate
from lagrangian.simulation.variational.collocation import gauss, lobatto

ORDERS = {"gauss4": 4, "gauss6": 6}
TIGHT = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-13}
L, G, M = 1.5, 9.81, 2.0
X, Y, X_DOT, Y_DOT = sp.symbols("x y x_dot y_dot")


def fitted_order(steps: list[float], errors: list[float]) -> float:
    """The slope of log(error) against log(dt), fitted by least squares."""
    return float(np.polyfit(np.log(steps), np.log(errors), 1)[0])


def relative_energy_error(run: Trajectory) -> np.ndarray:
    return np.abs(run.energy / run.energy[0] - 1)


# --------------------------------------------------------------------------- tableaus


@pytest.mark.parametrize(
    "tableau", [gauss(2), gauss(3), lobatto(3), lobatto(4)], ids=lambda t: t.name
)
def test_the_tableaus_are_symplectic_collocation_methods_of_their_order(tableau: object) -> None:
    a, a_hat, b, c = tableau.a, tableau.a_hat, tableau.b, tableau.c  # type: ignore[attr-defined]
    order = tableau.order  # type: ignore[attr-defined]
    # the quadrature (b, c) integrates polynomials of degree order - 1 (Gauss: 2s - 1)
    for k in range(1, order + 1):
        assert b @ c ** (k - 1) == pytest.approx(1 / k, abs=1e-14)
    np.testing.assert_allclose(a.sum(axis=1), c, atol=1e-14)  # each stage at its node
    # b_i a_hat_ij + b_j a_ji = b_i b_j (HLW VI.4.2): the pair is symplectic
    np.testing.assert_allclose(b[:, None] * a_hat + (b[:, None] * a).T, np.outer(b, b), atol=1e-15)


def test_the_coefficients_are_the_textbook_ones() -> None:
    root3 = np.sqrt(3.0)
    np.testing.assert_allclose(gauss(2).c, [(3 - root3) / 6, (3 + root3) / 6], atol=1e-15)
    np.testing.assert_allclose(
        gauss(2).a, [[1 / 4, 1 / 4 - root3 / 6], [1 / 4 + root3 / 6, 1 / 4]], atol=1e-15
    )
    # Lobatto IIIA and IIIB, s = 3 (HLW, Table II.1.2 and section II.2.1)
    np.testing.assert_allclose(
        lobatto(3).a, [[0, 0, 0], [5 / 24, 1 / 3, -1 / 24], [1 / 6, 2 / 3, 1 / 6]], atol=1e-15
    )
    np.testing.assert_allclose(
        lobatto(3).a_hat, [[1 / 6, -1 / 6, 0], [1 / 6, 1 / 3, 0], [1 / 6, 5 / 6, 0]], atol=1e-15
    )
    root5 = np.sqrt(5.0)
    np.testing.assert_allclose(lobatto(4).c, [0, (5 - root5) / 10, (5 + root5) / 10, 1])


# --------------------------------------------------------------------------- convergence


def oscillator(damping: float = 0.0) -> lg.System:
    m, k, b = sp.symbols("m k b")
    return lg.System(
        coordinates=[X],
        parameters={m: 1.5, k: 4.0, b: damping},
        kinetic=m * X_DOT**2 / 2,
        potential=k * X**2 / 2,
        dissipation=b * X_DOT**2 / 2,
    )


def oscillator_exact(t: float, damping: float) -> tuple[float, float]:
    """x, x_dot of 1.5 x'' + b x' + 4 x = 0 from x = 1, x' = 0 (underdamped)."""
    decay = damping / 3.0
    w = np.sqrt(4.0 / 1.5 - decay**2)
    x = np.exp(-decay * t) * (np.cos(w * t) + decay / w * np.sin(w * t))
    x_dot = -np.exp(-decay * t) * (w + decay**2 / w) * np.sin(w * t)
    return float(x), float(x_dot)


@pytest.mark.parametrize("method", ORDERS)
@pytest.mark.parametrize("damping", [0.0, 0.6], ids=["free", "damped"])
def test_oscillators_converge_at_the_order_of_the_method(method: str, damping: float) -> None:
    steps = [0.2, 0.1, 0.05, 0.025] if method == "gauss4" else [0.4, 0.2, 0.1, 0.05]
    exact = np.array(oscillator_exact(10.0, damping))
    errors = []
    for dt in steps:
        run = simulate(oscillator(damping), {"x": 1.0, "x_dot": 0.0}, 10.0, method=method, dt=dt)
        errors.append(float(np.abs(np.array([run.q[-1, 0], run.q_dot[-1, 0]]) - exact).max()))
    assert abs(fitted_order(steps, errors) - ORDERS[method]) < 0.3, errors


@pytest.mark.parametrize("method", ORDERS)
def test_a_pendulum_converges_at_the_order_of_the_method(method: str) -> None:
    pendulum, start = lg.examples.simple_pendulum(), {"theta": 2.0, "theta_dot": 0.0}
    reference = simulate(pendulum, start, 10.0, samples=2, **TIGHT)
    steps = [0.1, 0.05, 0.025, 0.0125] if method == "gauss4" else [0.1, 0.05, 0.025]
    errors = []
    for dt in steps:
        run = simulate(pendulum, start, 10.0, method=method, dt=dt, samples=2)
        errors.append(float(max(np.abs(run.q[-1] - reference.q[-1]).max(),
                                np.abs(run.q_dot[-1] - reference.q_dot[-1]).max())))  # fmt: skip
    assert abs(fitted_order(steps, errors) - ORDERS[method]) < 0.3, errors


@pytest.mark.parametrize("method", ORDERS)
def test_a_kepler_orbit_returns_after_one_period_at_the_order_of_the_method(method: str) -> None:
    # eccentricity 0.5 from the perihelion, GM = 1, semi-major axis 1: period 2 pi
    kepler = lg.System(
        coordinates=[X, Y], kinetic=(X_DOT**2 + Y_DOT**2) / 2, potential=-1 / sp.sqrt(X**2 + Y**2)
    )
    start = {"x": 0.5, "y": 0.0, "x_dot": 0.0, "y_dot": np.sqrt(3.0)}
    period = 2 * np.pi
    counts = [100, 200, 400, 800] if method == "gauss4" else [50, 100, 200, 400]
    errors = []
    for count in counts:
        run = simulate(kepler, start, period, method=method, dt=period / count)
        final = np.concatenate((run.q[-1], run.q_dot[-1]))
        errors.append(float(np.abs(final - np.array(list(start.values()))).max()))
    steps = [period / count for count in counts]
    assert abs(fitted_order(steps, errors) - ORDERS[method]) < 0.3, errors


# --------------------------------------------------------------------------- constraints


def cartesian_pendulum(rod: sp.Expr | None = None, **parameters: float) -> lg.System:
    m, g, l = sp.symbols("m g l")
    values = {m: M, g: G, l: L, **{sp.Symbol(k): v for k, v in parameters.items()}}
    return lg.System(
        coordinates=[X, Y],
        parameters=values,
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (X, Y))],
        constraints=[lg.Holonomic(X**2 + Y**2 - l**2 if rod is None else rod, name="rod")],
    )


@pytest.mark.parametrize("method", ORDERS)
def test_a_cartesian_pendulum_converges_at_the_order_with_the_rod_at_rounding(
    method: str,
) -> None:
    times = np.linspace(0.0, 2.0, 11)
    reference = simulate(
        lg.examples.simple_pendulum(), {"theta": 1.0, "theta_dot": 0.0}, 2.0, t_eval=times,
        parameters={"m": M, "g": G, "l": L}, **TIGHT,
    )  # fmt: skip
    theta, omega = reference["theta"], reference["theta_dot"]
    start = {"x": L * np.sin(1.0), "y": -L * np.cos(1.0), "x_dot": 0.0, "y_dot": 0.0}
    steps = [0.1, 0.05, 0.025, 0.0125] if method == "gauss4" else [0.2, 0.1, 0.05]
    errors, tension_errors = [], []
    for dt in steps:
        run = simulate(cartesian_pendulum(), start, 2.0, method=method, dt=dt, t_eval=times)
        assert "Lobatto IIIA–IIIB pair" in run.message
        assert run.constraint_residual is not None
        assert np.max(run.constraint_residual) <= 1e-12
        x_error = np.abs(run["x"] - L * np.sin(theta)).max()
        x_dot_error = np.abs(run["x_dot"] - L * np.cos(theta) * omega).max()
        errors.append(float(max(x_error, x_dot_error)))
        # lambda dh/dq = lambda (2x, 2y) is the rod force: |lambda| 2 l = m g cos + m l w^2
        tension = M * G * np.cos(theta) + M * L * omega**2
        tension_errors.append(float(np.abs(-2 * L * run["lambda_1"] - tension).max()))
    assert abs(fitted_order(steps, errors) - ORDERS[method]) < 0.3, errors
    assert abs(fitted_order(steps, tension_errors) - ORDERS[method]) < 0.3, tension_errors


def test_a_moving_pivot_converges_at_fourth_order() -> None:
    a, frequency, theta0 = 0.1, 2.0, 0.2
    x0, w, l, t = sp.symbols("x0 omega l t")
    rod = (X - x0 * sp.cos(w * t)) ** 2 + Y**2 - l**2
    pendulum = cartesian_pendulum(rod, x0=a, omega=frequency)
    times = np.linspace(0.0, 2.0, 11)
    reference = simulate(
        lg.examples.moving_pivot_pendulum(), {"theta": theta0, "theta_dot": 0.0}, 2.0,
        t_eval=times, parameters={"m": M, "g": G, "l": L, "x0": a, "omega": frequency}, **TIGHT,
    )  # fmt: skip
    start = {"x": L * np.sin(theta0) + a, "y": -L * np.cos(theta0), "x_dot": 0.0, "y_dot": 0.0}
    steps, errors = [0.1, 0.05, 0.025], []
    for dt in steps:
        run = simulate(pendulum, start, 2.0, method="gauss4", dt=dt, t_eval=times)
        assert np.max(run.constraint_residual) <= 1e-12  # type: ignore[arg-type]
        pivot = a * np.cos(frequency * times)
        errors.append(float(np.abs(run["x"] - pivot - L * np.sin(reference["theta"])).max()))
    assert abs(fitted_order(steps, errors) - 4) < 0.3, errors


# --------------------------------------------------------------------------- long runs


@pytest.mark.parametrize("method", ORDERS)
def test_the_double_pendulum_energy_error_stays_bounded(method: str) -> None:
    # chaotic motion for 1000 s in 20000 steps: the error of the last tenth is that of the first
    pendulum = lg.examples.double_pendulum()
    run = simulate(lg.derive(pendulum), pendulum.initial, 1000.0, method=method, dt=0.05)
    assert run.success and "Gauss–Legendre collocation" in run.message
    error = relative_energy_error(run)
    tenth = len(error) // 10
    first, last = error[1:tenth].max(), error[-tenth:].max()
    assert error.max() < (1e-4 if method == "gauss4" else 1e-5)
    assert last < 1.2 * first, (first, last)


def test_the_cartesian_double_pendulum_rods_hold_and_its_energy_is_bounded() -> None:
    x1, y1, x2, y2, m1, m2, l1, l2, g = sp.symbols("x1 y1 x2 y2 m1 m2 l1 l2 g")
    system = lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob1", m1, (x1, y1)), lg.Particle("bob2", m2, (x2, y2))],
        constraints=[
            lg.Holonomic(x1**2 + y1**2 - l1**2, name="upper rod"),
            lg.Holonomic((x2 - x1) ** 2 + (y2 - y1) ** 2 - l2**2, name="lower rod"),
        ],
    )
    start = {"x1": np.sin(1.0), "y1": -np.cos(1.0)}
    start |= {"x2": start["x1"] + np.sin(0.5), "y2": start["y1"] - np.cos(0.5)}
    start |= {f"{name}_dot": 0.0 for name in list(start)}
    run = simulate(system, start, 200.0, method="gauss4", dt=0.02, samples=2001)
    assert run.success
    assert np.max(run.constraint_residual) <= 1e-11  # type: ignore[arg-type]
    error = relative_energy_error(run)
    tenth = len(error) // 10
    assert error.max() < 1e-5
    assert error[-tenth:].max() < 1.2 * error[1:tenth].max()


# --------------------------------------------------------------------------- refusals


@pytest.mark.parametrize(
    ("keywords", "field", "match"),
    [
        ({"events": [lambda t, q, q_dot: q[0]]}, "events", "method 'gauss4' does not locate"),
        ({"rtol": 1e-6}, "rtol", "not gauss4"),
        ({"baumgarte": (1.0, 1.0)}, "baumgarte", "holds the constraints exactly"),
    ],
)
def test_what_does_not_apply_is_refused_by_name(
    keywords: dict[str, object], field: str, match: str
) -> None:
    system = cartesian_pendulum()
    start = {"x": 0.0, "y": -L, "x_dot": 1.0, "y_dot": 0.0}
    with pytest.raises(SimulationInputError, match=match) as error:
        simulate(system, start, 1.0, method="gauss4", dt=0.01, **keywords)  # type: ignore[arg-type]
    assert [problem.field for problem in error.value.problems] == [field]


def test_a_velocity_constraint_is_refused() -> None:
    knife = lg.System(
        coordinates=[X, Y],
        particles=[lg.Particle("blade", 1, (X, Y))],
        constraints=[lg.VelocityConstraint(X_DOT - Y_DOT, name="blade")],
    )
    with pytest.raises(SimulationInputError, match="the method 'gauss6' holds holonomic"):
        simulate(knife, {"x": 0, "y": 0, "x_dot": 1, "y_dot": 1}, 1.0, method="gauss6", dt=0.1)


@pytest.mark.parametrize("method", ["variational", "gauss4", "gauss6"])
def test_backend_numba_is_refused_as_they_run_compiled_anyway(method: str) -> None:
    with pytest.raises(SimulationInputError, match="runs on compiled loops") as error:
        simulate(oscillator(), {"x": 1.0, "x_dot": 0.0}, 1.0, method=method, dt=0.1,
                 backend="numba")  # fmt: skip
    assert [problem.field for problem in error.value.problems] == ["backend"]
