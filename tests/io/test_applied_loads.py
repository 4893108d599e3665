"""Loads in model files beyond a force at a centre: a force at a body-fixed point (``offset``),
a torque that one body or frame exerts on another (``by``, with its reaction), a torque on a
massless frame (``frame``) and a force at a rolling disc's contact point.  Each form, written in
YAML, TOML and JSON, gives the equations of the Python API (lagrangian.model.loads) and of a
derivation by hand; it survives the writer (file -> System -> file -> System); the schema
accepts it; and bad entries are refused with their field, the fix and exit code 2."""

from __future__ import annotations

import io
import json
import re
from typing import Any

import jsonschema
import pytest
import sympy as sp
import yaml

import lagrangian as lg
from lagrangian.analysis import cyclic_coordinates
from lagrangian.cli.main import main
from lagrangian.io import loads, schema
from lagrangian.io.dump import dumps
from lagrangian.model import Force, Frame, RigidBody, RollingDisc, System
from lagrangian.model.inertia import shape
from lagrangian.model.loads import force_at_point, frame_torque, torque_pair
from lagrangian.model.rotation import rotation_sequence
from lagrangian.render.json import eom_document

m, g, l, F, tau, Q0 = sp.symbols("m g l F tau Q0")
A1, C1, A2, C2, r, Fx, Fy = sp.symbols("A1 C1 A2 C2 r F_x F_y")
theta, a, b, psi, phi, x, y = sp.symbols("theta a b psi phi x y")


def ddot(q: sp.Symbol) -> sp.Symbol:
    return sp.Symbol(f"{q.name}_ddot")


def dot(q: sp.Symbol) -> sp.Symbol:
    return sp.Symbol(f"{q.name}_dot")


# -- the models, as plain data written out in each format ---------------------------------

ROD_TIP = {
    "name": "rod_tip",
    "coordinates": ["theta"],
    "parameters": {"m": 1.0, "g": 9.81, "l": 0.8, "F": 0.5},
    "gravity": [0, "-g"],
    "rigid_bodies": [
        {
            "name": "rod",
            "mass": "m",
            "inertia": "m*l**2/12",
            "position": ["l/2*sin(theta)", "-l/2*cos(theta)"],
            "angle": "theta",
        }
    ],
    "forces": [{"name": "push", "at": "rod", "offset": [0, "-l/2"], "force": ["F", 0]}],
}

ROD_TIP_3D = {
    "name": "rod_tip_3d",
    "coordinates": ["theta"],
    "parameters": {"m": 1.0, "g": 9.81, "l": 0.8, "F": 0.5},
    "gravity": [0, 0, "-g"],
    "rigid_bodies": [
        {
            "name": "rod",
            "mass": "m",
            "inertia": {"shape": "rod", "length": "l"},
            "position": [0, "l/2*sin(theta)", "-l/2*cos(theta)"],
            "rotations": [["x", "theta"]],
        }
    ],
    "forces": [{"at": "rod", "offset": [0, 0, "-l/2"], "force": [0, "F", 0]}],
}

MOTOR = {
    "name": "motor",
    "coordinates": ["a", "b"],
    "parameters": {"m": 1.0, "A1": 0.3, "C1": 0.5, "A2": 0.1, "C2": 0.2, "tau": 0.7},
    "rigid_bodies": [
        {
            "name": "stator",
            "mass": "m",
            "inertia": [["A1", 0, 0], [0, "A1", 0], [0, 0, "C1"]],
            "position": [0, 0, 0],
            "rotations": [["z", "a"]],
        },
        {
            "name": "rotor",
            "mass": "m",
            "inertia": [["A2", 0, 0], [0, "A2", 0], [0, 0, "C2"]],
            "position": [0, 0, 0],
            "parent": "stator",
            "rotations": [["z", "b"]],
        },
    ],
    "torques": [{"name": "drive", "body": "rotor", "by": "stator", "torque": [0, 0, "tau"]}],
}

PLANAR_MOTOR = {
    "name": "planar_motor",
    "coordinates": ["a", "b"],
    "parameters": {"m": 1.0, "C1": 0.5, "C2": 0.2, "tau": 0.7},
    "rigid_bodies": [
        {"name": "stator", "mass": "m", "inertia": "C1", "position": [0, 0], "angle": "a"},
        {"name": "rotor", "mass": "m", "inertia": "C2", "position": [0, 0], "angle": "b"},
    ],
    "torques": [{"body": "rotor", "by": "stator", "torque": "tau"}],
}

GIMBAL = {
    "name": "gimbal",
    "coordinates": ["psi", "theta"],
    "parameters": {"m": 1.0, "A1": 0.3, "C1": 0.5, "tau": 0.7, "Q0": 0.1},
    "generalized_forces": {"psi": "Q0"},
    "frames": [
        {"name": "heading", "rotations": [["z", "psi"]]},
        {"name": "tilt", "parent": "heading", "rotations": [["x", "theta"]]},
    ],
    "rigid_bodies": [
        {
            "name": "rotor",
            "mass": "m",
            "inertia": [["A1", 0, 0], [0, "A1", 0], [0, 0, "C1"]],
            "position": [0, 0, 0],
            "parent": "tilt",
        }
    ],
    "torques": [
        {"name": "lean", "frame": "tilt", "torque": ["tau", 0, 0]},
        {"name": "yaw", "frame": "heading", "torque": [0, 0, "tau"]},
    ],
}

#: A motor on a massless frame: the torque on the rotor, the reaction on the frame.
FRAME_MOTOR = {
    "name": "frame_motor",
    "coordinates": ["a", "b"],
    "parameters": {"m": 1.0, "A2": 0.1, "C2": 0.2, "tau": 0.7},
    "frames": [{"name": "cage", "rotations": [["z", "a"]]}],
    "rigid_bodies": [
        {
            "name": "rotor",
            "mass": "m",
            "inertia": [["A2", 0, 0], [0, "A2", 0], [0, 0, "C2"]],
            "position": [0, 0, 0],
            "parent": "cage",
            "rotations": [["z", "b"]],
        }
    ],
    "torques": [{"body": "rotor", "by": "cage", "torque": [0, 0, "tau"]}],
}

#: An upright coin (no lean) rolling on z = 0, pushed at its contact point.
COIN = {
    "name": "pushed_coin",
    "coordinates": ["x", "y", "psi", "phi"],
    "parameters": {"m": 1.0, "r": 0.3, "F_x": 0.5, "F_y": -0.2},
    "frames": [{"name": "heading", "rotations": [["z", "psi"]]}],
    "rigid_bodies": [
        {
            "name": "coin",
            "mass": "m",
            "inertia": {"shape": "disc", "radius": "r", "axis": "y"},
            "position": ["x", "y", "r"],
            "parent": "heading",
            "rotations": [["y", "phi"]],
        }
    ],
    "rolling": [{"body": "coin", "radius": "r"}],
    "forces": [{"name": "push", "at": "coin_contact", "force": ["F_x", "F_y", 0]}],
}

MODELS = {
    model["name"]: model for model in (ROD_TIP, ROD_TIP_3D, MOTOR, PLANAR_MOTOR, GIMBAL, COIN)
}
MODELS[FRAME_MOTOR["name"]] = FRAME_MOTOR


def _toml_value(value: Any) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + "}"
    return repr(value)


def as_toml(model: dict[str, Any]) -> str:
    """The model in TOML: lists of entries as arrays of tables, the rest as values."""
    head, tables = [], []
    for key, value in model.items():
        if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for entry in value:
                tables.append(f"\n[[{key}]]")
                tables += [f"{k} = {_toml_value(v)}" for k, v in entry.items()]
        else:
            head.append(f"{key} = {_toml_value(value)}")
    return "\n".join(head + tables) + "\n"


def written(model: dict[str, Any], fmt: str) -> str:
    if fmt == "yaml":
        return yaml.safe_dump(model, sort_keys=False)
    if fmt == "json":
        return json.dumps(model)
    return as_toml(model)


def load(model: dict[str, Any], fmt: str = "yaml") -> System:
    return loads(written(model, fmt), format=fmt, source=f"{model['name']}.{fmt}")


def residuals(system: System) -> list[sp.Expr]:
    return list(lg.derive(system).equations)


def same(first: list[sp.Expr], second: list[sp.Expr]) -> bool:
    return all(sp.simplify(p - q) == 0 for p, q in zip(first, second, strict=True))


FORMATS = ["yaml", "toml", "json"]


# -- a force at a body-fixed point --------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_force_at_the_tip_of_a_planar_rod(fmt: str) -> None:
    """F along x at the tip of a hanging rod of length l: Q = F l cos(theta) (the tip is at
    x = l sin(theta)), so (m l^2/3) theta_ddot + m g l/2 sin(theta) = F l cos(theta)."""
    system = load(ROD_TIP, fmt)
    (equation,) = residuals(system)
    hand = m * l**2 / 3 * ddot(theta) + m * g * l / 2 * sp.sin(theta) - F * l * sp.cos(theta)
    assert sp.simplify(equation - hand) == 0
    assert list(lg.derive(system).generalized_forces) == [F * l * sp.cos(theta)]


def test_a_force_at_a_planar_body_point_is_the_python_api() -> None:
    rod = RigidBody("rod", m, m * l**2 / 12, (l / 2 * sp.sin(theta), -l / 2 * sp.cos(theta)), theta)
    force, moment = force_at_point(rod, (0, -l / 2), (F, 0), name="push")
    by_hand = System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, l: 0.8, F: 0.5},
        gravity=(0, -g),
        rigid_bodies=[rod],
        forces=[force],
        torques=[moment],
        name="rod_tip",
    )
    assert load(ROD_TIP) == by_hand


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_force_at_the_tip_of_a_3d_rod(fmt: str) -> None:
    """The rod turned by theta about the world x axis, its tip at (0, l sin, -l cos): a force
    F along y there does Q = F l cos(theta); the equation is the planar rod's."""
    system = load(ROD_TIP_3D, fmt)
    (equation,) = residuals(system)
    hand = m * l**2 / 3 * ddot(theta) + m * g * l / 2 * sp.sin(theta) - F * l * sp.cos(theta)
    assert sp.simplify(equation - hand) == 0
    rod = next(body for body in system.rigid_bodies if body.name == "rod")  # R composed
    _, moment = force_at_point(rod, (0, 0, -l / 2), (0, F, 0))
    assert system.torques[0].torque == moment.torque


# -- a torque between two bodies ----------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_motor_between_rotor_and_stator_keeps_the_angular_momentum(fmt: str) -> None:
    """Stator turned by a, rotor by b relative to it (T = C1 a_dot^2/2 + C2 (a_dot +
    b_dot)^2/2): the motor's torque and its reaction do tau delta b only.  The a equation is
    d/dt of the total angular momentum (C1 + C2) a_dot + C2 b_dot = 0: it is conserved."""
    system = load(MOTOR, fmt)
    hand = [
        (C1 + C2) * ddot(a) + C2 * ddot(b),
        C2 * (ddot(a) + ddot(b)) - tau,
    ]
    assert same(residuals(system), hand)
    assert list(lg.derive(system).generalized_forces) == [0, tau]
    pair = torque_pair("rotor", "stator", (0, 0, tau), name="drive")
    api = load({**MOTOR, "torques": []}).replace(torques=list(pair))
    assert api == system
    assert same(residuals(api), residuals(system))
    assert [(t.body, t.name) for t in system.torques] == [
        ("rotor", "drive"),
        ("stator", "drive reaction"),
    ]
    # the analysis finds the same: a is cyclic and its momentum is conserved
    (cyclic, _) = cyclic_coordinates(system)
    assert cyclic.conserved and sp.expand(cyclic.momentum - (C1 + C2) * dot(a) - C2 * dot(b)) == 0


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_planar_motor_pair_leaves_the_total_angular_momentum_conserved(fmt: str) -> None:
    """Two wheels on one axle, angles a and b, the motor between them: C1 a_ddot = -tau,
    C2 b_ddot = tau; the sum is d/dt (C1 a_dot + C2 b_dot) = 0."""
    system = load(PLANAR_MOTOR, fmt)
    equations = residuals(system)
    assert same(equations, [C1 * ddot(a) + tau, C2 * ddot(b) - tau])
    momentum = C1 * dot(a) + C2 * dot(b)
    rate = sum(momentum.diff(dot(q)) * ddot(q) for q in (a, b))
    assert sp.expand(equations[0] + equations[1] - rate) == 0


def test_a_motor_on_a_massless_frame_puts_the_reaction_on_the_frame() -> None:
    """The rotor turns by b in a cage that turns by a: the drive does tau (a_dot + b_dot) on
    the rotor and -tau a_dot on the cage, so Q = (0, tau)."""
    system = load(FRAME_MOTOR)
    assert list(lg.derive(system).generalized_forces) == [0, tau]
    hand = [C2 * (ddot(a) + ddot(b)), C2 * (ddot(a) + ddot(b)) - tau]
    assert same(residuals(system), hand)
    # the Python API: the torque on the rotor, the reaction through frame_torque
    on_rotor, reaction = torque_pair("rotor", "cage", (0, 0, tau))
    plain = load({**FRAME_MOTOR, "torques": []})
    cage = plain.frames[0].orientation
    api = plain.replace(
        torques=[on_rotor], generalized_forces=frame_torque(cage, [a, b], reaction.torque)
    )
    assert same(residuals(api), residuals(system))


def test_a_steering_torque_between_fork_and_frame_drives_the_steer_angle_only() -> None:
    """The bicycle's chain of turns (yaw and lean frames, the rear frame pitched, the fork
    steered about the axis tilted back by lam): a torque T about the steer axis,
    u = R_rear (sin lam, 0, -cos lam) in world axes, by the rear frame on the fork does
    T delta steer and nothing else (Meijaard et al. 2007's steer torque)."""
    yaw, lean, pitch, lam, T = sp.symbols("yaw lean pitch lam T")
    rear = rotation_sequence([("z", yaw), ("x", lean), ("y", pitch)]).matrix
    axis = rear * sp.Matrix([sp.sin(lam), 0, -sp.cos(lam)])
    unit = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    model = {
        "coordinates": ["yaw", "lean", "pitch", "steer"],
        "parameters": {"lam": 0.3, "T": 1.0},
        "frames": [
            {"name": "yaw_frame", "rotations": [["z", "yaw"]]},
            {"name": "lean_frame", "parent": "yaw_frame", "rotations": [["x", "lean"]]},
        ],
        "rigid_bodies": [
            {
                "name": "rear_frame",
                "mass": 1,
                "inertia": [[2, 0, 0.3], [0, 3, 0], [0.3, 0, 1]],
                "position": [0, 0, 0],
                "parent": "lean_frame",
                "rotations": [["y", "pitch"]],
            },
            {
                "name": "fork",
                "mass": 1,
                "inertia": unit,
                "position": [0, 0, 0],
                "parent": "rear_frame",
                "rotations": [["y", "-lam"], ["z", "-steer"], ["y", "lam"]],
            },
        ],
        "torques": [{"body": "fork", "by": "rear_frame", "torque": [str(T * e) for e in axis]}],
    }
    forces = lg.derive(load({"name": "steer", **model})).generalized_forces
    assert [sp.simplify(q) for q in forces] == [0, 0, 0, T]


# -- a torque on a massless frame ---------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_torque_on_a_frame_gives_the_generalized_forces_of_its_rotation(fmt: str) -> None:
    """tau about the world x axis on the tilt frame (heading psi, then tilt theta about the
    heading's x axis): omega_s = psi_dot e_z + theta_dot (cos psi, sin psi, 0), so
    Q_theta = tau cos(psi); tau about z on the heading frame: Q_psi = tau, added to the
    file's own generalized force Q0."""
    system = load(GIMBAL, fmt)
    assert dict(system.generalized_forces) == {psi: Q0 + tau, theta: tau * sp.cos(psi)}
    tilt = next(f for f in system.frames if f.name == "tilt").orientation
    assert dict(frame_torque(tilt, [psi, theta], (tau, 0, 0))) == {theta: tau * sp.cos(psi)}


# -- a force at a rolling contact point ---------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_force_at_the_contact_point_of_an_upright_coin(fmt: str) -> None:
    """An upright coin (heading psi, spin phi about its axle y): the contact point's material
    velocity is v_C = (x_dot - r phi_dot cos psi, y_dot - r phi_dot sin psi, 0), so a push
    (F_x, F_y, 0) there does Q = (F_x, F_y, 0, -r (F_x cos psi + F_y sin psi))."""
    system = load(COIN, fmt)
    hand = [Fx, Fy, 0, -r * (Fx * sp.cos(psi) + Fy * sp.sin(psi))]
    ours = lg.derive(system).generalized_forces
    assert all(sp.simplify(q - h) == 0 for q, h in zip(ours, hand, strict=True))
    api = load({**COIN, "forces": []}).replace(forces=[Force("coin_contact", (Fx, Fy, 0), "push")])
    assert api == system


def test_a_named_contact_point_takes_forces_by_its_name() -> None:
    model = {**COIN, "rolling": [{"body": "coin", "radius": "r", "name": "tread"}]}
    model["forces"] = [{"at": "tread", "force": ["F_x", "F_y", 0]}]
    assert list(lg.derive(load(model)).generalized_forces) == list(
        lg.derive(load(COIN)).generalized_forces
    )


# -- the writer, the schema ---------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(MODELS))
@pytest.mark.parametrize("fmt", ["yaml", "json"])
def test_the_loads_survive_the_writer(name: str, fmt: str) -> None:
    """File -> System -> file -> System: the same System (its loads written as the forces,
    torques and generalized forces they become), the same equations and JSON."""
    first = load(MODELS[name])
    again = loads(dumps(first, format=fmt), format=fmt)
    assert again == first
    assert json.dumps(eom_document(lg.derive(first)), sort_keys=True) == json.dumps(
        eom_document(lg.derive(again)), sort_keys=True
    )


@pytest.mark.parametrize("name", sorted(MODELS))
def test_the_schema_accepts_every_form(name: str) -> None:
    jsonschema.Draft202012Validator(schema()).validate(MODELS[name])


def test_the_schema_wants_one_of_body_and_frame() -> None:
    validator = jsonschema.Draft202012Validator(schema())
    both = {**GIMBAL, "torques": [{"body": "rotor", "frame": "tilt", "torque": [0, 0, "tau"]}]}
    with pytest.raises(jsonschema.ValidationError, match=r"is valid under each of"):
        validator.validate(both)
    with pytest.raises(
        lg.errors.ModelError, match=r"exactly one of body, frame; found body and frame"
    ):
        load(both)


# -- bad input: exit code 2, the field and the fix ----------------------------------------

BAD = [
    (
        ROD_TIP,
        {"forces": [{"at": "rood", "offset": [0, 1], "force": ["F", 0]}]},
        r"forces\[0\]\.at .*unknown rigid body 'rood' — did you mean 'rod'\?",
    ),
    (
        ROD_TIP,
        {"forces": [{"at": "rod", "offset": [0, 0, 1], "force": ["F", 0]}]},
        r"forces\[0\]\.offset .*needs 2 components on a planar body, got 3 — give \[dx, dy\]",
    ),
    (
        ROD_TIP_3D,
        {"forces": [{"at": "rod", "offset": [0, 0, 1], "force": ["F", 0]}]},
        r"forces\[0\]\.force .*needs 3 components on a 3-D body, got 2",
    ),
    (
        ROD_TIP,
        {"forces": [{"at": "origin", "offset": [0, 1], "force": ["F", 0]}]},
        r"forces\[0\]\.at .*'origin' is not a rigid body .*leave out offset",
    ),
    (
        ROD_TIP,
        {"forces": [{"at": [0, 1], "offset": [0, 1], "force": ["F", 0]}]},
        r"forces\[0\]\.at .*acts at a point of a rigid body",
    ),
    (
        MOTOR,
        {"torques": [{"body": "rotor", "by": "rotor", "torque": [0, 0, "tau"]}]},
        r"torques\[0\]\.by .*needs two bodies or frames, got 'rotor' twice",
    ),
    (
        MOTOR,
        {"torques": [{"body": "rotor", "by": "statr", "torque": [0, 0, "tau"]}]},
        r"torques\[0\]\.by .*unknown rigid body or frame 'statr' — did you mean 'stator'\?",
    ),
    (
        MOTOR,
        {"torques": [{"body": "rotr", "by": "stator", "torque": [0, 0, "tau"]}]},
        r"torques\[0\]\.body .*unknown rigid body 'rotr' — did you mean 'rotor'\?",
    ),
    (
        MOTOR,
        {"torques": [{"body": "rotor", "by": "stator", "torque": [0, "tau"]}]},
        r"torques\[0\]\.torque .*3 components — give \[tau_x, tau_y, tau_z\]",
    ),
    (
        PLANAR_MOTOR,
        {"torques": [{"body": "rotor", "by": "stator", "torque": [0, 0, "tau"]}]},
        r"torques\[0\]\.torque .*a torque on a planar body is a scalar",
    ),
    (
        GIMBAL,
        {"torques": [{"frame": "tlit", "torque": ["tau", 0, 0]}]},
        r"torques\[0\]\.frame .*unknown frame 'tlit' — did you mean 'tilt'\?",
    ),
    (
        GIMBAL,
        {"torques": [{"frame": "rotor", "torque": ["tau", 0, 0]}]},
        r"torques\[0\]\.frame .*'rotor' is a rigid body — write body: rotor",
    ),
    (
        GIMBAL,
        {"torques": [{"body": "tilt", "torque": ["tau", 0, 0]}]},
        r"torques\[0\]\.body .*'tilt' is a frame — write frame: tilt",
    ),
    (
        GIMBAL,
        {"torques": [{"frame": "tilt", "torque": "tau"}]},
        r"torques\[0\]\.torque .*a torque on a 3-D body or a frame has 3 components",
    ),
    (
        GIMBAL,
        {"torques": [{"torque": ["tau", 0, 0]}]},
        r"torques\[0\] .*exactly one of body, frame; found none",
    ),
    (
        COIN,
        {"forces": [{"at": "coin_contct", "force": ["F_x", 0, 0]}]},
        r"forces\[0\]\.at .*unknown point 'coin_contct' — did you mean 'coin_contact'\?",
    ),
    (
        COIN,
        {"forces": [{"at": "heading", "force": ["F_x", 0, 0]}]},
        r"forces\[0\]\.at .*the frame 'heading' is a frame — a frame has no position",
    ),
]


@pytest.mark.parametrize(("model", "change", "match"), BAD)
def test_bad_loads_exit_2_naming_the_field(
    model: dict[str, Any], change: dict[str, Any], match: str, capsys, monkeypatch
) -> None:
    text = yaml.safe_dump({**model, **change}, sort_keys=False)
    monkeypatch.setattr("sys.stdin", io.StringIO(text))
    code = main(["derive", "-"])
    error = capsys.readouterr().err
    assert code == 2
    assert re.search(match, error), error
    assert "(line " in error  # located in the text


def test_a_bad_load_is_a_model_error_with_problems() -> None:
    bad = {**MOTOR, "torques": [{"body": "rotor", "by": "rotor", "torque": [0, 0, "tau"]}]}
    with pytest.raises(lg.errors.ModelError) as caught:
        load(bad)
    (problem,) = caught.value.problems
    assert problem.field == "torques[0].by" and problem.fix and problem.line is not None


def test_the_python_api_and_the_file_agree_on_the_rolling_coin_shapes() -> None:
    """The file's coin is the System built by hand (frames, the disc shape, rolling)."""
    coin = RigidBody(
        "coin",
        m,
        shape("disc", axis="y", radius=r),
        (x, y, r),
        parent="heading",
        rotations=[("y", phi)],
    )
    by_hand = System(
        coordinates=[x, y, psi, phi],
        parameters={m: 1.0, r: 0.3, Fx: 0.5, Fy: -0.2},
        frames=[Frame("heading", [("z", psi)])],
        rigid_bodies=[coin],
        rolling=[RollingDisc("coin", r)],
        forces=[Force("coin_contact", (Fx, Fy, 0), "push")],
        name="pushed_coin",
    )
    assert load(COIN) == by_hand
