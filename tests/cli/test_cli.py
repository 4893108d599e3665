"""The lagrangian command, run in-process through its entry point (exit codes, output)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import cyclic_coordinates
from lagrangian.cli.main import exit_code, main

EXAMPLES = [n for n in lg.examples.names() if n != "n_link_pendulum"]


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_derives_as_json_following_the_contract(
    capsys: pytest.CaptureFixture[str], name: str
) -> None:
    code, out, err = run(capsys, "derive", f"examples/{name}", "--format", "json")
    assert code == 0, err
    document = json.loads(out)
    for key in (
        "coordinates",
        "parameters",
        "lagrangian",
        "equations",
        "mass_matrix",
        "forcing",
        "coriolis",
        "potential_forces",
        "gravity",
        "generalized_forces",
        "dissipation_forces",
    ):
        assert key in document
    eom = lg.derive(lg.examples.get(name)())
    # Parseable strings (docs/architecture.md); names such as I or LM must be declared as
    # symbols, since SymPy's own namespace uses them.
    names = [
        *document["coordinates"],
        *document["velocities"],
        *document["accelerations"],
        *document["parameters"],
        "t",
    ]
    local = {name: sp.Symbol(name) for name in names}
    parsed = [sp.parse_expr(e, local_dict=local) for e in document["equations"]]
    assert all(sp.expand(a - b) == 0 for a, b in zip(parsed, eom.equations, strict=True))
    assert document["coordinates"] == [q.name for q in eom.coordinates]


def test_a_capacitors_force_is_a_potential_force_not_gravity(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # The charge on a capacitor: V = q^2/(2C), so dV/dq = q/C (the inverse capacitance law).
    code, out, _ = run(capsys, "derive", "examples/series_rlc", "--format", "json")
    document = json.loads(out)
    assert code == 0 and document["potential_forces"] == ["q/C"]
    assert document["gravity"] == document["potential_forces"]  # the old name, one release
    code, out, _ = run(capsys, "derive", "examples/series_rlc", "--matrix")
    assert code == 0 and "potential_forces G = ∂V/∂q =" in out and "gravity" not in out


def test_steps_text_for_the_double_pendulum(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "derive", "examples/double_pendulum", "--steps")
    assert code == 0
    assert "∂L/∂θ̇ = " in out and "d/dt(∂L/∂φ̇) = " in out
    assert out.count("⇒ ") == 2


def test_latex_and_matrix_outputs(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "derive", "examples/robot_arm", "--format", "latex", "--steps")
    assert code == 0 and r"\frac{\partial L}{\partial \dot{\theta}}" in out
    code, out, _ = run(capsys, "derive", "examples/robot_arm", "--matrix")
    assert (code == 0 and "M =" in out) or "mass matrix" in out.lower()


def test_set_overrides_a_parameter(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(
        capsys, "derive", "examples/simple_pendulum", "--format", "json", "--set", "m=2.5"
    )
    assert code == 0 and json.loads(out)["parameters"]["m"] == 2.5


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["derive", "examples/double_pendulm"], "Did you mean double_pendulum"),
        (["derive", "examples/simple_pendulum", "--set", "mass=2"], "'mass' is not a parameter"),
        (["derive", "examples/simple_pendulum", "--set", "m=heavy"], "expected NAME=NUMBER"),
        (["examples", "nothing_like_this"], "There is no example named"),
    ],
)
def test_bad_input_exits_2_without_traceback(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert message in err and "Traceback" not in err


def test_bad_usage_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit, match="2"):
        main(["derive", "examples/simple_pendulum", "--format", "pdf"])


def test_debug_shows_the_traceback(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "derive", "examples/nope", "--debug")
    assert code == 2 and "Traceback" in err


def test_examples_lists_and_describes(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "examples")
    listed = [line.split()[0] for line in out.splitlines()]
    assert code == 0 and listed == [*lg.examples.names(), *lg.examples.BENCHMARKS]
    assert "whipple_bicycle" in listed  # the field's benchmarks after the course examples
    code, out, _ = run(capsys, "examples", "atwood_machine")
    assert code == 0 and "name: atwood_machine" in out


def test_export_writes_files(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    code, out, _ = run(
        capsys, "export", "examples/double_pendulum", "--language", "c", "--out", str(tmp_path)
    )
    assert code == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["double_pendulum.c", "double_pendulum.h"]
    code, out, _ = run(capsys, "export", "examples/simple_pendulum")
    assert code == 0 and "def rhs(" in out


@pytest.mark.parametrize("name", lg.examples.names())
def test_every_example_simulates_to_csv(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, name: str
) -> None:
    out = tmp_path / "trajectory.csv"
    code, _, err = run(capsys, "simulate", f"examples/{name}", "--samples", "20", "--out", str(out))
    assert code == 0, err
    header, *rows = out.read_text().splitlines()
    system = lg.examples.get(name)()
    expected = [
        "t",
        *(q.name for q in system.coordinates),
        *(v.name for v in system.velocities),
        *(f"lambda_{j + 1}" for j in range(len(system.constraints))),
        "energy",
    ]
    columns = header.split(",")
    # h = sum q_dot dL/dq_dot - L follows when it differs from T + V (rheonomic, velocity
    # potentials, non-quadratic T), then the momenta of the cyclic coordinates that no
    # constraint involves
    constrained = set().union(*(c.expression.free_symbols for c in system.constraints))
    cyclic = [
        f"p_{c.coordinate.name}"
        for c in cyclic_coordinates(system)
        if not constrained & {c.coordinate, lg.velocity(c.coordinate)}
    ]
    assert columns in ([*expected, *cyclic], [*expected, "energy_function", *cyclic])
    assert len(rows) == 20


def test_simulate_to_standard_output_with_overrides_and_a_plot(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    picture = tmp_path / "pendulum.png"
    code, out, _ = run(
        capsys,
        "simulate",
        "examples/simple_pendulum",
        "--t-end",
        "1",
        "--samples",
        "3",
        "--set",
        "theta=0.2",
        "--method",
        "DOP853",
        "--plot",
        str(picture),
    )
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == "t,theta,theta_dot,energy" and lines[1].startswith("0,0.2")
    assert picture.stat().st_size > 1000


MODEL = """\
name: spring
coordinates: [x]
parameters: {m: 2.0, k: 8.0}
kinetic: "m*x_dot**2/2"
potential: "k*x**2/2"
initial: {x: 1.0, x_dot: 0.0}
simulate: {t_end: 1.0}
"""


def test_model_files_and_standard_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "spring.yaml"
    path.write_text(MODEL)
    code, out, _ = run(capsys, "derive", str(path))
    assert code == 0 and out.strip().splitlines()[0] == "k*x + m*x_ddot = 0"
    assert out.strip().endswith("Parameters: m = 2, k = 8 (derive --substitute puts them in)")
    import io

    monkeypatch.setattr("sys.stdin", io.StringIO(MODEL))
    code, out, _ = run(capsys, "derive", "-", "--format", "json")
    assert code == 0 and json.loads(out)["name"] == "spring"


def test_a_bad_model_file_names_file_field_line_and_column(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(MODEL.replace('"k*x**2/2"', '"kk*x**2/2"').replace("kinetic", "kinetc"))
    code, _, err = run(capsys, "derive", str(path))
    assert code == 2 and "Traceback" not in err
    assert "bad.yaml" in err and "unknown name 'kk'" in err and "line 5" in err
    assert "did you mean 'kinetic'" in err
    code, _, err = run(capsys, "derive", str(tmp_path / "missing.yaml"))
    assert code == 2 and "No model file" in err


def test_examples_prints_the_model_file(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "examples", "double_pendulum")
    assert code == 0 and "particles:" in out and out.startswith("# Double pendulum")
    # a scalable example at the size asked, as every other command reads NAME:N
    code, out, _ = run(capsys, "examples", "hard_disk_gas:3")
    assert code == 0 and "coordinates: [x1, x2, x3, y1, y2, y3]" in out
    code, _, err = run(capsys, "examples", "hard_disk_gas:101")
    assert code == 2 and "from 1 to 100" in err


@pytest.mark.parametrize("name", lg.examples.names())
def test_every_example_analyzes(capsys: pytest.CaptureFixture[str], name: str) -> None:
    code, out, err = run(capsys, "analyze", f"examples/{name}")
    assert code == 0, err
    document = json.loads(out)
    for key in (
        "dof",
        "constraints",
        "momenta",
        "cyclic",
        "conserved",
        "energy_function",
        "energy_conserved",
        "hamiltonian",
        "equilibria",
        "normal_modes",
    ):
        assert key in document
    system = lg.examples.get(name)()
    holonomic = [c for c in system.constraints if isinstance(c, lg.Holonomic)]
    equalities = [c for c in system.constraints if not isinstance(c, lg.Unilateral)]
    # dof counts the independent velocities (every equality constraint), the configuration
    # dimension only the holonomic ones (they differ for the rolling disc: 3 and 5)
    assert document["configuration_dimension"] == len(system.coordinates) - len(holonomic)
    assert document["dof"] == len(system.coordinates) - len(equalities)


def test_analyze_about_an_operating_point(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "analyze", "examples/simple_pendulum", "--about", "theta=0")
    assert code == 0
    linearization = json.loads(out)["linearization"]
    # small oscillations of the pendulum: omega = sqrt(g/l) = sqrt(9.81)
    assert float(sp.sympify(linearization["frequencies"][0])) == pytest.approx(9.81**0.5)
    code, _, err = run(capsys, "analyze", "examples/simple_pendulum", "--about", "theta")
    assert code == 2 and "expected NAME=NUMBER" in err


def test_mathml_output(capsys: pytest.CaptureFixture[str]) -> None:
    import xml.etree.ElementTree as ET

    code, out, _ = run(
        capsys, "derive", "examples/double_pendulum", "--format", "mathml", "--steps"
    )
    assert code == 0 and ET.fromstring(out).tag.endswith("math")


CONSTRAINED = """\
name: cartesian_pendulum
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, l: 1.0}
gravity: [0, -g]
particles:
  - {name: bob, mass: m, position: [x, y]}
constraints:
  - {holonomic: "x**2 + y**2 - l**2", name: rod}
initial: {x: 0.6, y: -0.8, x_dot: 0, y_dot: 0}
"""


def test_constrained_model_derives_with_multipliers(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    path = tmp_path / "cartesian_pendulum.yaml"
    path.write_text(CONSTRAINED)
    code, out, _ = run(capsys, "derive", str(path), "--format", "json")
    document = json.loads(out)
    assert code == 0 and document["multipliers"] == ["lambda_1"]
    assert document["constraint_jacobian"] == [["2*x", "2*y"]]
    x, lam, m = sp.symbols("x lambda_1 m")
    # lambda dh/dq is the constraint force (docs/architecture.md): m x'' = 2 lambda x
    first = sp.sympify(document["constrained_equations"][0])
    assert sp.expand(first - (m * sp.Symbol("x_ddot") - 2 * lam * x)) == 0
    code, out, _ = run(capsys, "analyze", str(path))
    assert code == 0 and json.loads(out)["dof"] == 1
    code, out, err = run(capsys, "simulate", str(path), "--t-end", "1")
    assert code == 0, err
    assert out.splitlines()[0] == "t,x,y,x_dot,y_dot,lambda_1,energy"


def test_version_prints_the_installed_version(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit, match="0"):
        main(["--version"])
    assert capsys.readouterr().out == f"lagrangian {lg.__version__}\n"


def test_debug_before_the_command_shows_the_traceback(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = run(capsys, "--debug", "derive", "examples/nope")
    assert code == 2 and "Traceback" in err
    code, _, err = run(capsys, "--debug", "examples", "nope")
    assert code == 2 and "Traceback" in err


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--method", "RK99"], "unknown method 'RK99'"),
        (["--t-end", "-1"], "is not after the start"),
        (["--set", "theta=0.1", "--rtol", "0"], "rtol must be positive"),
    ],
)
def test_bad_simulate_input_exits_2(
    capsys: pytest.CaptureFixture[str], options: list[str], message: str
) -> None:
    code, _, err = run(capsys, "simulate", "examples/simple_pendulum", *options)
    assert code == 2 and message in err and "Traceback" not in err


RUNAWAY = """\
coordinates: [x]
kinetic: "x_dot**2/2"
potential: "-x**4"
initial: {x: 1.0, x_dot: 0.0}
simulate: {t_end: 5.0}
"""


def test_a_failed_integration_exits_1(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    path = tmp_path / "runaway.yaml"  # x_ddot = 4 x**3 blows up in finite time
    path.write_text(RUNAWAY)
    code, _, err = run(capsys, "simulate", str(path))
    assert code == 1 and err.startswith("lagrangian: ") and "Traceback" not in err


def test_an_output_folder_that_does_not_exist_is_bad_input(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    out = tmp_path / "missing" / "traj.csv"
    code, _, err = run(capsys, "simulate", "examples/simple_pendulum", "--out", str(out))
    assert code == 2 and f"the folder {str(out.parent)!r} does not exist" in err
    assert "--out" in err and "mkdir -p" in err and ".traj.csv." not in err


def test_an_unreadable_model_is_bad_input_and_other_os_errors_fail() -> None:
    unreadable = PermissionError(13, "Permission denied", "models/spring.yaml")
    assert exit_code(unreadable, ["./models/spring.yaml"]) == 2
    assert exit_code(PermissionError(13, "Permission denied", "/var/cache/x"), ["m.yaml"]) == 1
    assert exit_code(OSError(28, "No space left on device"), ["m.yaml"]) == 1


def test_a_bug_is_an_internal_error_exiting_1(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    def broken(name: str | None) -> str:
        raise KeyError("oops")

    monkeypatch.setattr("lagrangian.cli.commands.examples_command", broken)
    code, _, err = run(capsys, "examples")
    first, hint = err.splitlines()
    assert code == 1 and first == "lagrangian: internal error: 'oops'"
    assert "a bug in lagrangian" in hint and "--debug" in hint


def test_help_and_version_load_neither_sympy_nor_numpy() -> None:
    code = """
import json, sys
from lagrangian.cli.main import main
for flag in ("--help", "--version"):
    try:
        main([flag])
    except SystemExit:
        pass
print(json.dumps([m for m in ("sympy", "numpy", "scipy", "matplotlib") if m in sys.modules]))
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout.splitlines()[-1]) == []


def test_a_mistyped_option_gets_a_suggestion(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stopped:
        main(["simulate", "examples/simple_pendulum", "--t-edn", "3"])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert "unrecognized arguments: --t-edn 3 — did you mean --t-end?" in err
    with pytest.raises(SystemExit):
        main(["derive", "examples/simple_pendulum", "--zzzzzz"])
    assert "did you mean" not in capsys.readouterr().err  # nothing close: no guess


def test_another_commands_option_is_named_as_such(capsys: pytest.CaptureFixture[str]) -> None:
    # suggesting the option itself ("--format json — did you mean --format?") told nothing
    with pytest.raises(SystemExit) as stopped:
        main(["simulate", "examples/simple_pendulum", "--format", "json"])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert "— simulate has no --format (derive, analyze do)" in err
    with pytest.raises(SystemExit):
        main(["--t-end=3", "simulate", "examples/simple_pendulum"])
    assert "— give --t-end after simulate" in capsys.readouterr().err


def test_a_unilateral_constraint_is_told_from_an_equality_in_every_format(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # the bouncing ball's y >= 0: its multiplier form is the motion in contact only
    main(["derive", "examples/bouncing_ball"])
    text = capsys.readouterr().out
    assert "  y >= 0\n  (while in contact: each unilateral constraint at 0" in text
    main(["derive", "examples/bouncing_ball", "--format", "json"])
    document = json.loads(capsys.readouterr().out)
    assert document["constraints"] == ["y"] and document["constraint_kinds"] == ["unilateral"]
    main(["derive", "examples/bouncing_ball", "--format", "latex"])
    latex = capsys.readouterr().out
    assert r"y &\geq 0" in latex and r"\text{while in contact" in latex
    main(["derive", "examples/bouncing_ball", "--format", "mathml"])
    mathml = capsys.readouterr().out
    # y >= 0, not "y = >= 0"; a heading or a note has no "=" after it
    assert '<mi>y</mi></mtd><mtd columnalign="left"><mo>&#8805;</mo><mn>0</mn>' in mathml
    assert 'force of constraint j)</mtext></mtd><mtd columnalign="left"></mtd>' in mathml
    main(["derive", "examples/simple_pendulum", "--format", "json"])
    assert "constraint_kinds" not in json.loads(capsys.readouterr().out)  # no constraints
    main(["derive", "examples/rolling_disc", "--format", "json"])
    assert json.loads(capsys.readouterr().out)["constraint_kinds"] == ["velocity", "velocity"]
    main(["derive", "examples/dumbbell"])
    assert "while in contact" not in capsys.readouterr().out  # equalities hold throughout
