"""What the rolling-contact tests share with sympy.physics.mechanics: KanesMethod's
dynamicsymbols renamed to lagrangian's plain symbols, and matrices evaluated to floats."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me

from lagrangian.symbolic.symbols import t


def plain_symbols(q: Sequence[Any], u: Sequence[Any]) -> dict[Any, sp.Symbol]:
    """q_i(t) -> q_i, u_i(t) -> q_i_dot (the speeds are the coordinates' rates), t -> t."""
    plain: dict[Any, sp.Symbol] = {me.dynamicsymbols._t: t}
    for qi, ui in zip(q, u):
        plain[ui] = sp.Symbol(qi.func.__name__ + "_dot")
        plain[qi] = sp.Symbol(qi.func.__name__)
    return plain


def numbers(expr: sp.Basic, values: dict) -> np.ndarray:
    """``expr`` (a matrix or vector) at ``values``, to 30 digits, as floats."""
    return np.array(sp.Matrix(expr).xreplace(values).evalf(30), dtype=float)
