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
from xml.dom.minidom import Element, Text

import sympy as sp
from sympy import Mul, Number, S
from sympy.core.mul import _mulsort
from sympy.printing.mathml import MathMLPresentationPrinter
from sympy.printing.precedence import PRECEDENCE, precedence_traditional
from sympy.printing.printer import Printer

from lagrangian.derivation import EquationsOfMotion
from lagrangian.render.rows import Row, step_rows
from lagrangian.render.text import KEPT_PRODUCT, TermOrder, extracts_minus_sign
from lagrangian.symbolic.conversion import to_sympy

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


class Markup(Text):
    """Finished MathML, written out as it stands (a node :class:`KeptPresentationPrinter`
    puts in the tree where SymPy's printer would put the subexpression's own nodes)."""

    __slots__ = ()

    def writexml(self, writer: Any, indent: str = "", addindent: str = "", newl: str = "") -> None:
        writer.write(self.data)


class KeptPresentationPrinter(OrderedPresentationPrinter):
    """``sympy.mathml(expr, printer="presentation")`` that writes each subexpression once and
    reuses its MathML wherever it recurs, character for character SymPy's
    (tests/render/test_fast_printing.py).

    SymPy's printer builds a DOM node for every occurrence of every symbol, sorts the factors
    of every product again by sort keys it keeps only the last thousand of, and searches every
    product for a denominator: an n-link chain's m_k + ... + m_n, in n of its terms, costs each
    of them its full length. Here a subexpression's nodes are written to text as soon as they
    are printed, and every later occurrence is one :class:`Markup` node holding that text; the
    order of terms and factors is :class:`~lagrangian.render.text.TermOrder`'s. Not kept (as
    in :class:`~lagrangian.render.text.KeptText`): a whole expression, a Float alone, and a
    product longer than :data:`~lagrangian.render.text.KEPT_PRODUCT`.

    >>> m1, m2, x, y = sp.symbols("m1 m2 x y")
    >>> expr = x * (m1 + m2) - y * (m1 + m2)
    >>> KeptPresentationPrinter().doprint(expr) == sp.mathml(expr, printer="presentation")
    True
    """

    def __init__(self, settings: dict[str, Any] | None = None) -> None:
        super().__init__(settings)
        self._written: dict[sp.Basic, str] = {}
        self._factors: dict[sp.Basic, str] = {}  # a factor's MathML, bracketed for a product

    def doprint(self, expr: Any) -> str:
        """MathMLPrinterBase.doprint."""
        node = Printer._print(self, expr)
        text = node.data if isinstance(node, Markup) else node.toxml()
        return str(text.encode("ascii", "xmlcharrefreplace").decode())

    def _print(self, expr: Any, **kwargs: Any) -> Any:
        if kwargs or not isinstance(expr, sp.Basic) or expr.is_Float:
            return super()._print(expr, **kwargs)
        text = self._written.get(expr)
        if text is None:
            node = super()._print(expr)
            if not isinstance(node, (Element, Text)):
                return node
            text = _written(node)
            if len(text) <= KEPT_PRODUCT or not expr.is_Mul:
                self._written[expr] = text
        return _markup(text, self.dom)

    def _written_text(self, expr: Any) -> str:
        """The MathML of ``expr``, as text."""
        return _written(self._print(expr))

    def _factor(self, expr: sp.Basic) -> str:
        """``parenthesize(expr, PRECEDENCE["Mul"])``, as text, kept for every factor."""
        text = self._factors.get(expr)
        if text is None:
            text = self._written_text(expr)
            if precedence_traditional(expr) <= MUL:
                text = f"<mrow><mo>(</mo>{text}<mo>)</mo></mrow>"
            self._factors[expr] = text
        return text

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> Markup:
        """MathMLPresentationPrinter._print_Add."""
        terms = self._as_ordered_terms(expr, order=order)
        parts = ["<mrow>", self._written_text(terms[0])]
        for term in terms[1:]:
            if extracts_minus_sign(term):
                parts += ("<mo>-</mo>", self._written_text(-term))
            else:
                parts += ("<mo>+</mo>", self._written_text(term))
        parts.append("</mrow>")
        return _markup("".join(parts), self.dom)

    def _print_Mul(self, expr: sp.Expr) -> Any:
        """MathMLPresentationPrinter._print_Mul of an evaluated product with no denominator,
        its factors ordered by :class:`TermOrder`; SymPy's own for the rest."""
        if self.order == "old" or not _plain_product(expr):
            return super()._print_Mul(expr)
        parts = ["<mrow>"]
        if extracts_minus_sign(expr):
            parts.append("<mo>-</mo>")
            expr = -expr
        coeff, factors = expr.as_coeff_mul()
        if coeff is S.One and len(factors) == 1:
            parts += (self._written_text(factors[0]), "</mrow>")
            return _markup("".join(parts), self.dom)
        terms = self._order.factors(Mul._from_args(factors))
        times = f"<mo>{self.mathml_tag(expr)}</mo>"
        if coeff != 1:
            parts += (self._written_text(coeff), times)
        for term in terms:
            parts.append(self._factor(term))
            if term != terms[-1]:
                parts.append(times)
        parts.append("</mrow>")
        return _markup("".join(parts), self.dom)


class _Parts(list[str]):
    """A writer for ``Node.writexml`` that keeps the pieces to join them once."""

    write = list.append


def _written(node: Element | Text) -> str:
    """``node.toxml()`` (the MathML of a subexpression)."""
    if isinstance(node, Markup):
        return node.data
    parts = _Parts()
    node.writexml(parts)
    return "".join(parts)


def _markup(text: str, dom: Any) -> Markup:
    node = Markup()
    node.data = text
    node.ownerDocument = dom
    return node


MUL = PRECEDENCE["Mul"]


def _plain_product(expr: sp.Expr) -> bool:
    """An evaluated, commuting product with no denominator (``fraction`` would find none):
    no fraction for a coefficient, no power but to a positive rational exponent."""
    if not isinstance(expr, Mul) or not expr.is_commutative:
        return False
    first, rest = expr.args[0], expr.args[1:]
    if first is S.One or (first.is_Rational and first.q != 1):
        return False
    for factor in (first, *rest) if not first.is_Number else rest:
        if isinstance(factor, (Number, sp.exp)):
            return False  # a second number: an unevaluated product
        if factor.is_Pow and not (factor.exp.is_Rational and factor.exp.p > 0):
            return False
        if factor.is_Pow and factor.base.is_Integer:
            return False  # 2**3 left unevaluated
    return True


def _plain_factor(factor: sp.Basic) -> bool:
    """A factor Mul.flatten only sorts among the others (of more than two): a symbol, a sine
    or cosine, a sum, or one of them to a rational power."""
    if factor.is_Pow:
        factor, exp = factor.args
        if not exp.is_Rational:
            return False
    return bool(
        factor.is_commutative and (factor.is_Symbol or isinstance(factor, (sp.sin, sp.cos, sp.Add)))
    )


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
        self.printer = KeptPresentationPrinter()
        self._swapped: dict[sp.Basic, tuple[sp.Basic, bool]] = {}
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
        text = self.printer.doprint(self._swap(to_sympy(expr)))
        # every placeholder in one pass (not one pass over the text per coordinate)
        text = _PLACEHOLDER.sub(lambda m: self.markup.get(m.group(), m.group()), text)
        for entity, code in NAMED_ENTITIES.items():  # numeric, so the output is plain XML
            text = text.replace(entity, code)
        # SymPy writes the operator of theta < 0 bare, which no XML reader takes
        return text.replace("<mo><</mo>", "<mo>&lt;</mo>")

    def _swap(self, expr: Any) -> Any:
        """``expr.xreplace(self.swap)``, each distinct subexpression replaced once (xreplace
        walks a subexpression again wherever it recurs)."""
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self._swap)
        if not isinstance(expr, sp.Basic) or type(expr)._xreplace is not sp.Basic._xreplace:
            return expr.xreplace(self.swap)
        return self._replaced(expr)[0]

    def _replaced(self, expr: sp.Basic) -> tuple[sp.Basic, bool]:
        """Basic._xreplace, kept for every subexpression."""
        if expr in self.swap:
            return self.swap[expr], True
        done = self._swapped.get(expr)
        if done is not None:
            return done
        args, changed = [], False
        for arg in expr.args:
            if not isinstance(arg, sp.Basic):
                args.append(arg)
            elif type(arg)._xreplace is not sp.Basic._xreplace:
                new, swapped = arg._xreplace(self.swap)
                args.append(new)
                changed |= swapped
            else:
                new, swapped = self._replaced(arg)
                args.append(new)
                changed |= swapped
        if not changed:
            result = expr
        elif (
            type(expr) is Mul
            and len(args) > 2  # a number times a sum: Mul distributes it
            and all(map(_plain_factor, args[args[0].is_Number :]))
        ):
            # what Mul(*args) makes of them: no factor merges with another (the new names are
            # new), so the factors sorted as Mul.flatten sorts them, a number first
            first = args[: args[0].is_Number]
            factors = args[len(first) :]
            _mulsort(factors)
            result = Mul._from_args(first + factors)
        else:
            result = expr.func(*args)
        done = self._swapped[expr] = (result, changed)
        return done


#: A row of :func:`mathml_table`: (left, right) is ``left = right``; (left, relation, right)
#: gives the relation (``&#8805;``), or none ("": a heading, or a line of text).
TableRow = tuple[str, str] | tuple[str, str, str]


def mathml_table(rows: Iterable[TableRow]) -> str:
    """One display-math table of ``left = right`` rows (MathML fragments).

    >>> table = mathml_table([("<mi>y</mi>", "&#8805;", "<mn>0</mn>"), ("<mi>a</mi>", "", "")])
    >>> '<mi>y</mi></mtd><mtd columnalign="left"><mo>&#8805;</mo><mn>0</mn>' in table
    True
    >>> '<mi>a</mi></mtd><mtd columnalign="left"></mtd>' in table
    True
    """
    cells = []
    for row in rows:
        left, relation, right = row if len(row) == 3 else (row[0], "=", row[1])
        sign = f"<mo>{relation}</mo>" if relation else ""
        cells.append(
            f'<mtr><mtd columnalign="right">{left}</mtd><mtd columnalign="left">{sign}{right}'
            "</mtd></mtr>"
        )
    body = "".join(cells)
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
