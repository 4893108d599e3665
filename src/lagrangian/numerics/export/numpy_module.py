"""export_numpy: a self-contained Python module (numpy only) of the equations of motion.

The module has ``COORDINATES``, ``PARAMETERS`` (names, in the order of ``p``), ``DEFAULTS``
(values, NaN where the model gives none) and the functions of
:mod:`lagrangian.numerics.export.common`; ``rhs(t, x, p)`` solves M q_ddot = forcing with
``numpy.linalg.solve``.
"""

from __future__ import annotations

from sympy.printing.numpy import NumPyPrinter

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.numerics.export.common import (
    RHS_SUMMARY,
    UNSORTED,
    ExportPlan,
    Routine,
    literal,
    nonzero_entries_code,
    plan_export,
    temporaries_code,
)

_INDENT = "    "


def export_numpy(eom: EquationsOfMotion) -> str:
    """The source of a Python module computing M, C qd, G, Q, forcing and rhs with numpy.

    >>> import lagrangian as lg
    >>> source = export_numpy(lg.derive(lg.examples.simple_pendulum()))
    >>> "def rhs(t, x, p):" in source
    True
    """
    plan = plan_export(eom, first_index=0)
    parts = [_constants(plan), *(_function(routine) for routine in plan.routines)]
    parts.append(_rhs(plan) if plan.has_rhs else _missing_rhs(plan))
    return _docstring(plan) + "\n\nimport numpy\n\n\n" + "\n\n\n".join(parts) + "\n"


def _docstring(plan: ExportPlan) -> str:
    lines = plan.header(lambda base, i: f"{base}[{i}]")
    body = "\n".join(lines).replace("\\", "\\\\").replace('"""', r"\"\"\"")
    return f'"""{body}\n"""'


def _constants(plan: ExportPlan) -> str:
    names = [name for name, _ in plan.parameters]
    values = [literal(v, "numpy.nan", "numpy.inf") for _, v in plan.parameters]
    return "\n".join(
        [
            f"COORDINATES = {_tuple([repr(q) for q in plan.coordinates])}",
            f"PARAMETERS = {_tuple([repr(name) for name in names])}",
            f"DEFAULTS = {_tuple(values)}",
        ]
    )


def _tuple(items: list[str]) -> str:
    return "(" + ", ".join(items) + ("," if len(items) == 1 else "") + ")"


def _function(routine: Routine) -> str:
    printer = NumPyPrinter({"fully_qualified_modules": True, **UNSORTED})
    lines = [f"def {routine.name}({', '.join(routine.arguments)}):", f'    """{routine.summary}"""']
    lines += [f"{_INDENT}{s} = {code}" for s, code in temporaries_code(routine, printer, "numpy")]
    rows, cols = routine.outputs.shape
    shape = f"({rows}, {cols})" if routine.is_matrix else f"{rows}"
    lines.append(f"{_INDENT}{routine.output} = numpy.zeros({shape})")
    entries = nonzero_entries_code(routine, printer, "numpy", first_index=0)
    lines += [f"{_INDENT}{routine.output}[{index}] = {code}" for index, code in entries]
    lines.append(f"{_INDENT}return {routine.output}")
    return "\n".join(lines)


def _rhs(plan: ExportPlan) -> str:
    matrix, vector = plan.solved
    solve = [
        "    x = numpy.asarray(x, dtype=float)",
        f"    q, qd = x[:{plan.n}], x[{plan.n}:]",
        f"    {plan.solved_name} = {matrix}({plan.solved_call})",
        f"    y = numpy.linalg.solve({plan.solved_name}, {vector}(q, qd, t, p))",
    ]
    parts = [
        "\n".join(
            [
                "def rhs(t, x, p):",
                f'    """{RHS_SUMMARY}"""',
                *solve,
                f"    return numpy.concatenate([qd, y[:{plan.n}]])",
            ]
        )
    ]
    if plan.m:
        parts.append(
            "\n".join(
                [
                    "def multipliers(t, x, p):",
                    '    """The Lagrange multipliers lambda at the state x."""',
                    *solve,
                    f"    return y[{plan.n}:]",
                ]
            )
        )
    return "\n\n\n".join(parts)


def _missing_rhs(plan: ExportPlan) -> str:
    # A module __getattr__ keeps `hasattr(module, "rhs")` False but explains the absence.
    return "\n".join(
        [
            "# No rhs(t, x, p): the mass matrix is singular (see the module docstring).",
            f"_NO_RHS = {' '.join(plan.singular_reason.split())!r}",
            "",
            "",
            "def __getattr__(name):",
            '    if name == "rhs":',
            '        raise AttributeError("rhs is not generated. " + _NO_RHS)',
            '    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")',
        ]
    )
