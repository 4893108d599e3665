"""Linearization about any state: x_dot = A x + B u, x = [q; q_dot] (deviations).

With q_ddot = a(q, q_dot, u, t) = M^-1 forcing, about x0, u0 (a0 = a there):

    A = [[0, I], [da/dq, da/dq_dot]],    B = [[0], [da/du]],
    da/dz = M^-1 (d forcing/dz - dM/dz a0)        (z any of q, q_dot, u)

The state may be a steady motion with non-zero velocities (a conical pendulum: theta fixed,
phi_dot constant); it is a solution when a0 = 0 and the equations do not depend on the
coordinates that move.  Otherwise the linearization still holds at that instant, and the note
says so.  Eigenvalues of A: frequencies are the positive imaginary parts (rad/s), growth
rates the positive real parts (1/s).

>>> import lagrangian as lg
>>> lin = linearize(lg.examples.simple_pendulum(), {"theta": 0})
>>> lin.A.tolist()
[[0, 1], [-g/l, 0]]
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import sympy as sp

from lagrangian.analysis.arguments import (
    Subject,
    Values,
    evaluate,
    frozen,
    is_zero_value,
    operating_state,
    positive_parameters,
)
from lagrangian.analysis.evaluation import EvaluationContext, evaluation_context
from lagrangian.analysis.manifold.constraint_manifold import (
    constraint_manifold,
    require_on_manifold,
)
from lagrangian.analysis.manifold.linearize import manifold_solution_note, reduced_state_space
from lagrangian.analysis.simplification import QUICK, simplify_small, simplify_small_matrix
from lagrangian.analysis.spectrum import eigenvalues, frequencies, growth_rates
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.symbolic.probe import depends_on, is_zero
from lagrangian.symbolic.symbols import name_of

SYMBOLIC_SIZE = 6  # largest A whose eigenvalues are computed symbolically on request


@dataclass(frozen=True)
class Linearization:
    """x_dot = A x + B u about ``state`` (and the inputs at their parameter values)."""

    state: Mapping[sp.Symbol, sp.Expr]
    state_vector: tuple[sp.Symbol, ...]
    inputs: tuple[sp.Symbol, ...]
    A: sp.ImmutableMatrix
    B: sp.ImmutableMatrix
    eigenvalues: tuple[sp.Expr, ...]
    frequencies: tuple[sp.Expr, ...]
    growth_rates: tuple[sp.Expr, ...]
    is_solution: bool
    note: str
    dependent: tuple[sp.Symbol, ...] = ()
    embedding: sp.ImmutableMatrix | None = None
    multipliers: Mapping[sp.Symbol, sp.Expr] = frozen({})
    #: A with every parameter that has a value replaced by it (A itself keeps the symbols);
    #: None when that changes nothing.
    A_at_values: sp.ImmutableMatrix | None = None

    def full_deviation(self, x: Sequence[Any]) -> sp.ImmutableMatrix:
        """[dq; dq_dot] of every coordinate and velocity for a deviation ``x`` of the state
        vector (on a constraint manifold the dependent ones follow from the independent)."""
        vector = sp.Matrix(list(x))
        if self.embedding is None:
            return sp.ImmutableMatrix(vector)
        return sp.ImmutableMatrix(self.embedding * vector)


def _inputs(eom: EquationsOfMotion, inputs: Sequence[Any]) -> tuple[sp.Symbol, ...]:
    by_name = {p.name: p for p in eom.parameters}
    names = [name_of(u) for u in inputs]
    unknown = [n for n in names if n not in by_name]
    if unknown:
        raise AnalysisError(
            f"Inputs must be parameters of the system: {', '.join(unknown)} are not "
            f"(parameters: {', '.join(sorted(by_name))})."
        )
    return tuple(by_name[n] for n in names)


def _rate_jacobian(m, f, variables, point, acc0, m0_inv) -> sp.Matrix:
    """M^-1 (df/dz - dM/dz a0) at the point, one column per variable z."""
    columns = []
    for z in variables:
        column = f.diff(z).xreplace(point) - m.diff(z).xreplace(point) * acc0
        columns.append(m0_inv * column)
    return sp.Matrix.hstack(*columns) if columns else sp.zeros(m.rows, 0)


def _at_rest(acc0: sp.MatrixBase, numbers: Mapping[sp.Symbol, sp.Expr]) -> bool:
    """a0 = 0 identically, or at the parameter values."""
    if all(is_zero(a) for a in acc0):
        return True
    numeric = evaluate(acc0, numbers)
    return not numeric.free_symbols and all(abs(complex(a)) < 1e-9 for a in numeric)


def _solution_note(eom, m, f, state, acc0, numbers) -> tuple[bool, list[str]]:
    notes = []
    if not _at_rest(acc0, numbers):
        values = ", ".join(
            f"{a.name} = {simplify_small(v)}" for a, v in zip(eom.accelerations, acc0)
        )
        notes.append(f"not a solution: at this state {values} (linearized at this instant)")
    moving = [q for q, v in zip(eom.coordinates, eom.velocities) if not is_zero_value(state[v])]
    drifting = [q.name for q in moving if depends_on(m, [q]) or depends_on(f, [q])]
    if drifting:
        notes.append(
            f"the equations depend on {', '.join(drifting)}, which moves: A changes along "
            "the motion"
        )
    if depends_on(f, [eom.time]) or depends_on(m, [eom.time]):
        notes.append(f"the equations depend on time: linearized at t = {state[eom.time]}")
    if not notes:
        notes.append("the state is a solution (equilibrium or steady motion)")
    return len(notes) == 1 and notes[0].startswith("the state is"), notes


def _state_space(eom, m, f, point, u) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """A, B and the accelerations a0 at the operating point."""
    if not eom.mass_matrix_is_regular:
        raise AnalysisError(
            "The mass matrix is singular, so x = [q; q_dot] is not a state: coordinate "
            f"orders {eom.orders_by_name()} (a coordinate without inertia)."
        )
    m0 = m.xreplace(point)
    if is_zero(m0.det()):
        raise AnalysisError(
            f"The mass matrix is singular at this state ({m0.tolist()}): a singular point of "
            "the coordinates; linearize about another state."
        )
    m0_inv = m0.inv()
    acc0 = sp.Matrix([simplify_small(a, QUICK) for a in m0_inv * f.xreplace(point)])
    n = len(eom.coordinates)
    lower = _rate_jacobian(m, f, (*eom.coordinates, *eom.velocities), point, acc0, m0_inv)
    a = simplify_small_matrix(
        sp.Matrix.vstack(sp.Matrix.hstack(sp.zeros(n), sp.eye(n)), lower), QUICK
    )
    b_lower = _rate_jacobian(m, f, u, point, acc0, m0_inv)
    b = simplify_small_matrix(sp.Matrix.vstack(sp.zeros(n, len(u)), b_lower), QUICK)
    return a, b, acc0


def _numeric_spectrum(a: sp.MatrixBase, numbers, notes: list[str]):
    """Eigenvalues, frequencies and growth rates at the parameter values (a note if none)."""
    numeric = evaluate(a, numbers)
    if numeric.free_symbols:
        missing = ", ".join(sorted(s.name for s in numeric.free_symbols))
        notes.append(f"no eigenvalues: {missing} have no values")
        return (), (), ()
    values = eigenvalues(numeric)
    return values, frequencies(values), growth_rates(values)


def _symbolic_spectrum(a: sp.MatrixBase, eom: EquationsOfMotion):
    forward = positive_parameters(eom)
    backward = {v: k for k, v in forward.items()}
    roots = sp.Matrix(a).xreplace(forward).eigenvals()
    values = [r for r, count in roots.items() for _ in range(count)]
    parts = [(sp.simplify(sp.im(r)), sp.simplify(sp.re(r))) for r in values]

    def positive(xs):
        kept = []
        for x in xs:
            x = x if x.is_positive else (sp.Abs(x) if x.is_positive is None and x != 0 else None)
            if x is not None and x not in kept:
                kept.append(x)
        return tuple(k.xreplace(backward) for k in kept)

    return (
        tuple(v.xreplace(backward) for v in values),
        positive(im for im, _ in parts),
        positive(re for _, re in parts),
    )


def linearize(
    subject: Subject,
    about: Values | None = None,
    inputs: Sequence[Any] = (),
    parameters: Values | None = None,
    symbolic: bool = False,
    independent: Sequence[Any] | None = None,
) -> Linearization:
    """x_dot = A x + B u about ``about`` (coordinate, ``NAME_dot`` and ``t`` values; the rest
    0); ``inputs`` are parameters treated as inputs u.  Eigenvalues are numeric at the
    parameter values, or symbolic when ``symbolic`` and A is at most 6 x 6.

    On a constrained system the state must satisfy the constraints (ConstraintError names
    each one it misses; :func:`lagrangian.constraints.project_state` moves it onto them) and
    the dependent coordinates and velocities are eliminated at the linear level
    (:mod:`lagrangian.analysis.manifold.linearize`); ``independent`` names the coordinates
    and ``NAME_dot`` velocities to keep (default: chosen by pivoting).

    >>> import lagrangian as lg
    >>> linearize(lg.examples.simple_pendulum(), {"theta": 0}).frequencies
    (3.13209195267317,)
    """
    context = evaluation_context(subject, parameters)
    return linearization_at_values(context, about, inputs, symbolic, independent)


def linearization_at_values(
    context: EvaluationContext,
    about: Values | None = None,
    inputs: Sequence[Any] = (),
    symbolic: bool = False,
    independent: Sequence[Any] | None = None,
) -> Linearization:
    """:func:`linearize` at the parameter values of ``context``."""
    eom, subs, numbers = context.eom, dict(context.substitutions), context.values
    state = operating_state(eom, about)
    u = _inputs(eom, inputs)
    m = sp.Matrix(eom.mass_matrix).xreplace(subs)
    f = sp.Matrix(eom.forcing).xreplace(subs)
    point = {**state, **{p: numbers.get(p, p) for p in u}}
    manifold = constraint_manifold(eom)
    if manifold is None:
        a, b, acc0 = _state_space(eom, m, f, point, u)
        is_solution, notes = _solution_note(eom, m, f, state, acc0, numbers)
        reduced = None
    else:
        fix = "move it onto them with lagrangian.constraints.project_state(system, state)"
        require_on_manifold(eom, state, numbers, fix)
        reduced = reduced_state_space(eom, manifold, point, u, subs, numbers, independent)
        a, b = reduced.A, reduced.B
        is_solution, notes = manifold_solution_note(eom, manifold, reduced, state, subs, numbers)
    if symbolic and a.rows <= SYMBOLIC_SIZE:
        values, freqs, growth = _symbolic_spectrum(a, eom)
    else:
        values, freqs, growth = _numeric_spectrum(a, numbers, notes)
    return Linearization(
        state=frozen(state),
        state_vector=reduced.state_vector if reduced else (*eom.coordinates, *eom.velocities),
        inputs=u,
        A=sp.ImmutableMatrix(a),
        B=sp.ImmutableMatrix(b),
        eigenvalues=values,
        frequencies=freqs,
        growth_rates=growth,
        is_solution=is_solution,
        note="; ".join(notes),
        dependent=reduced.dependent if reduced else (),
        embedding=reduced.embedding if reduced else None,
        multipliers=frozen(reduced.multipliers if reduced else {}),
        A_at_values=_at_values(a, numbers),
    )


def _at_values(
    matrix: sp.Matrix, numbers: Mapping[sp.Symbol, sp.Expr]
) -> sp.ImmutableMatrix | None:
    """``matrix`` at the parameter values (numbers to 15 digits), or None when it holds no
    parameter that has one."""
    known = {p: v for p, v in numbers.items() if p in matrix.free_symbols}
    if not known:
        return None
    return sp.ImmutableMatrix(matrix.xreplace(known).evalf(15))
