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
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from itertools import combinations_with_replacement

import numpy as np
import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, substitute, substitutions
from lagrangian.analysis.integrals.function_basis import FunctionBasis, function_basis
from lagrangian.analysis.integrals.lie_symmetries import (
    SearchProblem,
    evaluated,
    numeric,
    readable,
    sample_count,
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
    basis = function_basis(problem.lagrangian, eom.coordinates, degree)
    exponents = velocity_monomials(len(eom.coordinates), order)
    return integrals_in_basis(problem, parameters, basis, [Ansatz.uniform(exponents, basis)])


@dataclass(frozen=True)
class Ansatz:
    """Which basis functions multiply which velocity monomial: ``supports[m]`` the indices
    (into the basis) of the coefficient functions of ``exponents[m]``, and the last entry
    those of K_0, the part free of the velocities (never the constant function, which is
    no integral)."""

    exponents: tuple[tuple[int, ...], ...]
    supports: tuple[tuple[int, ...], ...]

    @classmethod
    def uniform(cls, exponents: Sequence[tuple[int, ...]], basis: FunctionBasis) -> Ansatz:
        """Every basis function with every monomial (the first function is the constant)."""
        every = tuple(range(len(basis.functions)))
        return cls(tuple(exponents), (*(every for _ in exponents), every[1:]))

    @property
    def unknowns(self) -> int:
        """The number of unknown coefficients."""
        return sum(len(s) for s in self.supports)


def integrals_in_basis(
    problem: SearchProblem,
    parameters: Values | None,
    basis: FunctionBasis,
    ansatze: Sequence[Ansatz],
    novel: Callable[[sp.Expr], bool] | None = None,
    simplified: bool = True,
) -> tuple[sp.Expr, ...]:
    """Every first integral sum_m K_m(t, q) m + K_0(t, q) whose coefficient functions are
    combinations of the basis functions an ansatz allows each velocity monomial m, each
    verified at random states to 30 digits (module docstring).  The ansatze are solved
    apart (parts of one ansatz that dI/dt never mixes), on the same samples; ``novel``, when
    given, drops a solution before its verification (one already known); ``simplified``
    False spares the general simplification of what is found (:func:`readable`)."""
    eom = problem.eom
    n = len(eom.coordinates)  # at least 1: a System has coordinates
    values = substitutions(eom, parameters)
    mass = to_sympy(substitute(eom.mass_matrix, values))
    forcing = to_sympy(substitute(eom.forcing, values))
    function = numeric(problem, [*mass, *forcing])
    most = max(ansatz.unknowns for ansatz in ansatze)
    points, rates = samples(basis, most, np.random.default_rng(13))
    phi, d_phi = total_derivatives(basis, points, rates)

    def sampled(ansatz: Ansatz, parameter_values: dict[sp.Symbol, float]) -> np.ndarray:
        rows = slice(sample_count(ansatz.unknowns))  # a smaller part, fewer samples
        given = [parameter_values[p] for p in problem.parameters]
        table = evaluated(function, points[rows], rates[rows], given)
        matrices = table[:, : n * n].reshape(-1, n, n)
        a = np.linalg.solve(matrices, table[:, n * n :, None])[:, :, 0]
        return velocity_columns(ansatz, phi[rows], d_phi[rows], rates[rows], a)

    rng = random.Random(5)
    generic = {p: rng.uniform(0.7, 1.7) for p in problem.parameters}
    v = eom.velocities
    found = []
    for ansatz in ansatze:
        monomials = [sp.Mul(*(s**e for s, e in zip(v, powers))) for powers in ansatz.exponents]
        for vector in exact_null_vectors(partial(sampled, ansatz), problem.parameters, generic):
            integral = integral_of(vector, basis, monomials, ansatz)
            if is_zero(integral) or (novel is not None and not novel(integral)):
                continue
            if constant_on_motions(integral, eom, mass, forcing):
                found.append(readable(integral, problem.parameters, simplified))
    return tuple(found)


def velocity_columns(
    ansatz: Ansatz,
    phi: np.ndarray,
    d_phi: np.ndarray,
    rates: np.ndarray,
    accelerations: np.ndarray,
) -> np.ndarray:
    """The samples of dI/dt, one column per unknown coefficient: for each velocity monomial
    m and basis function phi of its support, D(phi m) = D(phi) m + phi D(m); then D(phi)
    for K_0."""
    columns = []
    for powers, support in zip(ansatz.exponents, ansatz.supports):
        # d/dt prod v_i**a_i = sum_i a_i v_i**(a_i - 1) q_ddot_i prod_{j != i} v_j**a_j
        product = np.prod(rates**powers, axis=1)
        product_rate = np.zeros_like(product)
        for i, power in enumerate(powers):
            if power:
                lowered = list(powers)
                lowered[i] -= 1
                product_rate += power * accelerations[:, i] * np.prod(rates**lowered, axis=1)
        chosen = list(support)
        columns.append(d_phi[:, chosen] * product[:, None] + phi[:, chosen] * product_rate[:, None])
    columns.append(d_phi[:, list(ansatz.supports[-1])])
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
    vector: Sequence[sp.Expr],
    basis: FunctionBasis,
    monomials: Sequence[sp.Expr],
    ansatz: Ansatz,
) -> sp.Expr:
    """sum_m K_m monomial_m + K_0 with the coefficients of ``vector`` (as the columns of
    :func:`velocity_columns`: one block per monomial over its support, then K_0)."""
    total = sp.Integer(0)
    start = 0
    for monomial, support in zip([*monomials, sp.Integer(1)], ansatz.supports):
        coefficients = vector[start : start + len(support)]
        start += len(support)
        functions = [basis.functions[i] for i in support]
        total += monomial * sp.Add(*(c * f for c, f in zip(coefficients, functions)))
    return total
