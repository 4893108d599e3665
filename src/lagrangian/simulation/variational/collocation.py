"""``simulate(..., method="gauss4" | "gauss6", dt=...)``: symplectic collocation of order 4 and 6.

A symplectic partitioned Runge–Kutta method with coefficients (a, a_hat, b, c) applied to the
Lagrangian system p = dL/dq_dot, dp/dt = dL/dq + Q (Q the applied and dissipative forces not
in L, as for the midpoint rule of :mod:`lagrangian.simulation.variational.midpoint`) is a
variational
integrator: its stages are the critical point of a discrete action built with the quadrature
(b, c) (Hairer, Lubich & Wanner, Geometric Numerical Integration, 2nd ed., section VI.6.3;
Marsden & West 2001, Acta Numerica 10, section 2.6).  A step (q0, p0) -> (q1, p1) of size h
solves for the stage velocities V_i

    Q_i = q0 + h sum_j a_ij V_j,
    dL/dq_dot(Q_i, V_i, t_i) = p0 + h sum_j a_hat_ij (F_j + A(Q_j)^T Lambda_j),
    F_j = dL/dq(Q_j, V_j, t_j) + Q(Q_j, V_j, t_j),     t_i = t0 + c_i h,

then q1 = q0 + h sum_i b_i V_i, p1 = p0 + h sum_i b_i (F_i + A_i^T Lambda_i), and the
velocity v1 from p1 = dL/dq_dot(q1, v1, t1) (the inverse Legendre map).

* Without constraints, the Gauss–Legendre collocation methods, a = a_hat (Gauss methods are
  symplectic, section VI.4): s = 2 stages for order 4 (``gauss4``), s = 3 for order 6
  (``gauss6``), the highest order s stages can have (section II.1.3).
* With holonomic constraints h(q, t) = 0, the Lobatto IIIA–IIIB pair of the same order
  (s = 3 and 4 stages, order 2s - 2; section VII.1.5; L. Jay, SIAM J. Numer. Anal. 33 (1996)
  368–387): Lobatto nodes include both ends of the step, so the constraints hold at every
  stage Q_2..Q_s = q1, the multipliers Lambda_1..Lambda_{s-1} are found with the stages and
  Lambda_s with the velocity, from A(q1) v1 + dh/dt = 0, as in RATTLE (its s = 2 member).
  Both the positions and the velocities of the outputs lie on the constraints to rounding.

Both families are symplectic and symmetric: on a conservative system the energy error stays
bounded over long runs, at O(h^4) or O(h^6).  The multipliers reported are those of the
multiplier form at each output state (:mod:`lagrangian.numerics.constrained`), as accurate as
the state: the stage multipliers Lambda_s and Lambda_1 meeting at a node, combined as the
midpoint rule's are, are only second-order accurate.

>>> gauss(2).order, lobatto(3).order
(4, 4)
>>> print(np.round(gauss(2).a * 12, 6))  # 1/4, 1/4 -+ sqrt(3)/6
[[ 3.       -0.464102]
 [ 6.464102  3.      ]]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.polynomial import Polynomial
from numpy.polynomial import legendre as legendre_series


@dataclass(frozen=True)
class Tableau:
    """A symplectic partitioned Runge–Kutta method (module docstring): ``a`` for the
    positions, ``a_hat`` for the momenta, weights ``b`` and nodes ``c`` in [0, 1].

    ``lobatto`` is True for the Lobatto IIIA–IIIB pair: its first stage is q0, its last q1,
    the constraints are imposed at stages 2..s with multipliers at stages 1..s-1 (the last
    one comes with the velocity).  ``name`` is how the Trajectory's note names it.
    """

    name: str
    order: int
    a: np.ndarray
    a_hat: np.ndarray
    b: np.ndarray
    c: np.ndarray
    lobatto: bool

    @property
    def stages(self) -> int:
        """s, the number of stages."""
        return len(self.c)

    def extrapolation(self, ratio: float) -> np.ndarray:
        """E with E_ij = l_j(1 + ratio c_i), l_j the Lagrange polynomials of the nodes: the
        stage velocities of the previous step (of size h / ratio) extrapolated to this step's
        nodes, V_i ~ sum_j E_ij V_j^prev (the start of the Newton iteration, HLW VIII.6.1);
        ``ratio`` as :func:`lagrangian.numerics.stage_prediction.step_ratio` gives it,
        exactly 1 for steps of one size whose nodes differ by rounding."""
        return np.array(
            [[_lagrange(self.c, j)(1 + ratio * ci) for j in range(self.stages)] for ci in self.c]
        )


def _lagrange(nodes: np.ndarray, j: int) -> Polynomial:
    """The Lagrange polynomial l_j of ``nodes``: 1 at nodes[j], 0 at the others."""
    others = np.delete(nodes, j)
    numerator = Polynomial.fromroots(others) if len(others) else Polynomial([1.0])
    return numerator / float(np.prod(nodes[j] - others))


def _collocation(c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """a_ij = integral of l_j from 0 to c_i and b_j = integral of l_j from 0 to 1 (the
    collocation method of the nodes c, HLW II.1.3)."""
    integrals = [_lagrange(c, j).integ(lbnd=0.0) for j in range(len(c))]
    a = np.array([[float(integral(ci)) for integral in integrals] for ci in c])
    return a, np.array([float(integral(1.0)) for integral in integrals])


def _conjugate(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a_hat_ij = b_j (1 - a_ji / b_i): the momenta's coefficients that make the pair
    symplectic, b_i a_hat_ij + b_j a_ji = b_i b_j (HLW VI.4.2)."""
    return b[None, :] * (1.0 - a.T / b[:, None])


def gauss(stages: int) -> Tableau:
    """The Gauss–Legendre collocation method of ``stages`` stages (order 2 stages); a_hat = a."""
    roots, _ = legendre_series.leggauss(stages)
    c = (roots + 1.0) / 2.0
    a, b = _collocation(c)
    name = f"Gauss–Legendre collocation, {stages} stages, order {2 * stages}"
    return Tableau(name, 2 * stages, a, a.copy(), b, c, lobatto=False)


def lobatto(stages: int) -> Tableau:
    """The Lobatto IIIA–IIIB pair of ``stages`` stages (order 2 stages - 2)."""
    inner = legendre_series.Legendre.basis(stages - 1).deriv().roots()
    c = np.concatenate(([0.0], (np.sort(inner.real) + 1.0) / 2.0, [1.0]))
    a, b = _collocation(c)
    a[0], a[-1] = 0.0, b  # exactly: the first stage is q0, the last q1
    name = f"Lobatto IIIA–IIIB pair, {stages} stages, order {2 * stages - 2}"
    return Tableau(name, 2 * stages - 2, a, _conjugate(a, b), b, c, lobatto=True)


#: The collocation methods by name: (without constraints, with holonomic constraints).
COLLOCATION = {"gauss4": (gauss(2), lobatto(3)), "gauss6": (gauss(3), lobatto(4))}


def tableau_for(method: str, constrained: bool) -> Tableau:
    """The tableau ``method`` integrates with, with or without holonomic constraints."""
    free, with_constraints = COLLOCATION[method]
    return with_constraints if constrained else free
