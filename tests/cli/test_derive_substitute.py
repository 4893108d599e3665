"""derive shows the parameter values in force and, with --substitute, the equations with
them put in: in text, LaTeX and JSON, for mechanical, 3-D, constrained, driven and electrical
systems.  The reference is the symbolic equations with the values substituted afterwards."""

from __future__ import annotations

import html
import json
import re

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.cli.main import main

KINDS = (
    "double_pendulum",  # planar chain
    "heavy_symmetric_top",  # 3-D rigid body
    "dumbbell",  # holonomic constraint
    "moving_pivot_pendulum",  # explicit time
    "series_rlc",  # circuit
)


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def test_the_values_asked_for_are_shown_and_put_in(capsys: pytest.CaptureFixture[str]) -> None:
    symbolic = run(capsys, "derive", "examples/double_pendulum", "--set", "m1=2")
    assert "g*l1*(m1 + m2)*sin(theta)" in symbolic
    assert symbolic.rstrip().endswith(
        "Parameters: m1 = 2, m2 = 1, l1 = 1, l2 = 1, g = 9.81 (derive --substitute puts them in)"
    )
    numeric = run(capsys, "derive", "examples/double_pendulum", "--set", "m1=2", "--substitute")
    # By hand: (m1 + m2) l1^2 = 3 and g l1 (m1 + m2) = 29.43 in the theta equation.
    assert "3*theta_ddot + 29.43*sin(theta)" in numeric
    assert "(put in)" in numeric and "m1" not in numeric.splitlines()[0]
    latex = run(capsys, "derive", "examples/double_pendulum", "--substitute", "--format", "latex")
    assert r"2 \ddot{\theta} + 19.62 \sin{\left(\theta \right)}" in latex
    assert latex.rstrip().endswith(r"g = 9.81 \]")


@pytest.mark.parametrize("name", KINDS)
def test_substituted_equations_are_the_symbolic_ones_with_the_values(
    capsys: pytest.CaptureFixture[str], name: str
) -> None:
    system = lg.examples.get(name)()
    eom = lg.derive(system)
    values = {p: v for p, v in eom.parameters.items() if v is not None}
    document = json.loads(
        run(capsys, "derive", f"examples/{name}", "--substitute", "--format", "json")
    )
    assert document["parameters"] == {}
    states = [*eom.coordinates, *eom.velocities, *eom.accelerations, eom.time]
    local = {s.name: s for s in states}
    rng = np.random.default_rng(3)
    for given, expected in zip(document["equations"], eom.equations, strict=True):
        parsed = sp.parse_expr(given, local_dict=local)
        assert not parsed.free_symbols - set(states)
        for _ in range(3):
            point = dict(zip(states, rng.uniform(0.2, 1.3, len(states)), strict=True))
            want = float(expected.xreplace(values).xreplace(point))
            got = float(parsed.xreplace(point))
            assert got == pytest.approx(want, rel=1e-9, abs=1e-9 * max(1.0, abs(want)))
    text = run(capsys, "derive", f"examples/{name}", "--substitute")
    assert text.rstrip().endswith("(put in)")


def test_substituted_mathml_holds_the_numbers_by_hand(capsys: pytest.CaptureFixture[str]) -> None:
    mathml = run(
        capsys,
        "derive",
        "examples/double_pendulum",
        "--set",
        "m1=2",
        "--substitute",
        "--format",
        "mathml",
    )
    # By hand, as in the text: (m1 + m2) l1^2 = 3 and g l1 (m1 + m2) = 29.43.
    assert "<mn>3</mn>" in mathml and "<mn>29.43</mn>" in mathml


@pytest.mark.parametrize("name", KINDS)
def test_substituted_mathml_names_no_parameter(
    capsys: pytest.CaptureFixture[str], name: str
) -> None:
    system = lg.examples.get(name)()
    symbolic = run(capsys, "derive", f"examples/{name}", "--format", "mathml")
    numeric = run(capsys, "derive", f"examples/{name}", "--substitute", "--format", "mathml")
    identifiers = set(re.findall(r"<mi>([^<]+)</mi>", numeric))
    symbolic_identifiers = set(re.findall(r"<mi>([^<]+)</mi>", symbolic))
    given = {html.unescape(p.name) for p, v in system.parameters.items() if v is not None}
    # a parameter's name (its first letter, as MathML writes m_1 as <mi>m</mi>) is an
    # identifier of the symbolic equations and of none of the substituted ones
    letters = {html.unescape(i) for i in symbolic_identifiers - identifiers}
    assert letters, f"{name}: the substituted MathML still names every identifier"
    assert {name[0] for name in given} & letters
    assert numeric.count("<mtr>") == symbolic.count("<mtr>")
