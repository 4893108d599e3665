"""A 3-D chain of rigid rods joined by spherical joints, each rod turned by its own Euler
angles (body-fixed Z-X-Y relative to the world), against sympy.physics.mechanics' KanesMethod
on frames oriented by ``orient_body_fixed``: the mass matrix, the accelerations M^-1 forcing
and T at random states (three rods), and the same chain with Cartesian centres and the joints
as holonomic constraints in world axes, whose multiplier form gives Kane's accelerations (two
rods)."""

from __future__ import annotations

import random

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me
from test_rigid_body_3d import Reference, assert_same_motion, kanes

import lagrangian as lg
from lagrangian.model import rotation_sequence
from lagrangian.symbolic.symbols import velocity

G = sp.Symbol("g")


def _rods(n: int) -> list[tuple[sp.Symbol, ...]]:
    """(a, b, c, m, l, I, J) of every rod."""
    return [sp.symbols(f"a{i} b{i} c{i} m{i} l{i} I{i} J{i}") for i in range(1, n + 1)]


def _turns(a: sp.Symbol, b: sp.Symbol, c: sp.Symbol) -> list[tuple[str, sp.Symbol]]:
    return [("z", a), ("x", b), ("y", c)]


def _axes(n: int) -> list[sp.Matrix]:
    """The axis R_i e_z of every rod."""
    return [rotation_sequence(_turns(*rod[:3])).matrix[:, 2] for rod in _rods(n)]


def _centres(n: int) -> list[sp.Matrix]:
    """G_i = J_(i-1) - l_i/2 R_i e_z with J_0 = 0 and J_i = J_(i-1) - l_i R_i e_z."""
    joint, centres = sp.zeros(3, 1), []
    for rod, axis in zip(_rods(n), _axes(n)):
        length = rod[4]
        centres.append((joint - length / 2 * axis).applyfunc(sp.expand))
        joint = joint - length * axis
    return centres


def _parameters(n: int) -> list[sp.Symbol]:
    return [G, *(s for rod in _rods(n) for s in rod[3:])]


def euler_chain(n: int) -> lg.System:
    bodies = [
        lg.RigidBody(f"rod{i + 1}", m, sp.diag(I, I, J), tuple(centre), rotations=_turns(a, b, c))
        for i, ((a, b, c, m, _, I, J), centre) in enumerate(zip(_rods(n), _centres(n)))
    ]
    return lg.System(
        coordinates=[s for rod in _rods(n) for s in rod[:3]],
        parameters=_parameters(n),
        gravity=(0, 0, -G),
        rigid_bodies=bodies,
    )


def cartesian_chain(n: int) -> lg.System:
    coordinates, bodies, constraints = [], [], []
    previous_end = sp.zeros(3, 1)
    for i, ((a, b, c, m, l, I, J), axis) in enumerate(zip(_rods(n), _axes(n))):
        centre = sp.Matrix(sp.symbols(f"x{i + 1} y{i + 1} z{i + 1}"))
        coordinates += [*centre, a, b, c]
        rod = lg.RigidBody(
            f"rod{i + 1}", m, sp.diag(I, I, J), tuple(centre), rotations=_turns(a, b, c)
        )
        bodies.append(rod)
        constraints += [lg.Holonomic(sp.expand(e)) for e in centre + l / 2 * axis - previous_end]
        previous_end = centre - l / 2 * axis
    return lg.System(
        coordinates=coordinates,
        parameters=_parameters(n),
        gravity=(0, 0, -G),
        rigid_bodies=bodies,
        constraints=constraints,
    )


def kane_chain(n: int) -> Reference:
    world = me.ReferenceFrame("N")
    joint = me.Point("O")
    joint.set_vel(world, 0)
    coordinates, bodies, loads = [], [], []
    for i, (a, b, c, m, l, I, J) in enumerate(_rods(n)):
        angles = me.dynamicsymbols(f"{a} {b} {c}")
        coordinates += angles
        frame = me.ReferenceFrame(f"B{i + 1}")
        frame.orient_body_fixed(world, angles, "ZXY")
        centre = joint.locatenew(f"G{i + 1}", -l / 2 * frame.z)
        centre.v2pt_theory(joint, world, frame)
        end = joint.locatenew(f"J{i + 1}", -l * frame.z)
        end.v2pt_theory(joint, world, frame)
        inertia = (me.inertia(frame, I, I, J), centre)
        bodies.append(me.RigidBody(f"rod{i + 1}", centre, frame, m, inertia))
        loads.append((centre, -m * G * world.z))
        joint = end
    return kanes(world, coordinates, bodies, loads)


def test_three_rods_on_spherical_joints_match_kanes_method() -> None:
    assert_same_motion(euler_chain(3), kane_chain(3))


def test_the_mass_matrix_keeps_products_of_sines_and_cosines_of_single_angles() -> None:
    """No angle sums from product-to-sum rewriting, and sin^2 + cos^2 = 1 applied: the
    diagonal entry of the first angle is one trigonometric monomial over the constant."""
    mass = lg.derive(euler_chain(3)).mass_matrix
    arguments = {f.args[0] for e in mass for f in e.atoms(sp.sin, sp.cos)}
    assert all(argument.is_Symbol for argument in arguments)
    assert len(mass[0, 0].atoms(sp.cos)) == 2  # cos(b1)**2 * cos(c1)**2


def _numbers(expr: sp.Basic, values: dict[sp.Symbol, float]) -> np.ndarray:
    return np.array(sp.Matrix(expr).xreplace(values).evalf(), dtype=float)


def test_the_cartesian_chain_with_joint_constraints_gives_kanes_accelerations() -> None:
    n = 2
    equations = lg.constrained_equations(cartesian_chain(n))
    reference = kane_chain(n)
    angles = [s for rod in _rods(n) for s in rod[:3]]
    rng = random.Random(5)
    for _ in range(2):
        values = {p: rng.uniform(0.5, 1.5) for p in _parameters(n)}
        values.update({s: rng.uniform(-1.2, 1.2) for s in angles})
        values.update({velocity(s): rng.uniform(-1.5, 1.5) for s in angles})
        rates = sp.Matrix([values[velocity(s)] for s in angles])
        for i, centre in enumerate(_centres(n)):
            position = centre.xreplace(values)
            moving = centre.jacobian(angles).xreplace(values) * rates
            for k, axis in enumerate("xyz"):
                values[sp.Symbol(f"{axis}{i + 1}")] = float(position[k])
                values[sp.Symbol(f"{axis}{i + 1}_dot")] = float(moving[k])
        matrix = _numbers(equations.augmented_matrix, values)
        solution = np.linalg.solve(matrix, _numbers(equations.augmented_rhs, values).ravel())
        ours = np.concatenate([solution[6 * i + 3 : 6 * i + 6] for i in range(n)])
        mass = _numbers(reference.mass_matrix, values)
        theirs = np.linalg.solve(mass, _numbers(reference.forcing, values).ravel())
        np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-9)
