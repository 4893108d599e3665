"""The safe expression language of model files (README, "Model files").

Grammar, and nothing else::

    expr := number | name | expr OP expr | ("+" | "-") expr | "(" expr ")" | FUNC "(" args ")"
    OP   := + - * / **
    FUNC := sin cos tan cot sec csc asin acos atan atan2 sinh cosh tanh exp log sqrt
            Abs sign Heaviside

The text is read by :func:`ast.parse` and the tree is walked against an allow-list, building
SymPy objects directly: nothing is evaluated as code (no ``eval``, no ``sympify`` of text).
Decimals are exact (``0.1`` is ``Rational(1, 10)``).  Expressions must be real and defined
(no ``log(0)``, ``1/0``, ``asin(2)``).  Bounds on the text (10,000 characters), the nesting
(100 levels), numbers (1000 digits), exponents (±1000) and the work SymPy does on numbers keep
parsing fast; where SymPy's own evaluation is known to crawl (Abs, sign and Heaviside of
non-constants, powers of powers) it is sidestepped.  Refusals are ``ExpressionError``s that
name the field, the file, the line and the column, what was found and how to fix it.

>>> import sympy as sp
>>> k, x = sp.symbols("k x")
>>> parse_expression("0.5*k*x**2", {"k": k, "x": x}, field="potential")
k*x**2/2
"""

from __future__ import annotations

import ast
import difflib
import heapq
import keyword
import math
import re
import warnings
from collections.abc import Callable, Iterable, Mapping
from typing import NamedTuple, NoReturn, TypeGuard

import sympy as sp
from sympy.core.function import AppliedUndef

from lagrangian.errors import ExpressionError, Problem, TimeLimitError, raise_if_problems
from lagrangian.size_limits import active_operations, raise_advice
from lagrangian.symbolic.caches import remembered
from lagrangian.symbolic.canonical import EXPR
from lagrangian.symbolic.canonical import Builder as CanonicalBuilder
from lagrangian.symbolic.names import name_problem

MAX_LENGTH = 10_000
MAX_DEPTH = 100
MAX_DIGITS = 1000
MAX_EXPONENT = 1000
#: The most terms an expression may expand to: derivation expands products and powers of
#: sums, and (sin(x) + ... + sin(39*x))**30 would expand to 10**19 terms (hours, gigabytes).
MAX_TERMS = 100_000
#: How much larger (in bits) than its largest number an expression's numbers may grow once
#: multiplied out: derivation expands
#: products, and the product of (x + 1)...(x + 399) has coefficients of 900 digits, which
#: take minutes to form (a product of 150 such factors, 1,100 bits, takes a second).
MAX_EXPANDED_BITS = 2000
#: The most nodes an expression's tree may have once SymPy has formed it.  The text is at most
#: 10,000 characters, but SymPy rewrites some parts into bigger ones (Abs(u)**3 is
#: u**2*Abs(u)), and nested, such rewrites double the tree at every level.
MAX_NODES = 20_000
#: The highest integer power inside the base of a power whose exponent varies
#: (tan(x**999)**(x/(x + 1)) has derivatives SymPy takes minutes to form).
MAX_POWER_UNDER_VARIABLE_EXPONENT = 100
_NUMBER_LIMIT = 10**MAX_DIGITS
# Cost guards, in bits.  A power of numbers is computed only when it is small (the estimate
# may exceed the size by a bit per factor; the exact size is checked after).  Roots cost more:
# SymPy raises the base to the exponent's numerator and hunts for exact roots, and products may
# merge roots of one base, so roots have a small budget of their own.  All numbers of one
# expression together stay below the budget, so sums and products of numbers stay cheap.
_POWER_BITS = 4 * MAX_DIGITS
_ROOT_BITS = 512
_ARGUMENT_BITS = 512
_BUDGET_BITS = 50_000


#: Up to this many known names, a misspelling is compared with each (difflib); beyond, only
#: with the names one deletion away, found in an index, so that a file with thousands of
#: unknown names among thousands of known ones is answered in linear time, not quadratic.
_COMPARE_EACH = 64
#: Names longer than this get no suggestion (each costs its length squared to index).
_LONGEST_SUGGESTED = 64


def closest_name(word: str, choices: Iterable[str], cutoff: float = 0.6) -> str | None:
    """The one of ``choices`` that ``word`` most likely misspells, or None; in bounded time
    however many choices there are.

    >>> closest_name("stifness", ["stiffness", "name"])
    'stiffness'
    >>> closest_name("p1999x", [f"p{i}" for i in range(5000)])
    'p1999'
    """
    options = frozenset(choices)
    if len(word) > _LONGEST_SUGGESTED:
        return None
    if len(options) > _COMPARE_EACH:
        index = _deletion_index(options)
        options = frozenset(name for variant in _deletions(word) for name in index.get(variant, ()))
    close = difflib.get_close_matches(word, sorted(options), n=1, cutoff=cutoff)
    return close[0] if close else None


def _deletions(word: str) -> set[str]:
    """``word`` and every text one letter shorter (two words within one edit of each other,
    a letter deleted, inserted, changed or two swapped, share one of these)."""
    return {word, *(word[:i] + word[i + 1 :] for i in range(len(word)))}


@remembered(maxsize=4)
def _deletion_index(names: frozenset[str]) -> dict[str, tuple[str, ...]]:
    index: dict[str, list[str]] = {}
    for name in names:
        if len(name) <= _LONGEST_SUGGESTED:
            for variant in _deletions(name):
                index.setdefault(variant, []).append(name)
    return {variant: tuple(found) for variant, found in index.items()}


def _by_sign(function: type[sp.Function]) -> Callable[[sp.Expr], sp.Expr]:
    """``function`` (Abs, sign, Heaviside) evaluated from the sign of its argument only.

    SymPy's own evaluation of a non-constant argument splits it into real and imaginary parts,
    which for powers of (complex) symbols expands ``(re + i*im)**n``: Heaviside(x**300) takes
    a minute, Abs(exp(x)) becomes exp(re(x)).  Constants are evaluated as usual, and numeric
    factors come out as SymPy takes them out: Abs(-2*x) is 2*Abs(x), sign(-x) is -sign(x)."""

    def evaluate(arg: sp.Expr) -> sp.Expr:
        coefficient, rest = arg.as_coeff_Mul()
        if arg.is_number or arg.is_extended_negative or arg.is_extended_positive:
            return function(arg)
        if function is not sp.Heaviside and coefficient not in (0, 1):
            return function(coefficient) * evaluate(rest)
        return function(arg, evaluate=False)

    return evaluate


_ONE_ARGUMENT = (sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.sinh, sp.cosh, sp.tanh)
FUNCTIONS: dict[str, tuple[Callable[..., sp.Expr], tuple[int, ...]]] = {
    **{f.__name__: (f, (1,)) for f in _ONE_ARGUMENT},
    # the reciprocal functions as the quotients they are, which every printer and compiler
    # downstream knows (C has no cot)
    "cot": (lambda a: 1 / sp.tan(a), (1,)),
    "sec": (lambda a: 1 / sp.cos(a), (1,)),
    "csc": (lambda a: 1 / sp.sin(a), (1,)),
    "atan2": (sp.atan2, (2,)),
    "exp": (sp.exp, (1,)),
    "log": (lambda *args: _logarithm(*args), (1, 2)),
    "sqrt": (sp.sqrt, (1,)),
    **{f.__name__: (_by_sign(f), (1,)) for f in (sp.Abs, sp.sign, sp.Heaviside)},
}
CONSTANTS: dict[str, sp.Expr] = {"pi": sp.pi, "E": sp.E}
ALLOWED = "allowed: numbers, names, + - * / **, parentheses and calls of " + ", ".join(FUNCTIONS)

_REFUSED_NODES: dict[type, tuple[str, str]] = {
    ast.Attribute: ("attribute access", "write plain names, without dots"),
    ast.Subscript: ("indexing ('[...]')", "use one name per component, such as x1"),
    ast.Lambda: ("a lambda", ALLOWED),
    **dict.fromkeys(
        (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp), ("a comprehension", ALLOWED)
    ),
    ast.Compare: ("a comparison", "write the expression itself; a constraint h is h = 0"),
    ast.BoolOp: ("a boolean operator ('and', 'or')", ALLOWED),
    ast.NamedExpr: ("an assignment (':=')", ALLOWED),
    ast.JoinedStr: ("an f-string", ALLOWED),
    ast.Starred: ("a starred argument ('*')", "pass each argument on its own"),
    ast.IfExp: ("an if-expression", "use Heaviside or sign for piecewise terms"),
    ast.Tuple: ("a tuple (values separated by commas)", "give one expression per field"),
    **{
        kind: (f"a {kind.__name__.lower()}", "give one expression per field")
        for kind in (ast.List, ast.Dict, ast.Set)
    },
}
_OPERATORS: dict[type, str] = {
    ast.BitXor: "^",
    ast.MatMult: "@",
    ast.Mod: "%",
    ast.FloorDiv: "//",
    ast.LShift: "<<",
    ast.RShift: ">>",
    ast.BitOr: "|",
    ast.BitAnd: "&",
}
_OPERATOR_REFUSALS = {
    "^": ("'^' is not a power", "use ** for powers, such as x**2"),
    "//": ("the operator '//' is not allowed", "use / for division"),
}
_DECIMAL = re.compile(r"(\d*)\.?(\d*)(?:[eE]([+-]?\d+))?")
_UNDEFINED = frozenset((sp.zoo, sp.nan, sp.oo, -sp.oo))
_REAL_DOMAINS = "asin and acos take -1..1; log, sqrt and fractional powers take x >= 0"
_TOO_BIG = (f"a number of more than {MAX_DIGITS} digits", "use smaller numbers")


class _Refusal(Exception):
    """Raised inside the walk; the caller turns it into a positioned ExpressionError."""

    def __init__(self, message: str, fix: str, at: tuple[int, int] | None = None) -> None:
        super().__init__(message)
        self.message, self.fix, self.at = message, fix, at


def _locate(
    at: tuple[int, int], prefix: str, line: int | None, column: int | None
) -> tuple[int | None, int | None]:
    """File (line, column) of ``at``, a line and 0-based column in the text after the skipped
    leading ``prefix``; the text starts at ``line``, ``column`` (1-based, 1 when unknown)."""
    at_line, at_column = at[0] + prefix.count("\n"), at[1]
    if at[0] == 1:  # the skipped prefix shifts the columns of its own last line only
        at_column += len(prefix) - prefix.rfind("\n") - 1
    return (line or 1) + at_line - 1, at_column + ((column or 1) if at_line == 1 else 1)


def _bits(number: sp.Rational) -> int:
    return max(int(number.p).bit_length(), int(number.q).bit_length())


def _power_cost(base: sp.Basic) -> tuple[int, bool]:
    """Bits of the numbers SymPy computes in ``base**n`` per unit of ``n``, and whether a root
    is involved: powers of powers and of products combine, ``(2*3**(1/7))**7 == 2**7*3``."""
    if isinstance(base, sp.Rational):
        return _bits(base), False
    if isinstance(base, sp.Pow) and isinstance(base.exp, sp.Rational):
        bits, root = _power_cost(base.base)
        return bits * abs(int(base.exp.p)), root or not base.exp.is_Integer
    if isinstance(base, sp.Mul):
        costs = [_power_cost(factor) for factor in base.args]
        return max(bits for bits, _ in costs), any(root for _, root in costs)
    return 0, False


def _magnitude_bits(value: sp.Basic) -> int:
    """About log2|value| of a constant, from a 5-digit evaluation (0 if it cannot be had)."""
    try:
        parts = sp.N(value, 5).as_real_imag()
    except TimeLimitError:
        raise
    except Exception:
        return 0
    return max([p._mpf_[2] + p._mpf_[3] for p in parts if isinstance(p, sp.Float)] + [0])


def _check_exponent(exponent: sp.Basic) -> None:
    """Constant exponents (and arguments of exp, sinh, cosh) stay within ±1000."""
    if exponent.is_Number:
        too_big = abs(exponent) > MAX_EXPONENT
    else:
        too_big = exponent.is_number and _magnitude_bits(exponent) > MAX_EXPONENT.bit_length()
    if too_big:
        raise _Refusal(
            f"the exponent {_short(exponent)} is beyond ±{MAX_EXPONENT}", "make it smaller"
        )


def _short(value: sp.Basic) -> str:
    text = str(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _is_complex_constant(value: sp.Basic) -> bool:
    """Whether ``value`` is a constant SymPy knows is not real (``asin(2)``, ``log(-1)``).

    Such constants make SymPy's assumptions crawl (``(1/log(asin(3))).is_imaginary`` takes
    seconds) and a mechanical model never needs them.  The query itself may fail on numbers
    SymPy cannot evaluate at low precision; those count as real."""
    try:
        return bool(value.is_number and value.is_extended_real is False)
    except TimeLimitError:
        raise
    except Exception:
        return False


def _check_size(number: sp.Rational) -> sp.Rational:
    if abs(number.p) >= _NUMBER_LIMIT or number.q >= _NUMBER_LIMIT:
        raise _Refusal(*_TOO_BIG)
    return number


def _decimal(text: str) -> sp.Rational:
    """The exact rational a decimal literal means: ``"1.5e-3"`` -> 3/2000."""
    match = _DECIMAL.fullmatch(text.replace("_", ""))
    whole, fraction, exponent = match.groups() if match else ("", "", "")
    if not (whole or fraction):  # ast accepted it, so this is not expected
        raise _Refusal(f"the number {text[:20]!r} is not understood", "write it like 1e-3")
    if len(whole + fraction) > MAX_DIGITS or len(exponent or "") > 5:
        raise _Refusal(*_TOO_BIG)
    if abs(int(exponent or 0)) > MAX_EXPONENT:
        raise _Refusal(f"the exponent of {text!r} is beyond ±{MAX_EXPONENT}", "use a smaller one")
    shift = int(exponent or 0) - len(fraction)
    mantissa = int(whole + fraction)
    return _check_size(sp.Rational(mantissa * 10 ** max(shift, 0), 10 ** max(-shift, 0)))


def _number(value: object) -> sp.Rational:
    """An exact SymPy number for a bare int or float (a float by its shortest decimal text)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _Refusal(f"{value!r} is not an expression", "write a number or a formula")
    if isinstance(value, int):
        return _check_size(sp.Integer(value))
    if value != value or abs(value) == float("inf"):
        raise _Refusal(f"{value!r} is not a finite number", "write a finite number")
    magnitude = _decimal(repr(abs(value)))
    return -magnitude if value < 0 else magnitude


#: How much a :class:`ParseCache` keeps: the characters of the texts of its parts, each part
#: counted as this many characters more (at most 40,000 parts, some megabytes).
_SHARED_CHARACTERS = 4_000_000
_SHARED_PART_COST = 100


class _Built(NamedTuple):
    """A part built from a text: its value, the bits it spent of the budget and of the roots'
    budget, how many levels below it the build went, and the terms of a chain (or None)."""

    value: sp.Expr
    bits: int
    root_bits: int
    height: int
    terms: list[sp.Expr] | None


class ParseCache:
    """What the expressions of one model share while they are parsed: the parts built from
    each text (a chain's positions repeat ``l*sin(th1)`` in every position, and each position
    extends the one before), the sizes of SymPy trees, and the parts already checked.

    Pass one to :func:`parse_expression` for every expression of a model; it answers for one
    set of ``names`` at a time (other names start it afresh).  A shared part is taken only
    where building it again could refuse nothing (depth and number budgets), so results and
    refusals are those of parsing each text on its own.

    >>> x = sp.Symbol("x")
    >>> cache = ParseCache()
    >>> [parse_expression(t, {"x": x}, field="f", cache=cache) for t in ("2*x", "2*x + 1")]
    [2*x, 2*x + 1]
    """

    def __init__(self) -> None:
        self._start({})

    def use(self, names: Mapping[str, sp.Basic]) -> None:
        """Answer for ``names`` (forgetting everything found with other names)."""
        if self.names != names:
            self._start(names)

    def _start(self, names: Mapping[str, sp.Basic]) -> None:
        self.names: dict[str, sp.Basic] = dict(names)
        self.built: dict[str, _Built] = {}
        self.room = _SHARED_CHARACTERS  # for the texts of the parts kept
        self.sizes: dict[sp.Basic, int] = {}
        self.checked: set[sp.Basic] = set()
        self.degrees: dict[sp.Basic, dict[sp.Basic, int]] = {}
        self.products: dict[sp.Basic, int] = {}
        self.harmonics: dict[sp.Basic, int] = {}
        self.bits: dict[sp.Basic, int] = {}
        self.written: dict[sp.Basic, int] = {}
        self.parts = CanonicalBuilder()

    def keep(self, text: str, built: _Built) -> None:
        """Keep the part built from ``text`` while there is room (deeply nested texts repeat
        most of their characters in the text of each level; each part costs some more)."""
        cost = len(text) + _SHARED_PART_COST
        if cost <= self.room:
            self.room -= cost
            self.built[text] = built


class _Builder:
    """Turns an allow-listed ``ast`` tree into SymPy, refusing everything else."""

    def __init__(
        self, text: str, names: Mapping[str, sp.Basic], shared: ParseCache | None = None
    ) -> None:
        self.lines = text.split("\n")
        self.ascii = [line.isascii() for line in self.lines]
        self.names = {**CONSTANTS, **names}
        self.budget, self.root_budget = _BUDGET_BITS, _ROOT_BITS
        self.shared = shared
        self.sizes: dict[sp.Basic, int] = {} if shared is None else shared.sizes
        # sums and products in SymPy's canonical form from what is known of their parts,
        # without SymPy's general evaluation where nothing combines (the parts known for all
        # the expressions of a model)
        self.parts = CanonicalBuilder() if shared is None else shared.parts
        self.deepest = 0  # the deepest level the part being built has reached
        self.chain: tuple[ast.AST, list[sp.Expr]] | None = None  # the last chain's terms

    def key(self, node: ast.AST) -> str | None:
        """The text of a part worth sharing (an operation or a call on one line of ASCII
        text; the same text is the same tree), or None."""
        if self.shared is None or not isinstance(node, (ast.BinOp, ast.UnaryOp, ast.Call)):
            return None
        line = node.lineno
        if line != node.end_lineno or not self.ascii[line - 1]:
            return None
        return self.lines[line - 1][node.col_offset : node.end_col_offset]

    def reuse(self, built: _Built | None, depth: int) -> TypeGuard[_Built]:
        """Whether a part built before (from the same text) may stand here: it went no deeper
        than the limit would allow here, and its numbers fit in what is left of the budgets
        (then building it again could refuse nothing); if so, its numbers are spent."""
        if (
            built is None
            or depth + built.height > MAX_DEPTH
            or built.bits > self.budget
            or built.root_bits > self.root_budget
        ):
            return False
        self.budget -= built.bits
        self.root_budget -= built.root_bits
        self.deepest = max(self.deepest, depth + built.height)
        return True

    def at(self, node: ast.AST, end: bool = False) -> tuple[int, int]:
        """(line, 0-based character column) of a node; ast columns count UTF-8 bytes."""
        line = getattr(node, "end_lineno" if end else "lineno")
        offset = getattr(node, "end_col_offset" if end else "col_offset")
        return line, len(self.lines[line - 1].encode()[:offset].decode(errors="ignore"))

    def segment(self, node: ast.expr) -> str:
        """The source text of a node on one line (a number literal)."""
        line = self.lines[node.lineno - 1].encode()
        return line[node.col_offset : node.end_col_offset].decode()

    def refuse(self, node: ast.AST, message: str, fix: str = ALLOWED) -> NoReturn:
        raise _Refusal(message, fix, self.at(node))

    def spend(self, bits: int, root: bool = False) -> None:
        self.budget -= bits
        self.root_budget -= bits if root else 0
        if self.budget < 0 or self.root_budget < 0:
            raise _Refusal("the numbers in this expression are too large", "use smaller numbers")

    def size(self, value: sp.Basic) -> int:
        """Nodes of ``value``'s tree, a shared part counted at each use (each part's size is
        computed once, so a tree that doubles at each level costs only its levels)."""
        size = self.sizes.get(value)
        if size is None:
            size = self.sizes[value] = 1 + sum(self.size(arg) for arg in value.args)
        return size

    def build(self, node: ast.AST, depth: int) -> sp.Expr:
        if depth > MAX_DEPTH:
            self.refuse(node, f"nested more than {MAX_DEPTH} levels deep", "simplify it")
        key = self.key(node)
        if key is not None and self.shared is not None:
            built = self.shared.built.get(key)
            if self.reuse(built, depth):
                return built.value
        budget, root_budget, deepest = self.budget, self.root_budget, self.deepest
        self.deepest = depth
        try:
            value = self._dispatch(node, depth)
            if self.size(value) > MAX_NODES:
                raise _Refusal(
                    f"SymPy forms this part into more than {MAX_NODES:,} operations",
                    "write it more simply (powers of Abs(u) are rewritten as products with u, "
                    "which nesting doubles at each level)",
                )
            if value in _UNDEFINED:
                raise _Refusal(f"this part is undefined ({value})", "check the formula")
            if isinstance(value, sp.Rational):
                _check_size(value)
            elif _is_complex_constant(value):
                raise _Refusal(f"this part is not a real number ({_short(value)})", _REAL_DOMAINS)
        except _Refusal as refusal:
            refusal.at = refusal.at or self.at(node)
            raise
        except TimeLimitError:  # the command's time ran out here: not the expression's fault
            raise
        except Exception as error:  # SymPy's own refusals, such as Heaviside(asin(2))
            message = f"SymPy cannot form this part ({type(error).__name__}: {str(error)[:99]})"
            raise _Refusal(message, "check the formula", self.at(node)) from None
        if key is not None and self.shared is not None:
            chain = self.chain
            terms = chain[1] if chain is not None and chain[0] is node else None
            spent = (budget - self.budget, root_budget - self.root_budget)
            self.shared.keep(key, _Built(value, *spent, self.deepest - depth, terms))
        self.deepest = max(deepest, self.deepest)
        return value

    def _dispatch(self, node: ast.AST, depth: int) -> sp.Expr:
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
            return self._chain(node, depth, (ast.Add, ast.Sub))
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div)):
            return self._chain(node, depth, (ast.Mult, ast.Div))
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            return self._power(self.build(node.left, depth + 1), self.build(node.right, depth + 1))
        if isinstance(node, ast.BinOp):
            symbol = _OPERATORS[type(node.op)]
            line, start = self.at(node.left, end=True)  # point at the operator itself
            found = self.lines[line - 1].find(symbol, start)
            at = (line, found) if found >= 0 else self.at(node)
            default = (f"the operator '{symbol}' is not allowed", ALLOWED)
            raise _Refusal(*_OPERATOR_REFUSALS.get(symbol, default), at)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
            operand = self.build(node.operand, depth + 1)
            return _negative(operand) if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.Call):
            return self._call(node, depth)
        if isinstance(node, ast.Name):
            return self._name(node)
        if isinstance(node, ast.Constant):
            return self._constant(node)
        what, fix = _REFUSED_NODES.get(type(node), (f"'{type(node).__name__}'", ALLOWED))
        if isinstance(node, ast.UnaryOp):
            what = "the operator 'not'" if isinstance(node.op, ast.Not) else "the operator '~'"
        self.refuse(node, f"{what} is not allowed", fix)

    def _chain(self, node: ast.BinOp, depth: int, ops: tuple[type, ...]) -> sp.Expr:
        """A left-leaning chain ``a + b - c ...`` (or of ``*`` and ``/``) is one level deep,
        so a long sum is not mistaken for deep nesting."""
        links: list[tuple[ast.operator, ast.expr]] = []
        current: ast.expr = node
        terms: list[sp.Expr] | None = None
        while isinstance(current, ast.BinOp) and isinstance(current.op, ops):
            links.append((current.op, current.right))
            current = current.left
            if (
                len(links) == 1
                and isinstance(current, ast.BinOp)
                and isinstance(current.op, ops)
                and (key := self.key(current)) is not None
            ):
                # a chain that extends one built before (a + b + c after a + b): its terms
                built = self.shared.built.get(key) if self.shared is not None else None
                if built is not None and built.terms is not None and self.reuse(built, depth):
                    terms = list(built.terms)
                    break
        if terms is None:
            terms = [self.build(current, depth + 1)]
        for op, operand in reversed(links):
            value = self.build(operand, depth + 1)
            if isinstance(op, ast.Div) and value == sp.S.Zero:
                self.refuse(operand, "division by zero", "check the denominator")
            if isinstance(op, ast.Sub):
                value = _negative(value)
            terms.append(sp.Pow(value, -1) if isinstance(op, ast.Div) else value)
        self.chain = (node, terms)
        parts = self.parts
        combine = parts.sum if ops[0] is ast.Add else parts.product
        return combine([parts.part(term) for term in terms])[EXPR]

    def _power(self, base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
        """``base**exponent``, refused when a power of numbers would be too costly to compute."""
        _check_exponent(exponent)
        if base == sp.S.Zero and exponent.is_Number and exponent.is_negative:
            raise _Refusal("zero to a negative power (division by zero)", "check the formula")
        if isinstance(exponent, sp.Rational):
            bits, root = _power_cost(base)
            cost, root = bits * abs(int(exponent.p)), root or not exponent.is_Integer
            if cost > (_ROOT_BITS if root else _POWER_BITS):
                raise _Refusal("this power of numbers is too large to compute", "use smaller ones")
            self.spend(cost, root)
        if exponent.free_symbols and _highest_power(base) > MAX_POWER_UNDER_VARIABLE_EXPONENT:
            raise _Refusal(
                f"a power with an exponent that varies, over a power above "
                f"{MAX_POWER_UNDER_VARIABLE_EXPONENT} ({base}): its derivatives grow without "
                "end",
                "write the model without such a power (rescale the coordinate, or use exp and "
                "log of a smaller expression)",
            )
        # SymPy merges (b**e)**x into b**(e*x) after looking at re(b) and arg(b), expanding
        # (re + i*im)**n for a power inside b: ((x**999)**E)**E takes minutes.  Unmerged, the
        # power means the same.
        nested = isinstance(base, sp.Pow) and not (exponent.is_integer or base.exp.is_integer)
        if nested and not (base.exp.is_Number and abs(base.exp) < 1):
            return sp.Pow(base, exponent, evaluate=False)
        return form_power(base, exponent)

    def _call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            self.refuse(node.func, "only the listed functions can be called, by name", ALLOWED)
        name = node.func.id
        if name.startswith("_") or name in self.names:
            self._name(node.func)  # refuses names with '_'; the others are values
            self.refuse(node.func, f"{name!r} is not a function", f"for a product: {name}*(...)")
        if name not in FUNCTIONS:
            close = closest_name(name, FUNCTIONS)
            fix = f"did you mean {close!r}?" if close else ALLOWED
            self.refuse(node.func, f"unknown function {name!r}", fix)
        if node.keywords:
            self.refuse(node.keywords[0], "keyword arguments are not allowed", "pass x, not x=...")
        function, arities = FUNCTIONS[name]
        if len(node.args) not in arities:
            counts = " or ".join(map(str, arities))
            noun = "argument" if arities == (1,) else "arguments"
            self.refuse(node, f"{name} takes {counts} {noun}, got {len(node.args)}", ALLOWED)
        args = [self.build(arg, depth + 1) for arg in node.args]
        for arg in args:
            if name in ("exp", "sinh", "cosh"):
                _check_exponent(arg)
            if arg.is_number:
                self._check_argument(name, arg)
        if name == "sqrt":  # through the power guard: roots of big numbers are costly
            return self._power(args[0], sp.Rational(1, 2))
        return function(*args)

    def _check_argument(self, name: str, arg: sp.Expr) -> None:
        """SymPy evaluates a function of a constant to as many digits as the constant's size and
        numbers need (sin(10**900) needs 900 digits of pi), so both are bounded."""
        if any(_bits(number) > _ARGUMENT_BITS for number in arg.atoms(sp.Rational)):
            raise _Refusal(f"the argument of {name} has too long a number", "use shorter ones")
        bits = _magnitude_bits(arg)
        if bits > _ARGUMENT_BITS:
            raise _Refusal(f"the argument of {name} is about 2**{bits}", "use a smaller one")
        self.spend(bits)

    def _name(self, node: ast.Name) -> sp.Expr:
        name = node.id
        written = self.segment(node)  # as typed: Python reads 𝐱 and ｘ as x (NFKC)
        if not written.isascii():
            found = name_problem(written)
            if found is not None:
                self.refuse(node, *found)
        if name.startswith("_"):
            self.refuse(node, f"the name {name!r} is not allowed", "names cannot start with '_'")
        if name in self.names:
            return self.names[name]
        if name in FUNCTIONS:
            self.refuse(node, f"{name!r} is a function", f"call it, such as {name}(x)")
        close = closest_name(name, (n for n in self.names if n[:1] != "_"))
        known = ", ".join(heapq.nsmallest(20, self.names)) + (
            ", ..." if len(self.names) > 20 else ""
        )
        base = name.removesuffix("_ddot").removesuffix("_dot")
        if base != name:  # a velocity or acceleration: its coordinate is what is missing
            declare = f"add {base!r} to coordinates"
        else:
            declare = "declare it in parameters (in coordinates if it moves)"
        fix = (
            f"did you mean {close!r}? Else {declare}"
            if close
            else f"{declare}; known names: {known}"
        )
        self.refuse(node, f"unknown name {name!r}", fix)

    def _constant(self, node: ast.Constant) -> sp.Expr:
        value = node.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            kinds = {str: "text in quotes", bytes: "text in quotes", complex: "a complex number"}
            what = kinds.get(type(value), repr(value))
            self.refuse(node, f"{what} is not allowed", "write a number or a formula")
        number = _decimal(self.segment(node)) if isinstance(value, float) else _number(value)
        self.spend(_bits(number))
        return number


@remembered(maxsize=4096)
def _negative(value: sp.Expr) -> sp.Expr:
    """``-value`` as ``Mul(-1, value)`` forms it.  A symbol, or a product of factors that are
    neither numbers nor products, is negated by SymPy's own negation: its factors are in
    canonical order already and none merges with -1, so putting -1 in front is the product
    Mul forms, without sorting and gathering its factors again (ten times faster).  Numbers
    merge with -1 (-sqrt(2)*sqrt(3) is -sqrt(6)) and products that SymPy left nested are
    flattened: those are formed by Mul.  Remembered, as SymPy remembers Mul's products: a
    chain's positions negate the same terms again, and the same object is found faster
    than an equal new one downstream."""
    if value.is_Symbol or (value.is_Mul and not any(f.is_Mul or f.is_number for f in value.args)):
        return -value
    return sp.Mul(sp.S.NegativeOne, value)


def _read(text: str) -> ast.Expression:
    """The syntax tree of ``text``, or a refusal positioned where Python's parser stopped."""
    if not text.strip():
        raise _Refusal("the expression is empty", "write a number or a formula")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ast.parse(text, mode="eval")
    except SyntaxError as error:
        at = (max(error.lineno or 1, 1), max(error.offset or 1, 1) - 1)
        if "integer string conversion" in error.msg:  # Python's own limit, 4300 digits
            raise _Refusal(*_TOO_BIG, at) from None
        fix = "check for a missing operator (2*x, not 2x) or an unbalanced parenthesis"
        word = next((w for w in re.findall(r"\w+", text) if keyword.iskeyword(w)), None)
        if word is not None:  # lambda, as a name, stops Python's parser
            fix = f"{word!r} is a Python keyword, not a name: write {word}_ or another name"
        if "\n" in text.rstrip():
            fix += "; wrap an expression of several lines in parentheses"
        raise _Refusal(f"cannot read the expression: {error.msg}", fix, at) from None
    except (RecursionError, MemoryError):  # the parser's own stack limit
        raise _Refusal("too deeply nested or too long to read", "split the expression") from None
    except ValueError as error:  # such as text that cannot be encoded
        raise _Refusal(f"cannot read the expression: {error}", "remove odd characters") from None


def _logarithm(argument: sp.Expr, base: sp.Expr | None = None) -> sp.Expr:
    """log(x) or log(x, b), refusing what SymPy would quietly turn into 0 or zoo: a base of 0
    or 1 (log(x, 0) is log(x)/log(0) = 0 to SymPy) or a logarithm of 0."""
    if argument == 0:
        raise _Refusal("log(0) is undefined", "check the argument of log")
    if base is None:
        return sp.log(argument)
    if base.is_number and (base == 0 or base == 1 or base.is_negative):
        raise _Refusal(f"log to the base {base} is undefined", "use a positive base other than 1")
    return sp.log(argument, base)


def distinct_parts(value: sp.Basic) -> list[sp.Basic]:
    """The distinct subexpressions of ``value`` (itself first), in the order of their first
    appearance in ``sp.preorder_traversal(value)``: a walk that enters a shared part once
    (a long position reuses its sums of lengths at every level).

    >>> x = sp.Symbol("x")
    >>> distinct_parts(sp.sin(x + 1) * (x + 1))
    [(x + 1)*sin(x + 1), x + 1, 1, x, sin(x + 1)]
    """
    seen: set[sp.Basic] = set()
    parts: list[sp.Basic] = []
    stack = [value]
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        parts.append(node)
        stack.extend(reversed(node.args))
    return parts


#: Expressions whose free symbols are those of their parts (no symbol bound in them).
_PLAIN = (sp.Add, sp.Mul, sp.Pow, sp.Atom, sp.Function)


def is_plain(part: sp.Basic) -> bool:
    """Whether ``part`` (not a Symbol) neither is a time function nor binds or holds symbols
    of its own (derivatives, integrals, atoms with free symbols)."""
    if not isinstance(part, _PLAIN) or isinstance(part, AppliedUndef):
        return False
    return not (isinstance(part, sp.Atom) and part.free_symbols)


def free_symbols(value: sp.Basic, parts: list[sp.Basic] | None = None) -> set[sp.Basic]:
    """``value.free_symbols``, from a walk that enters each shared part once (SymPy's walks
    the tree: a rolling constraint's axle tilt recurs in most of its terms); ``parts``: the
    :func:`distinct_parts` of ``value``, when known.

    >>> x, y = sp.symbols("x y")
    >>> sorted(free_symbols(sp.sin(x + y) * (x + y)), key=str)
    [x, y]
    """
    parts = distinct_parts(value) if parts is None else parts
    if all(isinstance(part, _PLAIN) for part in parts):
        return {part for part in parts if part.is_Symbol}
    return set(value.free_symbols)


#: A test of whether an expression is identically zero (the caller's: the probe's is_zero).
ZeroTest = Callable[[sp.Expr], bool]


def _check_denominators(value: sp.Basic, parts: Iterable[sp.Basic], is_zero: ZeroTest) -> None:
    """Refuse a division by an expression that is identically zero, such as
    1/(sin(x)**2 + cos(x)**2 - 1), which SymPy keeps and a simulation would hang on
    (``parts``: the :func:`distinct_parts` of ``value``)."""
    for part in parts:
        if (
            isinstance(part, sp.Pow)
            and part.exp.is_negative
            and part.base.free_symbols
            and is_zero(part.base)
        ):
            raise _Refusal(
                f"division by {part.base}, which is identically zero", "check the denominator"
            )


def _highest_power(value: sp.Expr) -> int:
    """The largest |n| of an integer power inside ``value`` (0 when there is none).

    >>> x = sp.Symbol("x")
    >>> _highest_power(sp.tan(x**999) + x**2), _highest_power(sp.sin(x))
    (999, 0)
    """
    powers = [abs(int(p.exp)) for p in value.atoms(sp.Pow) if p.exp.is_Integer]
    return max(powers, default=0)


def form_power(base: sp.Expr, exponent: sp.Expr) -> sp.Expr:
    """``base**exponent`` as SymPy forms it, except where SymPy's evaluation crawls.

    An exponent with a sum in its denominator makes SymPy look for ``b**(c/log(b))`` through
    ``sign(im(b))``, which splits ``b`` into real and imaginary parts: for
    ``tan(x**999)**(x/(x + 1))`` it expands ``(re + i*im)**999`` for minutes, only to find
    that the power is not ``exp(c)``.  Such a power is kept as written; it means the same.

    >>> x = sp.Symbol("x")
    >>> form_power(sp.tan(x**999), x / (x + 1))
    tan(x**999)**(x/(x + 1))
    """
    if not exponent.is_Atom and sp.fraction(exponent)[1].is_Add:
        return sp.Pow(base, exponent, evaluate=False)
    return sp.Pow(base, exponent)


def expanded_terms(value: sp.Basic, limit: int = MAX_TERMS) -> int:
    """At most how many terms ``value`` has once its products and integer powers of sums are
    multiplied out (at most ``limit + 1``: the count stops there): the smaller of the count
    of products and of the monomials its degrees allow (a product of 29 factors x + i has 30
    terms, not 2**29).

    >>> x, y = sp.symbols("x y")
    >>> expanded_terms((x + y + 1) ** 2), expanded_terms(sp.sin((x + y) ** 9))
    (6, 1)
    """
    return _expanded_terms(value, limit, {}, {})


def _expanded_terms(
    value: sp.Basic, limit: int, degrees: dict[sp.Basic, dict[sp.Basic, int]], products: dict
) -> int:
    """:func:`expanded_terms`, with the degrees and products of parts known from ``degrees``
    and ``products`` (filled in as they are found; ``products`` for this ``limit`` only)."""
    monomials = 1
    for degree in _degrees(value, degrees).values():
        monomials = min(limit + 1, monomials * (degree + 1))
    return min(monomials, _products(value, limit, products))


def _degrees(value: sp.Basic, memo: dict[sp.Basic, dict[sp.Basic, int]]) -> dict[sp.Basic, int]:
    """The degree of ``value`` in each of its generators (symbols, and functions or powers
    that are not polynomial), read from its tree without expanding it (``memo``: the degrees
    of parts found before; the dicts are shared, never changed)."""
    found = memo.get(value)
    if found is not None:
        return found
    found = {}
    if isinstance(value, sp.Add):
        for a in value.args:
            for generator, degree in _degrees(a, memo).items():
                found[generator] = max(found.get(generator, 0), degree)
    elif isinstance(value, sp.Mul):
        for a in value.args:
            for generator, degree in _degrees(a, memo).items():
                found[generator] = found.get(generator, 0) + degree
    elif isinstance(value, sp.Pow) and value.exp.is_Integer and value.exp > 0:
        found = {g: d * int(value.exp) for g, d in _degrees(value.base, memo).items()}
    elif not value.is_number:
        found = {value: 1}
    memo[value] = found
    return found


def _products(
    value: sp.Basic, limit: int, memo: dict[sp.Basic, int], *, harmonics: bool = False
) -> int:
    """The terms of ``value`` multiplied out, like terms not merged (at most ``limit + 1``;
    ``memo``: the counts of parts found before, for this ``limit`` and ``harmonics``).
    ``harmonics``: a power of a sum with sines and cosines counts its harmonics
    (:func:`harmonic_terms`), not its monomials."""
    count = memo.get(value)
    if count is not None:
        return count
    count = 1  # a symbol, a number, a function: its arguments are not multiplied out
    if isinstance(value, sp.Add):
        count = min(
            limit + 1, sum(_products(a, limit, memo, harmonics=harmonics) for a in value.args)
        )
    elif isinstance(value, sp.Mul):
        for factor in value.args:
            count = min(limit + 1, count * _products(factor, limit, memo, harmonics=harmonics))
    elif isinstance(value, sp.Pow) and value.exp.is_Integer and value.exp > 1:
        terms = _products(value.base, limit, memo, harmonics=harmonics)
        n = int(value.exp)
        if harmonics and value.base.has(*_TRIG):
            memo[value] = count = _delannoy(terms, n, limit)
            return count
        # C(n + terms - 1, terms - 1): the monomials of degree n in ``terms``
        for i in range(1, min(n, terms - 1) + 1):
            count = count * (n + terms - 1 - min(n, terms - 1) + i) // i
            if count > limit:
                count = limit + 1
                break
    memo[value] = count
    return count


#: The operations of one term of a sum of harmonics: its coefficient, its product, the sine
#: or cosine and its argument.
OPERATIONS_PER_HARMONIC = 4
_TRIG = (sp.sin, sp.cos)


def harmonic_terms(value: sp.Basic, limit: int = MAX_TERMS) -> int:
    """At most how many terms ``value`` has once its powers and products of sines and
    cosines are multiplied out into sums of harmonics, as the derivation reduces them
    (capped at ``limit + 1``).  The frequencies of a power n of a sum of k terms with sines
    and cosines are the integer vectors h in k dimensions with |h|_1 <= n, whose number is
    the Delannoy number D(k, n) = sum_j 2^j C(k, j) C(n, j); h and -h make one term, and
    those of the wrong parity cancel, which leaves about D(k, n) / 3 (as counted against
    SymPy's product-to-sum expansion in the tests).  (sin a + sin b + sin c + cos d)**40 has
    some 600,000 harmonics, where its 12,341 monomials would suggest a small sum.

    >>> a, b = sp.symbols("a b")
    >>> harmonic_terms(sp.sin(a) ** 3), harmonic_terms((sp.sin(a) + sp.cos(b)) ** 2)
    (3, 5)
    """
    return _products(value, limit, {}, harmonics=True)


def _delannoy(k: int, n: int, limit: int) -> int:
    """The harmonics of a power n of k terms, D(k, n) / 3 rounded up (:func:`harmonic_terms`),
    capped at ``limit + 1``."""
    total = 0
    for j in range(min(k, n) + 1):
        total += 2**j * math.comb(k, j) * math.comb(n, j)
        if total > 3 * limit:
            return limit + 1
    return -(-total // 3)


def _check_harmonics(value: sp.Basic, memo: dict[sp.Basic, int]) -> None:
    """Refuse, by the size limit (:mod:`lagrangian.size_limits`), an expression whose sines
    and cosines multiply out into more operations than the limit allows (predicted from its
    structure before any work)."""
    if not value.has(*_TRIG):
        return
    limit = active_operations()
    terms_limit = int(min(limit, 10**12)) // OPERATIONS_PER_HARMONIC
    terms = _products(value, terms_limit, memo, harmonics=True)
    if terms > terms_limit:
        predicted = f"more than {terms_limit * OPERATIONS_PER_HARMONIC:,}"
        raise _Refusal(
            f"multiplied out into sums of harmonics (as the derivation reduces sines and "
            f"cosines), this expression would have {predicted} operations, beyond the size "
            f"limit of {limit:,.0f}",
            f"write it with fewer or lower powers of sums of sines and cosines; or "
            f"{raise_advice()}",
        )


def expanded_bits(value: sp.Basic) -> int:
    """About how many bits the largest number of ``value`` has once its products and integer
    powers of sums are multiplied out: a product adds its factors' sizes, a sum of n terms
    adds log2(n) (a binomial coefficient), a power n multiplies by n.

    >>> x = sp.Symbol("x")
    >>> expanded_bits((x + 1) ** 10), expanded_bits((x + 3) * (x + 5))
    (20, 7)
    """
    return _bits_memo(value, {})


def _bits_memo(value: sp.Basic, memo: dict[sp.Basic, int]) -> int:
    if value in memo:
        return memo[value]
    bits = 0
    if isinstance(value, sp.Rational):
        bits = _bits(value)
    elif isinstance(value, sp.Add):
        bits = max(_bits_memo(a, memo) for a in value.args) + (len(value.args) - 1).bit_length()
    elif isinstance(value, sp.Mul):
        bits = sum(_bits_memo(a, memo) for a in value.args)
    elif isinstance(value, sp.Pow) and value.exp.is_Integer:
        bits = abs(int(value.exp)) * _bits_memo(value.base, memo)
    memo[value] = bits
    return bits


def _written_bits(value: sp.Basic, memo: dict[sp.Basic, int]) -> int:
    """The bits of the largest number in ``value`` (0 when there is none)."""
    bits = memo.get(value)
    if bits is None:
        if isinstance(value, sp.Rational):
            bits = _bits(value)
        else:
            bits = max([_written_bits(a, memo) for a in value.args], default=0)
        memo[value] = bits
    return bits


def _unchecked_parts(value: sp.Basic, checked: set[sp.Basic]) -> list[sp.Basic]:
    """The :func:`distinct_parts` of ``value`` that are not in ``checked``, in their order
    (the parts of a checked part are checked too, so the walk does not enter it)."""
    seen: set[sp.Basic] = set()
    parts: list[sp.Basic] = []
    stack = [value]
    while stack:
        node = stack.pop()
        if node in seen or node in checked:
            continue
        seen.add(node)
        parts.append(node)
        stack.extend(reversed(node.args))
    return parts


def _check_result(
    value: sp.Basic, cache: ParseCache | None = None, zero_test: ZeroTest | None = None
) -> None:
    """Products and powers merge numbers and exponents (``x**999*x**9``): check the result.

    With a ``cache``, the parts that passed every check of a part in an expression before
    are not checked again (no refusal can come from them) and what the whole is counted from
    (degrees, products, sizes of numbers) is remembered for each part."""
    shared = cache if cache is not None else ParseCache()
    # each check in preorder, a shared part once
    parts = distinct_parts(value) if cache is None else _unchecked_parts(value, cache.checked)
    if zero_test is not None:
        _check_denominators(value, parts, zero_test)
    if _expanded_terms(value, MAX_TERMS, shared.degrees, shared.products) > MAX_TERMS:
        raise _Refusal(
            f"multiplied out, this expression has more than {MAX_TERMS:,} terms",
            "write it with fewer or shorter sums under powers and products",
        )
    _check_harmonics(value, shared.harmonics)
    written = _written_bits(value, shared.written)
    if (bits := _bits_memo(value, shared.bits)) > written + MAX_EXPANDED_BITS:
        raise _Refusal(
            f"multiplied out, this expression has numbers of about {bits * 3 // 10:,} digits",
            "write it with fewer sums under powers and products (a long product of sums "
            "multiplies out to huge coefficients)",
        )
    for part in parts:
        if part in _UNDEFINED:
            raise _Refusal(f"the expression is undefined ({part})", "check the formula")
        if isinstance(part, sp.Rational):
            _check_size(part)
        if isinstance(part, sp.Pow) and part.exp.is_Number and abs(part.exp) > MAX_EXPONENT:
            raise _Refusal(f"a power {part.exp} beyond ±{MAX_EXPONENT}", "use smaller exponents")
    if cache is not None:
        cache.checked.update(parts)


def parse_expression(
    text: str | int | float,
    names: Mapping[str, sp.Basic],
    *,
    field: str,
    source: str | None = None,
    line: int | None = None,
    column: int | None = None,
    cache: ParseCache | None = None,
    zero_test: ZeroTest | None = None,
) -> sp.Expr:
    """The SymPy expression a model file's text means, or an ExpressionError saying why not.

    The language (see the module): numbers, names, ``+ - * / **``, parentheses and calls of
    sin cos tan cot sec csc asin acos atan atan2 sinh cosh tanh exp log sqrt Abs sign Heaviside.
    ``names`` maps every allowed identifier to its SymPy object (``pi`` and ``E`` are added
    unless given).  ``field`` is the dotted path of the field, ``source`` the file name, and
    ``line``/``column`` where the text starts in the file (1-based); without them positions
    are counted from the start of the text.  A bare int or float becomes an exact number.
    ``cache``: a :class:`ParseCache` shared by the expressions of one model (the results are
    the same with it, and come faster where the texts repeat parts).  ``zero_test``: how to
    tell that a denominator is identically zero (``lagrangian.symbolic.probe.is_zero``; the
    parser sits below the probe and takes it from its caller), refused as a division by
    zero; None leaves denominators unchecked.

    >>> import sympy as sp
    >>> theta = sp.Symbol("theta")
    >>> parse_expression("1 - cos(theta)", {"theta": theta}, field="potential")
    1 - cos(theta)
    """
    prefix = ""
    try:
        if not isinstance(text, str):
            return _number(text)
        if len(text) > MAX_LENGTH:
            raise _Refusal(f"{len(text)} characters, more than {MAX_LENGTH}", "shorten it")
        text = text.replace("\r\n", "\n").replace("\r", "\n")
        body = text.lstrip(" \t\f\n")  # Python refuses leading indentation
        prefix = text[: len(text) - len(body)]
        declared = _declared_symbol(body, names)
        if declared is not None:
            return declared
        if cache is not None:
            cache.use(names)
        value = _Builder(body, names, cache).build(_read(body).body, 1)
        _check_result(value, cache, zero_test)
        return value
    except _Refusal as refusal:
        at_line, at_column = (
            (line, column) if refusal.at is None else _locate(refusal.at, prefix, line, column)
        )
        problem = Problem(field, refusal.message, refusal.fix, at_line, at_column, source)
        raise ExpressionError(problems=[problem]) from None


def _declared_symbol(text: str, names: Mapping[str, sp.Basic]) -> sp.Symbol | None:
    """The symbol ``text`` names when it is one declared name standing for a symbol (a mass,
    an inertia, a coordinate: most fields of a model file), else None.  Such a text reads
    as that symbol and nothing in it can be refused, so it needs no syntax tree and no checks.
    """
    if not (text.isascii() and text.isidentifier()) or text[0] == "_" or keyword.iskeyword(text):
        return None
    value = names.get(text)
    return value if isinstance(value, sp.Symbol) else None


#: The comparisons a condition may make, by the Python operator that writes them.
_COMPARISONS: dict[type, Callable[[sp.Expr, sp.Expr], sp.Basic]] = {
    ast.Lt: sp.StrictLessThan,
    ast.LtE: sp.LessThan,
    ast.Gt: sp.StrictGreaterThan,
    ast.GtE: sp.GreaterThan,
}


def parse_condition(
    text: str,
    names: Mapping[str, sp.Basic],
    *,
    field: str,
    source: str | None = None,
    line: int | None = None,
    column: int | None = None,
    zero_test: ZeroTest | None = None,
) -> sp.Basic:
    """A comparison of two expressions of the language (``theta < 0``, ``x >= l/2``) as a SymPy
    relational: the text is split at its one comparison operator by Python's parser (which
    runs nothing) and each side read by :func:`parse_expression`, positions kept.

    >>> theta = sp.Symbol("theta")
    >>> parse_condition("theta < 0", {"theta": theta}, field="when")
    theta < 0
    """
    try:
        tree = _read(text.strip()) if isinstance(text, str) else None
        compare = tree.body if tree is not None else None
        if not (
            isinstance(compare, ast.Compare)
            and len(compare.ops) == 1
            and type(compare.ops[0]) in _COMPARISONS
        ):
            raise _Refusal("not one comparison", "write one comparison, e.g. theta < 0")
    except _Refusal as refusal:
        problem = Problem(field, refusal.message, refusal.fix, line, column, source)
        raise ExpressionError(problems=[problem]) from None
    body = text.strip()
    offset = len(text) - len(text.lstrip())
    sides = []
    for node in (compare.left, compare.comparators[0]):
        segment = ast.get_source_segment(body, node) or ""
        at = None if column is None else column + offset + node.col_offset
        sides.append(parse_expression(segment, names, field=field, source=source, line=line,
                                      column=at, zero_test=zero_test))  # fmt: skip
    return _COMPARISONS[type(compare.ops[0])](*sides)


def parse_expressions(
    items: Iterable[tuple[str, str | int | float]],
    names: Mapping[str, sp.Basic],
    *,
    source: str | None = None,
    zero_test: ZeroTest | None = None,
) -> list[sp.Expr]:
    """Parse many ``(field, text)`` pairs; raise one ExpressionError listing every problem
    (``zero_test`` as for :func:`parse_expression`).

    >>> x = sp.Symbol("x")
    >>> parse_expressions([("a", "x + 1"), ("b", "2*x")], {"x": x})
    [x + 1, 2*x]
    """
    results: list[sp.Expr] = []
    problems: list[Problem] = []
    for field, text in items:
        try:
            results.append(
                parse_expression(text, names, field=field, source=source, zero_test=zero_test)
            )
        except ExpressionError as error:
            problems.extend(error.problems)
    raise_if_problems(problems, "Some expressions cannot be read", ExpressionError)
    return results
