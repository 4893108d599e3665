"""What each command does, from parsed arguments to the text it prints (no exit codes here)."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from lagrangian import examples, render
from lagrangian.analysis import AnalysisReport, analyze
from lagrangian.analysis.arguments import numeric_values, operating_state
from lagrangian.analysis.manifold.constraint_manifold import require_on_manifold
from lagrangian.constraints import ConstrainedEquations, constrained_equations, eliminate
from lagrangian.derivation import derive
from lagrangian.errors import (
    ConstraintError,
    ModelError,
    Problem,
    SimulationInputError,
    raise_if_problems,
)
from lagrangian.io import load, loads
from lagrangian.io.yaml_tree import MAX_CHARACTERS
from lagrangian.model import Holonomic, System
from lagrangian.numerics.export import export
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.analysis_text import analysis_text
from lagrangian.render.constrained import constrained_latex, constrained_mathml
from lagrangian.render.json import constrained_document, eom_document
from lagrangian.render.mathml import matrix_form_mathml
from lagrangian.symbolic.expressions import closest_name

EXAMPLE_PREFIX = "examples/"


def load_system(reference: str) -> System:
    """A System from ``examples/NAME`` (``NAME:SIZE`` for an example built to a size, such as
    ``n_link_pendulum:5``), a model file (YAML, TOML, JSON) or ``-``: standard input, read as
    the text of a model (YAML or JSON, or as ``--input-format`` says: ``-:toml``), never as a
    file name."""
    if reference == "-" or reference.startswith("-:"):
        fmt = reference[2:] or None
        if fmt not in (None, "yaml", "toml", "json"):
            raise ModelError(f"{reference!r}: standard input is read as -:yaml, -:toml or -:json")
        text = sys.stdin.read(MAX_CHARACTERS + 1)  # no more than a model file may hold
        return loads(text, format=fmt, source="<standard input>")
    name, _, size = reference.removeprefix(EXAMPLE_PREFIX).partition(":")
    if reference.startswith(EXAMPLE_PREFIX) or name in (*examples.CATALOG, *examples.BENCHMARKS):
        return _example(name, size)
    path = Path(reference)
    if not path.is_file():
        raise ModelError(
            f"No model file {reference!r} and no example of that name: give a path to a "
            ".yaml, .toml or .json file, examples/NAME (see `lagrangian examples`), or - to "
            "read standard input."
        )
    return load(path)


def _example(name: str, size: str) -> System:
    builder = examples.get(name)
    if not size:
        return builder()
    if name not in SCALABLE:
        raise ModelError(
            f"The example {name!r} has no size: write examples/{name}; "
            f"{', '.join(SCALABLE)} take one, as in {next(iter(SCALABLE))}:5."
        )
    if not size.isdigit() or not 1 <= int(size) <= MAX_SIZE:
        raise ModelError(
            f"{name}:{size}: the size must be a whole number from 1 to {MAX_SIZE}, as in {name}:5."
        )
    return builder(int(size))


#: The examples built to a size (``NAME:SIZE`` on the command line), and the largest size.
SCALABLE = ("n_link_pendulum",)
MAX_SIZE = 200


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
        elif not math.isfinite(value):
            message = f"{text.strip()} is not a finite number"
            problems.append(Problem(f"--set {item}", message, f"e.g. --set {name}=0.5"))
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


def apply_initial(system: System, items: Sequence[str]) -> System:
    """``--initial NAME=VALUE`` values of coordinates and velocities (``theta=0.5``,
    ``theta_dot=0``), every bad one reported at once with the name it may have meant."""
    if not items:
        return system
    known = {q.name: q for q in (*system.coordinates, *system.velocities)}
    parameters = {p.name for p in system.parameters}
    initial, problems = dict(system.initial), []
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip()
        try:
            value = float(text) if sep else None
        except ValueError:
            value = None
        if name not in known:
            problems.append(Problem(f"--initial {item}", *_not_initial(name, known, parameters)))
        elif value is None or value != value or abs(value) == float("inf"):
            problems.append(
                Problem(f"--initial {item}", "expected NAME=NUMBER", "e.g. --initial theta=0.5")
            )
        else:
            initial[known[name]] = value
    raise_if_problems(problems, "Bad --initial option", ModelError)
    return system.replace(initial=initial)


def _not_initial(name: str, known: dict[str, Any], parameters: set[str]) -> tuple[str, str]:
    """The message and the fix for ``--initial NAME=...`` of a name without an initial value."""
    if name in parameters:
        return f"{name!r} is a parameter", f"set it with --set {name}=VALUE"
    close = closest_name(name, known)
    hint = f"did you mean {close!r}? " if close else ""
    message = f"{name!r} is not a coordinate or velocity of the system"
    return message, hint + "choose one of: " + ", ".join(known)


def derivation_document(system: System, steps: bool) -> dict[str, Any]:
    """What ``derive --format json`` prints: the equations (with ``steps``), the ``units``
    of names when the model gives them, and the multiplier form of a constrained system."""
    eom = derive(system)
    document = eom_document(eom, steps=steps)
    if system.units:  # names described with their units, where the model gives them
        document["units"] = dict(system.units)
    if system.constraints:
        document.update(constrained_document(constrained_equations(eom, system.constraints)))
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
    return "\n".join(parts)


def derive_command(
    reference: str, *, fmt: str, steps: bool, matrix: bool, settings: Sequence[str]
) -> str:
    if fmt == "json":
        return str(derive_json(reference, steps=steps, settings=settings))
    system = apply_settings(load_system(reference), settings)
    if fmt == "latex":
        return derivation_latex(system, steps, matrix)
    eom = derive(system)
    constrained = constrained_equations(eom, system.constraints) if system.constraints else None
    if fmt == "mathml":
        parts = [render.steps_mathml(eom) if steps else render.equations_mathml(eom)]
        if matrix:
            parts.append(matrix_form_mathml(eom))
        if constrained is not None:
            parts.append(constrained_mathml(constrained, matrix))
        return "\n".join(parts)
    parts = [render.steps_text(eom) if steps else render.equations_text(eom)]
    if constrained is not None:
        parts.append(constrained_text(constrained))
    if matrix:
        parts.append(render.matrix_form_text(eom))
        if constrained is not None:
            parts.append(augmented_text(constrained))
    return "\n\n".join(parts)


@dataclasses.dataclass(frozen=True)
class JsonDocument:
    """A JSON document as the command line prints it, encoded piece by piece as it is
    written (:meth:`chunks`): a document of a hundred megabytes (a 200-link chain) is never
    held whole as text, nor as the list of pieces ``json.dumps`` joins."""

    document: dict[str, Any]

    def chunks(self) -> Iterator[str]:
        yield from json.JSONEncoder(indent=2, ensure_ascii=False).iterencode(self.document)
        yield "\n"

    def __str__(self) -> str:
        return "".join(self.chunks())


def derive_json(reference: str, *, steps: bool, settings: Sequence[str]) -> JsonDocument:
    """What ``derive --format json`` prints (:func:`derivation_document`)."""
    system = apply_settings(load_system(reference), settings)
    return JsonDocument(derivation_document(system, steps))


def augmented_text(equations: ConstrainedEquations) -> str:
    """The augmented system of the multiplier form, in plain text."""
    return "\n".join(
        [
            "augmented form [M, -A^T; A, 0] [q_ddot; lambda] = [forcing; gamma]:",
            f"  matrix: {equations.augmented_matrix.tolist()}",
            f"  unknowns: {list(equations.unknowns)}",
            f"  right side: {list(equations.augmented_rhs)}",
        ]
    )


def constrained_text(equations: ConstrainedEquations) -> str:
    """The constraints and the equations with their multipliers (lambda_j dh_j/dq)."""
    lines = ["With the constraints (lambda_j dh_j/dq is the force of constraint j):"]
    lines += [
        f"  {c.expression} = 0" if c.kind != "unilateral" else f"  {c.expression} >= 0"
        for c in equations.constraints
    ]
    lines += [f"{e} = 0" for e in equations.equations]
    return "\n".join(lines)


def export_command(
    reference: str,
    *,
    language: str,
    out: str,
    settings: Sequence[str],
    independent: str | None = None,
) -> str:
    """Generated code for ``language``: printed (``out`` is ``-``) or written into a folder.
    With ``independent`` (comma-separated coordinates) the holonomic constraints are
    eliminated first and the minimal-coordinate form is exported."""
    system = apply_settings(load_system(reference), settings)
    if independent is not None:
        names = [name.strip() for name in independent.split(",") if name.strip()]
        by_name = {q.name: q for q in system.coordinates}
        unknown = [name for name in names if name not in by_name]
        if unknown or not names:
            raise ConstraintError(
                f"--independent {independent!r}: name coordinates of the model "
                f"({', '.join(by_name)}), as many as it has degrees of freedom"
            )
        if any(not isinstance(c, Holonomic) for c in system.constraints):
            raise ConstraintError(
                "--independent: only holonomic constraints h(q, t) = 0 can be eliminated; "
                "this model has velocity or unilateral constraints — leave out --independent "
                "to export the multiplier form"
            )
        system = eliminate(system, [by_name[name] for name in names])
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
    reference: str,
    *,
    about: str | None,
    inputs: Sequence[str],
    settings: Sequence[str],
    fmt: str = "json",
    project: bool = False,
    search_degree: int = 2,
) -> str:
    """The analysis of docs/architecture.md as JSON, text or LaTeX (with ``linearization``
    when ``--about`` is given; further first integrals sought up to ``search_degree``).  On
    a constrained model an ``--about`` state off the constraints is refused, each missed
    constraint with its residual, unless ``--project`` moves it onto them."""
    system = apply_settings(load_system(reference), settings)
    fix = "add --project to move the --about state onto the constraints"
    report = analysis_of(system, about, inputs, project, search_degree, fix)
    if fmt == "text":
        return analysis_text(report)
    if fmt == "latex":
        return analysis_latex(report)
    return json.dumps(analysis_document(report), indent=2, ensure_ascii=False)


def analysis_of(
    system: System,
    about: str | None,
    inputs: Sequence[str],
    project: bool,
    search_degree: int,
    off_constraints_fix: str,
) -> AnalysisReport:
    """The analysis ``analyze`` prints, ``about`` as the command line writes a state
    (``theta=0.5,phi_dot=2``); on a constrained model a state off the constraints is refused
    with ``off_constraints_fix`` unless ``project``."""
    state = parse_state(about)
    if about and system.constraints and not project:
        eom = derive(system)
        point = operating_state(eom, state)
        require_on_manifold(eom, point, numeric_values(eom), off_constraints_fix)
    return analyze(
        system,
        about=state if about else None,
        inputs=list(inputs),
        project=project,
        search_degree=search_degree,
    )


#: The keywords of simulate that are flags of the simulate command.
_FLAGS = {
    "t_span": "--t-end",
    "method": "--method",
    "rtol": "--rtol",
    "atol": "--atol",
    "samples": "--samples",
    "dt": "--dt",
    "max_steps": "--max-steps",
    "max_wall_time": "--max-wall-time",
    "project_initial": "--project-initial",
}


#: Python phrases of simulate's messages that the command says otherwise.
_PHRASES = (
    (" or t_span=(t0, T)", ""),
    ("give the System simulation={'t_end': T}", "give the model simulate: {t_end: T}"),
    (" with lagrangian.constraints.project_state, or pass", ": pass"),
    ("project_initial=True", "--project-initial"),
)


def in_command_line_words(error: SimulationInputError) -> SimulationInputError:
    """``error`` with its fixes said as the command's flags (``--rtol``, not ``rtol=``)."""

    def flags(text: str) -> str:
        for python, shell in _PHRASES:
            text = text.replace(python, shell)
        text = re.sub(
            r"pass initial=\{'(\w+)': \.\.\.\}",
            r"give it with --initial \1=VALUE or in the model's initial: section",
            text,
        )
        for keyword, flag in _FLAGS.items():
            text = re.sub(rf"\b{keyword}='?([\w.+-]+)'?", rf"{flag} \1", text)
            text = re.sub(rf"\b{keyword}=(\.\.\.)?", flag, text)
        return text

    problems = [
        dataclasses.replace(p, field=_FLAGS.get(p.field, p.field), fix=flags(p.fix))
        for p in error.problems
    ]
    summary = str(error).splitlines()[0] if problems else flags(str(error))
    return SimulationInputError(summary, problems)


def examples_command(name: str | None) -> str:
    if name is None:
        listed = [*examples.names(), *examples.BENCHMARKS]
        width = max(len(n) for n in listed)
        return "\n".join(f"{n:<{width}}  {examples.describe(n)}" for n in listed)
    name = name.removeprefix(EXAMPLE_PREFIX)
    builder = examples.get(name)
    try:
        return examples.model_text(name)
    except ModelError:  # built in Python (it takes a size): describe it instead
        return f"{name}\n\n{(builder.__doc__ or '').strip()}"
