"""A time limit never interrupts compiled code: the probe that killed the Python process with a
segmentation fault (a step of x**999, whose derivative SymEngine asked SymPy for, and the
limit's exception raised inside that callback) ends with an answer or a TimeLimitError, each
run in a process of its own so that a crash is seen as one."""

from __future__ import annotations

import subprocess
import sys

import pytest

MODEL = '{"coordinates": ["x"], "kinetic": "x_dot**2/2", "potential": "Heaviside(x**999)"}'
#: Derives the probe under each limit given (seconds); prints one line per run.
PROBE = f"""
import sys
import lagrangian as lg
from lagrangian.errors import TimeLimitError

for seconds in map(float, sys.argv[1:]):
    system = lg.loads({MODEL!r}, format="json")
    try:
        print(lg.derive(system, time_limit=seconds).forcing[0], flush=True)
    except TimeLimitError:
        print("time limit", flush=True)
"""


def run_probe(*seconds: float) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-X", "faulthandler", "-c", PROBE, *map(str, seconds)],
        capture_output=True,
        text=True,
        timeout=120 + 10 * sum(seconds),
    )


@pytest.mark.slow
def test_the_probe_passes_20_runs_of_20_under_limits_of_1_to_5_s():
    for k in range(20):
        run = run_probe(1 + 4 * k / 19)
        assert run.returncode == 0, f"run {k + 1}: exit {run.returncode}\n{run.stderr[-3000:]}"
        assert run.stdout.strip() == "0"


def test_limits_that_land_anywhere_in_the_work_end_cleanly():
    # from a millisecond, inside the first conversion, to past the end of the derivation
    limits = [0.001 * 1.4**k for k in range(20)]
    run = run_probe(*limits)
    assert run.returncode == 0, f"exit {run.returncode}\n{run.stderr[-3000:]}"
    assert set(run.stdout.split("\n")[:-1]) <= {"0", "time limit"}, run.stdout
    assert run.stdout.splitlines()[-1] == "0"
