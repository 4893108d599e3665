"""The disks and walls a scene reads from unilateral constraints, against the geometry written
by hand: the gas's disks of radius r in the box [0, L]^2, a box tilted by a wall n . X >= c,
and constraints of other forms left undrawn."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.render.scene_contacts import contacts_of, wall_segments


def test_the_gas_has_disks_of_its_radius_and_the_four_sides_of_its_box() -> None:
    gas = lg.examples.hard_disk_gas(5, radius=0.05, side=2.0)
    contacts = contacts_of(gas)
    assert contacts.radii == {f"disk{k}": pytest.approx(0.05) for k in range(1, 6)}
    faces = {(w.normal, round(w.offset - contacts.radii[w.particle], 12)) for w in contacts.walls}
    # the centre keeps x >= r, x <= L - r ...: the walls themselves at x = 0, x = L, ...
    assert faces == {((1.0, 0.0), 0.0), ((-1.0, 0.0), -2.0), ((0.0, 1.0), 0.0),
                     ((0.0, -1.0), -2.0)}  # fmt: skip
    centres = {name: np.array([[0.5, 0.5], [1.5, 1.2]]) for name in contacts.radii}
    segments = sorted(sorted(map(tuple, s.tolist())) for _, s in wall_segments(contacts, centres))
    assert segments == [[(0, 0), (0, 2)], [(0, 0), (2, 0)], [(0, 2), (2, 2)], [(2, 0), (2, 2)]]


def test_a_slanted_wall_is_the_line_its_constraint_gives() -> None:
    x, y, m, g = sp.symbols("x y m g")
    ball = lg.Particle("ball", m, (x, y))
    system = lg.System(
        coordinates=(x, y),
        parameters={m: 1.0, g: 9.81},
        particles=[ball],
        gravity=(0, -g),
        constraints=[lg.Unilateral(y - x + 1, name="ramp", restitution=1)],
    )
    (wall,) = contacts_of(system).walls
    # y - x + 1 >= 0: the unit normal (-1, 1)/sqrt 2, the line n . X = -1/sqrt 2
    assert wall.normal == pytest.approx((-1 / math.sqrt(2), 1 / math.sqrt(2)))
    assert wall.offset == pytest.approx(-1 / math.sqrt(2))
    path = {"ball": np.array([[0.0, 0.0], [3.0, 2.0]])}
    [(_, segment)] = wall_segments(contacts_of(system), path)
    # across the box the ball's path spans: from (1, 0) to (3, 2), on y = x - 1
    assert np.allclose(sorted(segment.tolist()), [[1.0, 0.0], [3.0, 2.0]])


def test_constraints_of_other_forms_draw_nothing() -> None:
    x, y, a, m = sp.symbols("x y a m")
    inside = lg.System(
        coordinates=(x, y),
        parameters={a: 1.0, m: 1.0},
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Unilateral(a**2 - x**2 - y**2, name="rim", restitution=1)],
    )
    assert contacts_of(inside).radii == {} and contacts_of(inside).walls == ()
    assert contacts_of(lg.examples.bouncing_ball()).walls == ()  # no particle to draw
    assert contacts_of(lg.examples.newtons_cradle()).radii == {}
