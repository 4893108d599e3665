"""to_sympy: the one way a value becomes a SymPy object in lagrangian, without ever running
text as Python.

``sympy.sympify`` of a string evaluates it as Python code (``sympify("__import__('os')...")``
runs it), so no string from any API reaches it: text goes through the model files' own parser
(:mod:`lagrangian.symbolic.expressions`: numbers, names, arithmetic and a fixed list of
functions, built without ``eval``), and everything else through ``sympify(strict=True)``
(:mod:`lagrangian.symbolic.objects`), which converts numbers, SymPy and SymEngine objects and
refuses the rest.  A test walks the source
and fails on any other call of ``sympify``.

>>> to_sympy("m*g*l*(1 - cos(theta))")
g*l*m*(1 - cos(theta))
>>> to_sympy("__import__('os').system('ls')")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
lagrangian.errors.ExpressionError: expression (line 1, column 1): only the listed functions ...
"""

from __future__ import annotations

import re
from typing import Any

import sympy as sp

from lagrangian.symbolic.expressions import CONSTANTS, FUNCTIONS, parse_expression
from lagrangian.symbolic.objects import sympy_object
from lagrangian.symbolic.probe import is_zero

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def to_sympy(value: Any, field: str = "expression") -> Any:
    """``value`` as SymPy: text by the safe parser (its names become symbols), lists and tuples
    element by element, numeric NumPy arrays as matrices or arrays, and numbers, SymPy and
    SymEngine objects by ``sympify(strict=True)``.  ``field`` names the value in errors."""
    if isinstance(value, str):
        return parse_text(value, field)
    if isinstance(value, (list, tuple)):
        return type(value)(to_sympy(item, field) for item in value)
    return sympy_object(value)


def parse_text(text: str, field: str = "expression") -> sp.Expr:
    """The expression ``text`` means in the model-file language, its names as symbols."""
    reserved = set(FUNCTIONS) | set(CONSTANTS)
    names = {name: sp.Symbol(name) for name in _IDENTIFIER.findall(text) if name not in reserved}
    return parse_expression(text, names, field=field, zero_test=is_zero)


def to_matrix(value: Any, field: str = "matrix") -> sp.Matrix:
    """``value`` (a SymPy matrix, or nested lists of numbers, expressions or text) as a
    mutable SymPy Matrix, its text entries read by the safe parser (``sympy.Matrix`` would
    ``sympify`` them)."""
    if isinstance(value, sp.MatrixBase):
        return sp.Matrix(value)
    return sp.Matrix(to_sympy(list(value) if not isinstance(value, list) else value, field))
