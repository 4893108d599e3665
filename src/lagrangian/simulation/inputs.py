"""What simulate is told, checked at the boundary: every problem collected, raised once.

Each setting comes from the argument, else the System (``initial``, ``simulation``), else the
library default.  Names may be strings or SymPy symbols; unknown names get the closest known
one as a suggestion.

>>> import lagrangian as lg
>>> from lagrangian.numerics.compile import compile_equations
>>> compiled = compile_equations(lg.derive(lg.examples.simple_pendulum()))
>>> parameter_values(compiled, {"l": 2.0}, [])
{'m': 1.0, 'g': 9.81, 'l': 2.0}
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lagrangian.errors import Fix, Problem, Setting
from lagrangian.numerics.compile import CompiledEquations
from lagrangian.simulation.integrators.budget import DEFAULT_MAX_STEPS
from lagrangian.simulation.methods import DEFAULT_METHOD, TABLE
from lagrangian.symbolic.expressions import closest_name
from lagrangian.symbolic.symbols import name_of

#: The tolerances of the adaptive methods when neither the call nor the System gives them.
TOLERANCES: dict[str, float] = {"rtol": 1e-8, "atol": 1e-10}


@dataclass(frozen=True)
class Inputs:
    """Checked inputs of one simulation."""

    parameters: dict[str, float]
    p: np.ndarray
    x0: np.ndarray
    t_span: tuple[float, float]
    t_out: np.ndarray | None
    method: str
    rtol: float
    atol: float
    dt: float | None
    max_step: float
    max_steps: int = DEFAULT_MAX_STEPS
    max_wall_time: float | None = None


@dataclass(frozen=True)
class Fallbacks:
    """What an input falls back to when the call does not give it: the System's initial
    values and simulation settings (none when equations of motion were given)."""

    initial: Mapping[Any, float] = field(default_factory=dict)
    settings: Mapping[str, Any] = field(default_factory=dict)


def checked_inputs(
    compiled: CompiledEquations,
    given: Mapping[str, Any],
    fallbacks: Fallbacks,
    ends_only: bool = False,
) -> tuple[Inputs, list[Problem]]:
    """The inputs of ``given`` (the arguments of simulate) and every problem with them
    (placeholders stand where a value is wrong), for the caller to raise once with the
    problems of the options.  ``ends_only``: without ``samples`` or ``t_eval`` in ``given``
    the output times are the two ends of the span, the System's own ``samples`` left out
    (a sweep stores every member); a fixed-step method is still asked for its ``dt``.

    ``given`` holds initial, parameters, t_span and the :class:`~lagrangian.simulation.
    options.StepKeywords`, each possibly absent or None (then ``fallbacks``, or the
    default).  Whether a step keyword applies to the method is
    :class:`~lagrangian.simulation.options.Options`' question: here an unknown method reads
    as the default one, and a System setting the method does not take is left out.
    """
    settings = fallbacks.settings
    problems: list[Problem] = []

    def setting(name: str, default: Any = None) -> Any:
        value = given.get(name)
        return value if value is not None else settings.get(name, default)

    values = parameter_values(compiled, _names_to_values(given, "parameters", problems), problems)
    initial = _names_to_values(given, "initial", problems)
    x0 = initial_state(compiled, initial, fallbacks.initial, problems)
    t_span = time_span(given.get("t_span"), settings.get("t_end"), problems)
    t_eval = given.get("t_eval")
    samples = given.get("samples") if t_eval is not None or ends_only else setting("samples")
    t_out = output_times(t_span, samples, t_eval, problems)
    method = TABLE.get(setting("method", DEFAULT_METHOD), TABLE[DEFAULT_METHOD])
    rtol, atol = TOLERANCES["rtol"], TOLERANCES["atol"]
    max_step, dt = math.inf, None
    if method.takes_tolerances:
        rtol = _positive("rtol", setting("rtol", rtol), problems)
        atol = _positive("atol", setting("atol", atol), problems)
        max_step = _max_step(given.get("max_step"), problems)
    else:
        dt = _step(method.name, setting("dt"), t_out, problems)
    max_steps, max_wall_time = _budget(given, problems)
    _affordable(t_span, dt, max_step, max_steps, problems)
    _honoured(rtol, problems)
    _meaningful(rtol, atol, x0, problems)
    _fits_in_memory(t_out, len(x0), problems)
    if ends_only and t_out is None and t_eval is None:
        t_out = np.array(t_span, dtype=float)
    inputs = Inputs(
        parameters=values,
        p=np.array([values[name] for name in compiled.parameters], dtype=float),
        x0=x0,
        t_span=t_span,
        t_out=t_out,
        method=method.name,
        rtol=rtol,
        atol=atol,
        dt=dt,
        max_step=max_step,
        max_steps=max_steps,
        max_wall_time=max_wall_time,
    )
    return inputs, problems


def _budget(given: Mapping[str, Any], problems: list[Problem]) -> tuple[int, float | None]:
    """max_steps (a positive integer) and max_wall_time (positive seconds, or None)."""
    max_steps = given.get("max_steps")
    if max_steps is None:
        max_steps = DEFAULT_MAX_STEPS
    elif (
        isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps < 1
    ):
        fix = Fix("pass e.g. {}", (Setting("max_steps", 10**7),))
        problems.append(Problem("max_steps", f"{max_steps!r} is not a positive integer", fix))
        max_steps = DEFAULT_MAX_STEPS
    wall = given.get("max_wall_time")
    if wall is not None:
        wall = _positive("max_wall_time", wall, problems)
    return int(max_steps), wall


#: The smallest rtol SciPy's solvers honour (below it they clip it with a warning).
SMALLEST_RTOL = 100 * float(np.finfo(float).eps)
#: The memory the output rows of one run may take (the states, velocities, energies and
#: their working copies, about four numbers per state variable and row).
OUTPUT_BYTES = 2 * 1024**3


def _honoured(rtol: float, problems: list[Problem]) -> None:
    if 0 < rtol < SMALLEST_RTOL:
        message = (
            f"rtol={rtol:g} is below {SMALLEST_RTOL:.2g}, the smallest relative tolerance the "
            "solvers honour (100 times the machine epsilon)"
        )
        fix = Fix(f"pass {{}} or more (at least {SMALLEST_RTOL:.2g})", (Setting("rtol", 1e-13),))
        problems.append(Problem("rtol", message, fix))


def _meaningful(rtol: float, atol: float, x0: np.ndarray, problems: list[Problem]) -> None:
    """Refuse tolerances that let the error grow as large as the solution: rtol of 1 or more
    (100 % of each value), atol as large as the state's scale (its largest initial value, at
    least 1: atol has the units of the state, so a model in large units may take atol > 1).
    A tolerance refused already (not a positive number) is not refused twice."""
    flagged = {problem.field for problem in problems}
    if rtol >= 1 and "rtol" not in flagged:
        message = f"rtol={rtol:g} lets each step's error be as large as the values themselves"
        fix = Fix("pass a value below 1, such as {} (the default)", (Setting("rtol", 1e-8),))
        problems.append(Problem("rtol", message, fix))
    finite = np.abs(x0[np.isfinite(x0)])
    scale = max(1.0, float(np.max(finite))) if finite.size else 1.0
    if atol >= scale and "atol" not in flagged:
        message = (
            f"atol={atol:g} lets each step's error be as large as the state itself (its "
            f"scale, the largest initial value or 1, is {scale:g})"
        )
        fix = Fix("pass a value well below it, such as {} (the default)", (Setting("atol", 1e-10),))
        problems.append(Problem("atol", message, fix))


def _fits_in_memory(t_out: np.ndarray | None, size: int, problems: list[Problem]) -> None:
    """Refuse output times whose rows would not fit in :data:`OUTPUT_BYTES` (checked before
    anything is allocated but the times themselves)."""
    if t_out is None:
        return
    needed = len(t_out) * (4 * size + 4) * 8
    if needed > OUTPUT_BYTES:
        message = (
            f"{len(t_out):,} output rows would take about {needed / 1024**3:.1f} GiB, more than "
            f"the {OUTPUT_BYTES / 1024**3:g} GiB a run may use"
        )
        problems.append(Problem("samples", message, "ask for fewer samples or output times"))


def _is_integer(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _affordable(
    t_span: tuple[float, float],
    dt: float | None,
    max_step: float,
    max_steps: int,
    problems: list[Problem],
) -> None:
    """Refuse a step so small that the run could not end within max_steps (dt = 1e-300 would
    otherwise run for ever), or a dt longer than the span."""
    span = abs(t_span[1] - t_span[0])
    if dt is not None and math.isfinite(dt) and dt > span > 0:
        message = f"dt={dt:g} is longer than the time span, {span:g}: not one step fits"
        fix = Fix("pass a step shorter than the span, such as {}", (Setting("dt", span / 100),))
        problems.append(Problem("dt", message, fix))
        return
    for name, step in (("dt", dt), ("max_step", max_step)):
        if step is None or not math.isfinite(step) or step <= 0:
            continue
        needed = span / step
        if needed > max_steps:
            problems.append(
                Problem(
                    name,
                    f"a step of {step:g} needs {needed:.3g} steps over the time span, more "
                    f"than the step budget of {max_steps:,}",
                    Fix(
                        "use a larger {0.name}, a shorter time span, or pass {1}",
                        (Setting(name), Setting("max_steps")),
                    ),
                )
            )


def parameter_values(
    compiled: CompiledEquations, given: Mapping[Any, Any], problems: list[Problem]
) -> dict[str, float]:
    """Parameter values by name: ``given`` over the defaults; every parameter needs one."""
    values = dict(zip(compiled.parameters, compiled.defaults))
    for key, value in given.items():
        name = name_of(key)
        if name not in values:
            problems.append(_unknown("parameters", name, "a parameter", compiled.parameters))
            continue
        number = _number(f"parameters[{name!r}]", value, problems)
        values[name] = math.nan if number is None else number  # nan: reported already
    for name, default in values.items():
        if default is None:
            fix = Fix("pass {}", (Setting("parameters", entry=name),))
            problems.append(Problem("parameters", f"parameter {name} has no value", fix))
    return {name: math.nan if value is None else value for name, value in values.items()}


def initial_state(
    compiled: CompiledEquations,
    given: Mapping[Any, Any],
    fallback: Mapping[Any, Any],
    problems: list[Problem],
) -> np.ndarray:
    """The state x0 from initial coordinates and velocities (``given`` over ``fallback``).

    Velocities of first-order coordinates are not part of the state and may be omitted.
    """
    velocities = tuple(name + "_dot" for name in compiled.coordinates)
    known = (*compiled.coordinates, *velocities)
    values: dict[str, float | None] = {name_of(k): v for k, v in fallback.items()}
    for key, value in given.items():
        name = name_of(key)
        if name not in known:
            problems.append(_unknown("initial", name, "a coordinate or velocity", known))
        values[name] = _number(f"initial[{name!r}]", value, problems)
    missing = [name for name in compiled.state_names if name not in values]
    for name in missing:
        kind = "velocity" if name in velocities else "coordinate"
        problems.append(
            Problem(
                "initial",
                f"no initial value for the {kind} {name}",
                Fix(
                    "pass {}, or give the model an initial value of it",
                    (Setting("initial", entry=name),),
                ),
            )
        )
    return np.array([values.get(name) or 0.0 for name in compiled.state_names], dtype=float)


def time_span(given: Any, t_end: Any, problems: list[Problem]) -> tuple[float, float]:
    """(t0, t1) from ``t_span`` (a number T means (0, T)) or the System's ``t_end``."""
    span = given if given is not None else t_end
    if span is None:
        problems.append(
            Problem(
                "t_span",
                "no end time",
                Fix(
                    "pass the end time, {}, or give the model one (simulate: {{t_end: T}})",
                    (Setting("t_span"),),
                ),
            )
        )
        return (0.0, 1.0)
    ends = list(span) if isinstance(span, Iterable) else [0.0, span]
    numbers = [_number("t_span", value, problems) for value in ends]
    if len(numbers) != 2 or None in numbers:
        problems.append(Problem("t_span", f"{span!r} is not T or (t0, T)"))
        return (0.0, 1.0)
    t0, t1 = float(numbers[0] or 0.0), float(numbers[1] or 0.0)
    if not t1 > t0:
        problems.append(Problem("t_span", f"the end time {t1:g} is not after the start {t0:g}"))
    return (t0, t1)


#: The most output times a run may ask for (refused before any is allocated).
MAX_SAMPLES = 50_000_000


def output_times(
    t_span: tuple[float, float], samples: Any, t_eval: Any, problems: list[Problem]
) -> np.ndarray | None:
    """Output times: ``samples`` evenly spaced over t_span, or ``t_eval``, or None (every step)."""
    if samples is not None and t_eval is not None:
        problems.append(Problem("samples", "both samples and t_eval given", "pass only one"))
        return None
    if samples is not None:
        if not isinstance(samples, (int, np.integer)) or samples < 2:
            problems.append(Problem("samples", f"{samples!r} is not an integer >= 2"))
            return None
        if samples > MAX_SAMPLES:
            message = f"{samples:,} samples are more than the {MAX_SAMPLES:,} a run may write"
            problems.append(Problem("samples", message, "ask for fewer samples"))
            return None
        return np.linspace(*t_span, int(samples))
    if t_eval is not None:
        try:
            times = np.asarray(t_eval, dtype=float).ravel()
        except (TypeError, ValueError):
            problems.append(Problem("t_eval", f"{t_eval!r} is not a list of times"))
            return None
        if not np.all(np.isfinite(times)) or times.size == 0:
            problems.append(Problem("t_eval", "the times must be finite numbers, at least one"))
            return None
        inside = (times >= t_span[0]) & (times <= t_span[1])
        if not np.all(inside) or np.any(np.diff(times) <= 0):
            problems.append(
                Problem("t_eval", f"the times must increase and lie within t_span {t_span}")
            )
        return times
    return None


def _step(method: str, dt: Any, t_out: np.ndarray | None, problems: list[Problem]) -> float | None:
    """The step of a fixed-step method: ``dt``, else the spacing of evenly spaced samples."""
    if dt is not None:
        return _positive("dt", dt, problems)
    if t_out is not None and len(t_out) >= 2 and np.allclose(np.diff(t_out), t_out[1] - t_out[0]):
        return float(t_out[1] - t_out[0])
    problems.append(
        Problem(
            "dt",
            f"the fixed-step method {method} needs a step",
            Fix("pass {} or {}", (Setting("dt"), Setting("samples"))),
        )
    )
    return None


def _max_step(value: Any, problems: list[Problem]) -> float:
    """The largest step of an adaptive method: a positive number, infinity by default."""
    if value is None:
        return math.inf
    if not (isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0):
        problems.append(Problem("max_step", f"max_step must be a positive number, not {value!r}"))
        return math.inf
    return float(value)


def _positive(name: str, value: Any, problems: list[Problem]) -> float:
    number = _number(name, value, problems)
    if number is not None and not number > 0:
        problems.append(Problem(name, f"{name} must be positive, not {number:g}"))
    return number or 1.0


def _number(field: str, value: Any, problems: list[Problem]) -> float | None:
    try:
        number = float(value)
    except (TypeError, ValueError):
        problems.append(Problem(field, f"{value!r:.60} is not a number"))
        return None
    except OverflowError:  # an integer beyond a double (10**400): said without printing it
        size = getattr(value, "bit_length", lambda: 1024)()
        message = f"a number of about {int(size * math.log10(2)) + 1} digits is beyond a double"
        problems.append(Problem(field, message, "give a value below 1.8e308"))
        return None
    if not math.isfinite(number):
        problems.append(Problem(field, f"{value!r} is not a finite number"))
        return None
    return number


def _names_to_values(given: Mapping[str, Any], field: str, problems: list[Problem]) -> Mapping:
    """The mapping ``given[field]`` (empty when absent); a problem when it is not one."""
    value = given.get(field)
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        fix = f"pass {field}={{'name': value, ...}}, by name or symbol"
        problems.append(Problem(field, f"{value!r} is not a mapping of names to values", fix))
        return {}
    return value


def _unknown(field: str, name: str, kind: str, known: Iterable[str]) -> Problem:
    known = list(known)
    close = closest_name(name, known, cutoff=0.5)
    fix = f"did you mean {close!r}?" if close else f"known names: {', '.join(known)}"
    return Problem(field, f"{name!r} is not {kind} of this system", fix)
