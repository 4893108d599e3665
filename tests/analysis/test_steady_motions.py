"""Steady motions of constraints that move by a symmetry, against the textbook bead on a hoop
spinning at omega about its vertical diameter (Goldstein §2.7; Taylor, Classical Mechanics,
§7.6): at rest relative to the hoop at the bottom, stable while omega^2 < g/R, and at
cos(theta) = g/(R omega^2) (z = -g/omega^2), which exists and is stable beyond; here in
Cartesian x, y, z with the hoop's plane turning, x sin(wt) - y cos(wt) = 0."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import sympy as sp

from lagrangian.analysis import analyze
from lagrangian.analysis.steady_motions import steady_motions
from lagrangian.errors import AnalysisError

sys.path.insert(0, str(Path(__file__).parents[1] / "constraints"))
import constraint_systems as cs

x, y, z, g, R, m = sp.symbols("x y z g R m")


def _motions(spin: float) -> dict[str, tuple]:
    found = steady_motions(cs.rotating_hoop(), parameters={"omega": spin})
    where = {}
    for motion, velocities in zip(found.motions, found.velocities):
        if motion.exists is False:
            continue
        height = float(motion.state[z].subs({g: 9.81, R: 0.4}))
        side = float(motion.state[x].subs({g: 9.81, R: 0.4}))
        key = "bottom" if side == 0 and height < 0 else "top" if side == 0 else f"side {side:+.3f}"
        where[key] = (height, motion.stable, velocities, motion)
    return where


def test_slow_spin_keeps_the_bead_at_the_bottom() -> None:
    found = _motions(3.0)  # R omega^2 = 3.6 < g
    assert set(found) == {"bottom", "top"}
    assert found["bottom"][1] is True and found["top"][1] is False


def test_fast_spin_lifts_the_bead_to_cos_theta_g_over_r_omega_squared() -> None:
    spin = 6.0  # R omega^2 = 14.4 > g
    found = _motions(spin)
    sides = [k for k in found if k.startswith("side")]
    assert len(sides) == 2 and found["bottom"][1] is False
    for key in sides:
        height, stable, velocities, motion = found[key]
        assert height == pytest.approx(-9.81 / spin**2)
        assert stable is True
        # it turns with the hoop: y_dot = omega x at t = 0
        side = float(motion.state[x].subs({g: 9.81, R: 0.4}))
        assert float(velocities[sp.Symbol("y_dot")].subs({g: 9.81, R: 0.4})) == pytest.approx(
            spin * side
        )
        # the hoop pushes toward the axis with m omega^2 x and holds up m g
        (hoop,) = [v for k, v in motion.multipliers.items() if k.name == "lambda_2"]
        radial = 2 * hoop * motion.state[x]
        assert float((radial / m).subs({g: 9.81, R: 0.4})) == pytest.approx(-(spin**2) * side)


def test_the_report_lists_steady_motions_when_the_constraints_turn() -> None:
    report = analyze(cs.rotating_hoop())
    assert report.steady_motions is not None and report.equilibria is not None
    assert len(report.equilibria) == 0  # nothing is at rest in the turning frame's plane
    assert "moves with time" in report.equilibria.reason


def test_constraints_that_do_not_move_have_no_steady_motion_family() -> None:
    with pytest.raises(AnalysisError, match="no family of steady motions"):
        steady_motions(cs.pendulum())


def test_equilibrium_search_is_bounded_and_says_what_it_did_not_search():
    # degree-6 static equations in three unknowns: Groebner bases take hours, so the search
    # is numeric (seconds), and every root found is a root
    import lagrangian as lg
    from lagrangian.analysis.equilibria import equilibria
    from lagrangian.io.load import loads

    system = loads(
        "name: degree seven\ncoordinates: [x, y, z]\nparameters: {m: 1}\n"
        "kinetic: m*(x_dot**2 + y_dot**2 + z_dot**2)/2\n"
        "potential: x**7 + y**7 + z**7 - 3*x*y*z**4 + x**2*y**3 - y*z + x**3 - 2*x*y\n"
    )
    found = equilibria(system)
    assert found.method == "numeric"
    static = lg.derive(system).gravity
    for e in found:
        assert max(abs(float(g.subs(e.state))) for g in static) < 1e-9
    assert any(all(abs(float(v)) < 1e-12 for v in e.state.values()) for e in found)  # origin
