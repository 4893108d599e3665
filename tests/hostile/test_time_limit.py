"""``lagrangian.limits.time_limit``: symbolic work that runs past its time ends in a
TimeLimitError that says what to do; limits nest, come from a keyword or the environment,
leave no timer behind, and reach threads through ``check_time``.  The limits here are the
behaviour under test (short budgets that must fire), not assertions on speed."""

from __future__ import annotations

import gc
import math
import signal
import threading
import time
import weakref

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ArgumentError, LagrangianError, TimeLimitError
from lagrangian.limits import (
    _SWALLOWING,
    DEFAULT_SECONDS,
    ENVIRONMENT,
    bounded,
    check_time,
    configured_seconds,
    remaining_seconds,
    swallows_exceptions,
    time_limit,
)
from lagrangian.symbolic.caches import IdentityCache


def spin(seconds: float) -> None:
    """Busy Python work for ``seconds`` (a timer interrupts it between bytecodes)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        sum(range(1000))


def no_timer_left() -> bool:
    return signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0) and signal.getsignal(
        signal.SIGALRM
    ) in (signal.SIG_DFL, signal.default_int_handler, None)


def test_work_past_its_limit_raises_a_message_that_says_what_to_do():
    expected = r"deriving stopped after its time limit of 0\.2 s"
    with pytest.raises(TimeLimitError, match=expected), time_limit(0.2, what="deriving"):
        spin(30)
    assert no_timer_left()


def test_the_message_names_the_keyword_and_the_environment_variable():
    with pytest.raises(TimeLimitError, match="time_limit=") as stopped, time_limit(0.1):
        spin(30)
    assert ENVIRONMENT in str(stopped.value)
    assert isinstance(stopped.value, (LagrangianError, TimeoutError))
    assert stopped.value.exit_code == 1


def test_work_within_its_limit_is_unaffected():
    with time_limit(30):
        spin(0.05)
        check_time()
        assert 0 < remaining_seconds() <= 30
    assert remaining_seconds() is None and no_timer_left()


def test_symbolic_work_that_would_take_minutes_stops():
    system = lg.examples.n_link_pendulum(400)  # a derivation of many seconds (200 links: 3)
    with pytest.raises(TimeLimitError, match="time limit of 2 s"), time_limit(2):
        lg.derive(system)
    assert no_timer_left()
    # the interrupted derivation left nothing half-made behind: a small one still works
    assert lg.derive(lg.examples.simple_pendulum()).equations


def test_a_remembered_derivation_is_returned_without_a_timer():
    system = lg.examples.double_pendulum()
    eom = lg.derive(system)
    # a limit far too short for any derivation: the remembered one needs none
    assert lg.derive(system, time_limit=1e-6) is eom
    assert no_timer_left()
    with pytest.raises(ArgumentError, match="time_limit"):
        lg.derive(system, time_limit=-1)


def test_an_inner_limit_fires_first_and_the_outer_one_still_holds():
    with pytest.raises(TimeLimitError, match="outer"), time_limit(1.0, what="outer"):
        with pytest.raises(TimeLimitError, match="inner"), time_limit(0.1, what="inner"):
            spin(30)
        spin(30)  # the outer timer was put back
    assert no_timer_left()


def test_an_inner_limit_never_outlives_the_outer_one():
    with (
        pytest.raises(TimeLimitError, match="outer"),
        time_limit(0.2, what="outer"),
        time_limit(60, what="inner"),
    ):
        spin(30)


def test_an_inner_block_without_seconds_keeps_the_outer_limit(monkeypatch):
    monkeypatch.setenv(ENVIRONMENT, "0.05")  # would fire at once if it applied inside
    with time_limit(30, what="outer"), time_limit(what="inner"):
        spin(0.3)
        assert remaining_seconds() > 20


def test_the_environment_sets_the_default(monkeypatch):
    monkeypatch.setenv(ENVIRONMENT, "0.1")
    with pytest.raises(TimeLimitError, match=r"0\.1 s"), time_limit():
        spin(30)
    monkeypatch.setenv(ENVIRONMENT, "none")
    assert configured_seconds() is None
    monkeypatch.delenv(ENVIRONMENT)
    assert configured_seconds() == DEFAULT_SECONDS


@pytest.mark.parametrize("text", ["soon", "-5", "0", "nan"])
def test_a_bad_environment_value_names_the_variable(monkeypatch, text):
    monkeypatch.setenv(ENVIRONMENT, text)
    with pytest.raises(ArgumentError, match=ENVIRONMENT):
        configured_seconds()


@pytest.mark.parametrize("seconds", [0, -1.0, math.nan, "10", True])
def test_a_bad_keyword_names_the_keyword(seconds):
    with pytest.raises(ArgumentError, match="time_limit"):
        configured_seconds(seconds)


def test_infinity_means_no_limit():
    with time_limit(math.inf):
        assert remaining_seconds() is None
    assert no_timer_left()


def test_a_timer_set_elsewhere_counts_as_the_outer_limit():
    # As `lagrangian --timeout` arms its own: an inner default keeps it, an inner longer
    # limit does not outlive it, and its own handler answers when its time is up.
    fired = []

    def outer_handler(*_):
        fired.append(True)
        raise KeyboardInterrupt  # stands for the command's own error

    previous = signal.signal(signal.SIGALRM, outer_handler)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.3)
        with pytest.raises(KeyboardInterrupt), time_limit(60, what="inner"):
            spin(30)
        assert fired
        signal.setitimer(signal.ITIMER_REAL, 30)
        with time_limit():  # inherits the outer timer: sets nothing of its own
            assert signal.getsignal(signal.SIGALRM) is outer_handler
        with time_limit(0.1, what="inner"), pytest.raises(TimeLimitError, match="inner"):
            spin(30)
        assert signal.getsignal(signal.SIGALRM) is outer_handler  # put back
        assert 20 < signal.getitimer(signal.ITIMER_REAL)[0] <= 30  # with its time left
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def test_other_threads_stop_at_their_next_check():
    outcome = []

    def work():
        try:
            with time_limit(0.1, what="the worker"):
                for _ in range(3000):
                    time.sleep(0.01)
                    check_time()
        except TimeLimitError as error:
            outcome.append(str(error))

    worker = threading.Thread(target=work)
    worker.start()
    worker.join(timeout=60)
    assert outcome and "the worker stopped" in outcome[0]
    assert no_timer_left()  # no signal used outside the main thread


def test_bounded_gives_a_function_the_time_limit_keyword():
    @bounded("deriving")
    def derive_slowly(seconds, *, time_limit=None):
        spin(seconds)
        return "done"

    assert derive_slowly(0.01) == "done"
    with pytest.raises(TimeLimitError, match="deriving stopped"):
        derive_slowly(30, time_limit=0.1)
    assert derive_slowly.__name__ == "derive_slowly"


def test_analyze_and_export_take_the_time_limit_keyword():
    from lagrangian.numerics.export import export

    system = lg.examples.double_pendulum()
    with pytest.raises(TimeLimitError, match=r"analyze stopped after its time limit"):
        lg.analyze(system, time_limit=1e-3)
    assert no_timer_left()
    with pytest.raises(TimeLimitError, match=r"export stopped after its time limit"):
        export(lg.examples.n_link_pendulum(4), "c", time_limit=1e-3)
    assert no_timer_left()
    files = export(system, "numpy", time_limit=120)  # a generous limit changes nothing
    assert files == export(system, "numpy")


def test_derive_takes_the_time_limit_keyword():
    system = lg.examples.n_link_pendulum(6)
    with pytest.raises(TimeLimitError, match=r"derive stopped after its time limit"):
        lg.derive(system, time_limit=1e-3)
    assert no_timer_left()
    eom = lg.derive(system, time_limit=300)  # a stopped derivation left nothing half cached
    assert eom.mass_matrix.shape == (6, 6) and eom.equations[0].has(sp.Symbol("theta1_ddot"))


def test_an_interruption_that_is_swallowed_is_repeated():
    """Python swallows an exception raised in a garbage-collector callback or a destructor:
    the timer fires again until the interruption lands in the work itself."""
    swallowed = []
    with pytest.raises(TimeLimitError, match=r"time limit of 0\.2 s"), time_limit(0.2):
        try:
            time.sleep(3)
        except TimeLimitError:
            swallowed.append(True)  # as a garbage-collector callback would
        time.sleep(3)  # the work runs on: the repeated interruption stops it
    assert swallowed == [True] and no_timer_left()


def test_a_timer_set_elsewhere_counts_as_the_time_remaining():
    previous = signal.signal(signal.SIGALRM, lambda *_: None)
    signal.setitimer(signal.ITIMER_REAL, 40)  # as lagrangian --timeout 40 sets it
    try:
        assert 30 < remaining_seconds() <= 40
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert remaining_seconds() is None and no_timer_left()


def test_a_limit_that_falls_in_a_collector_callback_lands_in_the_work_instead(monkeypatch):
    # an exception raised in gc.callbacks is printed ("Exception ignored in ...") and
    # dropped: the limit waits for the work itself instead
    dropped = []
    monkeypatch.setattr("sys.unraisablehook", dropped.append)
    calls = []

    def slow_callback(phase, info):
        if phase == "start" and not calls:
            calls.append(phase)
            spin(0.4)  # the limit's alarm comes in here

    gc.callbacks.append(slow_callback)
    try:
        with pytest.raises(TimeLimitError), time_limit(0.1):
            gc.collect()
            spin(5.0)
    finally:
        gc.callbacks.remove(slow_callback)
    assert calls and not dropped


@pytest.mark.parametrize("marked", [True, False], ids=["marked", "unmarked"])
def test_a_limit_that_falls_in_a_weak_reference_callback_lands_in_the_work_instead(
    monkeypatch, marked
):
    # a weak reference's callback drops its exceptions as a destructor does; a callback
    # marked as one (the caches' are) lets the limit land in the work after it
    dropped = []
    monkeypatch.setattr("sys.unraisablehook", dropped.append)
    monkeypatch.setattr("lagrangian.limits._SWALLOWING", set(_SWALLOWING))  # the marks undone

    def slow_callback(ref):
        spin(0.4)  # the limit's alarm comes in here

    callback = swallows_exceptions(slow_callback) if marked else slow_callback

    class Key:
        pass

    key = Key()
    reference = weakref.ref(key, callback)
    with pytest.raises(TimeLimitError), time_limit(0.1):
        del key  # the callback runs here
        spin(5.0)
    assert reference() is None
    assert bool(dropped) is not marked  # unmarked, the first alarm is dropped (and printed)


def test_the_caches_weak_reference_callbacks_are_marked():
    cache = IdentityCache()

    class Key:
        pass

    key = Key()
    cache.get(key, lambda k: 1)
    ((reference, _),) = cache._entries.values()
    assert reference.__callback__.__code__ in _SWALLOWING


def test_a_limit_that_falls_in_a_destructor_lands_in_the_work_instead(monkeypatch):
    dropped = []
    monkeypatch.setattr("sys.unraisablehook", dropped.append)

    class SlowToGo:
        def __del__(self):
            spin(0.4)  # the limit's alarm comes in here

    with pytest.raises(TimeLimitError), time_limit(0.1):
        SlowToGo()  # made and let go at once
        spin(5.0)
    assert not dropped
