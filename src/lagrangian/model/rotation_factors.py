"""A rotation matrix given whole, recognised as a product of rotations about constant axes.

Users of sympy.physics.mechanics and of textbooks write a body's orientation as a product of
elementary matrices, R = Rz(yaw) Rx(lean) Ry(pitch) ..., multiplied out: the derivation gets
a matrix, not the sequence.  Differentiated (omega_b = vee(R^T R_dot)) and simplified back
with sin^2 + cos^2 = 1, such a matrix costs seconds to minutes per body; composed from its
factors (:func:`lagrangian.model.rotation.body_angular_velocity`) the angular velocity costs
nothing.  This module finds the factors:

    R(q, t) = F1(a1) F2(a2) ... Fm(am) C,   F_k(a) = exp(a hat(n_k)),

n_k constant unit axes (numbers or functions of the parameters), a_k the arguments of the
sines and cosines in R that move with q or t, and C a constant rotation (None when 1).

How: every moving argument a_k is replaced by an angle symbol alpha_k of its own, so R is a
function of the angles and the parameters alone.  If R is such a product, the first factor's
axis is the spatial angular velocity of its angle, vee(dR/d alpha_1 R^T), the same at every
value of the angles; peeled off, the rest is a product again.  The search runs on numbers (R
and its angle derivatives evaluated at a few random angles); the axes and C are then read off
symbolically at alpha = 0 (where every peeled factor is 1, so n_k = vee(dR/d alpha_k R^T) and
C = R there), and the product is checked against R at other random parameters and angles.
Anything that fails (an angle in two factors, a moving symbol outside a sine or cosine, a
matrix that is not a rotation) is no factoring: None, and the caller differentiates R.

>>> import sympy as sp
>>> a, b = sp.symbols("a b")
>>> Rz = sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])
>>> Rx = sp.Matrix([[1, 0, 0], [0, sp.cos(b), -sp.sin(b)], [0, sp.sin(b), sp.cos(b)]])
>>> found = factor_rotation(Rz * Rx, [a, b])
>>> [(tuple(n), angle) for n, angle in found.factors], found.tail
([((0, 0, 1), a), ((1, 0, 0), b)], None)
"""

from __future__ import annotations

import random
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np
import symengine as se
import sympy as sp

from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.native import to_symengine, to_symengine_sharing
from lagrangian.symbolic.symbols import t

#: Random angle samples the search compares the axes at, and the check's samples.
SEARCH_SAMPLES, CHECK_SAMPLES = 3, 2
#: The rates of an angle's turn recognised: multiples of 1/RATES (2 for a half angle).
RATES = 6
#: Agreement of numbers that are equal in exact arithmetic.
TOLERANCE = 1e-9
_SEED = 20070712


@dataclass(frozen=True)
class Factoring:
    """R = F1(a1) ... Fm(am) C: ``factors`` ((unit axis, angle), ...) in product order,
    ``tail`` the constant rotation C, None when it is 1."""

    factors: tuple[tuple[sp.ImmutableMatrix, sp.Expr], ...]
    tail: sp.ImmutableMatrix | None


def factor_rotation(matrix: sp.MatrixBase, coordinates: Iterable[sp.Symbol]) -> Factoring | None:
    """The factoring of the rotation ``matrix`` (module docstring) whose angles move with
    ``coordinates`` or t; None when it is not such a product (or does not move)."""
    moving = {*coordinates, t}
    matrix = sp.ImmutableMatrix(matrix)
    trig = sorted(matrix.atoms(sp.sin, sp.cos), key=sp.default_sort_key)
    angles = list(dict.fromkeys(f.args[0] for f in trig if f.args[0].free_symbols & moving))
    if not angles:
        return None
    by_name = {s.name: s for s in matrix.free_symbols}
    alphas = [_fresh(f"alpha{k}", set(by_name)) for k in range(len(angles))]
    # the angles put in and the entries differentiated and evaluated in SymEngine: SymPy's
    # substitution into nested products, diff and lambdify cost seconds
    try:
        angle_symbols = [to_symengine(a) for a in alphas]
        swap = {
            to_symengine(f): to_symengine(f.func(alphas[angles.index(f.args[0])]))
            for f in trig
            if f.args[0] in angles
        }
        memo: dict[Any, Any] = {}  # a product multiplied out repeats its parts
        entries = [to_symengine_sharing(e, memo).xreplace(swap) for e in matrix]
        symbols = set().union(*(e.free_symbols for e in entries))
        if symbols & {to_symengine(s) for s in moving}:
            return None  # a moving symbol outside the sines and cosines
        parameters = sorted(
            (by_name[str(s)] for s in symbols - set(angle_symbols)), key=sp.default_sort_key
        )
        derivatives = [[e.diff(a) for e in entries] for a in angle_symbols]
        arguments = [*angle_symbols, *(to_symengine(p) for p in parameters)]
        flat = [*entries, *(d for row in derivatives for d in row)]
        numeric = se.Lambdify(arguments, flat, backend="lambda")
    except (se.SympifyError, RuntimeError, TypeError, KeyError):
        return None
    rng = _Uniform(_SEED)
    values = rng.uniform(0.3, 1.3, len(parameters))
    order = _search(numeric, len(alphas), values, rng)
    if order is None:
        return None
    zero = {a: se.Integer(0) for a in angle_symbols}
    at_zero = se.DenseMatrix(3, 3, [e.xreplace(zero) for e in entries])
    factors = []
    for k, rate in order:
        turn = se.DenseMatrix(3, 3, [d.xreplace(zero) for d in derivatives[k]])
        axis = sp.Matrix([to_sympy(e) for e in _vee(turn * at_zero.T)])
        factors.append((_tidy(axis / rate), rate * angles[k]))
    tail = _tidy(sp.Matrix(3, 3, [to_sympy(e) for e in at_zero]))
    found = Factoring(tuple(factors), None if tail == sp.eye(3) else sp.ImmutableMatrix(tail))
    return found if _agrees(found, numeric, arguments, order, rng) else None


class _Uniform:
    """Uniform random numbers as arrays, from Python's generator: NumPy's ``random`` module
    is a further import (10 ms of CPU, 20 of wall time), paid by the first derivation of a
    process that factors a matrix (a tenth of deriving a rolling disc written with
    quaternions)."""

    def __init__(self, seed: int) -> None:
        self._rng = random.Random(seed)

    def uniform(self, low: float, high: float, size: int) -> np.ndarray:
        return np.array([self._rng.uniform(low, high) for _ in range(size)])


def _fresh(name: str, taken: set[str]) -> sp.Symbol:
    """A symbol for an angle, named apart from the matrix's own symbols (SymEngine's
    evaluation takes symbols, not dummies)."""
    while name in taken:
        name += "_"
    return sp.Symbol(name)


def _evaluated(numeric: Any, angles: np.ndarray, values: np.ndarray) -> list[np.ndarray]:
    """R and its derivatives by each angle at ``angles`` and parameter ``values``."""
    flat = np.asarray(numeric([*angles, *values]), dtype=float).ravel()
    return [flat[9 * k : 9 * k + 9].reshape(3, 3) for k in range(len(flat) // 9)]


def _search(numeric: Any, count: int, values: np.ndarray, rng: _Uniform) -> list | None:
    """The order of the factors' angles (indices), found on numbers: at each step the angle
    whose axis, seen from the factors found so far, is one constant unit vector."""
    samples = [rng.uniform(-3.0, 3.0, count) for _ in range(SEARCH_SAMPLES)]
    evaluated = [_evaluated(numeric, sample, values) for sample in samples]
    turned = [np.eye(3) for _ in samples]  # the product of the factors found, per sample
    remaining, order = list(range(count)), []
    while remaining:
        step = _first_factor(evaluated, turned, remaining)
        if step is None:
            return None
        k, axis, rate = step
        for s, sample in enumerate(samples):
            turned[s] = turned[s] @ _about(axis, float(rate) * sample[k])
        remaining.remove(k)
        order.append((k, rate))
    tails = [P.T @ e[0] for P, e in zip(turned, evaluated)]
    return order if all(np.allclose(c, tails[0], atol=TOLERANCE) for c in tails) else None


def _first_factor(evaluated: list, turned: list, remaining: list[int]) -> tuple | None:
    """(index, unit axis, rate): the angle whose turn, seen from the factors found so far,
    is about one constant axis; the rate |dR/d alpha R^T| a small rational (2 for the half
    angles of a quaternion: the factor turns by 2 alpha)."""
    for k in remaining:
        axes = [P.T @ _vee_numbers(e[1 + k] @ e[0].T) for P, e in zip(turned, evaluated)]
        norm = float(np.linalg.norm(axes[0]))
        rate = sp.Rational(round(norm * RATES), RATES)
        simple = rate > 0 and abs(norm - float(rate)) < TOLERANCE
        if simple and all(np.allclose(a, axes[0], atol=TOLERANCE) for a in axes):
            return k, axes[0] / norm, rate
    return None


def _agrees(
    found: Factoring,
    numeric: Any,
    arguments: list[Any],
    order: list[tuple[int, sp.Rational]],
    rng: _Uniform,
) -> bool:
    """The product of the factors equals R at random parameters and angles."""
    tail = sp.eye(3) if found.tail is None else found.tail
    pieces = [*(axis for axis, _ in found.factors), tail]
    entries = [to_symengine(e) for piece in pieces for e in piece]
    axes_and_tail = se.Lambdify(arguments, entries, backend="lambda")  # (the angles unused)
    for _ in range(CHECK_SAMPLES):
        sample = rng.uniform(-3.0, 3.0, len(order))
        values = rng.uniform(0.3, 1.3, len(arguments) - len(order))
        matrix = _evaluated(numeric, sample, values)[0]
        flat = np.asarray(axes_and_tail([*sample, *values]), dtype=float).ravel()
        product = np.eye(3)
        for i, (k, rate) in enumerate(order):
            product = product @ _about(flat[3 * i : 3 * i + 3], float(rate) * sample[k])
        if not np.allclose(product @ flat[-9:].reshape(3, 3), matrix, atol=TOLERANCE):
            return False
    return True


def _tidy(value: sp.MatrixBase) -> sp.ImmutableMatrix:
    """Entries in the sines and cosines of constants, expanded and reduced modulo
    sin^2 + cos^2 = 1 (cos^2 x written 1 - sin^2 x: exact, and canonical for such
    polynomials, so a unit axis comes out as (sin(lam), 0, -cos(lam)), not as products);
    numbers (most axes' entries) as they are."""
    entries = [e if e.is_Number else pythagorean_reduced(e) for e in value]
    return sp.ImmutableMatrix(value.rows, value.cols, entries)


def pythagorean_reduced(expr: sp.Expr) -> sp.Expr:
    """``expr`` expanded and reduced modulo sin^2 x + cos^2 x = 1 (cos^2 x -> 1 - sin^2 x),
    canonical for polynomials in the sines and cosines of unrelated arguments.

    >>> a = sp.Symbol("a")
    >>> pythagorean_reduced((sp.cos(a / 2) ** 2 + sp.sin(a / 2) ** 2) ** 2)
    1
    """
    expanded = sp.expand(expr)
    reduced = expanded.replace(
        lambda e: e.is_Pow and e.base.func is sp.cos and e.exp.is_Integer and e.exp >= 2,
        lambda e: (1 - sp.sin(e.base.args[0]) ** 2) ** (e.exp // 2) * e.base ** (e.exp % 2),
    )
    return expanded if reduced == expanded else sp.expand(reduced)


def _vee(skew: Any) -> list[Any]:
    return [skew[2, 1], skew[0, 2], skew[1, 0]]


def _vee_numbers(skew: np.ndarray) -> np.ndarray:
    return np.array([skew[2, 1], skew[0, 2], skew[1, 0]])


def _about(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: cos a 1 + sin a hat(n) + (1 - cos a) n n^T."""
    n = np.asarray(axis, dtype=float).ravel()
    hat = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    return np.cos(angle) * np.eye(3) + np.sin(angle) * hat + (1 - np.cos(angle)) * np.outer(n, n)
