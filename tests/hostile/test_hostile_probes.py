"""Every class of hostile or extreme input found by the audit (issue 19), through the command
line: each ends, within the test's own timeout and an address-space limit, in exit 2 with a
message naming the field, or in success where the input is legitimate; never in an internal
error, a hang or gigabytes of memory.  The timeout kills a probe that hangs; it is not a
speed assertion.  Probes that take long even when they work are marked slow."""

from __future__ import annotations

import pytest

from lagrangian.io.yaml_tree import MAX_CHARACTERS, MAX_VALUES

GiB = 1 << 30
MODEL = (
    "coordinates: [x]\nparameters: {m: 1}\nkinetic: m*x_dot**2/2\npotential: %s\n"
    "initial: {x: 0.5, x_dot: 0}\nsimulate: {t_end: 1}\n"
)
HARMONIC = MODEL % "x**2/2"


def laughs(levels: int) -> str:
    """Nested YAML aliases: 9**levels values from a few lines ("billion laughs")."""
    lines = ["l0: &l0 [x, x, x, x, x, x, x, x, x]"]
    lines += [f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 9) + "]" for i in range(1, levels)]
    return "\n".join(lines) + "\n" + HARMONIC


def many_unknown_names(count: int) -> str:
    """``count`` particles, each placed at a name nobody declared, among ``count`` parameters:
    a "did you mean" for each must not compare every pair."""
    parameters = ", ".join(f"pa{i}: 1" for i in range(count))
    particles = "\n".join(f"  - {{name: b{i}, mass: 1, position: [pb{i}]}}" for i in range(count))
    head = f"coordinates: [x]\nparameters: {{{parameters}}}\nkinetic: x_dot**2\n"
    return f"{head}particles:\n{particles}\n"


def refused(outcome, *words: str) -> None:
    """Exit 2, a message with each of ``words`` (the field), and no internal error."""
    outcome.assert_refused(*words)


# -- the reader: files built to exhaust it -------------------------------------------------

READER_PROBES = {
    "billion laughs": (laughs(10), [f"more than {MAX_VALUES:,} values"]),
    "lists nested 5,000 deep": (
        HARMONIC + "description: " + "[" * 5000 + "]" * 5000 + "\n",
        ["nested too deeply"],
    ),
    "maps nested 3,000 deep": (
        HARMONIC + "description: " + "{a: " * 3000 + "1" + "}" * 3000 + "\n",
        ["nested too deeply"],
    ),
    "an integer of 400 digits": (
        HARMONIC.replace("m: 1", "m: " + "9" * 400),
        ["parameters.m", "400 digits"],
    ),
    "an integer of 5,000 digits": (
        HARMONIC.replace("m: 1", "m: " + "9" * 5000),
        ["parameters.m", "5000 digits"],
    ),
    "an integer of 5,000 digits in an expression": (MODEL % ("9" * 5000 + "*x**2"), ["potential"]),
    "an integer of 309 digits (beyond a double)": (
        HARMONIC.replace("m: 1", "m: " + "9" * 309),
        ["parameters.m"],
    ),
    "a date that is no date": (HARMONIC.replace("m: 1", "m: 2024-13-45"), ["parameters.m"]),
    "a lone surrogate in a name": (
        'coordinates: ["x\\ud800"]\nkinetic: x_dot**2\n',
        ["coordinates[0]", "is not a name"],
    ),
    "!include": (HARMONIC.replace("[x]", "!include other.yaml"), ["unknown YAML tag '!include'"]),
    "!mytag": (HARMONIC.replace("[x]", "!mytag [x]"), ["unknown YAML tag '!mytag'"]),
    "!!python/object/apply": (
        HARMONIC.replace("[x]", "!!python/object/apply:os.system ['echo pwned']"),
        ["unknown YAML tag", "python/object/apply"],
    ),
    "a file of 2 million characters": (
        HARMONIC + "description: '" + "a" * (2 * MAX_CHARACTERS) + "'\n",
        ["size", f"more than the {MAX_CHARACTERS:,}"],
    ),
    "2,000 unknown names among 2,000 parameters": (
        many_unknown_names(2000),
        ["particles[1999].position[0]", "unknown name 'pb1999'"],
    ),
    "1,001 coordinates": (
        "coordinates: [" + ", ".join(f"q{i}" for i in range(1001)) + "]\nkinetic: q0_dot**2\n",
        ["coordinates", "more than the 1,000"],
    ),
}


@pytest.mark.parametrize("name", list(READER_PROBES))
def test_a_file_built_to_exhaust_the_reader_is_refused(cli, name):
    text, words = READER_PROBES[name]
    outcome = cli(["derive", "-"], text)
    refused(outcome, *words)
    assert "pwned" not in outcome.out + outcome.err


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ('{"coordinates": ["x"], "d": ' + "[" * 100_000 + "]" * 100_000 + "}", ["nested"]),
        ('{"coordinates": ["x"], "parameters": {"m": ' + "9" * 5000 + "}}", ["5000 digits"]),
    ],
    ids=["json nested 100,000 deep", "json integer of 5,000 digits"],
)
def test_hostile_json_is_refused(cli, text, words):
    refused(cli(["derive", "-", "--input-format", "json"], text), *words)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ('coordinates = ["x"]\nd = ' + "[" * 3000 + "]" * 3000 + "\n", ["nested too deeply"]),
        ('coordinates = ["x"]\n[parameters]\nm = ' + "9" * 5000 + "\n", ["5000 digits"]),
        ('coordinates = ["x"]\n[parameters]\nm = ' + "9" * 400 + "\n", ["400 digits"]),
        ('coordinates = ["x"]\nkinetic = "x_dot**2"\n[parameters]\nm = nan\n', ["parameters.m"]),
    ],
    ids=["toml nested", "toml 5,000 digits", "toml 400 digits", "toml nan"],
)
def test_hostile_toml_is_refused(cli, text, words):
    refused(cli(["derive", "-", "--input-format", "toml"], text), *words)


def test_billion_laughs_stays_small_in_memory(cli):
    # The audit saw 3.7 GB: the expansion is cut before it is built.
    outcome = cli(["derive", "-"], laughs(12), memory=GiB)
    refused(outcome, "values")
    assert outcome.peak_bytes < 1.5 * GiB


def test_the_real_command_refuses_billion_laughs_in_a_fresh_process(cli):
    refused(cli(["derive", "-"], laughs(10), fresh=True), f"more than {MAX_VALUES:,} values")


# -- expressions whose symbolic work would grow without end --------------------------------

EXPRESSION_PROBES = {
    "a power of a long sum of sines": (
        "(" + " + ".join(f"sin({i}*x)" for i in range(1, 41)) + ")**20",
        "more than 100,000 terms",
    ),
    "a stack of powers of Abs": ("Abs(" * 30 + "x" + " - 1)**3" * 30, "operations"),
    "a long product of sums": ("*".join(f"(x+{i})" for i in range(1, 400)), "digits"),
}


@pytest.mark.parametrize("name", list(EXPRESSION_PROBES))
def test_an_expression_that_would_blow_up_is_refused_at_parse_time(cli, name):
    text, words = EXPRESSION_PROBES[name]
    refused(cli(["derive", "-"], MODEL % text), "potential", words)


def test_a_multinomial_kinetic_energy_is_refused(cli):
    text = "coordinates: [x, y, z]\nkinetic: (x_dot + y_dot + z_dot + x + y + z)**60\n"
    refused(cli(["derive", "-"], text), "kinetic", "more than 100,000 terms")


def test_nested_heaviside_is_legitimate(cli):
    outcome = cli(["derive", "-"], MODEL % ("Heaviside(" * 50 + "x" + ")" * 50))
    assert outcome.code == 0, outcome


@pytest.mark.slow
@pytest.mark.parametrize(
    "text",
    ["*".join(f"(x+{i})" for i in range(1, 250))],
    ids=["a product of 249 sums"],
)
def test_symbolic_work_past_timeout_stops_with_a_message(cli, text):
    outcome = cli(["derive", "-", "--timeout", "20"], MODEL % text)
    assert outcome.code in (0, 1), outcome
    assert not outcome.internal, outcome
    if outcome.code == 1:
        assert "stopped after --timeout 20 s" in outcome.err, outcome


def test_a_varying_power_of_a_high_power_is_refused_when_read(cli):
    outcome = cli(["derive", "-"], MODEL % "tan(x**999)**(x/(x+1))")
    refused(outcome, "potential", "power above 100")


@pytest.mark.slow
def test_a_fifty_link_chain_is_derived_well_within_its_timeout(cli):
    outcome = cli(["derive", "n_link_pendulum:50", "--timeout", "20"])
    assert outcome.code == 0, outcome


def particle_chain(n: int) -> str:
    """A model file of ``n`` equal point masses, bob i at the sum of the rods above it."""
    coordinates = ", ".join(f"th{i}" for i in range(1, n + 1))
    lines = [f"coordinates: [{coordinates}]", "parameters: {g: 9.81, l: 1, m: 1}", "particles:"]
    x: list[str] = []
    y: list[str] = []
    for i in range(1, n + 1):
        x.append(f"l*sin(th{i})")
        y.append(f"-l*cos(th{i})")
        lines.append(f"  - {{name: p{i}, mass: m, position: [{' + '.join(x)}, {' + '.join(y)}]}}")
    return "\n".join([*lines, "gravity: [0, -g]"]) + "\n"


@pytest.mark.slow
@pytest.mark.parametrize("model", ["n_link_pendulum:200", "particle_chain.yaml"])
def test_a_chain_of_200_masses_is_derived_within_the_memory_bound(cli, tmp_path, model):
    # Legitimate, so it must succeed (and within 1 GiB).  Its time against the bound of
    # 30 s is measured by benchmarks/large_inputs.py: the timeout here only stops a hang.
    if model.endswith(".yaml"):
        (tmp_path / model).write_text(particle_chain(200))
    outcome = cli(["derive", model], timeout=240, fresh=True)
    assert outcome.code == 0, outcome
    assert outcome.peak_bytes < GiB, outcome.peak_bytes
    last = "theta200_ddot" if model.startswith("n_link") else "th200_ddot"
    assert outcome.out.count(" = 0\n") == 200 and last in outcome.out


# -- simulation options and values ---------------------------------------------------------


@pytest.mark.parametrize("samples", ["100000000", "1000000000000", str(2**70)])
def test_samples_beyond_memory_are_refused_before_allocation(cli, samples):
    outcome = cli(["simulate", "-", "--samples", samples, "--out", "out.csv"], HARMONIC)
    refused(outcome, "--samples")
    assert outcome.peak_bytes < 1.5 * GiB


def test_samples_in_scientific_notation_are_a_usage_error(cli):
    refused(cli(["simulate", "-", "--samples", "1e7"], HARMONIC), "--samples")


def test_ten_million_fixed_steps_are_refused_before_the_run(cli):
    argv = ["simulate", "-", "--method", "RK4", "--samples", "10000000", "--out", "out.csv"]
    refused(cli(argv, HARMONIC), "max-steps")


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["--set", "m=-1"], ["kinetic energy is negative", "m=-1"]),
        (["--set", "m=inf"], ["--set m=inf", "not a finite number"]),
        (["--rtol", "1e-300"], ["--rtol"]),
        (["--rtol", "1e300"], ["--rtol", "as large as the values", "below 1"]),
        (["--rtol", "1"], ["--rtol", "below 1"]),
        (["--atol", "1e300"], ["--atol", "as large as the state"]),
        (["--method", "RK4", "--dt", "5"], ["--dt", "longer than the time span"]),
        (["--method", "variational", "--dt", "2"], ["--dt", "longer than the time span"]),
    ],
    ids=[
        "negative mass",
        "infinite mass",
        "rtol below what the solver honours",
        "rtol 1e300",
        "rtol 1",
        "atol 1e300",
        "RK4 dt past the span",
        "variational dt past the span",
    ],
)
def test_a_simulation_asked_wrongly_is_refused(cli, argv, words):
    refused(cli(["simulate", "-", "--out", "-", *argv], HARMONIC), *words)


def test_a_nan_initial_value_is_bad_input(cli):
    refused(cli(["simulate", "-", "--set", "x=nan", "--out", "-"], HARMONIC), "x")


def test_analyze_about_a_nan_state_is_refused(cli):
    refused(cli(["analyze", "-", "--about", "x=nan"], HARMONIC), "x", "nan")


@pytest.mark.parametrize(
    "text",
    [MODEL % "1/(x - 0.7)", MODEL % "exp(800)*x**2", HARMONIC.replace("x: 0.5", "x: 1e200")],
    ids=["a division by zero on the way", "an energy beyond a double", "a huge initial value"],
)
def test_a_run_that_stops_being_finite_ends_with_a_message(cli, text):
    outcome = cli(["simulate", "-", "--out", "out.csv", "--t-end", "2"], text)
    assert outcome.code in (1, 2), outcome
    assert not outcome.internal, outcome
    assert "not a finite number" in outcome.err or "singular" in outcome.err, outcome


def test_an_integration_failure_keeps_its_rows_and_speaks_the_command_line(cli, tmp_path):
    outcome = cli(["simulate", "-", "--out", "out.csv", "--t-end", "10"], MODEL % "-x**4")
    assert outcome.code == 1, outcome
    assert not outcome.internal, outcome
    assert "raise_on_failure" not in outcome.err, outcome  # a Python keyword, not a flag
    rows = (tmp_path / "out.csv").read_text().splitlines()
    assert rows[0].startswith("t,") and len(rows) > 2


def test_a_missing_initial_value_is_explained_in_command_line_words(cli):
    text = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"
    outcome = cli(["simulate", "-", "--t-end", "1", "--out", "-"], text)
    refused(outcome, "x")
    assert "initial={" not in outcome.err
