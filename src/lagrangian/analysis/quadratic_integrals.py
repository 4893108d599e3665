"""First integrals quadratic in the velocities, whether or not a point symmetry gives them:

    I = sum_{i<=j} K_ij(t, q) q_dot_i q_dot_j + sum_i K_i(t, q) q_dot_i + K_0(t, q),

with dI/dt = 0 on the equations of motion.  The K are sought in the
:mod:`~lagrangian.analysis.function_basis` of the Lagrangian; dI/dt is linear in their
coefficients, so the null space of its samples (:mod:`~lagrangian.analysis.null_vectors`)
holds every such integral: the energy, the squares and products of momenta, and those of
hidden symmetries — the Laplace–Runge–Lenz vector of the Kepler problem (Goldstein §3.9), the
separate energies of an anisotropic oscillator and the Fradkin tensor of an isotropic one
(the Killing tensors of the metric, in the language of geometry).  Each one found is verified
at random states to 30 digits, the accelerations solved from M q_ddot = forcing there.

>>> import lagrangian as lg
>>> [str(i) for i in quadratic_integrals(lg.examples.simple_pendulum(), degree=1)]
['-2*g*cos(theta) + l*theta_dot**2']
"""

from __future__ import annotations

import random
from itertools import combinations_with_replacement

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.function_basis import FunctionBasis, function_basis
from lagrangian.analysis.lie_symmetries import (
    evaluated,
    numeric,
    readable,
    samples,
    search_problem,
    total_derivatives,
)
from lagrangian.analysis.null_vectors import exact_null_vectors
from lagrangian.derivation import EquationsOfMotion
from lagrangian.model.conversion import to_sympy
from lagrangian.model.probe import is_zero


def quadratic_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 2
) -> tuple[sp.Expr, ...]:
    """Every first integral quadratic in the velocities with coefficients in the function
    basis of total degree ``degree``, each verified at random states to 30 digits (module
    docstring)."""
    eom = equations_of(subject)
    problem = search_problem(eom, parameters)
    q, v = eom.coordinates, eom.velocities
    n = len(q)  # at least 1: a System has coordinates
    values = substitutions(eom, parameters)
    mass = to_sympy(substitute(eom.mass_matrix, values))
    forcing = to_sympy(substitute(eom.forcing, values))
    function = numeric(problem, [*mass, *forcing])
    basis = function_basis(problem.lagrangian, q, degree)
    k = len(basis.functions)
    pairs = list(combinations_with_replacement(range(n), 2))
    unknowns = (len(pairs) + n + 1) * k - 1
    points, rates = samples(basis, unknowns, np.random.default_rng(13))
    phi, d_phi = total_derivatives(basis, points, rates)

    def sampled(parameter_values: dict[sp.Symbol, float]) -> np.ndarray:
        given = [parameter_values[p] for p in problem.parameters]
        table = evaluated(function, points, rates, given)
        matrices = table[:, : n * n].reshape(-1, n, n)
        a = np.linalg.solve(matrices, table[:, n * n :, None])[:, :, 0]
        columns = []
        for i, j in pairs:
            product_rate = a[:, i] * rates[:, j] + rates[:, i] * a[:, j]
            product = rates[:, i] * rates[:, j]
            columns.append(d_phi * product[:, None] + phi * product_rate[:, None])
        for i in range(n):
            columns.append(d_phi * rates[:, i, None] + phi * a[:, i, None])
        columns.append(d_phi[:, 1:])  # K_0: a constant is no integral
        return np.column_stack(columns)

    rng = random.Random(5)
    generic = {p: rng.uniform(0.7, 1.7) for p in problem.parameters}
    monomials = [v[i] * v[j] for i, j in pairs] + list(v)
    found = []
    for vector in exact_null_vectors(sampled, problem.parameters, generic):
        integral = _integral(vector, basis, monomials)
        if not is_zero(integral) and _constant_on_motions(integral, eom, mass, forcing):
            found.append(readable(integral, problem.parameters))
    return tuple(found)


#: Random states at which dI/dt is evaluated on the equations of motion, and its tolerance.
CHECKS = 3
DIGITS = 30
TOLERANCE = sp.Float(1e-20)


def _constant_on_motions(
    integral: sp.Expr, eom: EquationsOfMotion, mass: sp.Matrix, forcing: sp.Matrix
) -> bool:
    """dI/dt = dI/dt + sum dI/dq q_dot + sum dI/dq_dot q_ddot vanishes at random states, the
    accelerations solved from M q_ddot = forcing at each to ``DIGITS`` digits (the symbolic
    solve of M would cost more than the whole search)."""
    q, v = eom.coordinates, eom.velocities
    rate = integral.diff(eom.time) + sum(
        (integral.diff(s) * r for s, r in zip(q, v)), sp.Integer(0)
    )
    slopes = [integral.diff(s) for s in v]
    rng = random.Random(23)
    symbols = set().union(integral.free_symbols, mass.free_symbols, forcing.free_symbols)
    for _ in range(CHECKS):
        point = {s: sp.Float(rng.uniform(0.3, 1.3), DIGITS) for s in sorted(symbols, key=str)}
        point.update({s: sp.Float(rng.uniform(-1.5, 1.5), DIGITS) for s in v})
        try:
            a = mass.xreplace(point).evalf(DIGITS).LUsolve(forcing.xreplace(point).evalf(DIGITS))
        except (ValueError, ZeroDivisionError):
            continue
        total = rate.xreplace(point) + sum(
            (s.xreplace(point) * a_i for s, a_i in zip(slopes, a)), sp.Integer(0)
        )
        value = sp.N(total, DIGITS)
        scale = 1 + max(abs(sp.N(term.xreplace(point), DIGITS)) for term in (integral, *slopes))
        if not value.is_number or abs(value) > TOLERANCE * scale:
            return False
    return True


def _integral(vector: list[sp.Expr], basis: FunctionBasis, monomials: list[sp.Expr]) -> sp.Expr:
    k = len(basis.functions)
    total = sp.Integer(0)
    for m, monomial in enumerate(monomials):
        coefficients = vector[m * k : (m + 1) * k]
        total += monomial * sp.Add(*(c * f for c, f in zip(coefficients, basis.functions)))
    last = vector[len(monomials) * k :]
    return total + sp.Add(*(c * f for c, f in zip(last, basis.functions[1:])))
