"""The right-hand side as one C function: SymEngine's LLVM backend, numba's fallback, and the
loops compiled once for every system, checked against SymPy's own numbers and SciPy's
solve_ivp on the same equations.
"""

from __future__ import annotations

import ctypes
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.fast import native
from lagrangian.numerics.fast.native import NativeFunction, native_function

pytest.importorskip("numba")

from lagrangian.numerics.fast import fast_equations
from lagrangian.numerics.fast.loops import compile_cached, single_loop
from lagrangian.numerics.fast.run import Settings, integrate

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
    expressions = [sp.Mod(x, y) + sp.cos(x), x * y]
    function = native_function([x, y], expressions)
    assert function.compiler == "numba"  # SymEngine's LLVM backend has no Mod
    assert call(function, [5.5, 2.0]) == pytest.approx([1.5 + math.cos(5.5), 11.0], rel=1e-15)


def test_the_fallback_path_integrates_as_the_llvm_path(monkeypatch: pytest.MonkeyPatch) -> None:
    start = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
    options = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10, "backend": "numba"}
    system = lg.examples.double_pendulum()
    llvm = lg.simulate(lg.derive(system), start, 2.0, **options)
    monkeypatch.setattr(native, "LLVM", False)
    eom = lg.derive(system.replace())  # a new value: compiled anew
    assert fast_equations(eom).function.compiler == "numba"
    fallback = lg.simulate(eom, start, 2.0, **options)
    assert np.array_equal(llvm.t, fallback.t)
    assert np.max(np.abs(llvm.q - fallback.q)) < 1e-12


@pytest.mark.parametrize("method", ["RK45", "DOP853"])
def test_the_loop_takes_solve_ivps_steps_to_the_same_state(method: str) -> None:
    eom = lg.derive(lg.examples.n_link_pendulum(4))
    compiled = compile_equations(eom)
    x0, p = np.array([0.5, 0.8, 1.1, 1.4, 0.1, 0.1, 0.1, 0.1]), np.array([1.0] * 8 + [9.81])
    reference = solve_ivp(
        lambda t, s: compiled.rhs(t, s, p), (0.0, 5.0), x0, method=method, rtol=1e-9, atol=1e-9
    )
    run = integrate(fast_equations(eom), Settings(method, (0.0, 5.0), x0[:0], 1e-9, 1e-9), x0, p)
    assert len(run.t) == len(reference.t)
    # step sizes differ only by the rounding of the error estimates that choose them
    assert np.max(np.abs(run.t - reference.t)) < 1e-8
    assert np.max(np.abs(run.x[-1] - reference.y[:, -1])) < 1e-12


def test_a_first_order_coordinate_is_solved_from_its_equation() -> None:
    system = lg.examples.rc_rl_circuit()
    eom = lg.derive(system)
    compiled, fast = compile_equations(eom), fast_equations(eom)
    assert fast.first and fast.second  # one of each kind
    p = np.array([v if v is not None else 1.0 for v in compiled.defaults])
    x0 = np.array([0.1] * len(fast.state_names))
    settings = Settings("DOP853", (0.0, 0.01), np.linspace(0.0, 0.01, 5), 1e-11, 1e-13)
    run = integrate(fast, settings, x0, p)
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


def test_the_loop_is_compiled_once_for_every_system() -> None:
    for links in (1, 2, 3):
        fast = fast_equations(lg.derive(lg.examples.n_link_pendulum(links)))
        x0, p = np.full(2 * links, 0.1), np.array([1.0] * (2 * links) + [9.81])
        run = integrate(fast, Settings("DOP853", (0.0, 0.5), x0[:0]), x0, p)
        assert run.t[-1] == 0.5
    loop = single_loop("adaptive")
    assert len(loop.signatures) == 1
    assert loop.stats.cache_path  # kept on disk


def test_a_loop_is_compiled_in_the_process_when_it_cannot_be_cached() -> None:
    namespace: dict[str, object] = {}
    exec("def twice(t):\n    return 2.0 * t\n", namespace)  # no file: numba has no cache for it
    from numba import types

    compiled = compile_cached(types.float64(types.float64), namespace["twice"])
    assert compiled(1.5) == 3.0


@pytest.mark.slow
def test_a_fresh_process_loads_the_loop_from_the_disk_cache(tmp_path: Path) -> None:
    script = (
        "import lagrangian as lg\n"
        "from lagrangian.numerics.fast.loops import single_loop\n"
        "lg.simulate(lg.examples.simple_pendulum(), {'theta': 0.1, 'theta_dot': 0.0}, 0.1,\n"
        "            backend='numba')\n"
        "print(sum(single_loop('adaptive').stats.cache_hits.values()))\n"
    )
    environment = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    hits = [
        subprocess.run(
            [sys.executable, "-c", script], env=environment, capture_output=True, text=True
        ).stdout.split()[-1]
        for _ in range(2)
    ]
    assert hits == ["0", "1"]


def test_a_linear_system_that_does_not_fit_its_state_is_refused() -> None:
    from lagrangian.numerics.fast.compiled_rates import linear_equations

    t, q, r, v = sp.symbols("t q r v")
    with pytest.raises(ValueError, match="do not fit together"):
        linear_equations(t, [q], [v], [], (sp.eye(2), sp.Matrix([0, 1, 2])))
    with pytest.raises(ValueError, match="do not fit together"):  # r's rate is not solved for
        linear_equations(t, [q, r], [v], [], (sp.eye(1), sp.Matrix([0])), first=[1])
