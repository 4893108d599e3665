"""rates_source(eom) -> Python source of the right-hand side dx/dt, for numba to compile.

The state equations (:mod:`lagrangian.numerics.state_equations`) are

    matrix(q, q_dot_S, t) z = vector(q, q_dot_S, t),    z = [q_ddot_S; q_dot_F],
    dx/dt = [q_dot; q_ddot_S],                          x = [q; q_dot_S],

so the generated function fills ``matrix`` and ``vector`` from their common subexpressions
(computed once), solves the linear system in place and writes dx/dt:

    def rates(t, x, p, matrix, vector, dx) -> bool     # False: the matrix is singular

Every symbol gets a safe local name (``q_0``, ``v_0``, ``p_0``, ``t``), the arithmetic is
printed with the ``math`` module (which numba compiles), and anything the printer cannot
express is refused with the function named, so nothing fails later inside numba.

>>> import lagrangian as lg
>>> source = rates_source(lg.derive(lg.examples.simple_pendulum()))
>>> print(source.text.splitlines()[0])
def rates(t, x, p, matrix, vector, dx):
>>> source.size, source.parameters
(1, ('m', 'g', 'l'))
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.numerics.state_equations import state_equations

INDENT = "    "


@dataclass(frozen=True)
class RatesSource:
    """The source of ``rates`` and what its arrays mean.

    ``size`` is the length of z (and of ``vector``); the state x has len(coordinates) + the
    number of second-order coordinates entries; ``parameters`` is the order of p.
    """

    text: str
    size: int
    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    state_names: tuple[str, ...]


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


def rates_source(eom: EquationsOfMotion) -> RatesSource:
    """The source of ``rates(t, x, p, matrix, vector, dx)`` for ``eom`` (module docstring).

    Raises SimulationError when an expression uses a function that has no numeric form.
    """
    equations = state_equations(eom)
    q, qd, p = list(eom.coordinates), list(eom.velocities), list(eom.parameters)
    n, second, first = len(q), equations.second, equations.first
    size = len(equations.vector)
    names: dict[sp.Symbol, sp.Symbol] = {eom.time: sp.Symbol("t")}
    reads = [f"{INDENT}# x = [q; q_dot_S], p = parameters"]
    for j, symbol in enumerate(q):
        names[symbol] = sp.Symbol(f"q_{j}")
    for j in second:
        names[qd[j]] = sp.Symbol(f"v_{j}")
    for i, symbol in enumerate(p):
        names[symbol] = sp.Symbol(f"p_{i}")
    _require_known([*equations.matrix, *equations.vector], set(names))
    entries = [e.xreplace(names) for e in (*equations.matrix, *equations.vector)]
    used = set().union(*(e.free_symbols for e in entries))
    reads += [f"{INDENT}q_{j} = x[{j}]" for j in range(n) if sp.Symbol(f"q_{j}") in used]
    reads += [
        f"{INDENT}v_{j} = x[{n + k}]" for k, j in enumerate(second) if sp.Symbol(f"v_{j}") in used
    ]
    reads += [f"{INDENT}p_{i} = p[{i}]" for i in range(len(p)) if sp.Symbol(f"p_{i}") in used]
    printer = _Printer()
    body = _assignments(entries, size, printer)
    if printer.unprintable:
        raise SimulationError(
            f"The equations use {', '.join(sorted(printer.unprintable))}, which the numba "
            "backend cannot compile: use backend='numpy'."
        )
    lines = [
        "def rates(t, x, p, matrix, vector, dx):",
        *reads,
        *body,
        f"{INDENT}if not solve_linear(matrix, vector):",
        f"{INDENT * 2}return False",
        *_derivatives(n, second, first),
        f"{INDENT}return True",
    ]
    return RatesSource(
        text="\n".join(lines) + "\n",
        size=size,
        coordinates=tuple(s.name for s in q),
        parameters=tuple(s.name for s in p),
        state_names=(*(s.name for s in q), *(qd[j].name for j in second)),
    )


def _assignments(entries: list[sp.Expr], size: int, printer: _Printer) -> list[str]:
    """Common subexpressions c_i once, then every entry of matrix and vector."""
    replacements, reduced = sp.cse(entries, symbols=sp.numbered_symbols("c_"), order="none")
    lines = [f"{INDENT}{s} = {printer.doprint(e)}" for s, e in replacements]
    for index, expr in enumerate(reduced):
        if index < size * size:
            target = f"matrix[{index // size}, {index % size}]"
        else:
            target = f"vector[{index - size * size}]"
        lines.append(f"{INDENT}{target} = {printer.doprint(expr)}")
    return lines


def _derivatives(n: int, second: tuple[int, ...], first: tuple[int, ...]) -> list[str]:
    """dx = [q_dot; q_ddot_S]: q_dot_S from the state, q_dot_F and q_ddot_S from z."""
    s = len(second)
    lines = [f"{INDENT}dx[{j}] = x[{n + k}]" for k, j in enumerate(second)]
    lines += [f"{INDENT}dx[{j}] = vector[{s + k}]" for k, j in enumerate(first)]
    lines += [f"{INDENT}dx[{n + k}] = vector[{k}]" for k in range(s)]
    return lines


def _require_known(entries: list[sp.Expr], known: set[sp.Symbol]) -> None:
    unknown = sorted(s.name for e in entries for s in e.free_symbols - known)
    if unknown:
        raise SimulationError(
            f"The equations use {', '.join(unknown)}, which are neither coordinates nor "
            "parameters: declare them as parameters of the System to give them values."
        )
