"""``derive --format json`` is written as it is encoded (a large document is never held whole
as text): the bytes are exactly ``json.dumps`` of the same document, with one newline."""

from __future__ import annotations

import json

import pytest

from lagrangian.cli.commands import load_system
from lagrangian.cli.main import CHUNK, main
from lagrangian.documents import derivation_document


@pytest.mark.parametrize(
    ("model", "steps"),
    [
        ("examples/double_pendulum", True),
        ("examples/atwood_machine", False),
        ("n_link_pendulum:12", True),
    ],
)
def test_the_streamed_document_is_json_dumps_of_it(model, steps, capsysbinary):
    argv = ["derive", model, "--format", "json"] + (["--steps"] if steps else [])
    assert main(argv) == 0
    written = capsysbinary.readouterr().out
    document = derivation_document(load_system(model), steps)
    assert written == (json.dumps(document, indent=2, ensure_ascii=False) + "\n").encode()
    if model.startswith("n_link"):
        assert len(written) > CHUNK  # written in more than one chunk


def test_text_output_ends_with_one_newline(capsysbinary):
    assert main(["derive", "examples/simple_pendulum"]) == 0
    written = capsysbinary.readouterr().out
    assert written.endswith(b"(derive --substitute puts them in)\n")
    assert not written.endswith(b"\n\n")
