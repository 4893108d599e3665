"""The Legendre transform's W = d2L/dq_dot2, taken row by row from the momenta, is SymPy's own
Hessian of L on systems with coupled, velocity-dependent and diagonal kinetic terms."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.hamiltonian import velocity_hessian


@pytest.mark.parametrize(
    "system",
    [
        lg.examples.double_pendulum(),
        lg.examples.charged_particle_em(),
        lg.examples.heavy_symmetric_top(),
        lg.examples.quartic_lagrangian(),
        lg.examples.hard_disk_gas(3),
    ],
    ids=lambda s: s.name,
)
def test_the_velocity_hessian_is_sympys(system: lg.System) -> None:
    eom = lg.derive(system)
    expected = sp.hessian(eom.lagrangian, eom.velocities)
    assert sp.simplify(velocity_hessian(eom) - expected) == sp.zeros(*expected.shape)
