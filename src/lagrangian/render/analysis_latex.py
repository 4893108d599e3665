"""An analysis report as LaTeX, for Jupyter: momenta, conserved quantities, the Hamiltonian,
equilibria with their stability, normal modes and the linearization.

>>> import lagrangian as lg
>>> text = analysis_latex(lg.analyze(lg.examples.simple_pendulum()))
>>> r"p_{\\theta}" in text
True
"""

from __future__ import annotations

import sympy as sp

from lagrangian.analysis import AnalysisReport
from lagrangian.render.latex import block, symbol_names


def _text(words: str) -> str:
    return r"\text{" + words.replace("_", r"\_").replace("&", r"\&") + "}"


def analysis_lines(report: AnalysisReport) -> list[str]:
    """One aligned line per result, parts that failed said as such."""
    names = symbol_names(report.coordinates)

    def tex(expr: sp.Basic) -> str:
        return sp.latex(sp.sympify(expr), symbol_names=names)

    lines = [rf"&{_text(report.name or 'system')}:\ {report.dof}\ {_text('degrees of freedom')}"]
    if report.momenta is not None:
        for q, p in zip(report.coordinates, report.momenta.momenta):
            lines.append(rf"p_{{{tex(q)}}} &= {tex(p)}")
    for quantity in report.conserved:
        lines.append(
            rf"{_text(quantity.name)} &= {tex(quantity.expression)}"
            rf"\quad {_text('(conserved)')}"
        )
    if report.hamiltonian is not None:
        lines.append(rf"H &= {tex(report.hamiltonian.hamiltonian)}")
    if report.equilibria is not None:
        for e in report.equilibria.equilibria:
            state = ",\\ ".join(f"{tex(q)} = {tex(v)}" for q, v in e.state.items())
            verdict = {True: "stable", False: "unstable", None: "undetermined"}[e.stable]
            lines.append(rf"&{_text('equilibrium')}\ {state}\ {_text('(' + verdict + ')')}")
    if report.normal_modes is not None:
        values = ",\\ ".join(tex(w) for w in report.normal_modes.frequencies)
        lines.append(rf"\omega &\in \{{{values}\}}")
    if report.linearization is not None:
        values = ",\\ ".join(tex(v) for v in report.linearization.eigenvalues)
        lines.append(rf"&{_text('eigenvalues of A')}:\ {values}")
    for failure in report.failures:
        lines.append(rf"&{_text(failure.part + ': ' + failure.reason)}")
    return lines


def analysis_latex(report: AnalysisReport, environment: str = "align*") -> str:
    """The report as one aligned LaTeX block."""
    return block(analysis_lines(report), environment)
