"""3-D rigid bodies in model files: inertia as a 3x3 matrix or a shape, orientation as Euler
angles, an axis and angle, a quaternion or a matrix, torques in world axes.  A file gives the
System built by hand, survives the writer (file -> System -> file -> System, same equations),
is valid under the JSON Schema, and bad entries are refused with their place in the file."""

from __future__ import annotations

import json
import textwrap

import jsonschema
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError, Problem
from lagrangian.io import loads, schema
from lagrangian.io.dump import dumps, model_document
from lagrangian.model.inertia import shape
from lagrangian.model.rotation import axis_angle, euler_rotation, quaternion_rotation

TOP_YAML = """\
name: Heavy symmetric top
coordinates: [phi, theta, psi]
parameters: {m: 1.0, g: 9.81, l: 0.5, A: 0.3, C: 0.5}
gravity: [0, 0, -g]
rigid_bodies:
  - name: top
    mass: m
    inertia: [[A, 0, 0], [0, A, 0], [0, 0, C]]
    position: ["l*sin(phi)*sin(theta)", "-l*cos(phi)*sin(theta)", "l*cos(theta)"]
    orientation: {euler: ZXZ, angles: [phi, theta, psi]}
initial: {theta: 0.5, psi_dot: 30}
"""


def _top_by_hand() -> lg.System:
    phi, theta, psi = lg.coordinates("phi theta psi")
    m, g, l, A, C = sp.symbols("m g l A C")
    R = euler_rotation("ZXZ", (phi, theta, psi))
    return lg.System(
        name="Heavy symmetric top",
        coordinates=[phi, theta, psi],
        parameters={m: 1.0, g: 9.81, l: 0.5, A: 0.3, C: 0.5},
        rigid_bodies=[
            lg.RigidBody("top", m, sp.diag(A, A, C), tuple(R.matrix[:, 2] * l), orientation=R)
        ],
        gravity=(0, 0, -g),
        initial={theta: 0.5, sp.Symbol("psi_dot"): 30},
    )


def test_the_heavy_top_file_is_the_top_built_by_hand() -> None:
    loaded, by_hand = loads(TOP_YAML), _top_by_hand()
    assert loaded == by_hand
    first, second = lg.derive(loaded), lg.derive(by_hand)
    assert first.mass_matrix == second.mass_matrix and first.forcing == second.forcing


#: One body of each form, every key of the new entries at least once.
EVERY_FORM = {
    "name": "Every 3-D form",
    "coordinates": ["a", "b", "c"],
    "parameters": {"m": 1.0, "r": 0.2, "h": 1.0, "g": 9.81, "k": 0.1},
    "gravity": [0, 0, "-g"],
    "rigid_bodies": [
        {
            "name": "matrix_inertia",
            "mass": "m",
            "inertia": [["2*m", 0, "k"], [0, "3*m", 0], ["k", 0, "4*m"]],
            "position": ["a", "b", "c"],
            "orientation": {"euler": "ZYX", "angles": ["a", "b", "c"], "intrinsic": False},
        },
        {
            "name": "cylinder",
            "mass": "m",
            "inertia": {"shape": "cylinder", "radius": "r", "length": "h", "axis": "x"},
            "position": [0, 0, "-h/2"],
            "orientation": {"axis": [1, 1, 0], "angle": "a + t"},
        },
        {
            "name": "ball",
            "mass": "m",
            "inertia": {"shape": "solid_sphere", "radius": "r"},
            "position": ["b", 0, 0],
            "orientation": {"quaternion": ["cos(a/2)", 0, "sin(a/2)*sin(b)", "sin(a/2)*cos(b)"]},
        },
        {
            "name": "brick",
            "mass": "m",
            "inertia": {"shape": "box", "length_x": 1, "length_y": "r", "length_z": "h"},
            "position": [0, "c", 0],
            "orientation": [["cos(c)", "-sin(c)", 0], ["sin(c)", "cos(c)", 0], [0, 0, 1]],
        },
    ],
    "torques": [{"name": "motor", "body": "cylinder", "torque": [0, 0, "k*sin(t)"]}],
}


def _every_form_by_hand() -> dict[str, lg.RigidBody]:
    a, b, c = lg.coordinates("a b c")
    m, r, h, k = sp.symbols("m r h k")
    return {
        "matrix_inertia": lg.RigidBody(
            "matrix_inertia",
            m,
            [[2 * m, 0, k], [0, 3 * m, 0], [k, 0, 4 * m]],
            (a, b, c),
            orientation=euler_rotation("ZYX", (a, b, c), intrinsic=False),
        ),
        "cylinder": lg.RigidBody(
            "cylinder",
            m,
            shape("cylinder", radius=r, length=h, axis="x"),
            (0, 0, -h / 2),
            orientation=axis_angle([1, 1, 0], a + lg.t),
        ),
        "ball": lg.RigidBody(
            "ball",
            m,
            shape("solid_sphere", radius=r),
            (b, 0, 0),
            orientation=quaternion_rotation(
                sp.cos(a / 2), 0, sp.sin(a / 2) * sp.sin(b), sp.sin(a / 2) * sp.cos(b)
            ),
        ),
        "brick": lg.RigidBody(
            "brick",
            m,
            shape("box", length_x=1, length_y=r, length_z=h),
            (0, c, 0),
            orientation=axis_angle([0, 0, 1], c).matrix,
        ),
    }


def test_every_form_reads_as_the_same_body_built_by_hand() -> None:
    system = loads(json.dumps(EVERY_FORM), format="json")
    bodies = {body.name: body for body in system.rigid_bodies}
    for name, body in _every_form_by_hand().items():
        assert bodies[name] == body, name
    assert system.torques[0].torque == (0, 0, sp.Symbol("k") * sp.sin(lg.t))


def test_the_new_forms_are_valid_under_the_schema() -> None:
    jsonschema.Draft202012Validator(schema()).validate(EVERY_FORM)
    jsonschema.Draft202012Validator(schema()).validate(model_document(loads(TOP_YAML)))


@pytest.mark.parametrize("fmt", ["yaml", "json"])
@pytest.mark.parametrize("source", ["every form", "top"])
def test_a_file_survives_the_writer_with_the_same_equations(fmt: str, source: str) -> None:
    original = (
        loads(json.dumps(EVERY_FORM), format="json") if source == "every form" else loads(TOP_YAML)
    )
    text = dumps(original, format=fmt)
    again = loads(text, format=fmt)
    assert again == original
    first, second = lg.derive(original), lg.derive(again)
    assert first.mass_matrix == second.mass_matrix and first.forcing == second.forcing


def test_the_writer_keeps_the_form_of_each_orientation_and_inertia() -> None:
    document = model_document(loads(json.dumps(EVERY_FORM), format="json"))
    written = {body["name"]: body for body in document["rigid_bodies"]}
    for entry in EVERY_FORM["rigid_bodies"]:
        assert sorted(written[entry["name"]]) == sorted(entry)
        assert type(written[entry["name"]]["inertia"]) is type(entry["inertia"])
        if "orientation" in entry:
            assert type(written[entry["name"]]["orientation"]) is type(entry["orientation"])
    assert written["cylinder"]["inertia"]["axis"] == "x"
    assert written["matrix_inertia"]["orientation"]["intrinsic"] is False
    assert document["torques"][0]["torque"] == [0, 0, "k*sin(t)"]


def test_a_toml_file_with_3d_bodies_loads() -> None:
    text = """\
    coordinates = ["a"]
    [[rigid_bodies]]
    name = "wheel"
    mass = 1
    inertia = {shape = "disc", radius = 0.5}
    position = [0, 0, 0]
    orientation = {axis = [0, 0, 1], angle = "a"}
    """
    system = loads(textwrap.dedent(text), format="toml")
    assert lg.derive(system).mass_matrix == sp.Matrix([[sp.Rational(1, 8)]])


# -- bad entries --------------------------------------------------------------------------------


def refused(text: str, match: str) -> tuple[Problem, ...]:
    with pytest.raises(ModelError, match=match) as caught:
        loads(textwrap.dedent(text), source="model")
    assert all(p.source == "model" and p.fix for p in caught.value.problems)
    return caught.value.problems


def where(problem: Problem) -> tuple[str, int | None, int | None]:
    return (problem.field, problem.line, problem.column)


BODY = """\
coordinates: [a, b, c]
parameters: {{m: 1, A: 1, C: 1.5}}
rigid_bodies:
  - name: top
    mass: m
    position: [0, 0, 0]
    inertia: {inertia}
    orientation: {orientation}
"""


def body(
    inertia: str = "[[A, 0, 0], [0, A, 0], [0, 0, C]]",
    orientation: str = "{euler: ZXZ, angles: [a, b, c]}",
) -> str:
    return BODY.format(inertia=inertia, orientation=orientation)


def test_an_unknown_shape_is_refused_with_a_suggestion() -> None:
    (problem,) = refused(
        body(inertia="{shape: cylindre, radius: 1, length: 2}"), r"unknown shape 'cylindre'"
    )
    assert "did you mean 'cylinder'?" in problem.fix
    assert where(problem) == ("rigid_bodies[0].inertia.shape", 7, 22)


@pytest.mark.parametrize(
    ("inertia", "match", "field"),
    [
        ("{shape: cylinder, radius: 1}", r"a cylinder needs its length", "rigid_bodies[0].inertia"),
        (
            "{shape: solid_sphere, radius: 1, length: 2}",
            r"a solid_sphere has no length",
            "rigid_bodies[0].inertia.length",
        ),
        (
            "{shape: cylinder, radus: 1, length: 2}",
            r"unknown key 'radus'.*did you mean 'radius'",
            "rigid_bodies[0].inertia.radus",
        ),
        (
            "{shape: box, length_x: 1, length_y: 1, length_z: 1, axis: x}",
            r"axis 'x' is not allowed",
            "rigid_bodies[0].inertia.axis",
        ),
        (
            "{shape: rod, length: 1, axis: w}",
            r"axis 'w' is not allowed",
            "rigid_bodies[0].inertia.axis",
        ),
        (
            "[[A, 0, 0], [0, A, 0]]",
            r"a 3x3 matrix needs 3 rows of 3 expressions, got rows of 3, 3 —",
            "rigid_bodies[0].inertia",
        ),
        ("[[A, 0], [0, A], [0, 0]]", r"got rows of 2, 2, 2", "rigid_bodies[0].inertia"),
        ("[[A, 0, 0], [0, A, 0], [0, 0, D]]", r"unknown name 'D'", "rigid_bodies[0].inertia[2][2]"),
    ],
)
def test_a_bad_inertia_is_refused_at_its_place(inertia: str, match: str, field: str) -> None:
    problems = refused(body(inertia=inertia), match)
    assert field in [p.field for p in problems]
    assert all(p.line is not None for p in problems)


@pytest.mark.parametrize(
    ("orientation", "match", "field"),
    [
        (
            "{euler: ZXX, angles: [a, b, c]}",
            r"unknown Euler sequence 'ZXX'.*did you mean",
            "rigid_bodies[0].orientation.euler",
        ),
        (
            "{euler: ZXZ, angles: [a, b]}",
            r"needs 3 components, got 2",
            "rigid_bodies[0].orientation.angles",
        ),
        ("{euler: ZXZ}", r"Euler angles need their angles", "rigid_bodies[0].orientation"),
        (
            "{euler: ZXZ, angles: [a, b, c], intrinsic: no_way}",
            r"must be true or false",
            "rigid_bodies[0].orientation.intrinsic",
        ),
        (
            "{euler: ZXZ, angles: [a, b, c], angle: a}",
            r"'angle' does not belong here",
            "rigid_bodies[0].orientation.angle",
        ),
        (
            "{quaternion: [1, 0, 0]}",
            r"needs 4 components, got 3",
            "rigid_bodies[0].orientation.quaternion",
        ),
        (
            "{axis: [0, 0, 0], angle: a}",
            r"the axis is the zero vector",
            "rigid_bodies[0].orientation.axis",
        ),
        ("{axis: [0, 0, 1]}", r"missing angle", "rigid_bodies[0].orientation"),
        (
            "{axis: [0, 0, 1], angle: a, euler: ZXZ}",
            r"exactly one of euler, axis, quaternion; found euler and axis",
            "rigid_bodies[0].orientation",
        ),
        (
            "{axes: [0, 0, 1], angle: a}",
            r"unknown key 'axes'.*did you mean 'axis'",
            "rigid_bodies[0].orientation.axes",
        ),
        ("[[1, 0, 0], [0, 1, 0]]", r"a 3x3 matrix needs 3 rows", "rigid_bodies[0].orientation"),
        ("up", r"must be a mapping", "rigid_bodies[0].orientation"),
    ],
)
def test_a_bad_orientation_is_refused_at_its_place(
    orientation: str, match: str, field: str
) -> None:
    problems = refused(body(orientation=orientation), match)
    assert field in [p.field for p in problems]
    assert all(p.line is not None for p in problems)


def test_a_matrix_that_is_not_a_rotation_is_refused_at_the_orientation() -> None:
    (problem,) = refused(
        body(orientation="[[1, a, 0], [0, 1, 0], [0, 0, 1]]"),
        r"the orientation of body 'top' is not orthonormal",
    )
    assert where(problem) == ("rigid_bodies[0].orientation", 8, 18)


def test_an_impossible_inertia_is_refused_at_the_inertia() -> None:
    (problem,) = refused(
        body(inertia="[[A, 0, 0], [0, A, 0], [0, 0, 3*C]]"),
        r"the principal moments of the inertia of body 'top' \(1, 1, 4.5\) violate",
    )
    assert where(problem) == ("rigid_bodies[0].inertia", 7, 14)


def test_a_body_with_an_angle_and_an_orientation_is_refused() -> None:
    text = body() + "    angle: a\n"
    (problem,) = refused(text, r"body 'top' has both an angle and an orientation")
    assert where(problem)[:2] == ("rigid_bodies[0]", 4)


def test_a_torque_on_a_3d_body_has_three_components() -> None:
    text = body() + "torques: [{body: top, torque: [1, 0]}]\n"
    refused(text, r"torques\[0\]\.torque .*a torque on a 3-D body has 3 components")
    text = body() + "torques: [{body: top, torque: 1}]\n"
    refused(text, r"torques\[0\]\.torque .*is not a vector")


@pytest.mark.parametrize(
    "entry",
    [
        {"inertia": {"shape": "sphere", "radius": 1}},
        {"inertia": {"shape": "solid_sphere", "radius": 1, "length": 1}},
        {"orientation": {"euler": "ZXZ", "angles": ["a", "b", "c"], "axis": [0, 0, 1]}},
        {"orientation": {"quaternion": [1, 0, 0]}},
        {"orientation": [[1, 0, 0], [0, 1, 0]]},
        {"angle": "a"},
    ],
)
def test_the_schema_refuses_what_the_loader_refuses(entry: dict) -> None:
    model = json.loads(json.dumps(EVERY_FORM))
    model["rigid_bodies"][0].update(entry)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.Draft202012Validator(schema()).validate(model)
    with pytest.raises(ModelError, match=r"not (describe )?a valid"):
        loads(json.dumps(model), format="json")
