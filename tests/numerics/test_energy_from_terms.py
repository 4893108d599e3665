"""E = T + V and h are compiled from the derivation's own SymEngine terms: the numbers must be
those of the SymPy energies (``eom.kinetic_energy`` + ``eom.potential_energy``, and h by its
definition sum q_dot dL/dq_dot - L), for every kind of system, the SymPy form taking over where
SymEngine cannot compile the terms (a one-sided spring's Heaviside)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from c_loop_setup import STOP

import lagrangian as lg
from lagrangian.io.load import loads
from lagrangian.numerics.compile import compile_equations

SYSTEMS = {
    "double pendulum": lg.examples.double_pendulum,
    "heavy symmetric top": lg.examples.heavy_symmetric_top,
    "charge in a field (velocity potential)": lg.examples.charged_particle_em,
    "moving pivot (explicit time)": lg.examples.moving_pivot_pendulum,
    "series RLC circuit": lg.examples.series_rlc,
    "one-sided stop": lambda: loads(STOP, format="yaml"),
}


def by_sympy(eom: lg.EquationsOfMotion, expr: sp.Expr, rows: np.ndarray, p: np.ndarray):
    symbols = [*eom.coordinates, *eom.velocities, eom.time, *eom.parameters]
    function = sp.lambdify(symbols, expr, "numpy")
    return np.array([function(*row[:-1], row[-1], *p) for row in rows], dtype=float)


@pytest.mark.parametrize("name", SYSTEMS)
def test_the_energies_are_the_sympy_ones(name: str) -> None:
    eom = lg.derive(SYSTEMS[name]())
    compiled = compile_equations(eom)
    n = len(eom.coordinates)
    rng = np.random.default_rng(11)
    q, qd = rng.uniform(0.2, 1.4, (20, n)), rng.uniform(-1, 1, (20, n))
    t = rng.uniform(0, 2, 20)
    p = rng.uniform(0.5, 2.0, len(eom.parameters))
    rows = np.hstack([q, qd, t[:, None]])
    energy = eom.kinetic_energy + eom.potential_energy
    lagrangian = eom.kinetic_energy - eom.potential_energy - eom.velocity_potential
    h = sum(v * lagrangian.diff(v) for v in eom.velocities) - lagrangian
    for j in range(20):
        values = (
            compiled.energy(q[j], qd[j], t[j], p),
            compiled.energy_function(q[j], qd[j], t[j], p),
        )
        np.testing.assert_allclose(
            values[0], by_sympy(eom, energy, rows[j : j + 1], p)[0], rtol=1e-12
        )
        np.testing.assert_allclose(values[1], by_sympy(eom, h, rows[j : j + 1], p)[0], rtol=1e-12)
    assert compiled.energy_function_differs == (sp.simplify(h - energy) != 0)
