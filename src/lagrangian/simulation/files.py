"""Output files written atomically: a reader sees the old file or the whole new one, never a
half-written one (a run stopped by Ctrl-C or a full disk leaves no truncated CSV behind).

The content goes to a new file in the same folder (same file system, same suffix, so a
writer that picks the format by suffix still does), which then replaces the target in one
step (``os.replace``).  Only a regular file, or a name that does not exist yet, is replaced
so: a device (``/dev/null``), a FIFO, a socket or a name of the standard streams
(``/dev/stdout``, ``/proc/self/fd/1``) is written as it stands, since replacing it would put
a regular file where the device was (for ``/dev/null`` run as root, for every program after).
A symbolic link stays a link: the file it points to is replaced, from a temporary file in
that file's folder.

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
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

#: Characters of the target's name (and of its suffix) kept in the temporary file's name.
NAME_KEPT = 64
#: Folders of the kernel's own files (devices, the standard streams' names), never a place
#: for a temporary file.
KERNEL_FOLDERS = ("dev", "proc")


@contextmanager
def written_atomically(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A new empty file next to ``path`` to write to; when the block ends without an error it
    replaces ``path``, else it is removed and the error goes on.  A ``path`` that is written
    in place (:func:`written_in_place`) is given itself; a folder is an IsADirectoryError
    naming it."""
    given = Path(path)
    if written_in_place(given):
        yield given
        return
    if given.is_dir():
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(given))
    target = Path(os.path.realpath(given))  # a link stays: the file it points to is replaced
    # unique to this writer (two processes writing one file each get their own), and short
    # enough for the file system however long the target's name is
    unique = f".{target.name[:NAME_KEPT]}.{secrets.token_hex(8)}{target.suffix[:NAME_KEPT]}"
    temporary = target.with_name(unique)
    try:
        with open(temporary, "x"):  # created as any new file (the umask's permissions)
            pass
    except OSError as error:  # name the file asked for, not the temporary one
        raise OSError(error.errno, error.strerror, str(given)) from None
    try:
        yield temporary
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def written_in_place(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is written as it stands rather than replaced: it exists and is
    neither a regular file nor a folder (a device, a FIFO, a socket, links followed), or it
    lies in ``/dev`` or ``/proc`` (``/dev/stdout`` may point to a regular file the shell
    opened, whose content a replacement would cut off from it).

    >>> written_in_place("/dev/null"), written_in_place("run.csv")
    (True, False)
    """
    parts = Path(os.path.abspath(path)).parts
    if len(parts) > 1 and parts[1] in KERNEL_FOLDERS:
        return True
    try:
        mode = os.stat(path).st_mode
    except OSError:  # missing, or its folder is: a new file (the error comes with the write)
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))
