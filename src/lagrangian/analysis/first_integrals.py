"""Constants of the motion beyond cyclic coordinates and the energy: the Noether charges of
Lie point symmetries (:mod:`~lagrangian.analysis.lie_symmetries`) and the integrals quadratic
in the velocities (:mod:`~lagrangian.analysis.quadratic_integrals`), kept when functionally
independent of those already known, within a bound on the size of the search and its time.

Independence is the rank of the gradients with respect to (q, q_dot) at random states: p_x,
p_y, L_z and the energy of a free particle in a plane are four conserved quantities but only
three independent ones, so the last of them found adds nothing and is left out.

>>> import lagrangian as lg
>>> search = first_integrals(lg.examples.planet(), known=())
>>> [q.origin for q in search.found]
['point symmetry', 'point symmetry']
"""

from __future__ import annotations

import math
import random
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of
from lagrangian.analysis.function_basis import atoms
from lagrangian.analysis.lie_symmetries import lie_point_symmetries
from lagrangian.analysis.quadratic_integrals import quadratic_integrals
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.solved import mass_matrix_is_regular
from lagrangian.model.conversion import to_sympy
from lagrangian.model.nonsmooth import derivative
from lagrangian.model.probe import RANK_TOLERANCE, evaluate

#: The largest number of unknown coefficients a search may have (a basis beyond it is cut
#: to a lower degree, then the search is skipped and the report says so).
MAX_UNKNOWNS = 300
#: Time after which no further stage of the search starts.
SEARCH_SECONDS = 20.0


@dataclass(frozen=True)
class ConservedQuantity:
    """A constant of the motion: its name (``p_phi``, ``h``), expression, why it is conserved
    and where it comes from (``origin``: cyclic coordinate, point symmetry, energy, Jacobi
    integral, quadratic first integral), and the parameter condition for it."""

    name: str
    expression: sp.Expr
    reason: str
    condition: sp.Basic = sp.true
    origin: str = ""

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
    """Lie point symmetry charges and quadratic first integrals functionally independent of
    ``known`` (and of each other), searched with functions of total ``degree`` at most."""
    eom = equations_of(subject)
    start = time.monotonic()
    independent = _Independence(eom, known)
    found: list[ConservedQuantity] = []
    searched: list[str] = []
    n = len(eom.coordinates)
    # each stage: its title, the search at a degree, the unknown functions it solves for
    # (xi, eta_i, f; or K_ij, K_i, K_0), and why it cannot run here (or "")
    singular = "" if mass_matrix_is_regular(eom) else "the mass matrix is singular"
    stages: list[tuple[str, Callable[[int], list[tuple[sp.Expr, str, str]]], int, str]] = [
        ("Lie point symmetries", lambda d: _charges(eom, parameters, d), n + 2, ""),
        (
            "integrals quadratic in the velocities",
            lambda d: _quadratic(eom, parameters, d),
            (n + 1) * (n + 2) // 2,
            singular,  # the accelerations are solved from M q_ddot = forcing
        ),
    ]
    for title, run, width, impossible in stages:
        if time.monotonic() - start > seconds:
            impossible = f"the {seconds:g} s budget was spent"
        if impossible:
            searched.append(f"{title}: not searched ({impossible})")
            continue
        chosen = _affordable_degree(eom, degree, width)
        if chosen is None:
            searched.append(f"{title}: not searched (more than {MAX_UNKNOWNS} unknowns)")
            continue
        searched.append(f"{title} with coefficients of degree <= {chosen}")
        for expression, reason, origin in run(chosen):
            if independent.adds(expression):
                name = f"I_{len(found) + 1}"
                found.append(ConservedQuantity(name, expression, reason, origin=origin))
    return FirstIntegralSearch(tuple(found), tuple(searched))


def _affordable_degree(eom: EquationsOfMotion, degree: int, width: int) -> int | None:
    """The highest degree <= ``degree`` whose basis keeps the unknowns within the bound (the
    basis counted before its dependent products are dropped: an upper bound)."""
    factors = 1 + len(eom.coordinates) + len(atoms(eom.lagrangian, eom.coordinates))
    for d in range(degree, 0, -1):
        if width * math.comb(factors + d, d) <= MAX_UNKNOWNS:
            return d
    return None


def _charges(
    eom: EquationsOfMotion, parameters: Values | None, degree: int
) -> list[tuple[sp.Expr, str, str]]:
    found = []
    for symmetry in lie_point_symmetries(eom, parameters, degree):
        reason = f"Noether: the action is invariant under {symmetry.describe(eom.coordinates)}"
        found.append((symmetry.charge, reason, "point symmetry"))
    return found


def _quadratic(
    eom: EquationsOfMotion, parameters: Values | None, degree: int
) -> list[tuple[sp.Expr, str, str]]:
    reason = "dI/dt = 0 on the equations of motion (a Killing tensor, no point symmetry)"
    return [
        (i, reason, "quadratic first integral")
        for i in quadratic_integrals(eom, parameters, degree)
    ]


class _Independence:
    """Greedy functional independence: the gradients in (q, q_dot) at random states."""

    def __init__(self, eom: EquationsOfMotion, known: Sequence[sp.Expr]) -> None:
        self.variables = (*eom.coordinates, *eom.velocities)
        self.time = eom.time
        self.rng = random.Random(17)
        self.points: dict[sp.Symbol, float] = {}
        self.rows: list[np.ndarray] = []
        for expression in known:
            self.adds(expression)

    def _point(self, symbols: set[sp.Symbol]) -> dict[sp.Symbol, float]:
        for s in sorted(symbols - set(self.points), key=str):
            self.points[s] = self.rng.uniform(0.3, 1.3)
        return self.points

    def adds(self, expression: sp.Expr) -> bool:
        """True (and remembered) when ``expression`` is independent of those before."""
        expression = to_sympy(expression)
        point = self._point(set(expression.free_symbols) | set(self.variables) | {self.time})
        gradient = [evaluate(derivative(expression, s), point) for s in self.variables]
        if any(g is None for g in gradient):
            return False  # not real and finite at the probe point: no judgement, not kept
        values = np.array(gradient, dtype=float)
        if not np.any(np.abs(values) > RANK_TOLERANCE):
            return False
        stacked = np.array([*self.rows, values])
        scaled = stacked / np.linalg.norm(stacked, axis=1, keepdims=True)
        singular = np.linalg.svd(scaled, compute_uv=False)
        if np.sum(singular > 1e-8 * singular[0]) < len(stacked):
            return False
        self.rows.append(values)
        return True
