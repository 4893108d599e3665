"""A derivation leaves nothing for the cycle collector: while it runs the collector is paused
(lagrangian.symbolic.sympy_view.cycle_collection_paused), so a reference cycle made on the
way would live on until the next full collection."""

import gc

import pytest

import lagrangian as lg
from lagrangian.derivation.lagrange import forget_derivations


@pytest.mark.parametrize(
    "build",
    [
        lambda: lg.examples.n_link_pendulum(12),
        lambda: lg.examples.double_pendulum(),
        lambda: lg.examples.whipple_bicycle(),
    ],
    ids=["chain", "double pendulum", "bicycle"],
)
def test_a_derivation_makes_no_reference_cycles(build):
    system = build()
    forget_derivations()
    gc.collect()
    lg.derive(system)
    assert gc.collect() == 0
