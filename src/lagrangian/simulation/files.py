"""Output files written atomically: a reader sees the old file or the whole new one, never a
half-written one (a run stopped by Ctrl-C or a full disk leaves no truncated CSV behind).

The content goes to a new file in the same folder (same file system, same suffix, so a
writer that picks the format by suffix still does), which then replaces the target in one
step (``os.replace``).

>>> import pathlib, tempfile
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> with written_atomically(folder / "out.csv") as temporary:
...     _ = temporary.write_text("t\\n0\\n")
>>> (folder / "out.csv").read_text(), sorted(p.name for p in folder.iterdir())
('t\\n0\\n', ['out.csv'])
"""

from __future__ import annotations

import errno
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

#: Characters of the target's name (and of its suffix) kept in the temporary file's name.
NAME_KEPT = 64


@contextmanager
def written_atomically(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A new empty file next to ``path`` to write to; when the block ends without an error it
    replaces ``path``, else it is removed and the error goes on."""
    target = Path(path)
    # unique to this writer (two processes writing one file each get their own), and short
    # enough for the file system however long the target's name is
    unique = f".{target.name[:NAME_KEPT]}.{secrets.token_hex(8)}{target.suffix[:NAME_KEPT]}"
    temporary = target.with_name(unique)
    try:
        with open(temporary, "x"):  # created as any new file (the umask's permissions)
            pass
    except FileNotFoundError:  # name the file asked for, not the temporary one
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT), str(target)) from None
    try:
        yield temporary
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
