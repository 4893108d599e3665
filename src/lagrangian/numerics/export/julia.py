"""export_julia: a Julia module of the equations of motion.

Indices count from 1 (``q[1]``). Results take the element type of the arguments (so
ForwardDiff dual numbers pass through); ``rhs`` solves M q_ddot = forcing with ``M \\ f``.
For DifferentialEquations.jl wrap it as ``(u, p, t) -> rhs(t, u, p)``.
"""

from __future__ import annotations

import json

from sympy.printing.julia import JuliaCodePrinter

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.numerics.export.common import (
    RHS_SUMMARY,
    UNSORTED,
    ExportPlan,
    Routine,
    camel_case,
    comment,
    literal,
    nonzero_entries_code,
    plan_export,
    temporaries_code,
)


class _Printer(JuliaCodePrinter):
    """Julia printer spelling Euler's number ``exp(1)``: Julia has no plain ``e``."""

    def _print_Exp1(self, expr: object) -> str:
        return "exp(1)"


def export_julia(eom: EquationsOfMotion) -> str:
    """The source of a Julia module with M, C qd, G, Q, forcing and rhs.

    >>> import lagrangian as lg
    >>> source = export_julia(lg.derive(lg.examples.simple_pendulum()))
    >>> "module SimplePendulum" in source
    True
    """
    plan = plan_export(eom, first_index=1)
    solvers = (["rhs", "multipliers"] if plan.m else ["rhs"]) if plan.has_rhs else []
    names = [r.name for r in plan.routines] + solvers
    parts = [
        comment(plan.header(lambda base, i: f"{base}[{i + 1}]"), "#"),
        f"module {camel_case(plan.base)}",
        f"export {', '.join(names)}",
        _constants(plan),
        *(_function(r) for r in plan.routines),
        _rhs(plan) if plan.has_rhs else "# No rhs: the mass matrix is singular (see the top).",
        "end # module",
    ]
    return "\n\n".join(parts) + "\n"


def _constants(plan: ExportPlan) -> str:
    coordinates = [julia_string(q) for q in plan.coordinates]
    names = [julia_string(name) for name, _ in plan.parameters]
    values = [literal(v, "NaN", "Inf") for _, v in plan.parameters]
    return "\n".join(
        [
            f"const COORDINATES = {_vector(coordinates, 'String[]')}",
            f"const PARAMETERS = {_vector(names, 'String[]')}",
            f"const DEFAULTS = {_vector(values, 'Float64[]')}  # NaN: no default",
        ]
    )


def julia_string(text: str) -> str:
    """A Julia string literal of ``text``: JSON's escapes, and ``$`` escaped, since Julia
    interpolates ``$(...)`` inside strings (a name must never run code)."""
    return json.dumps(text).replace("$", "\\$")


def _vector(items: list[str], empty: str) -> str:
    return f"[{', '.join(items)}]" if items else empty


def _docstring(signature: str, summary: str) -> str:
    return f'"""\n    {signature}\n\n{summary}\n"""'


def _function(routine: Routine) -> str:
    printer = _Printer(dict(UNSORTED))
    signature = f"{routine.name}({', '.join(routine.arguments)})"
    lines = [_docstring(signature, routine.summary), f"function {signature}"]
    lines += [f"    {s} = {code}" for s, code in temporaries_code(routine, printer, "Julia")]
    rows, cols = routine.outputs.shape
    shape = f"{rows}, {cols}" if routine.is_matrix else f"{rows}"
    element = "promote_type(eltype(q), typeof(t), eltype(p)" + (
        ", eltype(qd))" if "qd" in routine.arguments else ")"
    )
    lines.append(f"    {routine.output} = zeros({element}, {shape})")
    entries = nonzero_entries_code(routine, printer, "Julia", first_index=1)
    lines += [f"    {routine.output}[{index}] = {code}" for index, code in entries]
    lines += [f"    return {routine.output}", "end"]
    return "\n".join(lines)


def _rhs(plan: ExportPlan) -> str:
    n = plan.n
    matrix, vector = plan.solved
    solve = [
        f"    q = x[1:{n}]",
        f"    qd = x[{n + 1}:{2 * n}]",
        f"    {plan.solved_name} = {matrix}({plan.solved_call})",
        f"    y = {plan.solved_name} \\ {vector}(q, qd, t, p)",
    ]
    parts = [
        "\n".join(
            [
                _docstring("rhs(t, x, p)", RHS_SUMMARY),
                "function rhs(t, x, p)",
                *solve,
                f"    return vcat(qd, y[1:{n}])",
                "end",
            ]
        )
    ]
    if plan.m:
        parts.append(
            "\n".join(
                [
                    _docstring("multipliers(t, x, p)", "The Lagrange multipliers at the state x."),
                    "function multipliers(t, x, p)",
                    *solve,
                    f"    return y[{n + 1}:end]",
                    "end",
                ]
            )
        )
    return "\n\n".join(parts)
