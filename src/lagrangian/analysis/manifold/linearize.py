"""Linearization on the constraint manifold, by the method of sympy.physics.mechanics'
Linearizer (Peterson, Gede and Hubbard, "Symbolic linearization of equations of motion of
constrained multibody systems", Multibody Syst. Dyn. 33, 2015).

With the multiplier form S(q, t) z = R(q, q_dot, u, t), z = [q_ddot; lambda],

    S = [[M, -A^T], [A, 0]],    R = [forcing; gamma],

the constrained accelerations and their derivatives at the operating point (implicit
differentiation, as for M q_ddot = forcing) are

    z0 = S0^-1 R0,      dz/dw = S0^-1 (dR/dw - dS/dw z0)      (w any of q, q_dot, u).

The deviations are then confined to the manifold at the linear level: holonomic constraints at
position level, every constraint at velocity level,

    A_h dq = 0                  ->  dq     = P dq_i                 (q_i independent),
    A dv + d(A q_dot + b)/dq dq = 0 ->  dv = U_q dq + U_u du_i      (u_i independent),

and the state x = [dq_i; du_i] (n - r_h + n - r entries) obeys x_dot = A_red x + B_red u with

    dq_i_dot = E_q (U_q P dq_i + U_u du_i),
    du_i_dot = E_u (dq_ddot/dq P dq_i + dq_ddot/dq_dot (U_q P dq_i + U_u du_i) + dq_ddot/du u),

E_q, E_u picking the independent entries.  Without constraints P = U_u = I, U_q = 0 and this
is the usual [[0, I], [da/dq, da/dq_dot]].
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import evaluate, frozen, is_zero_value
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold
from lagrangian.analysis.partition import dependent_columns
from lagrangian.analysis.simplification import QUICK, simplify_small, simplify_small_matrix
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.probe import SEED, generic_rank, is_zero, random_values
from lagrangian.symbolic.symbols import name_of


@dataclass(frozen=True)
class ReducedStateSpace:
    """x_dot = A x + B u on the manifold, x = ``state_vector`` (independent coordinates, then
    independent velocities); ``embedding`` maps x to the deviations of every coordinate and
    velocity, [dq; dq_dot] = embedding x; ``dependent`` the eliminated coordinates and
    velocities; ``accelerations`` and ``multipliers`` their values at the operating point."""

    A: sp.ImmutableMatrix
    B: sp.ImmutableMatrix
    state_vector: tuple[sp.Symbol, ...]
    dependent: tuple[sp.Symbol, ...]
    embedding: sp.ImmutableMatrix
    accelerations: sp.ImmutableMatrix
    multipliers: Mapping[sp.Symbol, sp.Expr]


@dataclass(frozen=True)
class MultiplierPieces:
    """The pieces of the multiplier form M q_ddot = forcing + A^T lambda with the rows
    A q_dot + b = 0 and A q_ddot = gamma, the parameter substitutions made."""

    mass: sp.Matrix
    forcing: sp.Matrix
    jacobian: sp.Matrix
    rates: sp.Matrix
    gamma: sp.Matrix

    def depends_on(self, symbols: Sequence[sp.Symbol]) -> list[sp.Symbol]:
        """The ``symbols`` that any of the pieces contains."""
        parts = (self.mass, self.forcing, self.jacobian, self.rates, self.gamma)
        return [s for s in symbols if any(s in p.free_symbols for p in parts)]


def pieces(eom: EquationsOfMotion, manifold: ConstraintManifold, subs: Mapping) -> MultiplierPieces:
    """The matrices of the multiplier form with ``subs`` made."""
    values = dict(subs)
    return MultiplierPieces(
        sp.Matrix(eom.mass_matrix).xreplace(values),
        sp.Matrix(eom.forcing).xreplace(values),
        sp.Matrix(manifold.jacobian).xreplace(values),
        sp.Matrix(manifold.rates).xreplace(values),
        sp.Matrix(manifold.gamma).xreplace(values),
    )


def numbers_at(matrix: sp.MatrixBase, numbers: Mapping) -> list[list[float]]:
    """``matrix`` as floats at the parameter values (generic values for the rest), to
    choose dependent columns by."""
    numeric = evaluate(matrix, numbers)
    missing = numeric.free_symbols
    if missing:
        numeric = numeric.xreplace(random_values(missing, random.Random(SEED)))
    return [[float(sp.re(e)) for e in numeric.row(i)] for i in range(numeric.rows)]


def _augmented(p: MultiplierPieces) -> tuple[sp.Matrix, sp.Matrix]:
    m = p.jacobian.rows
    top = p.mass.row_join(-p.jacobian.T)
    return top.col_join(p.jacobian.row_join(sp.zeros(m, m))), p.forcing.col_join(p.gamma)


def _derivatives(p, point, variables, numbers) -> tuple[sp.Matrix, sp.Matrix]:
    """z0 = [q_ddot0; lambda0] and dz/dw for every w of ``variables`` (one column each)."""
    s, r = _augmented(p)
    s0 = s.xreplace(point)
    if generic_rank(evaluate(s0, numbers)) < s0.rows:
        raise AnalysisError(
            "The constrained mass matrix [[M, -A^T], [A, 0]] is singular at this state (a "
            "singular point of the coordinates or of the constraints, or a coordinate "
            "without inertia); linearize about another state."
        )
    z0 = s0.LUsolve(r.xreplace(point)).applyfunc(lambda e: simplify_small(e, QUICK))
    columns = [r.diff(w).xreplace(point) - s.diff(w).xreplace(point) * z0 for w in variables]
    if not columns:
        return z0, sp.zeros(s0.rows, 0)
    return z0, s0.LUsolve(sp.Matrix.hstack(*columns))


def _choose(
    eom: EquationsOfMotion,
    manifold: ConstraintManifold,
    jacobian: sp.MatrixBase,
    numbers: Mapping,
    independent: Sequence[Any] | None,
) -> tuple[list[int], list[int]]:
    """Dependent coordinate and velocity indices (see lagrangian.analysis.partition): by
    column pivoting, or the complement of the ``independent`` names given."""
    n = len(eom.coordinates)
    numeric = numbers_at(jacobian, numbers)
    holonomic = [numeric[r] for r in manifold.holonomic_rows]
    auto_q = dependent_columns(holonomic, range(n))
    auto_u = dependent_columns(numeric, range(n), start=auto_q)
    singular = [
        f"{what}: rank {len(found)} < {len(rows)}"
        for what, found, rows in (("position", auto_q, holonomic), ("velocity", auto_u, numeric))
        if len(found) < len(rows)
    ]
    if singular:
        raise AnalysisError(
            "The constraint Jacobian loses rank at this state (" + "; ".join(singular) + "): "
            f"a singular configuration of {', '.join(manifold.labels)}; linearize about "
            "another state."
        )
    if independent is None:
        return list(auto_q), list(auto_u)
    names = {name_of(k) for k in independent}
    dep_q = [j for j, s in enumerate(eom.coordinates) if s.name not in names]
    given_u = [j for j, s in enumerate(eom.velocities) if s.name in names]
    dep_u = [j for j in range(n) if j not in given_u] if given_u else list(auto_u)
    _check_choice(holonomic, dep_q, "coordinates", eom.coordinates)
    _check_choice(numeric, dep_u, "velocities", eom.velocities)
    return dep_q, dep_u


def _check_choice(rows: list[list[float]], dependent: list[int], what: str, symbols) -> None:
    """``dependent`` must be as many as the rows and make them invertible."""
    picked = [[row[j] for j in dependent] for row in rows]
    if len(dependent) == len(rows) and len(dependent_columns(picked, range(len(dependent)))) == len(
        rows
    ):
        return
    names = ", ".join(symbols[j].name for j in dependent) or "none"
    raise AnalysisError(
        f"The independent {what} given leave {names} to be eliminated, but the constraints "
        f"fix {len(rows)} of the {what}, and not those; give {len(symbols) - len(rows)} "
        f"independent {what} whose complement the constraints determine (or none, to have "
        "them chosen)."
    )


def reduced_state_space(
    eom: EquationsOfMotion,
    manifold: ConstraintManifold,
    point: Mapping[sp.Symbol, sp.Expr],
    inputs: Sequence[sp.Symbol],
    subs: Mapping[sp.Symbol, sp.Expr],
    numbers: Mapping[sp.Symbol, sp.Expr],
    independent: Sequence[Any] | None = None,
) -> ReducedStateSpace:
    """x_dot = A x + B u on the manifold about ``point`` (see the module docstring)."""
    q, v, n = list(eom.coordinates), list(eom.velocities), len(eom.coordinates)
    p = pieces(eom, manifold, subs)
    point = dict(point)
    z0, dz = _derivatives(p, point, [*q, *v, *inputs], numbers)
    jq, jv, ju = dz[:n, :n], dz[:n, n : 2 * n], dz[:n, 2 * n :]
    jacobian = p.jacobian.xreplace(point)
    dep_q, dep_u = _choose(eom, manifold, jacobian, numbers, independent)
    ind_q = [j for j in range(n) if j not in dep_q]
    ind_u = [j for j in range(n) if j not in dep_u]
    holonomic = list(manifold.holonomic_rows)
    position = tangent_map(jacobian.extract(holonomic, list(range(n))), dep_q, ind_q, n)
    rate = (p.jacobian * sp.Matrix(v) + p.rates).jacobian(q).xreplace(point)
    speeds = jacobian.extract(list(range(jacobian.rows)), dep_u)
    u_u = tangent_map(jacobian, dep_u, ind_u, n)
    u_q = sp.zeros(n, n)
    if dep_u:
        u_q_dep = -speeds.LUsolve(rate)
        for k, j in enumerate(dep_u):
            u_q[j, :] = u_q_dep[k, :]
    e_q, e_u = _selector(ind_q, n), _selector(ind_u, n)
    top = (e_q * u_q * position).row_join(e_q * u_u)
    bottom = (e_u * (jq + jv * u_q) * position).row_join(e_u * jv * u_u)
    a = simplify_small_matrix(top.col_join(bottom), QUICK)
    b = simplify_small_matrix(sp.zeros(len(ind_q), len(inputs)).col_join(e_u * ju), QUICK)
    embedding = position.row_join(sp.zeros(n, len(ind_u))).col_join((u_q * position).row_join(u_u))
    return ReducedStateSpace(
        A=sp.ImmutableMatrix(a),
        B=sp.ImmutableMatrix(b),
        state_vector=(*(q[j] for j in ind_q), *(v[j] for j in ind_u)),
        dependent=(*(q[j] for j in dep_q), *(v[j] for j in dep_u)),
        embedding=simplify_small_matrix(embedding, QUICK),
        accelerations=sp.ImmutableMatrix(z0[:n, :]),
        multipliers=frozen(dict(zip(manifold.multipliers, z0[n:, :]))),
    )


def _selector(indices: list[int], n: int) -> sp.Matrix:
    """The rows ``indices`` of the n x n identity."""
    return sp.Matrix(len(indices), n, lambda i, j: 1 if j == indices[i] else 0)


def tangent_map(jacobian: sp.MatrixBase, dep: list[int], ind: list[int], n: int) -> sp.Matrix:
    """The n x len(ind) map from the independent deviations to all of them, for
    jacobian d = 0: identity rows for ``ind``, -J_dep^-1 J_ind rows for ``dep`` (a basis of
    the tangent space of the constraints, written in the independent coordinates)."""
    result = sp.zeros(n, len(ind))
    for k, j in enumerate(ind):
        result[j, k] = 1
    if dep:
        rows = list(range(jacobian.rows))
        solved = -jacobian.extract(rows, dep).LUsolve(jacobian.extract(rows, ind))
        for k, j in enumerate(dep):
            result[j, :] = solved[k, :]
    return result


def _vanishes_here(expr: sp.Expr, numbers: Mapping) -> bool:
    """0 at the parameter values (identically, when some have no value)."""
    value = evaluate(expr, numbers)
    return is_zero(value) if value.free_symbols else abs(complex(value)) < 1e-9


def manifold_solution_note(
    eom: EquationsOfMotion,
    manifold: ConstraintManifold,
    reduced: ReducedStateSpace,
    state: Mapping[sp.Symbol, sp.Expr],
    subs: Mapping[sp.Symbol, sp.Expr],
    numbers: Mapping[sp.Symbol, sp.Expr],
) -> tuple[bool, list[str]]:
    """Whether the state is an equilibrium or a steady motion on the manifold (the
    constrained accelerations vanish and nothing the equations or the constraints depend
    on moves), and notes saying why not."""
    notes = []
    left = [
        f"{a.name} = {simplify_small(x)}"
        for a, x in zip(eom.accelerations, reduced.accelerations)
        if not _vanishes_here(x, numbers)
    ]
    if left:
        notes.append(
            f"not a solution: at this state {', '.join(left)} (linearized at this instant)"
        )
    moving = [q for q, v in zip(eom.coordinates, eom.velocities) if not is_zero_value(state[v])]
    drifting = pieces(eom, manifold, subs).depends_on(moving)
    if drifting:
        notes.append(
            f"the equations or constraints depend on {', '.join(q.name for q in drifting)}, "
            "which moves: A changes along the motion"
        )
    if pieces(eom, manifold, subs).depends_on([eom.time]):
        notes.append(f"the equations depend on time: linearized at t = {state[eom.time]}")
    steady = "a steady motion" if moving else "an equilibrium"
    if not notes:
        notes.append(f"the state is {steady} on the constraint manifold")
    kept = ", ".join(s.name for s in reduced.state_vector)
    gone = ", ".join(s.name for s in reduced.dependent) or "none"
    notes.append(f"state vector ({kept}); eliminated at the linear level: {gone}")
    return len(notes) == 2 and notes[0].startswith("the state is"), notes
