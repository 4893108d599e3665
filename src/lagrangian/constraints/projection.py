"""Projection onto the constraints: a configuration onto the holonomic constraint set, a whole
state (coordinates, then velocities) onto every equality constraint.

Coordinates move by damped Gauss–Newton least squares on h(q, t) = 0,

    q <- q - A(q)^+ h(q),          A = dh/dq, ^+ the pseudo-inverse,

from the given point and, when that does not reach h = 0, from further random starts; a
least-squares minimum with h != 0 from every start means the constraints are inconsistent.
Velocities then take the least-norm correction that satisfies every equality constraint at
velocity level, A q_dot + b = 0:

    q_dot <- q_dot - A^+ (A q_dot + b).

>>> import lagrangian as lg, sympy as sp
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)])
>>> fixed = project_state(ring, {"x": 2.0, "y": 0.0, "x_dot": 1.0, "y_dot": 1.0})
>>> round(fixed[x], 9), round(fixed[sp.Symbol("x_dot")], 9)
(1.0, 0.0)
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.constraints.pfaffian import backend, pfaffian_form
from lagrangian.derivation.backend import to_backend
from lagrangian.errors import ConstraintError, Fix, Problem, raise_if_problems
from lagrangian.model import Holonomic, System, Unilateral, VelocityConstraint, t, velocity
from lagrangian.model.constraints import label, statement
from lagrangian.model.system import require_system
from lagrangian.symbolic.probe import (
    SEED,
    PointFunction,
    Substitution,
    random_values,
    real_values,
    together,
)
from lagrangian.symbolic.symbols import name_of

#: Largest |h| of a configuration that satisfies the constraints.
SATISFIED = 1e-8


@dataclass(frozen=True)
class Projection:
    """The best configuration found, the constraints' values (residuals) there, and their
    Jacobian dh/dq (a row per equation, a column per unknown) there where the iterations
    evaluated it (else None)."""

    values: dict[sp.Symbol, float]
    residuals: tuple[float, ...]
    jacobian: np.ndarray | None = field(default=None, compare=False, repr=False)

    @property
    def satisfied(self) -> bool:
        return all(abs(r) < SATISFIED for r in self.residuals)


def project(
    equations: Sequence[sp.Expr],
    unknowns: Sequence[sp.Symbol],
    start: Mapping[sp.Symbol, float],
    starts: int = 4,
) -> Projection:
    """Least squares h(q) = 0 over ``unknowns`` by damped Gauss–Newton, from ``start`` and
    from further random starts until one satisfies every equation."""
    if not equations:
        return Projection(dict(start), ())
    # converted once, as the constraints' forms convert them (a rolling wheel's contact
    # height: hundreds of operations), and differentiated in SymEngine (SymPy's diff is slow)
    fast = [backend(e) for e in equations]
    at = _Equations(fast, [to_backend(u) for u in unknowns], _arguments(fast, start))
    rng = random.Random(SEED + 1)
    best: Projection | None = None
    for attempt in range(starts):
        values = dict(start)
        if attempt:
            values.update(random_values(unknowns, rng))
        found = _gauss_newton(at, unknowns, values)
        if found is not None and (best is None or _norm(found) < _norm(best)):
            best = found
        if best is not None and best.satisfied:
            break
    return best or Projection(dict(start), tuple(float("nan") for _ in equations))


def _arguments(equations: list[Any], start: Mapping[sp.Symbol, float]) -> list[sp.Symbol]:
    """The symbols of ``start`` that ``equations`` involve, by name: the functions of a point
    take these alone (a bicycle's contact height involves 8 of its 37 coordinates,
    parameters and t, and each argument is converted and passed at every call)."""
    free = {str(s) for s in together(equations).free_symbols}
    return sorted((s for s in start if name_of(s) in free), key=name_of)


class _Equations:
    """h(q) and dh/dq at a point, evaluated together (each None where not finite and real),
    with only the partial derivatives by the unknowns each equation involves taken: a
    chain's rod involves four of its 2n coordinates, and compiling the n x 2n matrix's
    zeros cost seconds at n = 200.  By one :class:`Substitution`, or, from the first point
    SymEngine cannot evaluate them at on (the derivative of |u| SymPy leaves unevaluated),
    each compiled by :class:`PointFunction`."""

    def __init__(self, equations: list[Any], unknowns: list[Any], symbols: list[sp.Symbol]):
        self.shape = (len(equations), len(unknowns))
        self.places: list[int] = []
        slopes = []
        for i, h in enumerate(equations):
            free = h.free_symbols
            for k, u in enumerate(unknowns):
                if u in free:
                    self.places.append(i * len(unknowns) + k)
                    slopes.append(h.diff(u))
        self.parts = (equations, slopes)
        self.symbols = symbols
        self.substituted: Substitution | None = Substitution([*equations, *slopes], symbols)
        self.compiled: tuple[PointFunction, PointFunction] | None = None

    def __call__(
        self, values: Mapping[sp.Symbol, float]
    ) -> tuple[np.ndarray | None, np.ndarray | None]:
        if self.substituted is not None:
            try:
                numbers = self.substituted(values)
            except ValueError:
                self.substituted = None
            else:
                m = self.shape[0]
                return real_values(numbers[:m]), self._jacobian(real_values(numbers[m:]))
        if self.compiled is None:
            self.compiled = (self._compiled(self.parts[0]), self._compiled(self.parts[1]))
        h, slopes = (part(values) for part in self.compiled)
        return (
            None if h is None else h.ravel(),
            self._jacobian(None if slopes is None else slopes.ravel()),
        )

    def _compiled(self, exprs: list[Any]) -> PointFunction:
        return PointFunction(se.DenseMatrix(len(exprs), 1, exprs), self.symbols)

    def _jacobian(self, slopes: np.ndarray | None) -> np.ndarray | None:
        if slopes is None:
            return None
        numbers = np.zeros(self.shape)
        numbers.flat[self.places] = slopes
        return numbers


def _norm(projection: Projection) -> float:
    return float(np.linalg.norm(projection.residuals))


def _gauss_newton(
    at: _Equations, unknowns: Sequence[sp.Symbol], values: dict[sp.Symbol, float]
) -> Projection | None:
    h, jac = at(values)
    if h is None:
        return None
    for _ in range(60):
        if jac is None or np.linalg.norm(h) < 1e-13:
            break
        step = np.linalg.lstsq(jac, -h, rcond=None)[0]
        for damping in (1.0, 0.5, 0.25, 0.1, 0.01):  # accept the first step that helps
            trial = dict(values)
            for s, ds in zip(unknowns, step):
                trial[s] += damping * ds
            h_trial, jac_trial = at(trial)
            if h_trial is not None and np.linalg.norm(h_trial) < np.linalg.norm(h):
                values, h, jac = trial, h_trial, jac_trial
                break
        else:
            break  # no step reduces |h|: a least-squares minimum
    residuals = tuple(float(v) for v in h)
    return Projection({s: float(v) for s, v in values.items()}, residuals, jac)


def numeric_state(system: System, state: Mapping[Any, float]) -> dict[sp.Symbol, float]:
    """Symbols to floats: ``state`` (names or symbols) over the parameters' defaults and
    t = 0; every coordinate and every parameter must get a value."""
    known = {s.name: s for s in (*system.coordinates, *system.velocities, *system.parameters, t)}
    values: dict[sp.Symbol, float] = {t: 0.0}
    values.update({p: float(v) for p, v in system.parameters.items() if v is not None})
    problems = []
    for key, value in state.items():
        symbol = known.get(name_of(key))
        if symbol is None:
            problems.append(
                Problem(
                    f"state.{key}",
                    f"{key!s} is not a coordinate, velocity, parameter or t",
                    "give values by coordinate, NAME_dot, parameter name or t",
                )
            )
        else:
            values[symbol] = float(value)
    for symbol in (*system.coordinates, *system.parameters):
        if symbol not in values:
            problems.append(
                Problem(f"state.{symbol}", "has no value", f"give {symbol} a value in the state")
            )
    raise_if_problems(problems, "The state is incomplete or unknown", ConstraintError)
    return values


def project_state(system: System, state: Mapping[Any, float]) -> dict[sp.Symbol, float]:
    """``state`` moved onto the constraints: coordinates onto the holonomic (and active
    unilateral, g = 0 when g < 0) constraints, then velocities onto A q_dot + b = 0."""
    require_system(system, "project_state(system, state)")
    values = numeric_state(system, state)
    for v in system.velocities:
        values.setdefault(v, 0.0)
    equations = [
        c.expression
        for c in system.constraints
        if isinstance(c, Holonomic)
        or (isinstance(c, Unilateral) and _value(c.expression, values) < 0)
    ]
    found = project(equations, system.coordinates, values, starts=1)
    if not found.satisfied:
        raise ConstraintError(
            "No configuration near this state satisfies the holonomic constraints "
            f"(residuals {found.residuals}); check the constraints with classify()."
        )
    values = found.values
    rows = [c for c in system.constraints if not isinstance(c, Unilateral)]
    if rows:
        forms = [pfaffian_form(c, system.coordinates) for c in rows]
        symbols = sorted(values, key=str)
        a = PointFunction(sp.Matrix([list(f.coefficients) for f in forms]), symbols)(values)
        b = PointFunction(sp.Matrix([f.time_coefficient for f in forms]), symbols)(values)
        if a is None or b is None:
            raise ConstraintError("The constraint Jacobian is not defined at this state.")
        q_dot = np.array([values[velocity(q)] for q in system.coordinates])
        q_dot -= np.linalg.pinv(a) @ (a @ q_dot + b.ravel())
        values.update({velocity(q): float(v) for q, v in zip(system.coordinates, q_dot)})
    return values


def _value(expr: sp.Expr, values: Mapping[sp.Symbol, float]) -> float:
    number = PointFunction(sp.Matrix([expr]), sorted(values, key=str))(values)
    return float("nan") if number is None else float(number[0, 0])


@dataclass(frozen=True)
class Violation:
    """A constraint that a state does not satisfy: which one, at what level (``position``:
    h(q, t) or g(q, t) < 0; ``velocity``: a.q_dot + b) and by how much."""

    index: int
    label: str
    statement: str
    level: str
    residual: float

    def problem(self, fix: str | Fix) -> Problem:
        """The violation as a Problem with ``fix`` in the words of the caller's interface."""
        what = "h(q, t)" if self.level == "position" else "a.q_dot + b"
        return Problem(
            self.label,
            f"{self.statement} is violated at {self.level} level "
            f"({what} = {self.residual:.6g} at this state)",
            fix,
        )


def violations(
    system: System, state: Mapping[Any, float], tolerance: float = SATISFIED
) -> tuple[Violation, ...]:
    """Every equality constraint that ``state`` misses by more than ``tolerance`` (a
    holonomic one at position level, h(q, t) = 0, then at velocity level, a.q_dot + b = 0;
    a velocity constraint at velocity level), and every unilateral g >= 0 that it
    penetrates.  ``state`` as for :func:`numeric_state`; unlisted velocities are 0.

    >>> import lagrangian as lg, sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)])
    >>> [(v.level, v.residual) for v in violations(ring, {"x": 2.0, "y": 0.0})]
    [('position', 3.0)]
    """
    values = numeric_state(system, state)
    for v in system.velocities:
        values.setdefault(v, 0.0)
    found: list[Violation] = []
    for index, constraint in enumerate(system.constraints):
        where = (index, label(index, constraint), statement(constraint))
        if not isinstance(constraint, VelocityConstraint):
            residual = _value(constraint.expression, values)
            penetrates = isinstance(constraint, Unilateral) and not residual >= -tolerance
            if penetrates or (isinstance(constraint, Holonomic) and not abs(residual) <= tolerance):
                found.append(Violation(*where, "position", residual))
                continue
        if isinstance(constraint, Unilateral):
            continue  # an inequality: any velocity may leave the contact
        rate = _value(pfaffian_form(constraint, system.coordinates).velocity_expression, values)
        if not abs(rate) <= tolerance:
            found.append(Violation(*where, "velocity", rate))
    return tuple(found)
