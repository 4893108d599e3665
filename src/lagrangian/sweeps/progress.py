"""The progress line of a sweep on standard error: members done, rate, time left.

>>> import io
>>> stream = io.StringIO()
>>> line = ProgressLine(1000, stream, force=True, clock=iter([0.0, 2.0]).__next__)
>>> line.advance(250)
>>> stream.getvalue()
'\\rmembers 250/1000 (25%)  125/s  0:06 left'
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from typing import TextIO


class ProgressLine:
    """One line redrawn as blocks finish; silent unless ``stream`` is a terminal or ``force``."""

    def __init__(
        self,
        total: int,
        stream: TextIO | None = None,
        force: bool = False,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.stream = stream or sys.stderr
        self.total, self.done, self.clock = total, 0, clock
        self.shown = force or self.stream.isatty()
        self.start = clock()

    def advance(self, members: int) -> None:
        """``members`` more are written."""
        self.done += members
        if not self.shown:
            return
        elapsed = max(self.clock() - self.start, 1e-9)
        rate = self.done / elapsed
        left = (self.total - self.done) / rate if rate > 0 else 0.0
        percent = int(100 * self.done / max(self.total, 1))
        self.stream.write(
            f"\rmembers {self.done}/{self.total} ({percent}%)  {rate:.4g}/s  "
            f"{_clock_time(left)} left"
        )
        self.stream.flush()

    def close(self) -> None:
        """End the line."""
        if self.shown and self.done:
            self.stream.write("\n")
            self.stream.flush()


def _clock_time(seconds: float) -> str:
    """``h:mm:ss`` or ``m:ss``."""
    whole = round(seconds)
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"
