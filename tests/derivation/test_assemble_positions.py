"""The assembly's positions converted to SymEngine with each distinct SymPy subexpression
once for all of them (derivation/assemble.py): each is the expression converting it alone
gives (equal, with its arguments in the same order), for the bicycle's bodies, a chain's
points (whose positions repeat the links above them) and numbers that SymPy keeps apart
(2 and 2.0)."""

from __future__ import annotations

import sympy as sp

import lagrangian as lg
from lagrangian.derivation.assemble import assemble
from lagrangian.derivation.backend import to_backend
from lagrangian.examples import BENCHMARKS


def _same_tree(a, b) -> bool:
    return a == b and a.args == b.args and all(_same_tree(x, y) for x, y in zip(a.args, b.args))


def _assert_positions_converted_alone(system: lg.System) -> None:
    positions = [p.position for p in (*system.particles, *system.rigid_bodies)]
    for position, point in zip(positions, assemble(system).points, strict=True):
        alone = [to_backend(x) for x in position]
        assert all(_same_tree(a, b) for a, b in zip(point.position, alone, strict=True))


def test_the_bicycles_positions_are_each_converted_alone() -> None:
    _assert_positions_converted_alone(BENCHMARKS["whipple_bicycle"]())


def test_a_chains_positions_are_each_converted_alone() -> None:
    _assert_positions_converted_alone(lg.examples.n_link_pendulum(6))


def test_an_integer_and_a_float_in_two_positions_stay_apart() -> None:
    (q,) = lg.coordinates("q")
    m = sp.Symbol("m")
    system = lg.System(
        coordinates=[q],
        parameters=[m],
        particles=[
            lg.Particle("a", m, (2 * sp.cos(q), 2 * sp.sin(q) + 1)),
            lg.Particle("b", m, (2.0 * sp.cos(q), 2.0 * sp.sin(q) + 1.0)),
        ],
    )
    _assert_positions_converted_alone(system)
    first, second = assemble(system).points
    assert first.position != second.position
