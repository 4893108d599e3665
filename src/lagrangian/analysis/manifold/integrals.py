"""First integrals of a constrained system on its constraints: I polynomial in the velocities
with dI/dt = 0 on the motions of the multiplier form

    M q_ddot - A^T lambda = forcing,    A q_ddot = gamma,

at states on the constraints (h(q, t) = 0 for the holonomic ones, A q_dot + b = 0 for all;
:mod:`lagrangian.analysis.manifold.constraint_manifold`).  The coefficients are sought in the
function basis of L
(:mod:`~lagrangian.analysis.integrals.function_basis`) as in
:mod:`~lagrangian.analysis.integrals.quadratic`, only the samples differ: random points are
moved onto the constraints (Newton steps on h, the velocities projected onto A q_dot + b = 0)
and the accelerations solved from the multiplier form there.  This works for non-holonomic
constraints too, and for holonomic ones that cannot be solved for some coordinates; the
integrals come out in the system's own coordinates (the three components of the angular
momentum of a particle on a sphere written in x, y, z).

Functions that are constant on the constraints (x**2 + y**2 + z**2 on that sphere, or
x x_dot + y y_dot + z z_dot) satisfy dI/dt = 0 there trivially; they are recognized by their
values at random states on the constraints and left out.  Each integral kept is verified at
random states on the constraints to 30 digits.

>>> import lagrangian as lg
>>> manifold_integrals(lg.examples.rolling_disc(), degree=0)
()
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.integrals.function_basis import function_basis, independent_columns
from lagrangian.analysis.integrals.lie_symmetries import (
    SearchProblem,
    evaluated,
    numeric,
    readable,
    samples,
    search_problem,
    total_derivatives,
)
from lagrangian.analysis.integrals.null_vectors import exact_null_vectors
from lagrangian.analysis.integrals.quadratic import (
    Ansatz,
    integral_of,
    velocity_columns,
    velocity_monomials,
)
from lagrangian.analysis.manifold.constraint_manifold import constraint_manifold
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero

#: Newton steps moving a sample onto the holonomic constraints, and the residual accepted.
NEWTON_STEPS = 40
ON_CONSTRAINTS = 1e-10
#: Random states at which each integral is checked, their precision and the tolerance.
CHECKS = 3
DIGITS = 30
TOLERANCE = sp.Float(1e-18)


class ConstrainedMotion:
    """The multiplier form of a constrained system, symbolic and as NumPy functions of
    (t, q, q_dot, parameters): states moved onto the constraints and the accelerations
    there, in floats on many samples or to 30 digits at one state."""

    def __init__(self, eom: EquationsOfMotion, parameters: Values | None) -> None:
        manifold = constraint_manifold(eom)
        if manifold is None:
            raise AnalysisError("the system has no constraints: use first_integrals")
        values = substitutions(eom, parameters)

        def given(expr: sp.Basic) -> sp.Matrix:
            return sp.Matrix(to_sympy(substitute(sp.Matrix(expr), values)))

        self.eom = eom
        q = eom.coordinates
        levels = manifold.position_equations
        self.levels = given(sp.Matrix(len(levels), 1, list(levels)))
        self.level_jacobian = self.levels.jacobian(q) if levels else sp.zeros(0, len(q))
        self.jacobian, self.rates = given(manifold.jacobian), given(manifold.rates)
        self.mass, self.forcing = given(eom.mass_matrix), given(eom.forcing)
        self.gamma = given(manifold.gamma)
        pieces = [
            self.levels,
            self.level_jacobian,
            self.jacobian,
            self.rates,
            self.mass,
            self.forcing,
            self.gamma,
        ]
        problem = search_problem(eom, parameters)
        state = {eom.time, *q, *eom.velocities}
        free = set(problem.parameters).union(*(m.free_symbols for m in pieces)) - state
        self.problem: SearchProblem = replace(problem, parameters=tuple(sorted(free, key=str)))
        self.position = numeric(self.problem, [*self.levels, *self.level_jacobian])
        self.velocity = numeric(self.problem, [*self.jacobian, *self.rates])
        self.dynamics = numeric(self.problem, [*self.mass, *self.forcing, *self.gamma])

    @property
    def parameters(self) -> tuple[sp.Symbol, ...]:
        """The parameters left as symbols in L, the forces and the constraints."""
        return self.problem.parameters

    @property
    def source(self) -> sp.Expr:
        """An expression holding the building blocks of L and of the constraints, from which
        the function basis is built (the sin(phi) of a knife edge's constraint is in no L)."""
        pieces = [*self.levels, *self.jacobian, *self.rates]
        return self.problem.lagrangian + sp.Add(*(sp.Dummy() * p for p in pieces))

    def normals(self) -> list[sp.Expr]:
        """Functions of the state whose zero set is the states on the constraints: each h_j
        and each row of A q_dot + b."""
        moving = self.jacobian * sp.Matrix(self.eom.velocities) + self.rates
        return [*self.levels, *moving]

    def states(
        self, points: np.ndarray, rates: np.ndarray, values: Sequence[float]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The samples (rows of (t, q) and of q_dot) moved onto the constraints, and the
        accelerations there; rows that do not reach the constraints are dropped."""
        n, k, rows = len(self.eom.coordinates), self.levels.rows, self.jacobian.rows
        points = points.copy()
        keep = np.ones(len(points), dtype=bool)
        with np.errstate(all="ignore"):
            for _ in range(NEWTON_STEPS if k else 0):
                table = evaluated(self.position, points, rates, list(values))
                residual = table[:, :k]
                jacobian = table[:, k:].reshape(-1, k, n)
                points[:, 1:] -= (np.linalg.pinv(jacobian) @ residual[:, :, None])[:, :, 0]
            if k:
                residual = evaluated(self.position, points, rates, list(values))[:, :k]
                keep &= np.all(np.abs(residual) < ON_CONSTRAINTS, axis=1)
            table = evaluated(self.velocity, points, rates, list(values))
            a_matrix = table[:, : rows * n].reshape(-1, rows, n)
            b = table[:, rows * n :]
            excess = (a_matrix @ rates[:, :, None])[:, :, 0] + b
            rates = rates - (np.linalg.pinv(a_matrix) @ excess[:, :, None])[:, :, 0]
            table = evaluated(self.dynamics, points, rates, list(values))
            mass = table[:, : n * n].reshape(-1, n, n)
            forcing = table[:, n * n : n * n + n]
            gamma = table[:, n * n + n :]
            system = np.zeros((len(points), n + rows, n + rows))
            system[:, :n, :n] = mass
            system[:, :n, n:] = -np.transpose(a_matrix, (0, 2, 1))
            system[:, n:, :n] = a_matrix
            keep &= np.all(np.isfinite(system), axis=(1, 2)) & np.all(np.isfinite(points), axis=1)
            keep &= np.abs(np.linalg.det(np.where(np.isfinite(system), system, 0.0))) > 1e-12
            right = np.concatenate([forcing, gamma], axis=1)
            system[~keep] = np.eye(n + rows)
            right[~keep] = 0.0
            solved = np.linalg.solve(system, right[:, :, None])[:, :n, 0]
        return points[keep], rates[keep], solved[keep]

    def exact_state(
        self, rng: random.Random, values: dict[sp.Symbol, sp.Expr]
    ) -> dict[sp.Symbol, sp.Expr] | None:
        """A random state on the constraints to ``DIGITS`` digits at the parameter
        ``values``, with the accelerations there (keyed by the acceleration symbols); None
        when the Newton steps do not reach the constraints."""
        eom = self.eom
        q, v = eom.coordinates, eom.velocities
        point: dict[sp.Symbol, sp.Expr] = dict(values)
        point.update({s: sp.Float(rng.uniform(0.3, 1.3), DIGITS) for s in (eom.time, *q)})
        point.update({s: sp.Float(rng.uniform(-1.5, 1.5), DIGITS) for s in v})
        for _ in range(NEWTON_STEPS if self.levels.rows else 0):
            residual = self.levels.xreplace(point).evalf(DIGITS)
            jacobian = self.level_jacobian.xreplace(point).evalf(DIGITS)
            step = jacobian.T * (jacobian * jacobian.T).LUsolve(residual)
            point.update({s: sp.Float(point[s] - step[i], DIGITS) for i, s in enumerate(q)})
            if max((abs(r) for r in residual), default=0) < 1e-25:
                break
        if any(abs(r) > 1e-20 for r in self.levels.xreplace(point).evalf(DIGITS)):
            return None
        a_matrix = self.jacobian.xreplace(point).evalf(DIGITS)
        excess = a_matrix * sp.Matrix([point[s] for s in v]) + self.rates.xreplace(point)
        if a_matrix.rows:
            step = a_matrix.T * (a_matrix * a_matrix.T).LUsolve(excess.evalf(DIGITS))
            point.update({s: sp.Float(point[s] - step[i], DIGITS) for i, s in enumerate(v)})
        n = len(q)
        system = sp.Matrix.vstack(
            sp.Matrix.hstack(self.mass, -self.jacobian.T),
            sp.Matrix.hstack(self.jacobian, sp.zeros(self.jacobian.rows)),
        )
        right = sp.Matrix.vstack(self.forcing, self.gamma)
        solved = system.xreplace(point).evalf(DIGITS).LUsolve(right.xreplace(point).evalf(DIGITS))
        point.update({acceleration: solved[i] for i, acceleration in enumerate(eom.accelerations)})
        return point if len(solved) == n + self.jacobian.rows else None


def manifold_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 2, order: int = 2
) -> tuple[sp.Expr, ...]:
    """Every first integral of degree <= ``order`` in the velocities, with coefficients in
    the function basis of total ``degree``, conserved on the constrained motions and not
    constant on the constraints alone, each verified to 30 digits (module docstring)."""
    eom = equations_of(subject)
    motion = ConstrainedMotion(eom, parameters)
    q, v = eom.coordinates, eom.velocities
    basis = function_basis(motion.source, q, degree)
    exponents = velocity_monomials(len(q), order)
    ansatz = Ansatz.uniform(exponents, basis)
    unknowns = ansatz.unknowns
    start, start_rates = samples(basis, unknowns, np.random.default_rng(13))

    def columns(parameter_values: dict[sp.Symbol, float]) -> tuple[np.ndarray, np.ndarray]:
        """dI/dt of each term of the ansatz at the samples, and the term itself there."""
        values = [parameter_values[p] for p in motion.parameters]
        points, rates, accelerations = motion.states(start, start_rates, values)
        phi, d_phi = total_derivatives(basis, points, rates)
        products = np.column_stack([np.prod(rates**powers, axis=1) for powers in exponents])
        terms = np.column_stack(
            [
                (phi[:, :, None] * products[:, None, :])
                .transpose(0, 2, 1)
                .reshape(len(points), -1),
                phi[:, 1:],
            ]
        )
        return velocity_columns(ansatz, phi, d_phi, rates, accelerations), terms

    rng = random.Random(5)
    generic = {p: rng.uniform(0.7, 1.7) for p in motion.parameters}
    # terms that are combinations of others on the constraints are left out, so that no
    # combination of those kept vanishes there (the ansatz has no trivial solutions)
    kept = independent_columns(columns(generic)[1])

    def sampled(parameter_values: dict[sp.Symbol, float]) -> np.ndarray:
        return columns(parameter_values)[0][:, kept]

    monomials = [sp.Mul(*(s**e for s, e in zip(v, powers))) for powers in exponents]
    checks = _check_states(motion)
    found = []
    for reduced in exact_null_vectors(sampled, motion.parameters, generic):
        vector: list[sp.Expr] = [sp.Integer(0)] * unknowns
        for j, c in zip(kept, reduced):
            vector[j] = c
        integral = integral_of(vector, basis, monomials, ansatz)
        if not is_zero(integral) and conserved_on_constraints(integral, eom, checks):
            found.append(readable(integral, motion.parameters))
    return tuple(found)


def _check_states(motion: ConstrainedMotion) -> list[dict[sp.Symbol, sp.Expr]]:
    rng = random.Random(23)
    values = {p: sp.Float(rng.uniform(0.7, 1.7), DIGITS) for p in motion.parameters}
    states = []
    for _ in range(4 * CHECKS):
        state = motion.exact_state(rng, values)
        if state is not None:
            states.append(state)
        if len(states) == CHECKS:
            break
    return states


def conserved_on_constraints(
    integral: sp.Expr, eom: EquationsOfMotion, states: Sequence[dict[sp.Symbol, sp.Expr]]
) -> bool:
    """dI/dt = 0 at each of ``states`` (on the constraints, with their accelerations) to
    ``TOLERANCE``, and I not the same at all of them (a function constant on the
    constraints alone is no integral of the motion)."""
    if len(states) < 2:
        return False
    q, v, a = eom.coordinates, eom.velocities, eom.accelerations
    rate = integral.diff(eom.time)
    rate += sum((integral.diff(s) * r for s, r in zip(q, v)), sp.Integer(0))
    rate += sum((integral.diff(s) * r for s, r in zip(v, a)), sp.Integer(0))
    values = []
    for state in states:
        value = sp.N(rate.xreplace(state), DIGITS)
        size = sp.N(integral.xreplace(state), DIGITS)
        if not value.is_number or not size.is_number:
            return False
        if abs(value) > TOLERANCE * (1 + abs(size)):
            return False
        values.append(size)
    spread = max(abs(x - values[0]) for x in values)
    return bool(spread > 1e-12 * (1 + max(abs(x) for x in values)))
