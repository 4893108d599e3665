"""Plain text for a terminal: equations of motion, derivation steps and the matrix form.

Labels use unicode (``∂L/∂θ̇``, a combining dot U+0307 or diaeresis U+0308 after the name);
expressions are ``sympy.sstr`` with the input's names (``theta_dot``), so they parse back.

>>> import lagrangian as lg
>>> print(equations_text(lg.derive(lg.examples.simple_pendulum())))
g*l*m*sin(theta) + l**2*m*theta_ddot = 0
"""

from __future__ import annotations

import re
from typing import Any

import sympy as sp
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


class SumPrinter(StrPrinter):
    """``sympy.sstr`` that writes each sum and product once and reuses the text wherever the
    same one recurs: the m_k + ... + m_n of an n-link chain's link k is in n of its terms, so
    its equations print in time proportional to their length, not to that times n.

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
        self._written: dict[tuple[sp.Basic, str | None], str] = {}

    def _print_Add(self, expr: sp.Add, order: str | None = None) -> str:
        order = order or self.order
        if order is None and len(expr.args) > SORTED_TERMS:
            order = "none"
        key = (expr, order)
        text = self._written.get(key)
        if text is None:
            text = self._written[key] = super()._print_Add(expr, order)
        return text

    def _print_Mul(self, expr: sp.Mul) -> str:
        key = (expr, self.order)
        text = self._written.get(key)
        if text is None:
            if self.order is None and any(
                a.is_Add and len(a.args) > SORTED_TERMS for a in expr.args
            ):
                self._settings["order"] = "none"  # for this product only
                try:
                    text = super()._print_Mul(expr)
                finally:
                    self._settings["order"] = None
            else:
                text = super()._print_Mul(expr)
            self._written[key] = text
        return text


#: Terms beyond which :class:`SumPrinter` leaves a sum in SymPy's order (not sorted).
SORTED_TERMS = 50


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
        ("gravity G = ∂V/∂q", eom.gravity),
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
