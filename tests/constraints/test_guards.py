"""A constrained system is never silently treated as unconstrained: analyze reports the
classification and degrees of freedom and says which parts are not computed; simulate
refuses with the way forward."""

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


def test_analyze_counts_the_constraint_and_computes_nothing_wrong() -> None:
    report = lg.analyze(cartesian_pendulum())
    assert report.dof == 1
    assert report.constraints and report.constraints[0]["name"] == "rod"
    assert report.equilibria is None and report.normal_modes is None
    assert "eliminate" in (report.failure("equilibria") or "")


def test_simulate_refuses_until_constrained_simulation_lands() -> None:
    with pytest.raises(SimulationError, match="constraints is not supported yet"):
        lg.simulate(cartesian_pendulum(), t_span=1.0)
    with pytest.raises(SimulationError, match="eliminate"):
        lg.simulate(
            lg.derive(cartesian_pendulum()), {"x": 0.6, "y": -0.8, "x_dot": 0, "y_dot": 0}, 1.0
        )
