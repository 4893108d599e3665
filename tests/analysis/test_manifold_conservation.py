"""Conservation on the constraint manifold: the energy function, the Jacobi integral of moving
constraints, cyclic momenta and Noether charges, against results derived by hand.

- a bead on a horizontal hoop of radius R turning at omega in its own plane about a point of
  its rim, in Cartesian x, y with the rheonomic constraint
  (x - R cos wt)^2 + (y - R sin wt)^2 = R^2: h = T is not conserved (the hoop does work), the
  Jacobi integral E - omega L_z is.  In the angle phi of the bead about the hoop's centre,
  measured from the pivot's diameter, T = m R^2 [w^2 + (w + phi_dot)^2 + 2 w (w + phi_dot)
  cos(phi)] / 2 and the reduced Lagrangian's h = T2 - T0 is
  m R^2 phi_dot^2 / 2 - m R^2 w^2 (1 + cos phi) (Goldstein §2.7): the two must agree;
- the bead on a hoop spinning about the vertical (3-D, two constraints): E - omega L_z against
  m R^2 th_dot^2 / 2 - m R^2 w^2 sin^2 th / 2 - m g R cos th;
- a skate: the blade does no work (h conserved, also with a force across the blade), and the
  heading's momentum I phi_dot is conserved (the blade's Jacobian has no phi column);
- a particle on a sphere: the three angular momenta are conserved, the linear ones are not.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import analyze, cyclic_coordinates, energy_conservation
from lagrangian.analysis.manifold.symmetries import jacobi_integral

sys.path.insert(0, str(Path(__file__).parents[1] / "constraints"))
import constraint_systems as cs

x, y, z = sp.symbols("x y z")
m, g, R, omega = sp.symbols("m g R omega")
HOOP = {"m": 0.4, "R": 0.5, "omega": 2.0}


def spinning_hoop() -> lg.System:
    """The bead on a horizontal hoop turning about a point of its rim."""
    t = lg.t
    return lg.System(
        name="hoop_turning_about_its_rim",
        coordinates=[x, y],
        parameters={m: HOOP["m"], R: HOOP["R"], omega: HOOP["omega"]},
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[
            lg.Holonomic(
                (x - R * sp.cos(omega * t)) ** 2 + (y - R * sp.sin(omega * t)) ** 2 - R**2,
                name="hoop",
            )
        ],
    )


def hoop_state(angle: float, rate: float, time: float) -> dict[str, float]:
    """x, y and their rates for the bead at angle phi (rate phi_dot) at time t."""
    radius, spin = HOOP["R"], HOOP["omega"]
    turn = spin * time + angle
    return {
        "t": time,
        "x": radius * (math.cos(spin * time) + math.cos(turn)),
        "y": radius * (math.sin(spin * time) + math.sin(turn)),
        "x_dot": -radius * (spin * math.sin(spin * time) + (spin + rate) * math.sin(turn)),
        "y_dot": radius * (spin * math.cos(spin * time) + (spin + rate) * math.cos(turn)),
    }


def test_the_turning_hoop_does_work_and_keeps_its_jacobi_integral() -> None:
    energy = energy_conservation(spinning_hoop())
    assert not energy.conserved
    assert "'hoop' (constraints[0]) moves with time" in energy.reason
    assert energy.constraint_power != 0
    found = jacobi_integral(spinning_hoop())
    assert found is not None and found.kappa == -omega
    assert "rotation in the (x, y) plane" in found.reason
    for angle, rate, time in [(0.3, 1.1, 0.0), (2.0, -0.4, 0.7), (-1.2, 2.5, 1.9)]:
        state = hoop_state(angle, rate, time)
        reduced = (
            HOOP["m"] * HOOP["R"] ** 2 * (rate**2 / 2 - HOOP["omega"] ** 2 * (1 + math.cos(angle)))
        )
        assert cs.numeric(found.expression, {**state, **HOOP}) == pytest.approx(reduced)


def test_the_jacobi_integral_holds_along_the_motion() -> None:
    found = jacobi_integral(spinning_hoop())
    assert found is not None
    start = hoop_state(0.4, 0.0, 0.0)
    run = lg.simulate(
        spinning_hoop(),
        {k: v for k, v in start.items() if k != "t"},
        2.0,
        samples=50,
        rtol=1e-10,
        atol=1e-12,
        project_steps=True,
        method="DOP853",
    )
    names = ["x", "y", "x_dot", "y_dot"]
    values = sp.lambdify(
        [sp.Symbol(n) for n in names],
        found.expression.subs({m: HOOP["m"], omega: HOOP["omega"]}),
        "numpy",
    )(*(np.asarray(run[n]) for n in names))
    assert np.ptp(values) < 1e-6 * abs(values[0])


def test_the_vertical_hoop_in_three_coordinates_has_the_textbook_jacobi_integral() -> None:
    report = analyze(cs.rotating_hoop())
    assert report.energy is not None and not report.energy.conserved
    (jacobi,) = [c for c in report.conserved if c.name == "jacobi"]
    mass, radius, spin = 0.5, 0.4, 3.0
    for angle, rate, time in [(0.5, 0.2, 0.0), (1.3, -1.0, 0.4)]:
        state = cs.hoop_state(angle, rate, time)
        reduced = (
            mass * radius**2 * rate**2 / 2
            - mass * radius**2 * spin**2 * math.sin(angle) ** 2 / 2
            - mass * 9.81 * radius * math.cos(angle)
        )
        values = {**state, "m": mass, "g": 9.81, "R": radius, "omega": spin}
        assert cs.numeric(jacobi.expression, values) == pytest.approx(reduced)
    assert report.dof == report.configuration_dimension == 1


def test_the_blade_does_no_work_even_against_a_force_across_it() -> None:
    energy = energy_conservation(cs.knife_edge())
    assert energy.conserved and "do no work" in energy.reason
    force = sp.Symbol("F")
    phi = sp.Symbol("phi")
    pushed = cs.knife_edge().replace(
        parameters={**cs.knife_edge().parameters, force: 1.5},
        generalized_forces={x: force * sp.sin(phi), y: -force * sp.cos(phi)},
    )
    energy = energy_conservation(pushed)
    assert energy.conserved and "vanish on the manifold" in energy.reason


def test_the_skate_keeps_its_heading_momentum_not_its_sideways_one() -> None:
    cyclic = {c.coordinate.name: c for c in cyclic_coordinates(cs.knife_edge())}
    assert set(cyclic) == {"y", "phi"}  # x is in the potential m g sin(alpha) x
    assert cyclic["phi"].conserved and cyclic["phi"].obstructions == ()
    assert not cyclic["y"].conserved and cyclic["y"].obstructions == ("constraint",)
    assert "'blade' (constraints[0])" in cyclic["y"].reason


def test_the_pendulum_rod_spoils_p_x() -> None:
    (cyclic,) = cyclic_coordinates(cs.pendulum())
    assert cyclic.coordinate == x and not cyclic.conserved
    assert cyclic.obstructions == ("constraint",)
    report = analyze(cs.pendulum())
    assert [c.name for c in report.conserved] == ["h"]


def test_on_a_sphere_angular_momenta_are_conserved_and_linear_ones_are_not() -> None:
    sphere = lg.System(
        coordinates=[x, y, z],
        parameters={m: 1.0, R: 1.0},
        particles=[lg.Particle("bead", m, (x, y, z))],
        constraints=[lg.Holonomic(x**2 + y**2 + z**2 - R**2, name="sphere")],
    )
    report = analyze(sphere)
    x_dot, y_dot, z_dot = sp.symbols("x_dot y_dot z_dot")
    angular = [
        m * (x * y_dot - y * x_dot),
        m * (x * z_dot - z * x_dot),
        m * (y * z_dot - z * y_dot),
    ]
    noether = [c.expression for c in report.conserved if c.name.startswith("noether")]
    assert len(noether) == 3
    for charge in noether:
        assert any(sp.simplify(charge / a).is_number for a in angular)
    assert all(not c.conserved for c in report.cyclic)  # x, y, z absent from L, held by R
