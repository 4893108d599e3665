"""How a simulation integrates: the options of :func:`lagrangian.simulate`, one frozen record
checked at construction against the method and the system.

An option that does not apply is refused by name, never ignored: ``rtol`` with the fixed-step
RK4, ``dt`` with an adaptive method, ``baumgarte`` on a system without constraints, ``events``
with the variational integrator...  Every problem is collected and raised once, as a
:class:`~lagrangian.errors.SimulationInputError` whose fixes name the keywords to set
(:class:`~lagrangian.errors.Fix`), which each front end words its own way.

The keywords that choose the method, its step and the output times are declared once, in
:class:`StepKeywords`, for :func:`lagrangian.simulate` and :func:`lagrangian.simulate_batch`.

>>> Options(method="RK4", given=frozenset({"rtol"}))
Traceback (most recent call last):
...
lagrangian.errors.SimulationInputError: Cannot simulate (1 problem):
  - rtol: rtol steers the adaptive methods (RK45, RK23, DOP853, Radau, BDF, LSODA), not RK4 — \
remove rtol, or choose an adaptive method such as method='DOP853'
>>> Options(method="DOP853").gains
(0.0, 0.0)
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, TypedDict

from numpy.typing import ArrayLike

from lagrangian.errors import (
    Fix,
    Problem,
    Setting,
    SimulationInputError,
    raise_if_problems,
)
from lagrangian.model.constraints import Constraint, Holonomic, Unilateral, label, statement
from lagrangian.simulation.methods import (
    BACKENDS,
    DEFAULT_METHOD,
    TABLE,
    Method,
    names_where,
    suggest_method,
)


class StepKeywords(TypedDict, total=False):
    """The keywords of simulate and simulate_batch that choose the method, its step and the
    output times (each also read from ``System.simulation`` when not given, but ``max_step``).

    method:
        A name of :data:`lagrangian.simulation.methods.TABLE` (default RK45).
    rtol, atol, max_step:
        Tolerances (default 1e-8, 1e-10) and largest step of an adaptive method.
    dt:
        The step of a fixed-step method (RK4, variational); default: the spacing of
        ``samples``.
    samples, t_eval:
        ``samples`` evenly spaced output times, or the output times ``t_eval``.
    max_steps, max_wall_time:
        The run's budget: at most ``max_steps`` accepted steps (default one million) and
        ``max_wall_time`` seconds (default no limit); see
        :mod:`lagrangian.simulation.integrators.budget`.
    """

    method: str
    rtol: float
    atol: float
    max_step: float
    dt: float
    samples: int
    t_eval: ArrayLike
    max_steps: int
    max_wall_time: float


def check_keywords(keywords: Mapping[str, Any], function: str) -> None:
    """Refuse a keyword that is not a :class:`StepKeywords` name, as Python refuses an
    unexpected keyword (TypeError), with the closest name."""
    known = tuple(StepKeywords.__annotations__)
    for name in keywords:
        if name not in known:
            close = difflib.get_close_matches(name, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise TypeError(f"{function}() got an unexpected keyword argument {name!r}{hint}")


@dataclass(frozen=True)
class Options:
    """The options of one simulation, as asked (see the module docstring).

    Attributes
    ----------
    method:
        The method used: given, else the System's, else RK45.
    backend:
        ``"numpy"`` or ``"numba"``.
    given:
        The step keywords passed explicitly (``rtol``, ``atol``, ``max_step``, ``dt``): those
        must apply to the method; the System's own settings that do not are left out.
    baumgarte, project_initial, project_steps:
        Constraint drift control (None: no Baumgarte stabilization asked).
    events:
        How many event functions are watched.
    constraints, inertia:
        The system's constraints, and whether every coordinate has inertia (second order).
    transitions:
        How many transitions the system has (resets of the state at a guard).
    driver:
        ``"simulate"``, ``"simulate_batch"`` (a batch has its own loops: RK45, DOP853, RK4,
        no constraints) or ``"sweep"`` (members run one by one as simulate runs them, the
        events a stop condition: :attr:`events_keyword`).
    """

    method: str = DEFAULT_METHOD
    backend: str = "numpy"
    given: frozenset[str] = frozenset()
    baumgarte: tuple[float, float] | None = None
    project_initial: bool = False
    project_steps: bool = False
    events: int = 0
    constraints: tuple[Constraint, ...] = ()
    inertia: bool = True
    transitions: int = 0
    driver: str = "simulate"

    def __post_init__(self) -> None:
        object.__setattr__(self, "given", frozenset(self.given))
        object.__setattr__(self, "constraints", tuple(self.constraints))
        problems: list[Problem] = []
        if self.method not in TABLE:
            problems.append(
                Problem("method", f"unknown method {self.method!r}", suggest_method(self.method))
            )
        else:
            for check in _CHECKS:
                problems.extend(check(self))
        raise_if_problems(problems, "Cannot simulate", SimulationInputError)
        if self.baumgarte is not None:
            object.__setattr__(self, "baumgarte", tuple(float(v) for v in self.baumgarte))

    @property
    def spec(self) -> Method:
        """The method's row of the table."""
        return TABLE[self.method]

    @property
    def gains(self) -> tuple[float, float]:
        """Baumgarte's (alpha, beta); (0, 0) when not asked (off)."""
        return (0.0, 0.0) if self.baumgarte is None else (self.baumgarte[0], self.baumgarte[1])

    @property
    def events_keyword(self) -> str:
        """The keyword of the events in the caller's words: ``stop_when`` for a batch or a
        sweep, whose one event is the stop condition."""
        return "events" if self.driver == "simulate" else "stop_when"

    @property
    def unilateral(self) -> bool:
        """Whether some constraint is unilateral (integrated by active sets)."""
        return any(isinstance(c, Unilateral) for c in self.constraints)


def _step_keywords(options: Options) -> list[Problem]:
    """rtol, atol and max_step steer the adaptive methods, dt is the step of the others."""
    method, problems = options.spec, []
    adaptive = ", ".join(names_where("takes_tolerances"))
    for name in sorted(options.given & {"rtol", "atol", "max_step"}):
        if not method.takes_tolerances:
            fix = Fix(
                "remove {0.name}, or choose an adaptive method such as {1}",
                (Setting(name), Setting("method", "DOP853")),
            )
            message = f"{name} steers the adaptive methods ({adaptive}), not {method.name}"
            problems.append(Problem(name, message, fix))
    if "dt" in options.given and not method.takes_step:
        problems.append(
            Problem(
                "dt",
                f"dt is the step of the fixed-step RK4, not of {method.name}",
                Fix(
                    "use {0.name} to bound an adaptive method's steps, or {1}",
                    (Setting("max_step"), Setting("method", "RK4")),
                ),
            )
        )
    return problems


def _baumgarte(options: Options) -> list[Problem]:
    if options.baumgarte is None:
        return []
    try:
        alpha, beta = (float(v) for v in options.baumgarte)
    except (TypeError, ValueError):
        alpha = beta = math.nan
    if not (math.isfinite(alpha) and math.isfinite(beta) and alpha >= 0 and beta >= 0):
        message = (
            f"baumgarte must be a pair (alpha, beta) of non-negative numbers, not "
            f"{options.baumgarte!r}"
        )
        return [Problem("baumgarte", message, "pass baumgarte=(alpha, beta), e.g. (10, 10)")]
    if not options.constraints:
        message = "baumgarte stabilizes constraints, and this system has none"
        return [Problem("baumgarte", message, "remove baumgarte=")]
    if options.spec.variational:
        message = f"the method {options.method!r} holds the constraints exactly at every step"
        return [Problem("baumgarte", message, "remove baumgarte=, or choose another method")]
    return []


def _projections(options: Options) -> list[Problem]:
    problems = []
    for name in ("project_initial", "project_steps"):
        if getattr(options, name) and not options.constraints:
            message = f"{name} moves states onto the constraints, and this system has none"
            problems.append(Problem(name, message, Fix("remove {}", (Setting(name, True),))))
    if not (options.project_steps and options.constraints):
        return problems
    explicit = names_where("explicit")
    if options.unilateral:
        message = (
            "project_steps does not apply to unilateral constraints (they are active only "
            "part of the time)"
        )
        problems.append(Problem("project_steps", message, "use baumgarte=(alpha, beta)"))
    elif options.method not in explicit:
        methods = ", ".join(explicit)
        message = f"project_steps works with the methods {methods}, not {options.method}"
        fix = "choose one of them, or baumgarte=(alpha, beta) instead"
        problems.append(Problem("project_steps", message, fix))
    return problems


def _backend(options: Options) -> list[Problem]:
    if options.backend not in BACKENDS:
        message = f"unknown backend {options.backend!r}"
        return [Problem("backend", message, "backends: 'numpy' (the default), 'numba'")]
    if options.backend != "numba" or not options.spec.variational:
        return []  # "numba": another name of the default (simulation/methods.py)
    message = (
        f"the method {options.method!r} runs on compiled loops whenever numba is installed; "
        "the backend 'numba' is another name of the default backend"
    )
    return [Problem("backend", message, Fix("remove {}", (Setting("backend", "numba"),)))]


def _variational(options: Options) -> list[Problem]:
    """The variational integrators (midpoint rule, collocation) step a regular Lagrangian
    with holonomic constraints, and locate no events."""
    if not options.spec.variational:
        return []
    problems, named = [], f"the method {options.method!r}"
    if options.events:
        message = f"{named} does not locate events yet"
        stop = options.events_keyword
        other = Fix("use another {0.name} with {1.name}", (Setting("method"), Setting(stop)))
        problems.append(Problem(stop, message, other))
    if not options.inertia:
        message = (
            f"{named} needs every coordinate to have inertia (a regular Legendre map p = dL/dq_dot)"
        )
        problems.append(Problem("method", message, "use another method"))
    for i, constraint in enumerate(options.constraints):
        if not isinstance(constraint, Holonomic):
            message = (
                f"the {constraint.kind} constraint {statement(constraint)} is not holonomic; "
                f"{named} holds holonomic constraints h(q, t) = 0 only"
            )
            fix = "use another method (RK45, DOP853, ...): it integrates the multiplier form"
            problems.append(Problem(label(i, constraint), message, fix))
    return problems


def _formulation(options: Options) -> list[Problem]:
    """What the multiplier form and the batch loops cannot take."""
    problems = []
    if options.driver == "simulate_batch":
        if not options.spec.compiled:
            message = f"simulate_batch has no method {options.method!r}"
            problems.append(Problem("method", message, f"methods: {names_where('compiled')}"))
        if options.unilateral:
            message = (
                "simulate_batch does not integrate unilateral constraints (their active sets "
                "change member by member)"
            )
            problems.append(Problem("constraints", message, "call simulate for each member"))
        if options.transitions:
            message = (
                "simulate_batch does not apply transitions (each member's state jumps at its "
                "own times)"
            )
            problems.append(Problem("transitions", message, "call simulate for each member"))
    if options.constraints and not options.inertia and not options.spec.variational:
        message = (
            "simulating constraints with first-order coordinates (no inertia) is not "
            "supported: every coordinate needs a velocity in the state"
        )
        fix = "give every coordinate a kinetic energy term"
        problems.append(Problem("constraints", message, fix))
    return problems


_CHECKS: tuple[Callable[[Options], list[Problem]], ...] = (
    _step_keywords,
    _baumgarte,
    _projections,
    _backend,
    _variational,
    _formulation,
)
