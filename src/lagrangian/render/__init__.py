"""The render layer: equations, derivation steps and systems as LaTeX and plain text, and
rich display in Jupyter (docs/architecture.md).

>>> import lagrangian as lg
>>> from lagrangian import render
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> print(render.steps_text(eom).splitlines()[-1])
⇒ g*l*m*sin(theta) + l**2*m*theta_ddot = 0
"""

from lagrangian.render.action_plot import plot_action_variation
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.animation import Animation, animate, animation_frame, animation_html
from lagrangian.render.jupyter import Latex, register
from lagrangian.render.jupyter import display_steps as steps
from lagrangian.render.latex import equations_latex, steps_latex, system_latex
from lagrangian.render.mathml import equations_mathml, steps_mathml
from lagrangian.render.plots import (
    plot_energy_drift,
    plot_phase_portrait,
    plot_time_series,
    save_plots,
)
from lagrangian.render.scene import Scene, scene_of
from lagrangian.render.text import equations_text, matrix_form_text, steps_text

__all__ = [
    "Animation",
    "Latex",
    "Scene",
    "analysis_latex",
    "animate",
    "animation_frame",
    "animation_html",
    "equations_latex",
    "equations_mathml",
    "equations_text",
    "matrix_form_text",
    "plot_action_variation",
    "plot_energy_drift",
    "plot_phase_portrait",
    "plot_time_series",
    "register",
    "save_plots",
    "scene_of",
    "steps",
    "steps_latex",
    "steps_mathml",
    "steps_text",
    "system_latex",
]
