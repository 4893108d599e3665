"""C(q, q_dot) q_dot of a planar chain read off its mass matrix, one product per monomial.

    (C q_dot)_j = sum_kl (dM_jk/dq_l - 1/2 dM_kl/dq_j) q_dot_k q_dot_l

(the Christoffel form, :mod:`lagrangian.derivation.kinetic`).  When every entry of M is a
product w_jk f_jk of parameters w_jk (symbols, numbers, their powers and sums of their
products) and at most one sine or cosine f_jk of a plain angle (a chain of links:
M_jk = l_j l_k (m_k + ... + m_n) cos(theta_j - theta_k)), each term of the sum is a number
times w_jk times a monomial f_jk' q_dot_a q_dot_b.  The terms that cancel (for a chain
every q_dot_j q_dot_k term of M_jk's derivatives) cancel here by their numbers, before any
expression is built, and what is left is (C q_dot)_j = sum_k w_jk sin(theta_j - theta_k)
q_dot_k^2: its monomials and their coefficients, which the tidying of the forcing takes
as they are instead of expanding and collecting the sum (:mod:`lagrangian.derivation.terms`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import symengine as se

from lagrangian.derivation.assemble import Assembly
from lagrangian.derivation.backend import Backend

_TRIG = (se.sin, se.cos)
_UNITS = (se.Integer(1), se.Integer(-1))


class VelocityProduct(NamedTuple):
    """One term of (C q_dot)_j: ``number * coefficient * monomial``, the coefficient free of
    the state (an entry's w_jk), the monomial a sine or cosine times two velocities."""

    monomial: Backend
    coefficient: Backend
    number: Backend

    @property
    def term(self) -> Backend:
        return self.number * self.coefficient * self.monomial


#: An entry of M as it was made: (w, f, the parts w is the product of), the entry w f.
EntrySplit = tuple[Backend, Backend, tuple[Backend, ...]]


def coriolis_products(
    mass: list[list[Backend]],
    asm: Assembly,
    splits: Mapping[tuple[int, int], EntrySplit] | None = None,
) -> tuple[tuple[VelocityProduct, ...], ...] | None:
    """The terms of (C q_dot)_j for each j, each monomial once; None unless every entry of
    the upper triangle of ``mass`` is a parameter product times at most one sine or cosine
    of a plain angle of the coordinates, and the terms of each monomial of a row come from
    one entry (then the general Christoffel sum, which adds them as expressions, is used).

    ``splits`` gives entries as they were made, w f (M's entries of planar columns): such
    an entry is not read back factor by factor when its parts are parameter products."""
    splits = splits or {}
    n = len(asm.q)
    index = {q: i for i, q in enumerate(asm.q)}
    state = {*asm.q, *asm.q_dot, *asm.q_ddot, asm.t}
    parameters: dict[Backend, bool] = {}  # factor -> whether it is a parameter factor
    # row -> (sine or cosine, a, b) -> [coefficient, number]: the monomial f q_dot_a q_dot_b
    rows: list[dict[tuple[Backend, int, int], list[Backend]]] = [{} for _ in range(n)]
    half = se.Rational(1, 2)
    for j in range(n):
        for k in range(j, n):
            made = splits.get((j, k))
            split = None if made is None else _split_as_made(made, state, parameters)
            if split is None:
                split = _parameters_times_trig(mass[j][k], state, parameters)
            if split is None:
                return None
            coefficient, trig, angle = split
            if trig is None:  # constant: no derivative
                continue
            slope = _angle_slope(trig)
            if slope is None:
                return None
            change, turned = slope
            for q, positive in angle:
                ell = index.get(q)
                if ell is None:
                    continue
                # f(a) with a = sum_i (+-1) q_i: df/dq = (+-1) f'(a)
                number = change if positive else -change
                within = (
                    _add(rows[j], turned, k, ell, coefficient, number)
                    and (j == k or _add(rows[k], turned, j, ell, coefficient, number))
                    and _add(
                        rows[ell], turned, j, k, coefficient, -number if j != k else -number * half
                    )
                )
                if not within:
                    return None
    v = asm.q_dot
    rates: dict[tuple[int, int], Backend] = {}  # q_dot_a q_dot_b, made once per pair

    def rate(a: int, b: int) -> Backend:
        known = rates.get((a, b))
        if known is None:
            known = rates[a, b] = v[a] * v[b]
        return known

    return tuple(
        tuple(
            VelocityProduct(turned * rate(a, b), coefficient, number)
            for (turned, a, b), (coefficient, number) in row.items()
            if not number.is_zero
        )
        for row in rows
    )


def _add(
    row: dict[tuple[Backend, int, int], list[Backend]],
    turned: Backend,
    a: int,
    b: int,
    coefficient: Backend,
    number: Backend,
) -> bool:
    """Add number * coefficient to the monomial turned q_dot_a q_dot_b of ``row``; False when
    the monomial has another coefficient already."""
    key = (turned, min(a, b), max(a, b))
    known = row.get(key)
    if known is None:
        row[key] = [coefficient, number]
        return True
    if known[0] is not coefficient and known[0] != coefficient:
        return False
    known[1] = known[1] + number
    return True


def _parameters_times_trig(
    entry: Backend, state: set[Backend], parameters: dict[Backend, bool]
) -> tuple[Backend, Backend | None, list[tuple[Backend, bool]]] | None:
    """(w, f, the symbols of f's angle each with whether its coefficient is +1) for an entry
    w f, f a sine or cosine of a plain angle of the state (None for an entry free of the
    state), w a product of parameter factors; else None."""
    trig = None
    angle: list[tuple[Backend, bool]] = []
    rest = []
    for factor in entry.args if entry.is_Mul else (entry,):
        if isinstance(factor, _TRIG) and trig is None:
            found = _state_angle_terms(factor, state)
            if found is None:
                return None
            trig, angle = factor, found
            continue
        plain = parameters.get(factor)
        if plain is None:
            plain = parameters[factor] = _parameter_factor(factor, state)
        if not plain:
            return None
        rest.append(factor)
    if trig is None:
        return entry, None, angle
    return (rest[0] if len(rest) == 1 else se.Mul(*rest)), trig, angle


def _split_as_made(
    made: EntrySplit, state: set[Backend], parameters: dict[Backend, bool]
) -> tuple[Backend, Backend, list[tuple[Backend, bool]]] | None:
    """What :func:`_parameters_times_trig` finds of the entry w f made as ``made``, when each
    of w's parts is a product of parameter factors (their product's factors are then such
    too, numbers and integer powers merged) and f's angle is plain of the state; else None
    (the entry is then read back)."""
    w, trig, parts = made
    for part in parts:
        plain = parameters.get(part)
        if plain is None:
            factors = part.args if part.is_Mul else (part,)
            plain = parameters[part] = all(_parameter_factor(f, state) for f in factors)
        if not plain:
            return None
    found = _state_angle_terms(trig, state)
    return None if found is None else (w, trig, found)


def _state_angle_terms(trig: Backend, state: set[Backend]) -> list[tuple[Backend, bool]] | None:
    """:func:`_plain_angle_terms` of the angle of the sine or cosine ``trig`` when it is plain
    and of the state; else None."""
    found = _plain_angle_terms(trig.args[0])
    if found is None or not any(symbol in state for symbol, _ in found):
        return None
    return found


def _plain_angle_terms(angle: Backend) -> list[tuple[Backend, bool]] | None:
    """The symbols of a plain angle (:func:`~lagrangian.derivation.trig.plain_angle`), each
    with whether its coefficient is +1 (else -1); None for an angle that is not plain."""
    found = []
    for term in angle.args if angle.is_Add else (angle,):
        if term.is_Symbol:
            found.append((term, True))
            continue
        args: tuple[Backend, ...] = term.args if term.is_Mul else ()
        if not (len(args) == 2 and args[1].is_Symbol and args[0] in _UNITS):
            return None
        found.append((args[1], args[0] == _UNITS[0]))
    return found


def _angle_slope(trig: Backend) -> tuple[Backend, Backend] | None:
    """(c, g) with c g = f'(a) for ``trig`` f(a), a sine or cosine: cos'(a) = -sin(a),
    sin'(a) = cos(a), the sine or cosine of the same angle as SymEngine's derivative writes
    it; None when that is not a sine or cosine (an angle SymEngine writes otherwise)."""
    angle = trig.args[0]
    if isinstance(trig, se.cos):
        turned, change = se.sin(angle), _UNITS[1]
    else:
        turned, change = se.cos(angle), _UNITS[0]
    return (change, turned) if isinstance(turned, _TRIG) else None


def _parameter_factor(factor: Backend, state: set[Backend]) -> bool:
    """A number, a parameter, its integer power, or a sum of products of those."""
    if factor.is_Add:
        return all(
            all(_plain(f, state) for f in (term.args if term.is_Mul else (term,)))
            for term in factor.args
        )
    return _plain(factor, state)


def _plain(factor: Backend, state: set[Backend]) -> bool:
    if factor.is_Number:
        return True
    if factor.is_Pow:
        base, exponent = factor.args
        return bool(base.is_Symbol and exponent.is_Integer and base not in state)
    return bool(factor.is_Symbol and factor not in state)
