"""Benchmark: the variational integrator over long runs, its energy error (no drift) and its
accuracy against SciPy's RK45 and DOP853 at equal work and at equal wall time.

What is measured
    speed   Steps per second of ``lg.simulate(eom, start, t_end, method=M, dt=0.01)`` on the
            double pendulum of the drift part, for M = variational (midpoint rule), gauss4 and
            gauss6, 10^6 steps (``--speed-steps``), every step an output (or
            ``--speed-samples`` output times), compiled and warmed up first: the wall time of
            the call (best of ``--repeat`` calls) and its CPU time (``time.process_time``, the
            better figure on a shared machine), the CPU time of the march alone (the compiled
            march over the same nodes, without lg.simulate's set-up and columns) and the
            largest relative energy error at the outputs.  With ``--baseline SRC`` the same
            measurement runs on another checkout's ``src`` (for example a worktree of the
            commit before) in the same run, the two alternating call by call; the table gives
            both and their ratio.  Every measurement is a fresh process.  ``--heading-note``
            adds words to the block's title (a new block beside the earlier ones).
    alternate
            The CPU time of the march alone of every method over ``--speed-steps`` steps (101
            outputs), this checkout and ``--baseline`` each in one process kept alive, the two
            alternating call by call for ``--rounds`` rounds: the best and the median.  Short
            calls side by side read a loaded machine better than whole runs: a burst of load
            costs one call of either side, and the best of many is near the quiet machine's.
    compile The one-time compile of the two compiled marches (midpoint rule, collocation):
            CPU seconds of a fresh process compiling both into an empty numba cache
            (``NUMBA_CACHE_DIR`` a new temporary folder), this checkout and ``--baseline``.
    drift   The double pendulum of ``lg.examples.double_pendulum`` (unit masses and rods,
            g = 9.81, released at rest at theta = 1, phi = 0.5: chaotic motion) integrated by
            ``simulate(..., method="variational", dt=0.01)`` for 10^6 steps (t = 10^4 s), every
            step an output. Reported: max |E - E0| / |E0| over the run and over each decade of
            steps (1-10, 11-100, ...: a drift shows as growth from decade to decade), and steps
            per second. RK4 at the same dt runs alongside for contrast (``--no-rk4`` skips it).
    work    A simple pendulum (m = l = 1, g = 9.81) released at rest at theta0 = 1 rad, for
            1000 1/4 periods T = 4 K(k^2) / w0 (k = sin(theta0/2), w0 = sqrt(g/l)), ending as
            the bob passes the bottom. The variational integrator at dt = T/n against RK45 and
            DOP853 (``scipy.integrate.solve_ivp`` on the same compiled equations of motion,
            rtol = atol) at
              - equal work: the tolerance is searched (secant steps on log nfev against
                log rtol) until the number of right-hand-side evaluations is within 2 % of the
                variational integrator's number of evaluations of its discrete equations (the
                midpoint terms with their Jacobian, once per Newton iteration, and the Legendre
                map at every output step: every step here);
              - equal wall time: the same search with the target nfev = the variational wall
                time / the measured seconds per evaluation of the method; the actual wall time
                is reported.
            Reported: max |E - E0| / |E0| over every step, and the phase error at the end:
            the time since the last turning point found from the final (theta, theta_dot) on
            the exact solution sin(theta/2) = k sn(K - w0 t, k) (a well-conditioned inversion as
            the bob passes the bottom), compared with T/4, as an angle 2 pi (tau - T/4) / T.

How
    The variational integrator runs through ``lg.simulate`` in the drift part and through its
    stepping loop ``lagrangian.simulation.variational.march.march`` in the work part (so that the
    evaluations are counted; the same code ``simulate`` calls); RK45 and DOP853 run through
    solve_ivp with every accepted step returned. Each case is compiled and warmed up once
    before it is timed. Wall times are single runs on a possibly shared machine.

Usage
    python benchmarks/variational.py                      # every part, 10^6 drift steps
    python benchmarks/variational.py --part speed --baseline ../before/src --record
    python benchmarks/variational.py --part speed --speed-steps 10000000 --speed-samples 101
    python benchmarks/variational.py --part alternate --speed-steps 100000 --rounds 10 \\
        --baseline ../before/src
    python benchmarks/variational.py --part compile --baseline ../before/src
    python benchmarks/variational.py --steps 100000       # a shorter drift run
    python benchmarks/variational.py --part work --periods 100 --per-period 40 80
    python benchmarks/variational.py --record             # write its section of RESULTS.md
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipk, ellipkinc

HERE = Path(__file__).resolve()
#: the package measured: this checkout's, installed or not, or the one of ``--source SRC``
SOURCE = next(
    (sys.argv[i + 1] for i, word in enumerate(sys.argv[:-1]) if word == "--source"),
    str(HERE.parents[1] / "src"),
)
sys.path.insert(0, SOURCE)
sys.path.insert(1, str(HERE.parent))

import lagrangian as lg  # noqa: E402
from lagrangian.numerics.compile import compile_equations  # noqa: E402
from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics  # noqa: E402
from lagrangian.simulation.variational.march import march  # noqa: E402
from machine import cpu_model, package_version  # noqa: E402

RESULTS = HERE.parent / "RESULTS.md"
BEGIN, END = "<!-- variational.py: begin -->", "<!-- variational.py: end -->"
DRIFT_DT = 0.01
THETA0, G = 1.0, 9.81
RK_METHODS = ("RK45", "DOP853")
DRIFT_FACTOR = 1.5  # allowed growth of the max energy error from decade 3 to the last


# --------------------------------------------------------------------------- speed

SPEED_METHODS = ("variational", "gauss4", "gauss6")


def speed_title(steps: int, samples: int, note: str = "") -> str:
    """The heading of a speed block: the steps per second through lg.simulate over ``steps``
    steps, every step an output (``samples`` 0, the block of earlier records) or ``samples``,
    with the words of ``note`` after them."""
    title = "### Steps per second through lg.simulate"
    if samples:
        title += f", {steps:,} steps, {samples} samples"
    return f"{title}{f', {note}' if note else ''}\n\n"


def compile_seconds() -> float:
    """CPU seconds to compile both compiled marches in this process (an empty cache)."""
    from lagrangian.numerics.fast.discrete_loops import discrete_march

    cpu = time.process_time()
    for kind in ("midpoint", "collocation"):
        discrete_march(kind)
    return time.process_time() - cpu


def run_compile(baseline: str | None) -> str:
    """The compile block: CPU seconds of the one-time compile of the marches, each checkout
    in a fresh process with an empty numba cache."""
    import tempfile

    sources = {"this checkout": SOURCE} | ({"baseline": baseline} if baseline else {})
    lines = ["| package | compile CPU s |", "|---|---:|"]
    for name, source in sources.items():
        with tempfile.TemporaryDirectory() as cache:
            command = [sys.executable, str(HERE), "--source", source, "--compile-worker"]
            environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
            done = subprocess.run(
                command, capture_output=True, text=True, check=True, env=environment
            )
        lines.append(f"| {name} | {float(done.stdout.strip().splitlines()[-1]):.1f} |")
    header = (
        "Both compiled marches (midpoint rule, collocation) compiled once into an empty numba "
        f"cache, each checkout in a fresh process; 1-minute load average at the end: "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores."
    )
    return "\n".join([header, "", *lines])


def measure_speed(method: str, steps: int, samples: int = 0) -> dict[str, float]:
    """One warm ``lg.simulate`` call of ``method`` over ``steps`` steps of the double pendulum,
    every step an output (``samples`` 0) or ``samples`` output times: wall and CPU seconds,
    the CPU seconds of the march alone (the compiled march over the same nodes, without
    lg.simulate's set-up and output columns) and the largest relative energy error at the
    outputs (in this process)."""
    pendulum = lg.examples.double_pendulum()
    eom = lg.derive(pendulum)
    start = dict(pendulum.initial)
    rows = {"samples": samples} if samples else {}
    lg.simulate(eom, start, 10 * DRIFT_DT, method=method, dt=DRIFT_DT, **rows)  # compile, warm up
    wall, cpu = time.perf_counter(), time.process_time()
    run = lg.simulate(
        eom, start, steps * DRIFT_DT, method=method, dt=DRIFT_DT, max_steps=steps + 1, **rows
    )
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    assert run.success and len(run.t) == (samples or steps + 1)
    return {
        "wall": wall,
        "cpu": cpu,
        "march": march_alone(eom, method, steps, run.t if samples else None),
        "error": float(relative_energy_error(run).max()),
    }


def march_alone(eom: lg.EquationsOfMotion, method: str, steps: int, t_out: object) -> float:
    """CPU seconds of the march of ``method`` alone over ``steps`` steps of the double
    pendulum (outputs at ``t_out``, or every node for None)."""
    from lagrangian.simulation.variational import midpoint as variational
    from lagrangian.simulation.variational.collocation import tableau_for

    mechanics = compile_discrete_mechanics(eom)
    p = np.array([float(eom.system.parameters[s]) for s in eom.parameters])
    initial = eom.system.initial
    x0 = np.array([float(initial.get(s, 0.0)) for s in (*eom.coordinates, *eom.velocities)])
    tableau = None if method == "variational" else tableau_for(method, False)
    schedule = variational.StepSchedule(0.0, steps * DRIFT_DT, DRIFT_DT, t_out)  # type: ignore[arg-type]
    cpu = time.process_time()
    run = variational.discrete_march(mechanics, tableau, x0, p, schedule, None, None)
    cpu = time.process_time() - cpu
    assert run.failure is None
    return cpu


def speed_in_process(source: str, method: str, steps: int, samples: int) -> dict[str, float]:
    """:func:`measure_speed` in a fresh process on the package at ``source``."""
    command = [sys.executable, str(HERE), "--source", source, "--speed-worker", method]
    sizes = ["--speed-steps", str(steps), "--speed-samples", str(samples)]
    done = subprocess.run([*command, *sizes], capture_output=True, text=True, check=True)
    return dict(json.loads(done.stdout.strip().splitlines()[-1]))


def run_speed(steps: int, repeat: int, baseline: str | None, samples: int = 0) -> str:
    """The speed table: per method the best of ``repeat`` calls, this checkout against the
    ``baseline`` source when given (alternating)."""
    sources = {"this checkout": SOURCE} | ({"baseline": baseline} if baseline else {})
    lines = [
        "| method | package | wall s | steps/s (wall) | steps/s (CPU) | march alone steps/s "
        "(CPU) | max abs(E - E0)/E0 |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    ratios = []
    for method in SPEED_METHODS:
        best: dict[str, dict[str, float]] = {}
        for _ in range(repeat):
            for name, source in sources.items():
                result = speed_in_process(source, method, steps, samples)
                print(f"  {method} {name}: {steps / result['wall']:,.0f} steps/s", file=sys.stderr)
                if name not in best or result["wall"] < best[name]["wall"]:
                    best[name] = result
        for name, result in best.items():
            lines.append(
                f"| {method} | {name} | {result['wall']:.2f} | {steps / result['wall']:,.0f} | "
                f"{steps / result['cpu']:,.0f} | {steps / result['march']:,.0f} | "
                f"{result['error']:.3e} |"
            )
        if "baseline" in best:
            ours, theirs = best["this checkout"], best["baseline"]
            ratios.append(
                f"- {method}: {theirs['wall'] / ours['wall']:.2f}x the baseline's steps per "
                f"second (wall), {theirs['cpu'] / ours['cpu']:.2f}x (CPU)"
            )
    header = (
        f"Double pendulum (theta = 1, phi = 0.5 at rest), dt = {DRIFT_DT:g}, {steps:,} steps, "
        f"{'every step an output' if not samples else f'{samples} output samples'}, through "
        f"lg.simulate; best of {repeat} calls, each in a fresh "
        f"process; 1-minute load average at the end: {os.getloadavg()[0]:.1f} on "
        f"{os.cpu_count()} cores (on a shared machine the CPU time is the figure to read)."
    )
    return "\n".join([header, "", *lines, *([""] if ratios else []), *ratios])


def alternate_worker() -> None:
    """Answer each line ``METHOD STEPS`` of standard input with the CPU seconds of the march
    alone of ``METHOD`` over ``STEPS`` steps (101 outputs), after "ready"."""
    eom = lg.derive(lg.examples.double_pendulum())
    for method in SPEED_METHODS:
        march_alone(eom, method, 1000, None)  # compile, warm up
    print("ready", flush=True)
    for line in sys.stdin:
        method, count = line.split()
        steps = int(count)
        t_out = np.linspace(0.0, steps * DRIFT_DT, 101)
        print(march_alone(eom, method, steps, t_out), flush=True)


def run_alternate(steps: int, rounds: int, baseline: str | None) -> str:
    """The march alone of every method, this checkout and the ``baseline`` in two processes
    kept alive, alternating call by call: best and median CPU steps per second."""
    sources = {"this checkout": SOURCE} | ({"baseline": baseline} if baseline else {})
    workers = {
        name: subprocess.Popen(
            [sys.executable, str(HERE), "--source", source, "--alternate-worker"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        for name, source in sources.items()
    }
    for worker in workers.values():
        while worker.stdout and worker.stdout.readline().strip() != "ready":
            pass
    seconds: dict[tuple[str, str], list[float]] = {}
    for _ in range(rounds):
        for method in SPEED_METHODS:
            for name, worker in workers.items():
                assert worker.stdin and worker.stdout
                worker.stdin.write(f"{method} {steps}\n")
                worker.stdin.flush()
                seconds.setdefault((method, name), []).append(float(worker.stdout.readline()))
    for worker in workers.values():
        assert worker.stdin
        worker.stdin.close()
        worker.wait()
    lines = [
        "| method | package | best steps/s (CPU) | median steps/s (CPU) |",
        "|---|---|---:|---:|",
    ]
    ratios = []
    for method in SPEED_METHODS:
        for name in sources:
            ordered = sorted(seconds[(method, name)])
            best, median = steps / ordered[0], steps / ordered[len(ordered) // 2]
            lines.append(f"| {method} | {name} | {best:,.0f} | {median:,.0f} |")
        if baseline:
            ours, theirs = (min(seconds[(method, name)]) for name in sources)
            ratios.append(f"- {method}: {theirs / ours:.2f}x the baseline's best")
    header = (
        f"Double pendulum (theta = 1, phi = 0.5 at rest), dt = {DRIFT_DT:g}, the march alone "
        f"(101 outputs) over {steps:,} steps, {rounds} rounds, each checkout in one process "
        f"kept alive, the two alternating call by call; 1-minute load average at the end: "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores."
    )
    return "\n".join([header, "", *lines, *([""] if ratios else []), *ratios])


# --------------------------------------------------------------------------- drift


@dataclass
class DriftResult:
    steps: int
    decades: list[tuple[str, float, float | None]]  # label, variational, RK4
    worst: tuple[float, float | None]
    seconds: float
    rk4_seconds: float | None


def relative_energy_error(trajectory: lg.simulate.Trajectory) -> np.ndarray:
    energy = trajectory.energy
    return np.abs(energy - energy[0]) / abs(energy[0])


def decade_maxima(error: np.ndarray) -> list[tuple[str, float]]:
    """max of error[k] over k in (10^(d-1), 10^d], d = 1, 2, ... (k = 0 is the start)."""
    rows, low = [], 1
    while low < len(error):
        high = min(10 * max(low - 1, 1), len(error) - 1)
        rows.append((f"{low:,}-{high:,}", float(error[low : high + 1].max())))
        low = high + 1
    return rows


def run_drift(steps: int, with_rk4: bool) -> DriftResult:
    pendulum = lg.examples.double_pendulum()
    eom = lg.derive(pendulum)
    start = dict(pendulum.initial)
    lg.simulate(eom, start, 10 * DRIFT_DT, method="variational", dt=DRIFT_DT)  # compile
    begin = time.perf_counter()
    run = lg.simulate(eom, start, steps * DRIFT_DT, method="variational", dt=DRIFT_DT)
    seconds = time.perf_counter() - begin
    error = relative_energy_error(run)
    rk4_error, rk4_seconds = None, None
    if with_rk4:
        lg.simulate(eom, start, 10 * DRIFT_DT, method="RK4", dt=DRIFT_DT)
        begin = time.perf_counter()
        rk4 = lg.simulate(eom, start, steps * DRIFT_DT, method="RK4", dt=DRIFT_DT)
        rk4_seconds = time.perf_counter() - begin
        rk4_error = relative_energy_error(rk4)
    decades = [
        (label, value, None if rk4_error is None else theirs)
        for (label, value), (_, theirs) in zip(
            decade_maxima(error), decade_maxima(error if rk4_error is None else rk4_error)
        )
    ]
    worst = (float(error.max()), None if rk4_error is None else float(rk4_error.max()))
    return DriftResult(steps, decades, worst, seconds, rk4_seconds)


def drift_report(result: DriftResult) -> str:
    rk4 = result.rk4_seconds is not None
    header = "| steps | variational max abs(E - E0)/E0 |" + (
        " RK4 max abs(E - E0)/E0 |" if rk4 else ""
    )
    lines = [header, "|---:|---:|" + ("---:|" if rk4 else "")]
    for label, ours, theirs in [*result.decades, ("all", *result.worst)]:
        row = f"| {label} | {ours:.3e} |" + (f" {theirs:.3e} |" if rk4 else "")
        lines.append(row)
    rate = result.steps / result.seconds
    summary = [
        f"Double pendulum (theta = 1, phi = 0.5 at rest), dt = {DRIFT_DT:g}, "
        f"{result.steps:,} steps (t = {result.steps * DRIFT_DT:g} s), every step an output.",
        "",
        *lines,
        "",
        f"variational: {result.seconds:.1f} s, {rate:,.0f} steps/s ({1e6 / rate:.0f} us per "
        "step, through lg.simulate)",
    ]
    if result.rk4_seconds is not None:
        summary.append(
            f"RK4 (same dt): {result.rk4_seconds:.1f} s, "
            f"{result.steps / result.rk4_seconds:,.0f} steps/s"
        )
    return "\n".join([*summary, "", "```", drift_verdict(result), "```"])


def drift_verdict(result: DriftResult) -> str:
    """PASS when the last decade's maximum is within DRIFT_FACTOR of the third decade's."""
    if len(result.decades) < 4:
        return "N/A   no drift (fewer than 4 decades of steps: run with --steps >= 1000)"
    third, last = result.decades[2], result.decades[-1]
    ratio = last[1] / third[1]
    verdict = "PASS" if ratio <= DRIFT_FACTOR else "FAIL"
    return (
        f"{verdict}  no drift: max error over steps {last[0]} is {ratio:.3f}x that over steps "
        f"{third[0]} (allowed {DRIFT_FACTOR:g}x)"
    )


# --------------------------------------------------------------------------- work


@dataclass
class Pendulum:
    """The simple pendulum of the work part and its exact period and phase."""

    eom: lg.EquationsOfMotion
    p: np.ndarray
    x0: np.ndarray
    periods: int

    @property
    def modulus(self) -> float:
        return math.sin(THETA0 / 2) ** 2

    @property
    def omega(self) -> float:
        return math.sqrt(G)

    @property
    def period(self) -> float:
        return 4 * ellipk(self.modulus) / self.omega

    @property
    def t_end(self) -> float:
        return (self.periods + 0.25) * self.period

    def phase(self, theta: np.ndarray, theta_dot: np.ndarray) -> np.ndarray:
        """The phase 2 pi tau / T in [0, 2 pi) of each state, tau the time since the last
        turning point at theta0 on the exact solution sin(theta/2) = k sn(K - w0 tau, k)."""
        k, quarter = math.sqrt(self.modulus), ellipk(self.modulus)
        s = np.clip(np.sin(theta / 2) / k, -1.0, 1.0)
        u = ellipkinc(np.arcsin(s), self.modulus)  # sn(u) = s, -K <= u <= K
        falling = (quarter - u) / self.omega  # theta_dot <= 0: tau in [0, T/2]
        tau = np.where(theta_dot <= 0, falling, self.period - falling)
        return 2 * math.pi * tau / self.period

    def phase_error(self, t: np.ndarray, theta: np.ndarray, theta_dot: np.ndarray) -> float:
        """The phase of the run at its end, unwrapped along its steps, minus the exact
        2 pi t_end / T (negative: the run lags)."""
        unwrapped = np.unwrap(self.phase(theta, theta_dot))
        return float(unwrapped[-1] - 2 * math.pi * t[-1] / self.period)


@dataclass
class WorkRow:
    method: str
    setting: str
    evaluations: int
    seconds: float
    energy_error: float
    phase_error: float


def make_pendulum(periods: int) -> Pendulum:
    system = lg.examples.simple_pendulum()
    eom = lg.derive(system)
    p = np.array([{"m": 1.0, "g": G, "l": 1.0}[s.name] for s in eom.parameters])
    return Pendulum(eom, p, np.array([THETA0, 0.0]), periods)


def run_variational(pendulum: Pendulum, per_period: int) -> WorkRow:
    mechanics = compile_discrete_mechanics(pendulum.eom)
    steps = round((pendulum.periods + 0.25) * per_period)
    grid = np.linspace(0.0, pendulum.t_end, steps + 1)
    march(mechanics, pendulum.x0, pendulum.p, grid[:11], np.arange(11))  # warm up
    begin = time.perf_counter()
    run = march(mechanics, pendulum.x0, pendulum.p, grid, np.arange(len(grid)))
    seconds = time.perf_counter() - begin
    energy = compile_equations(pendulum.eom).energy(run.q, run.q_dot, grid, pendulum.p)
    return WorkRow(
        "variational",
        f"dt = T/{per_period}",
        run.evaluations,
        seconds,
        float(np.max(np.abs(energy / energy[0] - 1))),
        pendulum.phase_error(grid, run.q[:, 0], run.q_dot[:, 0]),
    )


def run_scipy(pendulum: Pendulum, method: str, rtol: float) -> WorkRow:
    compiled = compile_equations(pendulum.eom)

    def field(t: float, x: np.ndarray) -> np.ndarray:
        return compiled.rhs(t, x, pendulum.p)

    begin = time.perf_counter()
    solution = solve_ivp(field, (0.0, pendulum.t_end), pendulum.x0, method, rtol=rtol, atol=rtol)
    seconds = time.perf_counter() - begin
    q, q_dot = solution.y[:1].T, solution.y[1:].T
    energy = compiled.energy(q, q_dot, solution.t, pendulum.p)
    return WorkRow(
        method,
        f"rtol = {rtol:.2e}",
        int(solution.nfev),
        seconds,
        float(np.max(np.abs(energy / energy[0] - 1))),
        pendulum.phase_error(solution.t, solution.y[0], solution.y[1]),
    )


def matched(pendulum: Pendulum, method: str, target: float, label: str) -> WorkRow:
    """The run of ``method`` whose nfev is closest to ``target`` (secant steps on log-log)."""
    slope = -1 / (5 if method == "RK45" else 8)  # nfev ~ rtol^(-1/order) for small rtol
    log_rtol, tried = math.log(1e-7), []
    for _ in range(8):
        row = run_scipy(pendulum, method, math.exp(log_rtol))
        tried.append((log_rtol, row))
        if abs(row.evaluations / target - 1) < 0.02:
            break
        if len(tried) > 1:
            (a, ra), (b, rb) = tried[-2], tried[-1]
            if a != b and ra.evaluations != rb.evaluations:
                slope = (math.log(rb.evaluations) - math.log(ra.evaluations)) / (b - a)
        step = (math.log(target) - math.log(row.evaluations)) / slope
        log_rtol = min(max(log_rtol + step, math.log(1e-13)), math.log(1e-2))
    best = min(tried, key=lambda pair: abs(math.log(pair[1].evaluations / target)))[1]
    best.method = f"{method}, {label}"
    return best


def run_work(periods: int, per_period: list[int]) -> list[WorkRow]:
    pendulum = make_pendulum(periods)
    for method in RK_METHODS:
        run_scipy(pendulum, method, 1e-3)  # compile and warm up
    rows = []
    for n in per_period:
        ours = run_variational(pendulum, n)
        rows.append(ours)
        print(f"  variational dt = T/{n}: {ours.evaluations} evaluations", file=sys.stderr)
        for method in RK_METHODS:
            work = matched(pendulum, method, ours.evaluations, "equal work")
            per_evaluation = work.seconds / work.evaluations
            wall = matched(pendulum, method, ours.seconds / per_evaluation, "equal wall time")
            rows += [work, wall]
            print(f"  {method}: done", file=sys.stderr)
    return rows


def work_report(rows: list[WorkRow], periods: int) -> str:
    pendulum = make_pendulum(periods)
    lines = [
        f"Simple pendulum (theta0 = {THETA0:g} rad, g = {G:g}, l = 1), {periods} 1/4 periods "
        f"(T = {pendulum.period:.6f} s, t = {pendulum.t_end:.1f} s).",
        "",
        "| method | setting | evaluations | wall s | max abs(E - E0)/E0 | phase error rad |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for row in rows:
        lines.append(
            f"| {row.method} | {row.setting} | {row.evaluations:,} | {row.seconds:.2f} | "
            f"{row.energy_error:.3e} | {row.phase_error:+.3e} |"
        )
    return "\n".join([*lines, "", *comparisons(rows)])


def comparisons(rows: list[WorkRow]) -> list[str]:
    """Per variational run: its energy and phase errors over those of each method it was
    matched against (below 1: the variational integrator is the more accurate)."""
    text, ours = [], None
    for row in rows:
        if row.method == "variational":
            ours = row
            continue
        if ours is None:
            continue
        energy = ours.energy_error / row.energy_error
        phase = abs(ours.phase_error) / max(abs(row.phase_error), 1e-300)
        text.append(
            f"- variational {ours.setting} against {row.method}: energy error ratio "
            f"{energy:.3g}, phase error ratio {phase:.3g}"
        )
    return text


# --------------------------------------------------------------------------- recording


def record(parts: list[str], command: str) -> None:
    """Write this benchmark's own section of RESULTS.md, between its markers: each of the
    ``parts`` (a "### title" block) replaces the block of the same title, the blocks of the
    parts not measured now are kept."""
    now = datetime.datetime.now().astimezone().isoformat(timespec="minutes")
    stamped = [part.replace("\n\n", f"\n\nRecorded {now} by `{command}`.\n\n", 1) for part in parts]
    existing = RESULTS.read_text() if RESULTS.exists() else "# Benchmark results\n"
    blocks: dict[str, str] = {}
    if BEGIN in existing and END in existing:
        body = existing.split(BEGIN, 1)[1].split(END, 1)[0]
        header, *kept = body.split("\n### ")
        # a block recorded before the blocks carried their own date keeps the section's
        lines = header.splitlines()
        when = next((line for line in lines if line.startswith("Recorded")), "")
        machine = next((line[2:] for line in lines if line.startswith("- CPU:")), "")
        when = f"{when.split(';')[0]} ({machine})" if when and machine else when
        for block in kept:
            title, text = block.split("\n", 1)
            if when and not text.strip().startswith("Recorded"):
                text = f"\n{when}.\n{text}"
            blocks["### " + title] = f"### {title}\n{text}".strip("\n")
    new = {part.split("\n", 1)[0]: part for part in stamped}
    order = [title for title in new if title not in blocks] + list(blocks)
    section = "\n".join(
        [
            BEGIN,
            "## Variational integrator (benchmarks/variational.py)",
            "",
            "See the docstring of benchmarks/variational.py for what is measured and how.",
            "",
            f"- platform: {platform.platform()}",
            f"- CPU: {cpu_model()}",
            f"- python {platform.python_version()}, numpy {package_version('numpy')}, "
            f"scipy {package_version('scipy')}, sympy {package_version('sympy')}",
            "",
            "\n\n".join(new.get(title, blocks.get(title, "")) for title in order),
            END,
        ]
    )
    if BEGIN in existing and END in existing:
        before, rest = existing.split(BEGIN, 1)
        after = rest.split(END, 1)[1]
        RESULTS.write_text(before + section + after)
    else:
        RESULTS.write_text(existing.rstrip("\n") + "\n\n" + section + "\n")


# --------------------------------------------------------------------------- command line


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--part",
        choices=("speed", "alternate", "compile", "drift", "work", "both"),
        default="both",
    )
    parser.add_argument("--heading-note", default="", help="speed: words added to the title")
    parser.add_argument("--compile-worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--speed-steps", type=int, default=10**6, help="speed: steps (10^6)")
    parser.add_argument(
        "--speed-samples", type=int, default=0, help="speed: output samples (0: every step)"
    )
    parser.add_argument("--repeat", type=int, default=3, help="speed: calls per method (3)")
    parser.add_argument("--baseline", help="speed: another checkout's src to measure alongside")
    parser.add_argument("--source", help=argparse.SUPPRESS)  # read before the imports
    parser.add_argument("--speed-worker", help=argparse.SUPPRESS)
    parser.add_argument("--alternate-worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--rounds", type=int, default=10, help="alternate: rounds (10)")
    parser.add_argument("--steps", type=int, default=10**6, help="drift steps (10^6)")
    parser.add_argument("--no-rk4", action="store_true", help="drift: skip the RK4 contrast")
    parser.add_argument("--periods", type=int, default=1000, help="work: periods (1000)")
    parser.add_argument(
        "--per-period", type=int, nargs="+", default=[40, 80], help="work: steps per period"
    )
    parser.add_argument(
        "--record", action="store_true", help=f"write the section in {RESULTS.name}"
    )
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    if args.speed_worker:
        print(json.dumps(measure_speed(args.speed_worker, args.speed_steps, args.speed_samples)))
        return 0
    if args.compile_worker:
        print(compile_seconds())
        return 0
    if args.alternate_worker:
        alternate_worker()
        return 0
    parts = []
    if args.part in ("speed", "both"):
        print("speed ...", file=sys.stderr)
        parts.append(
            speed_title(args.speed_steps, args.speed_samples, args.heading_note)
            + run_speed(args.speed_steps, args.repeat, args.baseline, args.speed_samples)
        )
    if args.part == "alternate":
        print("alternate ...", file=sys.stderr)
        title = (
            f"### March alone, two live processes alternating, {args.speed_steps:,} steps x "
            f"{args.rounds}{f', {args.heading_note}' if args.heading_note else ''}\n\n"
        )
        parts.append(title + run_alternate(args.speed_steps, args.rounds, args.baseline))
    if args.part == "compile":
        print("compile ...", file=sys.stderr)
        parts.append("### One-time compile of the marches\n\n" + run_compile(args.baseline))
    if args.part in ("drift", "both"):
        print("drift ...", file=sys.stderr)
        parts.append(
            "### Energy error over a long run\n\n"
            + drift_report(run_drift(args.steps, not args.no_rk4))
        )
    if args.part in ("work", "both"):
        print("work ...", file=sys.stderr)
        rows = run_work(args.periods, args.per_period)
        parts.append("### Equal work and equal wall time\n\n" + work_report(rows, args.periods))
    text = "\n\n".join(parts)
    print(text)
    if args.record:
        words = [word for word in (argv if argv is not None else sys.argv[1:])]
        record(parts, " ".join(["python benchmarks/variational.py", *words]))
        print(f"\nwritten to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
