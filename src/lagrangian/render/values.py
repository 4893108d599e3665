"""The parameter values a document holds for, written the one way every report writes them:
``m = 1, g = 9.81`` — the closing line of ``derive`` (the values in force, and whether they
are put in) and the "at ..." line of ``analyze`` (the values its statements are decided at),
in text and in LaTeX.

>>> import sympy as sp
>>> values_text([(sp.Symbol("m"), 1.0), (sp.Symbol("g"), sp.Float(9.81)), (sp.Symbol("k"), None)])
'm = 1, g = 9.81, k = no value'
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import sympy as sp

from lagrangian.analysis.evaluation import number_text
from lagrangian.model import System
from lagrangian.render.latex import expression_latex

#: Parameter and value (None: the parameter has no value; an expression where one is given).
Pairs = Iterable[tuple[Any, Any]]
#: Between two values in LaTeX.
SEPARATOR = r",\quad "


def values_text(pairs: Pairs) -> str:
    """``name = value, ...`` in plain text."""
    return ", ".join(f"{p} = {number_text(v)}" for p, v in pairs)


def values_latex(pairs: Pairs, tex: Callable[[Any], str]) -> str:
    """``name = value, ...`` in LaTeX, names (and expressions) by ``tex``."""
    shown = []
    for p, v in pairs:
        if v is None:
            value = r"\text{no value}"
        elif isinstance(v, sp.Basic) and not v.is_number:
            value = tex(v)
        else:
            value = number_text(v)
        shown.append(f"{tex(p)} = {value}")
    return SEPARATOR.join(shown)


def values_in_force(system: System, substituted: bool, latex: bool = False) -> str:
    """The parameters' values the equations hold for (after ``--set``), and whether they are
    put in: a student asking for m1=2 sees it, and how to see the equations with it.

    >>> import lagrangian as lg
    >>> values_in_force(lg.examples.simple_pendulum(), False)
    'Parameters: m = 1, g = 9.81, l = 1 (derive --substitute puts them in)'
    """
    given = list(system.parameters.items())
    if not given:
        return ""
    if latex:
        return f"\\[ {values_latex(given, lambda e: expression_latex(e, system.coordinates))} \\]"
    how = "put in" if substituted else "derive --substitute puts them in"
    return f"Parameters: {values_text((p.name, v) for p, v in given)} ({how})"
