"""Lie point symmetries of the action and their Noether charges, divergence symmetries and
time-dependent ones included (Noether's theorem with the Bessel-Hagen divergence term).

A generator X = xi(t, q) d/dt + sum_i eta_i(t, q) d/dq_i is a symmetry of the action when

    xi dL/dt + sum_i eta_i dL/dq_i + sum_i (D eta_i - q_dot_i D xi) dL/dq_dot_i + L D xi
        + sum_i Q_i (eta_i - q_dot_i xi) = D f

for some f(t, q), D the total time derivative and Q_i the forces that are not in L (applied
and dissipative; Djukic and Vujanovic's extension of Noether's theorem to them).  Then

    I = sum_i p_i (eta_i - q_dot_i xi) + L xi - f

is constant on every motion (Goldstein §13.7; Olver, *Applications of Lie Groups to
Differential Equations*, Theorem 4.29 and §5.3 on divergence symmetries).  xi, eta and f are
sought in a :mod:`~lagrangian.analysis.integrals.function_basis`; the condition is linear in their
coefficients, so sampling it at random (t, q, q_dot) gives a linear system whose null space
(:mod:`~lagrangian.analysis.integrals.null_vectors`) holds every symmetry in the basis.  Each one
found
is verified symbolically before it is reported.

>>> import lagrangian as lg
>>> [str(s.charge) for s in lie_point_symmetries(lg.examples.simple_pendulum())]
['l*m*(g*cos(theta) - l*theta_dot**2/2)']
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.integrals.function_basis import FunctionBasis, function_basis
from lagrangian.analysis.integrals.null_vectors import exact_null_vectors
from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.nonsmooth import derivative
from lagrangian.symbolic.probe import is_small, is_zero
from lagrangian.symbolic.symbols import time_derivative

#: Random samples per unknown coefficient (the system is over-determined by this factor).
OVERSAMPLING = 2


@dataclass(frozen=True)
class LieSymmetry:
    """A point symmetry xi d/dt + sum eta_i d/dq_i of the action, its divergence term f and
    its conserved charge."""

    time: sp.Expr
    coordinates: sp.ImmutableMatrix
    divergence: sp.Expr
    charge: sp.Expr

    def describe(self, coordinates: Sequence[sp.Symbol]) -> str:
        """The generator as text, ``X = t*d/dx`` (and its divergence term when not 0)."""
        parts = [] if self.time == 0 else [f"({self.time})*d/dt"]
        parts += [f"({e})*d/d{q}" for q, e in zip(coordinates, self.coordinates) if e != 0]
        text = "X = " + " + ".join(p.replace("(1)*", "") for p in parts)
        return text + (f", with divergence term f = {self.divergence}" if self.divergence else "")


@dataclass(frozen=True)
class SearchProblem:
    """The symbolic pieces of the search, and NumPy functions of (t, q, q_dot, p)."""

    eom: EquationsOfMotion
    lagrangian: sp.Expr
    forces: tuple[sp.Expr, ...]
    parameters: tuple[sp.Symbol, ...]


def search_problem(eom: EquationsOfMotion, parameters: Values | None) -> SearchProblem:
    """L and the forces outside it with the given substitutions made."""
    values = substitutions(eom, parameters)
    lagrangian = to_sympy(substitute(eom.lagrangian, values))
    forces = tuple(
        to_sympy(substitute(q + d, values))
        for q, d in zip(eom.generalized_forces, eom.dissipation_forces)
    )
    state = {eom.time, *eom.coordinates, *eom.velocities}
    free = set().union(lagrangian.free_symbols, *(f.free_symbols for f in forces)) - state
    return SearchProblem(eom, lagrangian, forces, tuple(sorted(free, key=str)))


def sample_count(unknowns: int) -> int:
    """The samples a search with ``unknowns`` takes: ``OVERSAMPLING`` per unknown and some
    more."""
    return OVERSAMPLING * unknowns + 10


def samples(
    basis: FunctionBasis, unknowns: int, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Random (t, q) rows and q_dot rows, :func:`sample_count` of them."""
    rows = sample_count(unknowns)
    points = basis.random_points(rows, rng)
    return points, rng.uniform(-2.0, 2.0, size=(rows, points.shape[1] - 1))


def numeric(problem: SearchProblem, exprs: Sequence[sp.Expr]) -> object:
    """``exprs`` as one NumPy function of (t, q..., q_dot..., parameters...)."""
    eom = problem.eom
    arguments = (eom.time, *eom.coordinates, *eom.velocities, *problem.parameters)
    return sp.lambdify(arguments, list(exprs), modules="numpy")


def evaluated(function: object, points: np.ndarray, rates: np.ndarray, values: list) -> np.ndarray:
    """``function`` (from :func:`numeric`) on the sample rows, shape (rows, outputs)."""
    out = function(*points.T, *rates.T, *values)  # type: ignore[operator]
    rows = points.shape[0]
    return np.column_stack([np.broadcast_to(np.asarray(o, dtype=float), (rows,)) for o in out])


def total_derivatives(basis: FunctionBasis, points: np.ndarray, rates: np.ndarray) -> tuple:
    """phi_k and D phi_k = d phi/dt + sum_j d phi/dq_j q_dot_j on the samples."""
    values, gradients = basis.values_and_gradients(points)
    rate = gradients[:, :, 0] + np.einsum("rkj,rj->rk", gradients[:, :, 1:], rates)
    return values, rate


def lie_point_symmetries(
    subject: Subject, parameters: Values | None = None, degree: int = 2
) -> tuple[LieSymmetry, ...]:
    """The point symmetries of the action whose xi, eta and f lie in the function basis of
    total degree ``degree`` (see the module docstring), each verified symbolically, with
    their Noether charges."""
    eom = equations_of(subject)
    problem = search_problem(eom, parameters)
    q, v = eom.coordinates, eom.velocities
    n = len(q)  # at least 1: a System has coordinates
    lagrangian = problem.lagrangian
    pieces = [
        lagrangian,
        derivative(lagrangian, eom.time),
        *(derivative(lagrangian, s) for s in q),
        *(derivative(lagrangian, s) for s in v),
        *problem.forces,
    ]
    function = numeric(problem, pieces)
    basis = function_basis(lagrangian, q, degree)
    k = len(basis.functions)
    unknowns = (n + 1) * k + k - 1
    points, rates = samples(basis, unknowns, np.random.default_rng(11))
    phi, d_phi = total_derivatives(basis, points, rates)

    def sampled(values: dict[sp.Symbol, float]) -> np.ndarray:
        table = evaluated(function, points, rates, [values[p] for p in problem.parameters])
        lag, lag_t = table[:, 0], table[:, 1]
        lag_q, lag_v, force = (
            table[:, 2 : 2 + n],
            table[:, 2 + n : 2 + 2 * n],
            table[:, 2 + 2 * n :],
        )
        momentum_rate = np.einsum("ri,ri->r", lag_v, rates)
        power = np.einsum("ri,ri->r", force, rates)
        columns = [
            lag_t[:, None] * phi + (lag - momentum_rate)[:, None] * d_phi - power[:, None] * phi
        ]
        for i in range(n):
            columns.append((lag_q[:, i] + force[:, i])[:, None] * phi + lag_v[:, i, None] * d_phi)
        columns.append(-d_phi[:, 1:])  # f: a constant changes nothing
        return np.column_stack(columns)

    rng = random.Random(5)
    generic = {p: rng.uniform(0.7, 1.7) for p in problem.parameters}
    found = []
    for vector in exact_null_vectors(sampled, problem.parameters, generic):
        symmetry = _symmetry(problem, basis, vector)
        if symmetry is not None:
            found.append(symmetry)
    return tuple(found)


def _combination(coefficients: Sequence[sp.Expr], functions: Sequence[sp.Expr]) -> sp.Expr:
    return sp.Add(*(c * f for c, f in zip(coefficients, functions) if c != 0))


def _symmetry(
    problem: SearchProblem, basis: FunctionBasis, vector: list[sp.Expr]
) -> LieSymmetry | None:
    """The symmetry of a null vector, or None when the symbolic check refutes it."""
    eom = problem.eom
    q, v = eom.coordinates, eom.velocities
    k, n = len(basis.functions), len(q)
    xi = _combination(vector[:k], basis.functions)
    eta = [_combination(vector[(i + 1) * k : (i + 2) * k], basis.functions) for i in range(n)]
    f = _combination(vector[(n + 1) * k :], basis.functions[1:])
    lagrangian = problem.lagrangian

    def rate(expr: sp.Expr) -> sp.Expr:
        return time_derivative(expr, q)

    d_xi = rate(xi)
    condition = xi * derivative(lagrangian, eom.time) + lagrangian * d_xi - rate(f)
    for i in range(n):
        moved = eta[i] - v[i] * xi
        condition += eta[i] * derivative(lagrangian, q[i]) + problem.forces[i] * moved
        condition += (rate(eta[i]) - v[i] * d_xi) * derivative(lagrangian, v[i])
    if not is_zero(sp.expand(condition)):
        return None
    momenta = [derivative(lagrangian, s) for s in v]
    charge = sum((p * (e - s * xi) for p, e, s in zip(momenta, eta, v)), sp.Integer(0))
    charge = charge + lagrangian * xi - f
    if is_zero(charge):
        return None
    return LieSymmetry(xi, sp.ImmutableMatrix(eta), f, readable(charge, problem.parameters))


def readable(
    expr: sp.Expr, parameters: Sequence[sp.Symbol] = (), simplified: bool = True
) -> sp.Expr:
    """``expr`` in its shortest form among expanded, factored and (when small and
    ``simplified``) simplified, after clearing the parameters from its denominators (a
    constant multiple of a conserved quantity is conserved: k*x/(m*r) + ... reads better as
    k*x/r + m*...)."""
    expanded = sp.expand(expr.replace(sp.cot, lambda u: sp.cos(u) / sp.sin(u)))
    terms = sp.Add.make_args(expanded)
    for p in parameters:
        lowest = sp.Integer(0) + min(term.as_powers_dict().get(p, 0) for term in terms)
        if lowest.is_number and lowest < 0:
            expanded = sp.expand(expanded * p ** (-lowest))
            terms = sp.Add.make_args(expanded)
    forms = [expanded, sp.factor_terms(expanded)]
    if simplified and is_small(expanded):
        forms.append(sp.factor_terms(sp.expand(sp.simplify(expanded))))
    return min(forms, key=sp.count_ops)
