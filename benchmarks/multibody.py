"""Benchmark: deriving a 3-D chain of n rigid rods joined by spherical joints.

The chain
    Rod i (mass m_i, length l_i, inertia diag(I_i, I_i, J_i) about its centre in its own axes)
    hangs from the end of rod i - 1 (rod 1 from a fixed point at the origin) by a spherical
    joint; gravity g along -z.  Each rod is oriented by its own Euler angles relative to the
    world, body-fixed Z-X-Y: R_i = Rz(a_i) Rx(b_i) Ry(c_i), its axis along -R_i e_z, so

        J_0 = 0,   G_i = J_(i-1) - l_i/2 R_i e_z,   J_i = J_(i-1) - l_i R_i e_z.

What is measured
    The wall time from nothing to the matrix form, in a fresh process per run:

    euler      lagrangian: the 3n Euler angles as coordinates, the rods as RigidBody with
               ``rotations`` (their angular velocities composed), then ``lg.derive`` and its
               ``mass_matrix`` and ``forcing``;
    cartesian  lagrangian: 6n coordinates (each centre's x, y, z and the Euler angles) and the
               3n joints as holonomic constraints written in world axes, G_i + l_i/2 R_i e_z =
               J_(i-1); ``lg.derive`` and ``lg.constrained_equations`` (M, forcing, the
               constraint Jacobian A and gamma of A q_ddot = gamma);
    kane       sympy.physics.mechanics KanesMethod on the same chain (frames by
               ``orient_body_fixed(N, (a, b, c), "ZXY")``, centres and joints by
               ``locatenew``/``v2pt_theory``, q' = u, gravity loads), then ``mass_matrix`` and
               ``forcing``.
    relative   lagrangian with joint angles: rod i turned relative to rod i - 1 by its own
               a_i, b_i, c_i (R_i = R_(i-1) Rz Rx Ry: each RigidBody has ``parent`` and
               ``rotations``, its centre written in world axes with the rotation products
               nested), then ``lg.derive``;
    kane_relative  KanesMethod on that chain (each frame oriented from the rod before).
    hand       lagrangian on the Euler-angle chain written the way a sympy user writes it:
               each rod's ``orientation`` the product Rz(a_i) Rx(b_i) Ry(c_i) of elementary
               rotation matrices (a matrix, not a sequence), the centres composed by hand
               from the joints, then ``lg.derive``; against the same Kane run as ``euler``.

    The ratios are KanesMethod's time over lagrangian's, both variants against the same Kane
    run (Kane's minimal coordinates: the Cartesian form has 3n more coordinates and 3n
    constraints to build), and the joint-angle chain against Kane's joint-angle chain.

    Untimed, for n <= CHECK_MAX_N, the worker checks each result against KanesMethod at a
    random state: for ``euler`` and ``relative`` M^-1 f against Kane's (the joint-angle Kane
    for ``relative``); for ``cartesian`` the angular accelerations of the augmented system
    [[M, -A^T], [A, 0]] [q_ddot; lambda] = [f; gamma] at the configuration and velocities the
    joints allow.

Usage
    python benchmarks/multibody.py                  # n = 3..8, 1 run each, 600 s cap
    python benchmarks/multibody.py --n 3 4 --repeat 3
    python benchmarks/multibody.py --n 3 4 --methods relative kane_relative
    python benchmarks/multibody.py --record         # also write the section in RESULTS.md

    A run of some ``--methods`` reports (and compares) only those; recorded, it replaces
    only their cells, and the section keeps the other methods' cells and notes as they were
    recorded before (the report says which were measured now).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import compiled_forms, cpu_model, package_version

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
RESULTS = HERE.parent / "RESULTS.md"
BEGIN, END = "<!-- multibody.py: begin -->", "<!-- multibody.py: end -->"

METHODS = ("euler", "cartesian", "kane", "relative", "kane_relative", "hand")
LABELS = {
    "euler": "lagrangian, Euler angles",
    "hand": "lagrangian, written by hand (orientations as matrix products)",
    "cartesian": "lagrangian, Cartesian + joint constraints",
    "kane": "KanesMethod",
    "relative": "lagrangian, joint angles (rods relative to each other)",
    "kane_relative": "KanesMethod, joint angles",
}
DEFAULT_N = (3, 4, 5, 6, 7, 8)
CHECK_MAX_N = 4
STARTUP_SECONDS = 120.0


# --------------------------------------------------------------------------- the chain


def chain_symbols(n: int):
    """Per rod (a, b, c, m, l, I, J), and g."""
    import sympy as sp

    rods = [sp.symbols(f"a{i} b{i} c{i} m{i} l{i} I{i} J{i}") for i in range(1, n + 1)]
    return rods, sp.Symbol("g")


def chain_geometry(n: int):
    """R_i, G_i and J_i (SymPy, in the plain angle symbols) of the chain."""
    import sympy as sp

    from lagrangian.model import rotation_sequence

    rods, _ = chain_symbols(n)
    joint = sp.zeros(3, 1)
    rotations, centres, joints = [], [], []
    for a, b, c, _, l, _, _ in rods:
        R = rotation_sequence([("z", a), ("x", b), ("y", c)]).matrix
        axis = R * sp.Matrix([0, 0, 1])
        centres.append((joint - l / 2 * axis).applyfunc(sp.expand))
        joint = (joint - l * axis).applyfunc(sp.expand)
        rotations.append(R)
        joints.append(joint)
    return rotations, centres, joints


def euler_chain(n: int):
    """The chain in lagrangian, its 3n Euler angles as coordinates."""
    _, centres, _ = chain_geometry(n)
    return rod_chain(n, centres, relative=False)


def rod_chain(n: int, centres, relative: bool):
    """The n rods as RigidBodies at ``centres``, each turned by its own angles a_i, b_i, c_i
    (Rz Rx Ry), relative to the rod before when ``relative``, else to the world."""
    import sympy as sp

    import lagrangian as lg

    rods, g = chain_symbols(n)
    bodies = [
        lg.RigidBody(
            f"rod{i + 1}",
            m,
            sp.diag(I, I, J),
            tuple(centre),
            parent=f"rod{i}" if relative and i else None,
            rotations=[("z", a), ("x", b), ("y", c)],
        )
        for i, ((a, b, c, m, _, I, J), centre) in enumerate(zip(rods, centres))
    ]
    return lg.System(
        coordinates=[s for rod in rods for s in rod[:3]],
        parameters=[g, *(s for rod in rods for s in rod[3:])],
        gravity=(0, 0, -g),
        rigid_bodies=bodies,
    )


def cartesian_chain(n: int):
    """The chain in lagrangian with each centre's x, y, z and Euler angles as coordinates and
    the joints as holonomic constraints in world axes."""
    import sympy as sp

    import lagrangian as lg

    rods, g = chain_symbols(n)
    rotations, _, _ = chain_geometry(n)
    coordinates, bodies, constraints = [], [], []
    previous_end = sp.zeros(3, 1)
    for i, ((a, b, c, m, l, I, J), R) in enumerate(zip(rods, rotations)):
        centre = sp.Matrix(sp.symbols(f"x{i + 1} y{i + 1} z{i + 1}"))
        coordinates += [*centre, a, b, c]
        axis = R * sp.Matrix([0, 0, 1])
        bodies.append(
            lg.RigidBody(
                f"rod{i + 1}",
                m,
                sp.diag(I, I, J),
                tuple(centre),
                rotations=[("z", a), ("x", b), ("y", c)],
            )
        )
        start = centre + l / 2 * axis
        constraints += [lg.Holonomic(sp.expand(e)) for e in start - previous_end]
        previous_end = centre - l / 2 * axis
    return lg.System(
        coordinates=coordinates,
        parameters=[g, *(s for rod in rods for s in rod[3:])],
        gravity=(0, 0, -g),
        rigid_bodies=bodies,
        constraints=constraints,
    )


def relative_chain(n: int):
    """The chain in lagrangian with joint angles: rod i turned relative to rod i - 1 (rod 1
    to the world) by its own a_i, b_i, c_i, R_i = R_(i-1) Rz(a_i) Rx(b_i) Ry(c_i), each rod a
    RigidBody with ``parent`` and ``rotations`` (positions written in world axes)."""
    _, centres, _ = relative_geometry(n)
    return rod_chain(n, centres, relative=True)


def relative_geometry(n: int):
    """R_i, G_i and J_i of the chain with joint angles (R_i = R_(i-1) Rz Rx Ry), the
    products of the rotations kept nested as a user writes them."""
    import sympy as sp

    from lagrangian.model import rotation_sequence

    rods, _ = chain_symbols(n)
    joint = sp.zeros(3, 1)
    R = sp.eye(3)
    rotations, centres, joints = [], [], []
    for a, b, c, _, l, _, _ in rods:
        R = R * rotation_sequence([("z", a), ("x", b), ("y", c)]).matrix
        axis = R * sp.Matrix([0, 0, 1])
        centres.append(joint - l / 2 * axis)
        joint = joint - l * axis
        rotations.append(R)
        joints.append(joint)
    return rotations, centres, joints


def elementary_rotations():
    """Rx, Ry, Rz: the elementary rotation matrices (body -> world) as functions of an angle."""
    import sympy as sp

    def rx(a):
        return sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])

    def ry(a):
        return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])

    def rz(a):
        return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])

    return rx, ry, rz


def hand_chain(n: int):
    """The Euler-angle chain written by hand: each rod's orientation a product of
    elementary rotation matrices, its centre the joint above it minus l_i/2 times the rod's
    axis (nothing expanded)."""
    import sympy as sp

    import lagrangian as lg

    rx, ry, rz = elementary_rotations()
    rods, g = chain_symbols(n)
    joint = sp.zeros(3, 1)
    bodies = []
    for i, (a, b, c, m, l, I, J) in enumerate(rods):
        R = rz(a) * rx(b) * ry(c)
        axis = R * sp.Matrix([0, 0, 1])
        centre = joint - l / 2 * axis
        bodies.append(lg.RigidBody(f"rod{i + 1}", m, sp.diag(I, I, J), centre, orientation=R))
        joint = joint - l * axis
    return lg.System(
        coordinates=[s for rod in rods for s in rod[:3]],
        parameters=[g, *(s for rod in rods for s in rod[3:])],
        gravity=(0, 0, -g),
        rigid_bodies=bodies,
    )


#: How the hand-written rolling disc gives its orientation (:func:`hand_rolling_disc`).
DISC_ORIENTATIONS = ("product", "expanded", "quaternion")


def hand_rolling_disc(orientation: str = "product"):
    """A thin disc rolling without slip on z = 0, written by hand: the contact point (x, y,
    0), heading psi, lean theta and spin phi; the orientation Rz(psi) Rx(theta) Ry(phi)
    given as the product of rotation matrices (``"product"``), as that matrix with every
    entry multiplied out (``"expanded"``) or as the product of the three half-angle
    quaternions (``"quaternion"``); the centre r up the disc plane from the contact, and
    the two no-slip conditions (the contact's material velocity v_centre + omega x (contact
    - centre), world x and y) written out as ``VelocityConstraint`` expressions with omega
    the sum of the rates about their axes."""
    import sympy as sp

    import lagrangian as lg
    from lagrangian.model import quaternion_rotation

    rx, ry, rz = elementary_rotations()
    q = sp.symbols("x y psi theta phi")
    x, y, psi, theta, phi = q
    m, g, r = sp.symbols("m g r")
    e_x, e_y, e_z = sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0]), sp.Matrix([0, 0, 1])
    lean = rz(psi) * rx(theta)
    contact = sp.Matrix([x, y, 0])
    centre = contact + r * lean * e_z
    if orientation == "quaternion":
        turned = quaternion_rotation(*_quaternion_product(psi, theta, phi))
    elif orientation == "expanded":
        turned = (lean * ry(phi)).applyfunc(sp.expand)
    else:
        turned = lean * ry(phi)
    inertia = sp.diag(m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    disc = lg.RigidBody("disc", m, inertia, centre, orientation=turned)
    rate = {s: sp.Symbol(f"{s.name}_dot") for s in q}
    omega = rate[psi] * e_z + rate[theta] * rz(psi) * e_x + rate[phi] * lean * e_y
    centre_velocity = centre.applyfunc(lambda e: sum(e.diff(s) * rate[s] for s in q))
    slip = centre_velocity + omega.cross(contact - centre)
    return lg.System(
        coordinates=list(q),
        parameters={m: 1.0, g: 9.81, r: 0.3},
        gravity=(0, 0, -g),
        rigid_bodies=[disc],
        constraints=[lg.VelocityConstraint(slip[0]), lg.VelocityConstraint(slip[1])],
    )


def _quaternion_product(psi, theta, phi):
    """(w, x, y, z) of qz(psi) qx(theta) qy(phi), each q_k(a) = (cos(a/2), sin(a/2) e_k)
    (Hamilton products written out)."""
    import sympy as sp

    def times(p, q):
        (a, b, c, d), (e, f, g, h) = p, q
        return (
            a * e - b * f - c * g - d * h,
            a * f + b * e + c * h - d * g,
            a * g - b * h + c * e + d * f,
            a * h + b * g - c * f + d * e,
        )

    half = [(sp.cos(a / 2), sp.sin(a / 2)) for a in (psi, theta, phi)]
    qz = (half[0][0], 0, 0, half[0][1])
    qx = (half[1][0], half[1][1], 0, 0)
    qy = (half[2][0], 0, half[2][1], 0)
    return times(times(qz, qx), qy)


def kane_rolling_disc():
    """KanesMethod on the rolling disc (its contact point's velocity as the nonholonomic
    constraints, x' and y' dependent): the method and its q and u."""
    import sympy as sp
    import sympy.physics.mechanics as me

    m, g, r = sp.symbols("m g r")
    q = me.dynamicsymbols("x y psi theta phi")
    u = me.dynamicsymbols("x_dot y_dot psi_dot theta_dot phi_dot")
    N, Y, L, D = (me.ReferenceFrame(name) for name in "NYLD")
    Y.orient_axis(N, N.z, q[2])
    L.orient_axis(Y, Y.x, q[3])
    D.orient_axis(L, L.y, q[4])
    Y.set_ang_vel(N, u[2] * N.z)
    L.set_ang_vel(Y, u[3] * Y.x)
    D.set_ang_vel(L, u[4] * L.y)
    contact = me.Point("C")
    contact.set_vel(N, u[0] * N.x + u[1] * N.y)
    centre = contact.locatenew("G", r * L.z)
    centre.v2pt_theory(contact, N, L)  # the contact and the centre both fixed in L
    slip = centre.vel(N) + D.ang_vel_in(N).cross(contact.pos_from(centre))
    t = me.dynamicsymbols._t
    method = me.KanesMethod(
        N,
        q,
        u[2:],
        kd_eqs=[qi.diff(t) - ui for qi, ui in zip(q, u)],
        u_dependent=u[:2],
        velocity_constraints=[slip.dot(N.x), slip.dot(N.y)],
    )
    inertia = me.inertia(D, m * r**2 / 4, m * r**2 / 2, m * r**2 / 4)
    method.kanes_equations(
        [me.RigidBody("disc", centre, D, m, (inertia, centre))], [(centre, -m * g * N.z)]
    )
    return {"method": method, "q": q, "u": u, "slip": [slip.dot(N.x), slip.dot(N.y)]}


def derive_hand(n: int):
    import lagrangian as lg

    eom = lg.derive(hand_chain(n))
    return {"mass_matrix": eom.mass_matrix, "forcing": eom.forcing}


def derive_euler(n: int):
    import lagrangian as lg

    eom = lg.derive(euler_chain(n))
    return {"mass_matrix": eom.mass_matrix, "forcing": eom.forcing}


def derive_cartesian(n: int):
    import lagrangian as lg

    equations = lg.constrained_equations(cartesian_chain(n))
    return {
        "mass_matrix": equations.mass_matrix,
        "forcing": equations.forcing,
        "constraint_jacobian": equations.constraint_jacobian,
        "gamma": equations.gamma,
    }


def derive_relative(n: int):
    import lagrangian as lg

    eom = lg.derive(relative_chain(n))
    return {"mass_matrix": eom.mass_matrix, "forcing": eom.forcing}


def kane_chain(n: int, relative: bool = False):
    """KanesMethod on the chain: (M, forcing) of M u' = forcing, q' = u, with the dynamic
    symbols replaced by the plain names a1, a1_dot, ... of the lagrangian systems; with
    ``relative`` each rod's frame is oriented relative to the rod before (joint angles)."""
    import sympy.physics.mechanics as me

    rods, g = chain_symbols(n)
    N = me.ReferenceFrame("N")
    joint = me.Point("O")
    joint.set_vel(N, 0)
    q, u, bodies, loads = [], [], [], []
    for i, (a, b, c, m, l, I, J) in enumerate(rods):
        angles = me.dynamicsymbols(f"{a} {b} {c}")
        speeds = me.dynamicsymbols(f"{a}_dot {b}_dot {c}_dot")
        q += angles
        u += speeds
        B = me.ReferenceFrame(f"B{i + 1}")
        B.orient_body_fixed(bodies[-1].frame if relative and bodies else N, angles, "ZXY")
        centre = joint.locatenew(f"G{i + 1}", -l / 2 * B.z)
        centre.v2pt_theory(joint, N, B)
        end = joint.locatenew(f"J{i + 1}", -l * B.z)
        end.v2pt_theory(joint, N, B)
        bodies.append(me.RigidBody(f"rod{i + 1}", centre, B, m, (me.inertia(B, I, I, J), centre)))
        loads.append((centre, -m * g * N.z))
        joint = end
    kinematics = [qi.diff(me.dynamicsymbols._t) - ui for qi, ui in zip(q, u)]
    method = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kinematics)
    method.kanes_equations(bodies, loads)
    return {"mass_matrix": method.mass_matrix, "forcing": method.forcing, "q": q, "u": u}


def kane_relative(n: int):
    return kane_chain(n, relative=True)


DERIVERS = {
    "euler": derive_euler,
    "cartesian": derive_cartesian,
    "kane": kane_chain,
    "relative": derive_relative,
    "kane_relative": kane_relative,
    "hand": derive_hand,
}


# --------------------------------------------------------------------------- the check


def plain(expr, q, u):
    """Kane's dynamic symbols as plain symbols (a1, a1_dot)."""
    import sympy as sp

    swap = {qi: sp.Symbol(str(qi.func)) for qi in q}
    swap.update({ui: sp.Symbol(str(ui.func)) for ui in u})
    return expr.xreplace(swap)


def random_values(n: int) -> dict:
    """Parameters, angles and angular rates at random, keyed by name."""
    import numpy as np

    rng = np.random.default_rng(2000 + n)
    values = {"g": 9.81}
    for i in range(1, n + 1):
        for name in ("m", "l", "I", "J"):
            values[f"{name}{i}"] = float(rng.uniform(0.5, 2.0))
        for name in ("a", "b", "c"):
            values[f"{name}{i}"] = float(rng.uniform(-1.2, 1.2))
            values[f"{name}{i}_dot"] = float(rng.uniform(-1.5, 1.5))
    return values


def numbers(matrix, values: dict):
    import numpy as np
    import sympy as sp

    rule = {s: values[s.name] for s in sp.Matrix(matrix).free_symbols}
    return np.array(sp.Matrix(matrix).xreplace(rule).evalf(), dtype=float)


def kane_accelerations(n: int, values: dict, relative: bool = False):
    import numpy as np

    result = kane_chain(n, relative)
    q, u = result["q"], result["u"]
    M = numbers(plain(result["mass_matrix"], q, u), values)
    f = numbers(plain(result["forcing"], q, u), values).ravel()
    return np.linalg.solve(M, f)


def cartesian_values(n: int, values: dict) -> dict:
    """``values`` with the centres x_i, y_i, z_i and their rates the joints imply."""
    import sympy as sp

    _, centres, _ = chain_geometry(n)
    angles = [sp.Symbol(f"{name}{i}") for i in range(1, n + 1) for name in "abc"]
    rule = {s: values[s.name] for c in centres for s in c.free_symbols}
    rates = sp.Matrix([values[f"{s.name}_dot"] for s in angles])
    full = dict(values)
    for i, centre in enumerate(centres, start=1):
        position = centre.xreplace(rule)
        velocity = centre.jacobian(angles).xreplace(rule) * rates
        for k, axis in enumerate("xyz"):
            full[f"{axis}{i}"] = float(position[k])
            full[f"{axis}{i}_dot"] = float(velocity[k])
    return full


def check(method: str, n: int, result: dict) -> str:
    """'ok', or how the result differs from KanesMethod at a random state."""
    import numpy as np

    values = random_values(n)
    theirs = kane_accelerations(n, values, relative=method == "relative")
    if method in ("euler", "relative", "hand"):
        M, f = numbers(result["mass_matrix"], values), numbers(result["forcing"], values)
        ours = np.linalg.solve(M, f.ravel())
    else:
        full = cartesian_values(n, values)
        M, f = numbers(result["mass_matrix"], full), numbers(result["forcing"], full).ravel()
        A, gamma = numbers(result["constraint_jacobian"], full), numbers(result["gamma"], full)
        m = A.shape[0]
        augmented = np.block([[M, -A.T], [A, np.zeros((m, m))]])
        solution = np.linalg.solve(augmented, np.concatenate([f, gamma.ravel()]))
        ours = np.concatenate([solution[6 * i + 3 : 6 * i + 6] for i in range(n)])
    if np.allclose(ours, theirs, rtol=1e-8, atol=1e-8):
        return "ok"
    return f"differs from KanesMethod: max |diff| = {np.max(np.abs(ours - theirs)):.3g}"


# --------------------------------------------------------------------------- the worker


def warm_up() -> None:
    """Import the checkout's lagrangian and SymPy's lazily imported parts, outside the clock."""
    if not os.environ.get("PYTHONPATH"):  # a source tree given on PYTHONPATH is the one timed
        sys.path.insert(0, str(SRC))  # else the checkout's, installed or not
    import sympy as sp
    import sympy.physics.mechanics

    import lagrangian as lg

    lg.derive  # noqa: B018  (the lazy import of the derivation, outside the clock)
    lg.constrained_equations  # noqa: B018
    # the model files' reader and the examples, as sympy.physics.mechanics is imported above:
    # a library's import is start-up (benchmarks/startup.py), not derivation
    import lagrangian.examples
    import lagrangian.io  # noqa: F401

    warm_a, warm_b = sp.symbols("warm_a warm_b")
    _ = (warm_a * sp.sin(warm_b) + warm_b * sp.cos(warm_a)) ** 2  # SymPy's lazy imports


class Stopwatch:
    """The wall and CPU time of a worker's timed part, and why the two differ: the process's
    context switches meanwhile (``getrusage``).  Voluntary ones are waits of its own (I/O, a
    lock, a sleep, a thread joined); involuntary ones are the scheduler handing its core to
    another process (the load of a shared machine).  The CPU time counts every thread."""

    def __init__(self) -> None:
        self._usage = resource.getrusage(resource.RUSAGE_SELF)
        self._wall, self._cpu = time.perf_counter(), time.process_time()

    def read(self) -> dict:
        """{"seconds", "cpu_seconds", "voluntary_switches", "involuntary_switches"} so far."""
        wall, cpu = time.perf_counter() - self._wall, time.process_time() - self._cpu
        usage = resource.getrusage(resource.RUSAGE_SELF)
        return {
            "seconds": wall,
            "cpu_seconds": cpu,
            "voluntary_switches": usage.ru_nvcsw - self._usage.ru_nvcsw,
            "involuntary_switches": usage.ru_nivcsw - self._usage.ru_nivcsw,
        }


def worker(method: str, n: int, verify: bool) -> int:
    """Time one derivation in this fresh process; print one JSON line."""
    warm_up()
    clock = Stopwatch()
    result = DERIVERS[method](n)
    outcome: dict = clock.read()
    if verify and not method.startswith("kane") and n <= CHECK_MAX_N:
        outcome["check"] = check(method, n, result)
    print(json.dumps(outcome), flush=True)
    return 0


def benchmark_parser(doc: str, methods: tuple[str, ...]) -> argparse.ArgumentParser:
    """The options of a benchmark that times ``methods`` in fresh worker processes (the
    bicycle's, the rolling disc's): --repeat, --cap, --record and the worker's own."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per method (3)")
    parser.add_argument("--cap", type=float, default=300.0, help="seconds per run (300)")
    parser.add_argument(
        "--record", action="store_true", help=f"write the section in {RESULTS.name}"
    )
    parser.add_argument("--worker", metavar="METHOD", choices=methods, help=argparse.SUPPRESS)
    parser.add_argument("--verify", action="store_true", help=argparse.SUPPRESS)
    return parser


def run(method: str, n: int, cap: float, verify: bool) -> dict:
    """One measurement in a fresh process; {"seconds": inf} when it overran the cap."""
    return run_worker(HERE, [method, str(n)], cap, verify)


def run_worker(script: Path, arguments: list[str], cap: float, verify: bool) -> dict:
    """``script --worker ARGUMENTS`` in a fresh process: the JSON line it prints last;
    {"seconds": inf} when it overran the cap, nan with the error when it failed."""
    command = [sys.executable, str(script), "--worker", *arguments]
    command += ["--verify"] if verify else []
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=cap + STARTUP_SECONDS, check=False
        )
    except subprocess.TimeoutExpired:
        return {"seconds": math.inf}
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    if done.returncode != 0 or not lines:
        return {"seconds": math.nan, "error": done.stderr.strip()[-300:]}
    return json.loads(lines[-1])


# --------------------------------------------------------------------------- the report


def measure(ns: list[int], repeat: int, cap: float, methods: tuple[str, ...] = METHODS) -> dict:
    """Median seconds per (method, n), and the checks; methods alternate run by run (those
    not in ``methods`` are left out: NaN)."""
    times: dict = {(m, n): [math.nan] for m in METHODS for n in ns}
    times.update({(m, n): [] for m in methods for n in ns})
    notes: list[str] = []
    for n in ns:
        for r in range(repeat):
            for method in methods:
                outcome = run(method, n, cap, verify=(r == 0))
                times[method, n].append(outcome["seconds"])
                if "error" in outcome:
                    notes.append(f"{LABELS[method]} n={n}: error: {outcome['error']}")
                if outcome.get("check", "ok") != "ok":
                    notes.append(f"WARNING {LABELS[method]} n={n}: {outcome['check']}")
                elif "check" in outcome:
                    notes.append(f"{LABELS[method]} n={n}: same accelerations as KanesMethod")
                print(
                    f"  n={n} {method:<9} run {r + 1}: {outcome['seconds']:.3g} s", file=sys.stderr
                )
    medians = {key: statistics.median(values) for key, values in times.items()}
    return {"medians": medians, "notes": notes}


def _seconds(value: float, cap: float) -> str:
    """A cell of seconds: "-" for a method not run, "> cap" for one that overran."""
    if math.isnan(value):
        return "-"
    return f"> {cap:g}" if math.isinf(value) else f"{value:.3g}"


def _ratio(kane: float, ours: float) -> str:
    if math.isinf(ours) or math.isnan(ours) or math.isnan(kane):
        return "-"
    return f"{kane / ours:.3g}"


def report(measured: dict, ns: list[int], repeat: int, cap: float, kept: str = "") -> str:
    """The table of ``measured`` (medians per (method, n); NaN: not run) for the chain
    lengths ``ns``, the notes and the verdicts of the pairs that both ran; ``kept`` names
    the earlier record the cells not measured now come from (see :func:`merged`)."""
    medians = measured["medians"]
    lines = [
        f"Median of {repeat} run(s) per cell, seconds; cap {cap:g} s per run.",
        *([kept] if kept else []),
        "",
        "| n | coordinates (Euler / Cartesian) | Euler s | Cartesian s | Kane s "
        "| Kane/Euler | Kane/Cartesian | joint angles s | Kane (joint angles) s "
        "| Kane/joint angles | by hand s | Kane/by hand |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    verdicts = []
    for n in ns:
        euler, cartesian, kane, relative, kane_relative, hand = (
            medians.get((m, n), math.nan) for m in METHODS
        )
        lines.append(
            f"| {n} | {3 * n} / {6 * n} | {_seconds(euler, cap)} | {_seconds(cartesian, cap)} "
            f"| {_seconds(kane, cap)} | {_ratio(kane, euler)} | {_ratio(kane, cartesian)} "
            f"| {_seconds(relative, cap)} | {_seconds(kane_relative, cap)} "
            f"| {_ratio(kane_relative, relative)} | {_seconds(hand, cap)} "
            f"| {_ratio(kane, hand)} |"
        )
        for method, ours, theirs in (
            ("euler", euler, kane),
            ("cartesian", cartesian, kane),
            ("relative", relative, kane_relative),
            ("hand", hand, kane),
        ):
            if math.isnan(ours) or math.isnan(theirs):
                continue  # one of them not run: nothing to compare
            passed = ours < theirs
            verdict = "PASS" if passed else "FAIL"
            verdicts.append(f"{verdict}  n={n}: {LABELS[method]} faster than KanesMethod")
    lines += ["", *measured["notes"], "", "```", *verdicts, "```"]
    return "\n".join(lines)


def record(
    text: str,
    command: str,
    title: str = "3-D chains of rigid bodies (benchmarks/multibody.py)",
    markers: tuple[str, str] = (BEGIN, END),
) -> None:
    """Write (or replace) this benchmark's section of RESULTS.md (the one between
    ``markers``: benchmarks/bicycle.py writes its own)."""
    begin, end = markers
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="minutes")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    section = "\n".join(
        [
            begin,
            f"## {title}, {now}",
            "",
            f"- platform: {platform.platform()}",
            f"- CPU: {cpu_model()} ({os.cpu_count()} cores)",
            f"- python {platform.python_version()}, sympy {package_version('sympy')}, "
            f"symengine {package_version('symengine')}",
            f"- lagrangian's compiled modules: {compiled_forms()}",
            f"- 1-minute load average at the end: {load:.2f}",
            "",
            f"`{command}`; see the docstring for what is timed.",
            "",
            text,
            "",
            end,
        ]
    )
    existing = RESULTS.read_text()
    if begin in existing and end in existing:
        head, rest = existing.split(begin, 1)
        tail = rest.split(end, 1)[1]
        updated = head + section + tail
    else:
        updated = existing.rstrip("\n") + "\n\n" + section + "\n"
    RESULTS.write_text(updated)


def publish(
    text: str, script: str, argv: list[str] | None, title: str, markers: tuple[str, str], keep: bool
) -> None:
    """Print a benchmark's report and, when ``keep`` (its ``--record``), write it as its
    section of RESULTS.md with the command that measured it."""
    print(text)
    if keep:
        shown = " ".join([f"python benchmarks/{script}", *(argv or sys.argv[1:])])
        record(text, shown.replace(" --record", ""), title, markers)
        print(f"\nwritten to {RESULTS}")


#: The table's columns of seconds, by method (older records have the first three only).
COLUMNS = {
    "Euler s": "euler",
    "Cartesian s": "cartesian",
    "Kane s": "kane",
    "joint angles s": "relative",
    "Kane (joint angles) s": "kane_relative",
    "by hand s": "hand",
}


def recorded(results: str, markers: tuple[str, str] = (BEGIN, END)) -> dict:
    """What this benchmark's section of RESULTS.md (the text ``results``) holds: the medians
    per (method, n) of its table (NaN where a cell is empty, inf where it overran the cap),
    its notes and the command it was made by; empty when there is no section."""
    begin, end = markers
    if begin not in results or end not in results:
        return {"medians": {}, "notes": [], "command": ""}
    section = results.split(begin, 1)[1].split(end, 1)[0]
    lines = section.splitlines()
    header = next((i for i, line in enumerate(lines) if line.startswith("| n |")), None)
    medians: dict = {}
    notes: list[str] = []
    if header is not None:
        names = [cell.strip() for cell in lines[header].strip("|").split("|")]
        body = header + 2  # past the alignment row
        while body < len(lines) and lines[body].startswith("|"):
            cells = [cell.strip() for cell in lines[body].strip("|").split("|")]
            n = int(cells[0])
            for name, cell in zip(names, cells):
                if name in COLUMNS:
                    medians[COLUMNS[name], n] = _parsed_seconds(cell)
            body += 1
        fence = next((i for i in range(body, len(lines)) if lines[i] == "```"), len(lines))
        notes = [line for line in lines[body:fence] if line.strip()]
    command = next((line.split("`")[1] for line in lines if line.startswith("`")), "")
    return {"medians": medians, "notes": notes, "command": command}


def _parsed_seconds(cell: str) -> float:
    if cell.startswith(">"):
        return math.inf
    try:
        return float(cell)
    except ValueError:
        return math.nan


def merged(
    measured: dict, ns: list[int], methods: tuple[str, ...], earlier: dict
) -> tuple[dict, list[int], str]:
    """The cells measured now (``methods`` at ``ns``) with every other cell of the
    ``earlier`` record (:func:`recorded`), the chain lengths of both, and the line that says
    where the kept cells come from ("" when none is kept)."""
    now = {(m, n) for m in methods for n in ns}
    kept = {key: value for key, value in earlier["medians"].items() if key not in now}
    if not any(not math.isnan(value) for value in kept.values()):
        return measured, ns, ""
    every = sorted(set(ns) | {n for _, n in kept})
    medians = {(m, n): math.nan for m in METHODS for n in every}
    medians.update(kept)
    medians.update({key: measured["medians"][key] for key in now})
    ran = [LABELS[m] for m in methods]
    notes = [  # those about a cell measured now are replaced by the new ones
        note
        for note in earlier["notes"]
        if not any(
            note.removeprefix("WARNING ").startswith(f"{label} n={n}:") for label in ran for n in ns
        )
    ]
    source = f" (`{earlier['command']}`)" if earlier["command"] else ""
    line = (
        f"Measured now: {', '.join(methods)}; the other cells are kept from the earlier "
        f"record{source}."
    )
    return {"medians": medians, "notes": [*notes, *measured["notes"]]}, every, line


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, nargs="+", help=f"chain lengths (default {DEFAULT_N})")
    parser.add_argument("--repeat", type=int, default=1, help="runs per method and n (1)")
    parser.add_argument("--cap", type=float, default=600.0, help="seconds per run (600)")
    parser.add_argument(
        "--record", action="store_true", help=f"write the section in {RESULTS.name}"
    )
    parser.add_argument(
        "--methods", nargs="+", choices=METHODS, help="the methods to run (all of them)"
    )
    parser.add_argument("--worker", nargs=2, metavar=("METHOD", "N"), help=argparse.SUPPRESS)
    parser.add_argument("--verify", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        return worker(args.worker[0], int(args.worker[1]), args.verify)
    ns = sorted(set(args.n or DEFAULT_N))
    methods = tuple(args.methods or METHODS)
    measured = measure(ns, args.repeat, args.cap, methods)
    text = report(measured, ns, args.repeat, args.cap)
    print(text)
    if args.record:
        shown = " ".join(["python benchmarks/multibody.py", *(argv or sys.argv[1:])])
        shown = shown.replace(" --record", "")
        if set(methods) != set(METHODS):  # keep the cells of the methods not run now
            earlier = recorded(RESULTS.read_text() if RESULTS.exists() else "")
            measured, ns, kept = merged(measured, ns, methods, earlier)
            text = report(measured, ns, args.repeat, args.cap, kept)
        record(text, shown)
        print(f"\nwritten to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
