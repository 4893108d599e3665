"""Members per second of a constrained ``lagrangian.simulate_batch`` (each member in the C loop,
multiplier form) against a Python loop of ``lagrangian.simulate`` calls, with and without the
C loop.

The members: ``--members`` pendulums in Cartesian coordinates (x, y) held on the circle
x^2 + y^2 = l^2 by a multiplier, released at rest from angles evenly spaced in [0.1, 2.5]
with lengths in [0.5, 2], to ``--t-end`` with DOP853 at rtol = atol = 1e-9, Baumgarte's
gains (10, 10) and 101 output rows (the multiplier and the residual of each row included).
Contenders, each warm (the equations derived and compiled before the clock starts), best of
``--repeat`` (the SciPy loop, slow and steady, runs once):

* ``batch (C loop)``: one ``simulate_batch`` call;
* ``simulate loop (C loop)``: ``simulate`` member by member, the default backend;
* ``simulate loop (SciPy)``: the same on a machine without a C compiler (the C loop
  disabled as ``benchmarks/simulate.py`` disables it: no compiler found), SciPy's DOP853 on
  the NumPy multiplier form.

The batch and the SciPy loop are also compared row by row (largest difference of q and of
the multipliers).

Usage
    python benchmarks/batch_constrained.py                 # 200 members, t_end = 10
    python benchmarks/batch_constrained.py --members 50 --t-end 2 --repeat 1
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import sympy as sp

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "src"))  # the checkout, installed or not
sys.path.insert(0, str(HERE.parent))
import lagrangian as lg  # noqa: E402
from lagrangian.numerics.fast import c_build, c_loop  # noqa: E402
from machine import cpu_model  # noqa: E402

TOLERANCES: dict[str, Any] = {"method": "DOP853", "rtol": 1e-9, "atol": 1e-9}
GAINS = (10.0, 10.0)


def cartesian_pendulum() -> lg.EquationsOfMotion:
    x, y, m, g, l = sp.symbols("x y m g l")
    system = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        gravity=(0, -g),
        particles=[lg.Particle("bob", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
    )
    return lg.derive(system)


def starts(k: int) -> tuple[dict[str, np.ndarray], np.ndarray]:
    theta, length = np.linspace(0.1, 2.5, k), np.linspace(0.5, 2.0, k)
    initial = {
        "x": length * np.sin(theta),
        "y": -length * np.cos(theta),
        "x_dot": np.zeros(k),
        "y_dot": np.zeros(k),
    }
    return initial, length


def run_batch(eom: lg.EquationsOfMotion, k: int, t_end: float) -> lg.Batch:
    initial, length = starts(k)
    return lg.simulate_batch(
        eom,
        initial,
        t_end,
        parameters={"l": length},
        baumgarte=GAINS,
        samples=101,
        **TOLERANCES,
    )


def run_loop(eom: lg.EquationsOfMotion, k: int, t_end: float) -> list[lg.Trajectory]:
    initial, length = starts(k)
    return [
        lg.simulate(
            eom,
            {name: float(values[i]) for name, values in initial.items()},
            t_end,
            parameters={"l": float(length[i])},
            baumgarte=GAINS,
            samples=101,
            **TOLERANCES,
        )
        for i in range(k)
    ]


def best(repeat: int, run: Callable[[], Any]) -> tuple[float, Any]:
    seconds, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = run()
        seconds.append(time.perf_counter() - start)
    return min(seconds), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", type=int, default=200)
    parser.add_argument("--t-end", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    k, t_end = args.members, args.t_end
    if not c_loop.available():
        sys.exit("the C loop is not available here (no C compiler): nothing to compare")
    eom = cartesian_pendulum()
    run_batch(eom, 2, 0.1)  # warm: derivation, LLVM compilation, multiplier form
    run_loop(eom, 2, 0.1)
    seconds: dict[str, float] = {}
    seconds["batch (C loop)"], batch = best(args.repeat, lambda: run_batch(eom, k, t_end))
    seconds["simulate loop (C loop)"], _ = best(args.repeat, lambda: run_loop(eom, k, t_end))
    c_build.find_compiler = lambda: None  # a machine without a C compiler
    c_build.loop_library.cache_clear()
    assert not c_loop.available()
    run_loop(eom, 2, 0.1)
    seconds["simulate loop (SciPy)"], loop = best(1, lambda: run_loop(eom, k, t_end))
    assert batch.multipliers is not None and all(member.success for member in loop)
    q = np.max(np.abs(batch.q - np.stack([member.q for member in loop])))
    lam = np.max(np.abs(batch.multipliers - np.stack([member.multipliers for member in loop])))
    scipy_rate = k / seconds["simulate loop (SciPy)"]
    print(f"{k} Cartesian pendulums to t = {t_end:g}, DOP853 rtol = atol = 1e-9, 101 rows")
    print(f"{cpu_model()}, Python {platform.python_version()}, lagrangian {lg.__version__}")
    print()
    print("| contender | seconds | members/s | vs SciPy loop |")
    print("|---|---:|---:|---:|")
    for name, value in seconds.items():
        rate = k / value
        print(f"| {name} | {value:.3f} | {rate:,.0f} | {rate / scipy_rate:.1f}x |")
    print()
    print(f"batch vs SciPy loop: max |dq| = {q:.2e}, max |d lambda| = {lam:.2e}")


if __name__ == "__main__":
    main()
