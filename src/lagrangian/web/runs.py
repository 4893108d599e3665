"""The work behind each API call, done in a worker process: the model text read with
:func:`lagrangian.io.loads` (never evaluated), then the pieces every front end prints
(:mod:`lagrangian.documents`), so each answer is the JSON the command line prints, with the
LaTeX the page typesets beside it (``latex``).

An error with the input is an answer too: HTTP 422 and ``{"problems": [{"field", "line",
"column", "message", "fix"}]}``, each fix naming the options of the request
(``options.max_steps``, :mod:`lagrangian.web.wording`).

>>> status, body = run("derive", "coordinates: [x]\\nkinetic: x_dot**2/2\\n", "yaml", {})
>>> status, json.loads(body)["equations"]
(200, ['x_ddot'])
>>> status, body = run("derive", "coordinates: [x]\\nkinetic: x_dot**\\n", "yaml", {})
>>> status, json.loads(body)["problems"][0]["line"]
(422, 2)
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from lagrangian.documents import (
    analysis_of,
    apply_initial,
    apply_settings,
    derivation_document,
    derivation_latex,
    run_document,
)
from lagrangian.errors import LagrangianError, Problem, SimulationError
from lagrangian.io import loads
from lagrangian.model import System
from lagrangian.numerics.export import export
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.scene import scene_of
from lagrangian.render.timing import spread_rows
from lagrangian.simulation import Trajectory, simulate
from lagrangian.size_limits import size_limit
from lagrangian.web.limits import TimeLimitExceeded
from lagrangian.web.wording import WEB, problem_document

#: Output times of a simulation asked without ``samples`` (the model's own count wins).
DEFAULT_SAMPLES = 1000
#: The name of the model text in messages.
SOURCE = "model"


def system_of(model: str, fmt: str, options: dict[str, Any]) -> System:
    """The System of the model text with the ``set`` overrides (``--set NAME=VALUE``) and
    the ``initial`` values (``--initial NAME=VALUE``)."""
    system = apply_settings(loads(model, format=fmt, source=SOURCE), options.get("set", []), WEB)
    return apply_initial(system, options.get("initial", []), WEB)


def derive_document(model: str, fmt: str, options: dict[str, Any]) -> dict[str, Any]:
    """``lagrangian derive --format json --steps`` and, as ``latex``, ``--format latex --steps
    --matrix``."""
    system = system_of(model, fmt, options)
    steps = options.get("steps", True)
    initial = {str(name): float(value) for name, value in system.initial.items()}
    return {
        **derivation_document(system, steps),
        "latex": derivation_latex(system, steps, True),
        "initial": initial,  # the model's initial values: the page's sliders start there
    }


def analyze_document(model: str, fmt: str, options: dict[str, Any]) -> dict[str, Any]:
    """``lagrangian analyze --format json`` (with ``--about``, ``--input``, ``--project``,
    ``--search-degree``) and, as ``latex``, ``--format latex``, from one analysis."""
    system = system_of(model, fmt, options)
    report = analysis_of(
        system,
        options.get("about"),
        options.get("input", []),
        options.get("project", False),
        options.get("search_degree", 2),
        WEB,
    )
    return {**analysis_document(report), "latex": analysis_latex(report)}


def export_document(model: str, fmt: str, options: dict[str, Any]) -> dict[str, Any]:
    """``lagrangian export --language LANGUAGE`` as ``{"language", "files": {NAME: TEXT}}``:
    the generated code of the equations (the multiplier form when the model has
    constraints), numpy by default."""
    language = options.get("language", "numpy")
    files = export(system_of(model, fmt, options), language)
    return {"language": language, "files": files}


def simulate_document(
    model: str, fmt: str, options: dict[str, Any], wall_seconds: float | None = None
) -> dict[str, Any]:
    """``lagrangian simulate`` as ``{"columns": {"t": [...], NAME: [...]}, "summary": {...},
    "scene": {...}, "rows": [...]}``: the CSV's columns, the run's status and drift, and the
    scene of ``--animate`` (bodies, springs, a circuit's schematic and currents...) with the
    sample each of its frames shows (:func:`scene_document`)."""
    system = system_of(model, fmt, options)
    given = {key: value for key, value in options.items() if key not in ("set", "initial")}
    t_end = given.pop("t_end", None)
    if "samples" not in given and "samples" not in system.simulation:
        given["samples"] = DEFAULT_SAMPLES
    if wall_seconds is not None:
        given["max_wall_time"] = wall_seconds
    trajectory = simulate(system, t_span=t_end, raise_on_failure=False, **given)
    if not trajectory.success:
        rows = len(trajectory.t)
        where = f" ({rows} rows, up to t = {trajectory.t[-1]:.6g})" if rows else ""
        raise SimulationError(f"{trajectory.worded_message(WEB)}{where}")
    return {**run_document(trajectory, WEB), **scene_document(system, trajectory)}


def scene_document(system: System, trajectory: Trajectory) -> dict[str, Any]:
    """The run's scene (``Scene.to_dict()``, the command line's animations' format) at no more
    than :data:`~lagrangian.render.timing.MAX_FRAMES` of its samples, evenly spread, and
    ``rows``: the sample (the row of ``columns``) each frame shows, so that the page's time
    slider, its plot cursor and its drawing show the same sample."""
    rows = spread_rows(len(trajectory.t))
    return {"scene": scene_of(system, trajectory, rows=rows).to_dict(), "rows": rows.tolist()}


def error_document(message: str, problems: tuple[Problem, ...] = (), fix: str = "") -> bytes:
    """The body of an error answer: every problem, or one made of the message."""
    listed = problems or (Problem("", message.splitlines()[0] if message else "error", fix),)
    summary = message.splitlines()[0] if message else ""
    return _json({"error": summary, "problems": [problem_document(p) for p in listed]})


def _json(document: dict[str, Any]) -> bytes:
    return json.dumps(document, ensure_ascii=False, allow_nan=False).encode("utf-8")


Runner = Callable[[str, str, dict[str, Any]], dict[str, Any]]
RUNS: dict[str, Runner] = {
    "derive": derive_document,
    "analyze": analyze_document,
    "simulate": simulate_document,
    "export": export_document,
}

#: Statuses of the answers.
OK, UNPROCESSABLE, INTERNAL = 200, 422, 500


def run(
    command: str, model: str, fmt: str, options: dict[str, Any], cpu_seconds: float | None = None
) -> tuple[int, bytes]:
    """The HTTP status and JSON body of ``command`` on the model text."""
    try:
        with size_limit(where="playground"):  # its message speaks of what the page offers
            if command == "simulate":
                document = simulate_document(model, fmt, options, cpu_seconds)
            else:
                document = RUNS[command](model, fmt, options)
        return OK, _json(document)
    except LagrangianError as error:
        return UNPROCESSABLE, error_document(str(error), error.problems)
    except TimeLimitExceeded:
        limit = f" of {cpu_seconds:g} s" if cpu_seconds else ""
        fix = "make the model smaller or simpler, or run it with the lagrangian command"
        return UNPROCESSABLE, error_document(f"The work used its CPU time{limit}", fix=fix)
    except MemoryError:
        fix = "make the model smaller or simpler, or run it with the lagrangian command"
        return UNPROCESSABLE, error_document("The work used all the memory it may use", fix=fix)
    except RecursionError:
        fix = "write the expressions with fewer nested parentheses"
        return UNPROCESSABLE, error_document("The model is nested too deeply", fix=fix)
    except Exception as error:  # a bug: say so plainly, the server goes on
        message = f"internal error: {type(error).__name__}: {error}"
        return INTERNAL, error_document(message, fix="please report it with the model")
