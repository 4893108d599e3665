"""Runs that always end: the probes of the re-audit, through the command line.

Each probe runs in a forked child bounded at 30 s and 1 GiB (:mod:`tests.hostile.conftest`;
the bound kills a probe that hangs, it is not a speed assertion) and ends in exit 2 with a
message naming the field or option and the fix, or in exit 0 with the right answer, never in
an internal error.  The answers are hand derivations: at rest at the kink of a V-shaped well
the mass stays there (both sides push towards it); a step Heaviside(x**k) in V has zero force
away from its jump, so x_ddot = 0.
"""

from __future__ import annotations

import csv
import json

import pytest

#: The bound of every probe here (the issue's: 30 s, 1 GiB).
BOUND = {"timeout": 30.0, "memory": 1 << 30}


def model(potential: str, kinetic: str = "x_dot**2/2", initial: str = "{x: 0, x_dot: 0}") -> str:
    return f"coordinates: [x]\nkinetic: {kinetic}\npotential: {potential}\ninitial: {initial}\n"


def column(path, name: str) -> list[float]:
    with open(path, newline="") as handle:
        return [float(row[name]) for row in csv.DictReader(handle)]


# -- budgets honoured everywhere, rest at a kink ---------------------------------------------


@pytest.mark.parametrize(
    ("potential", "x0"), [("x*sign(x)", 0.0), ("Abs(x)", 0.0), ("Abs(x - 1)", 1.0)]
)
def test_rest_at_a_kink_stays_at_rest_within_its_wall_time(cli, tmp_path, potential, x0):
    text = model(potential, initial=f"{{x: {x0}, x_dot: 0}}")
    argv = ["simulate", "-", "--t-end", "10", "--max-wall-time", "10", "--out", "run.csv"]
    outcome = cli(argv, text, **BOUND)
    assert outcome.code == 0, outcome
    assert set(column(tmp_path / "run.csv", "x")) == {x0}
    assert set(column(tmp_path / "run.csv", "x_dot")) == {0.0}


def test_a_potential_that_divides_by_zero_everywhere_is_refused_before_the_run(cli):
    text = model("x**2/2 + x/(sqrt(x**2) - Abs(x))", initial="{x: 1, x_dot: 0}")
    argv = ["simulate", "-", "--t-end", "10", "--max-steps", "1000", "--max-wall-time", "10"]
    outcome = cli([*argv, "--out", "run.csv"], text, **BOUND)
    outcome.assert_refused("--initial", "not a finite number", "division by zero")


def test_a_non_physical_velocity_is_refused_before_the_run(cli):
    argv = ["simulate", "examples/asymmetric_body", "--set", "phi_dot=1e308"]
    outcome = cli([*argv, "--max-wall-time", "5", "--out", "run.csv"], **BOUND)
    outcome.assert_refused("--initial", "phi_dot", "not a finite number")


def test_a_switched_run_stops_at_the_steps_of_the_whole_run(cli):
    # V = |x| from x = 1: a crossing of the kink every 2 sqrt(2), each a piece of the run
    text = model("Abs(x)", initial="{x: 1, x_dot: 0}")
    outcome = cli(["simulate", "-", "--t-end", "100", "--max-steps", "20", "--out", "r.csv"], text)
    assert outcome.code == 1, outcome
    assert not outcome.internal, outcome
    assert "step budget of 20 steps" in outcome.err and "--max-steps 200" in outcome.err


def test_a_kinetic_energy_with_a_kink_in_the_velocities_is_refused_with_the_reason(cli):
    outcome = cli(["derive", "-"], model("x**2/2", kinetic="x_dot**2/2 + Abs(x_dot)"), **BOUND)
    outcome.assert_refused("kinetic", "not smooth in the velocities", "dissipation")


# -- a cost model that refuses before working ------------------------------------------------


def test_a_step_of_a_high_power_is_derived(cli):
    outcome = cli(["derive", "-", "--format", "json"], model("Heaviside(x**999)"), **BOUND)
    assert outcome.code == 0, outcome
    assert json.loads(outcome.out)["equations"] == ["x_ddot"]


def test_a_sum_of_27_steps_is_derived(cli):
    steps = " + ".join(f"Heaviside(x**{k})" for k in range(1, 28))
    outcome = cli(["derive", "-", "--format", "json"], model(steps), **BOUND)
    assert outcome.code == 0, outcome
    assert json.loads(outcome.out)["equations"] == ["x_ddot"]


POWER = (
    "coordinates: [a, b, c, d]\n"
    "kinetic: (sin(a) + sin(b) + sin(c) + cos(d))**40*(a_dot**2 + b_dot**2 + c_dot**2 + "
    "d_dot**2)/2\n"
)


def test_a_power_of_a_sum_of_sines_is_refused_by_its_predicted_size(cli):
    outcome = cli(["derive", "-"], POWER, **BOUND)
    outcome.assert_refused("kinetic", "harmonics", "size limit of 5,000,000", "--size-limit")


def test_the_size_limit_option_moves_the_bound_of_the_prediction(cli):
    low = POWER.replace("**40", "**6")
    cli(["derive", "-", "--size-limit", "1000"], low, **BOUND).assert_refused("size limit of 1,000")
    assert cli(["derive", "-"], low, **BOUND).code == 0


@pytest.mark.parametrize("language", ["json", "yaml"])
def test_a_file_of_20000_parameters_is_refused_by_count(cli, tmp_path, language):
    parameters = {f"p{i}": 1.0 for i in range(20_000)}
    document = {"coordinates": ["x"], "parameters": parameters, "kinetic": "x_dot**2/2"}
    path = tmp_path / f"many.{language}"
    if language == "json":
        path.write_text(json.dumps(document))
    else:
        items = ", ".join(f"{k}: {v}" for k, v in parameters.items())
        path.write_text(f"coordinates: [x]\nparameters: {{{items}}}\nkinetic: x_dot**2/2\n")
    outcome = cli(["derive", str(path)], **BOUND)
    outcome.assert_refused("parameters.p5000", "20,000 parameters", "5,000")


# -- one rule for names ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("lookalike", "unicode_name"),
    [
        ("х", "CYRILLIC SMALL LETTER HA"),
        ("𝐱", "MATHEMATICAL BOLD SMALL X"),
        ("ｘ", "FULLWIDTH LATIN SMALL LETTER X"),
    ],
)
def test_a_lookalike_name_is_refused_with_the_ascii_name(cli, lookalike, unicode_name):
    text = (
        f"coordinates: [x, {lookalike}]\nkinetic: x_dot**2/2 + {lookalike}_dot**2/2\n"
        f"potential: x**2 + {lookalike}**2\n"
    )
    outcome = cli(["derive", "-"], text, **BOUND)
    outcome.assert_refused("coordinates[1]", unicode_name, "write x")


def test_a_greek_name_is_a_name(cli):
    outcome = cli(["derive", "-"], "coordinates: [θ]\nkinetic: θ_dot**2/2\npotential: θ**2/2\n")
    assert outcome.code == 0, outcome
    assert "θ" in outcome.out


# -- ordinary mistakes with their reason -----------------------------------------------------


def test_a_frame_given_a_mass_says_frames_have_no_mass(cli):
    text = "coordinates: [x]\nframes:\n  - {name: arm, mass: 1}\nkinetic: x_dot**2/2\n"
    cli(["derive", "-"], text, **BOUND).assert_refused("frames[0].mass", "frames have no mass")


def test_a_python_keyword_as_a_coordinate_is_refused_with_the_fix(cli):
    text = "coordinates: [lambda]\nkinetic: lambda_dot**2/2\n"
    outcome = cli(["derive", "-"], text, **BOUND)
    outcome.assert_refused("coordinates[0]", "Python keyword", "lam")
