"""The render layer: LaTeX and plain text of equations, steps and systems; Jupyter display."""

from __future__ import annotations

import sys
import types
from typing import Any

import pytest
import sympy as sp
from matplotlib.mathtext import MathTextParser

import lagrangian as lg
from lagrangian import render
from lagrangian.render.latex import coordinate_steps_latex, expression_latex, symbol_names
from lagrangian.render.text import DDOT, DOT, label

theta1, theta2 = sp.symbols("theta1 theta2")
theta1_dot, theta2_dot = sp.symbols("theta1_dot theta2_dot")


@pytest.fixture(scope="module")
def pendulum() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.simple_pendulum())


@pytest.fixture(scope="module")
def damped_double() -> lg.EquationsOfMotion:
    """A double pendulum with damping at both joints and a horizontal push on the lower bob."""
    m1, m2, l1, l2, g, c, push = sp.symbols("m1 m2 l1 l2 g c P")
    bob1 = (l1 * sp.sin(theta1), -l1 * sp.cos(theta1))
    bob2 = (bob1[0] + l2 * sp.sin(theta2), bob1[1] - l2 * sp.cos(theta2))
    system = lg.System(
        name="damped double pendulum",
        coordinates=[theta1, theta2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81, c: 0.1, push: None},
        particles=[lg.Particle("bob1", m1, bob1), lg.Particle("bob2", m2, bob2)],
        gravity=(0, -g),
        dissipation=c * (theta1_dot**2 + (theta2_dot - theta1_dot) ** 2) / 2,
        forces=[lg.Force("bob2", (push, 0))],
    )
    return lg.derive(system)


@pytest.fixture(scope="module")
def driven_oscillator() -> lg.EquationsOfMotion:
    """m x'' + b x' + k x = F0 cos(w t): dissipation on x, a force Q only on x."""
    x, y, x_dot, y_dot = sp.symbols("x y x_dot y_dot")
    m, k, b, f0, w = sp.symbols("m k b F0 w")
    system = lg.System(
        coordinates=[x, y],
        parameters=[m, k, b, f0, w],
        kinetic=m * (x_dot**2 + y_dot**2) / 2,
        potential=k * (x**2 + y**2) / 2,
        dissipation=b * x_dot**2 / 2,
        generalized_forces={x: f0 * sp.cos(w * lg.t)},
    )
    return lg.derive(system)


def body_lines(latex: str) -> list[str]:
    """The lines of an align* block without the environment, ``&`` and the ``\\\\`` ends."""
    lines = latex.splitlines()
    assert lines[0] == r"\begin{align*}"
    assert lines[-1] == r"\end{align*}"
    return [line.removesuffix(" \\\\").replace("&", "") for line in lines[1:-1]]


def assert_balanced_braces(latex: str) -> None:
    depth = 0
    for char in latex.replace(r"\{", "").replace(r"\}", ""):
        depth += {"{": 1, "}": -1}.get(char, 0)
        assert depth >= 0, latex
    assert depth == 0, latex
    assert latex.count(r"\left") == latex.count(r"\right"), latex
    assert latex.count(r"\begin") == latex.count(r"\end"), latex


def assert_mathtext_parses(line: str) -> None:
    MathTextParser("path").parse("$" + line + "$")


# -- LaTeX ---------------------------------------------------------------------------------


def test_symbol_names_put_accents_on_the_base_and_keep_subscripts() -> None:
    names = symbol_names([sp.Symbol("theta1"), sp.Symbol("x")])
    assert names[sp.Symbol("theta1_dot")] == r"\dot{\theta}_{1}"
    assert names[sp.Symbol("theta1_ddot")] == r"\ddot{\theta}_{1}"
    assert names[sp.Symbol("x_dot")] == r"\dot{x}"
    assert names[sp.Symbol("theta1")] == r"\theta_{1}"
    assert symbol_names([sp.Symbol("x_a")])[sp.Symbol("x_a_ddot")] == r"\ddot{x}_{a}"


def test_expression_latex_uses_dotted_names() -> None:
    expr = sp.Symbol("theta1_dot") ** 2 + sp.Symbol("theta1_ddot")
    text = expression_latex(expr, [theta1])
    assert r"\dot{\theta}_{1}^{2}" in text
    assert r"\ddot{\theta}_{1}" in text
    assert_mathtext_parses(text)


def test_pendulum_equation_latex(pendulum: lg.EquationsOfMotion) -> None:
    latex = render.equations_latex(pendulum)
    assert body_lines(latex) == [r"g l m \sin{\left(\theta \right)} + l^{2} m \ddot{\theta} = 0"]
    assert_mathtext_parses(body_lines(latex)[0])


def test_matrix_form_latex(damped_double: lg.EquationsOfMotion) -> None:
    latex = render.equations_latex(damped_double, form="matrix")
    assert_balanced_braces(latex)
    assert r"\left[\begin{matrix}\ddot{\theta}_{1}\\\ddot{\theta}_{2}\end{matrix}\right]" in latex
    assert latex.count("&=") == 1


def test_unknown_equation_form_is_refused(pendulum: lg.EquationsOfMotion) -> None:
    with pytest.raises(ValueError, match="form='residuals' or form='matrix'"):
        render.equations_latex(pendulum, form="hamilton")


def test_pendulum_steps_latex_as_in_the_notes(pendulum: lg.EquationsOfMotion) -> None:
    lines = body_lines(render.steps_latex(pendulum))
    assert lines[2].startswith("L = T - V = ")
    dl_dv = r"\frac{\partial L}{\partial \dot{\theta}}"
    assert lines[3:] == [
        rf"{dl_dv} = l^{{2}} m \dot{{\theta}}",
        rf"\frac{{d}}{{dt}}\left({dl_dv}\right) = l^{{2}} m \ddot{{\theta}}",
        r"\frac{\partial L}{\partial \theta} = - g l m \sin{\left(\theta \right)}",
        r"\Rightarrow\; g l m \sin{\left(\theta \right)} + l^{2} m \ddot{\theta} = 0",
    ]


@pytest.mark.parametrize("name", ["pendulum", "damped_double", "driven_oscillator"])
def test_every_steps_line_is_wellformed_math(name: str, request: pytest.FixtureRequest) -> None:
    eom = request.getfixturevalue(name)
    latex = render.steps_latex(eom)
    assert_balanced_braces(latex)
    for line in body_lines(latex):
        assert_balanced_braces(line)
        assert_mathtext_parses(line)
    for line in body_lines(render.equations_latex(eom)):
        assert_mathtext_parses(line)


def test_double_pendulum_steps_latex_labels(damped_double: lg.EquationsOfMotion) -> None:
    latex = render.steps_latex(damped_double)
    for sub in ("1", "2"):
        v = rf"\dot{{\theta}}_{{{sub}}}"
        assert rf"\frac{{\partial L}}{{\partial {v}}} &=" in latex
        assert rf"\frac{{d}}{{dt}}\left(\frac{{\partial L}}{{\partial {v}}}\right) &=" in latex
        assert rf"\frac{{\partial L}}{{\partial \theta_{{{sub}}}}} &=" in latex
        assert rf"\frac{{\partial F}}{{\partial {v}}} &=" in latex
        assert rf"Q_{{\theta_{{{sub}}}}} &=" in latex
    assert r"\ddot{\theta}_{1}" in latex
    assert "F &= " in latex
    assert latex.count(r"\Rightarrow") == 2


def test_dissipation_and_force_lines_only_where_nonzero(
    pendulum: lg.EquationsOfMotion, driven_oscillator: lg.EquationsOfMotion
) -> None:
    assert r"\partial F" not in render.steps_latex(pendulum)
    assert "Q_" not in render.steps_latex(pendulum)
    assert "F &= " not in render.steps_latex(pendulum)
    latex = render.steps_latex(driven_oscillator)
    assert r"\frac{\partial F}{\partial \dot{x}} &= b \dot{x}" in latex
    assert r"\partial \dot{y}} &= b" not in latex
    assert r"Q_{x} &= F_{0} \cos{\left(t w \right)}" in latex
    assert "Q_{y}" not in latex


def test_coordinate_steps_latex_alone(damped_double: lg.EquationsOfMotion) -> None:
    latex = coordinate_steps_latex(damped_double.steps[1], environment="aligned")
    assert latex.startswith(r"\begin{aligned}")
    assert r"\ddot{\theta}_{1}" in latex  # the other coordinate's accelerations are dotted too
    assert "theta_{1 dot}" not in latex
    assert_balanced_braces(latex)


def test_system_latex() -> None:
    system = lg.examples.n_link_pendulum(2)
    latex = render.system_latex(system)
    assert_balanced_braces(latex)
    assert r"\text{pendulum\_2\_links}" in latex
    assert r"q &= \left(\theta_{1}, \theta_{2}\right)" in latex
    assert "g = 9.81" in latex
    assert "particles: bob1, bob2; gravity" in latex
    assert "T &=" not in latex  # the energy comes from the particles, not an explicit field


def test_system_latex_shows_explicit_fields(driven_oscillator: lg.EquationsOfMotion) -> None:
    x, x_dot, m, b = sp.symbols("x x_dot m b")
    system = lg.System(
        coordinates=[x], parameters=[m, b], kinetic=m * x_dot**2 / 2, dissipation=b * x_dot**2
    )
    latex = render.system_latex(system)
    assert r"T &= \frac{m \dot{x}^{2}}{2}" in latex
    assert r"F &= b \dot{x}^{2}" in latex
    assert "V &=" not in latex
    assert "&m, b" in latex


# -- plain text ----------------------------------------------------------------------------


def test_labels_are_greek_with_combining_accents() -> None:
    assert label(sp.Symbol("theta"), DOT) == "θ\u0307"
    assert label(sp.Symbol("theta1"), DDOT) == "θ\u03081"
    assert label(sp.Symbol("phi_2")) == "φ_2"
    assert label(sp.Symbol("x")) == "x"
    assert label(sp.Symbol("Omega"), DOT) == "Ω\u0307"


def test_pendulum_steps_text(pendulum: lg.EquationsOfMotion) -> None:
    lines = render.steps_text(pendulum).splitlines()
    assert "L = T − V = g*l*m*cos(theta) + l**2*m*theta_dot**2/2" in lines
    assert "∂L/∂θ̇ = l**2*m*theta_dot" in lines
    assert "d/dt(∂L/∂θ̇) = l**2*m*theta_ddot" in lines
    assert "∂L/∂θ = -g*l*m*sin(theta)" in lines
    assert lines[-1] == "⇒ g*l*m*sin(theta) + l**2*m*theta_ddot = 0"
    assert not any(line.startswith(("F =", "∂F", "Q_")) for line in lines)


def test_steps_text_expressions_parse_back(damped_double: lg.EquationsOfMotion) -> None:
    text = render.steps_text(damped_double)
    steps = damped_double.steps[0]
    lines = dict(line.split(" = ", 1) for line in text.splitlines() if " = " in line)
    assert sp.sympify(lines["∂L/∂θ̇1"]) == steps.dL_dvelocity
    assert sp.sympify(lines["∂F/∂θ̇1"]) == steps.dF_dvelocity
    assert sp.sympify(lines["Q_θ1"]) == steps.generalized_force
    c, w1, w2 = sp.symbols("c theta1_dot theta2_dot")
    assert sp.expand(sp.sympify(lines["F"]) - c * (w1**2 + (w2 - w1) ** 2) / 2) == 0


def test_text_force_and_dissipation_lines(driven_oscillator: lg.EquationsOfMotion) -> None:
    lines = render.steps_text(driven_oscillator).splitlines()
    assert f"∂F/∂x{DOT} = b*x_dot" in lines
    assert "Q_x = F0*cos(t*w)" in lines
    assert not any(line.startswith((f"∂F/∂y{DOT}", "Q_y")) for line in lines)
    # residual form d/dt dL/dq_dot - dL/dq + dF/dq_dot - Q = 0
    assert "⇒ -F0*cos(t*w) + b*x_dot + k*x + m*x_ddot = 0" in lines


def test_equations_text(damped_double: lg.EquationsOfMotion) -> None:
    lines = render.equations_text(damped_double).splitlines()
    assert len(lines) == 2
    for line, equation in zip(lines, damped_double.equations, strict=True):
        residual, zero = line.rsplit(" = ", 1)
        assert zero == "0"
        assert sp.sympify(residual) == equation


def test_matrix_form_text(driven_oscillator: lg.EquationsOfMotion) -> None:
    blocks = render.matrix_form_text(driven_oscillator).split("\n\n")
    assert blocks[0] == "M q̈ + C q̇ + G = Q − ∂F/∂q̇"
    assert blocks[1] == "mass_matrix M =\n[m, 0]\n[0, m]"
    titles = [block.splitlines()[0] for block in blocks[1:]]
    assert titles == [
        "mass_matrix M =",
        "coriolis C q̇ =",
        "potential_forces G = ∂V/∂q =",
        "generalized_forces Q =",
        "dissipation_forces −∂F/∂q̇ =",
        "forcing (M q̈ = forcing) =",
    ]
    assert blocks[-1].splitlines()[1:] == ["[F0*cos(t*w) - b*x_dot - k*x]", "[-k*y]"]


# -- Jupyter -------------------------------------------------------------------------------


def test_latex_object_displays_in_jupyter(pendulum: lg.EquationsOfMotion) -> None:
    shown = render.steps(pendulum)
    assert isinstance(shown, render.Latex)
    assert shown._repr_latex_() == f"$${shown}$$"
    assert str(shown).startswith(r"\begin{aligned}")
    assert str(shown).endswith(r"\end{aligned}")
    assert r"\dot{\theta}" in str(shown)


def test_register_is_a_noop_without_ipython(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "IPython", None)  # import IPython raises ImportError
    assert render.register() is False


def test_register_is_a_noop_outside_a_running_shell(monkeypatch: pytest.MonkeyPatch) -> None:
    fake = types.ModuleType("IPython")
    fake.get_ipython = lambda: None  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "IPython", fake)
    assert render.register() is False


class _Formatter:
    def __init__(self) -> None:
        self.printers: dict[type, Any] = {}

    def for_type(self, cls: type, printer: Any) -> None:
        self.printers[cls] = printer


def test_register_adds_latex_formatters(
    monkeypatch: pytest.MonkeyPatch, pendulum: lg.EquationsOfMotion
) -> None:
    run = lg.simulate(lg.examples.mass_spring_damper(), t_span=1.0, samples=5)
    formatter, pictures, pages = _Formatter(), _Formatter(), _Formatter()
    shell = types.SimpleNamespace(
        display_formatter=types.SimpleNamespace(
            formatters={"text/latex": formatter, "image/png": pictures, "text/html": pages}
        )
    )
    fake = types.ModuleType("IPython")
    fake.get_ipython = lambda: shell  # type: ignore[attr-defined]
    fake.version_info = (8, 30)  # type: ignore[attr-defined]  (matplotlib's canvas asks)
    monkeypatch.setitem(sys.modules, "IPython", fake)
    assert render.register() is True
    printers = formatter.printers
    from lagrangian.render.analysis_latex import RESULT_TYPES

    assert set(printers) == {
        sp.Basic,
        sp.MatrixBase,
        lg.EquationsOfMotion,
        lg.CoordinateSteps,
        type(pendulum.steps),
        lg.System,
        lg.analysis.AnalysisReport,
        *RESULT_TYPES,
    }
    report_text = printers[lg.analysis.AnalysisReport](lg.analyze(lg.examples.simple_pendulum()))
    assert r"p_{\theta}" in report_text and "stable" in report_text
    equations = printers[lg.EquationsOfMotion](pendulum)
    assert equations.startswith(r"$$\begin{aligned}") and equations.endswith(r"\end{aligned}$$")
    assert r"\ddot{\theta}" in equations
    assert r"\partial L" in printers[lg.CoordinateSteps](pendulum.steps[0])
    # a bare equation typesets theta_ddot as a double-dotted theta, not theta with a subscript
    bare = printers[sp.Basic](pendulum.equations[0])
    assert r"\ddot{\theta}" in bare and "ddot}" not in bare.replace(r"\ddot{", "")
    assert r"\ddot{\theta}" in printers[sp.MatrixBase](
        pendulum.mass_matrix * sp.Matrix(pendulum.accelerations)
    )
    assert r"\partial L" in printers[type(pendulum.steps)](pendulum.steps)
    (drift_table,) = pages.printers.values()
    table = drift_table(run.drift())
    assert (
        table.startswith("<table>") and "energy_not_conserved" in table and "dissipation" in table
    )
    assert "simple" in printers[lg.System](lg.examples.simple_pendulum())
    trajectory = lg.simulate(lg.examples.simple_pendulum(), t_span=1.0, samples=20)
    assert pictures.printers[lg.Trajectory](trajectory).startswith(b"\x89PNG")
