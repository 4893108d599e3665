"""Constrained sample systems shared by the constraint tests, each built with the Python API,
and consistent states built independently from the system's natural parameters (angles, the
distance along a wire) rather than from anything the library computes."""

from __future__ import annotations

import math

import sympy as sp

import lagrangian as lg

x, y, z = sp.symbols("x y z")
x_dot, y_dot, z_dot = sp.symbols("x_dot y_dot z_dot")
phi, theta = sp.symbols("phi theta")
phi_dot, theta_dot = sp.symbols("phi_dot theta_dot")
m, g, l, r, omega, R = sp.symbols("m g l r omega R")
t = lg.t


def numeric(expr: sp.Expr, values: dict) -> float:
    """``expr`` at ``values`` (symbols or names -> numbers), as a float."""
    by_name = {str(k): v for k, v in values.items()}
    subs = {s: by_name[s.name] for s in expr.free_symbols if s.name in by_name}
    missing = [s for s in expr.free_symbols if s.name not in by_name]
    assert not missing, missing
    return float(sp.N(expr.xreplace({s: sp.Float(v, 30) for s, v in subs.items()}), 30))


def pendulum() -> lg.System:
    """A bob at Cartesian (x, y) on a rod of length l from the origin."""
    return lg.System(
        name="pendulum_cartesian",
        coordinates=[x, y],
        parameters={m: 1.3, g: 9.81, l: 0.7},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - l**2, name="rod")],
    )


def pendulum_state(angle: float, rate: float, l_value: float = 0.7) -> dict[str, float]:
    """x = l sin(theta), y = -l cos(theta) and their rates."""
    return {
        "x": l_value * math.sin(angle),
        "y": -l_value * math.cos(angle),
        "x_dot": l_value * math.cos(angle) * rate,
        "y_dot": l_value * math.sin(angle) * rate,
    }


def moving_pivot() -> lg.System:
    """Seed 000's rheonomic constraint (x - x0 cos(omega t))^2 + y^2 - l^2 = 0, with the
    parameter values of lagrangian.examples.moving_pivot_pendulum."""
    x0 = sp.Symbol("x0")
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0, x0: 0.1, omega: 2.0},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=[lg.Holonomic((x - x0 * sp.cos(omega * t)) ** 2 + y**2 - l**2)],
    )


def rotating_wire() -> lg.System:
    """A bead on a straight wire turning at omega in a horizontal plane (no gravity):
    x sin(omega t) - y cos(omega t) = 0."""
    return lg.System(
        coordinates=[x, y],
        parameters={m: 0.8, omega: 1.7},
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Holonomic(x * sp.sin(omega * t) - y * sp.cos(omega * t), name="wire")],
    )


def rotating_hoop() -> lg.System:
    """A bead on a hoop of radius R turning at omega about the vertical z axis."""
    return lg.System(
        coordinates=[x, y, z],
        parameters={m: 0.5, g: 9.81, R: 0.4, omega: 3.0},
        gravity=(0, 0, -g),
        particles=[lg.Particle("bead", m, (x, y, z))],
        constraints=[
            lg.Holonomic(x * sp.sin(omega * t) - y * sp.cos(omega * t), name="plane"),
            lg.Holonomic(x**2 + y**2 + z**2 - R**2, name="hoop"),
        ],
    )


def hoop_state(angle: float, rate: float, time: float) -> dict[str, float]:
    """x = R sin(theta) cos(omega t), y = R sin(theta) sin(omega t), z = -R cos(theta)."""
    radius, spin = 0.4, 3.0
    s, c, ws, wc = math.sin(angle), math.cos(angle), math.sin(spin * time), math.cos(spin * time)
    return {
        "t": time,
        "x": radius * s * wc,
        "y": radius * s * ws,
        "z": -radius * c,
        "x_dot": radius * (c * rate * wc - s * spin * ws),
        "y_dot": radius * (c * rate * ws + s * spin * wc),
        "z_dot": radius * s * rate,
    }


DUMBBELL_PARAMETERS = {"m1": 1.2, "m2": 0.7, "h": 0.9, "g": 9.81}


def dumbbell() -> lg.System:
    """Seed 003's dumbbell in Cartesian coordinates: |q1 - q2|^2 - h^2 = 0, forces f1, f2."""
    x1, y1, x2, y2 = sp.symbols("x1 y1 x2 y2")
    m1, m2, h = sp.symbols("m1 m2 h")
    f1x, f1y, f2x, f2y = sp.symbols("f1x f1y f2x f2y")
    return lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={
            **{sp.Symbol(k): v for k, v in DUMBBELL_PARAMETERS.items()},
            f1x: 0.3,
            f1y: -1.1,
            f2x: 2.0,
            f2y: 0.4,
        },
        gravity=(0, -g),
        particles=[lg.Particle("particle1", m1, (x1, y1)), lg.Particle("particle2", m2, (x2, y2))],
        forces=[lg.Force("particle1", (f1x, f1y)), lg.Force("particle2", (f2x, f2y))],
        constraints=[lg.Holonomic((x1 - x2) ** 2 + (y1 - y2) ** 2 - h**2, name="rod")],
    )


def knife_edge() -> lg.System:
    """A skate (knife edge) on a plane inclined at alpha, downhill along -x:
    x_dot sin(phi) - y_dot cos(phi) = 0."""
    inertia, alpha = sp.symbols("I alpha")
    return lg.System(
        coordinates=[x, y, phi],
        parameters={m: 2.0, inertia: 0.3, g: 9.81, alpha: 0.4},
        kinetic=m * (x_dot**2 + y_dot**2) / 2 + inertia * phi_dot**2 / 2,
        potential=m * g * sp.sin(alpha) * x,
        constraints=[lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi), "blade")],
    )


def rolling_disc() -> lg.System:
    """A vertical disc rolling on a plane: heading theta, spin phi, contact point (x, y);
    x_dot = r phi_dot cos(theta), y_dot = r phi_dot sin(theta); a torque tau on the spin."""
    heading, spin, tau = sp.symbols("J_heading J_spin tau")
    return lg.System(
        coordinates=[x, y, theta, phi],
        parameters={m: 1.5, r: 0.3, heading: 0.04, spin: 0.07, tau: 0.2},
        kinetic=m * (x_dot**2 + y_dot**2) / 2 + heading * theta_dot**2 / 2 + spin * phi_dot**2 / 2,
        generalized_forces={phi: tau},
        constraints=[
            lg.VelocityConstraint(x_dot - r * phi_dot * sp.cos(theta), "roll x"),
            lg.VelocityConstraint(y_dot - r * phi_dot * sp.sin(theta), "roll y"),
        ],
    )
