"""One reading of a limit serves the time limit and the size limit: the keyword, else the
environment variable, else the default, the words of "no limit", the same checks, and each
limit's messages in its own units and words (as each read its limit before they shared it)."""

from __future__ import annotations

import math
import re
import threading

import pytest

from lagrangian import limits, size_limits
from lagrangian.errors import ArgumentError
from lagrangian.limits import NO_LIMIT, LimitStack, configured_limit, configured_seconds
from lagrangian.size_limits import configured_operations

TIME, SIZE = limits.ENVIRONMENT, size_limits.ENVIRONMENT


@pytest.fixture(autouse=True)
def no_environment(monkeypatch):
    monkeypatch.delenv(TIME, raising=False)
    monkeypatch.delenv(SIZE, raising=False)


def test_without_a_value_or_the_environment_each_limit_is_its_default():
    assert configured_seconds() == limits.DEFAULT_SECONDS == 600.0
    assert configured_operations() == size_limits.DEFAULT_OPERATIONS == 5_000_000


@pytest.mark.parametrize("word", [*NO_LIMIT, "None", " OFF "])
def test_every_word_of_no_limit_means_no_limit_for_both(monkeypatch, word):
    monkeypatch.setenv(TIME, word)
    monkeypatch.setenv(SIZE, word)
    assert configured_seconds() is None  # the time limit's "none" is None
    assert configured_operations() == math.inf  # the size limit's is math.inf


def test_the_environment_gives_seconds_as_a_number_and_operations_as_a_whole_number(
    monkeypatch,
):
    monkeypatch.setenv(TIME, "2.5")
    monkeypatch.setenv(SIZE, "1000")
    assert configured_seconds() == 2.5
    assert configured_operations() == 1000
    monkeypatch.setenv(SIZE, "2.5")  # a size limit is a count
    with pytest.raises(ArgumentError, match=re.escape(f"{SIZE}='2.5' is not a whole number")):
        configured_operations()


@pytest.mark.parametrize(
    ("read", "variable", "text", "message"),
    [
        (
            configured_seconds,
            TIME,
            "soon",
            f"{TIME}='soon' is not a number of seconds: give a positive number, or none for "
            "no limit",
        ),
        (configured_seconds, TIME, "-5", f"{TIME}=-5.0: give a positive number of seconds"),
        (
            configured_operations,
            SIZE,
            "lots",
            f"{SIZE}='lots' is not a whole number of operations: give a positive whole "
            "number, or none for no limit",
        ),
        (configured_operations, SIZE, "0", f"{SIZE}=0: give a positive number of operations"),
    ],
)
def test_a_bad_environment_value_keeps_each_limits_message(
    monkeypatch, read, variable, text, message
):
    monkeypatch.setenv(variable, text)
    with pytest.raises(ArgumentError, match=f"^{re.escape(message)}$"):
        read()


@pytest.mark.parametrize(
    ("read", "value", "message"),
    [
        (
            configured_seconds,
            "10",
            "time_limit takes a number of seconds, not str: give a positive number, or "
            "math.inf for no limit",
        ),
        (configured_seconds, 0, "time_limit=0: give a positive number of seconds"),
        (configured_seconds, math.nan, "time_limit=nan: give a positive number of seconds"),
        (
            configured_operations,
            True,
            "size_limit takes a number of operations, not bool: give a positive whole number, "
            "or math.inf for no limit",
        ),
        (configured_operations, 0.5, "size_limit=0.5: give a positive number of operations"),
    ],
)
def test_a_bad_keyword_keeps_each_limits_message(read, value, message):
    with pytest.raises(ArgumentError, match=f"^{re.escape(message)}$"):
        read(value)


def test_a_size_limit_option_is_named_where_it_was_given():
    with pytest.raises(ArgumentError, match=r"^--size-limit=-3: give a positive number"):
        configured_operations(-3, "--size-limit")


def test_the_smallest_limit_differs_by_kind():
    # a time limit may be a fraction of a second; a size limit is at least one operation
    assert configured_seconds(0.01) == 0.01
    assert configured_operations(1) == 1
    with pytest.raises(ArgumentError, match="operations"):
        configured_operations(0.99)


def test_the_shared_reading_serves_another_unit_in_its_words(monkeypatch):
    monkeypatch.setenv("EXAMPLE_LIMIT", "off")
    read = {"environment": "EXAMPLE_LIMIT", "default": 3.0, "unit": "steps", "where": "steps"}
    assert configured_limit(None, **read) == math.inf
    assert configured_limit(7, **read) == 7
    with pytest.raises(ArgumentError, match=r"^steps=-1: give a positive number of steps$"):
        configured_limit(-1, **read)


def test_each_thread_and_each_kind_of_limit_has_its_own_stack():
    first: LimitStack[int] = LimitStack()
    second: LimitStack[str] = LimitStack()
    first.stack.append(1)
    seen = []
    worker = threading.Thread(target=lambda: seen.append(list(first.stack)))
    worker.start()
    worker.join()
    assert seen == [[]]  # another thread starts with no limit
    assert first.stack == [1] and second.stack == []
    with limits.time_limit(30), size_limits.size_limit(100):
        assert 0 < limits.remaining_seconds() <= 30  # each kind reads its own stack
        assert size_limits.active_operations() == 100
    assert limits.remaining_seconds() is None
