"""A progress bar on standard error for long simulations (only on a terminal)."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TextIO

WIDTH = 30


def progress_bar(
    t_start: float, t_end: float, stream: TextIO | None = None, force: bool = False
) -> Callable[[float], None] | None:
    """A callback drawing ``[#####.....]  42%  t = 4.2`` as time advances; None when the
    stream is not a terminal (CI logs stay clean) unless ``force``."""
    stream = stream or sys.stderr
    if not (force or stream.isatty()) or t_end <= t_start:
        return None
    shown = [-1]

    def update(t: float) -> None:
        fraction = min(max((t - t_start) / (t_end - t_start), 0.0), 1.0)
        percent = int(100 * fraction)
        if percent == shown[0]:
            return
        shown[0] = percent
        filled = int(WIDTH * fraction)
        stream.write(f"\r[{'#' * filled}{'.' * (WIDTH - filled)}] {percent:3d}%  t = {t:.4g}")
        if percent == 100:
            stream.write("\n")
        stream.flush()

    return update
