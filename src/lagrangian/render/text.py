"""Plain text for a terminal: equations of motion, derivation steps and the matrix form.

Labels use unicode (``∂L/∂θ̇``, a combining dot U+0307 or diaeresis U+0308 after the name);
expressions are ``sympy.sstr`` with the input's names (``theta_dot``), so they parse back.

>>> import lagrangian as lg
>>> print(equations_text(lg.derive(lg.examples.simple_pendulum())))
g*l*m*sin(theta) + l**2*m*theta_ddot = 0
"""

from __future__ import annotations

import re
from operator import itemgetter
from typing import Any

import sympy as sp
from sympy import Add, Mul, Number, Pow, S
from sympy.core.exprtools import decompose_power
from sympy.core.mul import _keep_coeff
from sympy.core.numbers import NumberSymbol
from sympy.core.sorting import default_sort_key
from sympy.printing.precedence import PRECEDENCE, precedence
from sympy.printing.printer import Printer
from sympy.printing.str import StrPrinter

from lagrangian.derivation import CoordinateSteps, EquationsOfMotion
from lagrangian.render.rows import Row, energy_rows, step_rows

DOT = "\u0307"
DDOT = "\u0308"

_GREEK = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "zeta": "ζ",
    "eta": "η", "theta": "θ", "iota": "ι", "kappa": "κ", "lambda": "λ", "lamda": "λ",
    "mu": "μ", "nu": "ν", "xi": "ξ", "rho": "ρ", "sigma": "σ", "tau": "τ",
    "upsilon": "υ", "phi": "φ", "chi": "χ", "psi": "ψ", "omega": "ω",
    "Gamma": "Γ", "Delta": "Δ", "Theta": "Θ", "Lambda": "Λ", "Xi": "Ξ", "Pi": "Π",
    "Sigma": "Σ", "Phi": "Φ", "Psi": "Ψ", "Omega": "Ω",
}  # fmt: skip


class TermOrder:
    """SymPy's order of the terms of a sum and the factors of a product (``order=None``:
    ``as_ordered_terms``, ``as_ordered_factors``, ``default_sort_key``), each computed once.

    SymPy caches only the last thousand sort keys, so the key of a sum that recurs in
    thousands of products (the m_k + ... + m_n of a chain) is built again and again. Here
    every key and term order is kept for the life of the object. A sum's terms
    compare by their monomials' non-zero exponents only (SymPy builds a vector over every
    generator of the sum), which orders them the same way.

    >>> x, y = sp.symbols("x y")
    >>> TermOrder().terms(1 + x**2 + x * y + y)
    [x**2, x*y, y, 1]
    """

    def __init__(self) -> None:
        self._keys: dict[sp.Basic, Any] = {}
        self._terms: dict[sp.Basic, list[sp.Expr]] = {}

    def factors(self, expr: sp.Basic) -> list[sp.Basic]:
        """Mul.as_ordered_factors: the commuting factors by sort key, then the others."""
        if not isinstance(expr, Mul):  # minus a product of two: the other factor
            return list(expr.as_ordered_factors())
        first = expr.args[0]
        if expr.is_commutative and not (first.is_Number and first.is_extended_negative):
            return sorted(expr.args, key=self.key)  # what args_cnc would split off
        commuting, others = expr.args_cnc()
        commuting.sort(key=self.key)
        return commuting + others

    def key(self, expr: Any) -> Any:
        """``default_sort_key(expr)``, computed once per subexpression."""
        if not isinstance(expr, sp.Basic):
            return default_sort_key(expr)
        key = self._keys.get(expr)
        if key is None:
            if type(expr).sort_key is sp.Expr.sort_key:
                key = self._expr_key(expr)
            else:
                key = expr.sort_key()
            self._keys[expr] = key
        return key

    def _expr_key(self, expr: sp.Expr) -> Any:
        """Expr.sort_key with order None, on cached keys of the parts."""
        coeff, rest = expr.as_coeff_Mul()
        exp: sp.Basic = S.One
        if rest.is_Pow:
            rest, exp = rest.as_base_exp()
            if rest is S.Exp1:  # as SymPy does: E**x sorts as exp(x)
                rest, exp = sp.Function("exp")(exp), S.One
        if rest.is_Dummy:
            args: tuple = (rest.sort_key(),)
        elif rest.is_Atom:
            args = (str(rest),)
        else:
            if rest.is_Add:
                parts = self.terms(rest)
            elif rest.is_Mul:
                parts = self.factors(rest)
            else:
                parts = rest.args
            args = tuple(self.key(a) for a in parts)
        return rest.class_key(), (len(args), args), self.key(exp), coeff

    def terms(self, expr: sp.Basic) -> list[sp.Expr]:
        """Expr.as_ordered_terms with order None (lex on monomials), computed once per sum."""
        terms = self._terms.get(expr)
        if terms is None:
            terms = self._terms[expr] = self._lex_terms(expr)
        return terms

    def _lex_terms(self, expr: sp.Basic) -> list[sp.Expr]:
        args = Add.make_args(expr)
        if any(t.is_Order for t in args):
            return list(expr.as_ordered_terms())
        if len(args) == 2:  # a positive number and a negative multiple: SymPy keeps 1 - x
            number, product = sorted(args, key=lambda t: not isinstance(t, (Number, NumberSymbol)))
            if isinstance(number, (Number, NumberSymbol)) and isinstance(product, Mul):
                factors = sorted(
                    product.args, key=lambda f: not isinstance(f, (Number, NumberSymbol))
                )
                if (
                    len(factors) == 2
                    and isinstance(factors[0], Number)
                    and number.is_positive
                    and factors[0].is_negative
                ):
                    return [number, product]
        monomials = [self._monomial(t) for t in args]
        generators = {base for _, powers, _ in monomials for base in powers}
        order = {g: i for i, g in enumerate(sorted(generators, key=self.key))}
        end = ((len(order), 0),)
        # SymPy's key is (-exponent of each generator in order, non-commuting keys,
        # coefficient); with positive exponents listing only the non-zero ones, and an end
        # mark after them, compares the same
        dense = any(e <= 0 for _, powers, _ in monomials for e in powers.values())

        def key(item: tuple[sp.Expr, tuple]) -> tuple:
            (re, im), powers, others = item[1]
            monomial: tuple[Any, ...]
            if dense:
                vector = [0] * len(order)
                for base, e in powers.items():
                    vector[order[base]] = -e
                monomial = tuple(vector)
            else:
                monomial = tuple(sorted((order[b], -e) for b, e in powers.items())) + end
            return monomial, tuple(self.key(f) for f in others), ((bool(im), im), (re, im))

        return [t for t, _ in sorted(zip(args, monomials), key=key)]

    def _monomial(
        self, term: sp.Expr
    ) -> tuple[tuple[float, float], dict[sp.Expr, int], tuple[sp.Expr, ...]]:
        """Expr.as_terms of one term: (coefficient (re, im), {generator: exponent}, the
        non-commuting factors). Not kept: a sum's order is, and most terms are in one sum."""
        coeff, rest = term.as_coeff_Mul()
        # complex(coeff) goes through evalf; a small integer is its float exactly
        small = coeff.is_Integer and abs(coeff.p) < 2**53
        value = complex(coeff.p) if small else complex(coeff)
        powers: dict[sp.Expr, int] = {}
        others = []
        if rest is not S.One:
            for factor in Mul.make_args(rest):
                if factor.is_number:
                    try:
                        value *= complex(factor)
                    except (TypeError, ValueError):
                        pass
                    else:
                        continue
                if factor.is_commutative:
                    base, e = decompose_power(factor)
                    powers[base] = e
                else:
                    others.append(factor)
        return (value.real, value.imag), powers, tuple(others)


class KeptText(Printer):
    """A printer that writes each subexpression once and reuses its text wherever it recurs,
    and orders terms and factors by one :class:`TermOrder` (mixed in before a SymPy printer).

    Not kept: a whole expression (the caller has its text), a Float alone (StrPrinter writes
    it by its depth), and a product longer than :data:`KEPT_PRODUCT` (the terms of a chain's
    equations occur once each, and most of their text is a kept sum).
    """

    def __init__(self, settings: dict[str, Any] | None = None) -> None:
        super().__init__(settings)
        self._written: dict[str | None, dict[sp.Basic, str]] = {}  # by order
        self._order = TermOrder()

    def _print(self, expr: Any, **kwargs: Any) -> str:
        if kwargs or not isinstance(expr, sp.Basic) or expr.is_Float:
            return str(super()._print(expr, **kwargs))
        written = self._written.setdefault(self._settings["order"], {})
        text = written.get(expr)
        if text is None:
            top = self._print_level == 0
            text = str(super()._print(expr))
            if not top and (len(text) <= KEPT_PRODUCT or not expr.is_Mul):
                written[expr] = text
        return text


class SumPrinter(KeptText, StrPrinter):
    """``sympy.sstr`` that writes each subexpression once and reuses the text wherever it
    recurs: the m_k + ... + m_n of an n-link chain's link k is in n of its terms, so its
    equations print in time proportional to their length, not to that times n.

    It keeps what SymPy recomputes on every use (its own caches hold only the last thousand
    results): the text (:class:`KeptText`), the sort key and term order (:class:`TermOrder`)
    and the precedence of every subexpression; the text is SymPy's, character for character
    (tests/render/test_fast_printing.py).

    A sum of more than :data:`SORTED_TERMS` terms, and a product that holds one, are written
    in SymPy's own order (``order="none"``) rather than sorted: sorting them costs more than
    the rest of a long chain's derivation, and such a line is read by search, not from left to
    right.

    >>> m1, m2, x, y = sp.symbols("m1 m2 x y")
    >>> SumPrinter().doprint((m1 + m2) * x + (m1 + m2) * y)
    'x*(m1 + m2) + y*(m1 + m2)'
    """

    def __init__(self, settings: dict[str, Any] | None = None) -> None:
        super().__init__(settings)
        self._precedences: dict[sp.Basic, int] = {}
        # the text of a factor written in a product (parenthesized by the product's precedence)
        self._plain_factors: dict[tuple[str | None, int], dict[sp.Basic, str]] = {}
        # the same for plain products (_plain_product), with the factor's sort key first
        self._plain_products: dict[tuple[str | None, int], dict[sp.Basic, tuple[Any, str]]] = {}

    def _print(self, expr: Any, **kwargs: Any) -> str:
        if type(expr) is not Mul or kwargs:
            return super()._print(expr, **kwargs)
        # a product (most of what a chain's equations hold), as KeptText._print and then
        # Printer._print would write it: a product is never a Float, Mul has no _sympystr,
        # and _print_Mul is the first printing method its classes name
        written = self._written.setdefault(self._settings["order"], {})
        text = written.get(expr)
        if text is None:
            top = self._print_level == 0
            self._print_level += 1  # StrPrinter writes a Float by this depth
            try:
                text = self._print_Mul(expr)
            finally:
                self._print_level -= 1
            if not top and len(text) <= KEPT_PRODUCT:
                written[expr] = text
        return text

    def parenthesize(self, item: Any, level: int, strict: bool = False) -> str:
        prec = self._precedence(item)
        if prec < level or (not strict and prec <= level):
            return f"({self._print(item)})"
        return self._print(item)

    def _precedence(self, item: Any) -> int:
        """``precedence(item)``, computed once per subexpression."""
        if type(item) is Mul and not extracts_minus_sign(item):
            return MUL  # precedence_Mul
        if not isinstance(item, sp.Basic):
            return precedence(item)
        prec = self._precedences.get(item)
        if prec is None:
            prec = self._precedences[item] = precedence(item)
        return prec

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> str:
        order = order or self.order
        if order is None and len(expr.args) > SORTED_TERMS:
            order = "none"
        if order is None:
            terms = self._order.terms(expr)
        elif order == "none":
            terms = list(expr.args)
        else:
            return super()._print_Add(expr, order)
        # StrPrinter._print_Add
        prec = self._precedence(expr)
        parts = []
        for term in terms:
            text = self._print(term)
            if text.startswith("-") and not term.is_Add:
                sign, text = "-", text[1:]
            else:
                sign = "+"
            # a product's precedence is never below a sum's: no need to work it out
            product = type(term) is Mul and prec <= ADD
            if term.is_Add or (not product and self._precedence(term) < prec):
                text = f"({text})"
            parts.append(f"{sign} {text}")
        first = parts[0]
        parts[0] = first[2:] if first[0] == "+" else "-" + first[2:]
        return " ".join(parts)

    def _print_Mul(self, expr: sp.Mul) -> str:
        text = self._plain_product(expr)
        if text is not None:
            return text
        if self.order is None and any(a.is_Add and len(a.args) > SORTED_TERMS for a in expr.args):
            self._settings["order"] = "none"  # for this product only
            try:
                return self._print(expr)
            finally:
                self._settings["order"] = None
        args = expr.args
        if args[0] is S.One or any(
            isinstance(a, Number) or (a.is_Pow and all(ai.is_Integer for ai in a.args))
            for a in args[1:]
        ):  # an unevaluated product: SymPy writes every factor as it stands
            return super()._print_Mul(expr)
        return self._print_product(expr)

    def _print_product(self, expr: sp.Mul) -> str:
        """StrPrinter._print_Mul of an evaluated product, its factors sorted by cached keys."""
        prec = self._precedence(expr)
        c, e = expr.as_coeff_Mul()
        sign = ""
        if (c.is_Rational and c.p < 0) or (not c.is_Rational and c < 0):
            expr, sign = _keep_coeff(-c, e), "-"
        if self.order in ("old", "none"):
            factors = list(Mul.make_args(expr))
        else:
            factors = self._order.factors(expr)
        plain = self._plain_factors.setdefault((self.order, prec), {})
        texts = []
        for item in factors:
            text = plain.get(item)
            if text is None:
                if _in_denominator(item) or item.is_Rational:
                    break
                text = plain[item] = self.parenthesize(item, prec)
            texts.append(text)
        else:  # no denominator and no number: the factors, parenthesized, one by one
            return sign + "*".join(texts)
        numerator: list[sp.Basic] = []
        denominator: list[sp.Basic] = []
        bracketed = []  # x**-1 with a product or power x: "1/(a*b)", not "1/a*b" (SymPy #14160)
        for item in factors:
            if _in_denominator(item):
                if item.exp is not S.NegativeOne:
                    denominator.append(_inverted_power(item))
                else:
                    if len(item.args[0].args) != 1 and isinstance(item.base, (Mul, Pow)):
                        bracketed.append(item)
                    denominator.append(item.base)
            elif item.is_Rational and item is not S.Infinity:
                if item.p != 1:
                    numerator.append(sp.Rational(item.p))
                if item.q != 1:
                    denominator.append(sp.Rational(item.q))
            else:
                numerator.append(item)
        numerator = numerator or [S.One]
        top = "*".join(self.parenthesize(x, prec) for x in numerator)
        bottom = [self.parenthesize(x, prec) for x in denominator]
        for item in bracketed:
            if item.base in denominator:
                i = denominator.index(item.base)
                bottom[i] = f"({bottom[i]})"
        if not bottom:
            return sign + top
        if len(bottom) == 1:
            return f"{sign}{top}/{bottom[0]}"
        return f"{sign}{top}/({'*'.join(bottom)})"

    def _plain_product(self, expr: sp.Mul) -> str | None:
        """What _print_Mul writes for a product of plain factors (:meth:`_plain_factor`) after
        at most a leading -1, such as c*l_j*l_k*(m_k + ...)*cos(theta_j - theta_k) of a chain;
        None for any other product.

        The same text by the same steps, with less made on the way. Such a product passes
        _print_Mul's tests (no long sum, no number after the first factor, no power of
        integers) to _print_product. Its precedence is MUL, or ADD after a -1 (precedence_Mul:
        no factor is a function of lower precedence, and -x*y*... could extract a minus
        sign; see extracts_minus_sign). For -1*x*y*..., as_coeff_Mul and _keep_coeff(1, .)
        give the product of the other factors (args[1:]: an evaluated product holds at most
        one number, first), which is commutative when the whole is and whose factors
        TermOrder.factors sorts by key as they stand; no factor stops _print_product's
        first loop. Each factor's sort key and text (parenthesized by the product's
        precedence) come from one lookup.
        """
        args = expr.args
        if args[0] is S.NegativeOne and len(args) > 2:
            sign, args, prec = "-", args[1:], ADD
        else:
            sign, prec = "", MUL
        ordered = self.order not in ("old", "none")
        if ordered and not expr.is_commutative:
            return None
        known = self._plain_products.setdefault((self.order, prec), {})
        entries = []
        for item in args:
            entry = known.get(item)
            if entry is None:
                if not self._plain_factor(item):
                    return None
                key = self._order.key(item) if ordered else None
                entry = known[item] = (key, self.parenthesize(item, prec))
            entries.append(entry)
        if ordered:
            entries.sort(key=_sort_key)  # stable, as sorted(args, key=TermOrder.key)
        return sign + "*".join([text for _, text in entries])

    def _plain_factor(self, item: sp.Basic) -> bool:
        """Not a number, nor in a denominator, nor a power of integers (written unevaluated),
        nor a sum written in SymPy's order, nor a function of lower precedence than a
        product: a factor that _print_product writes as it stands."""
        return not (
            item.is_Number
            or _in_denominator(item)
            or (item.is_Pow and all(a.is_Integer for a in item.args))
            or (self.order is None and item.is_Add and len(item.args) > SORTED_TERMS)
            or (isinstance(item, sp.Function) and getattr(item, "precedence", MUL) < MUL)
        )


def extracts_minus_sign(expr: sp.Basic) -> bool:
    """``expr.could_extract_minus_sign()``, without negating a product that does not start
    with a negative number (SymPy compares it with its negative first)."""
    if type(expr) is Mul:
        first, rest = expr.args[0], expr.args[1:]
        if not (first.is_Number and first.is_extended_negative):
            return False
        # -(c*x) is (-c)*x, which differs from c*x (Mul.__neg__), but for c*zoo*x
        if first.is_Rational and rest[0] is not S.ComplexInfinity and not rest[0].is_Number:
            return True
    return bool(expr.could_extract_minus_sign())


def _in_denominator(factor: sp.Basic) -> bool:
    """A power with a negative exponent: StrPrinter writes it after the ``/``."""
    return bool(
        factor.is_commutative and isinstance(factor, Pow) and factor.exp.as_coeff_Mul()[0] < 0
    )


def _inverted_power(power: sp.Pow) -> sp.Basic:
    """b**e with e < 0 as b**-e, unevaluated (the denominator StrPrinter writes)."""
    base, exp = power.as_base_exp()
    factors = list(Mul.make_args(exp))
    if factors[0] is S.NegativeOne:
        factors = factors[1:]
    else:
        factors[0] = -factors[0]
    return power.func(base, Mul._from_args(factors), evaluate=False)


#: Terms beyond which :class:`SumPrinter` leaves a sum in SymPy's order (not sorted).
SORTED_TERMS = 50

#: Characters beyond which :class:`SumPrinter` writes a product again rather than keep it.
KEPT_PRODUCT = 200

ADD, MUL = PRECEDENCE["Add"], PRECEDENCE["Mul"]

_sort_key = itemgetter(0)


def label(symbol: sp.Symbol, mark: str = "") -> str:
    """A display name: Greek words as letters, ``mark`` (a combining accent) on the letters.

    >>> label(sp.Symbol("theta1"), DOT)
    'θ̇1'
    """
    name = re.sub(r"[A-Za-z]+", lambda m: _GREEK.get(m.group(), m.group()), symbol.name)
    split = re.search(r"[\d_]", name[1:])
    end = split.start() + 1 if split else len(name)
    return name[:end] + mark + name[end:]


def _rows(matrix: sp.MatrixBase, printer: SumPrinter) -> list[str]:
    """One ``[a, b, ...]`` line per row, each entry ``sympy.sstr``."""
    return [
        "[" + ", ".join(printer.doprint(e) for e in matrix.row(i)) + "]" for i in range(matrix.rows)
    ]


def equations_text(eom: EquationsOfMotion) -> str:
    """One line ``residual = 0`` per coordinate, d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q."""
    printer = SumPrinter()
    return "\n".join(f"{printer.doprint(e)} = 0" for e in eom.equations)


def energy_text(eom: EquationsOfMotion, printer: SumPrinter | None = None) -> list[str]:
    """``T = ...``, ``V = ...``, (``U = ...``), ``L = T − V (− U) = ...``, (``F = ...``)."""
    printer = printer or SumPrinter()
    # the text uses the minus sign − in the definitions, as the steps do
    return [
        f"{label.replace(' - ', ' − ')} = {printer.doprint(expr)}"
        for label, expr in energy_rows(eom)
    ]


def coordinate_steps_text(steps: CoordinateSteps, printer: SumPrinter | None = None) -> list[str]:
    """One coordinate's derivation, step by step as one writes it by hand.

    >>> import lagrangian as lg
    >>> (s,) = lg.derive(lg.examples.simple_pendulum()).steps
    >>> coordinate_steps_text(s)[0]
    '∂L/∂θ̇ = l**2*m*theta_dot'
    """
    printer = printer or SumPrinter()
    q, v = label(steps.coordinate), label(steps.coordinate, DOT)
    labels = {
        Row.MOMENTUM: f"∂L/∂{v} = ",
        Row.RATE: f"d/dt(∂L/∂{v}) = ",
        Row.SLOPE: f"∂L/∂{q} = ",
        Row.FRICTION: f"∂F/∂{v} = ",
        Row.FORCE: f"Q_{q} = ",
    }
    shown = [(row, printer.doprint(expr)) for row, expr in step_rows(steps)]
    return [f"⇒ {text} = 0" if row is Row.EQUATION else labels[row] + text for row, text in shown]


def steps_text(eom: EquationsOfMotion) -> str:
    """T, V, L = T − V (and F), then each coordinate's steps, blocks separated by blank lines.

    >>> import lagrangian as lg
    >>> print(steps_text(lg.derive(lg.examples.simple_pendulum())).splitlines()[-1])
    ⇒ g*l*m*sin(theta) + l**2*m*theta_ddot = 0
    """
    printer = SumPrinter()
    blocks = ["\n".join(energy_text(eom, printer))]
    blocks.extend("\n".join(coordinate_steps_text(s, printer)) for s in eom.steps)
    return "\n\n".join(blocks)


def matrix_form_text(eom: EquationsOfMotion) -> str:
    """The matrix form, one block per term (the vocabulary of docs/architecture.md):

        M q̈ + C q̇ + G = Q − ∂F/∂q̇,    M q̈ = forcing

    Time terms and velocity-potential forces appear only when non-zero.

    >>> import lagrangian as lg
    >>> print(matrix_form_text(lg.derive(lg.examples.simple_pendulum())).splitlines()[3])
    [l**2*m]
    """
    q_dot, q_ddot = "q" + DOT, "q" + DDOT
    lhs, rhs = f"M {q_ddot} + C {q_dot}", f"Q − ∂F/∂{q_dot}"
    parts: list[tuple[str, sp.MatrixBase]] = [
        ("mass_matrix M", eom.mass_matrix),
        (f"coriolis C {q_dot}", eom.coriolis),
    ]
    if any(e != 0 for e in eom.time_terms):
        parts.append(("time_terms", eom.time_terms))
        lhs += " + time_terms"
    parts += [
        ("potential_forces G = ∂V/∂q", eom.gravity),
        ("generalized_forces Q", eom.generalized_forces),
        (f"dissipation_forces −∂F/∂{q_dot}", eom.dissipation_forces),
    ]
    if any(e != 0 for e in eom.velocity_potential_forces):
        parts.append(("velocity_potential_forces", eom.velocity_potential_forces))
        rhs += " + velocity_potential_forces"
    parts.append((f"forcing (M {q_ddot} = forcing)", eom.forcing))
    blocks = [f"{lhs} + G = {rhs}"]
    printer = SumPrinter()
    blocks.extend("\n".join([f"{title} =", *_rows(matrix, printer)]) for title, matrix in parts)
    return "\n\n".join(blocks)
