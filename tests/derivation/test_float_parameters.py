"""A model whose masses and positions hold Floats (as a Python user writes 0.3*x) derives the
same equations, to rounding, as the same model with those numbers as parameters: the
trigonometric algebra's products, doubled cross products and Christoffel sums are formed in
an order of its own, so a Float coefficient may round differently from a sum taken in
another order, never by more than the rounding of the numbers themselves."""

from __future__ import annotations

import dataclasses
import random

import numpy as np
import sympy as sp

import lagrangian as lg
from lagrangian.examples import BENCHMARKS
from lagrangian.symbolic.symbols import velocity

FLOATED = ("xB", "zB", "xH", "zH", "c", "w", "mB", "mH")


def _values(matrix: sp.MatrixBase, point: dict[sp.Symbol, float]) -> np.ndarray:
    exact = {s: sp.Float(v, 30) for s, v in point.items()}
    return np.array(
        [[complex(e.xreplace(exact).evalf(30)).real for e in row] for row in matrix.tolist()]
    )


def test_the_bicycle_with_float_geometry_is_its_exact_derivation_to_rounding() -> None:
    exact = BENCHMARKS["whipple_bicycle"]()
    by_name = {s.name: s for s in exact.parameters}
    floats = {by_name[n]: sp.Float(exact.parameters[by_name[n]]) for n in FLOATED}

    def floated(e: object) -> object:
        return e.xreplace(floats) if isinstance(e, sp.Basic) else e

    bodies = [
        dataclasses.replace(b, mass=floated(b.mass), position=tuple(map(floated, b.position)))
        for b in exact.rigid_bodies
    ]
    left = {s: v for s, v in exact.parameters.items() if s not in floats}
    with_floats = exact.replace(rigid_bodies=tuple(bodies), parameters=left)
    rng = random.Random(3)
    point = {s: float(v) for s, v in exact.parameters.items() if v is not None}
    for q in exact.coordinates:
        point[q] = rng.uniform(-0.6, 0.6)
        point[velocity(q)] = rng.uniform(-1.0, 1.0)
    reference, floated_eom = lg.derive(exact), lg.derive(with_floats)
    assert any(e.has(sp.Float) for e in floated_eom.mass_matrix)
    for name in ("mass_matrix", "forcing"):
        want = _values(sp.Matrix(getattr(reference, name)), point)
        got = _values(sp.Matrix(getattr(floated_eom, name)), point)
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
