"""Machines of the seed notes (001): the polar robot arm in manipulator form and the
directly-driven servo system whose stator-rotor mutual inductance is L_M cos(theta_r)."""

from __future__ import annotations

import sympy as sp

from lagrangian.model import Inductor, MutualInductance, Particle, Resistor, System, VoltageSource

__all__ = ["robot_arm", "servo_system"]


def robot_arm() -> System:
    """Polar robot arm: a mass m at radius r and angle theta, driven by a torque and a force.

    Seed 001 "Robotic Example": J = m r^2, T = 1/2 m r^2 theta_dot^2 + 1/2 m r_dot^2,
    V = m g r sin(theta), P = 1/2 B1 theta_dot^2 + 1/2 B2 r_dot^2, Q = (tau, f):

        [m r^2 0] [theta_ddot]   [2 m r r_dot theta_dot]   [m g r cos(theta)]   [tau - B1 theta_dot]
        [0     m] [r_ddot    ] + [-m r theta_dot^2     ] + [m g sin(theta)  ] = [f - B2 r_dot      ]

    M(q) q_ddot + C(q, q_dot) q_dot + G(q) = Q + dissipation_forces.  The notes fold B1, B2
    into the matrix next to the Coriolis terms; here ``coriolis`` holds only C q_dot and the
    damping is ``dissipation_forces`` = (-B1 theta_dot, -B2 r_dot).
    """
    theta, r = sp.symbols("theta r")
    theta_dot, r_dot = sp.symbols("theta_dot r_dot")
    m, g, B1, B2, tau, f = sp.symbols("m g B1 B2 tau f")
    return System(
        name="robot_arm",
        description="Polar robot arm: a mass m at radius r and angle theta, driven by a torque "
        "and a force.",
        coordinates=(theta, r),
        parameters={m: 1.0, g: 9.81, B1: 0.5, B2: 0.5, tau: 0.0, f: 0.0},
        # A point mass at (r cos(theta), r sin(theta)) has T = 1/2 m (r_dot^2 + r^2 theta_dot^2)
        # (so J = m r^2) and, under gravity (0, -g), V = m g r sin(theta).
        particles=(Particle("hand", m, (r * sp.cos(theta), r * sp.sin(theta))),),
        gravity=(0, -g),
        dissipation=B1 * theta_dot**2 / 2 + B2 * r_dot**2 / 2,
        generalized_forces={theta: tau, r: f},
        # Released at rest, horizontal, with the actuators off: the arm swings down while the
        # mass slides out along it.
        initial={theta: 0.0, r: 1.0, theta_dot: 0.0, r_dot: 0.0},
    )


def servo_system() -> System:
    """Directly-driven servo: stator and rotor windings coupled by L_M cos(theta_r), a shaft.

    Seed 001 "Directly-Driven Servo-System": q1, q2 are the stator and rotor charges
    (i_s = q1_dot, i_r = q2_dot) and q3 = theta_r the rotor angle;
    T = 1/2 Ls q1_dot^2 + LM cos(q3) q1_dot q2_dot + 1/2 Lr q2_dot^2 + 1/2 J q3_dot^2,
    V = 1/2 ks q3^2, P = 1/2 Rs q1_dot^2 + 1/2 Rr q2_dot^2 + 1/2 Bm q3_dot^2,
    Q = (us, ur, -T_L):

        Ls di_s/dt + LM cos(theta_r) di_r/dt - LM i_r sin(theta_r) omega + Rs i_s = us
        Lr di_r/dt + LM cos(theta_r) di_s/dt - LM i_s sin(theta_r) omega + Rr i_r = ur
        J domega/dt + LM i_s i_r sin(theta_r) + Bm omega + ks theta_r = -T_L

    The electromagnetic torque is T_e = -LM i_s i_r sin(theta_r).
    """
    # Solved for the derivatives (Cramer's rule on the 2x2 inductance block,
    # D = Ls Lr - LM^2 cos^2(theta_r)); derived here, because the notes' state-space formulas
    # have typos (the L_r L_M omega sin term lacks i_r; in di_r/dt the R_s term lacks
    # cos(theta_r) and has the wrong sign, and the L_s L_M term has a spurious 1/2 and sign):
    #   di_s/dt = (-Rs Lr i_s - 1/2 LM^2 i_s omega sin(2 theta_r) + Rr LM i_r cos(theta_r)
    #              + Lr LM i_r omega sin(theta_r) + Lr us - LM cos(theta_r) ur) / D
    #   di_r/dt = (Rs LM i_s cos(theta_r) + Ls LM i_s omega sin(theta_r) - Rr Ls i_r
    #              - 1/2 LM^2 i_r omega sin(2 theta_r) - LM cos(theta_r) us + Ls ur) / D
    #   domega/dt = (-LM i_s i_r sin(theta_r) - Bm omega - ks theta_r - T_L) / J
    q1, q2, q3 = sp.symbols("q1 q2 q3")
    i_s, i_r, omega = sp.symbols("q1_dot q2_dot q3_dot")
    Ls, Lr, LM, J, ks = sp.symbols("Ls Lr LM J ks")
    Rs, Rr, Bm, us, ur, T_L = sp.symbols("Rs Rr Bm us ur T_L")
    return System(
        name="servo_system",
        description="Directly-driven servo: stator and rotor windings coupled by "
        "L_M cos(theta_r), a shaft.",
        coordinates=(q1, q2, q3),
        # A small servo: LM^2 < Ls Lr keeps the inductance matrix positive definite.
        parameters={
            Ls: 0.01,
            Lr: 0.01,
            LM: 0.008,
            J: 1e-4,
            ks: 0.1,
            Rs: 1.0,
            Rr: 1.0,
            Bm: 1e-4,
            us: 10.0,
            ur: 10.0,
            T_L: 0.0,
        },
        kinetic=J * omega**2 / 2,
        potential=ks * q3**2 / 2,
        dissipation=Bm * omega**2 / 2,
        generalized_forces={q3: -T_L},
        circuit=(
            Inductor(Ls, current=i_s),
            Inductor(Lr, current=i_r),
            MutualInductance(LM * sp.cos(q3), currents=(i_s, i_r)),
            Resistor(Rs, current=i_s),
            Resistor(Rr, current=i_r),
            VoltageSource(us, coordinate=q1),
            VoltageSource(ur, coordinate=q2),
        ),
        # No current at t = 0, rotor turned 0.5 rad from the spring's rest angle.
        initial={q1: 0.0, q2: 0.0, q3: 0.5, i_s: 0.0, i_r: 0.0, omega: 0.0},
    )
