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
                    equations (``simulation/impacts.py``; a lone contact's flight, impulse
                    and calendar update in the compiled step ``numerics/fast/c_flight.c``
                    where there is a C compiler), the Trajectory built with its impacts;
        reference   an event-driven simulation in NumPy written below: a priority queue
                    (heapq) of the wall and pair collision times, each disk's times found
                    again against all others after its collisions, stale entries skipped by
                    collision counts (Rapaport, *The Art of Molecular Dynamics Simulation*,
                    ch. 14, without cells).
    A second model, the same disks in the uniform field (0, -g) (``--gravity g``, 2 by
    default; 0 leaves it out): balls bouncing in a box, every flight a parabola, the floor
    and ceiling met as roots of quadratics in time (the reference's walls likewise, its
    pairs still straight lines: the field moves both disks alike).
    Both contenders start from the same state, each run ``--repeat`` times (interleaved,
    the best time kept); the rate is collisions (wall and pair) per second of the run
    alone (and, for lagrangian, per second of the collisions past t_end / 10: the cost of
    one more collision, without the cost of a run), the derivation and the first
    compilation aside (timed separately as "setup": building the System, derive, and a
    first simulate over a short span, each stage).  The first collision times of both are
    compared.

Usage
    python benchmarks/impacts.py                 # 100 disks, t_end = 2, and in g = 2
    python benchmarks/impacts.py --disks 50 --t-end 1 --gravity 0
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
    """Hard disks in the box [0, side]^2 by a priority queue of collision times, in the
    uniform field ``field`` (g_x, g_y): each disk on its parabola, every pair's relative
    motion still a straight line (the field moves both alike)."""

    def __init__(
        self,
        x: np.ndarray,
        v: np.ndarray,
        radius: float,
        side: float,
        field: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        self.x, self.v = x.copy(), v.copy()
        self.radius, self.side, self.t = radius, side, 0.0
        self.field = np.array(field, dtype=float)
        self.counts = np.zeros(len(x), dtype=int)
        self.queue: list[tuple[float, int, int, int, int]] = []
        self.collisions: list[tuple[float, int, int]] = []  # (time, i, j); j = -1 a wall
        for i in range(len(x)):
            self.schedule(i)

    def schedule(self, i: int) -> None:
        """Push disk i's wall time and its pair times with every other disk."""
        lo, hi = self.radius, self.side - self.radius
        v, x = self.v[i], self.x[i]
        if self.field.any():
            wall = np.array([self.wall_time(x[k], v[k], self.field[k]) for k in range(2)])
        else:
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

    def wall_time(self, x: float, v: float, a: float) -> float:
        """The first s > 0 where x + v s + a s^2 / 2 meets a wall moving into it."""
        best = np.inf
        for wall, inward in ((self.radius, -1.0), (self.side - self.radius, 1.0)):
            c = x - wall
            if a == 0:
                roots = [-c / v] if v != 0 else []
            else:
                disc = v * v - 2 * a * c
                if disc < 0:
                    continue
                q = -(v + np.copysign(np.sqrt(disc), v)) / 2
                roots = [q / (a / 2), c / q] if q != 0 else [-v / (a / 2)]
            for s in roots:  # the wall is met moving into it (not the one just left)
                if 0 < s < best and (v + a * s) * inward > 0:
                    best = s
        return best

    def advance(self, s: float) -> None:
        """Every disk along its flight for the time s."""
        self.x += self.v * s + self.field * (s * s / 2)
        self.v += self.field * s

    def run(self, t_end: float) -> None:
        while self.queue:
            t, i, j, ci, cj = heapq.heappop(self.queue)
            if t > t_end:
                break
            if ci != self.counts[i] or (j >= 0 and cj != self.counts[j]):
                continue  # a disk collided since this time was found
            self.advance(t - self.t)
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
        self.advance(t_end - self.t)
        self.t = t_end


def prepare(disks: int) -> tuple[lg.System, lg.EquationsOfMotion, dict[str, float]]:
    """The gas, its equations and a first simulate (which compiles), each stage timed."""
    started = time.perf_counter()
    gas = hard_disk_gas(disks, radius=RADIUS)
    built = time.perf_counter()
    eom = lg.derive(gas)
    derived = time.perf_counter()
    lg.simulate(eom, dict(gas.initial), 1e-6, samples=2)  # compiles the pieces' forms
    done = time.perf_counter()
    stages = {"system": built - started, "derive": derived - built, "first": done - derived}
    return gas, eom, {**stages, "setup": done - started}


def measure(
    gas: lg.System, eom: lg.EquationsOfMotion, t_end: float, gravity: float = 0.0, repeat: int = 3
) -> dict[str, float]:
    """Both contenders on the gas, in the field (0, -gravity) when it is not 0 (balls
    bouncing in a box: every flight a parabola, the floor met as a quadratic's root); each
    run ``repeat`` times, the runs of both interleaved, the best time of each kept (the
    machine is shared: a burst of load then slows one run, not the ratio)."""
    disks = len(gas.coordinates) // 2
    initial = dict(gas.initial)
    field = {"g_x": 0.0, "g_y": -gravity}
    lg.simulate(eom, initial, t_end / 10, samples=11, parameters=field)  # its first run
    x, v = start_of(gas)
    best = {"ours_short_time": np.inf, "ours_time": np.inf, "theirs_time": np.inf}
    for _ in range(repeat):
        started = time.perf_counter()
        short = lg.simulate(eom, initial, t_end / 10, samples=11, parameters=field)
        best["ours_short_time"] = min(best["ours_short_time"], time.perf_counter() - started)
        started = time.perf_counter()
        run = lg.simulate(eom, initial, t_end, samples=11, parameters=field)
        best["ours_time"] = min(best["ours_time"], time.perf_counter() - started)
        reference = EventDrivenGas(x, v, RADIUS, 1.0, (0.0, -gravity))
        started = time.perf_counter()
        reference.run(t_end)
        best["theirs_time"] = min(best["theirs_time"], time.perf_counter() - started)
    ours_times = np.array([impact.t for impact in run.impacts])
    their_times = np.array([c[0] for c in reference.collisions])
    common = min(len(ours_times), len(their_times), 50)
    final = np.concatenate([run[f"x{k + 1}"][-1:] for k in range(disks)])
    return {
        **best,
        "ours_short_collisions": len(short.impacts),
        "ours_collisions": len(run.impacts),
        "theirs_collisions": len(reference.collisions),
        "first_times_differ": float(np.max(np.abs(ours_times[:common] - their_times[:common]))),
        "final_x_differ": float(np.max(np.abs(final - reference.x[:, 0]))),
    }


def start_of(gas: lg.System) -> tuple[np.ndarray, np.ndarray]:
    """The disks' positions and velocities at the start, one row a disk."""
    disks = len(gas.coordinates) // 2
    by_name = {str(key): value for key, value in gas.initial.items()}
    state = np.array([by_name[q.name] for q in gas.coordinates])
    velocities = np.array([by_name[f"{q.name}_dot"] for q in gas.coordinates])
    return state.reshape(2, disks).T, velocities.reshape(2, disks).T


def rows(result: dict[str, float], model: str) -> list[str]:
    """The table's rows of one model: the whole run, each further collision, the reference."""
    ours = result["ours_collisions"] / result["ours_time"]
    theirs = result["theirs_collisions"] / result["theirs_time"]
    # the cost of one more collision: the run over t_end against the run over t_end / 10
    extra = result["ours_collisions"] - result["ours_short_collisions"]
    marginal = extra / max(result["ours_time"] - result["ours_short_time"], 1e-9)
    return [
        f"| {model} | lagrangian.simulate (general model) | {result['ours_collisions']} | "
        f"{result['ours_time']:.3g} | {ours:.4g} | {ours / theirs:.2f} |",
        f"| {model} | lagrangian.simulate, each further collision (runs over t_end and "
        f"t_end / 10) | {extra} | {result['ours_time'] - result['ours_short_time']:.3g} | "
        f"{marginal:.4g} | {marginal / theirs:.2f} |",
        f"| {model} | event-driven reference (heapq + NumPy) | {result['theirs_collisions']} | "
        f"{result['theirs_time']:.3g} | {theirs:.4g} | 1 |",
    ]


def table(
    results: dict[str, dict[str, float]], stages: dict[str, float], disks: int, t_end: float
) -> str:
    lines = [
        f"{disks} hard disks, t_end = {t_end}; Python {platform.python_version()}, "
        f"{platform.machine()}",
        "",
        "| model | contender | collisions | run (s) | collisions / s | ratio to the reference |",
        "|---|---|---|---|---|---|",
    ]
    for model, result in results.items():
        lines += rows(result, model)
    lines += [
        "",
        f"setup of the model: System {stages['system']:.3g} s, derive {stages['derive']:.3g} s, "
        f"first simulate (compiles, finds the contacts' polynomials) {stages['first']:.3g} s.",
    ]
    for model, result in results.items():
        lines.append(
            f"{model}: the first {min(50, int(result['ours_collisions']))} collision times "
            f"differ from the reference's by at most {result['first_times_differ']:.2g}; "
            f"final x by at most {result['final_x_differ']:.2g} (chaos amplifies rounding "
            "over many collisions)."
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--disks", type=int, default=100)
    parser.add_argument("--t-end", type=float, default=2.0)
    second = "the field of the second model, balls bouncing in the box (0: none)"
    parser.add_argument("--gravity", type=float, default=2.0, help=second)
    parser.add_argument("--repeat", type=int, default=3, help="runs of each, the best kept")
    parser.add_argument("--record", action="store_true")
    args = parser.parse_args()
    gas, eom, stages = prepare(args.disks)
    results = {"gas": measure(gas, eom, args.t_end, repeat=args.repeat)}
    if args.gravity:
        field = f"in a field g = {args.gravity:g}"
        results[field] = measure(gas, eom, args.t_end, args.gravity, args.repeat)
    text = table(results, stages, args.disks, args.t_end)
    print(text)
    if args.record:
        stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M+00:00")
        command = (f"python benchmarks/impacts.py --disks {args.disks} --t-end {args.t_end} "
                   f"--gravity {args.gravity:g}")  # fmt: skip
        title = f"## Impacts: a gas of hard disks (benchmarks/impacts.py), {stamp}"
        section = f"\n{title}\n\n`{command}`\n\n{text}\n"
        with open(Path(__file__).with_name("RESULTS.md"), "a", encoding="utf-8") as stream:
            stream.write(section)


if __name__ == "__main__":
    main()
