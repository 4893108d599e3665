"""Small oscillations K v = omega^2 M v against textbook results.

References:
- two equal masses m between three equal springs k (seed 000): omega^2 = k/m with v = (1, 1)
  and 3k/m with v = (1, -1);
- equal double pendulum (masses m, lengths l): omega^2 = (g/l)(2 -+ sqrt 2), shapes
  (1, +-sqrt 2);
- simple pendulum omega = sqrt(g/l);
- bead on a hoop spinning at omega about its off-axis equilibrium cos th0 = g/(omega^2 R):
  oscillation at omega^2 sin^2 th0 = omega^2 - g^2/(omega^2 R^2).
"""

from __future__ import annotations

import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import equilibria, normal_modes

m1, k1, g, l, l1 = sp.symbols("m1 k1 g l l1")
m, R, omega = sp.symbols("m R omega")
theta, theta_dot = sp.symbols("theta theta_dot")


def _same(a: sp.Expr, b: sp.Expr) -> bool:
    return sp.simplify(a - b) == 0


def test_two_equal_masses_three_equal_springs() -> None:
    modes = normal_modes(
        lg.examples.two_masses_three_springs(), parameters={"m2": "m1", "k2": "k1", "k3": "k1"}
    )
    assert modes.symbolic
    assert modes.squared_frequencies == (k1 / m1, 3 * k1 / m1)
    assert [list(v) for v in modes.shapes] == [[1, 1], [1, -1]]
    assert _same(modes.frequencies[1] ** 2, 3 * k1 / m1)


def test_equal_double_pendulum() -> None:
    modes = normal_modes(lg.examples.double_pendulum(), parameters={"m2": "m1", "l2": "l1"})
    assert modes.symbolic
    slow, fast = modes.squared_frequencies
    assert _same(slow, g / l1 * (2 - sp.sqrt(2)))
    assert _same(fast, g / l1 * (2 + sp.sqrt(2)))
    assert _same(modes.shapes[0][1], sp.sqrt(2)) and _same(modes.shapes[1][1], -sp.sqrt(2))


def test_equal_double_pendulum_numeric_defaults() -> None:
    modes = normal_modes(lg.examples.double_pendulum())
    expected = [9.81 * (2 - math.sqrt(2)), 9.81 * (2 + math.sqrt(2))]
    assert [float(w2) for w2 in modes.squared_frequencies] == pytest.approx(expected)
    assert [float(x) for x in modes.shapes[0]] == pytest.approx([1 / math.sqrt(2), 1])


def test_simple_pendulum() -> None:
    modes = normal_modes(lg.examples.simple_pendulum())
    assert _same(modes.frequencies[0] ** 2, g / l)


def test_hoop_oscillates_about_the_off_axis_equilibrium() -> None:
    hoop = lg.System(
        coordinates=[theta],
        parameters={m: 1.0, sp.Symbol("g"): 9.81, R: 1.0, omega: 5.0},
        kinetic=m * R**2 / 2 * (theta_dot**2 + omega**2 * sp.sin(theta) ** 2),
        potential=-m * g * R * sp.cos(theta),
    )
    modes = normal_modes(hoop)
    branch = sp.acos(g / (omega**2 * R))
    assert modes.about[theta] in (branch, -branch)
    assert _same(modes.squared_frequencies[0], omega**2 - g**2 / (omega**2 * R**2))


def test_an_equilibrium_found_before_can_be_passed() -> None:
    found = equilibria(lg.examples.simple_pendulum())
    modes = normal_modes(lg.examples.simple_pendulum(), found.stable()[0])
    assert modes.about == {theta: 0}


def test_three_links_numerically() -> None:
    modes = normal_modes(lg.examples.n_link_pendulum(3))
    assert not modes.symbolic and len(modes.frequencies) == 3
    # Every mode satisfies K v = omega^2 M v with the matrices at the equilibrium.
    values = {s: v for s, v in lg.examples.n_link_pendulum(3).parameters.items()}
    k = modes.stiffness_matrix.subs(values)
    mass = modes.mass_matrix.subs(values)
    for w2, v in zip(modes.squared_frequencies, modes.shapes):
        residual = (k - w2 * mass) * v
        assert max(abs(float(e)) for e in residual) < 1e-9


def test_not_an_equilibrium_is_refused_with_the_eigenvalues() -> None:
    with pytest.raises(lg.AnalysisError, match=r"not an equilibrium.*eigenvalues: .*I"):
        normal_modes(lg.examples.double_pendulum(), about={"theta": 0.3})


def test_unstable_point_is_refused_with_the_eigenvalues() -> None:
    with pytest.raises(lg.AnalysisError, match=r"not a stable equilibrium.*saddle.*eigenvalues"):
        normal_modes(lg.examples.double_pendulum(), about={"theta": sp.pi})


def test_moving_state_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match=r"state of rest.*linearize"):
        normal_modes(lg.examples.simple_pendulum(), about={"theta_dot": 1})


def test_no_stable_equilibrium() -> None:
    with pytest.raises(lg.AnalysisError, match="No stable equilibrium"):
        normal_modes(lg.examples.planet())


def test_coordinate_singularity_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match="not positive definite"):
        normal_modes(lg.examples.spherical_pendulum())
