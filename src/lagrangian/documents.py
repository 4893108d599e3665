"""What every front end prints: the derivation document and its LaTeX, the analysis, and the
settings a front end applies to a System before (``--set``, ``--initial``, ``--about`` on the
command line; ``options.set``, ``options.initial``, ``options.about`` in the web API).

The command line (:mod:`lagrangian.cli`) and the playground (:mod:`lagrangian.web`) both call
these, so each answer of the web API is the JSON the command line prints.  Problems name the
option as the caller's interface does (a :class:`~lagrangian.errors.Wording`), and their fixes
are :class:`~lagrangian.errors.Fix` values the caller words.

>>> import lagrangian as lg
>>> from lagrangian.errors import Wording
>>> system = apply_settings(lg.examples.simple_pendulum(), ["m=2"], Wording())
>>> {p.name: value for p, value in system.parameters.items()}["m"]
2.0
>>> derivation_document(system, steps=False)["equations"]
['m*theta_ddot*l**2 + g*l*m*sin(theta)']
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from lagrangian import render
from lagrangian.analysis import AnalysisReport, analyze
from lagrangian.constraints import constrained_equations
from lagrangian.derivation import derive
from lagrangian.errors import Fix, ModelError, Problem, Setting, Wording, raise_if_problems
from lagrangian.model import System
from lagrangian.render.constrained import constrained_latex
from lagrangian.render.hybrid import has_jumps, hybrid_document, hybrid_latex_lines
from lagrangian.render.json import constrained_document, eom_document
from lagrangian.render.latex import block
from lagrangian.simulation import Trajectory
from lagrangian.simulation.impact_table import impact_records, impacts_summary
from lagrangian.symbolic.expressions import closest_name


def derivation_document(system: System, steps: bool) -> dict[str, Any]:
    """What ``derive --format json`` prints: the equations (with ``steps``), the ``units``
    of names when the model gives them, and the multiplier form of a constrained system."""
    eom = derive(system)
    document = eom_document(eom, steps=steps)
    if system.units:  # names described with their units, where the model gives them
        document["units"] = dict(system.units)
    if system.constraints:
        document.update(constrained_document(constrained_equations(eom, system.constraints)))
    document.update(hybrid_document(system))
    return document


def derivation_latex(system: System, steps: bool, matrix: bool) -> str:
    """What ``derive --format latex`` prints (with ``--steps``, ``--matrix``)."""
    eom = derive(system)
    parts = [render.steps_latex(eom) if steps else render.equations_latex(eom)]
    if matrix:
        parts.append(render.equations_latex(eom, form="matrix"))
    if system.constraints:
        equations = constrained_equations(eom, system.constraints)
        parts.append(constrained_latex(equations, matrix))
    if has_jumps(system):
        parts.append(block(hybrid_latex_lines(system)))
    return "\n".join(parts)


def run_document(trajectory: Trajectory, wording: Wording) -> dict[str, Any]:
    """A run as JSON (``simulate --out FILE.json``, the web API's simulate answer):
    ``columns`` (the CSV's, name -> values, None for NaN and infinities, which JSON has not)
    and ``summary`` (:func:`simulation_summary`)."""
    return {
        "columns": {name: finite_list(values) for name, values in trajectory.columns().items()},
        "summary": simulation_summary(trajectory, wording),
    }


def simulation_summary(trajectory: Trajectory, wording: Wording) -> dict[str, Any]:
    """What ``lagrangian simulate`` says after the run: its status and message (in the words
    of ``wording``), method, samples, parameters, drift and impacts."""
    return {
        "status": trajectory.status,
        "message": trajectory.worded_message(wording),
        "method": trajectory.method,
        "samples": len(trajectory.t),
        "parameters": dict(trajectory.parameters),
        "drift": {key: _finite(value) for key, value in trajectory.drift().items()},
        "drift_summary": trajectory.drift_summary(),
        "impacts": impact_records(trajectory.impacts),
        "impacts_summary": impacts_summary(trajectory.impacts),
    }


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def finite_list(values: np.ndarray) -> list[Any]:
    """An array as nested lists, with None for NaN and infinities (JSON has neither).

    >>> finite_list(np.array([1.0, np.nan]))
    [1.0, None]
    """
    array = np.asarray(values, dtype=float)
    if np.isfinite(array).all():
        return list(array.tolist())
    shown = array.astype(object)
    shown[~np.isfinite(array)] = None
    return list(shown.tolist())


def analysis_of(
    system: System,
    about: str | None,
    inputs: Sequence[str],
    project: bool,
    search_degree: int,
    wording: Wording,
) -> AnalysisReport:
    """The analysis ``analyze`` prints, ``about`` written as a state (``theta=0.5,phi_dot=2``);
    on a constrained model a state off the constraints is refused, with the fix of setting
    ``project`` in the words of ``wording``, unless ``project``."""
    state = parse_state(about, wording)
    return analyze(
        system,
        about=state if about else None,
        inputs=list(inputs),
        project=project,
        search_degree=search_degree,
    )


def parse_state(text: str | None, wording: Wording) -> dict[str, float]:
    """``NAME=VALUE[,NAME=VALUE...]`` as a mapping (the state of ``about``)."""
    if not text:
        return {}
    state, problems = {}, []
    example = Fix("e.g. {}", (Setting("about", "theta=0.5,phi_dot=2"),))
    for item in text.split(","):
        name, sep, value = item.partition("=")
        try:
            number = float(value)
        except ValueError:
            number = None
        if not sep or number is None:
            field = f"{wording.option('about')} {item}"
            problems.append(Problem(field, "expected NAME=NUMBER", example))
        else:
            state[name.strip()] = number
    raise_if_problems(problems, f"Bad {wording.option('about')} option", ModelError)
    return state


def apply_settings(system: System, settings: Sequence[str], wording: Wording) -> System:
    """``NAME=VALUE`` overrides of parameters and initial values (``--set``)."""
    if not settings:
        return system
    parameters = {p.name: p for p in system.parameters}
    initial_names = {q.name: q for q in (*system.coordinates, *system.velocities)}
    new_parameters, new_initial = dict(system.parameters), dict(system.initial)
    problems = []
    for item in settings:
        name, value = _assignment(item)
        field = f"{wording.option('set')} {item}"
        if value is None or not math.isfinite(value):
            shown = "expected NAME=NUMBER" if value is None else f"{value} is not a finite number"
            example = Setting("set", 0.5, entry=name or "m")
            problems.append(Problem(field, shown, Fix("e.g. {}", (example,))))
        elif name in parameters:
            new_parameters[parameters[name]] = value
        elif name in initial_names:
            new_initial[initial_names[name]] = value
        else:
            message = f"{name!r} is not a parameter, coordinate or velocity of the system"
            fix = "choose one of: " + ", ".join(sorted([*parameters, *initial_names]))
            problems.append(Problem(field, message, fix))
    raise_if_problems(problems, f"Bad {wording.option('set')} option", ModelError)
    return system.replace(parameters=new_parameters, initial=new_initial)


def apply_initial(system: System, items: Sequence[str], wording: Wording) -> System:
    """``NAME=VALUE`` initial values of coordinates and velocities (``theta=0.5``,
    ``theta_dot=0``; ``--initial``), every bad one reported at once with the name it may
    have meant."""
    if not items:
        return system
    known = {q.name: q for q in (*system.coordinates, *system.velocities)}
    parameters = {p.name for p in system.parameters}
    initial, problems = dict(system.initial), []
    for item in items:
        name, value = _assignment(item)
        field = f"{wording.option('initial')} {item}"
        if name not in known:
            problems.append(Problem(field, *_not_initial(name, known, parameters)))
        elif value is None or not math.isfinite(value):
            example = Fix("e.g. {}", (Setting("initial", 0.5, entry=name),))
            problems.append(Problem(field, "expected NAME=NUMBER", example))
        else:
            initial[known[name]] = value
    raise_if_problems(problems, f"Bad {wording.option('initial')} option", ModelError)
    return system.replace(initial=initial)


def _assignment(item: str) -> tuple[str, float | None]:
    """The name and the number of ``NAME=NUMBER`` (None for a number that is not one)."""
    name, sep, text = item.partition("=")
    try:
        return name.strip(), float(text) if sep else None
    except ValueError:
        return name.strip(), None


def _not_initial(name: str, known: dict[str, Any], parameters: set[str]) -> tuple[str, str | Fix]:
    """The message and the fix for an initial value of a name that has none."""
    if name in parameters:
        return f"{name!r} is a parameter", Fix("set it with {}", (Setting("set", entry=name),))
    close = closest_name(name, known)
    hint = f"did you mean {close!r}? " if close else ""
    message = f"{name!r} is not a coordinate or velocity of the system"
    return message, hint + "choose one of: " + ", ".join(known)
