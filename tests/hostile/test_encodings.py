"""A model that is not UTF-8 text (issue 34, item 3): Latin-1, UTF-16, binary bytes, in a file
or on standard input, ends in exit 2 naming the encoding problem, the byte and its position,
never in an internal error from the decoder."""

from __future__ import annotations

import pytest

MODEL = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2  # café\n"

PROBES = {
    "latin-1": (MODEL.encode("latin-1"), ["byte 0xe9 at position 61", "line 3, column 25"]),
    "utf-16": (MODEL.encode("utf-16"), ["byte 0xff at position 0", "the file is UTF-16"]),
    "binary": (b"coordinates: [x]\n\x00\x01\x02\xff", ["0x00 at position 17", "NUL byte"]),
}


@pytest.mark.parametrize("name", list(PROBES))
def test_a_model_file_that_is_not_utf8_is_refused_with_the_byte(cli, tmp_path, name):
    data, words = PROBES[name]
    (tmp_path / "model.yaml").write_bytes(data)
    outcome = cli(["derive", "model.yaml"])
    assert outcome.code == 2 and not outcome.internal, outcome
    for word in ["model.yaml", "not UTF-8 text", "save the file as UTF-8", *words]:
        assert word in outcome.err, (word, outcome)


def test_standard_input_that_is_not_utf8_is_refused_with_the_byte(cli):
    outcome = cli(["derive", "-"], "coordinates: [x]\n# \udce9\n")  # a byte no UTF-8 has
    assert outcome.code == 2 and not outcome.internal, outcome
    assert "<standard input>" in outcome.err and "position 19" in outcome.err, outcome
