"""First integrals quadratic in the velocities, whether or not a point symmetry gives them:

    I = sum_{i<=j} K_ij(t, q) q_dot_i q_dot_j + sum_i K_i(t, q) q_dot_i + K_0(t, q),

with dI/dt = 0 on the equations of motion.  The K are sought in the
:mod:`~lagrangian.analysis.integrals.function_basis` of the Lagrangian; dI/dt is linear in their
coefficients, so the null space of its samples (:mod:`~lagrangian.analysis.integrals.null_vectors`)
holds every such integral: the energy, the squares and products of momenta, and those of
hidden symmetries — the Laplace–Runge–Lenz vector of the Kepler problem (Goldstein §3.9), the
separate energies of an anisotropic oscillator and the Fradkin tensor of an isotropic one
(the Killing tensors of the metric, in the language of geometry).  Each one found is verified
at random states to 30 digits, the accelerations solved from M q_ddot = forcing there.

The same search with monomials of degree 3 in the velocities (:func:`cubic_integrals`) finds
the integrals cubic in the momenta, such as the third integral of the periodic Toda lattice
of three particles (Hénon, Phys. Rev. B 9, 1921 (1974)).

>>> import lagrangian as lg
>>> [str(i) for i in quadratic_integrals(lg.examples.simple_pendulum(), degree=1)]
['-2*g*cos(theta) + l*theta_dot**2']
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from itertools import combinations_with_replacement

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.integrals.function_basis import FunctionBasis, function_basis
from lagrangian.analysis.integrals.lie_symmetries import (
    evaluated,
    numeric,
    readable,
    samples,
    search_problem,
    total_derivatives,
)
from lagrangian.analysis.integrals.null_vectors import exact_null_vectors
from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero


def quadratic_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 2
) -> tuple[sp.Expr, ...]:
    """Every first integral quadratic in the velocities with coefficients in the function
    basis of total degree ``degree``, each verified at random states to 30 digits (module
    docstring)."""
    return polynomial_integrals(subject, parameters, degree, order=2)


def cubic_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 1
) -> tuple[sp.Expr, ...]:
    """Every first integral cubic (at most) in the velocities with coefficients in the
    function basis of total degree ``degree``: the third integral of the Toda lattice.

    >>> import lagrangian as lg
    >>> x = lg.coordinates("x")[0]
    >>> falling = lg.System(coordinates=[x], kinetic=lg.velocity(x) ** 2 / 2, potential=x)
    >>> cubic_integrals(falling)
    (2*x + x_dot**2, t + x_dot)
    """
    return polynomial_integrals(subject, parameters, degree, order=3)


def velocity_monomials(n: int, order: int) -> list[tuple[int, ...]]:
    """The exponents of the monomials in n velocities of degree ``order`` down to 1, highest
    first (the row-echelon form then pivots on the leading terms).

    >>> velocity_monomials(2, 2)
    [(2, 0), (1, 1), (0, 2), (1, 0), (0, 1)]
    """
    found = []
    for d in range(order, 0, -1):
        for chosen in combinations_with_replacement(range(n), d):
            found.append(tuple(chosen.count(i) for i in range(n)))
    return found


def polynomial_integrals(
    subject: Subject, parameters: Values | None = None, degree: int = 2, order: int = 2
) -> tuple[sp.Expr, ...]:
    """Every first integral I = sum over velocity monomials m of degree <= ``order`` of
    K_m(t, q) m, with K_m in the function basis of total degree ``degree``, each verified
    at random states to 30 digits (module docstring)."""
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
    exponents = velocity_monomials(n, order)
    unknowns = (len(exponents) + 1) * k - 1
    points, rates = samples(basis, unknowns, np.random.default_rng(13))
    phi, d_phi = total_derivatives(basis, points, rates)

    def sampled(parameter_values: dict[sp.Symbol, float]) -> np.ndarray:
        given = [parameter_values[p] for p in problem.parameters]
        table = evaluated(function, points, rates, given)
        matrices = table[:, : n * n].reshape(-1, n, n)
        a = np.linalg.solve(matrices, table[:, n * n :, None])[:, :, 0]
        return velocity_columns(exponents, phi, d_phi, rates, a)

    rng = random.Random(5)
    generic = {p: rng.uniform(0.7, 1.7) for p in problem.parameters}
    monomials = [sp.Mul(*(s**e for s, e in zip(v, powers))) for powers in exponents]
    found = []
    for vector in exact_null_vectors(sampled, problem.parameters, generic):
        integral = integral_of(vector, basis, monomials)
        if not is_zero(integral) and constant_on_motions(integral, eom, mass, forcing):
            found.append(readable(integral, problem.parameters))
    return tuple(found)


def velocity_columns(
    exponents: Sequence[tuple[int, ...]],
    phi: np.ndarray,
    d_phi: np.ndarray,
    rates: np.ndarray,
    accelerations: np.ndarray,
) -> np.ndarray:
    """The samples of dI/dt, one column per unknown coefficient: for each velocity monomial
    m and basis function phi, D(phi m) = D(phi) m + phi D(m); then D(phi) for K_0 (without
    the constant function, which is no integral)."""
    columns = []
    for powers in exponents:
        # d/dt prod v_i**a_i = sum_i a_i v_i**(a_i - 1) q_ddot_i prod_{j != i} v_j**a_j
        product = np.prod(rates**powers, axis=1)
        product_rate = np.zeros_like(product)
        for i, power in enumerate(powers):
            if power:
                lowered = list(powers)
                lowered[i] -= 1
                product_rate += power * accelerations[:, i] * np.prod(rates**lowered, axis=1)
        columns.append(d_phi * product[:, None] + phi * product_rate[:, None])
    columns.append(d_phi[:, 1:])
    return np.column_stack(columns)


#: Random states at which dI/dt is evaluated on the equations of motion, and its tolerance.
CHECKS = 3
DIGITS = 30
TOLERANCE = sp.Float(1e-20)


def constant_on_motions(
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


def integral_of(
    vector: Sequence[sp.Expr], basis: FunctionBasis, monomials: Sequence[sp.Expr]
) -> sp.Expr:
    """sum_m K_m monomial_m + K_0 with the coefficients of ``vector`` (as the columns of
    :func:`velocity_columns`: one block of basis functions per monomial, then K_0 without
    the constant)."""
    k = len(basis.functions)
    total = sp.Integer(0)
    for m, monomial in enumerate(monomials):
        coefficients = vector[m * k : (m + 1) * k]
        total += monomial * sp.Add(*(c * f for c, f in zip(coefficients, basis.functions)))
    last = vector[len(monomials) * k :]
    return total + sp.Add(*(c * f for c, f in zip(last, basis.functions[1:])))
