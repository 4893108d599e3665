"""Model files in YAML, TOML and JSON load to the same System as one built by hand, and bad
files get one ModelError naming every problem with its field, line and column."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ExpressionError, ModelError, Problem
from lagrangian.io import load, loads

theta1, theta2 = sp.symbols("theta1 theta2")
m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")

PENDULUM_YAML = """\
name: Double pendulum
description: Two bobs on massless rods.
coordinates: [theta1, theta2]
parameters: {m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81}
gravity: [0, -g]
particles:
  - {name: bob1, mass: m1, position: ["l1*sin(theta1)", "-l1*cos(theta1)"]}
  - name: bob2
    mass: m2
    position:
      - l1*sin(theta1) + l2*sin(theta2)
      - -l1*cos(theta1) - l2*cos(theta2)
initial: {theta1: 1.0, theta2: 0.0, theta1_dot: 0.0, theta2_dot: 0.0}
simulate: {t_end: 20, method: RK45, rtol: 1e-8, atol: 1e-10, samples: 1000}
"""

PENDULUM_TOML = """\
name = "Double pendulum"
description = "Two bobs on massless rods."
coordinates = ["theta1", "theta2"]
gravity = [0, "-g"]

[parameters]
m1 = 1.0
m2 = 1.0
l1 = 1.0
l2 = 1.0
g = 9.81

[[particles]]
name = "bob1"
mass = "m1"
position = ["l1*sin(theta1)", "-l1*cos(theta1)"]

[[particles]]
name = "bob2"
mass = "m2"
position = [
    "l1*sin(theta1) + l2*sin(theta2)",
    "-l1*cos(theta1) - l2*cos(theta2)",
]

[initial]
theta1 = 1.0
theta2 = 0.0
theta1_dot = 0.0
theta2_dot = 0.0

[simulate]
t_end = 20
method = "RK45"
rtol = 1e-8
atol = 1e-10
samples = 1000
"""

PENDULUM_JSON = """\
{
  "name": "Double pendulum",
  "description": "Two bobs on massless rods.",
  "coordinates": ["theta1", "theta2"],
  "parameters": {"m1": 1.0, "m2": 1.0, "l1": 1.0, "l2": 1.0, "g": 9.81},
  "gravity": [0, "-g"],
  "particles": [
    {"name": "bob1", "mass": "m1", "position": ["l1*sin(theta1)", "-l1*cos(theta1)"]},
    {"name": "bob2", "mass": "m2",
     "position": ["l1*sin(theta1) + l2*sin(theta2)", "-l1*cos(theta1) - l2*cos(theta2)"]}
  ],
  "initial": {"theta1": 1.0, "theta2": 0.0, "theta1_dot": 0.0, "theta2_dot": 0.0},
  "simulate": {"t_end": 20, "method": "RK45", "rtol": 1e-8, "atol": 1e-10, "samples": 1000}
}
"""

PENDULUMS = {"yaml": PENDULUM_YAML, "toml": PENDULUM_TOML, "json": PENDULUM_JSON}


def double_pendulum() -> lg.System:
    """The same double pendulum, built with the Python API."""
    bob1 = (l1 * sp.sin(theta1), -l1 * sp.cos(theta1))
    bob2 = (bob1[0] + l2 * sp.sin(theta2), bob1[1] - l2 * sp.cos(theta2))
    return lg.System(
        name="Double pendulum",
        description="Two bobs on massless rods.",
        coordinates=[theta1, theta2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob1", m1, bob1), lg.Particle("bob2", m2, bob2)],
        initial={theta1: 1.0, theta2: 0.0, lg.velocity(theta1): 0.0, lg.velocity(theta2): 0.0},
        simulation={"t_end": 20, "method": "RK45", "rtol": 1e-8, "atol": 1e-10, "samples": 1000},
    )


def refused(text: str, match: str, *, format: str = "yaml") -> tuple[Problem, ...]:
    """The problems of a model text that must not load."""
    with pytest.raises(ModelError, match=match) as caught:
        loads(textwrap.dedent(text), format=format, source="model")
    assert all(p.source == "model" and p.fix for p in caught.value.problems)
    return caught.value.problems


def where(problem: Problem) -> tuple[str, int | None, int | None]:
    return (problem.field, problem.line, problem.column)


# -- the same model in three formats ------------------------------------------------------
@pytest.mark.parametrize("format", ["yaml", "toml", "json"])
def test_every_format_gives_the_hand_built_system(format: str) -> None:
    assert loads(PENDULUMS[format], format=format) == double_pendulum()


def test_the_loaded_system_derives_the_hand_built_equations() -> None:
    loaded = lg.derive(loads(PENDULUM_YAML)).equations
    assert sp.simplify(loaded - lg.derive(double_pendulum()).equations) == sp.zeros(2, 1)


@pytest.mark.parametrize("format", ["yaml", "toml", "json"])
def test_round_trip_through_a_file(tmp_path: Path, format: str) -> None:
    path = tmp_path / f"pendulum.{format}"
    path.write_text(PENDULUMS[format], encoding="utf-8")
    assert load(path) == double_pendulum()
    assert load(str(path)) == double_pendulum()


def test_text_is_recognised_as_json_or_yaml() -> None:
    assert loads(PENDULUM_JSON) == loads(PENDULUM_YAML) == double_pendulum()
    assert loads(PENDULUM_TOML, format="toml") == double_pendulum()


def test_load_never_takes_text_for_a_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for text in (PENDULUM_JSON, PENDULUM_YAML, "coordinates: [x]"):
        with pytest.raises(ModelError, match=r"lagrangian\.loads"):
            load(text)
    with pytest.raises(ModelError, match="not int"):
        load(5)  # type: ignore[arg-type]
    with pytest.raises(ModelError, match="not NoneType"):
        loads(None)  # type: ignore[arg-type]


def test_text_naming_a_file_is_read_as_text_and_the_file_is_never_quoted(
    tmp_path: Path,
) -> None:
    secret = tmp_path / "shadow"
    secret.write_text("root:$6$very-secret-hash:19000:0:99999:7:::\n", encoding="utf-8")
    with pytest.raises(ModelError) as refused:
        loads(str(secret))  # untrusted text that happens to be a path
    assert "very-secret-hash" not in str(refused.value)


def test_the_name_defaults_to_the_file_stem(tmp_path: Path) -> None:
    path = tmp_path / "spring.model"
    path.write_text("coordinates = ['x']\nkinetic = 'x_dot**2/2'\n", encoding="utf-8")
    system = load(path, format="toml")
    assert (system.name, system.kinetic) == ("spring", sp.Symbol("x_dot") ** 2 / 2)
    assert loads("coordinates: [x]").name == ""


def test_a_missing_file_is_not_read_as_text(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"nowhere\.yaml"):
        load(str(tmp_path / "nowhere.yaml"))


# -- every section ------------------------------------------------------------------------
def test_bodies_springs_dampers_forces_and_torques() -> None:
    system = loads(
        textwrap.dedent("""\
        coordinates: [x, theta]
        parameters: {M: 2, m: 0.5, l: 1, g: 9.81, k: 10, b: 0.1, F: 1, tau: 0.2, x0: null}
        gravity: [0, -g]
        particles:
          - {name: cart, mass: M, position: [x, 0]}
        rigid_bodies:
          - name: rod
            mass: m
            inertia: m*l**2/12
            position: ["x + l/2*sin(theta)", "-l/2*cos(theta)"]
            angle: theta
        springs:
          - {name: wall, between: [cart, [x0, 0]], stiffness: k, rest_length: 0.5}
          - {between: [rod, cart], stiffness: 2.5}
        dampers: [{between: [cart, origin], coefficient: b}]
        forces:
          - {at: rod, force: [F, 0]}
          - {name: drag, at: [x, 0], force: ["-b*x_dot", 0]}
        torques: [{body: rod, torque: tau}]
        """)
    )
    x, theta, big_m, m, l, k, b, big_f, tau, x0 = sp.symbols("x theta M m l k b F tau x0")
    rod = lg.RigidBody(
        "rod", m, m * l**2 / 12, (x + l / 2 * sp.sin(theta), -l / 2 * sp.cos(theta)), theta
    )
    expected = lg.System(
        coordinates=[x, theta],
        parameters={big_m: 2, m: 0.5, l: 1, g: 9.81, k: 10, b: 0.1, big_f: 1, tau: 0.2, x0: None},
        gravity=(0, -g),
        particles=[lg.Particle("cart", big_m, (x, 0))],
        rigid_bodies=[rod],
        springs=[
            lg.Spring(("cart", (x0, 0)), k, sp.Rational(1, 2), name="wall"),
            lg.Spring(("rod", "cart"), sp.Rational(5, 2)),
        ],
        dampers=[lg.Damper(("cart", "origin"), b)],
        forces=[
            lg.Force("rod", (big_f, 0)),
            lg.Force((x, 0), (-b * sp.Symbol("x_dot"), 0), "drag"),
        ],
        torques=[lg.Torque("rod", tau)],
    )
    assert system == expected


def test_circuit_sections_in_system_order() -> None:
    system = loads(
        textwrap.dedent("""\
        coordinates = ["q1", "q2", "q3"]
        parameters = {L1 = 1, L2 = 1, LM = 0.5, C = 1, R = 2, u0 = 1, w = 3, J = 1}
        kinetic = "J*q3_dot**2/2"

        [circuit]
        inductors = [{name = "L1", inductance = "L1", current = "q1_dot"},
                     {inductance = "L2", current = "q2_dot"}]
        mutual = [{inductance = "LM*cos(q3)", currents = ["q1_dot", "q2_dot"]}]
        capacitors = [{capacitance = "C", charge = "q1 - q2"}]
        resistors = [{resistance = "R", current = "q1_dot - q2_dot"}]
        sources = [{voltage = "u0*sin(w*t)", coordinate = "q1"}]
        """),
        format="toml",
    )
    q1, q2, q3, q1d, q2d, q3d = sp.symbols("q1 q2 q3 q1_dot q2_dot q3_dot")
    big_l1, big_l2, lm, c, r, u0, w, j = sp.symbols("L1 L2 LM C R u0 w J")
    assert system.circuit == (
        lg.Inductor(big_l1, q1d, "L1"),
        lg.Inductor(big_l2, q2d),
        lg.MutualInductance(lm * sp.cos(q3), (q1d, q2d)),
        lg.Capacitor(c, q1 - q2),
        lg.Resistor(r, q1d - q2d),
        lg.VoltageSource(u0 * sp.sin(w * lg.t), q1),
    )
    assert system.kinetic == j * q3d**2 / 2


def test_energies_dissipation_and_time_dependent_forces() -> None:
    system = loads(
        textwrap.dedent("""\
        {"coordinates": ["x", "y"],
         "parameters": {"m": 1, "e": 1, "B": 2, "c": 0.25, "tau0": 1, "w": 1, "k": 3},
         "kinetic": "m*(x_dot**2 + y_dot**2)/2",
         "potential": "k*(x**2 + y**2)/2",
         "velocity_potential": "-e*B*(x*y_dot - y*x_dot)/2",
         "dissipation": "c*(x_dot**2 + y_dot**2)/2",
         "lagrangian": "x*y_dot - y*x_dot",
         "generalized_forces": {"x": "tau0*cos(w*t + pi/2)", "y": "E"}}
        """),
        format="json",
    )
    x, y, xd, yd, m, e, big_b, c, tau0, w, k = sp.symbols("x y x_dot y_dot m e B c tau0 w k")
    assert system.velocity_potential == -e * big_b * (x * yd - y * xd) / 2
    assert system.dissipation == c * (xd**2 + yd**2) / 2
    assert system.lagrangian == x * yd - y * xd
    assert system.generalized_forces == {x: -tau0 * sp.sin(w * lg.t), y: sp.E}
    eom = lg.derive(system)
    assert sp.expand(eom.equations[0]) == sp.expand(
        m * sp.Symbol("x_ddot") - e * big_b * yd - 2 * yd + c * xd + k * x + tau0 * sp.sin(w * lg.t)
    )


# -- bad files: every problem named with field, line and column ---------------------------
def test_unknown_section_with_a_suggestion() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        partcles: []
        """,
        r"partcles \(line 2, column 1\): unknown section 'partcles' — did you mean 'particles'\?",
    )
    assert where(problem) == ("partcles", 2, 1)


def test_unknown_key_in_an_entry_with_a_suggestion() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        parameters: {k: 1}
        particles: [{name: a, mass: 1, position: [x]}]
        springs:
          - between: [a, origin]
            stifness: k
        """,
        r"unknown key 'stifness' — did you mean 'stiffness'\?",
    )
    assert where(problem) == ("springs[0].stifness", 6, 5)


def test_a_list_where_a_mapping_is_expected() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        parameters: [m, k]
        """,
        r"parameters \(line 2, column 13\): must be a mapping of keys to values, got a list",
    )
    assert where(problem) == ("parameters", 2, 13)


def test_a_position_that_is_not_a_list() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        particles:
          - {name: a, mass: 1, position: "x"}
        """,
        r"must be a list of expressions, got 'x'",
    )
    assert where(problem) == ("particles[0].position", 3, 35)


def test_a_parameter_value_that_is_not_a_number() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        parameters:
          m: heavy
        kinetic: m*x_dot**2/2
        """,
        r"parameters\.m \(line 3, column 6\): value 'heavy' is not a number",
    )
    assert where(problem) == ("parameters.m", 3, 6)


def test_a_coordinate_listed_twice() -> None:
    (problem,) = refused("coordinates: [x, y, x]\n", r"coordinate 'x' is listed twice")
    assert where(problem) == ("coordinates[2]", 1, 21)


def test_a_name_that_is_a_coordinate_and_a_parameter() -> None:
    (problem,) = refused(
        "coordinates: [x]\nparameters: {m: 1, x: 2}\n",
        r"'x' is both a coordinate and a parameter",
    )
    assert where(problem) == ("parameters.x", 2, 20)


def test_two_bodies_with_one_name() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        particles:
          - {name: a, mass: 1, position: [x, 0]}
        rigid_bodies:
          - {name: a, mass: 1, inertia: 1, position: [x, 0], angle: x}
        """,
        r"rigid_bodies\[0\]\.name .*: name 'a' is taken \(by particles\[0\]\)",
    )
    assert where(problem) == ("rigid_bodies[0].name", 5, 12)


def test_an_unknown_name_in_an_expression() -> None:
    (problem,) = refused(
        """\
        coordinates: [theta]
        parameters: {m: 1, l: 1, g: 9.81}
        potential: "-m*gg*l*cos(theta)"
        """,
        r"potential \(line 3, column 16\): unknown name 'gg' — did you mean 'g'\?",
    )
    assert where(problem) == ("potential", 3, 16)


def test_disallowed_syntax_is_refused_without_evaluation() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        kinetic: "x_dot.__class__"
        """,
        r"kinetic .*: attribute access is not allowed",
    )
    assert where(problem) == ("kinetic", 2, 11)


def test_a_particle_without_mass() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        particles:
          - name: a
            position: [x]
        """,
        r"particles\[0\] \(line 3, column 5\): missing required key 'mass'",
    )
    assert where(problem) == ("particles[0]", 3, 5)


def test_empty_coordinates() -> None:
    (problem,) = refused("coordinates: []\n", r"no generalized coordinates")
    assert where(problem) == ("coordinates", 1, 14)


def test_missing_coordinates() -> None:
    (problem,) = refused("kinetic: 1\n", r"missing required section 'coordinates'")
    assert where(problem) == ("coordinates", 1, None)


def test_yaml_duplicate_keys_are_reported() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        parameters:
          k: 1
          k: 2
        """,
        r"duplicate key 'k' \(first given on line 3\)",
    )
    assert where(problem) == ("parameters.k", 4, 3)


def test_constraints_load_as_declarations() -> None:
    system = loads(
        """\
        coordinates: [x, y, phi]
        parameters: {l: 1}
        constraints:
          - {name: rod, holonomic: "x**2 + y**2 - l**2"}
          - {velocity: "x_dot*sin(phi) - y_dot*cos(phi)"}
          - {unilateral: "y + 2"}
        """
    )
    x, y, phi, l = sp.symbols("x y phi l")
    x_dot, y_dot = sp.symbols("x_dot y_dot")
    assert system.constraints == (
        lg.Holonomic(x**2 + y**2 - l**2, name="rod"),
        lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi)),
        lg.Unilateral(y + 2),
    )


def test_constraints_are_written_back_by_dump() -> None:
    from lagrangian.io.dump import dumps

    text = """\
        name: knife
        coordinates: [x, y, phi]
        parameters: {l: 1.0}
        constraints:
          - {name: rod, holonomic: "x**2 + y**2 - l**2"}
          - {velocity: "x_dot*sin(phi) - y_dot*cos(phi)"}
          - {unilateral: "y + 2"}
        """
    system = loads(textwrap.dedent(text))
    assert loads(dumps(system)) == system
    assert "- {name: rod, holonomic: x**2 + y**2 - l**2}" in dumps(system)


def test_bad_constraint_entries_are_refused_at_their_place() -> None:
    problems = refused(
        """\
        coordinates: [x, y]
        constraints:
          - {holonmic: "x"}
          - {holonomic: "x", velocity: "y_dot"}
          - {unilateral: "zz"}
        """,
        r"unknown key 'holonmic'",
    )
    assert [where(p) for p in problems] == [
        ("constraints[0].holonmic", 3, 6),
        ("constraints[1]", 4, 5),
        ("constraints[2].unilateral", 5, 19),
    ]
    assert "exactly one of holonomic, velocity, unilateral" in problems[1].message


def test_ill_formed_constraints_are_refused_by_the_system_at_their_place() -> None:
    problems = refused(
        """\
        coordinates: [x, y]
        parameters: {l: 1}
        constraints:
          - {holonomic: "x_dot"}
          - {velocity: "x_dot**2", name: v}
          - {holonomic: "l - 1"}
          - {velocity: "x"}
        """,
        r"not linear in the velocities",
    )
    assert [where(p) for p in problems] == [
        ("constraints[0].holonomic", 4, 18),
        ("constraints[1].velocity", 5, 17),
        ("constraints[2].holonomic", 6, 18),
        ("constraints[3].velocity", 7, 17),
    ]
    messages = [p.message for p in problems]
    assert "uses the velocity x_dot" in messages[0]
    assert "constraint 'v' (x_dot**2 = 0)" in messages[1]
    assert "involves no coordinate" in messages[2]
    assert "uses no velocity" in messages[3]


def test_duplicate_constraint_names_are_refused_at_the_name() -> None:
    (problem,) = refused(
        """\
        coordinates: [x, y]
        constraints:
          - {holonomic: x, name: a}
          - {name: a, holonomic: y}
        """,
        r"name 'a' is taken by constraints\[0\]",
    )
    assert where(problem) == ("constraints[1].name", 4, 12)


def test_all_problems_of_a_file_at_once() -> None:
    problems = refused(
        """\
        coordinates: [x, x]
        parameters: {m: heavy, k: 1}
        kinetic: m*x_dot**2/2 + kk
        partcles: []
        springs:
          - {between: [a, origin], stifness: k}
        simulate: {t_end: -1, samples: 2.5}
        """,
        r"model is not a valid model file \(7 problems\)",
    )
    assert [where(p) for p in problems] == [
        ("coordinates[1]", 1, 18),
        ("parameters.m", 2, 17),
        ("kinetic", 3, 25),
        ("partcles", 4, 1),
        ("springs[0].stifness", 6, 28),
        ("simulate.t_end", 7, 19),
        ("simulate.samples", 7, 32),
    ]


def test_only_expression_problems_raise_an_expression_error() -> None:
    with pytest.raises(ExpressionError, match=r"kinetic .*: '\^' is not a power"):
        loads("coordinates: [x]\nkinetic: x_dot^2\n")


# -- problems found by the System, placed in the file --------------------------------------
def test_a_velocity_in_a_potential_points_into_the_file() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        parameters: {b: 1}
        potential: "b*x*x_dot"
        """,
        r"potential \(line 3, column 13\): the velocity x_dot may not appear here",
    )
    assert where(problem) == ("potential", 3, 13)


def test_an_unknown_point_points_into_the_file() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        particles: [{name: bob, mass: 1, position: [x]}]
        springs: [{between: [bob, bobb], stiffness: 1}]
        """,
        r"unknown point 'bobb' — did you mean 'bob'\?",
    )
    assert where(problem) == ("springs[0].between[1]", 3, 27)


def test_circuit_problems_name_the_circuit_section() -> None:
    (problem,) = refused(
        """\
        coordinates: [q1, q2]
        circuit:
          inductors: [{inductance: 1, current: q1_dot}]
          capacitors:
            - {capacitance: 1, charge: q1}
            - {capacitance: 1, charge: "q2 + q1_dot"}
        """,
        r"circuit\.capacitors\[1\]\.charge .*: the velocity q1_dot may not appear",
    )
    assert where(problem) == ("circuit.capacitors[1].charge", 6, 33)


def test_inconsistent_dimensions_have_no_single_place() -> None:
    (problem,) = refused(
        """\
        coordinates: [x]
        particles:
          - {name: a, mass: 1, position: [x, 0]}
          - {name: b, mass: 1, position: [x, 0, 0]}
        """,
        r"positions: inconsistent dimensions",
    )
    assert where(problem) == ("positions", None, None)


def test_time_as_a_coordinate_points_at_the_coordinate() -> None:
    (problem,) = refused("coordinates: [x, t]\n", r"coordinates\[1\] .*: t is time")
    assert where(problem) == ("coordinates[1]", 1, 18)


# -- more bad values ----------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "match", "place"),
    [
        (
            "coordinates: [theta]\ngeneralized_forces: {thta: 1}\n",
            r"unknown coordinate 'thta' — did you mean 'theta'\?",
            ("generalized_forces.thta", 2, 22),
        ),
        (
            "coordinates: [x]\ninitial: {x_dt: 1}\n",
            r"'x_dt' is not a coordinate or a velocity — did you mean 'x_dot'\?",
            ("initial.x_dt", 2, 11),
        ),
        (
            "coordinates: [x]\ninitial: {x: fast}\n",
            r"value 'fast' is not a number",
            ("initial.x", 2, 14),
        ),
        (
            "coordinates: [x]\nsimulate: {method: 45}\n",
            r"simulate\.method .*: must be text, got 45",
            ("simulate.method", 2, 20),
        ),
        (
            "coordinates: [charge]\ncircuit: {sources: [{voltage: 1, coordinate: chrge}]}\n",
            r"'chrge' is not a coordinate — did you mean 'charge'\? name one of the coordinates",
            ("circuit.sources[0].coordinate", 2, 46),
        ),
        (
            "coordinates: [q]\ncircuit: {mutual: [{inductance: 1, currents: [q_dot]}]}\n",
            r"needs two currents, got 1",
            ("circuit.mutual[0].currents", 2, 46),
        ),
        (
            "coordinates: [x]\nsprings: [{between: [origin], stiffness: 1}]\n",
            r"needs two points, got 1",
            ("springs[0].between", 2, 21),
        ),
        (
            "coordinates: [x]\nforces: [{at: 3, force: [1]}]\n",
            r"must be a point, got 3",
            ("forces[0].at", 2, 15),
        ),
        (
            "coordinates: [x]\nkinetic: [x_dot]\n",
            r"expected an expression \(text or a number\), got a list",
            ("kinetic", 2, 10),
        ),
        (
            "coordinates: [x, 2y]\n",
            r"'2y' is not a name",
            ("coordinates[1]", 1, 18),
        ),
        ("- x\n- y\n", r"a model is a mapping of sections, got a list", ("(top level)", 1, 1)),
        ("# nothing\n", r"the model is empty", ("(top level)", None, None)),
    ],
)
def test_bad_values(text: str, match: str, place: tuple[str, int, int]) -> None:
    (problem,) = refused(text, match)
    assert where(problem) == place


# -- TOML and JSON positions, syntax errors ------------------------------------------------
def test_toml_problems_point_at_keys_and_values() -> None:
    problems = refused(
        """\
        coordinates = ["x"]

        [parameters]
        k = "stiff"

        [[springs]]
        between = ["origin", ["x", 0]]
        stiffness = "k*y"
        dampng = 1
        """,
        r"3 problems",
        format="toml",
    )
    assert [where(p) for p in problems] == [
        ("parameters.k", 4, 6),
        ("springs[0].stiffness", 8, 16),
        ("springs[0].dampng", 9, 1),
    ]


def test_json_problems_point_at_values() -> None:
    (problem,) = refused(
        """\
        {
          "coordinates": ["x"],
          "kinetic": "m*x_dot**2/2"
        }
        """,
        r"kinetic \(line 3, column 15\): unknown name 'm'",
        format="json",
    )
    assert where(problem) == ("kinetic", 3, 15)


@pytest.mark.parametrize(
    ("format", "text", "match", "place"),
    [
        ("yaml", "coordinates: [x\nkinetic: 1\n", r"not valid YAML", (2, 8)),
        ("toml", 'coordinates = ["x"\nkinetic = 1\n', r"not valid TOML", (2, 1)),
        ("json", '{"coordinates": ["x"],\n "kinetic": }', r"not valid JSON", (2, 13)),
    ],
)
def test_syntax_errors_name_line_and_column(
    format: str, text: str, match: str, place: tuple[int, int]
) -> None:
    (problem,) = refused(text, match, format=format)
    assert (problem.field, problem.line, problem.column) == ("syntax", *place)


def test_an_unknown_format_is_refused() -> None:
    with pytest.raises(ModelError, match=r"unknown format 'xml' — use one of yaml, toml, json"):
        loads("coordinates: [x]", format="xml")


def test_a_parameter_named_like_a_velocity_points_at_its_key() -> None:
    (problem,) = refused(
        "coordinates: [x]\nparameters: {k: 1, x_dot: 2}\n",
        r"parameters\.x_dot .*: clashes with a velocity name",
    )
    assert where(problem) == ("parameters.x_dot", 2, 20)
