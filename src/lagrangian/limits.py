"""Time limits for symbolic work: derive, analyze and export end in bounded time.

Some expressions keep SymPy busy for minutes (a power of a long sum, a chain of hundreds of
links).  A limit turns that into a :class:`~lagrangian.errors.TimeLimitError` that says what
to do, instead of a process that never answers.

- ``with time_limit(seconds):`` bounds a block.  In the main thread of a system with interval
  timers (Linux, macOS) a real-time timer (``signal.setitimer``) interrupts the work where it
  is; elsewhere (another thread, Windows) the work is stopped at its next
  :func:`check_time`, which long loops call.  The timer's exception is raised between two
  Python instructions, never inside compiled code, as long as no compiled library calls back
  into Python code that an exception could not leave: SymEngine would for the SymPy functions
  it has no class of its own for, so it never gets one (:mod:`lagrangian.symbolic.native`).
- Limits nest: an inner limit never outlives the outer one, and an inner block given no
  number of seconds keeps the outer limit as it is.  A timer another part of the program has
  set (``lagrangian --timeout``) counts as an outer limit.
- Without a number, the limit is ``$LAGRANGIAN_TIME_LIMIT`` (seconds; ``none`` for no limit),
  else :data:`DEFAULT_SECONDS`, generous for real systems.
- :func:`bounded` makes a public function take the ``time_limit`` keyword.

>>> with time_limit(5):
...     check_time()  # well within the time
>>> import time
>>> with time_limit(0.05, what="sleeping"):
...     time.sleep(1)  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
lagrangian.errors.TimeLimitError: sleeping stopped after its time limit of 0.05 s: ...
"""

from __future__ import annotations

import contextlib
import functools
import gc
import math
import os
import signal
import threading
import time
import weakref
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from types import CodeType
from typing import Any, Generic, TypeVar

from lagrangian.errors import ArgumentError, TimeLimitError

#: The environment variable that sets the time limit where no number is given.
ENVIRONMENT = "LAGRANGIAN_TIME_LIMIT"
#: The time limit, in seconds, when neither a keyword nor the environment gives one: ten
#: minutes, several times what a 50-link pendulum takes to derive.
DEFAULT_SECONDS = 600.0
#: What the message of a limit reached in the Python API advises.
FIX = (
    f"pass a larger time_limit= (seconds), or set the environment variable {ENVIRONMENT}; "
    "or simplify the model (fewer bodies, shorter expressions)"
)
#: The words that mean "no limit" in an environment variable of a limit (any case).
NO_LIMIT = ("none", "off", "inf", "infinity")
#: After its exception the timer fires again this often until the limit is left: code that
#: catches every exception (a C extension's conversion) may swallow it.  An alarm that comes
#: in a garbage-collector callback or a destructor, where Python would print the exception
#: and drop it, raises nothing and waits for the next (:func:`_swallowed_there`).
RETRY_SECONDS = 0.05

F = TypeVar("F", bound=Callable[..., Any])
L = TypeVar("L")


@dataclass(frozen=True)
class _Limit:
    deadline: float  # time.monotonic() at which the work stops
    message: str


class LimitStack(threading.local, Generic[L]):
    """The limits of one kind active in this thread, outermost first (``stack``): each
    thread has its own, so a limit set in one thread never stops another's work."""

    def __init__(self) -> None:
        self.stack: list[L] = []


_active: LimitStack[_Limit] = LimitStack()


def configured_limit(
    value: float | None,
    *,
    environment: str,
    default: float,
    unit: str,
    whole: bool = False,
    where: str,
) -> float:
    """A limit in ``unit`` (seconds, operations): ``value`` when given, else the environment
    variable ``environment``, else ``default``; ``math.inf`` means no limit (``math.inf``
    given, or a word of :data:`NO_LIMIT` in the environment).  ``whole``: the environment
    gives a whole number and the limit is at least 1 (else any positive number); ``where``
    names the keyword or option in the message of a bad value.

    >>> configured_limit(None, environment="UNSET_LIMIT", default=10.0, unit="seconds",
    ...                  where="time_limit")
    10.0
    >>> configured_limit(0, environment="UNSET_LIMIT", default=10.0, unit="seconds",
    ...                  where="time_limit")
    Traceback (most recent call last):
    ...
    lagrangian.errors.ArgumentError: time_limit=0: give a positive number of seconds
    """
    amount = "positive whole number" if whole else "positive number"
    if value is None:
        text = os.environ.get(environment, "").strip()
        if not text:
            return default
        if text.lower() in NO_LIMIT:
            return math.inf
        where = environment
        try:
            value = int(text) if whole else float(text)
        except ValueError:
            number = "whole number" if whole else "number"
            raise ArgumentError(
                f"{environment}={text[:40]!r} is not a {number} of {unit}: give a {amount}, "
                "or none for no limit"
            ) from None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ArgumentError(
            f"{where} takes a number of {unit}, not {type(value).__name__}: give a {amount}, "
            "or math.inf for no limit"
        )
    too_small = value < 1 if whole else value <= 0
    if math.isnan(value) or too_small:
        raise ArgumentError(f"{where}={value!r}: give a positive number of {unit}")
    return value


def configured_seconds(seconds: float | None = None) -> float | None:
    """The time limit in seconds: ``seconds`` when given, else ``$LAGRANGIAN_TIME_LIMIT``,
    else :data:`DEFAULT_SECONDS`; None means no limit (``math.inf``, or ``none`` in the
    environment).

    >>> configured_seconds(30.0), configured_seconds(math.inf)
    (30.0, None)
    """
    limit = configured_limit(
        seconds,
        environment=ENVIRONMENT,
        default=DEFAULT_SECONDS,
        unit="seconds",
        where="time_limit",
    )
    return None if math.isinf(limit) else float(limit)


def limit_message(seconds: float, what: str = "the work", fix: str = FIX) -> str:
    """What a TimeLimitError says when ``what`` ran past ``seconds``."""
    return f"{what} stopped after its time limit of {seconds:g} s: {fix}"


def check_time() -> None:
    """Raise TimeLimitError when the innermost active limit of this thread has passed; a
    cheap check for long loops, where no timer can interrupt (threads other than the main
    one, Windows)."""
    stack = _active.stack
    if stack and time.monotonic() >= min(limit.deadline for limit in stack):
        raise TimeLimitError(_expired(stack).message)


def remaining_seconds() -> float | None:
    """Seconds left before the innermost active limit of this thread (a real-time timer set
    elsewhere, ``lagrangian --timeout``, counts as one), or None without one."""
    stack = _active.stack
    if not stack:
        return _foreign_timer() or None
    return max(0.0, min(limit.deadline for limit in stack) - time.monotonic())


@contextlib.contextmanager
def time_limit(
    seconds: float | None = None,
    *,
    what: str = "the work",
    fix: str = FIX,
    message: str | None = None,
) -> Iterator[None]:
    """Raise TimeLimitError in the block when ``seconds`` of wall time have passed.

    ``seconds`` None: the configured limit (:func:`configured_seconds`), or inside another
    limit that limit unchanged.  ``what`` and ``fix`` make the message
    (:func:`limit_message`); ``message`` replaces it whole.
    """
    outer_timer = _foreign_timer()
    if seconds is None and (_active.stack or outer_timer):
        yield  # inside a limit: keep it
        return
    limit_seconds = configured_seconds(seconds)
    if limit_seconds is None:
        yield
        return
    limit = _Limit(
        time.monotonic() + limit_seconds, message or limit_message(limit_seconds, what, fix)
    )
    with _timer(limit, outer_timer):
        try:
            yield
        except TimeLimitError:
            raise
        except BaseException as error:
            # The interruption can land in code that catches every exception (SymPy's and
            # SymEngine's conversions do) and turns it into another error: past the deadline,
            # that error is the time limit's.
            if time.monotonic() >= limit.deadline:
                raise TimeLimitError(limit.message) from error
            raise


def bounded(what: str) -> Callable[[F], F]:
    """Decorate a public function whose signature has ``time_limit: float | None = None``:
    its work runs within that limit (:func:`time_limit`), with ``what`` named in the message.

    >>> @bounded("counting")
    ... def count(n, *, time_limit=None):
    ...     return sum(range(n))
    >>> count(10, time_limit=5)
    45
    """

    def decorate(function: F) -> F:
        @functools.wraps(function)
        def within_limit(*args: Any, **kwargs: Any) -> Any:
            with time_limit(kwargs.get("time_limit"), what=what):
                return function(*args, **kwargs)

        return within_limit  # type: ignore[return-value]

    return decorate


def _expired(stack: list[_Limit]) -> _Limit:
    return min(stack, key=lambda limit: limit.deadline)


def _can_interrupt() -> bool:
    return hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()


def _foreign_timer() -> float:
    """Seconds left on a real-time timer that this module did not set (0 when none)."""
    if not _can_interrupt() or _active.stack:
        return 0.0
    return signal.getitimer(signal.ITIMER_REAL)[0]


@contextlib.contextmanager
def _timer(limit: _Limit, outer_timer: float) -> Iterator[None]:
    """Push ``limit``; in the main thread arm SIGALRM for the earliest deadline (an outer
    timer set elsewhere included), and on the way out put back what was there before."""
    stack = _active.stack
    if not _can_interrupt():
        stack.append(limit)
        try:
            yield
        finally:
            stack.remove(limit)
        return
    started = time.monotonic()
    outermost = not stack
    previous_handler = signal.getsignal(signal.SIGALRM) if outermost else None

    def expire(signum: int, frame: Any) -> None:
        if outer_timer and time.monotonic() >= started + outer_timer - 1e-3:
            handler = previous_handler  # the outer timer's own time is up: its handler
            if callable(handler):
                handler(signum, frame)
                return
        signal.setitimer(signal.ITIMER_REAL, RETRY_SECONDS)  # in case this one is swallowed
        if _swallowed_there(frame):
            return  # Python would print the error and drop it: the next alarm lands elsewhere
        raise TimeLimitError(_expired(_active.stack).message)

    if outermost:
        signal.signal(signal.SIGALRM, expire)
    stack.append(limit)
    _arm(min(limit.deadline, *(o.deadline for o in stack), started + (outer_timer or math.inf)))
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)  # first: no repeated expiry past this point
        stack.remove(limit)
        if outermost:
            signal.signal(signal.SIGALRM, previous_handler)
            if outer_timer:  # the other timer keeps the time it had left
                _arm(started + outer_timer)
        else:
            _arm(min(o.deadline for o in stack))


#: The code of functions that Python runs where an exception is printed and dropped: the
#: callbacks of the weak collections and finalizers of the standard library, and those
#: marked by :func:`swallows_exceptions`.
_SWALLOWING: set[CodeType] = {
    weakref.WeakSet()._remove.__code__,  # type: ignore[attr-defined]
    weakref.WeakKeyDictionary()._remove.__code__,  # type: ignore[attr-defined]
    weakref.WeakValueDictionary()._remove.__code__,  # type: ignore[attr-defined]
    weakref.finalize.__call__.__code__,
}


def swallows_exceptions(function: F) -> F:
    """Mark ``function`` as one Python runs where it drops exceptions (a weak reference's
    callback): a time limit that expires in it lands in the work after it instead."""
    _SWALLOWING.add(function.__code__)
    return function


def _swallowed_there(frame: Any) -> bool:
    """Whether an exception raised at ``frame`` would be swallowed: it runs a garbage
    collector's callback (``gc.callbacks``, as Hypothesis and Dask register), a destructor
    or a weak reference's callback (:data:`_SWALLOWING`), where Python prints "Exception
    ignored in ..." to the user and carries on."""
    callbacks = {getattr(callback, "__code__", None) for callback in gc.callbacks}
    while frame is not None:
        code = frame.f_code
        if code in callbacks or code in _SWALLOWING or code.co_name == "__del__":
            return True
        frame = frame.f_back
    return False


def _arm(deadline: float) -> None:
    """Make SIGALRM come at ``deadline`` (time.monotonic()), at once if it has passed."""
    signal.setitimer(signal.ITIMER_REAL, max(deadline - time.monotonic(), 1e-6))
