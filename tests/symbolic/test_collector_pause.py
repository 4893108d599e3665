"""The cycle collector's pause moves what was made while paused to the oldest generation
without walking it (the first collection after a pause would otherwise walk a million
expressions of a long chain), and never leaks: a cycle made while paused is still freed by
a later full collection, and what the program froze stays frozen."""

from __future__ import annotations

import gc
import threading
import weakref
from collections.abc import Iterator

import pytest

from lagrangian.symbolic.sympy_view import cycle_collection_paused


class _Node:
    """An object that can refer to itself (a cycle only the collector frees)."""

    def __init__(self) -> None:
        self.other: _Node | None = None


def _cycle() -> weakref.ref[_Node]:
    """A garbage cycle, seen through a weak reference that dies when it is freed."""
    node = _Node()
    node.other = node
    return weakref.ref(node)


def _in_generation(obj: object, generation: int) -> bool:
    return any(o is obj for o in gc.get_objects(generation))


@pytest.fixture
def collector_on() -> Iterator[None]:
    was = gc.isenabled()
    gc.enable()
    try:
        yield
    finally:
        gc.enable() if was else gc.disable()


def test_a_cycle_made_while_paused_is_freed_by_a_later_full_collection(
    collector_on: None,
) -> None:
    with cycle_collection_paused():
        assert not gc.isenabled()
        freed_later = _cycle()
        kept = _Node()
    assert gc.isenabled()
    # moved to the oldest generation: no young collection walks it
    assert _in_generation(kept, 2)
    for _ in range(3):
        gc.collect(1)
    assert freed_later() is not None
    gc.collect()
    assert freed_later() is None


def test_nested_pauses_move_their_objects_once_the_outer_one_ends(collector_on: None) -> None:
    with cycle_collection_paused():
        with cycle_collection_paused():
            inner = _Node()
        assert not gc.isenabled()
        assert _in_generation(inner, 0)  # the outer pause still runs: nothing moved yet
    assert gc.isenabled()
    assert _in_generation(inner, 2)


def test_what_the_program_froze_stays_frozen(collector_on: None) -> None:
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        with cycle_collection_paused():
            made = _Node()
        assert gc.get_freeze_count() == frozen
        assert gc.isenabled()
        assert not _in_generation(made, 2)  # left to the young collections as before
    finally:
        gc.unfreeze()


def test_a_collector_off_stays_off_and_its_objects_where_they_were() -> None:
    was = gc.isenabled()
    gc.disable()
    try:
        with cycle_collection_paused():
            made = _Node()
        assert not gc.isenabled()
        assert _in_generation(made, 0)
    finally:
        gc.enable() if was else gc.disable()


def test_two_threads_pausing_at_once_move_both_threads_objects_at_the_end(
    collector_on: None,
) -> None:
    inside_a, inside_b, a_done = threading.Event(), threading.Event(), threading.Event()
    made: dict[str, _Node] = {}
    young_while_b_runs: list[bool] = []

    def first() -> None:
        with cycle_collection_paused():
            made["a"] = _Node()
            inside_a.set()
            inside_b.wait(10)
        a_done.set()

    def second() -> None:
        inside_a.wait(10)
        with cycle_collection_paused():
            inside_b.set()
            a_done.wait(10)
            made["b"] = _Node()
            # A ended, B still converts: the collector still off, nothing moved yet (a
            # pause that remembered only its own start would turn it on here, and leave it
            # off after B)
            young_while_b_runs.append(not gc.isenabled() and _in_generation(made["a"], 0))

    threads = [threading.Thread(target=first), threading.Thread(target=second)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(20)
    assert gc.isenabled()
    assert young_while_b_runs == [True]
    assert _in_generation(made["a"], 2) and _in_generation(made["b"], 2)


def test_the_callers_young_garbage_is_collected_before_a_pause(collector_on: None) -> None:
    """A garbage cycle the caller made just before is freed when a pause begins, not aged
    with what the pause made into the oldest generation (a loop of models would otherwise
    keep every round's cycles until a full collection that such a loop never sets off)."""
    gc.collect()  # no young collection falls due between the cycle and the pause
    before = _cycle()
    with cycle_collection_paused():
        pass
    assert before() is None
