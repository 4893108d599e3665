"""The gas of hard disks from the command line: its impacts table beside the CSV and the
marks of its plots carry every impact, each checked against the billiard-ball laws (e = 1):
a wall reverses the normal velocity of its disk, two disks keep their total momentum and
kinetic energy and exchange the velocity components along the line of their centres."""

from __future__ import annotations

import csv
from itertools import combinations
from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli.main import main

N = 3


def velocities(row: dict[str, str], when: str) -> np.ndarray:
    """The disks' velocities (N, 2) before or after an impact, from the table's columns."""
    return np.array(
        [[float(row[f"{axis}{i}_dot_{when}"]) for axis in "xy"] for i in range(1, N + 1)]
    )


def test_the_gas_writes_every_impact_to_its_table(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "gas.csv"
    code = main(["simulate", f"hard_disk_gas:{N}", "--t-end", "3", "--out", str(out)])
    said = capsys.readouterr().out
    assert code == 0
    with open(tmp_path / "gas.impacts.csv", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    count = int(said.split(" impacts")[0].split()[-1])  # "... 17 impacts (left3, ...)"
    assert len(rows) == count > N
    walls = {f"{side}{i}": i for i in range(1, N + 1) for side in ("left", "right")}
    walls |= {f"{side}{i}": i for i in range(1, N + 1) for side in ("bottom", "top")}
    pairs = {f"disks{i}_{j}": (i, j) for i, j in combinations(range(1, N + 1), 2)}
    times = [float(row["t"]) for row in rows]
    assert times == sorted(times) and times[0] > 0 and times[-1] <= 3
    kinds = set()
    for row in rows:
        (struck,) = row["constraints"].split(";")  # one contact at a time in this gas
        before, after = velocities(row, "before"), velocities(row, "after")
        assert float(row["energy_lost"]) == pytest.approx(0, abs=1e-12)
        assert float(row[f"impulse_{struck}"]) > 0
        np.testing.assert_allclose((after**2).sum(), (before**2).sum(), rtol=1e-12)
        if struck in walls:
            kinds.add("wall")
            k = walls[struck] - 1
            axis = 0 if struck.startswith(("left", "right")) else 1
            assert after[k, axis] == pytest.approx(-before[k, axis])
            assert after[k, 1 - axis] == pytest.approx(before[k, 1 - axis])
            others = np.delete(np.arange(N), k)
            np.testing.assert_array_equal(after[others], before[others])
        else:
            kinds.add("pair")
            i, j = (k - 1 for k in pairs[struck])
            np.testing.assert_allclose(after[i] + after[j], before[i] + before[j], atol=1e-12)
            # equal masses: the components along the centres' line are exchanged
            line = after[i] - before[i]
            line /= np.linalg.norm(line)
            assert after[i] @ line == pytest.approx(before[j] @ line)
            assert after[j] @ line == pytest.approx(before[i] @ line)
    assert kinds == {"wall", "pair"}


def test_the_gas_plots_mark_its_impacts() -> None:
    from lagrangian.render.plots import MARKED_IMPACTS, overview

    system = lg.examples.hard_disk_gas(N)
    run = lg.simulate(system, t_span=3.0, samples=301)
    assert 0 < len(run.impacts) < MARKED_IMPACTS
    figure = overview(run, system=system)
    for title in ("Time series", "Energy"):  # the energy's change, or its drift at e = 1
        (ax,) = [a for a in figure.axes if a.get_title().startswith(title)]
        marks = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
        assert [float(line.get_xdata()[0]) for line in marks] == [i.t for i in run.impacts]
