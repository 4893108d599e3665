"""The analysis report typeset: every part present, and parseable by matplotlib's mathtext."""

from __future__ import annotations

import pytest
from matplotlib.mathtext import MathTextParser

import lagrangian as lg
from lagrangian.render import analysis_latex
from lagrangian.render.analysis_latex import analysis_lines


@pytest.mark.parametrize("name", ["simple_pendulum", "double_pendulum", "planet"])
def test_report_lines_render(name: str) -> None:
    report = lg.analyze(lg.examples.get(name)())
    text = analysis_latex(report)
    assert text.startswith(r"\begin{align*}") and "H &=" in text
    parser = MathTextParser("path")
    for line in analysis_lines(report):
        if len(line) < 400:  # mathtext chokes on very long lines, not on the syntax
            parser.parse("$" + line.replace("&", "") + "$")


def test_unstable_and_stable_equilibria_are_named() -> None:
    text = analysis_latex(lg.analyze(lg.examples.simple_pendulum()))
    assert "(stable)" in text and "(unstable)" in text


def test_every_result_has_its_own_display() -> None:
    from lagrangian.render.analysis_latex import result_latex

    system = lg.examples.planet()
    report = lg.analyze(system, about={"r": 1.0, "theta_dot": 1.0})
    results = [
        report.momenta,
        report.energy,
        report.hamiltonian,
        report.equilibria,
        report.linearization,
        *report.cyclic,
        *lg.analysis.point_symmetries(system),
    ]
    parser = MathTextParser("path")
    for result in results:
        text = result_latex(result)
        assert text is not None and text.startswith(r"\begin{align*}")
        for line in text.splitlines()[1:-1]:
            line = line.rstrip("\\ ")
            if len(line) < 300 and "matrix" not in line:  # mathtext has no matrices
                parser.parse("$" + line.replace("&", "") + "$")
    assert r"\dot{\theta}" in result_latex(report.momenta)
    assert result_latex(object()) is None
