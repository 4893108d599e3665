"""Plots of trajectories: each function draws what it says on the Axes it returns, and
save_plots writes one PNG (to pytest's tmp_path, never into the repository)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
from matplotlib.figure import Figure

import lagrangian as lg
from lagrangian.render.plots import (
    plot_energy_drift,
    plot_phase_portrait,
    plot_time_series,
    save_plots,
)
from lagrangian.simulation import Trajectory, simulate


@pytest.fixture(scope="module")
def swing() -> Trajectory:
    return simulate(lg.examples.double_pendulum(), t_span=5.0, samples=251, method="DOP853")


def test_save_plots_writes_one_png_of_the_double_pendulum(swing: Trajectory, tmp_path) -> None:
    path = save_plots(swing, tmp_path / "double_pendulum.png")
    data = path.read_bytes()
    assert data.startswith(b"\x89PNG\r\n\x1a\n") and len(data) > 10_000


def test_time_series_draws_each_named_column(swing: Trajectory) -> None:
    ax = plot_time_series(swing)
    assert [line.get_label() for line in ax.get_lines()] == ["θ", "φ"]  # names as letters
    np.testing.assert_array_equal(ax.get_lines()[1].get_ydata(), swing["phi"])
    ax = plot_time_series(swing, names=["theta_dot"])
    assert [line.get_label() for line in ax.get_lines()] == ["θ\u0307"]  # theta_dot: θ̇


def test_phase_portrait_on_a_given_axes(swing: Trajectory) -> None:
    ax = Figure().add_subplot()
    assert plot_phase_portrait(swing, "phi", ax=ax) is ax
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("φ", "φ\u0307")
    np.testing.assert_array_equal(ax.get_lines()[0].get_xdata(), swing["phi"])


def test_energy_drift_is_relative_unless_the_initial_energy_is_zero(swing: Trajectory) -> None:
    ax = plot_energy_drift(swing)
    energy = swing.energy
    np.testing.assert_allclose(ax.get_lines()[0].get_ydata(), (energy - energy[0]) / abs(energy[0]))
    assert ax.get_ylabel() == "(E - E0) / |E0|"
    circuit = simulate(lg.examples.series_rlc(), t_span=0.1, samples=11)  # starts with E = 0
    assert plot_energy_drift(circuit).get_ylabel() == "E - E0"
    pivot = simulate(lg.examples.moving_pivot_pendulum(), t_span=1.0, samples=11)
    labels = [line.get_label() for line in plot_energy_drift(pivot).get_lines()]
    assert labels == ["E = T + V", "h"]


def test_coordinates_of_different_sizes_get_panels_of_their_own():
    # the heavy top spins: psi grows to tens of radians while theta nods by a fraction of one
    from lagrangian.render.plots import overview, scale_groups

    top = lg.simulate(lg.examples.heavy_symmetric_top(), t_span=10.0, samples=200)
    groups = scale_groups(top)  # psi ~ 480 rad, phi ~ 27 rad, theta within 0.62 rad
    assert ["theta"] in groups and ["psi"] in groups
    figure = overview(top)
    assert len(figure.axes) == len(groups) + 2  # the panels, the phase portrait, the energy


def test_a_constrained_overview_plots_the_constraint_forces_in_their_own_panel() -> None:
    """The rolling cylinder's friction is constant, -m g sin(alpha) / 3 (the solved
    multiplier), and gets a panel of its own; an unconstrained overview has none."""
    import math

    import sympy as sp

    from lagrangian.render.plots import overview
    from lagrangian.simulation import simulate

    system = lg.examples.cylinder_on_incline()
    figure = overview(simulate(system, t_span=1.0, samples=50), system=system)
    (panel,) = [ax for ax in figure.axes if ax.get_title() == "Constraint forces"]
    (line,) = panel.get_lines()
    values = dict(system.parameters)
    m, g, alpha = (values[sp.Symbol(n)] for n in ("m", "g", "alpha"))
    assert np.allclose(line.get_ydata(), -m * g * math.sin(alpha) / 3, rtol=1e-8)
    free = overview(simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=50))
    assert all(ax.get_title() != "Constraint forces" for ax in free.axes)


def test_impacts_are_marked_where_the_ball_hits_the_floor() -> None:
    """One dashed line per impact in the time series and the energy panel, at the impact
    times of the run (its impacts table), and none for a run without impacts."""
    from lagrangian.render.plots import MARKED_IMPACTS, overview
    from lagrangian.simulation import simulate

    system = lg.examples.bouncing_ball()
    run = simulate(system, t_span=2.0, samples=201)
    assert 0 < len(run.impacts) < MARKED_IMPACTS
    figure = overview(run, system=system)
    for title in ("Time series", "Energy change"):
        (ax,) = [a for a in figure.axes if a.get_title().startswith(title)]
        marks = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        assert [float(line.get_xdata()[0]) for line in marks] == [i.t for i in run.impacts]
        assert marks[0].get_label() == "impacts"
    free = overview(simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=20))
    assert not [line for a in free.axes for line in a.get_lines() if line.get_label() == "impacts"]


def test_contacts_that_never_close_get_no_curve() -> None:
    """Newton's cradle from rest with the first ball moving: its two contacts only strike
    (impulses, no lasting force), so their multipliers are never finite; a gas's dozens of
    idle contacts likewise add no panel and no legend of NaN lines."""
    from lagrangian.render.plots import overview

    cradle = lg.examples.newtons_cradle()
    run = simulate(cradle, t_span=1.0, samples=50)
    assert run.multipliers is not None and not np.isfinite(run.multipliers).any()
    figure = overview(run, system=cradle)
    assert not [ax for ax in figure.axes if ax.get_title().startswith("Constraint forces")]
    # a ball at rest on the floor: its contact acts, the panel shows that one curve only
    ball = lg.examples.bouncing_ball()
    resting = overview(simulate(ball, t_span=6.0, samples=300), system=ball)
    (panel,) = [ax for ax in resting.axes if ax.get_title().startswith("Constraint forces")]
    (line,) = panel.get_lines()
    assert np.nanmax(line.get_ydata()) == pytest.approx(9.81, rel=1e-6)  # m g at rest
