"""NumericFunction compiles quickly first and with LLVM's optimizer once it has evaluated
OPTIMIZE_AFTER_ROWS states: both tiers give the closed-form numbers."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from lagrangian.numerics import evaluate
from lagrangian.numerics.evaluate import NumericFunction

x, v, t = sp.symbols("x v t")
EXPRESSIONS = [sp.cos(x - v) * v**2 / 2 + sp.exp(-t) * x, sp.atan2(x, v)]


def closed_form(rows: np.ndarray, time: float) -> np.ndarray:
    q, w = rows[:, 0], rows[:, 1]
    return np.stack([np.cos(q - w) * w**2 / 2 + np.exp(-time) * q, np.arctan2(q, w)], axis=-1)


def test_both_tiers_give_the_closed_form(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(evaluate, "OPTIMIZE_AFTER_ROWS", 50)
    f = NumericFunction(([x, v], t), EXPRESSIONS, shape=(2,))
    rows = np.random.default_rng(3).uniform(-2, 2, (40, 2))
    quick = f(rows, 0.3)  # 40 states: the quick tier
    assert not f._optimized
    f(rows, 0.3)  # 80 states: the optimized tier replaces it
    assert f._optimized and f._fast is not None
    optimized = f(rows, 0.3)
    np.testing.assert_allclose(quick, closed_form(rows, 0.3), rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(optimized, quick, rtol=1e-15, atol=1e-15)


def test_single_states_count_towards_the_optimized_tier(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(evaluate, "OPTIMIZE_AFTER_ROWS", 3)
    f = NumericFunction(([x, v], t), EXPRESSIONS, shape=(2,))
    values = [f.raw([0.5, -0.25], 1.0) for _ in range(5)]
    assert f._optimized
    for value in values:
        np.testing.assert_allclose(value, closed_form(np.array([[0.5, -0.25]]), 1.0)[0])


def test_heaviside_compiles_natively_with_sympys_values() -> None:
    # SymEngine does not know Heaviside; written with sign it compiles (the fallback's
    # common-subexpression search took minutes on Heaviside(x**200)).  The reference is
    # SymPy's own value at each point, H(0) = 1/2 unless given.
    x = sp.Symbol("x")
    steps = [
        sp.Heaviside(x**3 - x),
        sp.Heaviside(x - 1, 0),
        sp.Heaviside(x + 1, 1),
        x * sp.Heaviside(x),
    ]
    function = NumericFunction(([x],), steps, shape=(4,))
    assert function._native is not None
    for value in (-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0):
        expected = [float(s.subs(x, value)) for s in steps]
        np.testing.assert_allclose(function([value]), expected, rtol=0, atol=1e-15)
