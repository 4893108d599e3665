"""export_c: C99 source and header of the equations of motion, no library but libm.

Every function is prefixed with the model's name (``double_pendulum_mass_matrix``) and writes
its result into a caller-provided array (the mass matrix row-major, ``M[n*i + j]``).
``NAME_rhs`` solves M q_ddot = forcing with a small Gaussian elimination with partial
pivoting written into the source, and returns -1 when a pivot is exactly zero.
"""

from __future__ import annotations

import re

import sympy as sp
from sympy.printing.c import C99CodePrinter, get_math_macros

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.numerics.export.common import (
    RHS_SUMMARY,
    UNSORTED,
    ExportPlan,
    Routine,
    comment,
    literal,
    one_line,
    plan_export,
    print_code,
    temporaries_code,
)

_SOLVER = """\
/* Solves A y = b in place (A row-major n x n is overwritten, b becomes y) by Gaussian
 * elimination with partial pivoting. Returns 0, or -1 when a pivot is exactly zero. */
static int solve_in_place(int n, double *A, double *b)
{
    for (int k = 0; k < n; ++k) {
        int pivot = k;
        for (int i = k + 1; i < n; ++i) {
            if (fabs(A[n * i + k]) > fabs(A[n * pivot + k])) {
                pivot = i;
            }
        }
        if (A[n * pivot + k] == 0.0) {
            return -1;
        }
        if (pivot != k) {
            for (int j = 0; j < n; ++j) {
                const double swap = A[n * k + j];
                A[n * k + j] = A[n * pivot + j];
                A[n * pivot + j] = swap;
            }
            const double swap = b[k];
            b[k] = b[pivot];
            b[pivot] = swap;
        }
        for (int i = k + 1; i < n; ++i) {
            const double factor = A[n * i + k] / A[n * k + k];
            for (int j = k; j < n; ++j) {
                A[n * i + j] -= factor * A[n * k + j];
            }
            b[i] -= factor * b[k];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        double sum = b[i];
        for (int j = i + 1; j < n; ++j) {
            sum -= A[n * i + j] * b[j];
        }
        b[i] = sum / A[n * i + i];
    }
    return 0;
}"""


def export_c(eom: EquationsOfMotion, name: str | None = None) -> tuple[str, str]:
    """(source, header) of C99 functions for M, C qd, G, Q, forcing and rhs.

    ``name`` (default: the system's name) prefixes every function and names the files;
    the source includes ``"NAME.h"``.

    >>> import lagrangian as lg
    >>> source, header = export_c(lg.derive(lg.examples.simple_pendulum()))
    >>> "int simple_pendulum_rhs(double t, const double *x, const double *p, double *dx);" in header
    True
    """
    plan = plan_export(eom, first_index=0, name=name)
    return _source(plan), _header(plan)


def _block_comment(lines: list[str]) -> str:
    safe = [line.replace("*/", "* /") for line in lines]
    return "/*\n" + comment(safe, " *") + "\n */"


def _signature(plan: ExportPlan, routine: Routine) -> str:
    types = {"q": "const double *q", "qd": "const double *qd", "t": "double t"}
    args = [types.get(a, "const double *p") for a in routine.arguments]
    return f"void {plan.base}_{routine.name}({', '.join(args)}, double *{routine.output})"


def _rhs_signature(plan: ExportPlan) -> str:
    return f"int {plan.base}_rhs(double t, const double *x, const double *p, double *dx)"


def _routine_doc(routine: Routine) -> str:
    layout = f" Row-major: [{routine.outputs.cols}*i + j]." if routine.is_matrix else ""
    return f"/* {routine.summary}{layout} */"


def _header(plan: ExportPlan) -> str:
    guard = plan.base.upper() + "_H"
    macro = plan.base.upper()
    lines = [
        _block_comment(plan.header(lambda base, i: f"{base}[{i}]")),
        f"#ifndef {guard}\n#define {guard}",
        '#ifdef __cplusplus\nextern "C" {\n#endif',
        f"#define {macro}_N_COORDINATES {plan.n}\n"
        f"#define {macro}_N_PARAMETERS {len(plan.parameters)}",
    ]
    if plan.parameters:
        lines.append(
            "/* Parameter defaults in the order of p (NAN where the model gives none). */\n"
            f"extern const double {plan.base}_defaults[{macro}_N_PARAMETERS];"
        )
    lines += [f"{_routine_doc(r)}\n{_signature(plan, r)};" for r in plan.routines]
    if plan.has_rhs:
        lines.append(
            f"/* {RHS_SUMMARY}\n * x and dx have 2*{plan.n} elements. Returns 0, or -1 when M is "
            f"singular at this state. */\n{_rhs_signature(plan)};"
        )
        if plan.m:
            lines.append(
                f"/* The {plan.m} Lagrange multipliers at the state x. Returns 0, or -1 when "
                f"the augmented matrix is singular. */\n{_multipliers_signature(plan)};"
            )
    else:
        lines.append("/* No rhs: the mass matrix is singular (see the comment at the top). */")
    lines += ["#ifdef __cplusplus\n}\n#endif", f"#endif /* {guard} */"]
    return "\n\n".join(lines) + "\n"


def _source(plan: ExportPlan) -> str:
    bodies = [_function(plan, r) for r in plan.routines]
    parts = [
        _block_comment(plan.header(lambda base, i: f"{base}[{i}]")),
        f'#include <math.h>\n\n#include "{plan.base}.h"',
    ]
    fallbacks = _macro_fallbacks("\n".join(bodies))
    if fallbacks:
        parts.append(fallbacks)
    if plan.parameters:
        values = ", ".join(literal(v, "NAN", "INFINITY") for _, v in plan.parameters)
        names = ", ".join(one_line(name) for name, _ in plan.parameters)
        parts.append(
            f"/* {names} */\nconst double {plan.base}_defaults"
            f"[{plan.base.upper()}_N_PARAMETERS] = {{{values}}};"
        )
    parts += bodies
    parts += [_SOLVER, _rhs(plan)] if plan.has_rhs else []
    parts += [_multipliers(plan)] if plan.has_rhs and plan.m else []
    return "\n\n".join(parts) + "\n"


def _macro_fallbacks(code: str) -> str:
    """Define the math.h constants the code uses: strict C99 (-std=c99) does not."""
    values: dict[str, sp.Basic] = {}
    for expr, name in get_math_macros().items():
        value = sp.N(expr, 21)  # some keys are codegen nodes (Sqrt) that stay symbolic
        if value.is_Float:
            values.setdefault(name, value)
    used = sorted(set(re.findall(r"\bM_[0-9A-Z_]+\b", code)) & set(values))
    return "\n".join(f"#ifndef {m}\n#define {m} {values[m]}\n#endif" for m in used)


def _function(plan: ExportPlan, routine: Routine) -> str:
    printer = C99CodePrinter(dict(UNSORTED))
    lines = [_routine_doc(routine), _signature(plan, routine), "{"]
    lines += [f"    (void){a};" for a in routine.arguments if not routine.uses(a)]
    lines += [
        f"    const double {s} = {code};" for s, code in temporaries_code(routine, printer, "C")
    ]
    for k, (_, _, expr) in enumerate(routine.entries()):
        lines.append(f"    {routine.output}[{k}] = {print_code(printer, expr, 'C')};")
    lines.append("}")
    return "\n".join(lines)


def _solve(plan: ExportPlan) -> list[str]:
    """The body lines that solve M q_ddot = forcing (or the augmented system) into y."""
    size = plan.n + plan.m
    matrix, vector = plan.solved
    return [
        "    const double *q = x;",
        f"    const double *qd = x + {plan.n};",
        f"    double K[{size * size}];",
        f"    double y[{size}];",
        f"    {plan.base}_{matrix}({plan.solved_call}, K);",
        f"    {plan.base}_{vector}(q, qd, t, p, y);",
        f"    if (solve_in_place({size}, K, y) != 0) {{",
        "        return -1;",
        "    }",
    ]


def _multipliers_signature(plan: ExportPlan) -> str:
    return (
        f"int {plan.base}_multipliers(double t, const double *x, const double *p, double *lambda)"
    )


def _multipliers(plan: ExportPlan) -> str:
    return "\n".join(
        [
            "/* The Lagrange multipliers lambda at the state x. */",
            _multipliers_signature(plan),
            "{",
            *_solve(plan),
            f"    for (int j = 0; j < {plan.m}; ++j) {{",
            f"        lambda[j] = y[{plan.n} + j];",
            "    }",
            "    return 0;",
            "}",
        ]
    )


def _rhs(plan: ExportPlan) -> str:
    n = plan.n
    return "\n".join(
        [
            f"/* {RHS_SUMMARY} */",
            _rhs_signature(plan),
            "{",
            *_solve(plan),
            f"    for (int i = 0; i < {n}; ++i) {{",
            "        dx[i] = qd[i];",
            f"        dx[{n} + i] = y[i];",
            "    }",
            "    return 0;",
            "}",
        ]
    )
