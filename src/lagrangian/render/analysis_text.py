"""``lagrangian analyze --format text``: an analysis report for people, one section per part.

The degrees of freedom come first, with the difference between the dimension of the
configuration manifold and the number of independent velocities spelled out for a
non-holonomic system; then the constraints, momenta, cyclic coordinates (each with whether its
momentum is conserved and what changes it), conserved quantities (with their conditions), the
energy function, the Hamiltonian (or why there is none), equilibria, normal modes, the
linearization, and the parts that could not be computed.

>>> import lagrangian as lg
>>> text = analysis_text(lg.analyze(lg.examples.simple_pendulum()))
>>> text.splitlines()[0]
'simple_pendulum: 1 coordinate, no constraint: dof = 1'
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

import sympy as sp

from lagrangian.analysis import (
    AnalysisReport,
    ConservedQuantity,
    CyclicCoordinate,
    Equilibrium,
    Linearization,
)
from lagrangian.analysis.evaluation import condition_text
from lagrangian.render.text import SumPrinter
from lagrangian.render.values import values_text

#: How an expression is written (a :class:`SumPrinter`'s ``doprint``).
Writer = Callable[[sp.Basic], str]

VERDICTS = {True: "stable", False: "unstable", None: "stability undetermined"}


def _state(state: Mapping[sp.Symbol, Any]) -> str:
    return ", ".join(f"{q} = {v}" for q, v in state.items())


def _section(title: str, lines: Iterable[str]) -> list[str]:
    body = [f"  {line}" for line in lines]
    return ["", f"{title}:", *body] if body else []


def _cyclic_line(c: CyclicCoordinate) -> str:
    if c.conserved and c.condition == sp.true:
        verdict = "momentum conserved"
    elif c.conserved:
        verdict = f"momentum conserved when {condition_text(c.condition)}"
    else:
        verdict = f"momentum not conserved ({', '.join(c.obstructions)})"
    return f"{c.coordinate}: p_{c.coordinate} = {c.momentum}; {verdict}. {c.reason}"


def _holds(c: ConservedQuantity) -> str:
    """`` (holds when k1 = k2)``, and whether the parameter values given meet that."""
    if not c.conditions:
        return ""
    if c.holds:
        return f" (holds when {condition_text(c.condition)}, as here)"
    return f" (holds when {condition_text(c.condition)}; not for the parameter values given)"


def _condition(condition: sp.Basic) -> str:
    """A condition as people write it: ``F = 0`` for an equation between parameters (SymPy
    prints ``Eq(F, 0)``), inequalities as SymPy prints them."""
    return condition_text(condition) if condition.has(sp.Eq) else str(condition)


def equilibrium_state(e: Equilibrium) -> str:
    """``theta = 0, x free``: the fixed coordinates' values, then the family's free ones
    (``every configuration`` when none is fixed)."""
    free = {q for q in e.free}
    fixed = _state({q: v for q, v in e.state.items() if q not in free})
    if not free:
        return fixed
    names = ", ".join(str(q) for q in e.state if q in free)
    return f"{fixed}, {names} free" if fixed else f"every configuration ({names} free)"


def _equilibrium_line(e: Equilibrium) -> str:
    everywhere = e.stable is None and set(e.free) == set(e.state)
    verdict = "neutral" if everywhere else VERDICTS[e.stable]
    line = f"{equilibrium_state(e)}: {verdict} ({e.reason})"
    if e.multipliers:
        line += f"; multipliers {_state(e.multipliers)}"
    if e.condition != sp.true:
        line += f"; exists when {_condition(e.condition)}"
    return line


def _linearization_lines(lin: Linearization) -> list[str]:
    lines = [
        f"about {_state(lin.state)}",
        f"state vector x = ({', '.join(s.name for s in lin.state_vector)})",
    ]
    if lin.dependent:
        lines.append(
            "eliminated at the linear level (constraints): "
            + ", ".join(s.name for s in lin.dependent)
        )
    lines.append(f"A = {lin.A.tolist()}")
    if lin.A_at_values is not None:
        lines.append(f"A at the parameter values = {lin.A_at_values.tolist()}")
    if lin.inputs:
        lines.append(f"B = {lin.B.tolist()} (inputs {', '.join(u.name for u in lin.inputs)})")
    lines += [
        f"eigenvalues: {', '.join(str(v) for v in lin.eigenvalues) or 'none'}",
        f"frequencies (rad/s): {', '.join(str(w) for w in lin.frequencies) or 'none'}",
        f"growth rates (1/s): {', '.join(str(g) for g in lin.growth_rates) or 'none'}",
        lin.note,
    ]
    return lines


def _conserved_line(report: AnalysisReport, c: ConservedQuantity, write: Writer) -> str:
    """``name = expression (holds when ...)  [origin]``; the energy function is written once,
    in its own section (a chain's has n^2 terms)."""
    energy = report.energy
    if energy is not None and c.expression is energy.energy_function:
        value = f"{c.name}: the energy function (below)"
    else:
        value = f"{c.name} = {write(c.expression)}"
    return f"{value}{_holds(c)}" + (f"  [{c.origin}]" if c.origin else "")


def _energy_lines(report: AnalysisReport, write: Writer) -> list[str]:
    energy = report.energy
    if energy is None:
        return []
    verdict = "conserved" if energy.conserved else "not conserved"
    if energy.conserved and energy.condition != sp.true:
        verdict = f"conserved when {condition_text(energy.condition)}, as here"
    h = report.names.energy
    lines = [f"{h} = {write(energy.energy_function)}", f"d{h}/dt = {energy.rate}: {verdict}"]
    lines.append(energy.reason)
    if energy.equals_total_energy:
        lines.append(f"{h} = T + V")
    else:
        lines.append(energy.total_energy_reason)
    return lines


def _hamiltonian_lines(report: AnalysisReport) -> list[str]:
    legendre = report.hamiltonian
    if legendre is None:
        return [f"none: {report.failure('hamiltonian')}"]
    # the velocities q_dot(q, p) of several links nest the same quotients many times: one
    # printer writes each once
    text = SumPrinter().doprint
    lines = [f"{report.names.hamiltonian} = {text(legendre.hamiltonian)}", legendre.reason]
    canonical = report.hamilton_equations
    if canonical is not None:
        for q, rate in zip(canonical.coordinates, canonical.coordinate_rates):
            lines.append(f"{q}_dot = {text(rate)}")
        for p, rate in zip(canonical.momenta, canonical.momentum_rates):
            lines.append(f"{p}_dot = {text(rate)}")
    elif report.failure("hamilton_equations"):
        lines.append(f"Hamilton's equations: none: {report.failure('hamilton_equations')}")
    return lines


def values_line(report: AnalysisReport) -> str:
    """The parameter values the statements are decided at (the general case is said where
    it differs)."""
    return f"at {values_text(report.parameter_values)} (where the general case differs, it is said)"


def _constraint_line(kind: str, expression: object, reason: str) -> str:
    """``unilateral y >= 0: ...``: the constraint as declared, then its classification (the
    declared kind said once where the classification begins with it).

    >>> _constraint_line("unilateral", "y", "unilateral: the inequality ...")
    'y >= 0: unilateral: the inequality ...'
    >>> _constraint_line("velocity", "x_dot - r*phi_dot", "non-holonomic: ...")
    'velocity x_dot - r*phi_dot = 0: non-holonomic: ...'
    """
    relation = ">=" if kind == "unilateral" else "="
    declared = "" if reason.startswith(f"{kind}:") else f"{kind} "
    return f"{declared}{expression} {relation} 0: {reason}"


def analysis_text(report: AnalysisReport) -> str:
    """The report as plain text (see the module docstring)."""
    # one printer for the report: a chain's sums of masses recur in every momentum and in h,
    # each written once (text as sympy.sstr's)
    write = SumPrinter().doprint
    lines = [f"{report.name or 'system'}: {report.freedom or f'dof = {report.dof}'}"]
    if report.parameter_values:
        lines.append(values_line(report))
    lines += _section(
        "Constraints",
        (_constraint_line(c.kind, c.expression, c.reason) for c in report.constraints),
    )
    forces = report.constraint_forces
    if forces is not None:
        solved = forces.solved
        lines += _section(
            "Constraint forces (each multiplier solved for the state)",
            [forces.reason] if solved is None else (f"{k} = {v}" for k, v in solved.items()),
        )
    if report.momenta is not None:
        momenta = report.momenta
        lines += _section(
            "Momenta",
            (
                f"{report.names.momentum(q)} = {write(p)}"
                for q, p in zip(momenta.coordinates, momenta.momenta)
            ),
        )
    lines += _section("Cyclic coordinates (absent from L and F)", map(_cyclic_line, report.cyclic))
    lines += _section("Conserved", (_conserved_line(report, c, write) for c in report.conserved))
    lines += _section("Search for first integrals", report.searched)
    lines += _section("Energy function", _energy_lines(report, write))
    lines += _section("Hamiltonian", _hamiltonian_lines(report))
    if report.equilibria is not None:
        found = [_equilibrium_line(e) for e in report.equilibria]
        partial = report.equilibria.count is not None  # only some of them listed: say so
        if (
            report.equilibria.method == "numeric"
            or not found
            or report.equilibria.general
            or partial
        ):
            found.append(f"({report.equilibria.reason})")  # how far the search went
        lines += _section("Equilibria", found)
    if report.steady_motions is not None:
        steady = report.steady_motions
        lines += _section(
            "Steady motions (moving with the constraints)",
            [
                f"{report.names.effective_potential} = {steady.effective_potential}; "
                f"{steady.reason}",
                *(
                    f"{_equilibrium_line(e)}; velocities {_state(v)}"
                    for e, v in zip(steady.motions, steady.velocities)
                    if e.exists is not False
                ),
            ],
        )
    if report.normal_modes is not None:
        modes = report.normal_modes
        lines += _section(
            "Normal modes",
            [
                f"about {_state(modes.about)}: {modes.reason}",
                *(
                    f"{report.names.frequency} = {w}, shape {list(v)}"
                    for w, v in zip(modes.frequencies, modes.shapes)
                ),
            ],
        )
    if report.linearization is not None:
        lines += _section("Linearization", _linearization_lines(report.linearization))
    # the Hamiltonian's section gives its reason (and that of Hamilton's equations)
    told = {"hamiltonian"} if report.hamiltonian is None else {"hamilton_equations"}
    lines += _section(
        "Not computed",
        (
            f"{f.part}: {'the reason is under Hamiltonian' if f.part in told else f.reason}"
            for f in report.failures
        ),
    )
    return "\n".join(lines)
