"""Model files built to exhaust the reader, and values that make no physical sense, end in a
clear refusal naming the field (exit code 2), never in an internal error or a hang."""

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.io.load import loads
from lagrangian.io.yaml_tree import MAX_VALUES

MODEL = "coordinates: [x]\nparameters: {m: 1}\nkinetic: m*x_dot**2/2\npotential: x**2/2\n"


def laughs(levels: int) -> str:
    """Nested aliases: 9**levels values from a few lines ("billion laughs")."""
    lines = ["l0: &l0 [x, x, x, x, x, x, x, x, x]"]
    for i in range(1, levels):
        lines.append(f"l{i}: &l{i} [" + ", ".join([f"*l{i - 1}"] * 9) + "]")
    return "\n".join(lines) + "\n" + MODEL


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (laughs(9), f"more than {MAX_VALUES:,} values"),
        (MODEL + "description: " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply"),
        (MODEL.replace("m: 1", "m: " + "9" * 400), "an integer of 400 digits"),
        (MODEL.replace("[x]", "!include other.yaml"), "unknown YAML tag '!include'"),
        (MODEL.replace("[x]", "!mytag [x]"), "unknown YAML tag '!mytag'"),
    ],
)
def test_hostile_yaml_is_refused_with_a_reason(text, message):
    with pytest.raises(ModelError, match=message) as refused:
        loads(text)
    assert refused.value.exit_code == 2


def test_deeply_nested_json_is_refused():
    with pytest.raises(ModelError, match="nested too deeply"):
        loads('{"coordinates": ["x"], "d": ' + "[" * 100_000 + "]" * 100_000 + "}", "json")


@pytest.mark.parametrize("setting", [{"m": -1.0}, {"m": -1e-3}])
def test_a_negative_mass_is_refused_before_simulating(setting):
    system = loads(MODEL)
    with pytest.raises(lg.SimulationInputError, match="kinetic energy is negative"):
        lg.simulate(system, {"x": 1, "x_dot": 0}, 1.0, parameters=setting)


def test_a_negative_mass_of_one_body_among_several_is_refused():
    with pytest.raises(lg.SimulationInputError, match="m1=-5"):
        lg.simulate(lg.examples.double_pendulum(), t_span=1.0, parameters={"m1": -5})
