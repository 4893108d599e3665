"""One status vocabulary: the C loop's codes are the values of ``Status``, every code has its
sentence and its word, and the words compare and print as the plain strings users read."""

from __future__ import annotations

import json
import re
from pathlib import Path

import lagrangian
from lagrangian.numerics.status import Outcome, Status

C_LOOP = Path(lagrangian.__file__).parent / "numerics" / "fast" / "c_loop.c"


def test_the_c_loops_end_codes_are_the_status_values() -> None:
    source = C_LOOP.read_text()
    codes = dict(re.findall(r"LG_([A-Z_]+) = (\d+)", source))
    assert codes  # the enum was found
    for name, value in codes.items():
        assert Status[name] == int(value), name


def test_every_status_has_a_sentence_and_a_word() -> None:
    for status in Status:
        assert status.message.endswith(".")
        assert status.outcome in Outcome
    assert [s for s in Status if not s.failed] == [
        Status.FINISHED,
        Status.STOPPED,
        Status.INTERRUPTED,
    ]


def test_the_words_are_the_plain_strings() -> None:
    assert Outcome.SUCCESS == "success"
    assert f"{Outcome.STOPPED}|{Outcome.FAILED!s}" == "stopped|failed"
    assert repr((Outcome.SUCCESS,)) == "('success',)"
    assert json.dumps({"status": Outcome.INTERRUPTED}) == '{"status": "interrupted"}'
