"""What each command does, from parsed arguments to the text it prints (no exit codes here)."""

from __future__ import annotations

import dataclasses
import json
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from lagrangian import examples, render
from lagrangian.cli.outputs import folder_problem
from lagrangian.cli.wording import COMMAND_LINE
from lagrangian.constraints import ConstrainedEquations, constrained_equations, eliminate
from lagrangian.constraints.multipliers import UNSOLVED
from lagrangian.derivation import derive
from lagrangian.documents import (
    analysis_of,
    apply_initial,
    apply_settings,
    derivation_document,
    derivation_latex,
)
from lagrangian.errors import ConstraintError, ModelError, OutputError
from lagrangian.io import load, loads
from lagrangian.io.load import MAX_BYTES, model_text
from lagrangian.io.yaml_tree import MAX_CHARACTERS
from lagrangian.model import Holonomic, System
from lagrangian.model.substitution import with_values
from lagrangian.numerics.export import export
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.analysis_text import analysis_text
from lagrangian.render.constrained import IN_CONTACT, constrained_mathml, in_contact
from lagrangian.render.hybrid import has_jumps, hybrid_mathml_rows, hybrid_text
from lagrangian.render.mathml import Dotted, mathml_table, matrix_form_mathml
from lagrangian.render.values import values_in_force

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
        source = "<standard input>"
        if sys.stdin is None:  # closed (<&-)
            raise ModelError("Standard input is closed: give the model as a file, or pipe it in.")
        stream = getattr(sys.stdin, "buffer", None)  # bytes: decoded as a file is
        if stream is None:
            return loads(sys.stdin.read(MAX_CHARACTERS + 1), format=fmt, source=source)
        return loads(model_text(stream.read(MAX_BYTES), source), format=fmt, source=source)
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
    largest = examples.SCALABLE.get(name)
    if largest is None:
        raise ModelError(
            f"The example {name!r} has no size: write examples/{name}; "
            f"{', '.join(examples.SCALABLE)} take one, as in {next(iter(examples.SCALABLE))}:5."
        )
    if not size.isdigit() or not 1 <= int(size) <= largest:
        raise ModelError(
            f"{name}:{size}: the size must be a whole number from 1 to {largest}, as in {name}:5."
        )
    return builder(int(size))


def derive_command(
    reference: str,
    *,
    fmt: str,
    steps: bool,
    matrix: bool,
    settings: Sequence[str],
    substitute: bool = False,
) -> str:
    """What ``derive`` prints: the equations in ``fmt``, symbolic or (``substitute``) with
    the parameters' values put in; text and LaTeX end with the values in force."""
    if fmt == "json":
        return str(derive_json(reference, steps=steps, settings=settings, substitute=substitute))
    given = apply_settings(load_system(reference), settings, COMMAND_LINE)
    system = with_values(given) if substitute else given
    if fmt == "latex":
        values = values_in_force(given, substitute, latex=True)
        return derivation_latex(system, steps, matrix) + (f"\n{values}" if values else "")
    eom = derive(system)
    constrained = constrained_equations(eom, system.constraints) if system.constraints else None
    if fmt == "mathml":
        parts = [render.steps_mathml(eom) if steps else render.equations_mathml(eom)]
        if matrix:
            parts.append(matrix_form_mathml(eom))
        if constrained is not None:
            parts.append(constrained_mathml(constrained, matrix))
        if has_jumps(system):
            parts.append(mathml_table(hybrid_mathml_rows(system, Dotted(eom))))
        return "\n".join(parts)
    parts = [render.steps_text(eom) if steps else render.equations_text(eom)]
    if constrained is not None:
        parts.append(constrained_text(constrained))
    if has_jumps(system):
        parts.append(hybrid_text(system))
    if matrix:
        parts.append(render.matrix_form_text(eom))
        if constrained is not None:
            parts.append(augmented_text(constrained))
    values = values_in_force(given, substitute)
    return "\n\n".join([*parts, values] if values else parts)


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


def derive_json(
    reference: str, *, steps: bool, settings: Sequence[str], substitute: bool = False
) -> JsonDocument:
    """What ``derive --format json`` prints (:func:`derivation_document`); ``substitute``:
    of the System with its parameters' values put in (``parameters`` then lists only the
    ones without a value)."""
    system = apply_settings(load_system(reference), settings, COMMAND_LINE)
    return JsonDocument(derivation_document(with_values(system) if substitute else system, steps))


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
    if in_contact(equations):
        lines.append(f"  ({IN_CONTACT}: the equations below)")
    lines += [f"{e} = 0" for e in equations.equations]
    forces = equations.constraint_forces
    lines.append("Constraint forces (each multiplier solved for the state):")
    if forces is None:
        lines.append(f"  {UNSOLVED}")
    else:
        lines += [f"  {lam} = {value}" for lam, value in forces.items()]
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
    system = apply_settings(load_system(reference), settings, COMMAND_LINE)
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
    problem = folder_problem("--out", out)
    if problem is not None:  # before the work of the derivation
        raise OutputError("Cannot write the code:", [problem])
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


def analyze_command(
    reference: str,
    *,
    about: str | None,
    inputs: Sequence[str],
    settings: Sequence[str],
    fmt: str = "json",
    project: bool = False,
    search_degree: int = 2,
    cycle: str | None = None,
    initial: Sequence[str] = (),
) -> str:
    """The analysis of docs/architecture.md as JSON, text or LaTeX (with ``linearization``
    when ``--about`` is given; further first integrals sought up to ``search_degree``; the
    limit cycle through the transition ``cycle``, from the ``initial`` values).  On a
    constrained model an ``--about`` state off the constraints is refused, each missed
    constraint with its residual, unless ``--project`` moves it onto them."""
    system = apply_settings(load_system(reference), settings, COMMAND_LINE)
    system = apply_initial(system, initial, COMMAND_LINE)
    report = analysis_of(system, about, inputs, project, search_degree, COMMAND_LINE)
    found = None
    if cycle:
        from lagrangian.simulation.limit_cycle import limit_cycle  # loads the integrators

        found = limit_cycle(system, section=cycle)
    if fmt in ("text", "latex"):
        printed = analysis_text(report) if fmt == "text" else analysis_latex(report)
        if found is None:
            return printed
        cycle_text = found.text() if fmt == "text" else f"% {found.text()}".replace("\n", "\n% ")
        return f"{printed}\n\n{cycle_text}"
    document = analysis_document(report)
    if found is not None:
        document["limit_cycle"] = found.document()
    return json.dumps(document, indent=2, ensure_ascii=False)


def examples_command(name: str | None) -> str:
    if name is None:
        listed = [*examples.names(), *examples.BENCHMARKS]
        width = max(len(n) for n in listed)
        return "\n".join(f"{n:<{width}}  {examples.describe(n)}" for n in listed)
    name, _, size = name.removeprefix(EXAMPLE_PREFIX).partition(":")
    builder = examples.get(name)
    if size:
        _example(name, size)  # the size checked as every command checks it
    try:
        return examples.model_text(name, int(size) if size else None)
    except ModelError:  # built in Python (it takes a size): describe it instead
        return f"{name}\n\n{(builder.__doc__ or '').strip()}"
