"""Stability of a state of rest from the stiffness matrix (the Hessian of the potential).

At rest the equations are M q_ddot = f(q) + D(q) q_dot + ...; with

    K = -df/dq        (= d2V_eff/dq2 when the static forces come from V_eff = -L(q, 0))

Lagrange–Dirichlet: K positive definite -> stable (a minimum of the effective potential).
A negative eigenvalue -> unstable (a saddle or maximum) unless gyroscopic forces (the skew
part of df/dq_dot) may stabilize an even number of such directions (Kelvin–Tait–Chetaev).
A singular semi-definite K leaves the question open: "undetermined at second order".

>>> stability_of(sp.Matrix([[2, 0], [0, 3]]))
(True, 'K is positive definite: a minimum of the (effective) potential (Lagrange–Dirichlet)')
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp

from lagrangian.analysis.at_rest import sparse_jacobian
from lagrangian.analysis.spectrum import symmetric_eigenvalues

TOLERANCE = 1e-10


def stiffness_matrix(static: sp.MatrixBase, coordinates: Sequence[sp.Symbol]) -> sp.Matrix:
    """K = -d(static forces)/dq, each force differentiated by the coordinates it holds."""
    return -sparse_jacobian(static, coordinates)  # d|u| = sign(u) du, as by hand


def sylvester_condition(stiffness: sp.MatrixBase) -> sp.Basic:
    """Every leading principal minor of K positive (K positive definite)."""
    n = stiffness.rows
    minors = [sp.factor(stiffness[:k, :k].det()) > 0 for k in range(1, n + 1)]
    return sp.And(*minors)


def _scale(matrix: sp.MatrixBase) -> float:
    return max((abs(complex(e)) for e in matrix), default=1.0) or 1.0


def _skew(matrix: sp.MatrixBase, scale: float | None = None) -> bool:
    """Whether ``matrix`` has a skew part above the tolerance (relative to its largest entry)."""
    tiny = TOLERANCE * (_scale(matrix) if scale is None else scale)
    return any(abs(complex(e)) > tiny for e in matrix - matrix.T)


def _eigenvalues(stiffness: sp.MatrixBase) -> tuple[float, ...]:
    """The eigenvalues of a symmetric numeric K, ascending: its diagonal when it is diagonal
    (the static forces of a chain each depend on their own coordinate alone), where the
    eigensolver would spend n^3 operations to return the same numbers."""
    if stiffness.is_diagonal():
        return tuple(sorted(float(sp.re(stiffness[i, i])) for i in range(stiffness.rows)))
    return symmetric_eigenvalues(stiffness)


def stability_of(
    stiffness: sp.MatrixBase,
    gyroscopic: sp.MatrixBase | None = None,
    neutral: Sequence[str] = (),
) -> tuple[bool | None, str]:
    """(stable, reason) from a numeric K (coordinates of a family of equilibria, ``neutral``,
    already removed) and optionally the numeric velocity Jacobian df/dq_dot."""
    along = f"; neutral along {', '.join(neutral)} (a family of equilibria)" if neutral else ""
    if stiffness.rows == 0:
        return None, (
            "neutral: every nearby configuration is at rest too (a family of equilibria"
            + (f" along {', '.join(neutral)}" if neutral else "")
            + "), so a push moves it off at constant speed"
        )
    scale = _scale(stiffness)
    if not stiffness.is_diagonal() and _skew(stiffness, scale):
        return None, (
            "K is not symmetric (positional forces not from a potential): the Hessian test "
            "does not apply; see the linearization's eigenvalues"
        )
    values = _eigenvalues(stiffness)
    tiny = TOLERANCE * scale
    negative = sum(1 for v in values if v < -tiny)
    if negative == 0 and all(v > tiny for v in values):
        return True, (
            "K is positive definite: a minimum of the (effective) potential "
            "(Lagrange–Dirichlet)" + along
        )
    if negative == 0:
        return None, (
            "K is positive semi-definite but singular: undetermined at second order" + along
        )
    spinning = gyroscopic is not None and _skew(gyroscopic)
    kind = "a maximum" if negative == len(values) else "a saddle"
    if spinning and negative % 2 == 0:
        return None, (
            f"K has {negative} negative eigenvalues ({kind} of the potential), but gyroscopic "
            "forces may stabilize an even number of them (Kelvin–Tait–Chetaev): see the "
            "linearization" + along
        )
    return False, (
        f"K has {negative} negative eigenvalue{'s' if negative > 1 else ''}: {kind} of the "
        "(effective) potential" + along
    )
