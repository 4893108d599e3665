"""LaTeX for equations of motion, their derivation steps and systems.

Velocities and accelerations are typeset with accents: ``theta1_dot`` -> ``\\dot{\\theta}_{1}``,
``theta1_ddot`` -> ``\\ddot{\\theta}_{1}``.  Multi-line results are one ``align*`` block (pass
``environment="aligned"`` to nest it inside ``$$ ... $$``, as Jupyter needs).

>>> import lagrangian as lg
>>> print(equations_latex(lg.derive(lg.examples.simple_pendulum())))
\\begin{align*}
g l m \\sin{\\left(\\theta \\right)} + l^{2} m \\ddot{\\theta} &= 0
\\end{align*}
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import Any

import sympy as sp
from sympy import Mul, Number, Pow, S
from sympy.printing.latex import LatexPrinter
from sympy.printing.precedence import PRECEDENCE, precedence_traditional
from sympy.simplify import fraction

from lagrangian.derivation import CoordinateSteps, EquationsOfMotion
from lagrangian.model import System
from lagrangian.render.rows import Row, energy_rows, step_rows
from lagrangian.render.text import KeptText, extracts_minus_sign
from lagrangian.symbolic.symbols import DDOT_SUFFIX, DOT_SUFFIX, acceleration, velocity

_TEXT_ESCAPES = {c: "\\" + c for c in "_&%#${}"}

# LatexPrinter's test for two numbers side by side (they get the number separator)
_NUMBER_BEFORE = re.compile(r"[0-9][} ]*$")
_NUMBER_AFTER = re.compile(r"(\d|\\frac{\d+}{\d+})")


class KeptLatexPrinter(KeptText, LatexPrinter):
    """``sympy.latex`` that writes each subexpression once (:class:`KeptText`): SymPy's text,
    character for character, in time proportional to its length for a long chain (SymPy sorts
    the factors of every product again, and searches every factor for ``Mod``).

    >>> m1, m2, x, y = sp.symbols("m1 m2 x y")
    >>> KeptLatexPrinter().doprint((m1 + m2) * x - (m1 + m2) * y)
    'x \\\\left(m_{1} + m_{2}\\\\right) - y \\\\left(m_{1} + m_{2}\\\\right)'
    """

    def __init__(self, settings: dict[str, Any] | None = None) -> None:
        super().__init__(settings)
        self._holding: dict[tuple[sp.Basic, Any], bool] = {}

    def _as_ordered_terms(self, expr: sp.Basic, order: str | None = None) -> list[sp.Basic]:
        if (order or self.order) is None:
            return self._order.terms(expr)
        return list(super()._as_ordered_terms(expr, order))

    def _needs_mul_brackets(self, expr: sp.Basic, first: bool = False, last: bool = False) -> bool:
        """LatexPrinter._needs_mul_brackets, its searches for Mod (and for sums, products and
        integrals) made once per subexpression."""
        if expr.is_Mul:
            if not first and extracts_minus_sign(expr):
                return True
        elif precedence_traditional(expr) < PRECEDENCE["Mul"] or expr.is_Relational:
            return True
        if expr.is_Piecewise or self._holds(expr, sp.Mod):
            return True
        return not last and self._holds(expr, (sp.Integral, sp.Product, sp.Sum))

    def _needs_add_brackets(self, expr: sp.Basic) -> bool:
        """LatexPrinter._needs_add_brackets: a relation, a sum, or one holding a Mod."""
        return bool(expr.is_Relational or self._holds(expr, sp.Mod) or expr.is_Add)

    def _holds(self, expr: sp.Basic, kinds: type | tuple[type, ...]) -> bool:
        """``expr.has(*kinds)`` for classes ``kinds``, kept for every subexpression."""
        key = (expr, kinds)
        found = self._holding.get(key)
        if found is None:
            found = isinstance(expr, kinds) or any(
                self._holds(a, kinds) for a in expr.args if isinstance(a, sp.Basic)
            )
            self._holding[key] = found
        return found

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> str:
        """LatexPrinter._print_Add."""
        parts = []
        for i, term in enumerate(self._as_ordered_terms(expr, order=order)):
            sign = ""
            if i and extracts_minus_sign(term):
                sign, term = " - ", -term
            elif i:
                sign = " + "
            text = self._print(term)
            if self._needs_add_brackets(term):
                text = rf"\left({text}\right)"
            parts.append(sign + text)
        return "".join(parts)

    def _print_Mul(self, expr: sp.Expr) -> str:
        """LatexPrinter._print_Mul of a product with no denominator, its factors ordered by
        :class:`TermOrder`; SymPy's own for the rest."""
        if self.order in ("old", "none") or not isinstance(expr, Mul):
            return str(super()._print_Mul(expr))
        if expr.args[0] is S.One or any(isinstance(a, Number) for a in expr.args[1:]):
            return str(super()._print_Mul(expr))  # unevaluated: every factor as it stands
        body, sign = expr, ""
        if extracts_minus_sign(expr):
            body, sign = -expr, "- "
        if body.is_Add or fraction(body, exact=True)[1] is not S.One:
            return str(super()._print_Mul(expr))
        if Pow(1, -1, evaluate=False) in body.args:
            return str(super()._print_Mul(expr))
        if not body.is_Mul:
            return sign + self._print(body)
        factors = self._order.factors(body)
        if any(_is_unit(f) for f in factors):  # SymPy writes units last
            return str(super()._print_Mul(expr))
        return sign + self._product(factors)

    def _product(self, factors: list[sp.Basic]) -> str:
        """LatexPrinter's convert_args: the factors, bracketed where a product needs it."""
        separator = self._settings["mul_symbol_latex"]
        between_numbers = self._settings["mul_symbol_latex_numbers"]
        tex = last = ""
        for i, factor in enumerate(factors):
            text = self._print(factor)
            if self._needs_mul_brackets(factor, first=i == 0, last=i == len(factors) - 1):
                text = rf"\left({text}\right)"
            if _NUMBER_BEFORE.search(last) and _NUMBER_AFTER.match(text):
                tex += between_numbers
            elif tex:
                tex += separator
            tex += text
            last = text
        return tex


def _is_unit(factor: sp.Basic) -> bool:
    """A unit or physical constant, which LatexPrinter writes after the other factors."""
    return (
        hasattr(factor, "_scale_factor")
        or hasattr(factor, "is_physical_constant")
        or (isinstance(factor, Pow) and hasattr(factor.base, "is_physical_constant"))
    )


def symbol_names(coordinates: Iterable[sp.Symbol]) -> dict[sp.Symbol, str]:
    """LaTeX names of q, q_dot, q_ddot: ``theta1_dot`` -> ``\\dot{\\theta}_{1}``.

    >>> symbol_names([sp.Symbol("theta1")])[sp.Symbol("theta1_dot")]
    '\\\\dot{\\\\theta}_{1}'
    """
    names: dict[sp.Symbol, str] = {}
    for q in coordinates:
        base, scripts = _split_scripts(sp.latex(q))
        names[q] = base + scripts
        names[velocity(q)] = rf"\dot{{{base}}}{scripts}"
        names[acceleration(q)] = rf"\ddot{{{base}}}{scripts}"
    return names


def _split_scripts(name: str) -> tuple[str, str]:
    """``\\theta_{1}`` -> (``\\theta``, ``_{1}``): the first sub/superscript outside braces."""
    depth = 0
    for i, char in enumerate(name):
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth == 0 and char in "_^" and i > 0:
            return name[:i], name[i:]
    return name, ""


def expression_latex(expr: sp.Basic, coordinates: Iterable[sp.Symbol]) -> str:
    """``sympy.latex`` with dotted velocities and accelerations of ``coordinates``.

    >>> theta = sp.Symbol("theta")
    >>> expression_latex(sp.Symbol("theta_dot") ** 2, [theta])
    '\\\\dot{\\\\theta}^{2}'
    """
    return sp.latex(expr, symbol_names=symbol_names(coordinates))


def block(lines: Sequence[str], environment: str = "align*") -> str:
    """Lines joined by ``\\\\`` inside ``\\begin{environment} ... \\end{environment}``."""
    begin, end = f"\\begin{{{environment}}}\n", f"\n\\end{{{environment}}}"
    if not lines:
        return begin + end
    # one join, so that the text of a long chain is not copied once more for the frame
    framed = list(lines)
    framed[0] = begin + framed[0]
    framed[-1] += end
    return " \\\\\n".join(framed)


def equations_latex(
    eom: EquationsOfMotion, form: str = "residuals", environment: str = "align*"
) -> str:
    """The equations of motion: one line ``residual = 0`` per coordinate, or the matrix form.

    form="residuals": d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q = 0 for each coordinate;
    form="matrix": M q_ddot = forcing, with the matrices written out.

    >>> import lagrangian as lg
    >>> eom = lg.derive(lg.examples.simple_pendulum())
    >>> matrix_form = equations_latex(eom, form="matrix")
    >>> r"\\ddot{\\theta}\\end{matrix}\\right] &= " in matrix_form
    True
    """
    tex = KeptLatexPrinter({"symbol_names": symbol_names(eom.coordinates)}).doprint
    if form == "residuals":
        lines = [f"{tex(e)} &= 0" for e in eom.equations]
    elif form == "matrix":
        mass = tex(eom.mass_matrix)
        q_ddot = tex(sp.Matrix(eom.accelerations))
        forcing = tex(eom.forcing)
        lines = [f"{mass} {q_ddot} &= {forcing}"]
    else:
        raise ValueError(f"Unknown form {form!r}: use form='residuals' or form='matrix'.")
    return block(lines, environment)


def energy_lines(eom: EquationsOfMotion, printer: KeptLatexPrinter | None = None) -> list[str]:
    """``T = ...``, ``V = ...``, (``U = ...``), ``L = T - V (- U) = ...``, (``F = ...``)."""
    printer = printer or KeptLatexPrinter({"symbol_names": symbol_names(eom.coordinates)})
    tex = printer.doprint

    def line(label: str) -> str:  # "L = T - V" -> "L &= T - V = ..."
        head, _, definition = label.partition(" = ")
        return f"{head} &= {definition} = " if definition else f"{head} &= "

    return [line(label) + tex(expr) for label, expr in energy_rows(eom)]


def coordinate_steps_lines(
    steps: CoordinateSteps,
    names: dict[sp.Symbol, str],
    printer: KeptLatexPrinter | None = None,
) -> list[str]:
    """The derivation lines of one coordinate, in the order one works them by hand (with
    ``printer``, one that writes these ``names``, shared by the coordinates).

    dL/dq_dot, d/dt(dL/dq_dot), dL/dq always; dF/dq_dot and Q_j when non-zero; then the
    equation d/dt(dL/dq_dot) - dL/dq + dF/dq_dot - Q_j = 0.
    """
    tex = (printer or KeptLatexPrinter({"symbol_names": names})).doprint

    q, v = tex(steps.coordinate), tex(steps.velocity)
    dl_dv = rf"\frac{{\partial L}}{{\partial {v}}}"
    labels = {
        Row.MOMENTUM: f"{dl_dv} &= ",
        Row.RATE: rf"\frac{{d}}{{dt}}\left({dl_dv}\right) &= ",
        Row.SLOPE: rf"\frac{{\partial L}}{{\partial {q}}} &= ",
        Row.FRICTION: rf"\frac{{\partial F}}{{\partial {v}}} &= ",
        Row.FORCE: f"Q_{{{q}}} &= ",
    }
    return [
        rf"\Rightarrow\; {tex(expr)} &= 0" if row is Row.EQUATION else labels[row] + tex(expr)
        for row, expr in step_rows(steps)
    ]


def steps_latex(eom: EquationsOfMotion, environment: str = "align*") -> str:
    """The whole derivation: T, V, L = T - V (and F), then every coordinate's steps.

    >>> import lagrangian as lg
    >>> lines = steps_latex(lg.derive(lg.examples.simple_pendulum())).splitlines()
    >>> print(lines[4])
    \\frac{\\partial L}{\\partial \\dot{\\theta}} &= l^{2} m \\dot{\\theta} \\\\
    """
    names = symbol_names(eom.coordinates)
    printer = KeptLatexPrinter({"symbol_names": names})
    lines = energy_lines(eom, printer)
    for steps in eom.steps:
        lines.extend(coordinate_steps_lines(steps, names, printer))
    return block(lines, environment)


def coordinate_steps_latex(steps: CoordinateSteps, environment: str = "align*") -> str:
    """The derivation of one coordinate's equation (coordinates read off the expressions)."""
    exprs = (steps.dL_dvelocity, steps.ddt_dL_dvelocity, steps.dL_dcoordinate, steps.equation)
    found = {steps.coordinate}
    for expr in exprs:
        for s in expr.free_symbols:
            for suffix in (DDOT_SUFFIX, DOT_SUFFIX):
                if isinstance(s, sp.Symbol) and s.name.endswith(suffix):
                    found.add(sp.Symbol(s.name.removesuffix(suffix)))
                    break
    names = symbol_names(sorted(found, key=str))
    return block(coordinate_steps_lines(steps, names), environment)


def system_latex(system: System, environment: str = "align*") -> str:
    """A short description: name, coordinates, parameters and the explicit energies.

    Energies contributed by elements (particles, springs, ...) show after ``derive``; here
    only the fields given explicitly (T, V, L, U, F, Q) appear, with the element names.

    >>> import lagrangian as lg
    >>> print(system_latex(lg.examples.simple_pendulum()).splitlines()[2])
    q &= \\left(\\theta\\right) \\\\
    """
    names = symbol_names(system.coordinates)

    def tex(expr: sp.Basic) -> str:
        return sp.latex(expr, symbol_names=names)

    coords = ", ".join(tex(q) for q in system.coordinates)
    lines = [rf"&\text{{{_escape_text(system.name or 'system')}}}", rf"q &= \left({coords}\right)"]
    if system.parameters:
        values = ", ".join(
            tex(p) if value is None else f"{tex(p)} = {value:g}"
            for p, value in system.parameters.items()
        )
        lines.append(rf"&{values}")
    fields = (
        ("T", system.kinetic),
        ("V", system.potential),
        ("L", system.lagrangian),
        ("U", system.velocity_potential),
        ("F", system.dissipation),
    )
    lines.extend(f"{label} &= {tex(expr)}" for label, expr in fields if expr != 0)
    lines.extend(
        f"Q_{{{tex(q)}}} &= {tex(force)}" for q, force in system.generalized_forces.items()
    )
    elements = _element_names(system)
    if elements:
        lines.append(rf"&\text{{{_escape_text(elements)}}}")
    return block(lines, environment)


def _element_names(system: System) -> str:
    """``particles: bob; gravity`` — which elements contribute energy or forces."""
    parts = []
    for label, items in (
        ("particles", system.particles),
        ("rigid bodies", system.rigid_bodies),
        ("springs", system.springs),
        ("dampers", system.dampers),
        ("forces", system.forces),
        ("torques", system.torques),
        ("circuit elements", system.circuit),
    ):
        named = [getattr(item, "name", "") for item in items]
        if named and all(named):
            parts.append(f"{label}: {', '.join(named)}")
        elif named:
            parts.append(f"{len(named)} {label}")
    if system.gravity:
        parts.append("gravity")
    return "; ".join(parts)


def _escape_text(text: str) -> str:
    """Escape the characters LaTeX treats specially inside ``\\text{...}``."""
    return "".join(_TEXT_ESCAPES.get(c, c) for c in text)
