"""to_sympy: the one way a value becomes a SymPy object in lagrangian, without ever running
text as Python.

``sympy.sympify`` of a string evaluates it as Python code (``sympify("__import__('os')...")``
runs it), so no string from any API reaches it: text goes through the model files' own parser
(:mod:`lagrangian.model.expressions`: numbers, names, arithmetic and a fixed list of
functions, built without ``eval``), and everything else through ``sympify(strict=True)``, which
converts numbers, SymPy and SymEngine objects and refuses the rest.  A test walks the source
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

import numpy as np
import sympy as sp

# SymPy's Add imports its tensor module on first use (tens of milliseconds); doing it with the
# other imports keeps that cost out of the first model built or derived.
import sympy.tensor.tensor

from lagrangian.model.expressions import CONSTANTS, FUNCTIONS, parse_expression

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def to_sympy(value: Any, field: str = "expression") -> Any:
    """``value`` as SymPy: text by the safe parser (its names become symbols), lists and tuples
    element by element, numeric NumPy arrays as matrices or arrays, and numbers, SymPy and
    SymEngine objects by ``sympify(strict=True)``.  ``field`` names the value in errors."""
    if isinstance(value, str):
        return parse_text(value, field)
    if isinstance(value, (list, tuple)):
        return type(value)(to_sympy(item, field) for item in value)
    if isinstance(value, np.ndarray) and value.dtype.kind in "biuf":
        return sp.sympify(value.tolist(), strict=False)  # numbers only: nothing to evaluate
    return sp.sympify(value, strict=True)


def parse_text(text: str, field: str = "expression") -> sp.Expr:
    """The expression ``text`` means in the model-file language, its names as symbols."""
    reserved = set(FUNCTIONS) | set(CONSTANTS)
    names = {name: sp.Symbol(name) for name in _IDENTIFIER.findall(text) if name not in reserved}
    return parse_expression(text, names, field=field)


def to_matrix(value: Any, field: str = "matrix") -> sp.Matrix:
    """``value`` (a SymPy matrix, or nested lists of numbers, expressions or text) as a
    mutable SymPy Matrix, its text entries read by the safe parser (``sympy.Matrix`` would
    ``sympify`` them)."""
    if isinstance(value, sp.MatrixBase):
        return sp.Matrix(value)
    return sp.Matrix(to_sympy(list(value) if not isinstance(value, list) else value, field))
