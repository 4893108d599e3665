"""How a compiled integration ended: status codes shared by the numba loops and their callers.

>>> describe(STEP_TOO_SMALL)
'Required step size is less than spacing between numbers.'
"""

from __future__ import annotations

#: The run reached the end of the time span.
FINISHED = 0
#: The stop condition turned negative; its time and state were recorded.
STOPPED = 1
#: The adaptive step fell below 10 ulp of t (SciPy's message).
STEP_TOO_SMALL = 2
#: The state stopped being finite.
NOT_FINITE = 3
#: The matrix of the state equations was singular.
SINGULAR = 4
#: The member took ``max_steps`` trial steps without reaching the end.
STEP_BUDGET = 5

_MESSAGES = {
    FINISHED: "The integration reached the end of the time span.",
    STOPPED: "Stopped by the stop condition.",
    STEP_TOO_SMALL: "Required step size is less than spacing between numbers.",
    NOT_FINITE: "The state is no longer finite (the solution blew up).",
    SINGULAR: (
        "The mass matrix is singular: the equations of motion do not determine the "
        "accelerations there (a coordinate singularity, or a body without inertia)."
    ),
    STEP_BUDGET: (
        "The step budget (max_steps) was spent before the end of the time span: raise "
        "max_steps, or use Radau, BDF or LSODA if the problem is stiff."
    ),
}


def describe(status: int) -> str:
    """The sentence for a status code."""
    return _MESSAGES[status]


def failed(status: int) -> bool:
    """Whether the status is a failure (not the end of the span nor a stop)."""
    return status not in (FINISHED, STOPPED)
