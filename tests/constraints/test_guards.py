"""A constrained system is never silently treated as unconstrained: analyze reports the
classification and degrees of freedom and analyzes on the constraint manifold; simulate
enforces the constraints by multipliers and refuses the unilateral ones."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationError

x, y, m, g, l = sp.symbols("x y m g l")


def cartesian_pendulum() -> lg.System:
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        particles=[lg.Particle("bob", m, (x, y))],
        gravity=(0, -g),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
        initial={x: 0.6, y: -0.8, sp.Symbol("x_dot"): 0.0, sp.Symbol("y_dot"): 0.0},
    )


def test_analyze_counts_the_constraint_and_works_on_the_manifold() -> None:
    report = lg.analyze(cartesian_pendulum())
    assert report.dof == 1
    assert report.constraints and report.constraints[0].name == "rod"
    # equilibria and modes on the constraint, never of the free particle (which has none)
    assert report.equilibria is not None
    assert [(dict(e.state), e.stable) for e in report.equilibria] == [
        ({x: 0, y: -l}, True),
        ({x: 0, y: l}, False),
    ]
    assert report.normal_modes is not None
    assert report.normal_modes.frequencies == (sp.sqrt(g) / sp.sqrt(l),)


def test_simulate_enforces_the_constraints_and_simulates_unilateral_ones() -> None:
    run = lg.simulate(cartesian_pendulum(), t_span=1.0, samples=11, baumgarte=(10, 10))
    assert run.success and run.multiplier_names == ("lambda_1",)
    residual = run.drift()["constraint_residual_max"]
    assert residual is not None and residual < 1e-6
    derived = lg.simulate(
        lg.derive(cartesian_pendulum()), {"x": 0.6, "y": -0.8, "x_dot": 0, "y_dot": 0}, 1.0
    )
    assert derived.multiplier_names == ("lambda_1",)  # never the unconstrained equations
    bowl = cartesian_pendulum().replace(constraints=[lg.Unilateral(l**2 - x**2 - y**2)])
    resting = lg.simulate(bowl, t_span=1.0)  # pulled taut by gravity: stays active
    assert resting.success and resting.events == () and resting.multiplier_names == ("lambda_1",)


def test_the_discrete_action_refuses_a_constrained_system() -> None:
    from lagrangian.simulation import stationary_path

    with pytest.raises(SimulationError, match="constrained system is not implemented yet"):
        stationary_path(cartesian_pendulum(), [0.6, -0.8], [0.0, -1.0], 1.0)
