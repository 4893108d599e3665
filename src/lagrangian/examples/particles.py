"""Single particles and mass-spring systems of the seed notes (000, 001): a particle in the
plane (Cartesian and polar), a mass on a spring, the mass-spring-damper, projectile and planet
in polar coordinates, two masses and three springs, the quartic Lagrangian, Stokes drag and a
charge in uniform electric and magnetic fields."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Damper, Force, Particle, Spring, System, velocity

__all__ = [
    "charged_particle_em",
    "mass_on_spring",
    "mass_spring_damper",
    "particle_plane_cartesian",
    "particle_plane_polar",
    "planet",
    "projectile_polar",
    "quartic_lagrangian",
    "stokes_drag",
    "two_masses_three_springs",
]


def _at_rest(**positions: float) -> dict[sp.Symbol, float]:
    """Initial values: the given coordinates, every velocity 0."""
    values = {sp.Symbol(name): value for name, value in positions.items()}
    return {**values, **{velocity(q): 0.0 for q in values}}


def particle_plane_cartesian() -> System:
    """Particle in a plane, Cartesian coordinates, pushed by a force (Fx, Fy).

    Seed 000: T = 1/2 m (x_dot^2 + y_dot^2), Q_x = Fx, Q_y = Fy, so m x_ddot = Fx and
    m y_ddot = Fy.
    """
    x, y = sp.symbols("x y")
    m, f_x, f_y = sp.symbols("m Fx Fy")
    return System(
        name="particle_plane_cartesian",
        description="Particle in a plane, Cartesian coordinates, pushed by a force (Fx, Fy).",
        coordinates=[x, y],
        parameters={m: 1.0, f_x: 0.0, f_y: 0.0},
        particles=[Particle("particle", m, (x, y))],
        forces=[Force("particle", (f_x, f_y))],
        initial={**_at_rest(x=0.0, y=0.0), velocity(x): 1.0},
    )


def particle_plane_polar() -> System:
    """Particle in a plane, polar coordinates, pushed by forces F_r, F_theta.

    Seed 000: T = 1/2 m (r_dot^2 + r^2 theta_dot^2); the force F_r r_hat + F_theta theta_hat
    gives Q_r = F_r and Q_theta = r F_theta, so

        m (r_ddot - r theta_dot^2) = F_r,    m r (r theta_ddot + 2 r_dot theta_dot) = r F_theta.
    """
    r, theta = sp.symbols("r theta")
    m, f_r, f_theta = sp.symbols("m F_r F_theta")
    radial = (sp.cos(theta), sp.sin(theta))
    transverse = (-sp.sin(theta), sp.cos(theta))
    force = tuple(f_r * a + f_theta * b for a, b in zip(radial, transverse, strict=True))
    return System(
        name="particle_plane_polar",
        description="Particle in a plane, polar coordinates, pushed by forces F_r, F_theta.",
        coordinates=[r, theta],
        parameters={m: 1.0, f_r: 0.0, f_theta: 0.0},
        particles=[Particle("particle", m, (r * sp.cos(theta), r * sp.sin(theta)))],
        forces=[Force("particle", force)],
        initial={**_at_rest(r=1.0, theta=0.0), velocity(theta): 1.0},
    )


def mass_on_spring() -> System:
    """Mass on a spring of stiffness k, pulled by a force F.

    Seed 000 (and 001): L = 1/2 m x_dot^2 - 1/2 k x^2, so m x_ddot + k x = F; released
    (F = 0) it oscillates, m x_ddot = -k x.
    """
    x = sp.Symbol("x")
    m, k, f = sp.symbols("m k F")
    return System(
        name="mass_on_spring",
        description="Mass on a spring of stiffness k, pulled by a force F.",
        coordinates=[x],
        parameters={m: 1.0, k: 10.0, f: 0.0},
        kinetic=m * velocity(x) ** 2 / 2,
        potential=k * x**2 / 2,
        generalized_forces={x: f},
        initial=_at_rest(x=0.1),
    )


def mass_spring_damper() -> System:
    """Mass at height h + x on a spring K and a damper B, driven by a force f.

    Seed 001: V = 1/2 K x^2 + m g (h + x), P = 1/2 B x_dot^2, Q = f:

        m x_ddot + B x_dot + K x + m g = f.
    """
    x = sp.Symbol("x")
    m, big_k, big_b, g, h, f = sp.symbols("m K B g h f")
    anchor = (h,)  # the spring and damper hold the mass at height h + x
    return System(
        name="mass_spring_damper",
        description="Mass at height h + x on a spring K and a damper B, driven by a force f.",
        coordinates=[x],
        parameters={m: 1.0, big_k: 20.0, big_b: 0.5, g: 9.81, h: 1.0, f: 0.0},
        particles=[Particle("mass", m, (h + x,))],
        springs=[Spring((anchor, "mass"), big_k)],
        dampers=[Damper((anchor, "mass"), big_b)],
        forces=[Force("mass", (f,))],
        gravity=(-g,),
        initial=_at_rest(x=0.0),
    )


def _polar_particle(m: sp.Symbol) -> tuple[tuple[sp.Symbol, sp.Symbol], Particle]:
    r, theta = sp.symbols("r theta")
    return (r, theta), Particle("particle", m, (r * sp.cos(theta), r * sp.sin(theta)))


def projectile_polar() -> System:
    """Projectile in polar coordinates (r, theta) under uniform gravity.

    Seed 000: L = 1/2 m (r_dot^2 + r^2 theta_dot^2) - m g r sin(theta):

        m (r_ddot - r theta_dot^2) + m g sin(theta) = 0,
        m r^2 theta_ddot + 2 m r r_dot theta_dot + m g r cos(theta) = 0
    (the notes print the second as m (r theta_ddot - 2 r_dot theta_dot) + m g cos(theta) = 0,
    a sign slip in the Coriolis term after dividing by r).
    """
    m, g = sp.symbols("m g")
    (r, theta), particle = _polar_particle(m)
    return System(
        name="projectile_polar",
        description="Projectile in polar coordinates (r, theta) under uniform gravity.",
        coordinates=[r, theta],
        parameters={m: 1.0, g: 9.81},
        particles=[particle],
        gravity=(0, -g),
        initial={r: 0.1, theta: 0.8, velocity(r): 10.0, velocity(theta): 0.0},
    )


def planet() -> System:
    """Planet in the central potential V = -m mu / r, polar coordinates.

    Seed 000: L = 1/2 m (r_dot^2 + r^2 theta_dot^2) + m mu / r:

        m r_ddot - m r theta_dot^2 + m mu / r^2 = 0,    d/dt (m r^2 theta_dot) = 0.
    """
    m, mu = sp.symbols("m mu")
    (r, theta), particle = _polar_particle(m)
    return System(
        name="planet",
        description="Planet in the central potential V = -m mu / r, polar coordinates.",
        coordinates=[r, theta],
        parameters={m: 1.0, mu: 1.0},
        particles=[particle],
        potential=-m * mu / r,
        # an ellipse of eccentricity 0.2 (perihelion 1, speed sqrt(1.2) there)
        initial={r: 1.0, theta: 0.0, velocity(r): 0.0, velocity(theta): 1.2**0.5},
    )


def two_masses_three_springs() -> System:
    """Two masses between two walls, joined by three springs k1, k2, k3 (1-D).

    Seed 000, x1 and x2 displacements from equilibrium:
    V = 1/2 k1 x1^2 + 1/2 k2 (x1 - x2)^2 + 1/2 k3 x2^2, so

        m1 x1_ddot + (k1 + k2) x1 - k2 x2 = 0,    m2 x2_ddot + (k2 + k3) x2 - k2 x1 = 0.
    """
    x1, x2 = sp.symbols("x1 x2")
    m1, m2, k1, k2, k3, a = sp.symbols("m1 m2 k1 k2 k3 a")
    # walls at 0 and 3a, masses at rest at a and 2a; rest lengths a leave the notes' V
    walls = ((sp.Integer(0),), (3 * a,))
    return System(
        name="two_masses_three_springs",
        description="Two masses between two walls, joined by three springs k1, k2, k3 (1-D).",
        coordinates=[x1, x2],
        parameters={m1: 1.0, m2: 1.0, k1: 10.0, k2: 5.0, k3: 10.0, a: 1.0},
        particles=[Particle("mass1", m1, (a + x1,)), Particle("mass2", m2, (2 * a + x2,))],
        springs=[
            Spring((walls[0], "mass1"), k1, a),
            Spring(("mass1", "mass2"), k2, a),
            Spring(("mass2", walls[1]), k3, a),
        ],
        initial=_at_rest(x1=0.1, x2=0.0),
    )


def quartic_lagrangian() -> System:
    """Particle with L = m^2 x_dot^4 / 12 + m x_dot^2 V - V^2, V = k x^2 / 2.

    Seed 000: the equation is (m x_ddot + dV/dx)(m x_dot^2 + 2 V) = 0, i.e. d(E^2)/dt = 0
    with E = 1/2 m x_dot^2 + V: motion in the potential V.  The mass matrix
    m^2 x_dot^2 + 2 m V depends on the velocity.
    """
    x = sp.Symbol("x")
    m, k = sp.symbols("m k")
    x_dot = velocity(x)
    potential = k * x**2 / 2
    return System(
        name="quartic_lagrangian",
        description="Particle with L = m^2 x_dot^4 / 12 + m x_dot^2 V - V^2, V = k x^2 / 2.",
        coordinates=[x],
        parameters={m: 1.0, k: 1.0},
        lagrangian=m**2 * x_dot**4 / 12 + m * x_dot**2 * potential - potential**2,
        initial={x: 1.0, x_dot: 0.0},
    )


def stokes_drag() -> System:
    """Sphere of radius a falling through a fluid of viscosity eta (Stokes drag).

    Seed 000: Rayleigh function F = 1/2 (6 pi eta a) (x_dot^2 + y_dot^2), so

        m x_ddot + 6 pi eta a x_dot = 0,    m y_ddot + 6 pi eta a y_dot + m g = 0.
    """
    x, y = sp.symbols("x y")
    m, g, eta, a = sp.symbols("m g eta a")
    drag = 6 * sp.pi * eta * a
    return System(
        name="stokes_drag",
        description="Sphere of radius a falling through a fluid of viscosity eta (Stokes drag).",
        coordinates=[x, y],
        # a 1 mm steel ball in glycerol
        parameters={m: 3.3e-5, g: 9.81, eta: 1.4, a: 1.0e-3},
        particles=[Particle("sphere", m, (x, y))],
        gravity=(0, -g),
        dissipation=drag * (velocity(x) ** 2 + velocity(y) ** 2) / 2,
        initial={**_at_rest(x=0.0, y=0.0), velocity(x): 0.01},
    )


def charged_particle_em() -> System:
    """Charge q_e in uniform fields E = E0 x_hat, B = B0 z_hat (velocity potential).

    Seed 000: U = q phi - q A.v with phi = -E0 x and A = B0/2 (-y, x, 0), and
    L = T - U gives the Lorentz force m r_ddot = q (E + v x B):

        m x_ddot = q (E0 + B0 y_dot),    m y_ddot = -q B0 x_dot,    m z_ddot = 0.
    """
    x, y, z = sp.symbols("x y z")
    m, q_e, e0, b0 = sp.symbols("m q_e E0 B0")
    scalar = -e0 * x
    vector = (-b0 * y / 2, b0 * x / 2, sp.Integer(0))
    speed = (velocity(x), velocity(y), velocity(z))
    return System(
        name="charged_particle_em",
        description="Charge q_e in uniform fields E = E0 x_hat, B = B0 z_hat (velocity potential).",
        coordinates=[x, y, z],
        parameters={m: 1.0, q_e: 1.0, e0: 0.1, b0: 1.0},
        particles=[Particle("charge", m, (x, y, z))],
        velocity_potential=q_e * scalar
        - q_e * sum(a * v for a, v in zip(vector, speed, strict=True)),
        initial={**_at_rest(x=0.0, y=0.0, z=0.0), velocity(x): 1.0, velocity(z): 0.1},
    )
