"""What each command does, from parsed arguments to the text it prints (no exit codes here)."""

from __future__ import annotations

import io
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from lagrangian import examples, render
from lagrangian.analysis import analyze
from lagrangian.cli.progress import progress_bar
from lagrangian.constraints import ConstrainedEquations, constrained_equations
from lagrangian.derivation import derive
from lagrangian.errors import ModelError, Problem
from lagrangian.io import load
from lagrangian.model import System
from lagrangian.numerics.export import export
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.animation import animate as write_animation
from lagrangian.render.json import constrained_document, eom_document
from lagrangian.render.plots import save_plots
from lagrangian.simulation import simulate

EXAMPLE_PREFIX = "examples/"


def load_system(reference: str) -> System:
    """A System from ``examples/NAME``, a model file (YAML, TOML, JSON) or ``-`` (stdin)."""
    if reference == "-":
        return load(sys.stdin.read())
    name = reference.removeprefix(EXAMPLE_PREFIX)
    if reference.startswith(EXAMPLE_PREFIX) or name in examples.CATALOG:
        return examples.get(name)()
    path = Path(reference)
    if not path.is_file():
        raise ModelError(
            f"No model file {reference!r} and no example of that name: give a path to a "
            ".yaml, .toml or .json file, examples/NAME (see `lagrangian examples`), or - to "
            "read standard input."
        )
    return load(path)


def apply_settings(system: System, settings: Sequence[str]) -> System:
    """``--set NAME=VALUE`` overrides of parameters and initial values."""
    if not settings:
        return system
    parameters = {p.name: p for p in system.parameters}
    initial_names = {q.name: q for q in (*system.coordinates, *system.velocities)}
    new_parameters, new_initial = dict(system.parameters), dict(system.initial)
    problems = []
    for item in settings:
        name, sep, text = item.partition("=")
        name = name.strip()
        try:
            value = float(text)
        except ValueError:
            value = None
        if not sep or value is None:
            problems.append(Problem(f"--set {item}", "expected NAME=NUMBER", "e.g. --set m=2.5"))
        elif name in parameters:
            new_parameters[parameters[name]] = value
        elif name in initial_names:
            new_initial[initial_names[name]] = value
        else:
            problems.append(
                Problem(
                    f"--set {item}",
                    f"{name!r} is not a parameter, coordinate or velocity of the system",
                    "choose one of: " + ", ".join(sorted([*parameters, *initial_names])),
                )
            )
    if problems:
        raise ModelError("Bad --set option:", problems)
    return system.replace(parameters=new_parameters, initial=new_initial)


def derive_command(
    reference: str, *, fmt: str, steps: bool, matrix: bool, settings: Sequence[str]
) -> str:
    system = apply_settings(load_system(reference), settings)
    eom = derive(system)
    constrained = constrained_equations(eom, system.constraints) if system.constraints else None
    if fmt == "json":
        document = eom_document(eom, steps=steps)
        if constrained is not None:
            document.update(constrained_document(constrained))
        return json.dumps(document, indent=2, ensure_ascii=False)
    if fmt == "mathml":
        return render.steps_mathml(eom) if steps else render.equations_mathml(eom)
    if fmt == "latex":
        return render.steps_latex(eom) if steps else render.equations_latex(eom)
    parts = [render.steps_text(eom) if steps else render.equations_text(eom)]
    if constrained is not None:
        parts.append(constrained_text(constrained))
    if matrix:
        parts.append(render.matrix_form_text(eom))
    return "\n\n".join(parts)


def constrained_text(equations: ConstrainedEquations) -> str:
    """The constraints and the equations with their multipliers (lambda_j dh_j/dq)."""
    lines = ["With the constraints (lambda_j dh_j/dq is the force of constraint j):"]
    lines += [
        f"  {c.expression} = 0" if c.kind != "unilateral" else f"  {c.expression} >= 0"
        for c in equations.constraints
    ]
    lines += [f"{e} = 0" for e in equations.equations]
    return "\n".join(lines)


def export_command(reference: str, *, language: str, out: str, settings: Sequence[str]) -> str:
    """Generated code for ``language``: printed (``out`` is ``-``) or written into a folder."""
    system = apply_settings(load_system(reference), settings)
    files = export(derive(system), language)
    if out == "-":
        return "\n".join(
            f"// ---- {name}\n{text}" if len(files) > 1 else text for name, text in files.items()
        )
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
    return "\n".join(str(folder / name) for name in files)


def parse_state(text: str | None) -> dict[str, float]:
    """``NAME=VALUE[,NAME=VALUE...]`` as a mapping (``--about``)."""
    if not text:
        return {}
    state, problems = {}, []
    for item in text.split(","):
        name, sep, value = item.partition("=")
        try:
            state[name.strip()] = float(value)
        except ValueError:
            problems.append(
                Problem(
                    f"--about {item}", "expected NAME=NUMBER", "e.g. --about theta=0.5,phi_dot=2"
                )
            )
        if not sep:
            problems.append(
                Problem(
                    f"--about {item}", "expected NAME=NUMBER", "e.g. --about theta=0.5,phi_dot=2"
                )
            )
    if problems:
        raise ModelError("Bad --about option:", problems)
    return state


def analyze_command(
    reference: str, *, about: str | None, inputs: Sequence[str], settings: Sequence[str]
) -> str:
    """The analysis JSON of docs/architecture.md (with ``linearization`` when ``--about`` is
    given)."""
    system = apply_settings(load_system(reference), settings)
    state = parse_state(about)
    report = analyze(system, about=state if about else None, inputs=list(inputs))
    return json.dumps(analysis_document(report), indent=2, ensure_ascii=False)


def simulate_command(
    reference: str,
    *,
    options: dict[str, Any],
    out: str,
    plot: str | None,
    settings: Sequence[str],
    animate: str | None = None,
    progress: bool = False,
) -> str:
    """Simulate; the CSV of docs/architecture.md goes to ``out`` (``-``: returned for standard
    output)."""
    system = apply_settings(load_system(reference), settings)
    given = {key: value for key, value in options.items() if value is not None}
    t_end = given.pop("t_end", None)
    end = t_end if t_end is not None else system.simulation.get("t_end", 0.0)
    bar = progress_bar(0.0, float(end), force=progress)
    trajectory = simulate(system, t_span=t_end, progress=bar, **given)
    messages = []
    if plot:
        save_plots(trajectory, plot)
        messages.append(f"plot written to {plot}")
    if animate:
        write_animation(system, trajectory, animate)
        messages.append(f"animation written to {animate}")
    if out == "-":
        buffer = io.StringIO()
        trajectory.to_csv(buffer)
        return buffer.getvalue()  # the CSV alone on standard output; the plot is on disk
    trajectory.to_csv(out)
    drift = trajectory.drift()
    messages.insert(
        0,
        f"{len(trajectory.t)} samples written to {out}; "
        f"max |dE/E0| = {drift.get('energy_relative')}",
    )
    return "\n".join(messages)


def examples_command(name: str | None) -> str:
    if name is None:
        width = max(len(n) for n in examples.names())
        return "\n".join(f"{n:<{width}}  {examples.describe(n)}" for n in examples.names())
    name = name.removeprefix(EXAMPLE_PREFIX)
    builder = examples.get(name)
    try:
        return examples.model_text(name)
    except ModelError:  # built in Python (it takes a size): describe it instead
        return f"{name}\n\n{(builder.__doc__ or '').strip()}"
