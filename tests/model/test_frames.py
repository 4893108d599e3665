"""Frames and relative orientations: simple rotations about body axes relative to a parent
body or frame, against sympy.physics.mechanics' ReferenceFrame (orient_axis,
orient_body_fixed), and the refusal of a bad parent or axis."""

from __future__ import annotations

import random

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.errors import ModelError
from lagrangian.io.dump import dumps
from lagrangian.model import Frame, RigidBody, System, rotation_sequence, shape
from lagrangian.model.rotation import (
    axis_angle,
    body_angular_velocity,
    euler_rotation,
    quaternion_rotation,
    rotation_axis,
    spatial_angular_velocity,
)
from lagrangian.symbolic.symbols import velocity

TIME = me.dynamicsymbols._t
a, b, c, d = sp.symbols("a b c d")
m, r = sp.symbols("m r")


def _plain(expr: sp.Basic, names: list[str]) -> sp.Basic:
    swap: dict = {}
    for name in names:
        f = me.dynamicsymbols(name)
        swap[f.diff(TIME)] = sp.Symbol(name + "_dot")
        swap[f] = sp.Symbol(name)
    return expr.xreplace(swap)


def _agree(ours: sp.MatrixBase, theirs: sp.MatrixBase, symbols: list, seed: int = 3) -> None:
    """Equal at random points (angles, rates) to 1e-12."""
    rng = random.Random(seed)
    for _ in range(4):
        values = {s: rng.uniform(-2.0, 2.0) for s in symbols}
        left = np.array(sp.Matrix(ours).xreplace(values).evalf(), dtype=float)
        right = np.array(sp.Matrix(theirs).xreplace(values).evalf(), dtype=float)
        np.testing.assert_allclose(left, right, atol=1e-12)


SYMBOLS = [a, b, c, d, *(velocity(s) for s in (a, b, c, d))]


def test_a_body_fixed_sequence_is_mechanics_orient_body_fixed() -> None:
    qa, qb, qc = me.dynamicsymbols("a b c")
    world, body = me.ReferenceFrame("N"), me.ReferenceFrame("B")
    body.orient_body_fixed(world, (qa, qb, qc), "zxz")
    ours = rotation_sequence([("z", a), ("x", b), ("z", c)])
    _agree(ours.matrix, _plain(world.dcm(body), ["a", "b", "c"]), SYMBOLS)
    omega = body.ang_vel_in(world)
    _agree(
        body_angular_velocity(ours, [a, b, c]), _plain(omega.to_matrix(body), list("abc")), SYMBOLS
    )
    spatial = _plain(omega.to_matrix(world), list("abc"))
    _agree(spatial_angular_velocity(ours, [a, b, c]), spatial, SYMBOLS)


def test_it_matches_euler_angles_exactly() -> None:
    ours = rotation_sequence([("Z", a), ("x", b), ("z", c)])
    euler = euler_rotation("ZXZ", (a, b, c))
    assert ours.matrix == euler.matrix
    assert body_angular_velocity(ours, [a, b, c]) == body_angular_velocity(euler, [a, b, c])


def test_a_chain_of_parents_and_a_tilted_axis_compose_like_mechanics() -> None:
    """N -> A (z, a) -> B (about [1, 1, 0] of A, b) -> C (y, c then x, d)."""
    qa, qb, qc, qd = me.dynamicsymbols("a b c d")
    world, first, second, third = (me.ReferenceFrame(n) for n in "NABC")
    first.orient_axis(world, world.z, qa)
    second.orient_axis(first, (first.x + first.y) / sp.sqrt(2), qb)
    middle = me.ReferenceFrame("M")
    middle.orient_axis(second, second.y, qc)
    third.orient_axis(middle, middle.x, qd)
    A = rotation_sequence([("z", a)])
    B = rotation_sequence([((1, 1, 0), b)], parent=A)
    C = rotation_sequence([("y", c), ("x", d)], parent=B)
    q = [a, b, c, d]
    _agree(C.matrix, _plain(world.dcm(third), list("abcd")), SYMBOLS)
    omega = third.ang_vel_in(world)
    _agree(body_angular_velocity(C, q), _plain(omega.to_matrix(third), list("abcd")), SYMBOLS)
    _agree(spatial_angular_velocity(C, q), _plain(omega.to_matrix(world), list("abcd")), SYMBOLS)


@pytest.mark.parametrize(
    ("parent_turns", "turns"),
    [
        ([("z", a), ("x", b), ("y", c)], [("y", -d), ("z", -a), ("y", d)]),  # a bicycle's fork
        ([("x", a)], [((0, 2, 0), b), ((0, -1, 0), c), ((1, 1, 0), d)]),  # scaled, tilted axes
        ([], [("z", 0), ("x", sp.pi / 3), ("y", a + b)]),
    ],
)
def test_the_composed_matrix_is_the_product_of_the_rotation_matrices(
    parent_turns: list, turns: list
) -> None:
    """The same entries, tree for tree, as R_parent R1 R2 ... multiplied as SymPy matrices
    (each Rk by Rodrigues' formula)."""
    parent = rotation_sequence(parent_turns) if parent_turns else None
    product = sp.eye(3) if parent is None else sp.Matrix(parent.matrix)
    for axis, angle in turns:
        product = product * axis_angle(rotation_axis(axis), angle).matrix
    composed = rotation_sequence(turns, parent=parent).matrix
    assert sp.srepr(composed) == sp.srepr(sp.ImmutableMatrix(product))


def test_a_parent_given_by_a_quaternion_composes_its_angular_velocity() -> None:
    """The parent's omega comes from its own form; the child's rotations are added to it."""
    half = sp.Symbol("a") / 2
    parent = quaternion_rotation(sp.cos(half), 0, sp.sin(half), 0)  # about y by a
    child = rotation_sequence([("z", b)], parent=parent)
    reference = rotation_sequence([("y", a), ("z", b)])
    _agree(child.matrix, reference.matrix, SYMBOLS)
    for omega in (body_angular_velocity, spatial_angular_velocity):
        _agree(omega(child, [a, b]), omega(reference, [a, b]), SYMBOLS)


def test_a_system_fills_in_the_composed_orientation_and_keeps_it_on_replace() -> None:
    rotor = RigidBody("rotor", m, shape("disc", radius=r, axis="x"), (0, 0, 0))
    rotor = RigidBody(**{**rotor.__dict__, "parent": "gimbal", "rotations": [("x", b)]})
    system = System(
        coordinates=[a, b],
        parameters=[m, r],
        frames=[Frame("gimbal", [("z", a)])],
        rigid_bodies=[rotor],
    )
    expected = rotation_sequence([("z", a), ("x", b)]).matrix
    assert system.rigid_bodies[0].orientation.matrix == expected
    assert system.frames[0].orientation.matrix == rotation_sequence([("z", a)]).matrix
    again = system.replace(name="again")
    assert again.rigid_bodies[0].orientation.matrix == expected
    assert not system.rigid_bodies[0].planar


def _wheel(**changes: object) -> RigidBody:
    fields = {
        "name": "wheel",
        "mass": m,
        "inertia": sp.diag(1, 1, 1),
        "position": (0, 0, 0),
        "parent": "fork",
        "rotations": [("y", b)],
    }
    return RigidBody(**{**fields, **changes})  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("frames", "body", "match"),
    [
        (
            [Frame("fork", [("z", a)])],
            _wheel(parent="frok"),
            r"body 'wheel': unknown parent 'frok'.*did you mean 'fork'",
        ),
        (
            [Frame("fork", [("z", a)], parent="wheel")],
            _wheel(),
            r"parents form a cycle \((wheel -> fork -> wheel|fork -> wheel -> fork)\)",
        ),
        ([Frame("fork", [("w", a)])], _wheel(), r"frame 'fork': unknown axis 'w'.*use x, y or z"),
        ([Frame("fork")], _wheel(rotations=[("q", b)]), r"body 'wheel': unknown axis 'q'"),
        (
            [Frame("fork")],
            _wheel(rotations=[((0, 0, 0), b)]),
            r"body 'wheel'.*not an axis.*non-zero vector",
        ),
        (
            [Frame("fork", [("z", sp.Symbol("e"))])],
            _wheel(),
            r"frames\[0\].rotations\[0\].*unknown name 'e'",
        ),
        ([Frame("wheel")], _wheel(parent=None), r"frames\[0\].name.*'wheel' is taken"),
        ([Frame("fork")], _wheel(orientation=sp.eye(3)), r"body 'wheel' has both.*not both"),
    ],
)
def test_bad_frames_are_refused_naming_the_body_and_the_fix(frames, body, match) -> None:
    with pytest.raises(ModelError, match=match):
        System(coordinates=[a, b], parameters=[m], frames=frames, rigid_bodies=[body])


def test_a_planar_parent_is_refused() -> None:
    rod = RigidBody("rod", m, 1, (a, 0), angle=a)
    with pytest.raises(ModelError, match=r"the parent 'rod' is a planar body"):
        System(coordinates=[a, b], parameters=[m], rigid_bodies=[rod, _wheel(parent="rod")])


GIMBAL = """\
name: gimbal
coordinates: [a, b]
parameters: {m: 1.0, C: 0.2, A: 0.1}
frames:
- {name: gimbal, rotations: [[z, a]]}
rigid_bodies:
- name: rotor
  mass: m
  inertia: [[C, 0, 0], [0, A, 0], [0, 0, A]]
  position: [0, 0, 0]
  parent: gimbal
  rotations: [[x, b]]
"""


def test_the_model_file_reads_frames_and_rotations_and_writes_them_back() -> None:
    system = lg.loads(GIMBAL)
    assert (
        system.rigid_bodies[0].orientation.matrix == rotation_sequence([("z", a), ("x", b)]).matrix
    )
    text = dumps(system)
    assert "parent: gimbal" in text and "- [x, b]" in text
    again = lg.loads(text)
    assert again.rigid_bodies[0].orientation.matrix == system.rigid_bodies[0].orientation.matrix


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (("[[z, a]]", "[[w, a]]"), r"frames\[0\].rotations\[0\].*frame 'gimbal': unknown axis 'w'"),
        (("parent: gimbal", "parent: gimbl"), r"rigid_bodies\[0\].parent.*did you mean 'gimbal'"),
        (("[[z, a]]", "[[z, a]], parent: rotor"), r"the parents form a cycle"),
        (("[[x, b]]", "[x, b]"), r"rotations\[0\].*is not one rotation"),
    ],
)
def test_bad_frames_in_a_model_file_exit_with_2(tmp_path, capsys, change, match) -> None:
    path = tmp_path / "gimbal.yaml"
    path.write_text(GIMBAL.replace(*change), encoding="utf-8")
    with pytest.raises(ModelError, match=match):
        lg.load(path)
    assert main(["derive", str(path)]) == 2
    assert "gimbal.yaml" in capsys.readouterr().err


def test_an_orientation_built_with_rotation_sequence_is_written_as_rotations() -> None:
    turns = rotation_sequence([("z", a), ((1, 1, 0), b)])
    body = RigidBody("r", m, sp.eye(3), (0, 0, 0), orientation=turns)
    text = dumps(System(coordinates=[a, b], parameters=[m], rigid_bodies=[body]))
    assert "- [z, a]" in text and "orientation" not in text
    again = lg.loads(text)
    assert again.rigid_bodies[0].orientation.matrix == turns.matrix
