"""The impacts of a Trajectory as people and programs read them: one line of summary, a CSV
table (one row an impact, beside the trajectory's own CSV) and JSON-ready records.

>>> from lagrangian.simulation.trajectory import Impact
>>> hit = Impact(0.45, ("floor",), {"floor": 7.97}, {"y_dot": -4.43}, {"y_dot": 3.54}, 3.53)
>>> rest = Impact(4.06, ("floor",), {"floor": 0.0005}, {"y_dot": -0.0005}, {"y_dot": 0.0}, 0.0,
...               ("floor",))
>>> impacts_summary((hit, rest))
'2 impacts (floor); at rest on floor from t = 4.06'
>>> impacts_summary([Impact(0.1 * k, (f"wall{k}",), {f"wall{k}": 1.0}, {}, {}, 0.0)
...                  for k in range(8)])
'8 impacts (wall0, wall1, wall2, wall3, wall4, wall5 and 2 more constraints)'
>>> impact_records((hit,))[0]["after"]
{'y_dot': 3.54}
"""

from __future__ import annotations

import csv
import os
from collections import Counter
from collections.abc import Sequence
from typing import Any, TextIO

from lagrangian.analysis.evaluation import names_text
from lagrangian.simulation.files import written_atomically
from lagrangian.simulation.trajectory import Impact


def impacts_summary(impacts: Sequence[Impact]) -> str:
    """How many impacts and transitions (impacts without impulses: a reset of the state)
    there were, on what, and where a contact came to rest; '' when there were none."""
    parts = []
    for noun, group in (("impact", [i for i in impacts if i.impulses]),
                        ("transition", [i for i in impacts if not i.impulses])):  # fmt: skip
        if group:
            names = list(Counter(name for impact in group for name in impact.constraints))
            plural = noun if len(group) == 1 else f"{noun}s"
            parts.append(f"{len(group)} {plural} ({names_text(names, 'more constraints')})")
    for impact in impacts:
        parts.extend(f"at rest on {name} from t = {impact.t:.6g}" for name in impact.rest)
    return "; ".join(parts)


def impact_records(impacts: Sequence[Impact]) -> list[dict[str, Any]]:
    """Each impact as a JSON-ready mapping (the fields of :class:`Impact`)."""
    return [
        {
            "t": impact.t,
            "constraints": list(impact.constraints),
            "impulses": dict(impact.impulses),
            "before": dict(impact.before),
            "after": dict(impact.after),
            "energy_lost": impact.energy_lost,
            "rest": list(impact.rest),
        }
        for impact in impacts
    ]


def write_impacts_csv(
    impacts: Sequence[Impact], destination: str | os.PathLike[str] | TextIO
) -> None:
    """One row an impact: t, the constraints (joined by +), the energy lost, the contacts come
    to rest, then impulse_NAME of every constraint and NAME_dot_before, NAME_dot_after of
    every velocity (17 significant digits); a file is written atomically."""
    if isinstance(destination, (str, os.PathLike)):
        with (
            written_atomically(destination) as temporary,
            open(temporary, "w", encoding="utf-8", newline="") as stream,
        ):
            _write(impacts, stream)
    else:
        _write(impacts, destination)


def _write(impacts: Sequence[Impact], stream: TextIO) -> None:
    constraints = list(dict.fromkeys(n for i in impacts for n in i.impulses))
    velocities = list(dict.fromkeys(n for i in impacts for n in i.before))
    header = ["t", "constraints", "energy_lost", "rest"]
    header += [f"impulse_{n}" for n in constraints]
    header += [f"{v}_{when}" for v in velocities for when in ("before", "after")]
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header)
    for impact in impacts:
        row: list[Any] = [_number(impact.t), "+".join(impact.constraints),
                          _number(impact.energy_lost), "+".join(impact.rest)]  # fmt: skip
        row += [_number(impact.impulses[n]) if n in impact.impulses else "" for n in constraints]
        row += [_number(side[v]) for v in velocities for side in (impact.before, impact.after)]
        writer.writerow(row)


def _number(value: float) -> str:
    return f"{value:.17g}"
