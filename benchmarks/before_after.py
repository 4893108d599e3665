"""Benchmark: two checkouts side by side on the 3-D benchmarks, with KanesMethod in the same run.

What is measured
    The workers of ``bicycle.py``, ``rolling_disc.py`` and ``multibody.py`` (each the wall
    time from nothing to the equations, in a fresh process; see their docstrings), run
    from this checkout (after) and from another one (before, ``--before DIR``: a checkout
    or a copy of one, with its own ``src`` and ``benchmarks``).  Round by round every
    formulation runs once in each checkout, one after the other, and KanesMethod once, so
    a load that comes and goes on a shared machine falls on both alike.

    Reported per formulation: the median and the range (min-max) of the runs of each
    checkout, after's median over before's, and KanesMethod's median over each.

Usage
    python benchmarks/before_after.py --before ../old-checkout              # 3 rounds
    python benchmarks/before_after.py --before ../old-checkout --repeat 5 --record
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
from pathlib import Path

import multibody

HERE = Path(__file__).resolve().parent
#: (label, script, worker arguments, the Kane job it is compared with)
JOBS = (
    ("bicycle, built-in example", "bicycle.py", ["lagrangian"], "bicycle kane"),
    ("bicycle, by hand (rotation matrices)", "bicycle.py", ["hand"], "bicycle kane"),
    ("rolling disc, RollingDisc element", "rolling_disc.py", ["element"], "disc kane"),
    ("rolling disc, built-in example", "rolling_disc.py", ["example"], "disc kane"),
    ("rolling disc, matrix product", "rolling_disc.py", ["product"], "disc kane"),
    ("rolling disc, matrix expanded", "rolling_disc.py", ["expanded"], "disc kane"),
    ("rolling disc, quaternions", "rolling_disc.py", ["quaternion"], "disc kane"),
    *(
        (f"3-D chain n={n}, {label}", "multibody.py", [method, str(n)], f"chain kane {n}")
        for n in (3, 4)
        for method, label in (
            ("euler", "Euler angles"),
            ("hand", "by hand (matrix products)"),
            ("cartesian", "Cartesian + joints"),
        )
    ),
    ("3-D chain n=3, joint angles", "multibody.py", ["relative", "3"], "chain kane_relative 3"),
)
KANE = {
    "bicycle kane": ("bicycle.py", ["kane"]),
    "disc kane": ("rolling_disc.py", ["kane"]),
    "chain kane 3": ("multibody.py", ["kane", "3"]),
    "chain kane 4": ("multibody.py", ["kane", "4"]),
    "chain kane_relative 3": ("multibody.py", ["kane_relative", "3"]),
}
BEGIN, END = "<!-- before_after.py: begin -->", "<!-- before_after.py: end -->"


def measure(before: Path, repeat: int, cap: float) -> dict:
    """Seconds of every run: {("before"|"after", label): [...], ("kane", key): [...]}."""
    times: dict = {}
    trees = {"before": before / "benchmarks", "after": HERE}
    for r in range(repeat):
        for label, script, arguments, _ in JOBS:
            for side, tree in trees.items():
                outcome = multibody.run_worker(tree / script, arguments, cap, verify=False)
                times.setdefault((side, label), []).append(outcome["seconds"])
                cpu = outcome.get("cpu_seconds", math.nan)
                times.setdefault((side, "cpu", label), []).append(cpu)
                _count_switches(times, (side, label), outcome)
                note = f" ({outcome['error'][-120:]})" if "error" in outcome else ""
                print(f"  {side:<6} {label}: {outcome['seconds']:.3g} s{note}", file=sys.stderr)
        for key, (script, arguments) in KANE.items():
            outcome = multibody.run_worker(HERE / script, arguments, cap, verify=False)
            times.setdefault(("kane", key), []).append(outcome["seconds"])
            cpu = outcome.get("cpu_seconds", math.nan)
            times.setdefault(("kane", "cpu", key), []).append(cpu)
            _count_switches(times, ("kane", key), outcome)
            print(f"  kane   {key}: {outcome['seconds']:.3g} s", file=sys.stderr)
        print(f"round {r + 1} of {repeat} done", file=sys.stderr)
    return times


def _count_switches(times: dict, key: tuple[str, str], outcome: dict) -> None:
    """The run's wall time beyond its CPU time and its context switches (the workers'
    ``multibody.Stopwatch``), kept under ("waits", *key)."""
    waited = outcome["seconds"] - outcome.get("cpu_seconds", math.nan)
    switches = [outcome.get(f"{kind}_switches", math.nan) for kind in ("voluntary", "involuntary")]
    times.setdefault(("waits", *key), []).append((waited, *switches))


def waits_table(times: dict) -> list[str]:
    """Why the wall time exceeds the CPU time: per formulation (after) and per KanesMethod
    job, the medians of the seconds waited, the voluntary context switches (the process
    waiting for something of its own: I/O, a lock, a sleep) and the involuntary ones (the
    scheduler giving its core to another process)."""
    lines = [
        "| run | wall - CPU s | voluntary switches | involuntary switches |",
        "|---|---:|---:|---:|",
    ]
    keys = [("after", label) for label, *_ in JOBS] + [("kane", key) for key in KANE]
    for key in keys:
        runs = times.get(("waits", *key), [])
        if not runs:
            continue
        columns = [_median([run[i] for run in runs]) for i in range(3)]
        lines.append(
            f"| {key[1]} ({key[0]}) | {columns[0]:.3g} | {columns[1]:.0f} | {columns[2]:.0f} |"
        )
    return lines


def _cell(values: list[float]) -> str:
    finite = [v for v in values if math.isfinite(v)]
    if not finite:
        return "failed"
    middle = statistics.median(finite)
    return f"{middle:.3g} ({min(finite):.3g}-{max(finite):.3g})"


def _median(values: list[float]) -> float:
    finite = [v for v in values if math.isfinite(v)]
    return statistics.median(finite) if finite else math.nan


def report(times: dict, repeat: int, before: Path) -> str:
    """Two tables: wall time (the project's measure), then the CPU time of the worker
    process (its own work only: steadier when other processes share the cores)."""
    lines = [
        f"Median (min-max) of {repeat} run(s) per cell, seconds; before = `{before.name}`, "
        "after = this checkout.",
    ]
    for title, kind in (("Wall time", ()), ("CPU time of the worker process", ("cpu",))):
        lines += [
            "",
            f"{title}:",
            "",
            "| formulation | before s | after s | after/before | Kane s | Kane/before "
            "| Kane/after |",
            "|---|---:|---:|---:|---:|---:|---:|",
        ]
        for label, _, _, kane_key in JOBS:
            old, new = times[("before", *kind, label)], times[("after", *kind, label)]
            kane = times[("kane", *kind, kane_key)]
            m_old, m_new, m_kane = _median(old), _median(new), _median(kane)
            lines.append(
                f"| {label} | {_cell(old)} | {_cell(new)} | {m_new / m_old:.2f} "
                f"| {_cell(kane)} | {m_kane / m_old:.2f} | {m_kane / m_new:.2f} |"
            )
    lines += [
        "",
        "Why the wall time exceeds the CPU time (medians per run):",
        "",
        *waits_table(times),
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, required=True, help="the other checkout")
    parser.add_argument("--repeat", type=int, default=3, help="rounds (3)")
    parser.add_argument("--cap", type=float, default=600.0, help="seconds per run (600)")
    parser.add_argument("--record", action="store_true", help="write a section in RESULTS.md")
    args = parser.parse_args(argv)
    before = args.before.resolve()
    if not (before / "benchmarks" / "bicycle.py").exists():
        parser.error(f"--before {args.before}: no benchmarks/bicycle.py there; give a checkout")
    text = report(measure(before, args.repeat, args.cap), args.repeat, before)
    title = "3-D formulations before and after, against KanesMethod (benchmarks/before_after.py)"
    multibody.publish(text, "before_after.py", argv, title, (BEGIN, END), args.record)
    return 0


if __name__ == "__main__":
    sys.exit(main())
