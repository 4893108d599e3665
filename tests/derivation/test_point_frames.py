"""The points' Jacobian rows turned into the frames their centres hang from
(lagrangian.derivation.assemble.frames_carried, kinetic._frames): J^T J is unchanged,
(R^T J)^T R^T J = J^T J, and the chain is read from the model, never guessed; each entry
of J^T J formed in the frame where it has the fewest products (kinetic._entries_by_frame)
is the entry formed in world axes."""

from __future__ import annotations

from typing import Any

import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.assemble import assemble, frames_carried
from lagrangian.derivation.kinetic import _add_gram, _entries_by_frame, _frames
from lagrangian.derivation.trig_polynomial import Sum
from lagrangian.examples import BENCHMARKS
from lagrangian.model.rotation import axis_angle, euler_rotation, unit_axis


def _gram(algebra, weight, rows, n, entries=None):
    """weight J^T J as finished polynomials, upper triangle (``entries`` only, when given)."""
    shares = [[Sum() for _ in range(n)] for _ in range(n)]
    _add_gram(algebra, shares, algebra.convert(weight), rows, rows, entries)
    return {
        (j, k): algebra.finish(algebra.gather(shares[j][k])) for j in range(n) for k in range(j, n)
    }


def _monomials(rows):
    return sum(len(p) for row in rows for p in row)


def test_the_bicycles_bodies_hang_from_the_heading_lean_and_pitch() -> None:
    """The yaml's chains: the rear frame z(yaw) x(lean) y(pitch); the fork and the front
    wheel continue with the constant tilt y(-lam), where the chain their centres move with
    ends; the rear wheel's centre (x, y, rR cos(lean)) has no heading."""
    system = BENCHMARKS["whipple_bicycle"]()
    asm = assemble(system)
    yaw, lean, pitch = (s for s in asm.q if str(s) in ("yaw", "lean", "pitch"))
    carried = {
        b.name: frames_carried(p.orientation, p.position, asm.q)
        for b, p in zip(system.rigid_bodies, asm.points)
    }
    chain = ((2, yaw), (0, lean), (1, pitch))
    assert carried == {"rear_wheel": (), "rear_frame": chain, "fork": chain, "front_wheel": chain}


def test_the_fork_has_the_same_gram_matrix_in_its_frame_with_fewer_terms(
    bicycle_fork: tuple[Any, ...],
) -> None:
    asm, algebra, fork, world, turned = bicycle_fork
    assert _monomials(turned) < 0.6 * _monomials(world)
    n = len(asm.q)
    assert _gram(algebra, fork.mass, turned, n) == _gram(algebra, fork.mass, world, n)


def test_each_entry_formed_in_the_frame_of_its_fewest_products_is_the_world_entry(
    bicycle_fork: tuple[Any, ...],
) -> None:
    """The fork's entries spread over the world axes and the frames of the heading, the
    lean and the pitch (the translations' entries in world axes, where their column is a
    unit vector), each once; together they are J^T J formed in world axes, with fewer
    products than in the last frame alone."""
    asm, algebra, fork, world, _ = bicycle_fork
    n = len(asm.q)
    frames = _frames(algebra, world, frames_carried(fork.orientation, fork.position, asm.q))
    chosen = _entries_by_frame(frames)
    assert len(chosen) == 4
    assert [rows for rows, _ in chosen] == frames
    every = [entry for _, entries in chosen for entry in entries]
    assert len(every) == len(set(every))
    x_row = next(entries for rows, entries in chosen if rows is world)
    assert (0, 0) in x_row and (1, 1) in x_row  # M_xx = M_yy = m: one product each
    made = {}
    for rows, entries in chosen:
        made.update(
            {e: p for e, p in _gram(algebra, fork.mass, rows, n, entries).items() if e in entries}
        )
    expected = _gram(algebra, fork.mass, world, n)
    assert {e: p for e, p in made.items() if p} == {e: p for e, p in expected.items() if p}

    def products(rows, entries):
        return sum(len(row[j]) * len(row[k]) for j, k in entries for row in rows)

    upper = {(j, k) for j in range(n) for k in range(j, n)}
    assert sum(products(rows, entries) for rows, entries in chosen) < products(frames[-1], upper)


def test_orientations_not_known_as_a_chain_carry_nothing() -> None:
    """A matrix, an axis that is not a coordinate axis (tilted, or a coordinate axis
    reversed), an angle that is not a coordinate: the rows stay as they were (the chain ends
    there)."""
    a, b = lg.coordinates("a b")
    m, lam = sp.symbols("m lam")
    centre = (sp.cos(a), sp.sin(a), sp.sin(b))
    orientations = {
        "matrix": euler_rotation("ZXZ", (a, b, 0)).matrix,
        "tilted axis": axis_angle((1, 1, 0), a),
        "reversed axis": axis_angle((0, 0, -1), a),
        "constant first": euler_rotation("ZXZ", (lam, a, b)),
        "euler": euler_rotation("ZXZ", (a, b, 0)),
    }
    system = lg.System(
        coordinates=[a, b],
        parameters=[m, lam],
        rigid_bodies=[
            lg.RigidBody(name, m, sp.eye(3), centre, orientation=R)
            for name, R in orientations.items()
        ],
    )
    asm = assemble(system)
    carried = [frames_carried(p.orientation, p.position, asm.q) for p in asm.points]
    qa, qb = asm.q
    assert carried == [(), (), (), (), ((2, qa), (0, qb))]


def test_an_axis_given_in_floats_is_carried_as_sympy_compares_it() -> None:
    """(0, 0, 1.0) is the z axis exactly where SymPy takes Float 1.0 as equal to 1 (before
    SymPy 1.13, which also hashes the two apart: the whole-axis look-up misses it and the
    entry-by-entry comparison decides).  The model's constructors give exact axes; an
    orientation that hands over its floats is taken as the comparison says."""
    unit = unit_axis((0, 0, 1.0))
    assert unit[2].is_Float  # the float kept: this is the case the look-up misses

    class FloatAxis:
        def factors(self) -> tuple[tuple[sp.ImmutableMatrix, Any], ...]:
            return ((unit, sp.Symbol("q0")),)

    q = se.symbols("q0 q1")
    r = se.Symbol("r")
    centre = (r * se.cos(q[0]), r * se.sin(q[0]), r * se.cos(q[1]))
    expected = ((2, q[0]),) if unit[2] == 1 else ()
    assert frames_carried(FloatAxis(), centre, q) == expected  # type: ignore[arg-type]
