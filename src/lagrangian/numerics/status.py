"""How an integration ended: one vocabulary for every loop and every result.

:class:`Status` is the code a loop returns (the C loop's ``LG_*`` codes of ``c_loop.c`` are
its values, the vectorized batch's and the Python loop's ends are named by it), each with
its sentence; :class:`Outcome` is the word users read in ``Trajectory.status`` and
``Batch.status``: a string (``"success"``, ``"stopped"``, ``"failed"``, ``"interrupted"``)
that compares, prints and serializes as the plain word.

>>> Status.STEP_TOO_SMALL.message
'Required step size is less than spacing between numbers.'
>>> Status.STOPPED.outcome, Status.SINGULAR.outcome, Status.SINGULAR.failed
('stopped', 'failed', True)
>>> Outcome.SUCCESS == "success", f"{Outcome.FAILED}"
(True, 'failed')
"""

from __future__ import annotations

from enum import Enum, IntEnum


class Outcome(str, Enum):
    """How a run ended, in the word users read (a ``str``: ``== "success"`` holds)."""

    SUCCESS = "success"
    STOPPED = "stopped"
    FAILED = "failed"
    INTERRUPTED = "interrupted"

    # the plain word everywhere it is shown, as before there was an enumeration
    def __str__(self) -> str:
        return str(self.value)

    def __repr__(self) -> str:
        return repr(self.value)

    def __format__(self, spec: str) -> str:
        return format(str(self.value), spec)


class Status(IntEnum):
    """The code of how a loop ended (the values of ``c_loop.c``'s ``LG_*`` codes)."""

    #: The run reached the end of the time span.
    FINISHED = 0
    #: A terminal event or the stop condition ended it; its time and state were recorded.
    STOPPED = 1
    #: The adaptive step fell below 10 ulp of t (SciPy's message).
    STEP_TOO_SMALL = 2
    #: The state stopped being finite.
    NOT_FINITE = 3
    #: The matrix of the state equations was singular.
    SINGULAR = 4
    #: ``max_steps`` steps were taken before the end.
    STEP_BUDGET = 5
    #: The wall-time budget (``max_wall_time``) ran out.
    WALL_TIME = 6
    #: The problem is stiff for the explicit method: too many steps still to take.
    STIFF = 7
    #: The step size collapsed (the last steps advanced t by almost nothing).
    COLLAPSED = 8
    #: Ctrl-C ended it, the rows so far kept.
    INTERRUPTED = 9
    #: The Python loop failed; its own message says why.
    FAILED = 10

    @property
    def message(self) -> str:
        """The sentence for this end."""
        return _MESSAGES[self]

    @property
    def failed(self) -> bool:
        """Whether this end is a failure (not the end of the span, a stop or Ctrl-C)."""
        return self.outcome is Outcome.FAILED

    @property
    def outcome(self) -> Outcome:
        """The word users read for this end."""
        return _OUTCOMES.get(self, Outcome.FAILED)


_OUTCOMES = {
    Status.FINISHED: Outcome.SUCCESS,
    Status.STOPPED: Outcome.STOPPED,
    Status.INTERRUPTED: Outcome.INTERRUPTED,
}

_MESSAGES = {
    Status.FINISHED: "The integration reached the end of the time span.",
    Status.STOPPED: "Stopped by the stop condition.",
    Status.STEP_TOO_SMALL: "Required step size is less than spacing between numbers.",
    Status.NOT_FINITE: "The state is no longer finite (the solution blew up).",
    Status.SINGULAR: (
        "The mass matrix is singular: the equations of motion do not determine the "
        "accelerations there (a coordinate singularity, or a body without inertia)."
    ),
    Status.STEP_BUDGET: (
        "The step budget (max_steps) was spent before the end of the time span: raise "
        "max_steps, or use Radau, BDF or LSODA if the problem is stiff."
    ),
    Status.WALL_TIME: (
        "The wall-time budget (max_wall_time) was spent before the end of the time span."
    ),
    Status.STIFF: (
        "The problem is stiff for this explicit method: use an implicit method (Radau, BDF, LSODA)."
    ),
    Status.COLLAPSED: (
        "The step size collapsed: the equations may be singular there, or stiff; use an "
        "implicit method (Radau, BDF, LSODA)."
    ),
    Status.INTERRUPTED: "Interrupted (Ctrl-C); the rows computed before are kept.",
    Status.FAILED: "The integration failed.",
}
