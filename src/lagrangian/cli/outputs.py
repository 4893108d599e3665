"""The output paths of a command, checked before any work: a folder given for a file, a file
in a folder that does not exist or cannot be written, a file given for export's folder.  Each
problem names the option, the path as the user gave it (never the temporary file an atomic
write goes through, :mod:`lagrangian.simulation.files`) and the fix.

>>> import tempfile
>>> folder = tempfile.mkdtemp()
>>> print(file_problems({"--out": folder}, "run.csv")[0].message)  # doctest: +ELLIPSIS
'...' is a folder, not a file
"""

from __future__ import annotations

import os
import shlex
from collections.abc import Mapping
from pathlib import Path

from lagrangian.errors import Problem
from lagrangian.simulation.files import written_in_place


def file_problems(options: Mapping[str, str | None], example: str) -> list[Problem]:
    """The problems of the files ``options`` name (option -> path; None and ``-`` are not
    files); ``example`` is a file name to suggest in a folder given instead of a file."""
    problems = []
    for option, path in options.items():
        if path is None or path == "-" or written_in_place(path):
            continue  # standard output, a device, a FIFO: written as they stand
        if os.path.isdir(path):
            fix = f"name a file in it, such as {os.path.join(path, example)}"
            problems.append(Problem(option, f"{path!r} is a folder, not a file", fix))
            continue
        # the folder the file goes into, links followed (where an atomic write puts its
        # temporary file), said as the user wrote it
        given = os.path.dirname(path) or "."
        problem = _folder_problem(option, path, given, Path(os.path.realpath(path)).parent)
        if problem is not None:
            problems.append(problem)
    return problems


def folder_problem(option: str, folder: str) -> Problem | None:
    """The problem of ``folder`` as a folder to write files into (made when missing, with
    its parents), or None: a file, or nothing writable on its way."""
    if folder == "-":
        return None
    path = Path(os.path.realpath(folder))
    if path.exists() and not path.is_dir():
        fix = "name a folder for the files (it is made if missing), or - for standard output"
        return Problem(option, f"{folder!r} is a file, not a folder", fix)
    existing = next(p for p in (path, *path.parents) if p.exists())
    if not existing.is_dir():
        return Problem(
            option, f"{str(existing)!r} is a file, not a folder", f"name another {option}"
        )
    return _writable(option, folder, str(existing), existing)


def _folder_problem(option: str, path: str, given: str, folder: Path) -> Problem | None:
    if not folder.exists():
        fix = (
            f"make it first (mkdir -p {shlex.quote(given)}), or name a file in a folder that exists"
        )
        return Problem(option, f"{path!r}: the folder {given!r} does not exist", fix)
    if not folder.is_dir():
        fix = "name a file in a folder"
        return Problem(option, f"{path!r}: {given!r} is a file, not a folder", fix)
    return _writable(option, path, given, folder)


def _writable(option: str, path: str, given: str, folder: Path) -> Problem | None:
    if os.access(folder, os.W_OK | os.X_OK):
        return None
    message = (
        f"{path!r}: the folder {given!r} cannot be written to (no permission, or a read-only "
        "file system)"
    )
    return Problem(option, message, "name a place you can write to")
