"""Non-smooth right-hand sides: sign, Abs, Heaviside and Coulomb friction, against closed forms.

References: a block sliding with Coulomb friction decelerates at mu g and stops at v0/(mu g)
after v0^2/(2 mu g); a block at rest under a force c t slips when c t = mu m g; a V-shaped well
k|x| has the period 4 sqrt(2 m x0 / k); a force switched on at t1 gives F (t - t1)^2 / (2 m).
"""

import math

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg

G = 9.81


def block(text_forces: str = "", dissipation: str = "mu*m*g*Abs(x_dot)", **parameters):
    values = {"m": 1.0, "mu": 0.5, "g": G, **parameters}
    lines = "\n".join(f"  {k}: {v}" for k, v in values.items())
    return lg.loads(
        "name: block\ncoordinates: [x]\nparameters:\n"
        + lines
        + "\nkinetic: m*x_dot**2/2\n"
        + f"dissipation: {dissipation}\n"
        + text_forces
    )


def test_coulomb_friction_derives_sign():
    eom = lg.derive(block())
    assert sp.simplify(eom.equations[0] - sp.sympify("g*m*mu*sign(x_dot) + m*x_ddot")) == 0
    assert "Derivative" not in str(eom.equations)


def test_block_with_coulomb_friction_stops_at_the_known_time():
    v0, mu = 2.0, 0.5
    t_stop, distance = v0 / (mu * G), v0**2 / (2 * mu * G)
    times = np.linspace(0, 1.0, 101)
    trajectory = lg.simulate(block(), {"x": 0.0, "x_dot": v0}, 1.0, t_eval=times, rtol=1e-10)
    slides = [e for e in trajectory.events if "slide" in e.name]
    assert len(slides) == 1
    assert slides[0].t == pytest.approx(t_stop, rel=1e-9)
    x, v = trajectory["x"], trajectory["x_dot"]
    before = trajectory.t < t_stop
    t = trajectory.t[before]
    assert np.allclose(x[before], v0 * t - mu * G * t**2 / 2, atol=1e-9)
    after = trajectory.t > t_stop
    assert np.allclose(x[after], distance, atol=1e-9)
    assert np.all(np.abs(v[after]) < 1e-12)  # stuck, not chattering


def test_block_sticks_then_slips_under_a_growing_force():
    # m x'' = c t - mu m g sign(x_dot), at rest: held by static friction until c t = mu m g
    c, mu = 2.0, 0.5
    t_slip = mu * G / c
    system = block("generalized_forces: {x: c*t}\n", c=c)
    t_end = t_slip + 1.0
    times = np.linspace(0, t_end, 201)
    trajectory = lg.simulate(system, {"x": 0.0, "x_dot": 0.0}, t_end, t_eval=times, rtol=1e-11)
    names = [e.name for e in trajectory.events]
    assert any("slide" in n for n in names) and any("plus" in n for n in names), names
    leave = next(e for e in trajectory.events if "plus" in e.name)
    assert leave.t == pytest.approx(t_slip, rel=1e-7)
    x = trajectory["x"]
    stuck = trajectory.t < t_slip
    assert np.all(np.abs(x[stuck]) < 1e-12)
    late = trajectory.t > t_slip
    expected = c * (trajectory.t[late] - t_slip) ** 3 / 6  # x'' = c (t - t_slip)
    assert np.allclose(x[late], expected, rtol=1e-6, atol=1e-9)


def test_v_shaped_well_period_and_energy():
    k, m, x0 = 2.0, 0.5, 1.5
    system = lg.loads(
        "name: V well\ncoordinates: [x]\n"
        f"parameters: {{m: {m}, k: {k}}}\n"
        "kinetic: m*x_dot**2/2\npotential: k*Abs(x)\n"
    )
    assert "sign(x)" in str(lg.derive(system).equations[0])
    period = 4 * math.sqrt(2 * m * x0 / k)
    trajectory = lg.simulate(
        system, {"x": x0, "x_dot": 0.0}, 3 * period, t_eval=[0, period, 2 * period, 3 * period]
    )
    assert np.allclose(trajectory["x"], x0, atol=1e-7)
    assert trajectory.drift()["energy_relative"] < 1e-10
    crossings = [e.t for e in trajectory.events if "switch" in e.name]
    assert len(crossings) == 6
    assert crossings[0] == pytest.approx(period / 4, rel=1e-10)


def test_force_switched_on_at_a_time():
    f0, t1, m = 3.0, 0.4, 2.0
    system = lg.loads(
        "name: switched\ncoordinates: [x]\n"
        f"parameters: {{m: {m}, f0: {f0}, t1: {t1}}}\n"
        "kinetic: m*x_dot**2/2\ngeneralized_forces: {x: f0*Heaviside(t - t1)}\n"
    )
    times = np.linspace(0, 1, 11)
    trajectory = lg.simulate(system, {"x": 0.0, "x_dot": 0.0}, 1.0, t_eval=times, rtol=1e-10)
    expected = np.where(times > t1, f0 * (times - t1) ** 2 / (2 * m), 0.0)
    assert np.allclose(trajectory["x"], expected, atol=1e-10)
    assert [e.t for e in trajectory.events] == [pytest.approx(t1, rel=1e-12)]


def test_atan2_and_abs_through_the_python_api():
    x, x_dot, k, m = sp.symbols("x x_dot k m")
    system = lg.System(
        coordinates=[x],
        kinetic=m * x_dot**2 / 2,
        potential=k * sp.Abs(x) + k * sp.atan2(x, 1),
        parameters={k: 1.0, m: 1.0},
    )
    residual = lg.derive(system).equations[0]
    assert "Derivative" not in str(residual) and "re(" not in str(residual)
    expected = m * sp.Symbol("x_ddot") + k * sp.sign(x) + k / (x**2 + 1)
    value = {x: -0.7, k: 1.3, m: 0.8, sp.Symbol("x_ddot"): 0.2}
    assert float(residual.subs(value)) == pytest.approx(float(expected.subs(value)))


def test_analysis_of_non_smooth_systems_completes():
    well = lg.loads(
        "name: V well\ncoordinates: [x]\nparameters: {m: 1, k: 1}\n"
        "kinetic: m*x_dot**2/2\npotential: k*Abs(x)\n"
    )
    for system in (block(), well):
        report = lg.analyze(system)
        assert not [f for f in report.failures if "internal error" in f.reason], report.failures
    # the energy of the well is conserved; the friction's is not
    assert lg.analyze(well).energy.conserved and not lg.analyze(block()).energy.conserved
