"""The right-hand side as one C function: SymEngine's LLVM backend and numba's fallback (for
the variational marches), checked against SymPy's own numbers, and the C loop on a system with
a first-order coordinate against SciPy's solve_ivp on the same equations.
"""

from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.native import NativeFunction, native_function
from lagrangian.numerics.fast.settings import Settings

x, y = sp.symbols("x y")
_C_FUNCTION = ctypes.CFUNCTYPE(
    None, ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double), ctypes.c_void_p
)


def call(function: NativeFunction, inputs: list[float]) -> np.ndarray:
    """out = f(inputs), through the C signature every compiled right-hand side has."""
    given = np.array(inputs, dtype=float)
    out = np.empty(function.outputs)
    _C_FUNCTION(function.address)(
        out.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
        given.ctypes.data_as(ctypes.POINTER(ctypes.c_double)),
        function.user_data,
    )
    return out


def test_llvm_compiles_the_expressions_to_sympys_numbers() -> None:
    expressions = [y, -sp.sin(x) * sp.exp(y), sp.atan2(x, y) + sp.sqrt(x**2 + 1)]
    function = native_function([x, y], expressions)
    assert function.compiler == "llvm"
    point = {x: 0.7, y: -0.3}
    expected = [float(e.subs(point)) for e in expressions]
    assert call(function, [0.7, -0.3]) == pytest.approx(expected, rel=1e-14, abs=1e-15)


def test_a_users_x1_is_not_taken_for_a_temporary_of_symengines_cse() -> None:
    x0, x1 = sp.symbols("x0 x1")
    expressions = [sp.sin(x0 + x1) ** 2, sp.sin(x0 + x1) * x1]
    function = native_function([x0, x1], expressions)
    expected = [math.sin(0.5) ** 2, math.sin(0.5) * 0.2]
    assert call(function, [0.3, 0.2]) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize(
    ("expression", "values"),
    [
        (sp.Heaviside(x), {-1.0: 0.0, 0.0: 0.5, 2.0: 1.0}),
        (sp.Heaviside(x, 1), {-1.0: 0.0, 0.0: 1.0, 2.0: 1.0}),
    ],
)
def test_heaviside_stays_on_llvm_with_sympys_value_at_zero(
    expression: sp.Expr, values: dict[float, float]
) -> None:
    function = native_function([x], [expression * 3])
    assert function.compiler == "llvm"
    for at, expected in values.items():
        assert call(function, [at])[0] == 3 * expected


def test_numba_compiles_what_llvm_cannot_to_the_same_numbers() -> None:
    pytest.importorskip("numba")
    expressions = [sp.Mod(x, y) + sp.cos(x), x * y]
    function = native_function([x, y], expressions)
    assert function.compiler == "numba"  # SymEngine's LLVM backend has no Mod
    assert call(function, [5.5, 2.0]) == pytest.approx([1.5 + math.cos(5.5), 11.0], rel=1e-15)


def test_a_first_order_coordinate_is_solved_from_its_equation() -> None:
    if not c_loop.available():
        pytest.skip("no C compiler")
    system = lg.examples.rc_rl_circuit()
    eom = lg.derive(system)
    compiled, fast = compile_equations(eom), c_loop.native_equations(eom)
    assert fast is not None
    assert fast.first and fast.second  # one of each kind
    p = np.array([v if v is not None else 1.0 for v in compiled.defaults])
    x0 = np.array([0.1] * len(fast.state_names))
    settings = Settings("DOP853", (0.0, 0.01), np.linspace(0.0, 0.01, 5), 1e-11, 1e-13)
    run = c_loop.integrate(fast, settings, x0, p)
    reference = solve_ivp(
        lambda t, s: compiled.rhs(t, s, p),
        (0.0, 0.01),
        x0,
        method="DOP853",
        rtol=1e-11,
        atol=1e-13,
        t_eval=settings.t_out,
    )
    assert np.allclose(run.x, reference.y.T, rtol=1e-10, atol=1e-14)
