"""Linearization x_dot = A x + B u against textbook results.

References:
- cyclotron frequency: a charge in B = B0 z_hat (E0 = 0) circles at omega_c = q B0 / m;
- simple pendulum: about the bottom omega = sqrt(g/l); upright, growth rate sqrt(g/l);
- damped oscillator m x'' + B x' + K x = f: lambda = -B/(2m) +- i sqrt(K/m - B^2/(4m^2));
- conical pendulum (spherical pendulum, theta = th0, phi_dot = Omega with
  Omega^2 = g/(l cos th0)): small oscillations about it at Omega sqrt(1 + 3 cos^2 th0)
  (from the Routhian V_eff = p_phi^2/(2 m l^2 sin^2 th) - m g l cos th);
- robot arm (seed 001) at r = 1: the inputs (tau, f) enter as q_ddot = M^-1 Q, M = diag(m r^2, m).
"""

from __future__ import annotations

import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import linearize

m, g, l, q_e, b0 = sp.symbols("m g l q_e B0")


def test_cyclotron_frequency_symbolic() -> None:
    lin = linearize(lg.examples.charged_particle_em(), parameters={"E0": 0}, symbolic=True)
    assert lin.frequencies == (b0 * q_e / m,)
    assert lin.growth_rates == ()
    assert sorted(lin.eigenvalues, key=sp.default_sort_key).count(0) == 4
    assert lin.is_solution


def test_cyclotron_frequency_numeric() -> None:
    values = {"E0": 0, "B0": 2.0, "q_e": 3.0, "m": 1.5}
    lin = linearize(lg.examples.charged_particle_em(), parameters=values)
    assert [float(w) for w in lin.frequencies] == pytest.approx([2.0 * 3.0 / 1.5])


def test_pendulum_bottom_and_top() -> None:
    bottom = linearize(lg.examples.simple_pendulum(), {"theta": 0})
    assert sp.Matrix([[0, 1], [-g / l, 0]]) == bottom.A
    assert [float(w) for w in bottom.frequencies] == pytest.approx([math.sqrt(9.81)])
    top = linearize(lg.examples.simple_pendulum(), {"theta": sp.pi})
    assert top.frequencies == ()
    assert [float(s) for s in top.growth_rates] == pytest.approx([math.sqrt(9.81)])


def test_damped_oscillator_eigenvalues() -> None:
    lin = linearize(lg.examples.mass_spring_damper(), {"x": -9.81 / 20})
    assert lin.is_solution, lin.note
    decay, frequency = -0.5 / 2, math.sqrt(20 - 0.5**2 / 4)
    expected = sorted([complex(decay, -frequency), complex(decay, frequency)], key=lambda z: z.imag)
    assert [complex(v) for v in lin.eigenvalues] == pytest.approx(expected)
    assert lin.growth_rates == ()


def test_conical_pendulum_is_a_steady_motion() -> None:
    th0 = 0.6
    spin = math.sqrt(9.81 / math.cos(th0))
    lin = linearize(lg.examples.spherical_pendulum(), {"theta": th0, "phi_dot": spin})
    assert lin.is_solution, lin.note
    expected = spin * math.sqrt(1 + 3 * math.cos(th0) ** 2)
    assert [float(w) for w in lin.frequencies] == pytest.approx([expected], rel=1e-10)


def test_a_state_that_is_not_a_solution_is_still_linearized() -> None:
    lin = linearize(lg.examples.spherical_pendulum(), {"theta": 0.5, "phi_dot": 1})
    assert not lin.is_solution
    assert "not a solution" in lin.note and "theta_ddot" in lin.note
    assert lin.A.shape == (4, 4)


def test_inputs_give_b() -> None:
    lin = linearize(lg.examples.robot_arm(), {"r": 1}, inputs=["tau", "f"])
    assert sp.Matrix([[0, 0], [0, 0], [1 / m, 0], [0, 1 / m]]) == lin.B
    assert [u.name for u in lin.inputs] == ["tau", "f"]


def test_time_dependent_equations_are_linearized_at_the_given_time() -> None:
    lin = linearize(lg.examples.moving_pivot_pendulum(), {"theta": 0, "t": 0})
    assert "depend on time" in lin.note and not lin.is_solution


def test_bad_names_are_refused() -> None:
    with pytest.raises(lg.AnalysisError, match="no coordinate, velocity or time named 'psi'"):
        linearize(lg.examples.simple_pendulum(), {"psi": 0})
    with pytest.raises(lg.AnalysisError, match=r"Inputs must be parameters.*theta"):
        linearize(lg.examples.simple_pendulum(), inputs=["theta"])


def test_singular_mass_matrix_is_refused() -> None:
    with pytest.raises(lg.AnalysisError, match="mass matrix is singular"):
        linearize(lg.examples.rc_rl_circuit())
    with pytest.raises(lg.AnalysisError, match="singular at this state"):
        linearize(lg.examples.spherical_pendulum())
