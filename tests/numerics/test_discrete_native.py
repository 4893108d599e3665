"""The discrete mechanics as C functions (for the compiled variational integrators) give the
NumPy functions' numbers, and the constraint Hessians are SymPy's second derivatives."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
from lagrangian.numerics.fast.discrete import native_mechanics
from lagrangian.numerics.fast.native import NativeFunction

pytest.importorskip("numba")  # native_mechanics requires it (the loops that call these)

RNG = np.random.default_rng(11)
_SIGNATURE = ctypes.CFUNCTYPE(
    None, ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double), ctypes.c_void_p
)


def call(function: NativeFunction, inputs: np.ndarray) -> np.ndarray:
    """out = f(in) through the C function's address."""
    out = np.empty(function.outputs)
    inputs = np.ascontiguousarray(inputs, dtype=float)
    double = ctypes.POINTER(ctypes.c_double)
    _SIGNATURE(function.address)(
        out.ctypes.data_as(double), inputs.ctypes.data_as(double), function.user_data
    )
    return out


def rheonomic_double_rod() -> tuple[lg.System, list[sp.Expr]]:
    """Two bobs on rods, the upper pivot moving: constraints with q, t and parameters."""
    x1, y1, x2, y2, m, g, a, w, t = sp.symbols("x1 y1 x2 y2 m g a w t")
    rods = [
        (x1 - a * sp.cos(w * t)) ** 2 + y1**2 - 1,
        (x2 - x1) ** 2 + (y2 - y1) ** 2 - 1,
    ]
    system = lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={m: 1.3, g: 9.81, a: 0.2, w: 1.7},
        gravity=(0, -g),
        particles=[lg.Particle("one", m, (x1, y1)), lg.Particle("two", m, (x2, y2))],
        constraints=[lg.Holonomic(rod) for rod in rods],
        dissipation=0.1 * sp.Symbol("x1_dot") ** 2,
    )
    return system, rods


def test_the_c_functions_give_the_numpy_numbers() -> None:
    system, rods = rheonomic_double_rod()
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, rods)
    native = native_mechanics(mechanics)
    assert native_mechanics(mechanics) is native  # compiled once per mechanics
    assert (native.coordinates, native.constraint_count) == (4, 2)
    p = np.array([float(system.parameters[s]) for s in eom.parameters])
    for _ in range(3):
        q, v, t = RNG.uniform(-1, 1, 4), RNG.uniform(-1, 1, 4), float(RNG.uniform(0, 3))
        midpoint = np.concatenate([np.ravel(x) for x in mechanics.midpoint(q, v, t, p)])
        np.testing.assert_allclose(call(native.midpoint, [*q, *v, t, *p]), midpoint, atol=1e-12)
        legendre = np.concatenate([np.ravel(x) for x in mechanics.legendre(q, v, t, p)])
        np.testing.assert_allclose(call(native.legendre, [*q, *v, t, *p]), legendre, atol=1e-12)
        terms = (*mechanics.constraints(q, t, p), mechanics.constraint_hessians(q, t, p))
        constraints = np.concatenate([np.ravel(x) for x in terms])
        np.testing.assert_allclose(call(native.constraints, [*q, t, *p]), constraints, atol=1e-12)


def test_the_constraint_hessians_are_the_second_derivatives() -> None:
    system, rods = rheonomic_double_rod()
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, rods)
    q, t = RNG.uniform(-1, 1, 4), 0.7
    p = {s: float(system.parameters[s]) for s in eom.parameters}
    values = {**dict(zip(eom.coordinates, q)), eom.time: t, **p}
    expected = [
        [[float(rod.diff(a, b).subs(values)) for b in eom.coordinates] for a in eom.coordinates]
        for rod in rods
    ]
    found = mechanics.constraint_hessians(q, t, np.array([float(v) for v in p.values()]))
    np.testing.assert_allclose(found, expected, atol=1e-12)
    free = compile_discrete_mechanics(eom)
    assert free.constraint_hessians(q, t, np.zeros(4)).shape == (0, 4, 4)
    assert native_mechanics(free).constraints.outputs == 1  # a C function needs an output
