"""The exported code's common subexpressions, found by SymEngine: the generated NumPy module
evaluates every piece as SymPy's own lambdify of the equations does, for a chain (many
shared sines and cosines) and for a model whose symbols have the names SymEngine gives its
temporaries (x0, x1, ...) and those the export renames the model's symbols to (_a0, ...)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg

PIECES = ("mass_matrix", "coriolis", "gravity", "forcing")
x0, x1, a0, x0_dot, x1_dot, a0_dot = sp.symbols("x0 x1 _a0 x0_dot x1_dot _a0_dot")
k, s0 = sp.symbols("k s0")


def temporary_names() -> lg.System:
    return lg.System(
        coordinates=[x0, x1, a0],
        parameters={k: 2.0, s0: 0.5},
        kinetic=(x0_dot**2 + x1_dot**2 + a0_dot**2) / 2
        + s0 * sp.cos(x0 - x1) * x0_dot * x1_dot
        + s0 * sp.sin(x1 - a0) * x1_dot * a0_dot,
        potential=k * (sp.cos(x0 - x1) + sp.cos(x1 - a0) + x0**2 + a0**2),
        name="temporary names",
    )


@pytest.mark.parametrize(
    "build", [lambda: lg.examples.n_link_pendulum(6), temporary_names], ids=["chain", "names"]
)
def test_numpy_export_evaluates_as_sympy(build, tmp_path: Path) -> None:
    eom = lg.derive(build())
    ((file_name, source),) = lg.export(eom, "numpy").items()
    (tmp_path / file_name).write_text(source)
    spec = importlib.util.spec_from_file_location("exported_cse", tmp_path / file_name)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    arguments = [list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)]
    rng = np.random.default_rng(3)
    n = len(eom.coordinates)
    for _ in range(3):
        q, qd = rng.uniform(-1.5, 1.5, n), rng.uniform(-2, 2, n)
        p = rng.uniform(0.5, 2.0, len(eom.parameters))
        for piece in PIECES:
            expected = sp.lambdify(arguments, getattr(eom, piece), modules="numpy")(q, qd, 0.0, p)
            function = getattr(module, piece)
            values = (
                function(q, qd, 0.0, p)
                if "qd" in function.__code__.co_varnames
                else function(q, 0.0, p)
            )
            np.testing.assert_allclose(
                np.asarray(values, dtype=float).ravel(),
                np.asarray(expected, dtype=float).ravel(),
                rtol=1e-10,
                atol=1e-10,
            )
