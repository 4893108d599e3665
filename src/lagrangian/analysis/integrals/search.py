"""Constants of the motion beyond cyclic coordinates and the energy: the Noether charges of
Lie point symmetries (:mod:`~lagrangian.analysis.integrals.lie_symmetries`) and the integrals
quadratic in the velocities (:mod:`~lagrangian.analysis.integrals.quadratic`; with ``degree``
>= 3 also cubic ones; where there are angles, also those with coefficients trigonometric in
them, :mod:`~lagrangian.analysis.integrals.trigonometric`), kept when functionally
independent of those already known, within a bound on the size of the search and its time.
Then the integrals that exist only under a relation between the parameters
(:mod:`~lagrangian.analysis.integrals.conditional`: L_z of a 2-D oscillator when k1 = k2),
each with that condition and whether the values given meet it.
With constraints the polynomial integrals are sought on the constrained equations
(:mod:`~lagrangian.analysis.manifold.integrals`).

Independence is the rank of the gradients with respect to (q, q_dot) at random states (on the
constraints, along them): p_x, p_y, L_z and the energy of a free particle in a plane are four
conserved quantities but only three independent ones, so the last of them found adds nothing
and is left out.

>>> import lagrangian as lg
>>> search = first_integrals(lg.examples.planet(), known=())
>>> [q.origin for q in search.found]
['point symmetry', 'point symmetry', 'quadratic first integral']
"""

from __future__ import annotations

import math
import random
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from typing import Any, Generic, TypeVar

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    equations_of,
    numeric_values,
    substitute,
    substitutions,
)
from lagrangian.analysis.evaluation import condition_text
from lagrangian.analysis.integrals.conditional import candidate_relations, relation_holds
from lagrangian.analysis.integrals.function_basis import atoms
from lagrangian.analysis.integrals.lie_symmetries import lie_point_symmetries
from lagrangian.analysis.integrals.quadratic import constant_on_motions, polynomial_integrals
from lagrangian.analysis.integrals.trigonometric import trigonometric_search
from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
from lagrangian.analysis.manifold.integrals import ConstrainedMotion, manifold_integrals
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.solved import mass_matrix_is_regular
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import derivative
from lagrangian.symbolic.probe import RANK_TOLERANCE, evaluate

T = TypeVar("T")

#: The largest number of unknown coefficients a search may have (a basis beyond it is cut
#: to a lower degree, then the search is skipped and the report says so).
MAX_UNKNOWNS = 300
#: Time after which no further stage of the search starts.
SEARCH_SECONDS = 20.0
#: The most coordinates a system may have for the search to run.  Long before it the Lie
#: and polynomial stages' bases have more than MAX_UNKNOWNS unknowns at the lowest degree (a
#: chain: from about 8 links); what is left, the trigonometric and conditional stages and the
#: independence test (the energy, n^2 terms for a chain, differentiated by each of the 2n
#: state variables), grows faster than the system (half a minute at 20 links, unbounded at
#: 100), so beyond it the search is skipped whole and the report says what was not searched.
MAX_SEARCH_COORDINATES = 20


@dataclass(frozen=True)
class ConservedQuantity:
    """A constant of the motion: its name (``p_phi``, ``h``), expression, why it is conserved
    and where it comes from (``origin``: cyclic coordinate, point symmetry, energy, Jacobi
    integral, quadratic or cubic first integral), the parameter condition under which it is
    conserved (``sp.true``: always) and whether the parameter values given (substitutions
    over the defaults) meet that condition (``holds``; False: conserved only when the
    condition is met, not for the values given)."""

    name: str
    expression: sp.Expr
    reason: str
    condition: sp.Basic = sp.true
    origin: str = ""
    holds: bool = True

    @property
    def conditions(self) -> tuple[sp.Basic, ...]:
        """The relations between parameters the condition asks for (``(Eq(k1, k2),)``), all
        to hold at once; empty when the quantity is always conserved."""
        if self.condition == sp.true:
            return ()
        return tuple(sorted(sp.And.make_args(self.condition), key=str))

    @property
    def explicit_time(self) -> bool:
        """True when the quantity depends on t explicitly (conserved, yet a function of t)."""
        return sp.Symbol("t") in self.expression.free_symbols


@dataclass(frozen=True)
class FirstIntegralSearch:
    """The independent quantities found and what was searched (or skipped, and why)."""

    found: tuple[ConservedQuantity, ...]
    searched: tuple[str, ...] = field(default_factory=tuple)


def first_integrals(
    subject: Subject,
    parameters: Values | None = None,
    known: Sequence[sp.Expr] = (),
    degree: int = 2,
    seconds: float = SEARCH_SECONDS,
) -> FirstIntegralSearch:
    """Lie point symmetry charges and quadratic first integrals (with ``degree`` >= 3 also
    cubic ones) functionally independent of ``known`` (and of each other), searched with
    functions of total ``degree`` at most; then those that hold only under a relation
    between the parameters (:mod:`~lagrangian.analysis.integrals.conditional`), each with
    its condition and whether the parameter values given meet it."""
    eom = equations_of(subject)
    n = len(eom.coordinates)
    if n > MAX_SEARCH_COORDINATES:
        return FirstIntegralSearch(
            (),
            (
                "Lie point symmetries, integrals quadratic in the velocities, trigonometric "
                "and conditional integrals: not searched (the system has "
                f"{n} coordinates, more than the {MAX_SEARCH_COORDINATES} the search handles)",
            ),
        )
    deadline = time.monotonic() + seconds
    manifold = constraint_manifold(eom)  # None, or without rows when all are unilateral
    motion = ConstrainedMotion(eom, parameters) if manifold and manifold.size else None
    # built at the first result: the gradients of the known quantities (h of a long chain)
    # cost more than a search that finds nothing
    independent = _Lazy(lambda: _Independence(eom, known, motion))

    def novel(expression: sp.Expr | None = None) -> bool:
        """Whether ``expression`` is independent of the quantities known; without one,
        whether any integral without explicit time could still be."""
        if expression is None:
            return not independent.get().complete
        return independent.get().would_add(expression)

    found: list[ConservedQuantity] = []
    searched: list[str] = []
    stages = _stages(eom, parameters, degree, deadline, degree >= 3, motion, novel=novel)
    for line, results in stages:
        searched.append(line)
        for expression, reason, origin in sorted(results, key=partial(_size, eom)):
            if independent.get().adds(expression):
                name = f"I_{len(found) + 1}"
                found.append(ConservedQuantity(name, expression, reason, origin=origin))
    everything = [*known, *(c.expression for c in found)]
    for quantity, line in _conditional(eom, parameters, everything, degree, deadline):
        if quantity is None:
            searched.append(line)
        else:
            found.append(replace(quantity, name=f"I_{len(found) + 1}"))
    return FirstIntegralSearch(tuple(found), tuple(searched))


Results = list[tuple[sp.Expr, str, str]]
#: A stage: its title, its search at a degree, its number of unknowns at a degree, and why
#: it cannot run here ("" when it can; a function when that depends on the stages before).
Stage = tuple[str, Callable[[int], Results], Callable[[int], int], str | Callable[[], str]]


def _stages(
    eom: EquationsOfMotion,
    parameters: Values | None,
    degree: int,
    deadline: float,
    cubic: bool = False,
    motion: ConstrainedMotion | None = None,
    lie: bool = True,
    novel: Callable[..., bool] | None = None,
) -> Iterator[tuple[str, Results]]:
    """Each stage of the search: what it covered (or why not) and what it found; with
    constraints (``motion``) on the constrained equations, states on the constraints; with
    ``novel`` (the test of independence from what is known) also the integrals
    trigonometric in the angles."""
    n = len(eom.coordinates)
    # each stage: its title, the search at a degree, the unknown functions it solves for
    # (xi, eta_i, f; or one K per velocity monomial and K_0), and why it cannot run here
    singular = "" if mass_matrix_is_regular(eom) else "the mass matrix is singular"
    source = eom.lagrangian
    stages: list[Stage] = []
    if motion is not None:
        singular, source = "", motion.source  # the multiplier form gives the accelerations
        lie = False
        stages.append(
            (
                "Lie point symmetries",
                lambda d: [],
                lambda d: 0,
                "the constraint forces are not in L; the integrals below include the "
                "charges the constraints keep",
            )
        )
    if lie:
        stages.append(
            (
                "Lie point symmetries",
                partial(_charges, eom, parameters),
                partial(_basis_unknowns, eom, n + 2, source),
                "",
            )
        )
    for order, title in ((2, "quadratic"), (3, "cubic"))[: 2 if cubic else 1]:
        stages.append(
            (
                f"integrals {title} in the velocities",
                partial(_polynomial, eom, parameters, order=order, motion=motion),
                partial(_basis_unknowns, eom, math.comb(n + order, order), source),
                singular,  # the accelerations are solved from M q_ddot = forcing
            )
        )
        if order == 2 and novel is not None and motion is None:
            stages += _trigonometric_stage(eom, parameters, novel, singular)
    for title, run, cost, why_not in stages:
        # asked only now: a stage may depend on what the stages before it found
        impossible = why_not() if callable(why_not) else why_not
        if time.monotonic() > deadline:
            impossible = "the time budget was spent"
        if impossible:
            yield f"{title}: not searched ({impossible})", []
            continue
        chosen = _affordable_degree(degree, cost)
        if chosen is None:
            yield f"{title}: not searched (more than {MAX_UNKNOWNS} unknowns)", []
            continue
        where = "" if motion is None else ", on the constrained equations"
        yield f"{title} with coefficients of degree <= {chosen}{where}", run(chosen)


def _conditional(
    eom: EquationsOfMotion,
    parameters: Values | None,
    known: Sequence[sp.Expr],
    degree: int,
    deadline: float,
) -> Iterator[tuple[ConservedQuantity | None, str]]:
    """The integrals quadratic in the velocities under each candidate relation between the
    parameters, independent of ``known`` there and not conserved without the relation; each
    search's line (what it covered) comes first, with no quantity."""
    if time.monotonic() > deadline or not mass_matrix_is_regular(eom) or constraint_manifold(eom):
        return
    width = math.comb(len(eom.coordinates) + 2, 2)
    if _affordable_degree(degree, partial(_basis_unknowns, eom, width, None)) is None:
        return
    given = substitutions(eom, parameters)
    numbers = numeric_values(eom, parameters)
    mass, forcing = (to_sympy(substitute(m, given)) for m in (eom.mass_matrix, eom.forcing))
    for relation in candidate_relations(eom, parameters, deadline):
        when = condition_text(relation)
        tied = {relation.rhs: relation.lhs}
        independent = _Lazy(partial(_Independence, eom, [substitute(k, tied) for k in known]))
        for line, results in _stages(eom, {**given, **tied}, degree, deadline, lie=False):
            yield None, f"{line}, when {when}"
            for expression, _, origin in sorted(results, key=partial(_size, eom)):
                if not independent.get().adds(expression):
                    continue
                if constant_on_motions(expression, eom, mass, forcing):
                    # no condition after all (the search for every value missed it)
                    reason = "dI/dt = 0 on the equations of motion"
                    yield ConservedQuantity("", expression, reason, origin=origin), line
                    continue
                reason = f"dI/dt = 0 on the equations of motion when {when} (else not 0)"
                holds = relation_holds(relation, numbers)
                yield ConservedQuantity("", expression, reason, relation, origin, holds), line


def _basis_unknowns(eom: EquationsOfMotion, width: int, source: sp.Expr | None, degree: int) -> int:
    """The unknowns of ``width`` unknown functions in the basis of ``degree`` built from
    ``source`` (else L), counted before its dependent products are dropped: an upper
    bound."""
    source = eom.lagrangian if source is None else source
    factors = 1 + len(eom.coordinates) + len(atoms(source, eom.coordinates))
    return width * math.comb(factors + degree, degree)


def _affordable_degree(degree: int, cost: Callable[[int], int]) -> int | None:
    """The highest degree <= ``degree`` whose unknowns (``cost``) are within the bound."""
    for d in range(degree, 0, -1):
        if cost(d) <= MAX_UNKNOWNS:
            return d
    return None


def _trigonometric_stage(
    eom: EquationsOfMotion,
    parameters: Values | None,
    novel: Callable[..., bool],
    impossible: str,
) -> list[Stage]:
    """The search with coefficients trigonometric in the angles, when there are angles."""
    search = trigonometric_search(eom, parameters)
    if search is None:
        return []
    angles = ", ".join(map(str, search.angles.all))

    def run(degree: int) -> Results:
        reason = "dI/dt = 0 on the equations of motion (coefficients trigonometric in the angles)"
        return [(i, reason, "quadratic first integral") for i in search.integrals(degree, novel)]

    title = f"integrals quadratic in the velocities, trigonometric in {angles}"

    def why_not() -> str:
        return impossible or ("" if novel() else "the integrals known fix every motion")

    return [(title, run, search.unknowns, why_not)]


def _charges(
    eom: EquationsOfMotion, parameters: Values | None, degree: int
) -> list[tuple[sp.Expr, str, str]]:
    found = []
    for symmetry in lie_point_symmetries(eom, parameters, degree):
        reason = f"Noether: the action is invariant under {symmetry.describe(eom.coordinates)}"
        found.append((symmetry.charge, reason, "point symmetry"))
    return found


def _size(eom: EquationsOfMotion, result: tuple[sp.Expr, str, str]) -> tuple[int, int]:
    """The degree of a first integral in the velocities, then its length: the independence
    test keeps the first of dependent ones (L_z before L_z**2)."""
    expression = result[0]
    try:
        degree = sp.Poly(expression, *eom.velocities).total_degree()
    except sp.PolynomialError:  # a charge of a Lagrangian not polynomial in the velocities
        degree = len(eom.velocities) + 3
    return degree, sp.count_ops(expression)


def _polynomial(
    eom: EquationsOfMotion,
    parameters: Values | None,
    degree: int,
    order: int,
    motion: ConstrainedMotion | None = None,
) -> Results:
    if motion is not None:
        reason = "dI/dt = 0 on the constrained equations of motion (multiplier form)"
        origin = "quadratic first integral" if order == 2 else "cubic first integral"
        return [(i, reason, origin) for i in manifold_integrals(eom, parameters, degree, order)]
    if order == 2:
        reason = "dI/dt = 0 on the equations of motion (a Killing tensor, no point symmetry)"
        origin = "quadratic first integral"
    else:
        reason = "dI/dt = 0 on the equations of motion (cubic in the velocities)"
        origin = "cubic first integral"
    return [(i, reason, origin) for i in polynomial_integrals(eom, parameters, degree, order)]


class _Lazy(Generic[T]):
    """A value made by ``make`` when first asked for."""

    def __init__(self, make: Callable[[], T]) -> None:
        self.make = make
        self.value: T | None = None

    def get(self) -> T:
        if self.value is None:
            self.value = self.make()
        return self.value


class _Independence:
    """Greedy functional independence: the gradients in (q, q_dot) at random states."""

    def __init__(
        self,
        eom: EquationsOfMotion,
        known: Sequence[sp.Expr],
        motion: ConstrainedMotion | None = None,
    ) -> None:
        self.variables = (*eom.coordinates, *eom.velocities)
        self.time = eom.time
        self.timeless = 0  # how many of the rows are of quantities without explicit time
        self.rng = random.Random(17)
        self.points: dict[sp.Symbol, Any] = {}
        self.rows: list[np.ndarray] = []
        self.tangent: np.ndarray | None = None
        if motion is not None:
            self._on_constraints(motion)
        for expression in known:
            self.adds(expression)

    def _on_constraints(self, motion: ConstrainedMotion) -> None:
        """Gradients are compared along the constraints only (the energy and L**2/(2 m R**2)
        of a particle on a sphere differ off it, not on it): at a state on them, with the
        normal directions (gradients of h and of A q_dot + b) projected out."""
        values = {p: sp.Float(self.rng.uniform(0.7, 1.7), 30) for p in motion.parameters}
        state = None
        for _ in range(10):
            state = state or motion.exact_state(self.rng, values)
        if state is None:
            return
        self.points = dict(state)
        rows = []
        for f in motion.normals():
            rows.append([evaluate(derivative(f, s), self.points) for s in self.variables])
        if any(value is None for row in rows for value in row):
            return
        normals = np.array(rows, dtype=float).reshape(len(rows), len(self.variables))
        self.tangent = np.eye(len(self.variables)) - np.linalg.pinv(normals) @ normals

    def _point(self, symbols: set[sp.Symbol]) -> dict[sp.Symbol, float]:
        for s in sorted(symbols - set(self.points), key=str):
            self.points[s] = self.rng.uniform(0.3, 1.3)
        return self.points

    def adds(self, expression: sp.Expr) -> bool:
        """True (and remembered) when ``expression`` is independent of those before."""
        row = self._independent_row(expression)
        if row is None:
            return False
        self.rows.append(row)
        self.timeless += self.time not in to_sympy(expression).free_symbols
        return True

    @property
    def complete(self) -> bool:
        """True when no further integral without explicit time can be independent: 2n - 1
        of them, or 2n of any kind, already fix every motion of the 2n-dimensional state
        space (a pendulum's energy)."""
        room = len(self.variables)
        return self.timeless >= room - 1 or len(self.rows) >= room

    def would_add(self, expression: sp.Expr) -> bool:
        """True when ``expression`` is independent of those before (not remembered)."""
        return self._independent_row(expression) is not None

    def _independent_row(self, expression: sp.Expr) -> np.ndarray | None:
        """The gradient of ``expression`` at the probe point when it is independent of
        those before, else None."""
        expression = to_sympy(expression)
        point = self._point(set(expression.free_symbols) | set(self.variables) | {self.time})
        gradient = [evaluate(derivative(expression, s), point) for s in self.variables]
        if any(g is None for g in gradient):
            return None  # not real and finite at the probe point: no judgement, not kept
        values = np.array(gradient, dtype=float)
        if self.tangent is not None:
            values = self.tangent @ values
        if not np.any(np.abs(values) > RANK_TOLERANCE):
            return None
        stacked = np.array([*self.rows, values])
        scaled = stacked / np.linalg.norm(stacked, axis=1, keepdims=True)
        singular = np.linalg.svd(scaled, compute_uv=False)
        if np.sum(singular > 1e-8 * singular[0]) < len(stacked):
            return None
        return values
