"""Is a velocity constraint a holonomic one in disguise?  Exactness, integrating factors and
the Frobenius condition for a Pfaffian form omega = a(q, t).dq + b(q, t) dt.

- omega is *exact* when d omega = 0 (every curl component da_j/dz_i - da_i/dz_j vanishes);
  then omega = dh with h the path integral of omega, and a.q_dot + b = 0 says h_dot = 0:
  the constraint is h(q, t) = h(q(0), 0), the constant fixed by the initial state.
- omega is *integrable* when some factor mu makes mu omega exact.  By Frobenius that happens
  exactly when omega ^ d omega = 0; factors are searched among 1, 1/a_k, 1/a_k^2, 1/q_k,
  1/q_k^2, 1/(q_i q_j), 1/(q_i^2 + q_j^2) and checked by the curl of mu omega.
- A *set* of forms omega_1..omega_m is integrable when d omega_i ^ omega_1 ^ ... ^ omega_m = 0
  for every i (Frobenius); holonomic constraints take part with omega = dh.
- Otherwise the constraint is non-holonomic: the knife edge sin(phi) dx - cos(phi) dy has
  omega ^ d omega = -dx ^ dy ^ dphi != 0.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> found = integrate_form((x, y), (x, y))     # x x_dot + y y_dot = 0
>>> found.integrated, found.factor
(x**2/2 + y**2/2, 1)
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations

import numpy as np
import sympy as sp

from lagrangian.constraints.forms import (
    Form,
    describe,
    exterior_derivative,
    one_form,
    wedge,
    wedge_values,
)
from lagrangian.constraints.pfaffian import backend
from lagrangian.derivation.backend import to_backend
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import (
    SEED,
    PointFunction,
    is_small,
    is_zero,
    random_values,
    values_at,
)

#: Forms with a coefficient of more operations are decided at random points, not by symbolic
#: wedge products (whose expansion grows as the product of the coefficients' sizes: a
#: bicycle's no-slip constraint has thousands of operations).
LARGE_COEFFICIENT = 400
#: Random points at which a large form is probed, and the relative size below which a value
#: there counts as zero.
PROBES = 3
RELATIVE_ZERO = 1e-9

#: A form's value at one point: index tuple -> number.
FormValues = dict[tuple[int, ...], float]


@dataclass(frozen=True)
class Integrability:
    """The verdict on one Pfaffian form.

    ``integrated`` is h with mu omega = dh (None when not integrable or not found), so the
    constraint is h(q, t) = const; ``factor`` is mu; ``reason`` says why, in words.
    """

    integrable: bool
    integrated: sp.Expr | None
    factor: sp.Expr | None
    reason: str


def _vanishes(form: Form) -> bool:
    return all(is_zero(c) for c in form.values())


def _nonzero_part(form: Form) -> Form:
    """The components that do not vanish, simplified when small (for messages)."""
    return {k: sp.simplify(c) if is_small(c, 40) else c for k, c in form.items() if not is_zero(c)}


def integrate_form(
    coefficients: Sequence[sp.Expr], variables: Sequence[sp.Symbol]
) -> Integrability:
    """Integrability of omega = sum_k coefficients[k] d variables[k]."""
    if _large([coefficients]):
        return _probed_form(coefficients, variables)
    omega = one_form(coefficients)
    d_omega = exterior_derivative(omega, variables)
    if _vanishes(d_omega):
        return _integrated(omega, variables, sp.Integer(1), "omega is exact (d omega = 0)")
    twisted = _nonzero_part(wedge(omega, d_omega))
    if twisted:
        return Integrability(
            False,
            None,
            None,
            f"omega ^ d omega = {describe(twisted, variables)} != 0, so by Frobenius no "
            "h(q, t) has dh proportional to omega",
        )
    for factor in _candidate_factors(coefficients, variables):
        scaled = {k: sp.cancel(factor * c) for k, c in omega.items()}
        if _vanishes(exterior_derivative(scaled, variables)):
            reason = f"mu omega is exact with the integrating factor mu = {factor}"
            return _integrated(scaled, variables, factor, reason)
    return Integrability(
        True,
        None,
        None,
        "omega ^ d omega = 0, so an integrating factor exists (Frobenius), but none of the "
        "factors tried makes omega exact; the integrated form is not given",
    )


def _candidate_factors(
    coefficients: Sequence[sp.Expr], variables: Sequence[sp.Symbol]
) -> list[sp.Expr]:
    present = [z for z in variables if any(z in to_sympy(a).free_symbols for a in coefficients)]
    found: list[sp.Expr] = []
    nonzero = [to_sympy(a) for a in coefficients if a != 0]
    for a in nonzero:
        found += [1 / a, 1 / a**2]
    for z in present:
        found += [1 / z, 1 / z**2]
    for zi, zj in combinations(present, 2):
        found += [1 / (zi * zj), 1 / (zi**2 + zj**2)]
    for ai, aj in combinations(nonzero, 2):
        found.append(1 / (ai * aj))
    unique: list[sp.Expr] = []
    for f in found:
        if f.is_number or f in unique:
            continue
        unique.append(f)
    return unique


def _integrated(
    exact: Form, variables: Sequence[sp.Symbol], factor: sp.Expr, how: str
) -> Integrability:
    """h = the integral of the exact form, variable by variable:
    h = int a_0 dz_0, then h += int (a_k - dh/dz_k) dz_k for k = 1, 2, ..."""
    h = sp.Integer(0)
    for k, z in enumerate(variables):
        rest = exact.get((k,), sp.Integer(0)) - h.diff(z)
        rest = sp.simplify(rest) if is_small(rest, 80) else rest
        if rest == 0 or is_zero(rest):
            continue
        antiderivative = sp.integrate(rest, z)
        if antiderivative.has(sp.Integral):
            return Integrability(True, None, factor, how + "; its integral is not elementary")
        h += antiderivative
    h = sp.simplify(h) if is_small(h, 80) else h
    if not all(is_zero(h.diff(z) - exact.get((k,), 0)) for k, z in enumerate(variables)):
        return Integrability(True, None, factor, how + "; the integral could not be checked")
    equation = "omega" if factor == 1 else "mu omega"
    return Integrability(True, h, factor, f"{how}: {equation} = d({h})")


def frobenius(forms: Sequence[Form], variables: Sequence[sp.Symbol]) -> tuple[bool, str]:
    """The Frobenius condition for independent 1-forms: d omega_i ^ omega_1 ^ ... ^ omega_m = 0
    for every i.  Returns (holds, reason)."""
    if len(forms) + 2 > len(variables):
        return True, "at most one direction of motion is left, which is always integrable"
    if _large([list(form.values()) for form in forms]):
        return _probed_frobenius(forms, variables)
    product: Form = {(): sp.Integer(1)}
    for form in forms:
        product = wedge(product, form)
    m = len(forms)
    all_forms = (
        " ^ ".join(f"omega_{j + 1}" for j in range(m)) if m <= 3 else (f"omega_1 ^ ... ^ omega_{m}")
    )
    for i, form in enumerate(forms):
        twisted = _nonzero_part(wedge(exterior_derivative(form, variables), product))
        if twisted:
            return False, f"d omega_{i + 1} ^ {all_forms} = {describe(twisted, variables)} != 0"
    return True, "d omega_i ^ omega_1 ^ ... ^ omega_m = 0 for every i"


def _large(coefficient_lists: Sequence[Sequence[sp.Expr]]) -> bool:
    return any(
        not is_small(to_sympy(a), LARGE_COEFFICIENT) for row in coefficient_lists for a in row
    )


class _ProbedForms:
    """The coefficients a_k of 1-forms and their slopes da_k/dz_i as numbers at random
    points: ``points()`` gives, at each, the forms and their exterior derivatives."""

    def __init__(self, rows: Sequence[Sequence[sp.Expr]], variables: Sequence[sp.Symbol]):
        self.n = len(variables)
        exprs = [to_sympy(a) for row in rows for a in row]
        symbols = set(variables).union(*(a.free_symbols for a in exprs))
        self.symbols = sorted(symbols, key=str)
        self.variables = tuple(variables)
        self.exprs = exprs
        # differentiated in SymEngine: SymPy takes seconds on a rolling wheel's coefficients
        fast = [backend(a) for a in exprs]
        self.entries = [*fast, *(a.diff(to_backend(z)) for a in fast for z in variables)]
        self.count = len(rows)

    def function(self, point: dict[sp.Symbol, float]) -> np.ndarray | None:
        """The coefficients, then their slopes, at ``point`` (None where not finite)."""
        try:
            return values_at(self.entries, point)
        except ValueError:  # a derivative SymEngine leaves unevaluated: SymPy's
            slopes = [a.diff(z) for a in self.exprs for z in self.variables]
            return PointFunction(sp.Matrix([*self.exprs, *slopes]), self.symbols)(point)

    def points(self) -> list[list[tuple[FormValues, FormValues]]]:
        """At each probe where every value is finite: [(omega_j, d omega_j) for each form]."""
        rng, n = random.Random(SEED), self.n
        found: list[list[tuple[FormValues, FormValues]]] = []
        for _ in range(PROBES):
            values = self.function(random_values(self.symbols, rng))
            if values is None:
                continue
            values = values.ravel()
            a = values[: self.count * n].reshape(self.count, n)
            slopes = values[self.count * n :].reshape(self.count, n, n)  # [form, k, i]
            forms = []
            for j in range(self.count):
                omega: FormValues = {(k,): float(a[j, k]) for k in range(n)}
                curl = slopes[j].T - slopes[j]  # curl[i, k] = da_k/dz_i - da_i/dz_k
                d_omega: FormValues = {
                    (i, k): float(curl[i, k]) for i in range(n) for k in range(i + 1, n)
                }
                forms.append((omega, d_omega))
            found.append(forms)
        return found


def _scale(*forms: dict[tuple[int, ...], float]) -> float:
    return float(np.prod([max(1.0, max(map(abs, f.values()), default=0.0)) for f in forms]))


def _component(form: dict[tuple[int, ...], float], variables: Sequence[sp.Symbol]) -> str:
    indices, value = max(form.items(), key=lambda item: abs(item[1]))
    return f"its {'^'.join(f'd{variables[i]}' for i in indices)} component is {value:.3g}"


def _probed_form(coefficients: Sequence[sp.Expr], variables: Sequence[sp.Symbol]) -> Integrability:
    """:func:`integrate_form` for a large form, decided at random points."""
    points = _ProbedForms([coefficients], variables).points()
    exact = bool(points)
    for [(omega, d_omega)] in points:
        if max(map(abs, d_omega.values()), default=0.0) > RELATIVE_ZERO * _scale(d_omega):
            exact = False
        twisted = wedge_values(omega, d_omega)
        if max(map(abs, twisted.values()), default=0.0) > RELATIVE_ZERO * _scale(omega, d_omega):
            return Integrability(
                False,
                None,
                None,
                f"omega ^ d omega != 0 (at a random point {_component(twisted, variables)}), "
                "so by Frobenius no h(q, t) has dh proportional to omega",
            )
    if exact:
        return Integrability(
            True, None, sp.Integer(1), "omega is exact (d omega = 0 at random points)"
        )
    return Integrability(
        True,
        None,
        None,
        "omega ^ d omega = 0 at random points, so an integrating factor exists (Frobenius); "
        "the form is too large to seek it",
    )


def _probed_frobenius(forms: Sequence[Form], variables: Sequence[sp.Symbol]) -> tuple[bool, str]:
    """:func:`frobenius` for large forms, decided at random points."""
    n = len(variables)
    rows = [[form.get((k,), sp.Integer(0)) for k in range(n)] for form in forms]
    for probed in _ProbedForms(rows, variables).points():
        product: dict[tuple[int, ...], float] = {(): 1.0}
        for omega, _ in probed:
            product = wedge_values(product, omega)
        for i, (_, d_omega) in enumerate(probed):
            twisted = wedge_values(d_omega, product)
            scale = _scale(d_omega, *(omega for omega, _ in probed))
            if max(map(abs, twisted.values()), default=0.0) > RELATIVE_ZERO * scale:
                where = _component(twisted, variables)
                return False, f"d omega_{i + 1} ^ omega_1 ^ ... != 0 (at a random point {where})"
    return True, "d omega_i ^ omega_1 ^ ... ^ omega_m = 0 for every i, at random points"
