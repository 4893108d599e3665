"""The Hamiltonian by the Legendre transform, and Hamilton's equations (Goldstein, Classical
Mechanics, 3rd ed., §8.1).

    p = dL/dq_dot,    H(q, p, t) = sum_j p_j q_dot_j - L    with q_dot = q_dot(q, p, t).

When L is quadratic in the velocities, L = 1/2 q_dot^T W q_dot + b.q_dot + L0, the momenta
p = W q_dot + b invert linearly and

    H = 1/2 (p - b)^T W^-1 (p - b) - L0

(a charge in a field: b = q A, L0 = -q phi, H = (p - q A)^2/(2 m) + q phi).  Hamilton's
equations, with applied forces Q and a dissipation function F:

    q_dot = dH/dp,    p_dot = -dH/dq + Q - dF/dq_dot.

>>> import lagrangian as lg
>>> hamiltonian(lg.examples.simple_pendulum()).hamiltonian
-g*l*m*cos(theta) + p_theta**2/(2*l**2*m)
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, equations_of, frozen
from lagrangian.analysis.momenta import momentum_symbols
from lagrangian.analysis.simplification import QUICK, simplify_small
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.model.probe import DIGITS, SEED, depends_on, generic_rank, random_values


@dataclass(frozen=True)
class Hamiltonian:
    """H(q, p, t) and the inverse Legendre map q_dot(q, p, t); for a constrained system,
    in its reduced coordinates, with the ``eliminated`` ones as functions of them."""

    hamiltonian: sp.Expr
    coordinates: tuple[sp.Symbol, ...]
    momenta: tuple[sp.Symbol, ...]
    velocities: Mapping[sp.Symbol, sp.Expr]
    reason: str
    eliminated: Mapping[sp.Symbol, sp.Expr] = frozen({})


@dataclass(frozen=True)
class HamiltonEquations:
    """q_dot = dH/dp and p_dot = -dH/dq + Q - dF/dq_dot, in (q, p, t)."""

    coordinates: tuple[sp.Symbol, ...]
    momenta: tuple[sp.Symbol, ...]
    coordinate_rates: sp.ImmutableMatrix
    momentum_rates: sp.ImmutableMatrix


def velocity_hessian(eom: EquationsOfMotion) -> sp.ImmutableMatrix:
    """W = d2L/dq_dot dq_dot^T."""
    return sp.ImmutableMatrix(sp.hessian(eom.lagrangian, eom.velocities))


def _refuse_singular(eom: EquationsOfMotion, hessian: sp.MatrixBase) -> None:
    n = len(eom.coordinates)
    rank = generic_rank(hessian)
    if rank == n:
        return
    idle = [q.name for j, q in enumerate(eom.coordinates) if all(e == 0 for e in hessian.row(j))]
    which = (
        f"L does not depend on the velocities of {', '.join(idle)}"
        if idle
        else "the velocities enter L only in fewer combinations than there are coordinates"
    )
    raise AnalysisError(
        f"singular Legendre transform: d2L/dq_dot2 has rank {rank} < {n}; {which}, so "
        "p = dL/dq_dot cannot be solved for the velocities (those momenta are constraints, "
        "not equations for the velocities)."
    )


def _legendre_quadratic(eom: EquationsOfMotion, w: sp.MatrixBase, p: tuple[sp.Symbol, ...]):
    """H = 1/2 (p - b)^T W^-1 (p - b) - L0 and q_dot = W^-1 (p - b), written as
    sum (p_j - b_j)^2/(2 W_jj) for a diagonal W and with W^-1 = adj(W)/det(W) otherwise."""
    at_rest = {v: 0 for v in eom.velocities}
    shifted = sp.Matrix([pj - s.dL_dvelocity.xreplace(at_rest) for pj, s in zip(p, eom.steps)])
    l0 = sp.expand(eom.lagrangian.xreplace(at_rest))
    n = w.rows
    if w.is_diagonal():
        velocities = [shifted[j] / w[j, j] for j in range(n)]
        kinetic = sp.Add(*[shifted[j] ** 2 / (2 * w[j, j]) for j in range(n)])
    elif n <= 3:
        det = sp.factor(sp.expand(w.det(method="berkowitz")))
        adjugate = w.adjugate()
        velocities = [sp.expand((adjugate.row(j) * shifted)[0, 0]) / det for j in range(n)]
        kinetic = sp.expand((shifted.T * adjugate * shifted)[0, 0]) / (2 * det)
    else:
        solved = w.LUsolve(shifted)
        velocities = list(solved)
        kinetic = (shifted.T * solved)[0, 0] / 2
    return kinetic - l0, dict(zip(eom.velocities, velocities))


def _sample_point(symbols: set[sp.Symbol]) -> dict[sp.Symbol, sp.Float]:
    """A generic point (positive values, so the real branch near positive velocities)."""
    values = random_values(symbols, random.Random(SEED))
    return {s: sp.Float(v, DIGITS) for s, v in values.items()}


def _general(eom: EquationsOfMotion, p: tuple[sp.Symbol, ...]):
    """Solve p = dL/dq_dot with sympy.solve; of several branches, keep the one that inverts
    the map at a sample point (the real one, near positive velocities)."""
    momenta = [s.dL_dvelocity for s in eom.steps]
    equations = [pj - mj for pj, mj in zip(p, momenta)]
    try:
        branches = sp.solve(equations, list(eom.velocities), dict=True)
    except NotImplementedError as error:
        raise AnalysisError(
            f"The Legendre map p = dL/dq_dot could not be inverted: {error}"
        ) from error
    symbols = set().union(*[m.free_symbols for m in momenta]) | set(eom.velocities)
    sample = _sample_point(symbols)
    p_sample = {pj: mj.xreplace(sample).evalf(DIGITS) for pj, mj in zip(p, momenta)}
    good = []
    for branch in branches:
        if len(branch) < len(p):
            continue
        back = [(branch[v].xreplace(sample).xreplace(p_sample) - sample[v]) for v in branch]
        if all(abs(complex(e.evalf(DIGITS))) < 1e-12 for e in back):
            good.append(branch)
    if not good:
        raise AnalysisError("The Legendre map p = dL/dq_dot has no inverse SymPy could find.")
    solved = good[0]
    h = sum((pj * v for pj, v in zip(p, eom.velocities)), sp.Integer(0)) - eom.lagrangian
    return h.xreplace(solved), solved


def hamiltonian(subject: Subject) -> Hamiltonian:
    """H(q, p, t) by the Legendre transform, momenta named ``p_q``.

    Refused (AnalysisError "singular Legendre transform") when d2L/dq_dot2 is singular.

    >>> import lagrangian as lg
    >>> hamiltonian(lg.examples.planet()).hamiltonian
    -m*mu/r + p_r**2/(2*m) + p_theta**2/(2*m*r**2)
    """
    eom = equations_of(subject)
    p = momentum_symbols(eom)
    w = velocity_hessian(eom)
    _refuse_singular(eom, w)
    if depends_on(w, eom.velocities):
        h, velocities = _general(eom, p)
        reason = "p = dL/dq_dot solved for the velocities by sympy.solve (L not quadratic)"
    else:
        h, velocities = _legendre_quadratic(eom, w, p)
        reason = "L quadratic in the velocities: q_dot = W^-1 (p - b), H = (p-b)W^-1(p-b)/2 - L0"
    return Hamiltonian(
        hamiltonian=h,
        coordinates=tuple(eom.coordinates),
        momenta=p,
        velocities=frozen(velocities),
        reason=reason,
    )


def hamilton_equations(subject: Subject, legendre: Hamiltonian | None = None) -> HamiltonEquations:
    """q_dot = dH/dp, p_dot = -dH/dq + Q - dF/dq_dot (forces written in q, p, t).

    >>> import lagrangian as lg
    >>> eqs = hamilton_equations(lg.examples.simple_pendulum())
    >>> eqs.coordinate_rates[0], eqs.momentum_rates[0]
    (p_theta/(l**2*m), -g*l*m*sin(theta))
    """
    eom = equations_of(subject)
    legendre = legendre or hamiltonian(eom)
    h, velocities = legendre.hamiltonian, dict(legendre.velocities)
    forces = [
        (q_force + friction).xreplace(velocities)
        for q_force, friction in zip(eom.generalized_forces, eom.dissipation_forces)
    ]
    rates = [simplify_small(h.diff(pj), QUICK) for pj in legendre.momenta]
    p_rates = [simplify_small(-h.diff(q) + f, QUICK) for q, f in zip(eom.coordinates, forces)]
    return HamiltonEquations(
        coordinates=legendre.coordinates,
        momenta=legendre.momenta,
        coordinate_rates=sp.ImmutableMatrix(rates),
        momentum_rates=sp.ImmutableMatrix(p_rates),
    )
