"""Conserved quantities along simulated trajectories, against the physics: Kepler's second
law (p_theta of the planet), the angular momentum of a central force written in Cartesian
coordinates, a quantity that is not conserved (its drift is large), constraint forces that
spoil a cyclic momentum, and the CSV round trip of the new columns."""

from __future__ import annotations

import io

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationError
from lagrangian.simulation import Trajectory

TIGHT = {"method": "DOP853", "rtol": 1e-11, "atol": 1e-12}


def central_force_cartesian() -> lg.System:
    """A particle in the plane attracted by a spring to the origin: V = k (x^2 + y^2) / 2."""
    x, y, m, k = sp.symbols("x y m k")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 2.0, k: 3.0},
        potential=k * (x**2 + y**2) / 2,
        particles=[lg.Particle("p", m, (x, y))],
        initial={"x": 1.0, "y": 0.0, "x_dot": 0.3, "y_dot": 0.8},
    )


def test_planet_keeps_its_areal_velocity() -> None:
    """Kepler's second law: p_theta = m r^2 theta_dot is constant (theta is cyclic)."""
    run = lg.simulate(lg.examples.planet(), t_span=20.0, samples=400, **TIGHT)
    assert list(run.conserved) == ["p_theta"]
    r, theta_dot = run["r"], run["theta_dot"]
    np.testing.assert_allclose(run["p_theta"], r**2 * theta_dot)  # m = 1
    assert np.ptp(r) > 0.1  # a genuine ellipse, so r^2 theta_dot is not trivially constant
    assert run.drift()["conserved_p_theta_relative"] < 1e-9
    assert run.names[-2:] == ("energy", "p_theta")


def test_requested_angular_momentum_is_conserved_and_position_is_not() -> None:
    x, y_dot, m = sp.symbols("x y_dot m")
    run = lg.simulate(
        central_force_cartesian(),
        t_span=10.0,
        samples=200,
        conserved={"L_z": "m*(x*y_dot - y*x_dot)", "x_position": x, "sympy_L": m * (x * y_dot)},
        **TIGHT,
    )
    assert run["L_z"][0] == pytest.approx(2.0 * 0.8)
    drift = run.drift()
    assert drift["conserved_L_z_relative"] < 1e-9
    assert drift["conserved_x_position_absolute"] > 0.5  # it oscillates: drift reports it
    assert drift["conserved_sympy_L_relative"] > 0.1


def test_time_functions_are_accepted_as_conserved_quantities() -> None:
    t = sp.Symbol("t")
    x, y = sp.Function("x")(t), sp.Function("y")(t)
    run = lg.simulate(
        central_force_cartesian(),
        t_span=5.0,
        samples=50,
        conserved={"L_z": sp.Symbol("m") * (x * y.diff(t) - y * x.diff(t))},
        **TIGHT,
    )
    assert run.drift()["conserved_L_z_relative"] < 1e-9


def test_a_constraint_on_a_cyclic_coordinate_removes_its_momentum() -> None:
    """In the Cartesian pendulum x is absent from L, but the rod pulls along x: m x_dot is
    not conserved, so it is not reported."""
    x, y, m, g, l = sp.symbols("x y m g l")
    pendulum = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
    )
    free = pendulum.replace(constraints=())
    assert (
        "p_x"
        in lg.simulate(
            free, {"x": 0.5, "y": -0.8, "x_dot": 0, "y_dot": 0}, 0.1, samples=3
        ).conserved
    )
    start = {"x": np.sin(0.5), "y": -np.cos(0.5), "x_dot": 0.0, "y_dot": 0.0}
    assert "p_x" not in lg.simulate(pendulum, start, 0.1, samples=3).conserved


def test_a_gas_in_a_box_keeps_no_momentum_and_asks_no_analysis(monkeypatch) -> None:
    """Disks flying freely (no field: every coordinate absent from L) in a box: each wall
    pushes along a coordinate, so no momentum is conserved through the impacts; that is seen
    from the constraints' symbols, without the analysis of cyclic coordinates (which asks
    every constraint for its force along every coordinate), while a free coordinate of the
    same system is still analysed and reported."""
    from lagrangian.examples.gas import hard_disk_gas
    from lagrangian.simulation import conserved

    gas = hard_disk_gas(3, radius=0.08)
    speeds = [sp.Symbol(f"{q.name}_dot") for q in gas.coordinates]
    flying = gas.replace(particles=(), gravity=None, kinetic=sum(v**2 for v in speeds) / 2)
    asked = []
    analysis = conserved.cyclic_coordinates
    monkeypatch.setattr(
        conserved, "cyclic_coordinates", lambda eom: asked.append(eom) or analysis(eom)
    )
    run = lg.simulate(flying, t_span=1.0, samples=3)
    assert run.success and run.impacts and not run.conserved and not asked
    z = sp.Symbol("z")
    lifted = flying.replace(
        coordinates=(*flying.coordinates, z), kinetic=flying.kinetic + sp.Symbol("z_dot") ** 2 / 2
    )
    run = lg.simulate(lifted, {**flying.initial, "z": 0.0, "z_dot": 0.5}, 1.0, samples=3)
    assert list(run.conserved) == ["p_z"] and len(asked) == 1
    np.testing.assert_allclose(run["p_z"], 0.5)


def test_bad_conserved_quantities_are_named() -> None:
    with pytest.raises(SimulationError, match=r"conserved\.bad.*nonsense") as caught:
        lg.simulate(
            central_force_cartesian(),
            t_span=1.0,
            conserved={"bad": "nonsense*x", "worse": sp.Symbol("z"), "odd": [1, 2]},
        )
    text = str(caught.value)
    assert "conserved.worse" in text and "z" in text
    assert "conserved.odd" in text


def test_conserved_columns_survive_csv() -> None:
    run = lg.simulate(lg.examples.planet(), t_span=1.0, samples=5)
    buffer = io.StringIO()
    run.to_csv(buffer)
    assert buffer.getvalue().splitlines()[0].endswith(",energy,p_theta")
    buffer.seek(0)
    back = Trajectory.from_csv(buffer)
    np.testing.assert_allclose(back["p_theta"], run["p_theta"], rtol=1e-15)


def test_conserved_column_of_the_wrong_length_is_refused() -> None:
    with pytest.raises(SimulationError, match=r"conserved\['c'\] has shape \(3,\)"):
        Trajectory(
            t=[0.0, 1.0],
            q=[[0.0], [1.0]],
            q_dot=[[1.0], [1.0]],
            coordinates=("x",),
            energy=[0.5, 0.5],
            conserved={"c": [1.0, 2.0, 3.0]},
        )
