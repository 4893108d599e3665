"""Members per second of ``lagrangian.sweeps`` with 1 and 2 Dask workers, against a plain
``scipy.integrate.solve_ivp`` loop over the same members.

The members: double-pendulum starts at rest on a grid of (theta, phi) in [-2, 2]^2
(``--grid`` per side), integrated to ``--t-end`` with DOP853 at rtol = atol = 1e-9, the end
state kept (``samples`` = 2).  The loop calls solve_ivp once per member on the same compiled
right-hand side (lagrangian's own, one state at a time).  A sweep is timed on a LocalCluster
already started (the start is reported on its own): the time covers scattering the model,
each worker deriving and compiling it once, the blocks and writing the Zarr store.  Scaling
efficiency = rate(2 workers) / (2 rate(1 worker)).

Constrained systems run in the multiplier form, each block as one ``lg.simulate_batch`` on
a worker (member by member in the C loop): ``--constrained N`` times N
members of a pendulum in Cartesian coordinates held on its circle by a multiplier, to
``--constrained-t-end``, against a plain loop of ``lg.simulate`` calls in one process.

Usage
    python benchmarks/sweep.py                  # 24 x 24 members, t_end = 10
    python benchmarks/sweep.py --grid 12 --t-end 5 --chunk-size 64 --constrained 64
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[1] / "src"))  # the checkout, installed or not

import lagrangian as lg  # noqa: E402
from lagrangian.numerics.compile import compile_equations  # noqa: E402
from lagrangian.sweeps import sweep  # noqa: E402

OPTIONS = {"method": "DOP853", "rtol": 1e-9, "atol": 1e-9}

CARTESIAN_PENDULUM = """
name: cartesian_pendulum
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, l: 1.0}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: "x**2 + y**2 - l**2"}
initial: {x: 0.0, y: -1.0, x_dot: 1.0, y_dot: 0.0}
"""


def solve_ivp_loop(system: lg.System, angles: np.ndarray, t_end: float) -> float:
    """Members per second of one solve_ivp call per member on the compiled right-hand side."""
    from scipy.integrate import solve_ivp

    compiled = compile_equations(lg.derive(system))
    p = np.array([float(system.parameters[s]) for s in system.parameters], dtype=float)
    order = [s.name for s in system.parameters]
    assert tuple(order) == tuple(compiled.parameters)
    start = time.perf_counter()
    for theta in angles:
        for phi in angles:
            x0 = np.array([theta, phi, 0.0, 0.0])
            solve_ivp(lambda t, x: compiled.rhs(t, x, p), (0.0, t_end), x0, **OPTIONS)
    return len(angles) ** 2 / (time.perf_counter() - start)


def simulate_loop(system: lg.System, vary: dict[str, np.ndarray], t_end: float) -> float:
    """Members per second of one lg.simulate call per member (derived and compiled once),
    the end state kept (``samples`` = 2, as the sweep)."""
    ((name, values),) = vary.items()
    lg.simulate(system, {name: float(values[0])}, t_end, samples=2, **OPTIONS)  # compile
    start = time.perf_counter()
    for value in values:
        lg.simulate(system, {name: float(value)}, t_end, samples=2, **OPTIONS)
    return len(values) / (time.perf_counter() - start)


def sweep_rate(
    system: lg.System,
    vary: dict[str, np.ndarray],
    t_end: float,
    workers: int,
    chunk_size: int,
) -> tuple[float, float]:
    """(seconds to start the cluster, members per second of the sweep on it)."""
    from dask.distributed import LocalCluster

    start = time.perf_counter()
    with LocalCluster(
        n_workers=workers, threads_per_worker=1, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        started = time.perf_counter() - start
        with tempfile.TemporaryDirectory() as folder:
            begin = time.perf_counter()
            report = sweep(
                system,
                vary,
                t_end,
                out=Path(folder) / "bench.zarr",
                scheduler=cluster.scheduler_address,
                chunk_size=chunk_size,
                **OPTIONS,
            )
            seconds = time.perf_counter() - begin
            assert report.status.get("success") == report.members
    return started, report.members / seconds


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grid", type=int, default=24, help="members per side (24)")
    parser.add_argument("--t-end", type=float, default=10.0, help="end time (10)")
    parser.add_argument("--chunk-size", type=int, default=64, help="members per block (64)")
    parser.add_argument(
        "--constrained", type=int, default=256, help="constrained members (256; 0: none)"
    )
    parser.add_argument(
        "--constrained-t-end", type=float, default=100.0, help="their end time (100)"
    )
    args = parser.parse_args(argv)
    system = lg.examples.double_pendulum().replace(initial={"theta_dot": 0.0, "phi_dot": 0.0})
    angles = np.linspace(-2.0, 2.0, args.grid)
    vary = {"theta": angles, "phi": angles}
    loop = solve_ivp_loop(system, angles, args.t_end)
    start1, one = sweep_rate(system, vary, args.t_end, 1, args.chunk_size)
    start2, two = sweep_rate(system, vary, args.t_end, 2, args.chunk_size)
    python = sys.version.split()[0]
    print(f"- platform: {platform.platform()}, {os.cpu_count()} cores, python {python}")
    print(
        f"- {args.grid}x{args.grid} = {args.grid**2} double-pendulum members, t_end = "
        f"{args.t_end:g}, DOP853 rtol = atol = 1e-9, chunk size {args.chunk_size}\n"
    )
    print("| run | members/s | vs solve_ivp loop | cluster start s |")
    print("|---|---:|---:|---:|")
    print(f"| solve_ivp loop, 1 process | {loop:.4g} | 1 | - |")
    print(f"| sweep, 1 worker | {one:.4g} | {one / loop:.3g} | {start1:.2g} |")
    print(f"| sweep, 2 workers | {two:.4g} | {two / loop:.3g} | {start2:.2g} |")
    print(f"\nscaling efficiency 1 -> 2 workers: {two / (2 * one):.0%}")
    if args.constrained:
        constrained(args.constrained, args.constrained_t_end)
    return 0


def constrained(members: int, t_end: float) -> None:
    """The table of the constrained members (module docstring)."""
    system = lg.loads(CARTESIAN_PENDULUM)
    vary = {"x_dot": np.linspace(0.5, 6.0, members)}
    loop = simulate_loop(system, vary, t_end)
    chunk = max(1, members // 8)
    start1, one = sweep_rate(system, vary, t_end, 1, chunk)
    start2, two = sweep_rate(system, vary, t_end, 2, chunk)
    print(
        f"\n{members} constrained members (Cartesian pendulum, multiplier form, lg.simulate "
        f"per member), t_end = {t_end:g}, chunk size {chunk}\n"
    )
    print("| run | members/s | vs simulate loop | cluster start s |")
    print("|---|---:|---:|---:|")
    print(f"| lg.simulate loop, 1 process | {loop:.4g} | 1 | - |")
    print(f"| sweep, 1 worker | {one:.4g} | {one / loop:.3g} | {start1:.2g} |")
    print(f"| sweep, 2 workers | {two:.4g} | {two / loop:.3g} | {start2:.2g} |")
    print(f"\nscaling efficiency 1 -> 2 workers: {two / (2 * one):.0%}")


if __name__ == "__main__":
    sys.exit(main())
