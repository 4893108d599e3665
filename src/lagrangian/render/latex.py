"""LaTeX for equations of motion, their derivation steps and systems.

Velocities and accelerations are typeset with accents: ``theta1_dot`` -> ``\\dot{\\theta}_{1}``,
``theta1_ddot`` -> ``\\ddot{\\theta}_{1}``.  Multi-line results are one ``align*`` block (pass
``environment="aligned"`` to nest it inside ``$$ ... $$``, as Jupyter needs).

>>> import lagrangian as lg
>>> print(equations_latex(lg.derive(lg.examples.simple_pendulum())))
\\begin{align*}
g l m \\sin{\\left(\\theta \\right)} + l^{2} m \\ddot{\\theta} &= 0
\\end{align*}
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import sympy as sp

from lagrangian.derivation import CoordinateSteps, EquationsOfMotion
from lagrangian.model import System
from lagrangian.model.symbols import DDOT_SUFFIX, DOT_SUFFIX, acceleration, velocity
from lagrangian.render.rows import Row, energy_rows, step_rows

_TEXT_ESCAPES = {c: "\\" + c for c in "_&%#${}"}


def symbol_names(coordinates: Iterable[sp.Symbol]) -> dict[sp.Symbol, str]:
    """LaTeX names of q, q_dot, q_ddot: ``theta1_dot`` -> ``\\dot{\\theta}_{1}``.

    >>> symbol_names([sp.Symbol("theta1")])[sp.Symbol("theta1_dot")]
    '\\\\dot{\\\\theta}_{1}'
    """
    names: dict[sp.Symbol, str] = {}
    for q in coordinates:
        base, scripts = _split_scripts(sp.latex(q))
        names[q] = base + scripts
        names[velocity(q)] = rf"\dot{{{base}}}{scripts}"
        names[acceleration(q)] = rf"\ddot{{{base}}}{scripts}"
    return names


def _split_scripts(name: str) -> tuple[str, str]:
    """``\\theta_{1}`` -> (``\\theta``, ``_{1}``): the first sub/superscript outside braces."""
    depth = 0
    for i, char in enumerate(name):
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth == 0 and char in "_^" and i > 0:
            return name[:i], name[i:]
    return name, ""


def expression_latex(expr: sp.Basic, coordinates: Iterable[sp.Symbol]) -> str:
    """``sympy.latex`` with dotted velocities and accelerations of ``coordinates``.

    >>> theta = sp.Symbol("theta")
    >>> expression_latex(sp.Symbol("theta_dot") ** 2, [theta])
    '\\\\dot{\\\\theta}^{2}'
    """
    return sp.latex(expr, symbol_names=symbol_names(coordinates))


def block(lines: Sequence[str], environment: str = "align*") -> str:
    """Lines joined by ``\\\\`` inside ``\\begin{environment} ... \\end{environment}``."""
    body = " \\\\\n".join(lines)
    return f"\\begin{{{environment}}}\n{body}\n\\end{{{environment}}}"


def equations_latex(
    eom: EquationsOfMotion, form: str = "residuals", environment: str = "align*"
) -> str:
    """The equations of motion: one line ``residual = 0`` per coordinate, or the matrix form.

    form="residuals": d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q = 0 for each coordinate;
    form="matrix": M q_ddot = forcing, with the matrices written out.

    >>> import lagrangian as lg
    >>> eom = lg.derive(lg.examples.simple_pendulum())
    >>> matrix_form = equations_latex(eom, form="matrix")
    >>> r"\\ddot{\\theta}\\end{matrix}\\right] &= " in matrix_form
    True
    """
    names = symbol_names(eom.coordinates)
    if form == "residuals":
        lines = [f"{sp.latex(e, symbol_names=names)} &= 0" for e in eom.equations]
    elif form == "matrix":
        mass = sp.latex(eom.mass_matrix, symbol_names=names)
        q_ddot = sp.latex(sp.Matrix(eom.accelerations), symbol_names=names)
        forcing = sp.latex(eom.forcing, symbol_names=names)
        lines = [f"{mass} {q_ddot} &= {forcing}"]
    else:
        raise ValueError(f"Unknown form {form!r}: use form='residuals' or form='matrix'.")
    return block(lines, environment)


def energy_lines(eom: EquationsOfMotion) -> list[str]:
    """``T = ...``, ``V = ...``, (``U = ...``), ``L = T - V (- U) = ...``, (``F = ...``)."""
    names = symbol_names(eom.coordinates)

    def tex(expr: sp.Basic) -> str:
        return sp.latex(expr, symbol_names=names)

    def line(label: str) -> str:  # "L = T - V" -> "L &= T - V = ..."
        head, _, definition = label.partition(" = ")
        return f"{head} &= {definition} = " if definition else f"{head} &= "

    return [line(label) + tex(expr) for label, expr in energy_rows(eom)]


def coordinate_steps_lines(steps: CoordinateSteps, names: dict[sp.Symbol, str]) -> list[str]:
    """The derivation lines of one coordinate, in the order one works them by hand.

    dL/dq_dot, d/dt(dL/dq_dot), dL/dq always; dF/dq_dot and Q_j when non-zero; then the
    equation d/dt(dL/dq_dot) - dL/dq + dF/dq_dot - Q_j = 0.
    """

    def tex(expr: sp.Basic) -> str:
        return sp.latex(expr, symbol_names=names)

    q, v = tex(steps.coordinate), tex(steps.velocity)
    dl_dv = rf"\frac{{\partial L}}{{\partial {v}}}"
    labels = {
        Row.MOMENTUM: f"{dl_dv} &= ",
        Row.RATE: rf"\frac{{d}}{{dt}}\left({dl_dv}\right) &= ",
        Row.SLOPE: rf"\frac{{\partial L}}{{\partial {q}}} &= ",
        Row.FRICTION: rf"\frac{{\partial F}}{{\partial {v}}} &= ",
        Row.FORCE: f"Q_{{{q}}} &= ",
    }
    return [
        rf"\Rightarrow\; {tex(expr)} &= 0" if row is Row.EQUATION else labels[row] + tex(expr)
        for row, expr in step_rows(steps)
    ]


def steps_latex(eom: EquationsOfMotion, environment: str = "align*") -> str:
    """The whole derivation: T, V, L = T - V (and F), then every coordinate's steps.

    >>> import lagrangian as lg
    >>> lines = steps_latex(lg.derive(lg.examples.simple_pendulum())).splitlines()
    >>> print(lines[4])
    \\frac{\\partial L}{\\partial \\dot{\\theta}} &= l^{2} m \\dot{\\theta} \\\\
    """
    names = symbol_names(eom.coordinates)
    lines = energy_lines(eom)
    for steps in eom.steps:
        lines.extend(coordinate_steps_lines(steps, names))
    return block(lines, environment)


def coordinate_steps_latex(steps: CoordinateSteps, environment: str = "align*") -> str:
    """The derivation of one coordinate's equation (coordinates read off the expressions)."""
    exprs = (steps.dL_dvelocity, steps.ddt_dL_dvelocity, steps.dL_dcoordinate, steps.equation)
    found = {steps.coordinate}
    for expr in exprs:
        for s in expr.free_symbols:
            for suffix in (DDOT_SUFFIX, DOT_SUFFIX):
                if isinstance(s, sp.Symbol) and s.name.endswith(suffix):
                    found.add(sp.Symbol(s.name.removesuffix(suffix)))
                    break
    names = symbol_names(sorted(found, key=str))
    return block(coordinate_steps_lines(steps, names), environment)


def system_latex(system: System, environment: str = "align*") -> str:
    """A short description: name, coordinates, parameters and the explicit energies.

    Energies contributed by elements (particles, springs, ...) show after ``derive``; here
    only the fields given explicitly (T, V, L, U, F, Q) appear, with the element names.

    >>> import lagrangian as lg
    >>> print(system_latex(lg.examples.simple_pendulum()).splitlines()[2])
    q &= \\left(\\theta\\right) \\\\
    """
    names = symbol_names(system.coordinates)

    def tex(expr: sp.Basic) -> str:
        return sp.latex(expr, symbol_names=names)

    coords = ", ".join(tex(q) for q in system.coordinates)
    lines = [rf"&\text{{{_escape_text(system.name or 'system')}}}", rf"q &= \left({coords}\right)"]
    if system.parameters:
        values = ", ".join(
            tex(p) if value is None else f"{tex(p)} = {value:g}"
            for p, value in system.parameters.items()
        )
        lines.append(rf"&{values}")
    fields = (
        ("T", system.kinetic),
        ("V", system.potential),
        ("L", system.lagrangian),
        ("U", system.velocity_potential),
        ("F", system.dissipation),
    )
    lines.extend(f"{label} &= {tex(expr)}" for label, expr in fields if expr != 0)
    lines.extend(
        f"Q_{{{tex(q)}}} &= {tex(force)}" for q, force in system.generalized_forces.items()
    )
    elements = _element_names(system)
    if elements:
        lines.append(rf"&\text{{{_escape_text(elements)}}}")
    return block(lines, environment)


def _element_names(system: System) -> str:
    """``particles: bob; gravity`` — which elements contribute energy or forces."""
    parts = []
    for label, items in (
        ("particles", system.particles),
        ("rigid bodies", system.rigid_bodies),
        ("springs", system.springs),
        ("dampers", system.dampers),
        ("forces", system.forces),
        ("torques", system.torques),
        ("circuit elements", system.circuit),
    ):
        named = [getattr(item, "name", "") for item in items]
        if named and all(named):
            parts.append(f"{label}: {', '.join(named)}")
        elif named:
            parts.append(f"{len(named)} {label}")
    if system.gravity:
        parts.append("gravity")
    return "; ".join(parts)


def _escape_text(text: str) -> str:
    """Escape the characters LaTeX treats specially inside ``\\text{...}``."""
    return "".join(_TEXT_ESCAPES.get(c, c) for c in text)
