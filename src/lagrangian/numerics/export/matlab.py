"""export_matlab: one MATLAB/Octave function file per function of the equations of motion.

Indices count from 1 (``q(1)``); vectors are columns. ``rhs.m`` solves M q_ddot = forcing
with ``M \\ f``; ``default_parameters.m`` returns the model's parameter values (NaN where none).
"""

from __future__ import annotations

from sympy.printing.octave import OctaveCodePrinter

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.numerics.export.common import (
    RHS_SUMMARY,
    UNSORTED,
    ExportPlan,
    Routine,
    comment,
    literal,
    nonzero_entries_code,
    plan_export,
    temporaries_code,
)


def export_matlab(eom: EquationsOfMotion) -> dict[str, str]:
    """Function files ``mass_matrix.m``, ``coriolis.m``, ``gravity.m``,
    ``generalized_forces.m``, ``forcing.m``, ``rhs.m`` (regular M only) and
    ``default_parameters.m``, as file name -> content.

    >>> import lagrangian as lg
    >>> files = export_matlab(lg.derive(lg.examples.simple_pendulum()))
    >>> files["mass_matrix.m"].splitlines()[0]
    'function M = mass_matrix(q, t, p)'
    """
    plan = plan_export(eom, first_index=1)
    files = {f"{r.name}.m": _function(plan, r) for r in plan.routines}
    if plan.has_rhs:
        files["rhs.m"] = _rhs(plan)
        if plan.m:
            files["multipliers.m"] = _multipliers(plan)
    files["default_parameters.m"] = _defaults(plan)
    return files


def _help(plan: ExportPlan, name: str, summary: str) -> str:
    """The help text MATLAB shows for ``help name``: summary line, then the header."""
    header = plan.header(lambda base, i: f"{base}({i + 1})")
    return comment([f"{name.upper()}  {summary}", "", *header], "%")


def _function(plan: ExportPlan, routine: Routine) -> str:
    printer = OctaveCodePrinter(dict(UNSORTED))
    lines = [
        f"function {routine.output} = {routine.name}({', '.join(routine.arguments)})",
        _help(plan, routine.name, routine.summary),
    ]
    lines += [f"  {s} = {code};" for s, code in temporaries_code(routine, printer, "MATLAB")]
    rows, cols = routine.outputs.shape
    lines.append(f"  {routine.output} = zeros({rows}, {cols});")
    entries = nonzero_entries_code(routine, printer, "MATLAB", first_index=1)
    lines += [f"  {routine.output}({index}) = {code};" for index, code in entries]
    lines.append("end")
    return "\n".join(lines) + "\n"


def _solve(plan: ExportPlan) -> list[str]:
    n = plan.n
    matrix, vector = plan.solved
    return [
        "  x = x(:);",
        f"  q = x(1:{n});",
        f"  qd = x({n + 1}:{2 * n});",
        f"  {plan.solved_name} = {matrix}({plan.solved_call});",
        f"  y = {plan.solved_name} \\ {vector}(q, qd, t, p);",
    ]


def _rhs(plan: ExportPlan) -> str:
    return "\n".join(
        [
            "function dx = rhs(t, x, p)",
            _help(plan, "rhs", RHS_SUMMARY),
            *_solve(plan),
            f"  dx = [qd; y(1:{plan.n})];",
            "end",
            "",
        ]
    )


def _multipliers(plan: ExportPlan) -> str:
    return "\n".join(
        [
            "function lambda = multipliers(t, x, p)",
            _help(plan, "multipliers", "The Lagrange multipliers lambda at the state x."),
            *_solve(plan),
            f"  lambda = y({plan.n + 1}:end);",
            "end",
            "",
        ]
    )


def _defaults(plan: ExportPlan) -> str:
    values = "; ".join(literal(v, "NaN", "Inf") for _, v in plan.parameters)
    return "\n".join(
        [
            "function p = default_parameters()",
            _help(plan, "default_parameters", "The parameter vector p with the model's values."),
            f"  p = [{values}];" if plan.parameters else "  p = zeros(0, 1);",
            "end",
            "",
        ]
    )
