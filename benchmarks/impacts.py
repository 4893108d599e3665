"""Benchmark: collisions per second of a gas of hard disks, the general model against a plain
event-driven simulation written here.

What is measured
    100 elastic hard disks (mass 1, radius 0.02) in the unit box, the built-in example
    ``lagrangian.examples.hard_disk_gas(100, radius=0.02)``: disks on a 10 x 10 lattice,
    speed 1 in seeded random directions; every wall and every pair a unilateral constraint
    with e = 1 (400 + 4950 constraints), simulated over ``--t-end`` with 11 output rows:
        lagrangian  ``lagrangian.simulate`` of the derived equations: the piecewise loop of the
                    unilateral constraints, each piece in closed form (free flight), every
                    contact found as the root of its gap's polynomial by the calendar of
                    ``simulation/flight.py``, every impact resolved by the impulsive Lagrange
                    equations (``simulation/impacts.py``), the Trajectory built with its
                    impacts;
        reference   an event-driven simulation in NumPy written below: a priority queue
                    (heapq) of the wall and pair collision times, each disk's times found
                    again against all others after its collisions, stale entries skipped by
                    collision counts (Rapaport, *The Art of Molecular Dynamics Simulation*,
                    ch. 14, without cells).
    Both start from the same state; the rate is collisions (wall and pair) per second of the
    run alone (and, for lagrangian, per second of the collisions past t_end / 10: the cost of
    one more collision, without the cost of a run), the derivation and the first compilation
    aside (timed separately as "setup": building the System, derive, and a first simulate
    over a short span).  The first
    collision times of both are compared.

Usage
    python benchmarks/impacts.py                 # 100 disks, t_end = 2
    python benchmarks/impacts.py --disks 50 --t-end 1
    python benchmarks/impacts.py --record        # also append the table to benchmarks/RESULTS.md
"""

from __future__ import annotations

import argparse
import heapq
import platform
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

import lagrangian as lg
from lagrangian.examples.gas import hard_disk_gas

#: The disks' radius, whatever their number (the built-in example's for 100 disks).
RADIUS = 0.02


class EventDrivenGas:
    """Hard disks in the box [0, side]^2 by a priority queue of collision times."""

    def __init__(self, x: np.ndarray, v: np.ndarray, radius: float, side: float) -> None:
        self.x, self.v = x.copy(), v.copy()
        self.radius, self.side, self.t = radius, side, 0.0
        self.counts = np.zeros(len(x), dtype=int)
        self.queue: list[tuple[float, int, int, int, int]] = []
        self.collisions: list[tuple[float, int, int]] = []  # (time, i, j); j = -1 a wall
        for i in range(len(x)):
            self.schedule(i)

    def schedule(self, i: int) -> None:
        """Push disk i's wall time and its pair times with every other disk."""
        lo, hi = self.radius, self.side - self.radius
        v, x = self.v[i], self.x[i]
        with np.errstate(divide="ignore", invalid="ignore"):
            wall = np.where(v > 0, (hi - x) / v, np.where(v < 0, (lo - x) / v, np.inf))
        axis = int(np.argmin(wall))
        heapq.heappush(self.queue, (self.t + wall[axis], i, -1 - axis, self.counts[i], 0))
        dx, dv = self.x - x, self.v - v
        b = np.einsum("ij,ij->i", dx, dv)
        dv2 = np.einsum("ij,ij->i", dv, dv)
        dx2 = np.einsum("ij,ij->i", dx, dx)
        disc = b * b - dv2 * (dx2 - 4 * self.radius**2)
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where((b < 0) & (disc > 0), -(b + np.sqrt(disc)) / dv2, np.inf)
        dt[i] = np.inf
        for j in np.flatnonzero(np.isfinite(dt)):
            heapq.heappush(self.queue, (self.t + dt[j], i, int(j), self.counts[i], self.counts[j]))

    def run(self, t_end: float) -> None:
        while self.queue:
            t, i, j, ci, cj = heapq.heappop(self.queue)
            if t > t_end:
                break
            if ci != self.counts[i] or (j >= 0 and cj != self.counts[j]):
                continue  # a disk collided since this time was found
            self.x += self.v * (t - self.t)
            self.t = t
            if j < 0:
                self.v[i, -1 - j] *= -1
                self.counts[i] += 1
                self.collisions.append((t, i, -1))
                self.schedule(i)
            else:
                n = self.x[j] - self.x[i]
                n /= np.linalg.norm(n)
                dv = np.dot(self.v[j] - self.v[i], n) * n
                self.v[i] += dv
                self.v[j] -= dv
                self.counts[i] += 1
                self.counts[j] += 1
                self.collisions.append((t, i, j))
                self.schedule(i)
                self.schedule(j)
        self.x += self.v * (t_end - self.t)
        self.t = t_end


def measure(disks: int, t_end: float) -> dict[str, float]:
    started = time.perf_counter()
    gas = hard_disk_gas(disks, radius=RADIUS)
    eom = lg.derive(gas)
    initial = dict(gas.initial)
    lg.simulate(eom, initial, 1e-6, samples=2)  # compiles the pieces' forms
    setup = time.perf_counter() - started
    started = time.perf_counter()
    short = lg.simulate(eom, initial, t_end / 10, samples=11)
    ours_short = time.perf_counter() - started
    started = time.perf_counter()
    run = lg.simulate(eom, initial, t_end, samples=11)
    ours = time.perf_counter() - started
    by_name = {str(key): value for key, value in initial.items()}
    state = np.array([by_name[q.name] for q in gas.coordinates])
    velocities = np.array([by_name[f"{q.name}_dot"] for q in gas.coordinates])
    x = state.reshape(2, disks).T
    v = velocities.reshape(2, disks).T
    reference = EventDrivenGas(x, v, RADIUS, 1.0)
    started = time.perf_counter()
    reference.run(t_end)
    theirs = time.perf_counter() - started
    ours_times = np.array([impact.t for impact in run.impacts])
    their_times = np.array([c[0] for c in reference.collisions])
    common = min(len(ours_times), len(their_times), 50)
    final = np.concatenate([run[f"x{k + 1}"][-1:] for k in range(disks)])
    return {
        "setup": setup,
        "ours_short_time": ours_short,
        "ours_short_collisions": len(short.impacts),
        "ours_time": ours,
        "ours_collisions": len(run.impacts),
        "theirs_time": theirs,
        "theirs_collisions": len(reference.collisions),
        "first_times_differ": float(np.max(np.abs(ours_times[:common] - their_times[:common]))),
        "final_x_differ": float(np.max(np.abs(final - reference.x[:, 0]))),
    }


def table(result: dict[str, float], disks: int, t_end: float) -> str:
    ours = result["ours_collisions"] / result["ours_time"]
    theirs = result["theirs_collisions"] / result["theirs_time"]
    # the cost of one more collision: the run over t_end against the run over t_end / 10
    extra = result["ours_collisions"] - result["ours_short_collisions"]
    marginal = extra / max(result["ours_time"] - result["ours_short_time"], 1e-9)
    fixed = result["ours_time"] - result["ours_collisions"] / marginal
    return "\n".join(
        [
            f"{disks} hard disks, t_end = {t_end}; Python {platform.python_version()}, "
            f"{platform.machine()}",
            "",
            "| contender | collisions | run (s) | collisions / s | ratio to the reference |",
            "|---|---|---|---|---|",
            f"| lagrangian.simulate (general model) | {result['ours_collisions']} | "
            f"{result['ours_time']:.3g} | {ours:.4g} | {ours / theirs:.2f} |",
            f"| lagrangian.simulate, each further collision (runs over t_end and t_end / 10) | "
            f"{extra} | {result['ours_time'] - result['ours_short_time']:.3g} | "
            f"{marginal:.4g} | {marginal / theirs:.2f} |",
            f"| event-driven reference (heapq + NumPy) | {result['theirs_collisions']} | "
            f"{result['theirs_time']:.3g} | {theirs:.4g} | 1 |",
            "",
            f"lagrangian.simulate's cost per run besides its collisions (input checks, the "
            f"calendar's first roots, the Trajectory with one multiplier column per constraint):"
            f" about {fixed:.3g} s.",
            f"setup of the model (System, derive, first simulate): {result['setup']:.3g} s; "
            f"the first {min(50, int(result['ours_collisions']))} collision times differ by at "
            f"most {result['first_times_differ']:.2g}; final x differ by at most "
            f"{result['final_x_differ']:.2g} (chaos amplifies rounding over many collisions).",
        ]
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--disks", type=int, default=100)
    parser.add_argument("--t-end", type=float, default=2.0)
    parser.add_argument("--record", action="store_true")
    args = parser.parse_args()
    result = measure(args.disks, args.t_end)
    text = table(result, args.disks, args.t_end)
    print(text)
    if args.record:
        stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M+00:00")
        command = f"python benchmarks/impacts.py --disks {args.disks} --t-end {args.t_end}"
        title = f"## Impacts: a gas of hard disks (benchmarks/impacts.py), {stamp}"
        section = f"\n{title}\n\n`{command}`\n\n{text}\n"
        with open(Path(__file__).with_name("RESULTS.md"), "a", encoding="utf-8") as stream:
            stream.write(section)


if __name__ == "__main__":
    main()
