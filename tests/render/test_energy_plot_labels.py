"""The energy plot is labelled as the drift report speaks: a drift where the system conserves
its energy, the change and why where it does not, and h named where it is the conserved one."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import sympy as sp

import lagrangian as lg
from lagrangian.render.plots import energy_title, plot_energy_drift


def test_a_conserved_energy_is_plotted_as_a_drift() -> None:
    run = lg.simulate(lg.examples.double_pendulum(), t_span=1.0, samples=21)
    assert plot_energy_drift(run).get_title() == "Energy drift"


def test_a_damped_energy_is_plotted_as_a_change_with_its_reason() -> None:
    run = lg.simulate(lg.examples.mass_spring_damper(), t_span=1.0, samples=21)
    ax = plot_energy_drift(run)
    assert ax.get_title() == "Energy change (not conserved: dissipation)"
    assert [line.get_label() for line in ax.get_lines()] == ["E = T + V"]
    pivot = lg.simulate(lg.examples.moving_pivot_pendulum(), t_span=1.0, samples=21)
    assert energy_title(pivot) == "Energy change (not conserved: explicit time dependence)"


def test_the_jacobi_integral_is_named_where_it_is_the_conserved_energy() -> None:
    theta, theta_dot, omega = sp.symbols("theta theta_dot omega")
    hoop = lg.System(
        coordinates=[theta],
        parameters={omega: 5.0},
        kinetic=(theta_dot**2 + omega**2 * sp.sin(theta) ** 2) / 2,
        potential=-9.81 * sp.cos(theta),
    )
    run = lg.simulate(hoop, {"theta": 0.5, "theta_dot": 0.0}, 1.0, samples=21)
    title = plot_energy_drift(run).get_title()
    assert title.startswith("Drift of h, the conserved energy")
    assert "T + V not conserved: constraints that do work" in title


def test_a_trajectory_read_back_from_csv_keeps_the_plain_title(tmp_path) -> None:
    run = lg.simulate(lg.examples.mass_spring_damper(), t_span=1.0, samples=21)
    run.to_csv(tmp_path / "run.csv")
    assert energy_title(lg.Trajectory.from_csv(tmp_path / "run.csv")) == "Energy drift"
