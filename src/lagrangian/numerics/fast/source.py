"""values_source(symbols, expressions) -> Python source of out[i] = expressions[i](in), for numba.

The fallback of :mod:`lagrangian.numerics.fast.native` where SymEngine's LLVM backend cannot
compile the right-hand side: the expressions are printed as one Python function with the C
signature of every compiled right-hand side,

    def values(out, inputs, user_data):     # void f(double *out, const double *in, void *)

which ``numba.cfunc`` compiles.  Common subexpressions are computed once, every symbol gets a
safe local name (``a_0``, ``a_1``, ...), the arithmetic is printed with the ``math`` module
(which numba compiles), and anything the printer cannot express is refused with the function
named, so nothing fails later inside numba.

>>> import sympy as sp
>>> x, v = sp.symbols("x v")
>>> print(values_source([x, v], [v, -sp.sin(x)]))
def values(out, inputs, user_data):
    a = carray(inputs, (2,))
    y = carray(out, (2,))
    a_0 = a[0]
    a_1 = a[1]
    y[0] = a_1
    y[1] = -math.sin(a_0)
<BLANKLINE>
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from lagrangian.errors import Fix, Problem, Setting, SimulationError
from lagrangian.symbolic.conversion import to_sympy

INDENT = "    "


class _Printer(PythonCodePrinter):
    """Python with the math module; records the functions it cannot print."""

    def __init__(self) -> None:
        super().__init__({"fully_qualified_modules": True, "standard": "python3", "strict": False})
        self.unprintable: set[str] = set()

    def _print_not_supported(self, expr: sp.Basic) -> str:
        self.unprintable.add(type(expr).__name__)
        return super()._print_not_supported(expr)

    def _print_Heaviside(self, expr: sp.Basic) -> str:
        # H(0) = 1/2 as in SymPy's default, unless given: H(x, h0)
        x = self._print(expr.args[0])
        h0 = self._print(expr.args[1]) if len(expr.args) > 1 else "0.5"
        return f"(1.0 if {x} > 0 else (0.0 if {x} < 0 else {h0}))"


def values_source(symbols: Sequence[sp.Symbol], expressions: Sequence[sp.Expr]) -> str:
    """The source of ``values(out, inputs, user_data)``: out[i] = expressions[i] at
    inputs = the values of ``symbols`` (module docstring).

    Raises SimulationError when an expression uses a symbol not in ``symbols`` or a function
    that has no numeric form.
    """
    names = {symbol: sp.Symbol(f"a_{i}") for i, symbol in enumerate(symbols)}
    _require_known(expressions, set(names))
    entries = [to_sympy(e).xreplace(names) for e in expressions]
    used = set().union(*(e.free_symbols for e in entries))
    lines = [
        "def values(out, inputs, user_data):",
        f"{INDENT}a = carray(inputs, ({len(symbols)},))",
        f"{INDENT}y = carray(out, ({len(entries)},))",
        *(f"{INDENT}{s} = a[{i}]" for i, s in enumerate(names.values()) if s in used),
    ]
    printer = _Printer()
    replacements, reduced = sp.cse(entries, symbols=sp.numbered_symbols("c_"), order="none")
    lines += [f"{INDENT}{s} = {printer.doprint(e)}" for s, e in replacements]
    lines += [f"{INDENT}y[{i}] = {printer.doprint(e)}" for i, e in enumerate(reduced)]
    if printer.unprintable:
        message = (
            f"the equations use {', '.join(sorted(printer.unprintable))}, which the numba "
            "backend cannot compile"
        )
        fix = Fix("use {}", (Setting("backend", "numpy"),))
        raise SimulationError("", [Problem("backend", message, fix)])
    return "\n".join(lines) + "\n"


def _require_known(expressions: Sequence[sp.Expr], known: set[sp.Symbol]) -> None:
    unknown = sorted({s.name for e in expressions for s in to_sympy(e).free_symbols - known})
    if unknown:
        raise SimulationError(
            f"The equations use {', '.join(unknown)}, which are neither coordinates nor "
            "parameters: declare them as parameters of the System to give them values."
        )
