"""The safe expression language of model files (DESIGN.md, "Expression language").

Allowed: numbers, names (coordinates, ``NAME_dot``, parameters, ``t``, ``pi``, ``E``),
``+ - * / **``, parentheses, and calls of sin cos tan asin acos atan atan2 sinh cosh tanh exp
log sqrt Abs sign Heaviside.  The text is parsed by Python's ``ast`` and every node is checked
against an allow-list and turned into SymPy directly: nothing is ever evaluated as code
(no ``eval``, no ``sympify`` of the text).  Decimal literals become exact rationals
(``0.1`` -> 1/10) so derivations stay exact.  Sizes are bounded so no input can hang.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> parse_expression("0.5*k*x**2", {"x": x, "k": sp.Symbol("k")}, field="potential")
k*x**2/2
"""

from __future__ import annotations

import ast
import difflib
import warnings
from collections.abc import Callable, Iterable, Mapping
from fractions import Fraction
from typing import Any

import sympy as sp

from lagrangian.errors import ExpressionError, Problem, raise_if_problems

MAX_LENGTH = 10_000
MAX_DEPTH = 100
MAX_DIGITS = 1000
MAX_EXPONENT = 1000

FUNCTIONS: dict[str, tuple[Callable[..., sp.Expr], tuple[int, ...]]] = {
    "sin": (sp.sin, (1,)),
    "cos": (sp.cos, (1,)),
    "tan": (sp.tan, (1,)),
    "asin": (sp.asin, (1,)),
    "acos": (sp.acos, (1,)),
    "atan": (sp.atan, (1,)),
    "atan2": (sp.atan2, (2,)),
    "sinh": (sp.sinh, (1,)),
    "cosh": (sp.cosh, (1,)),
    "tanh": (sp.tanh, (1,)),
    "exp": (sp.exp, (1,)),
    "log": (sp.log, (1, 2)),
    "sqrt": (sp.sqrt, (1,)),
    "Abs": (sp.Abs, (1,)),
    "sign": (sp.sign, (1,)),
    "Heaviside": (sp.Heaviside, (1,)),
}
CONSTANTS: dict[str, sp.Expr] = {"pi": sp.pi, "E": sp.E}
ALLOWED = "numbers, names, + - * / **, parentheses and the functions " + " ".join(FUNCTIONS)

_BINARY = {
    ast.Add: sp.Add,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: sp.Mul,
    ast.Div: lambda a, b: a / b,
    ast.Pow: sp.Pow,
}
_CHAINED = (ast.Add, ast.Sub, ast.Mult, ast.Div)
_REFUSED_OPERATORS = {
    ast.BitXor: ("'^' is not a power", "use ** for powers"),
    ast.MatMult: ("'@' is not allowed", ALLOWED),
    ast.Mod: ("'%' is not allowed", ALLOWED),
    ast.FloorDiv: ("'//' is not allowed", "use / for division"),
}


class _Refusal(Exception):
    """Raised inside the walk; turned into an ExpressionError with the position."""

    def __init__(self, node: ast.AST | None, message: str, fix: str = ALLOWED) -> None:
        super().__init__(message)
        self.node, self.message, self.fix = node, message, fix


def _number(node: ast.Constant) -> sp.Expr:
    value = node.value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        kind = "a string" if isinstance(value, (str, bytes)) else repr(value)
        raise _Refusal(node, f"{kind} is not a number or a name")
    if isinstance(value, int):
        if len(str(abs(value))) > MAX_DIGITS:
            raise _Refusal(
                node, f"an integer of more than {MAX_DIGITS} digits", "use a smaller number"
            )
        return sp.Integer(value)
    if value != value or value in (float("inf"), float("-inf")):
        raise _Refusal(node, "not a finite number")
    # The decimal text the user wrote, exactly: repr gives the shortest round-trip form.
    return sp.Rational(Fraction(repr(value)))


class _Builder:
    """Turns an allow-listed ``ast`` tree into SymPy, refusing everything else."""

    def __init__(self, names: Mapping[str, sp.Basic]) -> None:
        self.names = {**CONSTANTS, **names}

    def build(self, node: ast.AST, depth: int = 0) -> sp.Expr:
        if depth > MAX_DEPTH:
            raise _Refusal(
                node, f"nested more than {MAX_DEPTH} levels deep", "simplify the expression"
            )
        if isinstance(node, ast.Expression):
            return self.build(node.body, depth + 1)
        if isinstance(node, ast.Constant):
            return _number(node)
        if isinstance(node, ast.Name):
            return self._name(node)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
            operand = self.build(node.operand, depth + 1)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.BinOp):
            return self._binary(node, depth)
        if isinstance(node, ast.Call):
            return self._call(node, depth)
        raise _Refusal(node, f"{_describe(node)} is not allowed")

    def _name(self, node: ast.Name) -> sp.Expr:
        if node.id.startswith("_"):
            raise _Refusal(
                node,
                f"the name {node.id!r} is not allowed",
                "names may not start with an underscore",
            )
        if node.id in self.names:
            return self.names[node.id]
        if node.id in FUNCTIONS:
            raise _Refusal(node, f"{node.id} is a function", f"call it: {node.id}(...)")
        close = difflib.get_close_matches(node.id, sorted(self.names), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        return _raise(
            _Refusal(
                node,
                f"unknown name {node.id!r}",
                hint + "declare it in parameters (or coordinates)",
            )
        )

    def _binary(self, node: ast.BinOp, depth: int) -> sp.Expr:
        """A left-leaning chain a + b - c + ... (or * and /) is walked as one level, so a long
        sum is not mistaken for deep nesting."""
        chain: list[ast.BinOp] = []
        current: ast.AST = node
        while isinstance(current, ast.BinOp) and type(current.op) in _CHAINED:
            chain.append(current)
            current = current.left
        if not chain:
            return self._single(node, depth)
        result = self.build(current, depth + 1)
        for link in reversed(chain):
            result = _BINARY[type(link.op)](result, self.build(link.right, depth + 1))
        return result

    def _single(self, node: ast.BinOp, depth: int) -> sp.Expr:
        if type(node.op) in _REFUSED_OPERATORS:
            message, fix = _REFUSED_OPERATORS[type(node.op)]
            raise _Refusal(node, message, fix)
        if type(node.op) not in _BINARY:
            raise _Refusal(node, f"the operator {type(node.op).__name__} is not allowed")
        left = self.build(node.left, depth + 1)
        right = self.build(node.right, depth + 1)
        if isinstance(node.op, ast.Pow):
            _check_power(node, left, right)
        return _BINARY[type(node.op)](left, right)

    def _call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            raise _Refusal(node, f"calling {_describe(node.func)} is not allowed")
        name = node.func.id
        if name not in FUNCTIONS:
            close = difflib.get_close_matches(name, sorted(FUNCTIONS), n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise _Refusal(node, f"unknown function {name!r}", hint + "allowed: " + ALLOWED)
        if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
            raise _Refusal(node, f"{name}() takes plain arguments only")
        function, arities = FUNCTIONS[name]
        if len(node.args) not in arities:
            expected = " or ".join(str(a) for a in arities)
            raise _Refusal(
                node,
                f"{name}() takes {expected} argument(s), got {len(node.args)}",
                f"write {name}(x)" if arities == (1,) else f"write {name}(y, x)",
            )
        return function(*[self.build(a, depth + 1) for a in node.args])


def _raise(refusal: _Refusal) -> sp.Expr:
    raise refusal


def _check_power(node: ast.BinOp, base: sp.Expr, exponent: sp.Expr) -> None:
    """Refuse numeric exponents too large to compute (``9**9**9``)."""
    if exponent.is_number and exponent.is_finite is not False:
        size = abs(exponent)
        if size.is_number and bool(size > MAX_EXPONENT):
            raise _Refusal(
                node,
                f"the exponent {exponent} is larger than {MAX_EXPONENT}",
                "use a smaller exponent",
            )
    if base.is_number and base.is_finite and exponent.is_number:
        magnitude = abs(base)
        if bool(magnitude > 1) and bool(abs(exponent) * sp.log(magnitude, 10) > MAX_DIGITS):
            raise _Refusal(node, "the power is too large a number", "use a smaller number")


def _describe(node: ast.AST) -> str:
    names = {
        ast.Attribute: "attribute access",
        ast.Subscript: "indexing",
        ast.Lambda: "a lambda",
        ast.ListComp: "a comprehension",
        ast.SetComp: "a comprehension",
        ast.DictComp: "a comprehension",
        ast.GeneratorExp: "a comprehension",
        ast.Compare: "a comparison",
        ast.BoolOp: "a boolean operator",
        ast.NamedExpr: "an assignment",
        ast.JoinedStr: "an f-string",
        ast.List: "a list",
        ast.Tuple: "a tuple",
        ast.Dict: "a dict",
        ast.Set: "a set",
        ast.IfExp: "an if-expression",
        ast.Starred: "a starred argument",
        ast.Call: "a call",
        ast.Await: "await",
        ast.Yield: "yield",
    }
    return names.get(type(node), type(node).__name__)


def _position(
    node: ast.AST | None, line: int | None, column: int | None
) -> tuple[int | None, int | None]:
    """File position of ``node``: its line/column in the text shifted by where the text is."""
    node_line = getattr(node, "lineno", None)
    node_column = getattr(node, "col_offset", None)
    if node_line is None:
        return line, column
    file_line = node_line if line is None else line + node_line - 1
    file_column = node_column + 1 if node_column is not None else None
    if node_line == 1 and column is not None and file_column is not None:
        file_column += column - 1
    return file_line, file_column


def parse_expression(
    text: str | int | float,
    names: Mapping[str, sp.Basic],
    *,
    field: str,
    source: str | None = None,
    line: int | None = None,
    column: int | None = None,
) -> sp.Expr:
    """A SymPy expression from user text, or ExpressionError naming field, line and column.

    ``names`` maps every allowed identifier to its SymPy object; ``line``/``column`` say where
    the text starts in its file (1-based) so errors point into the file.
    """

    def refuse(node: ast.AST | None, message: str, fix: str = ALLOWED) -> ExpressionError:
        at_line, at_column = _position(node, line, column)
        return ExpressionError(problems=[Problem(field, message, fix, at_line, at_column, source)])

    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise refuse(None, f"{text!r} is not an expression", "write a number or a formula")
    if isinstance(text, (int, float)):
        return _number(ast.Constant(value=text))
    if len(text) > MAX_LENGTH:
        raise refuse(None, f"longer than {MAX_LENGTH} characters", "shorten the expression")
    if not text.strip():
        raise refuse(None, "empty expression", "write a number or a formula")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as error:
        node = ast.Constant(value=0, lineno=error.lineno or 1, col_offset=(error.offset or 1) - 1)
        raise refuse(node, f"syntax error: {error.msg}", ALLOWED) from None
    except (RecursionError, MemoryError, ValueError):
        raise refuse(
            None, f"nested more than {MAX_DEPTH} levels deep", "simplify the expression"
        ) from None
    try:
        return _Builder(names).build(tree)
    except _Refusal as refusal:
        raise refuse(refusal.node, refusal.message, refusal.fix) from None
    except RecursionError:
        raise refuse(
            None, f"nested more than {MAX_DEPTH} levels deep", "simplify the expression"
        ) from None


def parse_expressions(
    items: Iterable[tuple[str, Any]], names: Mapping[str, sp.Basic], *, source: str | None = None
) -> list[sp.Expr]:
    """Parse many ``(field, text)`` pairs; raise one ExpressionError listing every problem."""
    results: list[sp.Expr] = []
    problems: list[Problem] = []
    for field, text in items:
        try:
            results.append(parse_expression(text, names, field=field, source=source))
        except ExpressionError as error:
            problems.extend(error.problems)
    raise_if_problems(problems, "Some expressions are not valid", ExpressionError)
    return results
