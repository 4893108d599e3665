"""compile_equations(eom) -> CompiledEquations: the equations of motion as NumPy functions.

    M(q, t) q_ddot = forcing(q, q_dot, t)        x = [q; q_dot],  dx/dt = [q_dot; q_ddot]

(with first-order coordinates the state is x = [q; q_dot_S], see :mod:`lagrangian.numerics.state`)

    E = T + V                                     energy
    h = sum_j q_dot_j dL/dq_dot_j - L             energy function, conserved when dL/dt = 0

Every function takes the parameters as an array ``p`` in the order of ``eom.parameters``, so a
new mass needs no new compilation, and works on one state (q of shape (n,)) or a batch (q of
shape (k, n)).  Compilation is cached per EquationsOfMotion object.

>>> import numpy as np, lagrangian as lg
>>> compiled = compile_equations(lg.derive(lg.examples.simple_pendulum()))
>>> compiled.state_names, compiled.parameters
(('theta', 'theta_dot'), ('m', 'g', 'l'))
>>> compiled.rhs(0.0, np.array([np.pi / 2, 0.0]), np.array([1.0, 9.81, 1.0]))
array([ 0.  , -9.81])
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeAlias

import numpy as np
import symengine as se
import sympy as sp
from scipy.linalg.lapack import dgesv

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.derivation.terms import euler_lagrange_terms, matrix_piece
from lagrangian.errors import SimulationError, SimulationInputError
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.numerics.state_equations import StateEquations, state_equations
from lagrangian.symbolic.caches import IdentityCache

#: Time: one float, or one per state of a batch.
Time: TypeAlias = "float | np.ndarray"

_CACHE: IdentityCache[EquationsOfMotion, CompiledEquations] = IdentityCache()


def compile_equations(eom: EquationsOfMotion) -> CompiledEquations:
    """The numeric functions of ``eom``, compiled once per EquationsOfMotion object.

    Raises SimulationInputError when ``eom`` has algebraic coordinates (not supported yet)
    or uses names that are neither coordinates nor parameters.
    """
    return _CACHE.get(eom, _compile)


@dataclass(frozen=True)
class CompiledEquations:
    """NumPy functions of one system's equations of motion.

    Attributes
    ----------
    coordinates, parameters:
        Names, in the order of the arrays q, q_dot and p.
    defaults:
        Default parameter values (None where the model gives none).
    orders:
        2 or 1 per coordinate (1: no inertia, its velocity is not part of the state).
    state_names:
        Names of the state x: every coordinate, then ``NAME_dot`` of the second-order ones.
    energy_function_differs:
        Whether h = sum q_dot dL/dq_dot - L differs from T + V (moving constraints, velocity
        potentials, parts of T of degree 0 or 1 in the velocities).
    """

    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    defaults: tuple[float | None, ...]
    orders: tuple[int, ...]
    state_names: tuple[str, ...]
    energy_function_differs: bool
    _second: np.ndarray = field(repr=False)
    _first: np.ndarray = field(repr=False)
    _system: NumericFunction = field(repr=False)
    _mass_matrix: NumericFunction = field(repr=False)
    _forcing: NumericFunction = field(repr=False)
    _energy: NumericFunction = field(repr=False)
    _energy_function: NumericFunction = field(repr=False)

    @property
    def regular(self) -> bool:
        """True when every coordinate is of second order (x = [q; q_dot])."""
        return len(self._first) == 0

    def mass_matrix(
        self, q: np.ndarray, t: Time, p: np.ndarray, qd: np.ndarray | None = None
    ) -> np.ndarray:
        """M(q, t), shape (n, n) or (k, n, n); ``qd`` only when M depends on the velocities."""
        if qd is None:
            qd = np.zeros_like(np.asarray(q, dtype=float))
        return self._mass_matrix(q, qd, t, p)

    def forcing(self, q: np.ndarray, qd: np.ndarray, t: Time, p: np.ndarray) -> np.ndarray:
        """forcing(q, q_dot, t) of M q_ddot = forcing, shape (n,) or (k, n)."""
        return self._forcing(q, qd, t, p)

    def energy(self, q: np.ndarray, qd: np.ndarray, t: Time, p: np.ndarray) -> np.ndarray:
        """E = T + V, a 0-d array or shape (k,)."""
        return self._energy(q, qd, t, p)

    def energy_function(self, q: np.ndarray, qd: np.ndarray, t: Time, p: np.ndarray) -> np.ndarray:
        """h = sum_j q_dot_j dL/dq_dot_j - L, a 0-d array or shape (k,)."""
        return self._energy_function(q, qd, t, p)

    def rhs(self, t: Time, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        """dx/dt for a state x of shape (len(state_names),) or a batch (k, len(state_names)).

        Raises SimulationError when the matrix of the state equations is singular at x.
        """
        q_dot, q_ddot = self._rates(t, x, p)
        return np.concatenate((q_dot, q_ddot), axis=-1)

    def velocities(self, t: Time, x: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Every q_dot at state x (first-order ones solved from their equations)."""
        x = np.asarray(x, dtype=float)
        if self.regular:
            return x[..., len(self.coordinates) :]
        return self._rates(t, x, p)[0]

    def state(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """The state x = [q; q_dot_S] from every q and q_dot."""
        q, qd = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
        return np.concatenate((q, qd[..., self._second]), axis=-1)

    def _rates(self, t: Time, x: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q_dot, q_ddot_S) at x: one lambdified call and one linear solve."""
        n = len(self.coordinates)
        x = np.asarray(x, dtype=float)
        q, qd_second = x[..., :n], x[..., n:]
        if x.ndim == 1:
            values = np.array(self._system.raw(q, qd_second, t, p), dtype=float)
        else:
            values = self._system(q, qd_second, t, p)
        matrix, vector = values[..., : n * n].reshape((*x.shape[:-1], n, n)), values[..., n * n :]
        z = self._solve(matrix, vector, t, x)
        if self.regular:
            return qd_second, z
        s = len(self._second)
        q_dot = np.empty_like(q)
        q_dot[..., self._second] = qd_second
        q_dot[..., self._first] = z[..., s:]
        return q_dot, z[..., :s]

    def _solve(self, matrix: np.ndarray, vector: np.ndarray, t: Time, x: np.ndarray) -> np.ndarray:
        if x.ndim == 1:
            # LAPACK's dgesv directly: a fifth of numpy.linalg.solve's overhead per call
            *_, z, info = dgesv(matrix, vector)
            if info == 0:
                return z
        else:
            try:
                return np.linalg.solve(matrix, vector[..., None])[..., 0]
            except np.linalg.LinAlgError:
                pass
        if x.ndim == 1:
            state = ", ".join(f"{name}={value:.6g}" for name, value in zip(self.state_names, x))
            where = f"at t = {float(t):.6g}, {state}"
        else:  # a batch: t and x hold one row per member
            where = "in this batch of states"
        raise SimulationError(
            f"The mass matrix is singular {where}: the equations of motion do not "
            "determine the accelerations there (a coordinate singularity, or a body "
            "without inertia)."
        )


def _compile(eom: EquationsOfMotion) -> CompiledEquations:
    equations = state_equations(eom)
    q, qd, t = list(eom.coordinates), list(eom.velocities), eom.time
    p = list(eom.parameters)
    n = len(q)
    energy, difference, differs = _energy_functions(eom)
    energy_function = energy + difference
    _require_known_symbols(eom, equations, energy, energy_function)
    qd_second = [qd[j] for j in equations.second]
    full = (q, qd, t, p)
    return CompiledEquations(
        coordinates=tuple(s.name for s in q),
        parameters=tuple(s.name for s in p),
        defaults=tuple(None if v is None else float(v) for v in eom.parameters.values()),
        orders=tuple(eom.coordinate_orders[s] for s in q),
        state_names=(*(s.name for s in q), *(s.name for s in qd_second)),
        energy_function_differs=differs,
        _second=np.array(equations.second, dtype=int),
        _first=np.array(equations.first, dtype=int),
        _system=NumericFunction(
            (q, qd_second, t, p), [*equations.matrix, *equations.vector], (n * n + n,)
        ),
        _mass_matrix=NumericFunction(full, list(eom.mass_matrix), (n, n)),
        _forcing=NumericFunction(full, list(eom.forcing), (n,)),
        _energy=NumericFunction(full, [energy], (), sympy_form=_energy_sympy(eom, 0)),
        _energy_function=NumericFunction(
            full, [energy_function], (), sympy_form=_energy_sympy(eom, difference)
        ),
    )


def _energy_functions(eom: EquationsOfMotion) -> tuple[Any, Any, bool]:
    """E = T + V, h - E where h = sum_j q_dot_j dL/dq_dot_j - L (Goldstein, 3rd ed., §2.7), and
    whether they differ: SymEngine expressions of the derivation's own T, V and U (the ones
    ``eom.kinetic_energy`` and the others convert), compiled without a conversion.

    With L = T - V - U, h - E = euler(T) - 2 T - euler(U) + U, where euler(f) = sum_j q_dot_j
    df/dq_dot_j = d/ds f(s q_dot) at s = 1 (one derivative instead of n); it vanishes when T
    is quadratic and U linear in the velocities.
    """
    terms = euler_lagrange_terms(eom.system)
    kinetic, assembly = terms.kinetic.kinetic_energy, terms.assembly
    difference = _euler(kinetic, eom.velocities) - 2 * kinetic
    if assembly.velocity_potential != 0:
        u = assembly.velocity_potential
        difference += u - _euler(u, eom.velocities)
    energy = kinetic + assembly.potential
    difference = se.expand(difference)  # SymEngine: a tenth of SymPy's time on a 10-link T
    return energy, difference, difference != 0


def _energy_sympy(eom: EquationsOfMotion, difference: Any) -> Callable[[], list[sp.Expr]]:
    """The SymPy form of E (``difference`` 0) or h = E + difference, made when first asked
    (from the System: the compiled functions must not keep ``eom``, their cache's key, alive)."""
    system = eom.system

    def form() -> list[sp.Expr]:
        energy = matrix_piece(system, "kinetic_energy") + matrix_piece(system, "potential_energy")
        if difference == 0:
            return [energy]
        return [energy + euler_lagrange_terms(system).view(difference)]

    return form


def _euler(expr: sp.Expr, velocities: tuple[sp.Symbol, ...]) -> Any:
    """sum_j v_j d expr / d v_j, as d/ds expr(s v) at s = 1 (a SymEngine expression)."""
    s = se.Symbol("_euler_scale")
    scaled = se.sympify(expr).xreplace({se.sympify(v): s * se.sympify(v) for v in velocities})
    return scaled.diff(s).xreplace({s: se.Integer(1)})


def _require_known_symbols(
    eom: EquationsOfMotion, equations: StateEquations, *scalars: Any
) -> None:
    """Every name the equations and ``scalars`` (SymPy or SymEngine) use is a coordinate, a
    velocity, the time or a parameter."""
    known = {s.name for s in (*eom.coordinates, *eom.velocities, eom.time, *eom.parameters)}
    used = equations.matrix.free_symbols | equations.vector.free_symbols
    for expr in scalars:
        used |= expr.free_symbols
    unknown = sorted({str(s) for s in used} - known)
    if unknown:
        raise SimulationInputError(
            f"The equations use {', '.join(unknown)}, which are neither coordinates nor "
            "parameters: declare them as parameters of the System to give them values."
        )
