"""The first-integral search is skipped whole for a system beyond MAX_SEARCH_COORDINATES,
and says so; at the bound it still runs, and a stage too large is weighed before it is built."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.integrals import search, trigonometric
from lagrangian.analysis.integrals.search import MAX_SEARCH_COORDINATES, first_integrals


def test_a_hundred_link_chain_is_not_searched_and_the_search_says_so(monkeypatch) -> None:
    def refuse(*args, **kwargs):
        raise AssertionError("a stage of the search ran")

    monkeypatch.setattr(search, "_stages", refuse)
    monkeypatch.setattr(search, "_conditional", refuse)
    result = first_integrals(lg.examples.n_link_pendulum(100))
    assert result.found == ()
    (line,) = result.searched
    assert "not searched" in line
    assert f"100 coordinates, more than the {MAX_SEARCH_COORDINATES}" in line
    for stage in ("Lie point symmetries", "quadratic", "trigonometric", "conditional"):
        assert stage in line


def test_a_small_system_is_searched() -> None:
    """The double pendulum's search runs (its stages are listed, none skipped whole)."""
    result = first_integrals(lg.examples.n_link_pendulum(2))
    assert result.searched
    assert not any("coordinates, more than" in line for line in result.searched)


def test_a_twelve_link_chains_trigonometric_stage_is_weighed_without_being_built(
    monkeypatch,
) -> None:
    """Its ansatz of degree 4 in 12 angles has millions of unknowns: counted, not built (it
    ran out of the analysis's time share before), and the search says it was too large."""

    def refuse(*args, **kwargs):
        raise AssertionError("the ansatz was built to be counted")

    monkeypatch.setattr(trigonometric, "trigonometric_ansatz", refuse)
    result = first_integrals(lg.examples.n_link_pendulum(12))
    (line,) = [line for line in result.searched if "trigonometric" in line]
    assert line.endswith(f"not searched (more than {search.MAX_UNKNOWNS} unknowns)")


def test_the_trigonometric_monomials_are_counted_as_built() -> None:
    angles = sp.symbols("a1:6")
    for n in range(6):
        for degree in range(-1, 5):
            built = trigonometric._trigonometric_monomials(angles[:n], degree)
            assert trigonometric._trigonometric_count(n, degree) == len(built)
            assert len(set(built)) == len(built)  # a basis: no product twice


@pytest.mark.parametrize(
    "name", ["planet", "spherical_pendulum", "heavy_symmetric_top", "double_pendulum"]
)
def test_the_ansatz_sizes_are_those_of_the_ansatz_built(name) -> None:
    q = lg.derive(lg.examples.get(name)()).coordinates
    splits = [
        trigonometric.Angles(turning=tuple(q)),
        trigonometric.Angles(turning=q[:1], cyclic=q[1:2]),
        trigonometric.Angles(cyclic=q[:2]),
        trigonometric.Angles(turning=q[1:], translations=q[:1]),
        trigonometric.Angles(),
    ]
    for angles in splits:
        for degree in range(4):
            for even_and_odd in (False, True):
                _, ansatze = trigonometric.trigonometric_ansatz(q, angles, degree, even_and_odd)
                counted = trigonometric.ansatz_sizes(q, angles, degree, even_and_odd)
                assert counted == [a.unknowns for a in ansatze]
