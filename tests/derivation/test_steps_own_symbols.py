"""Every step of every built-in example is written in the system's own symbols: the sums of
parameters the derivation keeps whole as placeholders (a chain's m_k + ... + m_n, the
bicycle's sums of masses) are put back in every step, the momenta dL/dq_dot included."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian import examples
from lagrangian.symbolic.symbols import t

NAMES = [name for name in examples.names() if name != "n_link_pendulum"]


def own_symbols(system: lg.System) -> set:
    eom = lg.derive(system)
    return {t, *eom.coordinates, *eom.velocities, *eom.accelerations, *eom.parameters}


def build(name: str) -> lg.System:
    if name in examples.BENCHMARKS:
        return examples.BENCHMARKS[name]()
    base, *size = name.split(":")
    return examples.get(base)(*[int(n) for n in size])


@pytest.mark.parametrize("name", [*NAMES, "n_link_pendulum:12", *examples.BENCHMARKS])
def test_every_step_is_in_the_systems_own_symbols(name):
    system = build(name)
    allowed = own_symbols(system)
    for step in lg.derive(system).steps:
        for part in (step.dL_dvelocity, step.ddt_dL_dvelocity, step.dL_dcoordinate, step.equation):
            stray = part.free_symbols - allowed
            assert not stray, (step.coordinate, stray)
