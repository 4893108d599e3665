"""Equilibria and normal modes on the constraint manifold against the same systems in angles.

- Cartesian pendulum: rest at (0, -l) (stable, the rod pulling up with m g: lambda = -m g/(2 l))
  and (0, l) (unstable); small oscillations at sqrt(g/l), swinging along x;
- double pendulum in Cartesian coordinates (two rods): four equilibria, one stable, and the
  normal modes of examples/double_pendulum (angles), omega^2 = (g/l)(2 -+ sqrt 2) for equal
  masses and rods, with shapes mapped by x1 = l th1, x2 = l (th1 + th2);
- a skate on an incline (non-holonomic): at rest only across the slope, phi = +-pi/2, the
  blade holding it with lambda = +-m g sin(alpha), a family over x and y;
- the rolling disc: upright at rest it falls (unstable).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import equilibria, normal_modes

sys.path.insert(0, str(Path(__file__).parents[1] / "constraints"))
import constraint_systems as cs

x, y, m, g, l = sp.symbols("x y m g l")


def cartesian_double_pendulum() -> lg.System:
    """examples/double_pendulum with the bobs at Cartesian (x1, y1), (x2, y2) on two rods."""
    x1, y1, x2, y2, m1, m2, l1, l2 = sp.symbols("x1 y1 x2 y2 m1 m2 l1 l2")
    return lg.System(
        name="double_pendulum_cartesian",
        coordinates=[x1, y1, x2, y2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob1", m1, (x1, y1)), lg.Particle("bob2", m2, (x2, y2))],
        constraints=[
            lg.Holonomic(x1**2 + y1**2 - l1**2, name="rod1"),
            lg.Holonomic((x2 - x1) ** 2 + (y2 - y1) ** 2 - l2**2, name="rod2"),
        ],
    )


def test_cartesian_pendulum_rests_below_and_above() -> None:
    found = equilibria(cs.pendulum())
    assert [(dict(e.state), e.stable) for e in found] == [
        ({x: 0, y: -l}, True),
        ({x: 0, y: l}, False),
    ]
    below = found.equilibria[0]
    (lam,) = below.multipliers.values()
    assert sp.simplify(lam + m * g / (2 * l)) == 0
    # the stiffness on the circle, in x: m g / l, as for the pendulum in its angle (m g l)
    assert below.stiffness_coordinates == (x,)
    assert sp.simplify(below.stiffness[0, 0] - m * g / l) == 0
    assert below.stability_condition == sp.true


def test_cartesian_pendulum_swings_at_sqrt_g_over_l_along_x() -> None:
    modes = normal_modes(cs.pendulum())
    assert modes.frequencies == (sp.sqrt(g) / sp.sqrt(l),)
    assert modes.shapes == (sp.ImmutableMatrix([1, 0]),)
    about_state = normal_modes(cs.pendulum(), {"x": 0, "y": -0.7})
    assert [float(w) for w in about_state.frequencies] == pytest.approx([math.sqrt(9.81 / 0.7)])


def test_cartesian_double_pendulum_has_the_angle_forms_modes() -> None:
    system = cartesian_double_pendulum()
    found = equilibria(system)
    assert sorted(e.stable for e in found) == [False, False, False, True]
    modes = normal_modes(system)
    angles = normal_modes(lg.examples.double_pendulum())
    ours = [float(w) for w in modes.frequencies]
    assert ours == pytest.approx([float(w) for w in angles.frequencies], rel=1e-10)
    assert ours == pytest.approx(
        [math.sqrt(9.81 * (2 - math.sqrt(2))), math.sqrt(9.81 * (2 + math.sqrt(2)))]
    )
    for cartesian, angular in zip(modes.shapes, angles.shapes):
        th1, th2 = (float(v) for v in angular)
        dx1, dy1, dx2, dy2 = (float(v) for v in cartesian)
        assert (dy1, dy2) == pytest.approx((0.0, 0.0), abs=1e-12)
        assert dx2 / dx1 == pytest.approx((th1 + th2) / th1, rel=1e-9)


def test_the_skate_rests_only_across_the_slope() -> None:
    found = equilibria(cs.knife_edge())
    phi, lam = sp.Symbol("phi"), sp.Symbol("lambda_1")
    states = sorted((e.state[phi], e.multipliers[lam]) for e in found)
    alpha = sp.Symbol("alpha")
    assert states == sorted(
        [(-sp.pi / 2, -g * m * sp.sin(alpha)), (sp.pi / 2, g * m * sp.sin(alpha))]
    )
    assert all(set(e.free) == {x, y} for e in found)


def test_the_upright_rolling_disc_falls_at_rest() -> None:
    theta = sp.Symbol("theta")
    upright = [e for e in equilibria(lg.examples.rolling_disc()) if e.state[theta] == 0]
    assert len(upright) == 1 and upright[0].stable is False


def four_bar() -> lg.System:
    """A four-bar linkage in its three link angles, closed by two loop equations; a mass at
    the crank's tip, at the coupler's joint and in the middle of the rocker."""
    a, b, c = sp.symbols("a b c")
    l1, l2, l3, d = sp.symbols("l1 l2 l3 d")
    tip = (l1 * sp.cos(a), l1 * sp.sin(a))
    joint = (tip[0] + l2 * sp.cos(b), tip[1] + l2 * sp.sin(b))
    rocker = (d + l3 * sp.cos(c) / 2, l3 * sp.sin(c) / 2)
    return lg.System(
        name="four_bar",
        coordinates=[a, b, c],
        parameters={m: 1.0, g: 9.81, l1: 1.0, l2: 2.0, l3: 1.5, d: 2.5},
        gravity=(0, -g),
        particles=[
            lg.Particle("tip", m, tip),
            lg.Particle("joint", m, joint),
            lg.Particle("rocker", m, rocker),
        ],
        constraints=[
            lg.Holonomic(joint[0] - d - l3 * sp.cos(c), name="loop x"),
            lg.Holonomic(joint[1] - l3 * sp.sin(c), name="loop y"),
        ],
    )


def test_a_four_bar_linkage_is_analyzed_numerically_on_its_closed_chain() -> None:
    report = lg.analyze(four_bar())
    assert (report.dof, report.configuration_dimension) == (1, 1)
    assert report.equilibria is not None and report.equilibria.method == "numeric"
    stable = report.equilibria.stable()
    assert len(stable) == 2  # one in each assembly mode
    assert "closed chain" in (report.failure("hamiltonian") or "")
    modes = report.normal_modes
    assert modes is not None
    # the frequency does not depend on which angle is kept independent
    about = {q.name: float(v) for q, v in modes.about.items()}
    for kept in (["a", "a_dot"], ["c", "c_dot"]):
        lin = lg.analysis.linearize(four_bar(), about, independent=kept)
        assert [float(w) for w in lin.frequencies] == pytest.approx(
            [float(w) for w in modes.frequencies], rel=1e-8
        )
