"""The first-integral search is skipped whole for a system beyond MAX_SEARCH_COORDINATES,
and says so; at the bound it still runs."""

from __future__ import annotations

import lagrangian as lg
from lagrangian.analysis.integrals import search
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
