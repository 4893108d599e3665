"""Running the parts of an analysis one by one: a part that fails, or runs past its share of
the time, is recorded with its reason and the report goes on with the next.

Each part may take :data:`PART_SHARE` of the time the analysis has left (none when there is
no limit), so that no part whose expressions grow can take the whole time and leave no
report; the command's own limit, once spent, stops the analysis (TimeLimitError).

>>> runner = PartRunner()
>>> runner.run("ratio", lambda: 1 / 0) is None, runner.failures[0].reason
(True, 'internal error: ZeroDivisionError: division by zero')
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeVar

from lagrangian import limits
from lagrangian.errors import LagrangianError, TimeLimitError

T = TypeVar("T")

#: The share of the analysis's time left that one part may take: a part still running then
#: is stopped and listed among the failures, and the report goes on with the next part.
PART_SHARE = 0.25


@dataclass(frozen=True)
class Failure:
    """A part of the report that could not be computed for this system, and why."""

    part: str
    reason: str


def part_limit_message(part: str, seconds: float, left: float) -> str:
    """What the report says of a part stopped at the end of its share of the time."""
    return (
        f"{part} stopped after {seconds:.3g} s, its share ({PART_SHARE:.0%}) of the "
        f"{left:.3g} s the analysis had left: its expressions are too large for the time (the "
        "other parts are reported); give the analysis more time (lagrangian --timeout "
        "SECONDS, analyze(..., time_limit=SECONDS), or $LAGRANGIAN_TIME_LIMIT), or simplify "
        "the model"
    )


class PartRunner:
    """Runs the parts, keeping each failure's reason; each part within its share of the time
    left (:data:`PART_SHARE`)."""

    def __init__(self) -> None:
        self.failures: list[Failure] = []

    def run(self, part: str, compute: Callable[[], T]) -> T | None:
        """``compute()``, or None with the failure recorded under ``part``."""
        left = limits.remaining_seconds()
        message = None
        try:
            if left is None:  # no time limit: none for the part either
                return compute()
            limits.check_time()  # the command's time is spent: no part may start
            seconds = max(PART_SHARE * left, 1e-3)
            message = part_limit_message(part, seconds, left)
            with limits.time_limit(seconds, message=message):
                return compute()
        except TimeLimitError as error:
            if message is None or str(error) != message:
                raise  # the command's own limit: no later part may start
            self.failures.append(Failure(part, message))
        except LagrangianError as error:
            self.failures.append(Failure(part, str(error)))
        except Exception as error:  # a bug or a SymPy limitation: report it, keep going
            self.failures.append(Failure(part, f"internal error: {type(error).__name__}: {error}"))
        return None
