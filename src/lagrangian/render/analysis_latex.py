"""An analysis report as LaTeX, for Jupyter: momenta, conserved quantities, the Hamiltonian,
equilibria with their stability, normal modes and the linearization.

>>> import lagrangian as lg
>>> text = analysis_latex(lg.analyze(lg.examples.simple_pendulum()))
>>> r"p_{\\theta}" in text
True
"""

from __future__ import annotations

import sympy as sp

from lagrangian.analysis import (
    AnalysisReport,
    ConjugateMomenta,
    CyclicCoordinate,
    EnergyConservation,
    Equilibria,
    Hamiltonian,
    Linearization,
    NormalModes,
    Symmetry,
)
from lagrangian.render.constrained import FORCES_HEADING
from lagrangian.render.latex import KeptLatexPrinter, block, symbol_names
from lagrangian.render.values import values_latex
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_small

#: Operations beyond which an expression is not typeset (sympy.latex takes seconds per
#: ten thousand operations, and a page of them says nothing): it is named, with its size.
TYPESET_OPERATIONS = 20_000
#: Characters that LaTeX text mode does not take as they are (reasons quote formulas).
_ESCAPES = {"_": r"\_", "&": r"\&", "%": r"\%", "#": r"\#", "$": r"\$", "{": r"\{", "}": r"\}"}


def _text(words: str) -> str:
    escaped = "".join(_ESCAPES.get(ch, ch) for ch in words).replace("^", r"\^{}")
    return r"\text{" + escaped + "}"


def analysis_lines(report: AnalysisReport) -> list[str]:
    """One aligned line per result, parts that failed said as such."""
    names = symbol_names(report.coordinates)
    # one printer for the report: a chain's sums of masses recur in every momentum and in h,
    # each typeset once (the text as sympy.latex's)
    printer = KeptLatexPrinter({"symbol_names": names})

    def tex(expr: sp.Basic) -> str:
        expr = to_sympy(expr)
        if not is_small(expr, TYPESET_OPERATIONS):  # the Hamiltonian of five links or more
            return _text(
                f"(more than {TYPESET_OPERATIONS:,} operations: too long to typeset; the "
                "text and JSON reports write it out)"
            )
        return printer.doprint(_shown(expr))

    lines = [rf"&{_text(report.name or 'system')}:\ {report.dof}\ {_text('degrees of freedom')}"]
    if report.parameter_values:
        values = values_latex(report.parameter_values, tex)
        lines.append(rf"&{_text('at')}\ {values}")
    if report.freedom and report.configuration_dimension != report.independent_velocities:
        lines.append(rf"&{_text(report.freedom)}")
    forces = report.constraint_forces
    if forces is not None and forces.solved is not None:
        lines.append(FORCES_HEADING)
        lines += [rf"{tex(k)} &= {tex(v)}" for k, v in forces.solved.items()]
    elif forces is not None:
        lines.append(rf"&{_text('constraint forces ' + forces.reason)}")
    if report.momenta is not None:
        for q, p in zip(report.coordinates, report.momenta.momenta):
            lines.append(rf"{tex(sp.Symbol(report.names.momentum(q)))} &= {tex(p)}")
    for c in report.cyclic:
        verdict = "conserved" if c.conserved else "not conserved: " + ", ".join(c.obstructions)
        lines.append(rf"&{tex(c.coordinate)}\ {_text('cyclic; momentum ' + verdict)}")
    for quantity in report.conserved:
        when = ""
        if quantity.conditions:
            relations = ", ".join(f"{r.lhs} = {r.rhs}" for r in quantity.conditions)
            here = "as here" if quantity.holds else "not for the parameter values given"
            when = f" holds when {relations}, {here}"
        origin = f"; {quantity.origin}" if quantity.origin else ""
        verdict = "(" + (when.strip() if when else "conserved") + origin + ")"
        lines.append(rf"{_text(quantity.name)} &= {tex(quantity.expression)}\quad {_text(verdict)}")
    if report.energy is not None and not report.energy.conserved:
        h = tex(sp.Symbol(report.names.energy))
        lines.append(
            rf"\frac{{d{h}}}{{dt}} &= {tex(report.energy.rate)}\quad "
            + _text(f"({report.names.energy} not conserved)")
        )
    if report.hamiltonian is not None:
        H = tex(sp.Symbol(report.names.hamiltonian))
        lines.append(rf"{H} &= {tex(report.hamiltonian.hamiltonian)}")
    if report.equilibria is not None:
        for e in report.equilibria.equilibria:
            fixed = [f"{tex(q)} = {tex(v)}" for q, v in e.state.items() if q not in e.free]
            free = [tex(q) for q in e.state if q in e.free]
            if free:
                fixed.append(",\\ ".join(free) + r"\ " + _text("free"))
            state = ",\\ ".join(fixed)
            verdict = {True: "stable", False: "unstable", None: "undetermined"}[e.stable]
            if e.stable is None and set(e.free) == set(e.state):
                verdict = "neutral"
            lines.append(rf"&{_text('equilibrium')}\ {state}\ {_text('(' + verdict + ')')}")
            if e.multipliers:
                held = ",\\ ".join(f"{tex(k)} = {tex(v)}" for k, v in e.multipliers.items())
                lines.append(rf"&\quad {held}")
        if not report.equilibria.equilibria:
            lines.append(rf"&{_text('no equilibrium: ' + report.equilibria.reason)}")
        elif report.equilibria.general:  # what holds for other parameter values
            lines.append(rf"&{_text(report.equilibria.general)}")
        if report.equilibria.equilibria and report.equilibria.count is not None:
            lines.append(rf"&{_text(report.equilibria.reason)}")  # only some listed
    if report.steady_motions is not None:
        for e in report.steady_motions.motions:
            if e.exists is False:
                continue
            state = ",\\ ".join(f"{tex(q)} = {tex(v)}" for q, v in e.state.items())
            verdict = {True: "stable", False: "unstable", None: "undetermined"}[e.stable]
            words = _text("steady motion with the constraints")
            lines.append(rf"&{words}\ {state}\ {_text('(' + verdict + ')')}")
    if report.normal_modes is not None:
        values = ",\\ ".join(tex(w) for w in report.normal_modes.frequencies)
        lines.append(rf"{tex(sp.Symbol(report.names.frequency))} &\in \{{{values}\}}")
    if report.linearization is not None:
        values = ",\\ ".join(tex(v) for v in report.linearization.eigenvalues)
        lines.append(rf"&{_text('eigenvalues of A')}:\ {values}")
        if report.linearization.dependent:
            gone = ", ".join(s.name for s in report.linearization.dependent)
            lines.append(rf"&{_text('eliminated on the constraint manifold: ' + gone)}")
    for failure in report.failures:
        lines.append(rf"&{_text('not computed: ' + failure.part + ': ' + failure.reason)}")
    return lines


def analysis_latex(report: AnalysisReport, environment: str = "align*") -> str:
    """The report as one aligned LaTeX block."""
    return block(analysis_lines(report), environment)


def _shown(expr: sp.Basic) -> sp.Basic:
    """``expr`` with its floating-point numbers at six significant digits, as the text report
    writes them (5.19615, not 5.19615242270663): a frequency is read, not computed with."""
    floats = expr.atoms(sp.Float)
    return (
        expr.xreplace({f: sp.Float(float(f"{float(f):.6g}")) for f in floats}) if floats else expr
    )


def _tex(expr: object) -> str:
    """LaTeX of an expression whose velocities are written NAME_dot (dotted by name)."""
    value = _shown(to_sympy(expr))
    coordinates = {
        sp.Symbol(s.name.removesuffix("_ddot").removesuffix("_dot")) for s in value.free_symbols
    }
    return sp.latex(value, symbol_names=symbol_names(coordinates))


def _equilibrium_lines(found: Equilibria) -> list[str]:
    verdicts = {True: "stable", False: "unstable", None: "undetermined"}
    return [
        ",\\ ".join(f"{_tex(q)} = {_tex(v)}" for q, v in e.state.items())
        + rf"\quad {_text(verdicts[e.stable])}"
        for e in found.equilibria
    ]


SEPARATOR = ",\\ "

#: The analysis results that have their own display.
RESULT_TYPES = (
    ConjugateMomenta,
    EnergyConservation,
    Hamiltonian,
    Equilibria,
    NormalModes,
    Linearization,
    Symmetry,
    CyclicCoordinate,
)


def result_latex(result: object) -> str | None:
    """LaTeX of one analysis result (momenta, energy, Hamiltonian, equilibria, modes,
    linearization, symmetry, cyclic coordinate); None for anything else."""
    lines: list[str]
    if isinstance(result, ConjugateMomenta):
        lines = [
            rf"p_{{{_tex(q)}}} &= {_tex(p)}" for q, p in zip(result.coordinates, result.momenta)
        ]
    elif isinstance(result, EnergyConservation):
        verdict = "conserved" if result.conserved else "not conserved"
        lines = [
            rf"h &= {_tex(result.energy_function)}",
            rf"\frac{{dh}}{{dt}} &= {_tex(result.rate)}\quad {_text(verdict)}",
        ]
    elif isinstance(result, Hamiltonian):
        lines = [rf"H &= {_tex(result.hamiltonian)}"]
    elif isinstance(result, Equilibria):
        lines = [f"&{line}" for line in _equilibrium_lines(result)] or [rf"&{_text('none')}"]
    elif isinstance(result, NormalModes):
        lines = [rf"\omega_{{{i + 1}}} &= {_tex(w)}" for i, w in enumerate(result.frequencies)]
    elif isinstance(result, Linearization):
        lines = [
            rf"A &= {_tex(result.A)}",
            rf"\lambda &\in \{{{SEPARATOR.join(_tex(v) for v in result.eigenvalues)}\}}",
        ]
    elif isinstance(result, Symmetry):
        lines = [
            rf"&{_text(result.description)}:\ {_tex(result.conserved)} = "
            rf"{_text('const')}"
        ]
    elif isinstance(result, CyclicCoordinate):
        lines = [
            rf"p_{{{_tex(result.coordinate)}}} &= {_tex(result.momentum)} = "
            rf"{_text('const')}"
        ]
    else:
        return None
    return block(lines)
