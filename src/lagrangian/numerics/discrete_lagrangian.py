"""The derivatives of L, of the non-conservative forces and of holonomic constraints that the
midpoint discrete Lagrangian needs, as NumPy functions.

The midpoint discrete Lagrangian (Marsden & West 2001, section 2.6)

    L_d(q0, q1) = dt L(q_m, v_m, t_m),   q_m = (q0 + q1)/2,  v_m = (q1 - q0)/dt,  t_m = t0 + dt/2

has D1 L_d = dt/2 L_q - L_v and D2 L_d = dt/2 L_q + L_v at the midpoint, and its mixed second
derivative needs the Hessian blocks L_qq, L_qv, L_vv there.  The forces that are not in L,

    Q = generalized_forces - dF/dq_dot       (applied forces, forces at points, dissipation),

enter the discrete Lagrange-d'Alembert principle with their Jacobians Q_q, Q_v; holonomic
constraints h(q, t) = 0 with A = dh/dq, dh/dt and the Hessians d2h_j/dq2 (the collocation
integrators evaluate A at stages that move with the unknowns).

* :func:`compile_lagrangian` — L, L_q, L_v (for the discrete action of Hamilton's principle);
* :func:`compile_discrete_mechanics` — everything the variational integrators evaluate, as
  NumPy functions, and the same terms as expressions (:class:`DiscreteTerms`) for the
  compiled loops of :mod:`lagrangian.numerics.fast.discrete`.

The Newton iterations that solve the discrete equations, in NumPy or compiled, share one set
of tolerances: :data:`MAX_ITERATIONS`, :data:`SMALL_CORRECTION`, :data:`RESIDUAL_GUARD`.

>>> import numpy as np, lagrangian as lg
>>> eom = lg.derive(lg.examples.simple_pendulum())
>>> mechanics = compile_discrete_mechanics(eom)
>>> L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v = mechanics.midpoint(
...     np.array([0.0]), np.array([2.0]), 0.0, np.array([1.0, 9.81, 1.0]))
>>> L_v, L_vv  # m l^2 theta_dot and m l^2
(array([2.]), array([[1.]]))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import SimulationInputError
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.conversion import to_sympy

#: Newton iterations allowed per solve of the discrete equations.
MAX_ITERATIONS = 25
#: A Newton correction below this fraction of the size of the unknowns ends the iteration:
#: the error after it is of its square (quadratic convergence), below rounding.
SMALL_CORRECTION = 1e-8
#: The residual accepted after the last correction, relative to the size of its terms (a
#: guard against a correction that converged to nonsense).
RESIDUAL_GUARD = 1e-8


@dataclass(frozen=True)
class LagrangianFunctions:
    """L, dL/dq and dL/dq_dot of one system as NumPy functions of (q, q_dot, t, p)."""

    lagrangian: NumericFunction
    dL_dq: NumericFunction
    dL_dq_dot: NumericFunction


_LAGRANGIAN_CACHE: IdentityCache[EquationsOfMotion, LagrangianFunctions] = IdentityCache()


def compile_lagrangian(eom: EquationsOfMotion) -> LagrangianFunctions:
    """L, L_q and L_v of ``eom`` (compiled once per EquationsOfMotion object)."""
    return _LAGRANGIAN_CACHE.get(eom, _compile_lagrangian)


def _compile_lagrangian(eom: EquationsOfMotion) -> LagrangianFunctions:
    q, qd, t, p = list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)
    lagrangian = eom.lagrangian
    _require_known(eom, [lagrangian], "The Lagrangian uses")
    groups, n = (q, qd, t, p), len(q)
    return LagrangianFunctions(
        lagrangian=NumericFunction(groups, [lagrangian], ()),
        dL_dq=NumericFunction(groups, [sp.diff(lagrangian, s) for s in q], (n,)),
        dL_dq_dot=NumericFunction(groups, [sp.diff(lagrangian, s) for s in qd], (n,)),
    )


@dataclass(frozen=True)
class DiscreteTerms:
    """The expressions behind :class:`DiscreteMechanics`, for compilers other than NumPy's.

    ``midpoint`` (3n + 5n^2 terms: L_q, L_v, Q, then L_qq, L_qv, L_vv, Q_q, Q_v row by row)
    and ``legendre`` (L_v, L_vv) are functions of [q, v, t, p]; ``constraints`` (h, A row by
    row, dh/dt, then the Hessian of each h_j row by row: m(2 + n + n^2) terms) of [q, t, p].
    """

    coordinates: tuple[sp.Symbol, ...]
    velocities: tuple[sp.Symbol, ...]
    time: sp.Symbol
    parameters: tuple[sp.Symbol, ...]
    midpoint: tuple[sp.Expr, ...]
    legendre: tuple[sp.Expr, ...]
    constraints: tuple[sp.Expr, ...]


@dataclass(frozen=True)
class DiscreteMechanics:
    """NumPy functions of one system for the variational integrator (one state at a time).

    Attributes
    ----------
    coordinates, parameters:
        Names, in the order of the arrays q (and v) and p.
    constraint_count:
        m, the number of holonomic constraints h(q, t) = 0.
    forced:
        Whether Q (applied forces and dissipation) has a term (is not the zero expression).
    legendre_linear:
        Whether L_vv does not depend on the velocities (L quadratic in them), so that the
        Legendre map p = L_v(q, v, t) is affine in v and one Newton step inverts it.
    terms:
        The same functions as expressions.
    """

    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    constraint_count: int
    forced: bool
    legendre_linear: bool
    terms: DiscreteTerms = field(repr=False, compare=False)
    _midpoint: NumericFunction = field(repr=False)
    _legendre: NumericFunction = field(repr=False)
    _constraints: NumericFunction = field(repr=False)

    def midpoint(
        self, q: np.ndarray, v: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, ...]:
        """(L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v) at (q, v, t); (L_qv)_ij = d2L/dq_i dv_j."""
        n = len(self.coordinates)
        values = np.array(self._midpoint.raw(q, v, t, p), dtype=float)
        vectors, matrices = values[: 3 * n], values[3 * n :].reshape(5, n, n)
        return (vectors[:n], vectors[n : 2 * n], vectors[2 * n :], *matrices)

    def legendre(
        self, q: np.ndarray, v: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(L_v, L_vv) at (q, v, t): the momentum and its derivative in v."""
        n = len(self.coordinates)
        values = np.array(self._legendre.raw(q, v, t, p), dtype=float)
        return values[:n], values[n:].reshape(n, n)

    def constraints(
        self, q: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(h, A, dh/dt) at (q, t): residuals (m,), Jacobian dh/dq (m, n), explicit rate (m,)."""
        n, m = len(self.coordinates), self.constraint_count
        if m == 0:
            return np.zeros(0), np.zeros((0, n)), np.zeros(0)
        values = np.array(self._constraints.raw(q, t, p), dtype=float)
        return values[:m], values[m : m + m * n].reshape(m, n), values[m + m * n : 2 * m + m * n]

    def constraint_hessians(self, q: np.ndarray, t: float, p: np.ndarray) -> np.ndarray:
        """d2h_j/dq_a dq_b at (q, t), shape (m, n, n)."""
        n, m = len(self.coordinates), self.constraint_count
        if m == 0:
            return np.zeros((0, n, n))
        values = np.array(self._constraints.raw(q, t, p), dtype=float)
        return values[2 * m + m * n :].reshape(m, n, n)

    def residuals(
        self, q: np.ndarray, v: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(h, A v + dh/dt): the constraints at position and at velocity level."""
        h, a, h_t = self.constraints(q, t, p)
        return h, a @ v + h_t


_MECHANICS_CACHE: IdentityCache[EquationsOfMotion, dict[tuple[sp.Expr, ...], DiscreteMechanics]]
_MECHANICS_CACHE = IdentityCache()


def compile_discrete_mechanics(
    eom: EquationsOfMotion, constraints: Sequence[sp.Expr] = ()
) -> DiscreteMechanics:
    """The functions of :class:`DiscreteMechanics` for ``eom`` and the holonomic constraints
    h_j(q, t) = 0 given by their expressions (compiled once per eom and constraints)."""
    known = _MECHANICS_CACHE.get(eom, lambda _: {})
    key = tuple(to_sympy(h) for h in constraints)
    if key not in known:
        known[key] = _compile_mechanics(eom, key)
    return known[key]


def _compile_mechanics(
    eom: EquationsOfMotion, constraints: tuple[sp.Expr, ...]
) -> DiscreteMechanics:
    q, v, t, p = list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)
    lagrangian = eom.lagrangian
    forces = list(eom.generalized_forces + eom.dissipation_forces)
    _require_known(eom, [lagrangian, *forces, *constraints], "The equations use")
    L_q = [sp.diff(lagrangian, s) for s in q]
    L_v = [sp.diff(lagrangian, s) for s in v]
    L_vv = _jacobian(L_v, v)
    midpoint = [
        *L_q,
        *L_v,
        *forces,
        *_jacobian(L_q, q),
        *_jacobian(L_q, v),
        *L_vv,
        *_jacobian(forces, q),
        *_jacobian(forces, v),
    ]
    A = _jacobian(list(constraints), q)
    constraint_terms = [
        *constraints,
        *A,
        *(sp.diff(h, t) for h in constraints),
        *_jacobian(A, q),  # row (j, a), column b: d2h_j/dq_a dq_b
    ]
    terms = DiscreteTerms(
        tuple(q), tuple(v), t, tuple(p), tuple(midpoint), (*L_v, *L_vv), tuple(constraint_terms)
    )
    return DiscreteMechanics(
        coordinates=tuple(s.name for s in q),
        parameters=tuple(s.name for s in p),
        constraint_count=len(constraints),
        forced=any(f != 0 for f in forces),
        legendre_linear=not any(e.free_symbols & set(v) for e in L_vv),
        terms=terms,
        _midpoint=NumericFunction((q, v, t, p), midpoint, (len(midpoint),)),
        _legendre=NumericFunction((q, v, t, p), terms.legendre, (len(q) * (len(q) + 1),)),
        _constraints=NumericFunction((q, t, p), constraint_terms, (len(constraint_terms),)),
    )


def _jacobian(expressions: Sequence[sp.Expr], symbols: Sequence[sp.Symbol]) -> list[sp.Expr]:
    """d expressions_i / d symbols_j, row by row."""
    return [sp.diff(e, s) for e in expressions for s in symbols]


def _require_known(eom: EquationsOfMotion, expressions: Sequence[sp.Expr], what: str) -> None:
    known = {*eom.coordinates, *eom.velocities, eom.time, *eom.parameters}
    used: set[sp.Basic] = set()
    for expression in expressions:
        used |= to_sympy(expression).free_symbols
    unknown = sorted(str(s) for s in used - known)
    if unknown:
        raise SimulationInputError(
            f"{what} {', '.join(unknown)}, which are neither coordinates nor parameters: "
            "declare them as parameters of the System to give them values."
        )
