"""Impacts and transitions on the command line: the run says how many and where a contact
came to rest, and writes a table of them beside its CSV."""

from __future__ import annotations

import csv

import pytest

from lagrangian.cli.main import main


def test_simulate_reports_the_bounces_and_the_rest_and_writes_their_table(tmp_path, capsys):
    out = tmp_path / "ball.csv"
    code = main(["simulate", "examples/bouncing_ball", "--out", str(out)])
    said = capsys.readouterr()
    assert code == 0, said.err
    # e = 0.8 from 1 m: the bounces accumulate at t1 (1 + e)/(1 - e) = 4.0637 s
    assert "impacts (floor); at rest on floor from t = 4.063" in said.out
    with open(tmp_path / "ball.impacts.csv", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert len(rows) > 30 and rows[-1]["rest"] == "floor"
    first = rows[0]
    assert float(first["y_dot_after"]) == pytest.approx(-0.8 * float(first["y_dot_before"]))
    assert float(first["impulse_floor"]) > 0


def test_a_walker_reports_transitions(tmp_path, capsys):
    out = tmp_path / "walk.csv"
    assert main(["simulate", "examples/simplest_walker", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    assert "5 transitions (heel_strike)" in said
    assert "energy not conserved: forcing, transitions" in said
    assert (tmp_path / "walk.impacts.csv").read_text(encoding="utf-8").count("heel_strike") == 5
