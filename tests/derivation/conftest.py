"""The bicycle's fork as the kinetic form meets it, for the tests of its rows and products."""

from __future__ import annotations

from typing import Any, NamedTuple

import pytest

from lagrangian.derivation.assemble import Assembly, assemble, frames_carried
from lagrangian.derivation.kinetic import _frames, _jacobian_row
from lagrangian.derivation.trig_polynomial import TrigAlgebra, algebra_for
from lagrangian.examples import BENCHMARKS


class Fork(NamedTuple):
    """The bicycle's assembly and algebra, its fork's point, and the fork centre's Jacobian
    rows in world axes and turned into the frames the centre hangs from."""

    asm: Assembly
    algebra: TrigAlgebra
    fork: Any
    world: list[Any]
    rows: list[Any]


@pytest.fixture
def bicycle_fork() -> Fork:
    system = BENCHMARKS["whipple_bicycle"]()
    asm = assemble(system)
    algebra = algebra_for([*asm.q, *asm.q_dot, *asm.q_ddot, asm.t])
    fork = next(p for b, p in zip(system.rigid_bodies, asm.points) if b.name == "fork")
    world = [_jacobian_row(algebra, x, asm.q) for x in fork.position]
    rows = _frames(algebra, world, frames_carried(fork.orientation, fork.position, asm.q))[-1]
    return Fork(asm, algebra, fork, world, rows)
