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
