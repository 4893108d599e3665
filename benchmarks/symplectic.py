"""Benchmark: the compiled variational integrators (midpoint rule, gauss4, gauss6): their speed
against the NumPy march of before, and their accuracy against DOP853 at equal work and at
equal wall time over 1000 periods of a pendulum.

What is measured
    speed   The double pendulum of ``lg.examples.double_pendulum`` (unit masses and rods,
            g = 9.81, released at rest at theta = 1, phi = 0.5), dt = 0.01, every step an
            output:
              - ``lg.simulate(eom, ..., method="variational", dt=0.01)`` for ``--steps`` steps
                (default 10^5) on the compiled path, against the NumPy march that was the
                only path before (``lagrangian.simulation.variational.midpoint.COMPILED = False``,
                timed on a tenth of the steps: its rate does not depend on the length); both
                compiled and warm, best of 3.  Steps per second and their ratio.
              - the marches alone (``lagrangian.simulation.variational.midpoint.discrete_march``,
              what
                simulate calls) of variational, gauss4 and gauss6, compiled and in NumPy.
              - end to end in a fresh process, numba's cache holding the loops: import
                lagrangian, derive, the first simulate of 10^4 steps (compiling the terms by
                LLVM, starting numba, loading the cached loop), then a second one.
    work    A simple pendulum (m = l = 1, g = 9.81) released at rest at theta0 = 1 rad, for
            1000 1/4 periods (T = 4 K(k^2) / w0, ending as the bob passes the bottom; the
            ``Pendulum`` of ``benchmarks/variational.py``).  Each variational integrator at
            dt = T/n (march alone, compiled, every step kept) against DOP853 in the C loop
            (SciPy's steps, every accepted step kept) at
              - equal work: the tolerance (rtol = atol) searched until DOP853's evaluations of
                the right-hand side (SciPy's nfev, rejected steps included) are within 3 % of
                the integrator's evaluations of its discrete equations (every stage's terms
                with their Jacobians, once per Newton iteration, and the Legendre map at every
                step): secant steps on the compiled loop's count of 12 per accepted step + 2,
                rescaled by SciPy's nfev at the tolerance found until the two agree;
              - equal wall time: the same search on the loop's time (best of 3).
            Reported: max |E - E0| / |E0| over every step; its growth, the largest error over
            the last tenth of the run over that of the first tenth (1: bounded, a drift grows
            with t); and the phase error at the end (the angle of the final (theta,
            theta_dot) on the exact solution minus 2 pi t / T).  Every DOP853 row gives
            SciPy's nfev.

Usage
    python benchmarks/symplectic.py                     # both parts
    python benchmarks/symplectic.py --part speed --steps 20000
    python benchmarks/symplectic.py --record            # append the results to RESULTS.md
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "src"))  # benchmark the checkout, installed or not
sys.path.insert(0, str(HERE.parent))

import lagrangian as lg  # noqa: E402
from lagrangian.numerics.compile import compile_equations  # noqa: E402
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics  # noqa: E402
from lagrangian.numerics.fast.c_loop import integrate  # noqa: E402
from lagrangian.numerics.fast.c_loop import native_equations as fast_equations  # noqa: E402
from lagrangian.numerics.fast.settings import Settings  # noqa: E402
from lagrangian.simulation.variational import midpoint as variational  # noqa: E402
from lagrangian.simulation.variational.collocation import tableau_for  # noqa: E402
from machine import cpu_model, package_version  # noqa: E402
from variational import Pendulum, make_pendulum  # noqa: E402

RESULTS = HERE.parent / "RESULTS.md"
DT = 0.01
METHODS = ("variational", "gauss4", "gauss6")
PER_PERIOD = {"variational": (40, 80), "gauss4": (10, 20), "gauss6": (5, 10)}


def best_of(repeats: int, run: Callable[[], Any]) -> tuple[float, Any]:
    """The shortest wall time of ``repeats`` calls of ``run``, and the last result."""
    best, result = math.inf, None
    for _ in range(repeats):
        begin = time.perf_counter()
        result = run()
        best = min(best, time.perf_counter() - begin)
    return best, result


# --------------------------------------------------------------------------- speed


def simulate_rate(steps: int, compiled: bool) -> float:
    """Steps per second of lg.simulate(method="variational") on the double pendulum."""
    pendulum = lg.examples.double_pendulum()
    eom, start = lg.derive(pendulum), dict(pendulum.initial)
    variational.COMPILED = compiled
    try:
        lg.simulate(eom, start, 10 * DT, method="variational", dt=DT)  # compile and warm up
        seconds, run = best_of(
            3, lambda: lg.simulate(eom, start, steps * DT, method="variational", dt=DT)
        )
    finally:
        variational.COMPILED = True
    assert run.success and len(run.t) == steps + 1
    return steps / seconds


def march_rate(method: str, steps: int, compiled: bool) -> float:
    """Steps per second of the march of ``method`` alone on the double pendulum."""
    eom = lg.derive(lg.examples.double_pendulum())
    mechanics = compile_discrete_mechanics(eom)
    p = np.array([float(eom.system.parameters[s]) for s in eom.parameters])
    x0, grid = np.array([1.0, 0.5, 0.0, 0.0]), np.linspace(0.0, steps * DT, steps + 1)
    tableau = None if method == "variational" else tableau_for(method, False)
    variational.COMPILED = compiled
    try:
        march = variational.discrete_march
        march(mechanics, tableau, x0, p, grid[:11], np.arange(11), None)
        seconds, run = best_of(
            3, lambda: march(mechanics, tableau, x0, p, grid, np.arange(len(grid)), None)
        )
    finally:
        variational.COMPILED = True
    assert run.failure is None
    return steps / seconds


END_TO_END = """
import time
begin = time.perf_counter()
import lagrangian as lg
imported = time.perf_counter()
pendulum = lg.examples.double_pendulum()
eom = lg.derive(pendulum)
derived = time.perf_counter()
lg.simulate(eom, dict(pendulum.initial), 100.0, method="variational", dt=0.01)
first = time.perf_counter()
lg.simulate(eom, dict(pendulum.initial), 100.0, method="variational", dt=0.01)
second = time.perf_counter()
print(imported - begin, derived - imported, first - derived, second - first)
"""


def end_to_end() -> tuple[float, list[float]]:
    """(wall time of a fresh process, its parts: import, derive, first and second simulate)."""
    begin = time.perf_counter()
    output = subprocess.run(
        [sys.executable, "-c", END_TO_END],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "PYTHONPATH": str(HERE.parents[1] / "src")},
    ).stdout
    return time.perf_counter() - begin, [float(v) for v in output.split()]


def speed_report(steps: int) -> str:
    compiled, numpy = simulate_rate(steps, True), simulate_rate(max(steps // 10, 1000), False)
    lines = [
        f"Double pendulum (theta = 1, phi = 0.5 at rest), dt = {DT:g}, every step an output.",
        "",
        "| path | steps | steps/s | us per step |",
        "|---|---:|---:|---:|",
        f"| lg.simulate, compiled | {steps:,} | {compiled:,.0f} | {1e6 / compiled:.2f} |",
        f"| lg.simulate, NumPy march (before) | {max(steps // 10, 1000):,} | {numpy:,.0f} | "
        f"{1e6 / numpy:.1f} |",
    ]
    rates = {}
    for method in METHODS:
        for compiled_march in (True, False):
            count = steps if compiled_march else 2000
            rate = march_rate(method, count, compiled_march)
            rates[method, compiled_march] = rate
            label = "compiled" if compiled_march else "NumPy"
            lines.append(
                f"| march alone, {method}, {label} | {count:,} | {rate:,.0f} | {1e6 / rate:.2f} |"
            )
    wall, (imports, derive, first, second) = end_to_end()
    lines += [
        "",
        f"lg.simulate: compiled {compiled / numpy:.0f}x the NumPy march. Marches alone, "
        + ", ".join(f"{m} {rates[m, True] / rates[m, False]:.0f}x" for m in METHODS)
        + ".",
        "",
        f"End to end, fresh process, loops in numba's cache: {wall:.2f} s (import {imports:.2f} s,"
        f" derive {derive:.2f} s, first simulate of 10,000 steps {first:.2f} s, second "
        f"{second:.3f} s).",
        "",
        "```",
        f"{'PASS' if compiled >= 200_000 else 'FAIL'}  variational through lg.simulate "
        f">= 200,000 steps/s ({compiled:,.0f})",
        "```",
    ]
    return "\n".join(lines)


# --------------------------------------------------------------------------- work


@dataclass
class Row:
    method: str
    setting: str
    evaluations: int
    seconds: float
    energy_error: float
    growth: float
    phase_error: float


def energy_errors(
    pendulum: Pendulum, t: np.ndarray, q: np.ndarray, q_dot: np.ndarray
) -> tuple[float, float]:
    """max |E/E0 - 1| over the run, and over its last tenth divided by over its first."""
    energy = compile_equations(pendulum.eom).energy(q, q_dot, t, pendulum.p)
    error = np.abs(energy / energy[0] - 1)
    first, last = error[1:][t[1:] <= t[-1] / 10], error[t >= 0.9 * t[-1]]
    return float(error.max()), float(last.max() / first.max())


def discrete_row(pendulum: Pendulum, method: str, per_period: int) -> Row:
    """The march of ``method`` at dt = T/per_period, compiled, every step kept."""
    mechanics = compile_discrete_mechanics(pendulum.eom)
    steps = round((pendulum.periods + 0.25) * per_period)
    grid = np.linspace(0.0, pendulum.t_end, steps + 1)
    tableau = None if method == "variational" else tableau_for(method, False)
    march, x0, p = variational.discrete_march, pendulum.x0, pendulum.p
    march(mechanics, tableau, x0, p, grid[:11], np.arange(11), None)  # compile and warm up
    seconds, run = best_of(
        3, lambda: march(mechanics, tableau, x0, p, grid, np.arange(len(grid)), None)
    )
    return Row(
        method,
        f"dt = T/{per_period}",
        run.evaluations,
        seconds,
        *energy_errors(pendulum, grid, run.q, run.q_dot),
        pendulum.phase_error(grid, run.q[:, 0], run.q_dot[:, 0]),
    )


def dop853_row(pendulum: Pendulum, rtol: float, label: str) -> Row:
    """DOP853 on the compiled loop at rtol = atol, every accepted step kept (best of 3)."""
    fast = fast_equations(pendulum.eom)
    settings = Settings("DOP853", (0.0, pendulum.t_end), np.zeros(0), rtol=rtol, atol=rtol)
    seconds, run = best_of(3, lambda: integrate(fast, settings, pendulum.x0, pendulum.p))
    return Row(
        f"DOP853, {label}",
        f"rtol = {rtol:.2e}",
        12 * (len(run.t) - 1) + 2,  # accepted steps only: see with_scipy_nfev
        seconds,
        *energy_errors(pendulum, run.t, run.x[:, :1], run.x[:, 1:]),
        pendulum.phase_error(run.t, run.x[:, 0], run.x[:, 1]),
    )


def matched(pendulum: Pendulum, target: float, measure: str, label: str) -> Row:
    """The DOP853 row whose ``measure`` ("evaluations" or "seconds") is nearest ``target``
    (secant steps on log measure against log rtol)."""
    slope = -1 / 8  # evaluations ~ rtol^(-1/8) for small rtol
    log_rtol, tried = math.log(1e-8), []
    for _ in range(10):
        row = dop853_row(pendulum, math.exp(log_rtol), label)
        tried.append((log_rtol, row))
        value = getattr(row, measure)
        if abs(value / target - 1) < 0.02:
            break
        if len(tried) > 1:
            (a, row_a), (b, row_b) = tried[-2], tried[-1]
            va, vb = getattr(row_a, measure), getattr(row_b, measure)
            if a != b and va != vb:
                slope = min((math.log(vb) - math.log(va)) / (b - a), -0.02)
        step = (math.log(target) - math.log(value)) / slope
        log_rtol = min(max(log_rtol + step, math.log(1e-14)), math.log(1e-3))
    return min(tried, key=lambda pair: abs(math.log(getattr(pair[1], measure) / target)))[1]


def with_scipy_nfev(pendulum: Pendulum, row: Row) -> Row:
    """``row`` with SciPy's own count of right-hand-side evaluations at its tolerance
    (rejected steps included: the compiled loop takes the same steps)."""
    rtol = float(row.setting.split("=")[1])
    compiled = compile_equations(pendulum.eom)
    solution = solve_ivp(
        lambda t, x: compiled.rhs(t, x, pendulum.p), (0.0, pendulum.t_end), pendulum.x0,
        "DOP853", rtol=rtol, atol=rtol,
    )  # fmt: skip
    row.evaluations = int(solution.nfev)
    return row


def equal_work(pendulum: Pendulum, target: int) -> Row:
    """The DOP853 row whose SciPy nfev is within 3 % of ``target``: searched on the
    compiled loop's count of accepted steps, the goal rescaled by the ratio of the two
    counts at the tolerance found."""
    goal, rows = float(target), []
    for _ in range(4):
        estimate = matched(pendulum, goal, "evaluations", "equal work")
        accepted_only = estimate.evaluations
        row = with_scipy_nfev(pendulum, estimate)
        rows.append(row)
        if abs(row.evaluations / target - 1) < 0.03:
            break
        goal = target * accepted_only / row.evaluations
    return min(rows, key=lambda row: abs(math.log(row.evaluations / target)))


def run_work(periods: int) -> list[Row]:
    pendulum = make_pendulum(periods)
    dop853_row(pendulum, 1e-6, "warm-up")
    rows = []
    for method in METHODS:
        for per_period in PER_PERIOD[method]:
            ours = discrete_row(pendulum, method, per_period)
            work = equal_work(pendulum, ours.evaluations)
            wall = matched(pendulum, ours.seconds, "seconds", "equal wall time")
            rows += [ours, work, with_scipy_nfev(pendulum, wall)]
            print(f"  {method} T/{per_period}: done", file=sys.stderr)
    return rows


def work_report(rows: list[Row], periods: int) -> str:
    pendulum = make_pendulum(periods)
    lines = [
        f"Simple pendulum (theta0 = 1 rad, g = 9.81, l = 1), {periods} 1/4 periods "
        f"(T = {pendulum.period:.6f} s, t = {pendulum.t_end:.1f} s); every step kept.",
        "",
        "| method | setting | evaluations | wall s | max abs(E - E0)/E0 | growth | "
        "phase error rad |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        lines.append(
            f"| {row.method} | {row.setting} | {row.evaluations:,} | {row.seconds:.4f} | "
            f"{row.energy_error:.3e} | {row.growth:.3g} | {row.phase_error:+.3e} |"
        )
    ours = None
    lines.append("")
    for row in rows:
        if not row.method.startswith("DOP853"):
            ours = row
            continue
        assert ours is not None
        energy = ours.energy_error / row.energy_error
        phase = abs(ours.phase_error) / max(abs(row.phase_error), 1e-300)
        lines.append(
            f"- {ours.method} {ours.setting} against {row.method}: energy error ratio "
            f"{energy:.3g}, phase error ratio {phase:.3g} (below 1: {ours.method} more accurate)"
        )
    return "\n".join(lines)


# --------------------------------------------------------------------------- recording


def record(text: str) -> None:
    """Append this run's section to RESULTS.md."""
    now = datetime.datetime.now().astimezone().isoformat(timespec="minutes")
    section = [
        f"## Variational integrators compiled, gauss4 and gauss6 (benchmarks/symplectic.py), {now}",
        "",
        f"- platform: {platform.platform()}",
        f"- CPU: {cpu_model()}",
        f"- python {platform.python_version()}, numpy {package_version('numpy')}, "
        f"scipy {package_version('scipy')}, numba {package_version('numba')}, "
        f"symengine {package_version('symengine')}",
        "",
        text,
    ]
    existing = RESULTS.read_text() if RESULTS.exists() else "# Benchmark results\n"
    RESULTS.write_text(existing.rstrip("\n") + "\n\n" + "\n".join(section) + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--part", choices=("speed", "work", "both"), default="both")
    parser.add_argument("--steps", type=int, default=100_000, help="speed: steps (10^5)")
    parser.add_argument("--periods", type=int, default=1000, help="work: periods (1000)")
    parser.add_argument("--record", action="store_true", help=f"append to {RESULTS.name}")
    args = parser.parse_args(argv)
    parts = []
    if args.part in ("speed", "both"):
        print("speed ...", file=sys.stderr)
        parts.append("### Speed\n\n" + speed_report(args.steps))
    if args.part in ("work", "both"):
        print("work ...", file=sys.stderr)
        rows = run_work(args.periods)
        parts.append(
            "### Against DOP853 at equal work and equal wall time\n\n"
            + work_report(rows, args.periods)
        )
    text = "\n\n".join(parts)
    print(text)
    if args.record:
        record(text)
        print(f"\nwritten to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
