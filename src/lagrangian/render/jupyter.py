"""Rich display in Jupyter: typeset equations, steps and systems.

IPython is optional: :func:`register` does nothing when it is not installed or not running,
and nothing is registered until it is called (``lg.render.register()``, or
``%load_ext lagrangian``, which calls it).
The render layer adds no methods to the model and derive types; it registers formatters.

>>> import lagrangian as lg
>>> shown = display_steps(lg.derive(lg.examples.simple_pendulum()))
>>> shown._repr_latex_().startswith("$$\\\\begin{aligned}")
True
"""

from __future__ import annotations

import html
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis import AnalysisReport
from lagrangian.derivation import CoordinateSteps, EquationsOfMotion
from lagrangian.derivation.steps import Steps
from lagrangian.model import System
from lagrangian.render.analysis_latex import RESULT_TYPES, analysis_latex, result_latex
from lagrangian.render.latex import (
    coordinate_steps_latex,
    equations_latex,
    expression_latex,
    steps_latex,
    system_latex,
)
from lagrangian.render.plots import overview_png
from lagrangian.simulation.trajectory import Drift, Trajectory
from lagrangian.symbolic.symbols import DDOT_SUFFIX, DOT_SUFFIX

# MathJax 3 and KaTeX refuse align* inside $$...$$ ("erroneous nesting"); aligned works.
_NESTED = "aligned"


@dataclass(frozen=True)
class Latex:
    """LaTeX math that Jupyter typesets (``display(Latex(...))``) and ``print`` shows as is.

    >>> str(Latex(r"\\dot{x} = v"))
    '\\\\dot{x} = v'
    """

    text: str

    def _repr_latex_(self) -> str:
        return f"$${self.text}$$"

    def __str__(self) -> str:
        return self.text


def display_steps(eom: EquationsOfMotion) -> Latex:
    """The derivation of ``eom`` as a displayable :class:`Latex` (``display(...)`` it)."""
    return Latex(steps_latex(eom, environment=_NESTED))


def _eom_latex(eom: EquationsOfMotion) -> str:
    return Latex(equations_latex(eom, environment=_NESTED))._repr_latex_()


def _coordinate_steps_latex(steps: CoordinateSteps) -> str:
    return Latex(coordinate_steps_latex(steps, environment=_NESTED))._repr_latex_()


def _every_steps_latex(steps: Steps) -> str:
    return "\n".join(_coordinate_steps_latex(one) for one in steps)


def drift_html(drift: Drift) -> str:
    """The drift report as an HTML table: each quantity, its drift or why it has none."""
    rows = []
    for key, value in drift.items():
        shown = f"{value:.3g}" if isinstance(value, float) else html.escape(str(value))
        rows.append(f"<tr><td>{html.escape(key)}</td><td>{shown}</td></tr>")
    head = "<tr><th>quantity</th><th>drift, or why it has none</th></tr>"
    return f"<table>{head}{''.join(rows)}</table>"


def _system_latex(system: System) -> str:
    return Latex(system_latex(system, environment=_NESTED))._repr_latex_()


def _analysis_latex(report: AnalysisReport) -> str:
    return Latex(analysis_latex(report, environment=_NESTED))._repr_latex_()


def _result_latex(result: object) -> str | None:
    text = result_latex(result)
    if text is None:
        return None
    return Latex(text.replace("align*", _NESTED))._repr_latex_()


def dotted_latex(expr: sp.Basic) -> str:
    r"""``expr`` (an expression or a matrix) as display LaTeX with every ``NAME_dot`` and
    ``NAME_ddot`` typeset as a dotted name (θ̇, θ̈), not as a subscript.

    >>> print(dotted_latex(sp.Symbol("theta_ddot") + sp.Symbol("phi_dot")))
    $\displaystyle \dot{\phi} + \ddot{\theta}$
    """
    stems = set()
    for symbol in expr.free_symbols:
        name = getattr(symbol, "name", "")
        for suffix in (DDOT_SUFFIX, DOT_SUFFIX):
            if name.endswith(suffix) and len(name) > len(suffix):
                stems.add(sp.Symbol(name[: -len(suffix)]))
                break
    return f"$\\displaystyle {expression_latex(expr, sorted(stems, key=str))}$"


def register(shell: Any = None) -> bool:
    """Register 'text/latex' formatters for SymPy expressions and matrices (velocities and
    accelerations as dotted names), EquationsOfMotion, CoordinateSteps (and the
    ``eom.steps`` of every coordinate), System, AnalysisReport and the analysis results, an
    'image/png' one for Trajectory (time series, phase portrait, energy drift) and a
    'text/html' table for ``Trajectory.drift()``, in ``shell`` (the running IPython when None).
    Importing lagrangian registers nothing: call this, or ``%load_ext lagrangian``.
    An animation (``lg.render.animate(system, trajectory)``) shows as its player by itself.

    Returns True when registered, False (doing nothing) when IPython is missing or not running.

    >>> register()  # outside IPython
    False
    """
    if shell is None:
        try:
            from IPython import get_ipython
        except ImportError:
            return False
        shell = get_ipython()
        if shell is None:
            return False
    formatter = shell.display_formatter.formatters["text/latex"]
    formatter.for_type(sp.Basic, dotted_latex)  # theta_ddot as a double-dotted theta
    formatter.for_type(sp.MatrixBase, dotted_latex)
    formatter.for_type(EquationsOfMotion, _eom_latex)
    formatter.for_type(CoordinateSteps, _coordinate_steps_latex)
    formatter.for_type(Steps, _every_steps_latex)
    formatter.for_type(System, _system_latex)
    formatter.for_type(AnalysisReport, _analysis_latex)
    for kind in RESULT_TYPES:
        formatter.for_type(kind, _result_latex)
    shell.display_formatter.formatters["image/png"].for_type(Trajectory, overview_png)
    shell.display_formatter.formatters["text/html"].for_type(Drift, drift_html)
    return True
