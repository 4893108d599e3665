"""compile_constrained(equations) -> CompiledConstrained: the multiplier form as NumPy functions.

With the constraints differentiated to A q_ddot = gamma (:func:`lagrangian.constraints.
constrained_equations`), the accelerations and multipliers solve

    [ M  -A^T ] [ q_ddot ]   [ forcing                          ]
    [ A    0  ] [ lambda ] = [ gamma - 2 alpha c - beta^2 h     ]

where c = A q_dot + b is the velocity residual of every row (b = dh/dt for a holonomic one)
and h the position residual of the holonomic rows (0 for velocity rows).  alpha = beta = 0
is the plain index-1 form; alpha, beta > 0 is Baumgarte's stabilization, which pulls a drift
of the residuals back to zero (c_dot + 2 alpha c + beta^2 h = 0).

>>> import numpy as np, sympy as sp, lagrangian as lg
>>> from lagrangian.constraints import constrained_equations
>>> x, y = sp.symbols("x y")
>>> ring = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(x**2 + y**2 - 1)],
...     particles=[lg.Particle("bead", 1, (x, y))])
>>> compiled = compile_constrained(constrained_equations(ring))
>>> q_ddot, lam = compiled.accelerations(np.array([1.0, 0.0]), np.array([0.0, 1.0]), 0.0,
...                                      np.zeros(0))
>>> np.round(q_ddot, 12), np.round(lam, 12)
(array([-1.,  0.]), array([-0.5]))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import sympy as sp

from lagrangian.constraints import ConstrainedEquations
from lagrangian.constraints.pfaffian import pfaffian_form
from lagrangian.errors import SimulationError, SimulationInputError
from lagrangian.model.constraints import VelocityConstraint
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.symbolic.caches import IdentityCache

#: Newton steps of :meth:`CompiledConstrained.project` (one or two suffice after a step).
PROJECTION_ITERATIONS = 20


class FormParts(NamedTuple):
    """The multiplier form at one state: M, the forcing, the Jacobian A (one row a_j per
    constraint), gamma of A q_ddot = gamma, the rates c = A q_dot + b and the position
    residuals h (0 for velocity rows)."""

    mass: np.ndarray
    forcing: np.ndarray
    jacobian: np.ndarray
    gamma: np.ndarray
    rates: np.ndarray
    h: np.ndarray


@dataclass(frozen=True)
class CompiledConstrained:
    """NumPy functions of the multiplier form of one system (one state at a time).

    Attributes
    ----------
    coordinates, parameters, multipliers:
        Names, in the order of the arrays q (and q_dot), p and lambda.
    holonomic:
        Per constraint, whether it has a position residual h (holonomic) or not (velocity).
    """

    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    multipliers: tuple[str, ...]
    holonomic: tuple[bool, ...]
    _all: NumericFunction = field(repr=False)

    def parts(self, q: np.ndarray, qd: np.ndarray, t: float, p: np.ndarray) -> FormParts:
        """Every piece of the multiplier form at one state (an impact needs M, A and the
        rates A q_dot + b together)."""
        n, m = len(self.coordinates), len(self.multipliers)
        values = np.array(self._all.raw(q, qd, t, p), dtype=float)
        sizes = (n * n, n, m * n, m, m, m)
        cuts = np.cumsum(sizes)[:-1]
        mass, forcing, a, gamma, c, h = np.split(values, cuts)
        return FormParts(mass.reshape(n, n), forcing, a.reshape(m, n), gamma, c, h)

    def residuals(
        self, q: np.ndarray, qd: np.ndarray, t: float, p: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(h, c): position residuals (0 for velocity rows) and velocity residuals A q_dot + b."""
        *_, c, h = self.parts(np.asarray(q, float), np.asarray(qd, float), t, p)
        return h, c

    def project(
        self, q: np.ndarray, qd: np.ndarray, t: float, p: np.ndarray, tolerance: float = 1e-12
    ) -> tuple[np.ndarray, np.ndarray]:
        """The nearest state on the constraints (Euclidean coordinate projection).

            q  <- q - A_h^T (A_h A_h^T)^+ h(q)        (Newton, until max |h| <= tolerance)
            q_dot <- q_dot - A^T (A A^T)^+ (A q_dot + b)

        A_h are the Jacobian rows of the holonomic constraints, A every row at the new q.
        Raises SimulationError when the Newton iteration does not reach the constraints.
        """
        q, qd = np.array(q, dtype=float), np.array(qd, dtype=float)
        holonomic = np.array(self.holonomic, dtype=bool)
        for _ in range(PROJECTION_ITERATIONS):
            *_, a, _, c, h = self.parts(q, qd, t, p)
            if not np.any(holonomic) or np.max(np.abs(h[holonomic])) <= tolerance:
                break
            rows = a[holonomic]
            q -= rows.T @ np.linalg.lstsq(rows @ rows.T, h[holonomic], rcond=None)[0]
        else:
            raise SimulationError(
                f"Projection onto the constraints did not converge at t = {t:.6g} (largest "
                f"residual {np.max(np.abs(h)):.3g}): take smaller steps (max_step, rtol)."
            )
        qd -= a.T @ np.linalg.lstsq(a @ a.T, c, rcond=None)[0]
        return q, qd

    def accelerations(
        self,
        q: np.ndarray,
        qd: np.ndarray,
        t: float,
        p: np.ndarray,
        alpha: float = 0.0,
        beta: float = 0.0,
    ) -> tuple[np.ndarray, np.ndarray]:
        """(q_ddot, lambda) at one state, with Baumgarte's alpha and beta (0: off).

        Raises SimulationError when the augmented matrix is singular there.
        """
        n, m = len(self.coordinates), len(self.multipliers)
        mass, forcing, a, gamma, c, h = self.parts(
            np.asarray(q, float), np.asarray(qd, float), t, p
        )
        matrix = np.zeros((n + m, n + m))
        matrix[:n, :n], matrix[:n, n:], matrix[n:, :n] = mass, -a.T, a
        vector = np.concatenate((forcing, gamma - 2.0 * alpha * c - beta**2 * h))
        try:
            z = np.linalg.solve(matrix, vector)
        except np.linalg.LinAlgError:
            state = ", ".join(f"{name}={v:.6g}" for name, v in zip(self.coordinates, q))
            raise SimulationError(
                f"The augmented matrix [[M, -A^T], [A, 0]] is singular at t = {t:.6g} "
                f"({state}): the constraints are dependent there or M is singular on them."
            ) from None
        return z[:n], z[n:]


_COMPILED: IdentityCache[ConstrainedEquations, CompiledConstrained] = IdentityCache()


def compile_constrained(equations: ConstrainedEquations) -> CompiledConstrained:
    """The numeric functions of the multiplier form (holonomic and velocity constraints),
    compiled once per ConstrainedEquations object.

    Unilateral constraints are compiled as active holonomic ones (the caller refuses them).
    """
    return _COMPILED.get(equations, _compile_multiplier_form)


def _compile_multiplier_form(equations: ConstrainedEquations) -> CompiledConstrained:
    q, qd = list(equations.coordinates), list(equations.velocities)
    p, t = list(equations.parameters), equations.time
    forms = [pfaffian_form(c, q) for c in equations.constraints]
    holonomic = tuple(not isinstance(c, VelocityConstraint) for c in equations.constraints)
    velocity_residuals = [f.velocity_expression for f in forms]
    positions = [
        c.expression if hol else sp.Integer(0) for c, hol in zip(equations.constraints, holonomic)
    ]
    expressions = [
        *equations.mass_matrix,
        *equations.forcing,
        *equations.constraint_jacobian,
        *equations.gamma,
        *velocity_residuals,
        *positions,
    ]
    known = {*q, *qd, t, *p}
    unknown = sorted(
        {s.name for e in expressions for s in e.free_symbols} - {s.name for s in known}
    )
    if unknown:
        raise SimulationInputError(
            f"The equations use {', '.join(unknown)}, which are neither coordinates nor "
            "parameters: declare them as parameters of the System to give them values."
        )
    return CompiledConstrained(
        coordinates=tuple(s.name for s in q),
        parameters=tuple(s.name for s in p),
        multipliers=tuple(s.name for s in equations.multipliers),
        holonomic=holonomic,
        _all=NumericFunction((q, qd, t, p), expressions, (len(expressions),)),
    )
