"""Drift reported honestly: a number for each quantity the system conserves (h when it is the
conserved energy, the conserved momenta, the constraint residuals), and for the others the
reason they change, never a drift number that is physics, not integration error."""

from __future__ import annotations

import io

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.simulation.conservation import REASONS

TIGHT = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}
ENERGY_NUMBERS = ("energy_absolute", "energy_relative")
H_NUMBERS = ("energy_function_absolute", "energy_function_relative")


def rotating_hoop() -> lg.System:
    """A bead on a hoop of radius R turning at omega about its vertical diameter: in the angle
    theta from the bottom, T = m R^2 (theta_dot^2 + omega^2 sin^2 theta) / 2 has a part of
    degree 0 in the velocities (rheonomic), so h = T2 - T0 + V, the Jacobi integral, is
    conserved while T + V is not: the motor turning the hoop does work (Goldstein §2.7)."""
    theta, theta_dot, m, big_r, omega, g = sp.symbols("theta theta_dot m R omega g")
    return lg.System(
        coordinates=[theta],
        parameters={m: 1.0, big_r: 1.0, omega: 5.0, g: 9.81},
        kinetic=m * big_r**2 / 2 * (theta_dot**2 + omega**2 * sp.sin(theta) ** 2),
        potential=-m * g * big_r * sp.cos(theta),
        initial={theta: 0.5, theta_dot: 0.0},
    )


def test_a_damped_oscillator_reports_dissipation_and_no_drift_number() -> None:
    run = lg.simulate(lg.examples.mass_spring_damper(), t_span=5.0, samples=101)
    drift = run.drift()
    assert drift == {"energy_not_conserved": "dissipation"}
    assert run.drift_summary() == "energy not conserved: dissipation"
    with pytest.raises(KeyError, match=r"energy is not conserved here \(dissipation\)"):
        drift["energy_relative"]
    assert np.ptp(run.energy) > 1e-3  # it does lose energy: a drift number would mislead


def test_without_damping_or_force_the_same_model_reports_its_energy_drift() -> None:
    run = lg.simulate(
        lg.examples.mass_spring_damper(), t_span=5.0, parameters={"B": 0.0}, samples=101, **TIGHT
    )
    drift = run.drift()
    assert "energy_not_conserved" not in drift and drift["energy_relative"] < 1e-8
    driven = lg.simulate(lg.examples.mass_spring_damper(), t_span=1.0, parameters={"f": 2.0})
    assert driven.drift()["energy_not_conserved"] == "forcing, dissipation"


def test_a_moving_pivot_pendulum_reports_explicit_time_dependence() -> None:
    run = lg.simulate(lg.examples.moving_pivot_pendulum(), t_span=2.0, samples=51)
    drift = run.drift()
    assert drift["energy_not_conserved"] == "explicit time dependence"
    assert drift["energy_function_not_conserved"] == "explicit time dependence"
    assert not set(ENERGY_NUMBERS + H_NUMBERS) & set(drift)
    assert run.drift_summary() == "energy not conserved: explicit time dependence"


def test_a_circuit_with_a_resistor_reports_dissipation() -> None:
    run = lg.simulate(lg.examples.series_rlc(), t_span=0.02, samples=51)
    drift = run.drift()
    assert drift["energy_not_conserved"] == "forcing, dissipation"  # the source u = 1 V too
    assert not set(ENERGY_NUMBERS) & set(drift)
    free = lg.simulate(lg.examples.series_rlc(), t_span=0.02, parameters={"u": 0.0}, samples=51)
    assert free.drift()["energy_not_conserved"] == "dissipation"


def test_the_double_pendulum_reports_its_energy_drift() -> None:
    run = lg.simulate(lg.examples.double_pendulum(), t_span=5.0, samples=101, **TIGHT)
    drift = run.drift()
    assert set(drift) == set(ENERGY_NUMBERS)
    relative = np.max(np.abs(run.energy - run.energy[0])) / abs(run.energy[0])
    assert drift["energy_relative"] == pytest.approx(relative) and relative < 1e-8
    assert run.drift_summary() == f"max |dE/E0| = {relative:.3g}"


def test_a_bead_on_a_rotating_hoop_reports_the_jacobi_integral_conserved() -> None:
    run = lg.simulate(rotating_hoop(), t_span=5.0, samples=201, **TIGHT)
    drift = run.drift()
    h = run.energy_function
    assert h is not None
    assert drift["energy_function_relative"] == pytest.approx(np.max(np.abs(h - h[0])) / abs(h[0]))
    assert drift["energy_function_relative"] < 1e-8
    assert drift["energy_not_conserved"].startswith("constraints that do work")
    assert np.ptp(run.energy) > 0.1  # T + V swings: the motor feeds and takes energy
    assert "h is the conserved energy" in run.drift_summary()


def test_a_constraint_that_moves_with_time_does_work() -> None:
    # a bead on a straight wire turning at omega about the origin, in Cartesian coordinates
    x, y, m, omega = sp.symbols("x y m omega")
    t = sp.Symbol("t")
    wire = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, omega: 1.0},
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Holonomic(x * sp.sin(omega * t) - y * sp.cos(omega * t))],
    )
    start = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 1.0}
    run = lg.simulate(wire, start, 1.0, samples=11, **TIGHT)
    drift = run.drift()
    assert drift["energy_not_conserved"] == "constraints that do work"
    assert drift["constraint_residual_max"] < 1e-8


def test_a_cyclic_momentum_pushed_by_a_force_is_not_conserved() -> None:
    x, x_dot, f = sp.symbols("x x_dot f")
    pushed = lg.System(
        coordinates=[x],
        parameters={f: 1.0},
        kinetic=x_dot**2 / 2,
        generalized_forces={x: f},
    )
    run = lg.simulate(pushed, {"x": 0.0, "x_dot": 0.0}, 1.0, samples=5)
    drift = run.drift()
    assert drift["conserved_p_x_not_conserved"] == "forcing"
    assert drift["energy_not_conserved"] == "forcing"
    coasting = lg.simulate(pushed, {"x": 0.0, "x_dot": 1.0}, 1.0, samples=5, parameters={"f": 0})
    assert coasting.drift()["conserved_p_x_relative"] == 0.0


def test_the_reasons_are_the_documented_words() -> None:
    reasons = {
        lg.simulate(lg.examples.mass_spring_damper(), t_span=0.1).drift()["energy_not_conserved"],
        lg.simulate(lg.examples.moving_pivot_pendulum(), t_span=0.1).drift()[
            "energy_not_conserved"
        ],
    }
    assert reasons <= set(REASONS)


def test_a_trajectory_without_that_knowledge_reports_every_drift() -> None:
    run = lg.simulate(lg.examples.mass_spring_damper(), t_span=1.0, samples=11)
    buffer = io.StringIO()
    run.to_csv(buffer)
    back = lg.Trajectory.from_csv(io.StringIO(buffer.getvalue()))
    assert back.not_conserved is None and set(ENERGY_NUMBERS) <= set(back.drift())
