"""libyaml composes a model file exactly as PyYAML does: the same values, the same lines and
columns of every value and key, the same problems; what it cannot read alike goes to PyYAML."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.io import yaml_tree
from lagrangian.io.yaml_tree import MAX_DEPTH, read_json, read_yaml

pytestmark = pytest.mark.skipif(not yaml.__with_libyaml__, reason="PyYAML without libyaml")

MODELS = sorted((Path(lg.__file__).parent / "examples" / "models").glob("*.yaml"))

TEXTS = {
    "block scalars": "coordinates: [x]\nkinetic: |\n  m*x_dot**2/2\npotential: >-\n    k*x**2/2\n",
    "quotes and flow": "coordinates: ['x', \"y\"]\nparameters: {m: 1e-3, k: 2.5E+2, g: 9.81}\n",
    "comments, CRLF": "# a model\r\ncoordinates: [x]  # one\r\npotential: x**2\r\n",
    "anchors": "parameters: &p {m: 1}\nother: *p\nlist: [&a 1, *a]\n",
    "duplicate keys": "coordinates: [x]\npotential: x\npotential: 2*x\n",
    "merge key": "base: &b {m: 1}\nparameters:\n  <<: *b\n",
    "tags": "coordinates: !!python/name:os.system [x]\nvalue: !!str 1\n",
    "dates and numbers": "when: 2024-13-45\nbig: 1" + "0" * 400 + "\nhex: 0x1F\nbool: yes\n",
    "nested deep": "a: " + "[" * (MAX_DEPTH + 1) + "]" * (MAX_DEPTH + 1) + "\n",
    "nested to the limit": "a: " + "[" * (MAX_DEPTH - 1) + "]" * (MAX_DEPTH - 1) + "\n",
    "key not a name": "? [a, b]\n: 1\n",
    "empty": "",
    "tabs": "coordinates:\t[x]\n",  # libyaml reads these three, PyYAML refuses them
    "a tab before a value": "a:  \t1\n",
    "a tab after a value": "a: 1\t\n",
    "Greek": "coordinates: [θ]\npotential: 1 - cos(θ)\n",
    # texts that libyaml reads otherwise than PyYAML (an empty value a column apart, a tag on
    # nothing, a block scalar's indicator before a comment): composed by PyYAML
    "empty value in a flow": "[.a: ]\n",
    "an explicit key alone": "?\n",
    "a tag on nothing": " !\n",
    "block scalar before a comment": "\n|#,\n",
    "empty values": "coordinates:\nparameters: {m: }\n",
}

#: Texts whose characters read apart (?!|>) are in full-line comments only, or in lines that
#: look like comments inside a quoted or block scalar.
COMMENTED = {
    "above and below": "# steer > 0 turns right? yes! |a|\nx: 1\n# the end >\n",
    "indented in a map": "a:\n  # b > 0?\n  b: 1\n    # !c |\n  c: [1, 2]\n",
    "between items": "- 1\n  # ?\n- 2\n# !!str\n- [3]\n",
    "in a flow": "a: [1,\n  # > ?\n  2, {b: 3,\n # |\n c: 4}]\n",
    "in a plain scalar": "a: one\n  # two > one?\n",
    "plain on after it": "a: one\n  # two > one?\n  three\n",
    "CR line breaks": "# a > b\rx: 1\r  # ?\ry: 2\r",
    "CRLF line breaks": "# a > b\r\nx: 1\r\n  # ?\r\n",
    "hash alone": "#>\n#\nx: 1 # not a full line, no mark\n",
    "in double quotes": 'a: "one\n  # two > one? !\n  three"\nb: 1\n',
    "in single quotes": "a: 'one\n  # it''s | >\n  three'\nb: 1\n",
    "a quoted key": '{"one\n  # ? two": 1}\n',
    "a quote closing on it": 'a: ["one\n  # two", ? three]\n',
    "a quote closing, then a tag": '{"one\n # two": !!str }\n',
    "a quote closing, then a block": 'a: "one\n # two" |\n  three\n',
    "in a block scalar": "a: |\n  one\n  # two > one?\nb: >\n  # ! |\n",
    "a tab elsewhere": "# >\na:\t1\n",
    "not a comment after all": "a: 1\n  b # ?\n",
}


def both_ways(read, text: str, monkeypatch: pytest.MonkeyPatch):
    """What ``read`` makes of ``text`` with libyaml, then with PyYAML alone (document data,
    positions, problems, or the error's message)."""
    results = []
    for fast in (True, False):
        with monkeypatch.context() as patched:
            if not fast:
                patched.setattr(yaml_tree, "_FastLoader", None)
            try:
                document, problems = read(text, "model.yaml")
                results.append((document.data, document.values, document.keys, problems))
            except ModelError as error:
                results.append(str(error))
    return results


@pytest.mark.parametrize("path", MODELS, ids=lambda path: path.stem)
def test_the_example_models_compose_alike(path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    fast, python = both_ways(read_yaml, path.read_text(), monkeypatch)
    assert fast == python


@pytest.mark.parametrize("name", TEXTS)
def test_texts_compose_alike(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    fast, python = both_ways(read_yaml, TEXTS[name], monkeypatch)
    assert fast == python


@pytest.mark.parametrize("name", COMMENTED)
def test_texts_with_comments_compose_alike(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    fast, python = both_ways(read_yaml, COMMENTED[name], monkeypatch)
    assert fast == python


@pytest.mark.parametrize(
    ("name", "by_libyaml"),
    [
        ("above and below", True),
        ("indented in a map", True),
        ("in a flow", True),
        ("CR line breaks", True),
        ("in double quotes", False),  # the line is the string's text, not a comment
        ("a quoted key", False),
        ("a quote closing, then a tag", False),
        ("a tab elsewhere", False),
        ("not a comment after all", False),
    ],
)
def test_only_comments_hold_what_reads_apart(name: str, by_libyaml: bool) -> None:
    assert (yaml_tree._composed_alike(COMMENTED[name]) is not None) == by_libyaml


def test_the_bicycle_with_a_condition_in_its_comment_is_composed_by_libyaml() -> None:
    text = lg.examples.model_text("whipple_bicycle")
    assert ">" in text
    assert yaml_tree._composed_alike(text) is not None


def test_json_composes_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    text = '{"coordinates": ["x"],\n\t"potential": "x**2", "parameters": {"m": 1e-3}}'
    fast, python = both_ways(read_json, text, monkeypatch)
    assert fast == python


@pytest.mark.parametrize("text", ["a: [1, 2\n", "a: b: c\n", "a:\n\t- 1\n", "x: 'open\n"])
def test_syntax_errors_are_pyyaml_s(text: str, monkeypatch: pytest.MonkeyPatch) -> None:
    fast, python = both_ways(read_yaml, text, monkeypatch)
    assert isinstance(fast, str)
    assert fast == python


def test_nesting_far_beyond_the_limit_is_not_given_to_libyaml() -> None:
    # libyaml's composer recurses in C without a limit (100,000 levels end the process):
    # such a text goes to PyYAML, which refuses it as nested too deeply
    deep = 100_000
    with pytest.raises(ModelError, match="nested too deeply"):
        read_yaml("[" * deep + "]" * deep, "model.yaml")
