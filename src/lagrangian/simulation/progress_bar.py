"""A progress bar on standard error for long work (only on a terminal unless forced).

>>> import io
>>> stream = io.StringIO()
>>> bar = progress_bar(0.0, 10.0, stream, force=True)
>>> bar(5.0)
>>> stream.getvalue()
'\\r[###############...............]  50%  t = 5'
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TextIO

WIDTH = 30


def progress_bar(
    start: float,
    end: float,
    stream: TextIO | None = None,
    force: bool = False,
    label: str = "t = ",
) -> Callable[[float], None] | None:
    """A callback drawing ``[#####.....]  42%  t = 4.2`` as the value advances from start to
    end (``label`` names it); None when the stream is not a terminal (CI logs stay clean)
    unless ``force``."""
    stream = stream or sys.stderr
    if not (force or stream.isatty()) or end <= start:
        return None
    shown = [-1]

    def update(value: float) -> None:
        fraction = min(max((value - start) / (end - start), 0.0), 1.0)
        percent = int(100 * fraction)
        if percent == shown[0]:
            return
        shown[0] = percent
        filled = int(WIDTH * fraction)
        stream.write(
            f"\r[{'#' * filled}{'.' * (WIDTH - filled)}] {percent:3d}%  {label}{value:.4g}"
        )
        if percent == 100:
            stream.write("\n")
        stream.flush()

    return update
