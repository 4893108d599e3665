"""The C loop compiles the derivation's own SymEngine entries of M and the forcing (no
conversion back from SymPy): the compiled function must give the numbers the SymPy form
gives, for every kind of system, and fall back on the SymPy form where SymEngine cannot
compile the entries (a nonsmooth force)."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from c_loop_setup import STOP

import lagrangian as lg
from lagrangian.derivation.backend import backend_entries
from lagrangian.io.load import loads
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.state_equations import state_equations

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler for the C loop")

COULOMB = """
name: block with Coulomb friction
coordinates: [x]
parameters: {m: 1.0, k: 4.0, mu: 0.3, g: 9.81}
kinetic: m*x_dot**2/2
potential: k*x**2/2
generalized_forces: {x: -mu*m*g*sign(x_dot)}
"""

SYSTEMS = {
    "10-link pendulum": lambda: lg.examples.n_link_pendulum(10),
    "heavy symmetric top": lambda: lg.examples.heavy_symmetric_top(),
    "two-mesh circuit": lambda: lg.examples.two_mesh_circuit(),
    "moving pivot": lambda: lg.examples.moving_pivot_pendulum(),
    "Coulomb friction": lambda: loads(COULOMB, format="yaml"),
    "one-sided stop": lambda: loads(STOP, format="yaml"),
}


def sympy_values(eom: lg.EquationsOfMotion, inputs: np.ndarray) -> np.ndarray:
    """M and the forcing (row by row) at ``inputs``, from the SymPy matrices by lambdify."""
    equations = state_equations(eom)
    exprs = [*equations.matrix, *equations.vector]
    return np.array(sp.lambdify([c_loop.state_symbols(eom)], exprs, "numpy")(inputs), float)


@pytest.mark.parametrize("name", SYSTEMS)
def test_the_compiled_entries_give_the_sympy_numbers(name: str) -> None:
    eom = lg.derive(SYSTEMS[name]())
    fast = c_loop.native_equations(eom)
    assert fast is not None
    rng = np.random.default_rng(7)
    for _ in range(5):
        inputs = rng.uniform(0.2, 1.5, len(c_loop.state_symbols(eom)))
        compiled = np.asarray(fast.function.owner(inputs), dtype=float).ravel()
        np.testing.assert_allclose(compiled, sympy_values(eom, inputs), rtol=1e-12, atol=1e-12)


def test_derived_matrices_carry_their_entries_and_others_do_not() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    entries = backend_entries(eom.mass_matrix)
    assert entries is not None and len(entries) == 4
    assert backend_entries(sp.ImmutableMatrix(eom.mass_matrix.tolist())) is None
