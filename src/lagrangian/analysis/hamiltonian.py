"""The Hamiltonian by the Legendre transform, and Hamilton's equations (Goldstein, Classical
Mechanics, 3rd ed., §8.1).

    p = dL/dq_dot,    H(q, p, t) = sum_j p_j q_dot_j - L    with q_dot = q_dot(q, p, t).

When L is quadratic in the velocities, L = 1/2 q_dot^T W q_dot + b.q_dot + L0, the momenta
p = W q_dot + b invert linearly and

    H = 1/2 (p - b)^T W^-1 (p - b) - L0

(a charge in a field: b = q A, L0 = -q phi, H = (p - q A)^2/(2 m) + q phi).  Hamilton's
equations, with applied forces Q and a dissipation function F:

    q_dot = dH/dp,    p_dot = -dH/dq + Q - dF/dq_dot.

W^-1 written out grows about eightfold with each coupled coordinate (the n! terms of each
entry, nested by elimination): its size is predicted from the entries of W before it is built
(:func:`elimination_sizes`), and past the size limit (:mod:`lagrangian.size_limits`) the
Hamiltonian is refused with that reason (SizeLimitError).  Of a long H, Hamilton's equations
are written as q_dot = q_dot(q, p) and p_dot = dL/dq at q_dot(q, p) (+ Q - dF/dq_dot), equal
to the derivatives of H (dH/dq = -dL/dq, Goldstein §8.1) and a fraction of their size.

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
from lagrangian.analysis.at_rest import (
    VelocityFree,
    expression_at_rest,
    velocity_monomial,
)
from lagrangian.analysis.momenta import momentum_symbols
from lagrangian.analysis.simplification import QUICK, simplify_small
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.energies import rest_potential
from lagrangian.derivation.steps import step_momenta, step_slopes
from lagrangian.errors import AnalysisError, SizeLimitError
from lagrangian.size_limits import active_operations, check_size, operations
from lagrangian.symbolic.probe import (
    DIGITS,
    SEED,
    depends_on,
    generic_rank,
    is_small,
    random_values,
)

#: Operations of H up to which Hamilton's equations are its derivatives, simplified; a longer
#: H (a chain of four links or more) has dH/dq several times longer than the equal
#: -dL/dq at q_dot(q, p) (Goldstein §8.1), which is used instead.
DIFFERENTIATED = 2000


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
    """W = d2L/dq_dot dq_dot^T, row j the gradient of p_j = dL/dq_dot_j (the derivation's
    first step) in the velocities it contains: n^2 second derivatives of L would be taken
    otherwise, where a gas of n/2 disks has n non-zero entries."""
    free = VelocityFree(frozenset(eom.velocities))
    column = {v: j for j, v in enumerate(eom.velocities)}
    rows = []
    for momentum in step_momenta(eom.system):
        row = _linear_row(momentum, free, column)
        if row is None:
            free = momentum.free_symbols
            row = [momentum.diff(v) if v in free else sp.Integer(0) for v in eom.velocities]
        rows.append(row)
    return sp.ImmutableMatrix(rows)


def _linear_row(
    momentum: sp.Expr, free: VelocityFree, column: Mapping[sp.Symbol, int]
) -> list[sp.Expr] | None:
    """dp/dq_dot read off the terms of p when each is a coefficient free of the velocities,
    or such a coefficient times one velocity (the momenta of every T quadratic in the
    velocities): one pass over p instead of a derivative of all of p by each velocity
    (n^3 for a chain).  None for any other p (differentiated then)."""
    terms: list[list[sp.Expr]] = [[] for _ in column]
    for term in sp.Add.make_args(momentum):
        monomial = velocity_monomial(term, free)
        if monomial is None or monomial[0] > 1:
            return None
        if monomial[0] == 1:
            terms[column[monomial[2]]].append(sp.Mul(*monomial[1]))
    return [sp.Add(*t) for t in terms]


def _refuse_singular(eom: EquationsOfMotion, hessian: sp.MatrixBase) -> None:
    n = len(eom.coordinates)
    # W is derive's M for a Lagrangian quadratic in the velocities: its rank is known then
    known = hessian == eom.mass_matrix and eom.mass_matrix_is_regular
    rank = n if known else generic_rank(hessian)
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


def _diagonal(w: sp.MatrixBase) -> bool:
    """``Matrix.is_diagonal`` (every entry off the diagonal zero), stopping at the first
    that is not: a chain's dense W would have each of its n^2 entries asked."""
    return not any(
        w[i, j] != 0 and w[i, j].is_zero is not True
        for i in range(w.rows)
        for j in range(w.cols)
        if i != j
    )


def _legendre_quadratic(eom: EquationsOfMotion, w: sp.MatrixBase, p: tuple[sp.Symbol, ...]):
    """H = 1/2 (p - b)^T W^-1 (p - b) - L0 and q_dot = W^-1 (p - b), written as
    sum (p_j - b_j)^2/(2 W_jj) for a diagonal W and with W^-1 = adj(W)/det(W) otherwise."""
    free = VelocityFree(frozenset(eom.velocities))
    shifted = sp.Matrix(
        [pj - expression_at_rest(m, free) for pj, m in zip(p, step_momenta(eom.system))]
    )
    n = w.rows
    if _diagonal(w):
        velocities = [shifted[j] / w[j, j] for j in range(n)]
        kinetic = sp.Add(*[shifted[j] ** 2 / (2 * w[j, j]) for j in range(n)])
    elif n <= 3:
        det = sp.factor(sp.expand(w.det(method="berkowitz")))
        adjugate = w.adjugate()
        velocities = [sp.expand((adjugate.row(j) * shifted)[0, 0]) / det for j in range(n)]
        kinetic = sp.expand((shifted.T * adjugate * shifted)[0, 0]) / (2 * det)
    else:
        _refuse_long_inverse(w, shifted)
        solved = w.LUsolve(shifted)
        velocities = list(solved)
        kinetic = (shifted.T * solved)[0, 0] / 2
    # L0 last: a W^-1 too long to write out is refused before anything else is built
    return kinetic + rest_potential(eom.system), dict(zip(eom.velocities, velocities))


def elimination_sizes(w: sp.MatrixBase, rhs: sp.MatrixBase) -> list[int]:
    """The operations of each entry of W^-1 rhs as Gaussian elimination writes it (what
    ``Matrix.LUsolve`` builds), found from the operations of the entries alone: each step
    a_ij - a_ik a_kj / a_kk adds the sizes of four entries, so a dense n x n matrix whose
    entries depend on the coordinates gives entries about 8^n times longer than its own (the
    n! terms of the expanded inverse, nested)."""
    n = w.rows
    a: list[list[int | None]] = [
        [None if w[i, j] == 0 else operations(w[i, j]) for j in range(n)] for i in range(n)
    ]
    b: list[int | None] = [None if e == 0 else operations(e) for e in rhs]

    def added(*sizes: int | None) -> int | None:
        kept = [s for s in sizes if s is not None]
        return sum(kept) + len(kept) - 1 if kept else None

    def multiplied(*sizes: int | None) -> int | None:
        known = [s for s in sizes if s is not None]
        return sum(known) + len(known) if len(known) == len(sizes) else None

    for k in range(n):
        pivot = a[k][k] or 0
        for i in range(k + 1, n):
            factor = multiplied(a[i][k], pivot)  # a_ik / a_kk
            if factor is None:
                continue
            for j in range(k + 1, n):
                a[i][j] = added(a[i][j], multiplied(factor, a[k][j]))
            b[i] = added(b[i], multiplied(factor, b[k]))
    x: list[int | None] = [None] * n
    for i in reversed(range(n)):
        products = [multiplied(a[i][j], x[j]) for j in range(i + 1, n)]
        x[i] = multiplied(added(b[i], *products), a[i][i] or 0)
    return [size or 0 for size in x]


def _refuse_long_inverse(w: sp.MatrixBase, shifted: sp.MatrixBase) -> None:
    """SizeLimitError, before anything is built, when q_dot = W^-1 (p - b) written out would
    pass the size limit (:func:`lagrangian.size_limits.active_operations`)."""
    longest = max(elimination_sizes(w, shifted))
    limit = active_operations()
    if longest <= limit:
        return
    n = w.rows
    raise SizeLimitError(
        f"the Hamiltonian written out needs W^-1 for the {n} x {n} mass matrix "
        "W = d2L/dq_dot2, whose entries depend on the coordinates: its velocities q_dot(q, p) "
        f"would have about {longest:,} operations, more than the size limit of {limit:,.0f} "
        "(a dense inverse grows about eightfold with each coordinate). H is still "
        "1/2 (p - b)^T W(q)^-1 (p - b) - L(q, 0, t) with b = dL/dq_dot at rest and W the mass "
        "matrix that derive writes out; Hamilton's equations are the equations of motion "
        "with p = W q_dot + b. To have H written out: simplify the model (fewer coupled "
        "coordinates), or raise the size limit (lagrangian --size-limit, "
        "analyze(..., size_limit=), $LAGRANGIAN_SIZE_LIMIT)"
    )


def _sample_point(symbols: set[sp.Symbol]) -> dict[sp.Symbol, sp.Float]:
    """A generic point (positive values, so the real branch near positive velocities)."""
    values = random_values(symbols, random.Random(SEED))
    return {s: sp.Float(v, DIGITS) for s, v in values.items()}


def _general(eom: EquationsOfMotion, p: tuple[sp.Symbol, ...]):
    """Solve p = dL/dq_dot with sympy.solve; of several branches, keep the one that inverts
    the map at a sample point (the real one, near positive velocities)."""
    momenta = list(step_momenta(eom.system))
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
    for v, value in velocities.items():
        check_size(value, f"analyze: the velocity {v} as a function of (q, p)")
    check_size(h, "analyze: the Hamiltonian H(q, p)")
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
    if is_small(h, DIFFERENTIATED):
        rates = [simplify_small(h.diff(pj), QUICK) for pj in legendre.momenta]
        p_rates = [simplify_small(-h.diff(q) + f, QUICK) for q, f in zip(eom.coordinates, forces)]
    else:  # dH/dp = q_dot(q, p) and dH/dq = -dL/dq there: a fraction of the size of dH/dq
        rates = [velocities[v] for v in eom.velocities]
        slopes = step_slopes(eom.system)
        p_rates = [s.xreplace(velocities) + f for s, f in zip(slopes, forces)]
    for p_j, rate in zip(legendre.momenta, p_rates):
        check_size(rate, f"analyze: Hamilton's equation for d{p_j}/dt")
    return HamiltonEquations(
        coordinates=legendre.coordinates,
        momenta=legendre.momenta,
        coordinate_rates=sp.ImmutableMatrix(rates),
        momentum_rates=sp.ImmutableMatrix(p_rates),
    )
