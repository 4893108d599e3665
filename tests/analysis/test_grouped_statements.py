"""Statements about many constraints are said once, naming them all: the gas's 22 contacts
left out of the analysis, a cradle ball's two neighbours that change its momentum.  The
names expected are written here from the gas's construction (four walls a disk, a contact a
pair of disks), not read from the analysis."""

from __future__ import annotations

import dataclasses
import json
import re
from itertools import combinations

import sympy as sp

import lagrangian as lg
from lagrangian.analysis.manifold.left_out import constraint_names
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_text import analysis_text


def gas_contacts(n: int) -> list[str]:
    """The constraints of n disks, in the order the gas is built: walls, then pairs."""
    walls = [f"{side}{i}" for i in range(1, n + 1) for side in ("left", "right", "bottom", "top")]
    return walls + [f"disks{i}_{j}" for i, j in combinations(range(1, n + 1), 2)]


def test_the_gas_says_once_that_its_contacts_are_left_out() -> None:
    report = lg.analyze(lg.examples.hard_disk_gas(4))
    names = gas_contacts(4)
    assert len(names) == 22
    statement = "22 unilateral constraints, taken as released (g > 0): " + ", ".join(
        repr(name) for name in names
    )
    assert report.freedom.count("left out of this analysis") == 1
    assert f"{statement} (constraints[0] to constraints[21])" in report.freedom
    document = analysis_document(report)
    said = [document["freedom"], document["first_integral_search"][0]]
    assert said[1].startswith("searched without the constraints, away from contact: 22 ")
    for statement in said:  # each contact named once in each
        assert statement.count("taken as released") == 1
        for name in names:
            assert len(re.findall(rf"'{name}'", statement)) == 1, name
    text = analysis_text(report)
    assert text.count("left out of this analysis") == 1 and text.count("taken as released") == 2
    assert json.dumps(document).count("taken as released") == 2


def test_each_reason_is_its_own_statement_and_positions_apart_are_listed() -> None:
    x, y, m, g, length = sp.symbols("x y m g l")
    rod = x**2 + y**2 - length**2
    system = lg.System(
        coordinates=(x, y),
        parameters={m: 1.0, g: 9.81, length: 1.0},
        particles=[lg.Particle("bob", m, (x, y))],
        gravity=(0, -g),
        constraints=[
            lg.Unilateral(y + 2, name="floor"),
            lg.Holonomic(rod, name="rod"),
            lg.Unilateral(x + 2, name="wall"),
            lg.Holonomic(2 * rod, name="rod_again"),
        ],
    )
    freedom = lg.analyze(system, search_degree=0).freedom
    assert (
        "2 unilateral constraints, taken as released (g > 0): 'floor', 'wall' "
        "(constraints[0], constraints[2])"
    ) in freedom
    assert "'rod_again' (constraints[3]) redundant: its Jacobian row is a combination" in freedom
    assert freedom.count("left out of this analysis") == 2


def test_constraints_are_named_together_as_one_or_many() -> None:
    a, b = lg.Unilateral(sp.Symbol("x"), name="a"), lg.Unilateral(sp.Symbol("y"))
    assert constraint_names([(3, a)]) == "'a' (constraints[3])"
    assert constraint_names([(3, a), (4, b)]) == "constraints[3] to constraints[4]"
    assert constraint_names([(0, a), (5, a)]) == "'a', 'a' (constraints[0], constraints[5])"


def test_a_cyclic_momentum_names_every_contact_that_changes_it_once() -> None:
    cradle = lg.analyze(lg.examples.newtons_cradle(), search_degree=0)
    middle = next(c for c in cradle.cyclic if c.coordinate.name == "x2")
    assert not middle.conserved and middle.obstructions == ("constraint",)
    assert (
        "the unilateral constraints 'first', 'second' (constraints[0] to constraints[1]) "
        "while in contact change it"
    ) in middle.reason
    # a gas in no field: every coordinate is cyclic, each changed by its own disk's contacts
    n = 5
    free = dataclasses.replace(lg.examples.hard_disk_gas(n), gravity=None)
    cyclic = {c.coordinate.name: c for c in lg.analyze(free, search_degree=0).cyclic}
    assert len(cyclic) == 2 * n
    for axis, walls in (("x", ("left", "right")), ("y", ("bottom", "top"))):
        for i in range(1, n + 1):
            reason = cyclic[f"{axis}{i}"].reason
            named = set(re.findall(r"'(\w+)'", reason))
            pairs = {f"disks{a}_{b}" for a, b in combinations(range(1, n + 1), 2) if i in (a, b)}
            assert named == {f"{walls[0]}{i}", f"{walls[1]}{i}"} | pairs, (axis, i)
            assert reason.count("while in contact") == 1
