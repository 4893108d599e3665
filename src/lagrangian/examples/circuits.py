"""Electrical and electromechanical circuits of the seed notes (001): the series RLC circuit,
the two-mesh circuit with a shared inductor, the RC + RL circuit whose first charge has no
inductance, and the capacitor microphone.

Charges are the generalized coordinates (inductor ~ mass, capacitor ~ spring, resistor ~
damper).  Sources are plain parameters, as in the notes (``u``, ``U_a``, ``u_a``, ``v``); give
a time-dependent source by replacing one with an expression of :data:`lagrangian.model.t`.
"""

from __future__ import annotations

import sympy as sp

from lagrangian.model import (
    Capacitor,
    Damper,
    Force,
    Inductor,
    Particle,
    Resistor,
    Spring,
    System,
    VoltageSource,
)

__all__ = ["capacitor_microphone", "rc_rl_circuit", "series_rlc", "two_mesh_circuit"]

#: Vacuum permittivity, F/m.
EPSILON_0 = 8.8541878128e-12


def series_rlc() -> System:
    """Series RLC circuit driven by a voltage u; the charge q is the coordinate.

    Seed 001 "Electrical Example: RLC Circuit": T = 1/2 L q_dot^2, V = q^2/(2 C),
    P = 1/2 R q_dot^2, Q = u, so

        L q_ddot + R q_dot + q/C = u    (KVL: L di/dt + v_C + R i = u).
    """
    q = sp.Symbol("q")
    q_dot = sp.Symbol("q_dot")
    L, C, R, u = sp.symbols("L C R u")
    return System(
        name="series_rlc",
        description="Series RLC circuit driven by a voltage u; the charge q is the coordinate.",
        coordinates=(q,),
        # 100 rad/s natural frequency, damping ratio 0.05, a 1 V step.
        parameters={L: 0.1, C: 1e-3, R: 1.0, u: 1.0},
        circuit=(
            Inductor(L, current=q_dot),
            Capacitor(C, charge=q),
            Resistor(R, current=q_dot),
            VoltageSource(u, coordinate=q),
        ),
        initial={q: 0.0, q_dot: 0.0},
    )


def two_mesh_circuit() -> System:
    """Two meshes sharing the inductor L12, mesh 1 driven by U_a; mesh charges q1, q2.

    Seed 001 "Two Mesh Electric Circuit":
    T = 1/2 L1 q1_dot^2 + 1/2 L12 (q1_dot - q2_dot)^2 + 1/2 L2 q2_dot^2,
    V = q1^2/(2 C1) + q2^2/(2 C2), P = 1/2 R1 q1_dot^2 + 1/2 R2 q2_dot^2, Q = (U_a, 0):

        (L1 + L12) q1_ddot - L12 q2_ddot + R1 q1_dot + q1/C1 = U_a
        -L12 q1_ddot + (L2 + L12) q2_ddot + R2 q2_dot + q2/C2 = 0
    """
    q1, q2 = sp.symbols("q1 q2")
    i1, i2 = sp.symbols("q1_dot q2_dot")
    L1, L2, L12, C1, C2, R1, R2, U_a = sp.symbols("L1 L2 L12 C1 C2 R1 R2 U_a")
    return System(
        name="two_mesh_circuit",
        description="Two meshes sharing the inductor L12, mesh 1 driven by U_a; "
        "mesh charges q1, q2.",
        coordinates=(q1, q2),
        parameters={L1: 0.1, L2: 0.1, L12: 0.05, C1: 1e-3, C2: 1e-3, R1: 1.0, R2: 1.0, U_a: 1.0},
        circuit=(
            Inductor(L1, current=i1),
            Inductor(L12, current=i1 - i2),  # the shared branch carries i1 - i2
            Inductor(L2, current=i2),
            Capacitor(C1, charge=q1),
            Capacitor(C2, charge=q2),
            Resistor(R1, current=i1),
            Resistor(R2, current=i2),
            VoltageSource(U_a, coordinate=q1),
        ),
        initial={q1: 0.0, q2: 0.0, i1: 0.0, i2: 0.0},
    )


def rc_rl_circuit() -> System:
    """Source u_a through R into capacitor C, in parallel with the branch L, R_L; charges q1, q2.

    Seed 001 "Another Example": T = 1/2 L q2_dot^2, V = (q1 - q2)^2/(2 C),
    P = 1/2 R q1_dot^2 + 1/2 R_L q2_dot^2, Q = (u_a, 0):

        R q1_dot + (q1 - q2)/C = u_a
        L q2_ddot + R_L q2_dot + (q2 - q1)/C = 0

    q1 has no inductance, so the mass matrix is singular: q1 obeys a first-order equation,
    q1_dot = (u_a - (q1 - q2)/C)/R, and q2 a second-order one,
    q2_ddot = (-R_L q2_dot + (q1 - q2)/C)/L.  With u_C = (q1 - q2)/C and i_L = q2_dot these
    are the notes' state equations du_C/dt = (-u_C/R - i_L + u_a/R)/C,
    di_L/dt = (u_C - R_L i_L)/L.
    """
    q1, q2 = sp.symbols("q1 q2")
    i_a, i_L = sp.symbols("q1_dot q2_dot")
    L, C, R, R_L, u_a = sp.symbols("L C R R_L u_a")
    return System(
        name="rc_rl_circuit",
        description="Source u_a through R into capacitor C, in parallel with the branch L, R_L; "
        "charges q1, q2.",
        coordinates=(q1, q2),
        parameters={L: 0.1, C: 1e-3, R: 10.0, R_L: 1.0, u_a: 1.0},
        circuit=(
            Inductor(L, current=i_L),
            Capacitor(C, charge=q1 - q2),
            Resistor(R, current=i_a),
            Resistor(R_L, current=i_L),
            VoltageSource(u_a, coordinate=q1),
        ),
        # q1_dot is not a state: the first-order equation fixes it; this is its value at
        # t = 0 with the defaults (u_a / R), given so every velocity has an initial value.
        initial={q1: 0.0, q2: 0.0, i_a: 0.1, i_L: 0.0},
    )


def capacitor_microphone() -> System:
    """Capacitor microphone: diaphragm displacement x on a spring and damper, plate charge q.

    Seed 001 "Capacitor Microphone".  The diaphragm (mass m, spring K, damper B, sound force
    f) narrows the plate gap to x0 - x, so the capacitance is eps A/(x0 - x) and
    V_electric = q^2 (x0 - x)/(2 eps A); the circuit has L, R and the bias voltage v:

        m x_ddot + B x_dot + K x - q^2/(2 eps A) = f
        L q_ddot + R q_dot + (x0 - x) q/(eps A) = v
    """
    x, q = sp.symbols("x q")
    x_dot, q_dot = sp.symbols("x_dot q_dot")
    m, K, B, f = sp.symbols("m K B f")
    L, R, v, eps, A, x0 = sp.symbols("L R v eps A x0")
    return System(
        name="capacitor_microphone",
        description="Capacitor microphone: diaphragm displacement x on a spring and damper, "
        "plate charge q.",
        coordinates=(x, q),
        # A 1 cm^2 diaphragm 20 um from the back plate (44 pF), resonance near 2.25 kHz,
        # 48 V phantom-power bias; pull-in needs a deflection of x0/3, the bias gives x0/13.
        parameters={
            m: 1e-5,
            K: 2000.0,
            B: 0.03,
            f: 0.0,
            L: 0.1,
            R: 1e5,
            v: 48.0,
            eps: EPSILON_0,
            A: 1e-4,
            x0: 2e-5,
        },
        particles=(Particle("diaphragm", m, (x,)),),
        springs=(Spring(("origin", "diaphragm"), K),),
        dampers=(Damper(("origin", "diaphragm"), B),),
        forces=(Force("diaphragm", (f,)),),
        circuit=(
            Inductor(L, current=q_dot),
            Resistor(R, current=q_dot),
            Capacitor(eps * A / (x0 - x), charge=q),
            VoltageSource(v, coordinate=q),
        ),
        # Uncharged and at rest: switching the bias on charges the plates and pulls the
        # diaphragm in.
        initial={x: 0.0, q: 0.0, x_dot: 0.0, q_dot: 0.0},
    )
