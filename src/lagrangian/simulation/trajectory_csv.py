"""The columns of a trajectory CSV read back (:meth:`Trajectory.from_csv`), checked: text that
is not such a CSV — not UTF-8, a header without ``t`` and ``energy`` or without a coordinate
and its velocity, a repeated name, a row of another length, a value that is not a number —
is a SimulationInputError naming the line and the column, never a raw error of the parser.

>>> import io
>>> names, columns = read_columns(io.StringIO("t,x,x_dot,energy\\n0,1,0,0.5\\n"))
>>> names, columns["x"]
(['t', 'x', 'x_dot', 'energy'], array([1.]))
>>> read_columns(io.StringIO("t,x,x_dot,energy\\n0,1,0\\n"))
Traceback (most recent call last):
...
lagrangian.errors.SimulationInputError: Not a trajectory CSV (1 problem):
  - <stream>: row (line 2): 3 values, and the header names 4 — write the file with \
Trajectory.to_csv
"""

from __future__ import annotations

import io
import os
from collections import Counter
from typing import Any, TextIO

import numpy as np

from lagrangian.errors import Problem, SimulationInputError, decode_text, raise_if_problems

DOT = "_dot"
#: Problems listed at most: a long file that is no CSV says so in a few lines.
MOST_PROBLEMS = 10
FIX = "write the file with Trajectory.to_csv"


def read_columns(source: str | os.PathLike[str] | TextIO) -> tuple[list[str], dict[str, Any]]:
    """The column names of the CSV at ``source`` (a path, or a text stream) and each column
    as an array; SimulationInputError with the problems found."""
    if isinstance(source, (str, os.PathLike)):
        where = str(source)
        with open(source, "rb") as stream:
            text = decode_text(stream.read(), where, SimulationInputError)
    else:
        where, text = getattr(source, "name", "<stream>"), source.read()
        if not isinstance(text, str):
            raise SimulationInputError(f"{where}: from_csv reads text; open the file in text mode")
    header, *rows = text.splitlines() or [""]
    names = header.split(",")
    problems = _header_problems(names, header, where)
    raise_if_problems(problems, "Not a trajectory CSV", SimulationInputError)
    data = np.zeros((0, len(names)))
    if any(row.strip() for row in rows):
        data = _numbers(names, rows, where)
    return names, dict(zip(names, data.T))


def _numbers(names: list[str], rows: list[str], where: str) -> np.ndarray:
    """The rows as a table of numbers, one column a name."""
    try:
        data = np.loadtxt(io.StringIO("\n".join(rows)), delimiter=",", ndmin=2)
    except ValueError:  # rows of other lengths, or not numbers: found below
        data = None
    if data is None or data.shape[1] != len(names):  # find the line, for the message
        problems = _row_problems(names, rows, where)
        raise_if_problems(problems, "Not a trajectory CSV", SimulationInputError)
        raise SimulationInputError(f"{where}: not a trajectory CSV; {FIX}")
    return data


def _header_problems(names: list[str], header: str, where: str) -> list[Problem]:
    if names[:1] != ["t"] or "energy" not in names:
        message = f"the header {header[:80]!r} must start with t and hold energy"
        return [Problem("header", message, FIX, 1, source=where)]
    problems = []
    repeated = sorted(name for name, count in Counter(names).items() if count > 1)
    if repeated:
        message = f"the columns {', '.join(repeated)} are named more than once"
        problems.append(Problem("header", message, FIX, 1, source=where))
    known = set(names)  # a gas has a column per contact: look names up, not along the list
    if not any(name + DOT in known for name in names[1:]):
        message = "no coordinate column with its velocity (NAME and NAME_dot)"
        problems.append(Problem("header", message, FIX, 1, source=where))
    return problems


def _row_problems(names: list[str], rows: list[str], where: str) -> list[Problem]:
    """What is wrong with the rows: a row of another length, a value that is no number (the
    first :data:`MOST_PROBLEMS`)."""
    problems: list[Problem] = []
    for line, row in enumerate(rows, start=2):
        if len(problems) >= MOST_PROBLEMS:
            break
        if not row.strip():
            continue
        values = row.split(",")
        if len(values) != len(names):
            message = f"{len(values)} values, and the header names {len(names)}"
            problems.append(Problem("row", message, FIX, line, source=where))
            continue
        for column, (name, value) in enumerate(zip(names, values), start=1):
            try:
                float(value)
            except ValueError:
                message = f"{value[:40]!r} is not a number"
                problems.append(Problem(name, message, FIX, line, column, where))
    return problems
