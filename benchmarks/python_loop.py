"""Benchmark: the Python loop of two checkouts side by side (single runs and a batch, no C loop).

What is measured
    Every row runs with no C compiler found (the path of a machine without one), in a fresh
    process per checkout and round, alternating the two checkouts round by round so that a
    load that comes and goes on a shared machine falls on both alike.  Times are CPU seconds
    of the process (``time.process_time``, best of the calls in the process): on a machine
    shared by several workers the wall time measures the neighbours as much as the code.

    pendulum    the case of ``simulate.py``'s row "SciPy solvers": the 10-link pendulum
                over 10 s, DOP853, rtol = atol = 1e-9, every step kept, best of 5
                ``lagrangian.simulate`` calls;
    batch       the case of ``simulate.py``'s batch row "vectorized": ``--batch`` double
                pendulums over 10 s, DOP853, rtol = atol = 1e-9, the two ends kept, best of 2
                ``lagrangian.simulate_batch`` calls;
    events      the double pendulum over 30 s, DOP853, rtol = atol = 1e-9, two events
                (theta = 0, phi_dot rising through 0), best of 3;
    rk4         the double pendulum over 10 s by RK4, dt = 1e-3, best of 3;
    rk45 rows   the double pendulum over 30 s, RK45, rtol = atol = 1e-9, 3000 output times,
                best of 3;
    bare loop   x' = A x (2 states), RK45, rtol = atol = 1e-10 over 200, every step, through
                the loop's entry ``integrators.loop.integrate`` alone, best of 9: the loop's
                own cost with a right-hand side that costs nothing, beside SciPy alone
                (the same solver stepped by a bare ``while``), best of 9.

    Reported per row: the median and range of each checkout's rounds, and after / before.

Usage
    python benchmarks/python_loop.py --before ../old-checkout           # 3 rounds, 1000 pendulums
    python benchmarks/python_loop.py --before ../old-checkout --repeat 5 --batch 2000
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROWS = ("pendulum", "batch", "events", "rk4", "rk45 rows", "bare loop", "SciPy alone")


def features(src: str, batch: int) -> dict:
    """Every row in this process (CPU seconds), from the checkout's ``src``."""
    sys.path.insert(0, src)
    import numpy as np
    from scipy.integrate import RK45

    import lagrangian as lg
    from lagrangian.numerics.fast import c_build
    from lagrangian.simulation.integrators.budget import Budget
    from lagrangian.simulation.integrators.loop import integrate

    c_build.find_compiler = lambda: None
    links = lg.derive(lg.examples.n_link_pendulum(10))
    names = [f"theta{i}" for i in range(1, 11)]
    leaning = {**{name: 0.5 for name in names}, **{name + "_dot": 0.0 for name in names}}
    double = lg.derive(lg.examples.double_pendulum())
    angles = np.random.default_rng(0).uniform(-1.0, 1.0, size=(batch, 2))
    members = {"theta": angles[:, 0], "phi": angles[:, 1], "theta_dot": 0.0, "phi_dot": 0.0}
    start = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}

    def crossing(t, q, q_dot):
        return q[0]

    def rising(t, q, q_dot):
        return q_dot[1]

    rising.direction = 1  # type: ignore[attr-defined]
    tight = {"rtol": 1e-9, "atol": 1e-9}
    cases = {
        "pendulum": lambda: lg.simulate(links, leaning, 10.0, method="DOP853", **tight),
        "batch": lambda: lg.simulate_batch(
            double, members, 10.0, method="DOP853", samples=2, **tight
        ),
        "events": lambda: lg.simulate(
            double, start, 30.0, method="DOP853", events=[crossing, rising], **tight
        ),
        "rk4": lambda: lg.simulate(double, start, 10.0, method="RK4", dt=1e-3),
        "rk45 rows": lambda: lg.simulate(double, start, 30.0, method="RK45", samples=3000, **tight),
    }
    A = np.array([[0.0, 1.0], [-1.0, 0.0]])

    def solver() -> RK45:
        return RK45(lambda t, x: A @ x, 0.0, np.array([1.0, 0.0]), 200.0, rtol=1e-10, atol=1e-10)

    def alone() -> None:
        stepping = solver()
        while stepping.status == "running":
            stepping.step()

    cases["bare loop"] = lambda: integrate(
        solver, 0.0, np.array([1.0, 0.0]), None, None, None, None, Budget("RK45")
    )
    cases["SciPy alone"] = alone
    result = {}
    calls = {"bare loop": 9, "SciPy alone": 9, "pendulum": 5, "batch": 2}
    lg.simulate(links, leaning, 0.1, method="DOP853", **tight)  # compiled before the clock
    lg.simulate_batch(double, {**members, "theta": 0.1, "phi": 0.1}, 0.1, samples=2)
    for name, case in cases.items():
        runs = []
        for _ in range(calls.get(name, 3)):
            clock = time.process_time()
            case()
            runs.append(time.process_time() - clock)
        result[name] = min(runs)
    return result


def run(command: list[str]) -> dict:
    env = dict(os.environ, PYTHONPATH="")
    done = subprocess.run(command, capture_output=True, text=True, env=env, timeout=3600)
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            return json.loads(line)
    raise RuntimeError(done.stderr[-2000:])


def measure(checkout: Path, batch: int) -> dict:
    """Every row once from ``checkout`` (its own src)."""
    script = str(HERE / "python_loop.py")
    return run([sys.executable, script, "--worker", str(checkout / "src"), "--batch", str(batch)])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", type=Path, help="the other checkout (its src, benchmarks)")
    parser.add_argument("--repeat", type=int, default=3, help="rounds (3)")
    parser.add_argument("--batch", type=int, default=1000, help="double pendulums (1000)")
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(features(args.worker, args.batch)), flush=True)
        return 0
    checkouts = {"before": args.before.resolve(), "after": HERE.parent}
    print(f"python benchmarks/python_loop.py --repeat {args.repeat} --batch {args.batch}")
    results: dict[str, list[dict]] = {"before": [], "after": []}
    for r in range(args.repeat):
        for label, checkout in checkouts.items():
            results[label].append(measure(checkout, args.batch))
            print(f"round {r + 1} {label}: {results[label][-1]}", file=sys.stderr, flush=True)
    print("| row | before s (median, range) | after s (median, range) | after / before |")
    print("|---|---:|---:|---:|")
    for row in ROWS:
        cells, medians = [], []
        for label in ("before", "after"):
            values = [runs[row] for runs in results[label]]
            medians.append(statistics.median(values))
            cells.append(f"{medians[-1]:.3g} ({min(values):.3g}-{max(values):.3g})")
        print(f"| {row} | {cells[0]} | {cells[1]} | {medians[1] / medians[0]:.3f} |")
    print(f"\n1-minute load average at the end: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
