"""Presentation MathML of the equations and steps (``lagrangian derive --format mathml``),
with velocities and accelerations as dotted symbols (θ̇, θ̈), as textbooks print them.

>>> import lagrangian as lg
>>> text = equations_mathml(lg.derive(lg.examples.simple_pendulum()))
>>> text.startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">')
True
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from string import ascii_lowercase
from typing import Any

import sympy as sp
from sympy.printing.mathml import MathMLPresentationPrinter

from lagrangian.derivation import EquationsOfMotion
from lagrangian.model.conversion import to_sympy
from lagrangian.render.rows import Row, step_rows
from lagrangian.render.text import TermOrder

DOT, DDOT = "&#729;", "&#168;"  # ˙ and ¨ as accents over the coordinate
NAMED_ENTITIES = {
    "&InvisibleTimes;": "&#8290;",
    "&ApplyFunction;": "&#8289;",
    "&dd;": "&#8518;",
    "&ExponentialE;": "&#8519;",
    "&ImaginaryI;": "&#8520;",
}


class OrderedPresentationPrinter(MathMLPresentationPrinter):
    """``sympy.mathml(expr, printer="presentation")``, the terms of each sum ordered once
    (:class:`~lagrangian.render.text.TermOrder`) however often the printer meets it."""

    def __init__(self, settings: dict[str, Any] | None = None) -> None:
        super().__init__(settings)
        self._order = TermOrder()

    def _as_ordered_terms(self, expr: sp.Basic, order: str | None = None) -> list[sp.Basic]:
        if (order or self.order) is None:
            return self._order.terms(expr)
        return list(super()._as_ordered_terms(expr, order))


def _placeholder(index: int) -> str:
    """A name SymPy's printer keeps whole (letters only: no sub- or superscripts)."""
    letters = ""
    index += 1
    while index:
        index, rest = divmod(index - 1, 26)
        letters = ascii_lowercase[rest] + letters
    return PLACEHOLDER_PREFIX + letters


PLACEHOLDER_PREFIX = "lgdotted"
_PLACEHOLDER = re.compile(f"<mi>{PLACEHOLDER_PREFIX}[a-z]+</mi>")


class Dotted:
    """Prints expressions with q_dot as q̇ and q_ddot as q̈."""

    def __init__(self, eom: EquationsOfMotion) -> None:
        self.swap: dict[sp.Symbol, sp.Symbol] = {}
        self.markup: dict[str, str] = {}
        self.printer = OrderedPresentationPrinter()
        pairs = [(v, q, DOT) for q, v in zip(eom.coordinates, eom.velocities)]
        pairs += [(a, q, DDOT) for q, a in zip(eom.coordinates, eom.accelerations)]
        for index, (symbol, coordinate, accent) in enumerate(pairs):
            name = _placeholder(index)
            self.swap[symbol] = sp.Symbol(name)
            base = sp.mathml(coordinate, printer="presentation")
            self.markup[f"<mi>{name}</mi>"] = (
                f'<mover accent="true">{base}<mo>{accent}</mo></mover>'
            )

    def __call__(self, expr: sp.Basic) -> str:
        text = self.printer.doprint(to_sympy(expr).xreplace(self.swap))
        # every placeholder in one pass (not one pass over the text per coordinate)
        text = _PLACEHOLDER.sub(lambda m: self.markup.get(m.group(), m.group()), text)
        for entity, code in NAMED_ENTITIES.items():  # numeric, so the output is plain XML
            text = text.replace(entity, code)
        return text


def mathml_table(rows: Iterable[tuple[str, str]]) -> str:
    """One display-math table of ``left = right`` rows (MathML fragments)."""
    body = "".join(
        f'<mtr><mtd columnalign="right">{left}</mtd><mtd columnalign="left"><mo>=</mo>{right}'
        "</mtd></mtr>"
        for left, right in rows
    )
    return (
        f'<math xmlns="http://www.w3.org/1998/Math/MathML" display="block"><mtable>{body}'
        "</mtable></math>"
    )


def equations_mathml(eom: EquationsOfMotion) -> str:
    """Every equation as ``residual = 0``, one table row each."""
    dotted = Dotted(eom)
    return mathml_table((dotted(e), "<mn>0</mn>") for e in eom.equations)


def _label(row: Row, q: str, v: str) -> str:
    def partial(top: str, bottom: str) -> str:
        d = "<mo>&#8706;</mo>"
        return f"<mfrac><mrow>{d}{top}</mrow><mrow>{d}{bottom}</mrow></mfrac>"

    labels = {
        Row.MOMENTUM: partial("<mi>L</mi>", v),
        Row.RATE: "<mfrac><mi>d</mi><mrow><mi>d</mi><mi>t</mi></mrow></mfrac>"
        + partial("<mi>L</mi>", v),
        Row.SLOPE: partial("<mi>L</mi>", q),
        Row.FRICTION: partial("<mi>F</mi>", v),
        Row.FORCE: f"<msub><mi>Q</mi>{q}</msub>",
    }
    return labels[row]


def steps_mathml(eom: EquationsOfMotion) -> str:
    """The derivation, coordinate by coordinate: the step-by-step rows, then the equation."""
    dotted = Dotted(eom)
    rows = [("<mi>L</mi>", dotted(eom.lagrangian))]
    for steps in eom.steps:
        q, v = dotted(steps.coordinate), dotted(steps.velocity)
        for row, expr in step_rows(steps):
            if row is Row.EQUATION:
                rows.append((dotted(expr), "<mn>0</mn>"))
            else:
                rows.append((_label(row, q, v), dotted(expr)))
    return mathml_table(rows)


def matrix_form_mathml(eom: EquationsOfMotion) -> str:
    """The matrix form M q̈ = forcing, with the matrices written out."""
    dotted = Dotted(eom)
    left = dotted(eom.mass_matrix) + dotted(sp.Matrix(eom.accelerations))
    return mathml_table([(left, dotted(eom.forcing))])
