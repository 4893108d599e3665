"""Equilibria and their stability against hand results.

References:
- bead on a hoop spinning at omega (textbook): V_eff = -m g R cos(th) - m R^2 omega^2
  sin^2(th)/2 is stationary at th = 0, pi and cos(th) = g/(omega^2 R) (real when
  omega^2 >= g/R); th = 0 is stable iff omega^2 < g/R, the off-axis branch is stable when it
  exists, th = pi never is;
- double pendulum: (0, 0) is stable, (pi, pi) a maximum, the two mixed ones saddles;
- inverted pendulum on a torsion spring k (buckling): V = k th^2/2 + m g l cos(th); for
  k < m g l the upright th = 0 is unstable and th* = +-root of k th = m g l sin(th) are stable;
- planet: no equilibrium at finite r; moving pivot: no state of rest.
"""

from __future__ import annotations

import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import equilibria

m, g, R, omega, k, l = sp.symbols("m g R omega k l")
theta, phi = sp.symbols("theta phi")
theta_dot = sp.Symbol("theta_dot")


def hoop(spin: float) -> lg.System:
    kinetic = m * R**2 / 2 * (theta_dot**2 + omega**2 * sp.sin(theta) ** 2)
    return lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, R: 1.0, omega: spin},
        kinetic=kinetic,
        potential=-m * g * R * sp.cos(theta),
    )


def _by_angle(found) -> dict[sp.Expr, object]:
    return {e.state[theta]: e for e in found}


def test_hoop_has_every_branch_with_its_condition() -> None:
    found = equilibria(hoop(5.0))
    assert found.method == "symbolic"
    branch = sp.acos(g / (omega**2 * R))
    angles = _by_angle(found)
    assert set(angles) == {0, sp.pi, branch, -branch}
    off_axis = angles[branch]
    # the branch is real when omega^2 R >= g: true at omega = 5, false at omega = 2
    condition = off_axis.condition
    assert condition.subs({g: 9.81, R: 1.0, omega: 5.0}) == sp.true
    assert condition.subs({g: 9.81, R: 1.0, omega: 2.0}) == sp.false
    assert off_axis.exists and off_axis.stable
    assert angles[0].stable is False and angles[sp.pi].stable is False
    # th = 0 is stable exactly when omega^2 < g/R
    criterion = angles[0].stability_condition
    assert criterion.subs({m: 1, g: 9.81, R: 1.0, omega: 2.0}) == sp.true
    assert criterion.subs({m: 1, g: 9.81, R: 1.0, omega: 5.0}) == sp.false


def test_slow_hoop_has_no_off_axis_equilibrium() -> None:
    angles = _by_angle(equilibria(hoop(2.0)))
    branch = sp.acos(g / (omega**2 * R))
    assert angles[branch].exists is False and angles[branch].stable is None
    assert angles[0].stable is True
    assert angles[sp.pi].stable is False


def test_parameters_substitute_before_solving() -> None:
    # g / (omega^2 R) = 8/16: cos(th) = 1/2
    found = equilibria(hoop(5.0), parameters={"omega": 4, "g": 8, "R": 1})
    assert {e.state[theta] for e in found} == {0, sp.pi, sp.pi / 3, -sp.pi / 3}
    assert all(e.stable for e in found if e.state[theta] in (sp.pi / 3, -sp.pi / 3))


def test_double_pendulum_stability_pattern() -> None:
    found = equilibria(lg.examples.double_pendulum())
    stable = {(e.state[theta], e.state[phi]): e.stable for e in found}
    assert stable == {
        (0, 0): True,
        (sp.pi, 0): False,
        (0, sp.pi): False,
        (sp.pi, sp.pi): False,
    }
    reasons = {(e.state[theta], e.state[phi]): e.reason for e in found}
    assert "maximum" in reasons[(sp.pi, sp.pi)]
    assert "saddle" in reasons[(sp.pi, 0)]
    assert "Lagrange–Dirichlet" in reasons[(0, 0)]


def test_buckling_is_found_numerically() -> None:
    system = lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, l: 1.0, k: 5.0},
        kinetic=m * l**2 * theta_dot**2 / 2,
        potential=k * theta**2 / 2 + m * g * l * sp.cos(theta),
    )
    found = equilibria(system)
    assert found.method == "numeric"
    values = sorted(float(e.state[theta]) for e in found)
    assert len(values) == 3 and abs(values[1]) < 1e-12
    root = values[2]
    assert abs(5.0 * root - 9.81 * math.sin(root)) < 1e-10
    assert values[0] == pytest.approx(-root)
    stable = {round(float(e.state[theta]), 6): e.stable for e in found}
    assert stable == {round(-root, 6): True, 0.0: False, round(root, 6): True}


def test_spherical_pendulum_family_is_neutral_along_phi() -> None:
    found = equilibria(lg.examples.spherical_pendulum())
    bottom = next(e for e in found if e.state[theta] == 0)
    assert bottom.free == (phi,) and bottom.state[phi] == phi
    assert bottom.stable is True and "neutral along phi" in bottom.reason


def test_degenerate_hessian_is_undetermined_at_second_order() -> None:
    (rest,) = equilibria(lg.examples.quartic_lagrangian())
    assert rest.state == {sp.Symbol("x"): 0}
    assert rest.stable is None
    assert "undetermined at second order" in rest.reason


def test_systems_without_a_state_of_rest() -> None:
    assert len(equilibria(lg.examples.planet())) == 0
    moving = equilibria(lg.examples.moving_pivot_pendulum())
    assert len(moving) == 0 and "depend on time" in moving.reason
    falling = equilibria(lg.examples.atwood_machine())
    assert len(falling) == 0 and "do not depend on the coordinates" in falling.reason


def test_mass_spring_damper_rests_where_the_spring_holds_the_weight() -> None:
    # Seed 001: K x + m g = f at rest.
    (rest,) = equilibria(lg.examples.mass_spring_damper())
    big_k, f = sp.symbols("K f")
    assert sp.simplify(rest.state[sp.Symbol("x")] - (f - m * g) / big_k) == 0
    assert rest.stable is True


def test_every_configuration_rests_without_static_forces() -> None:
    (everywhere,) = equilibria(lg.examples.charged_particle_em(), parameters={"E0": 0})
    assert len(everywhere.free) == 3 and everywhere.stable is None


def test_effective_potential_of_the_hoop() -> None:
    found = equilibria(hoop(5.0))
    expected = -m * g * R * sp.cos(theta) - m * R**2 * omega**2 * sp.sin(theta) ** 2 / 2
    assert sp.simplify(found.effective_potential - expected) == 0


def test_unknown_parameter_names_are_refused() -> None:
    with pytest.raises(lg.AnalysisError, match="no parameter named 'omega2'"):
        equilibria(hoop(5.0), parameters={"omega2": 1})


def test_a_particle_in_the_plane_without_force_rests_everywhere_at_the_values_given() -> None:
    # polar coordinates, F_r and F_theta given as 0: the static forces F_r and F_theta r vanish
    # for every (r, theta), so every configuration is at rest; for F_r != 0 none is.
    found = equilibria(lg.examples.particle_plane_polar())
    (everywhere,) = found
    r, f_r, f_theta = sp.symbols("r F_r F_theta")
    assert everywhere.free == (r, theta) and everywhere.stable is None
    assert everywhere.condition == sp.And(sp.Eq(f_r, 0), sp.Eq(f_theta, 0))
    assert "for F_r ≠ 0: the static forces [F_r] do not depend on the coordinates" in found.general
    assert "for F_theta ≠ 0: the static forces [F_theta*r] do not vanish" in found.general
    pushed = equilibria(lg.examples.particle_plane_polar(), {"F_r": 1})
    assert len(pushed) == 0 and pushed.general == ""
