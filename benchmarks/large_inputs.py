"""Benchmark: the largest legitimate inputs, through the command line, against the bound that
every command must meet on them (30 s of wall time and 1 GiB of memory, issue 19).

What is measured
    Each case is one ``lagrangian`` command in a fresh process, as a user runs it: its wall
    time, its CPU time (user + system, of the child alone) and its peak resident memory.
    The cases are chains of point masses, the largest systems a student writes by hand or
    by loop:

    n_link_pendulum:200          the built-in chain of 200 links (masses m_1 ... m_200)
    n_link_pendulum:200 json     the same, ``--format json``
    particle chain file          200 equal masses, each placed in a model file at the sum
                                 of the rods above it (a 600 kB YAML file, written here)
    spring chain file            200 masses joined by springs (1-D, a model file)

    Every output is checked before it counts: exit 0, and the equation of the last
    coordinate is in it.  The anchor is the bound itself (sympy.physics.mechanics takes
    minutes for a chain of 20 links: benchmarks/derive.py), reported as the fraction of
    the bound each run used.

Usage
    python benchmarks/large_inputs.py              # every case, 1 repeat
    python benchmarks/large_inputs.py --repeat 3   # the median of 3
    python benchmarks/large_inputs.py --record     # also append the results to RESULTS.md
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from machine import cpu_model, package_version

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
RESULTS = HERE.parent / "RESULTS.md"
#: The bound of issue 19: every command ends within this wall time and memory.
BOUND_SECONDS = 30.0
BOUND_BYTES = 1 << 30
#: A run past this is killed and reported as failing (several times the bound).
KILL_SECONDS = 300.0
LINKS = 200


def particle_chain(n: int) -> str:
    """A model file of ``n`` equal point masses, bob i at the sum of the rods above it."""
    coordinates = ", ".join(f"th{i}" for i in range(1, n + 1))
    lines = [f"coordinates: [{coordinates}]", "parameters: {g: 9.81, l: 1, m: 1}", "particles:"]
    x: list[str] = []
    y: list[str] = []
    for i in range(1, n + 1):
        x.append(f"l*sin(th{i})")
        y.append(f"-l*cos(th{i})")
        lines.append(f"  - {{name: p{i}, mass: m, position: [{' + '.join(x)}, {' + '.join(y)}]}}")
    lines.append("gravity: [0, -g]")
    return "\n".join(lines) + "\n"


def spring_chain(n: int) -> str:
    """A model file of ``n`` masses in a line, neighbours joined by springs."""
    coordinates = ", ".join(f"x{i}" for i in range(1, n + 1))
    kinetic = " + ".join(f"m*x{i}_dot**2/2" for i in range(1, n + 1))
    potential = " + ".join(f"k*(x{i + 1} - x{i})**2/2" for i in range(1, n))
    return (
        f"coordinates: [{coordinates}]\nparameters: {{m: 1, k: 1}}\n"
        f"kinetic: {kinetic}\npotential: {potential}\n"
    )


@dataclass(frozen=True)
class Case:
    name: str
    argv: tuple[str, ...]
    last_equation: str  # text the output must hold: the last coordinate's acceleration


@dataclass(frozen=True)
class Run:
    wall: float
    cpu: float
    peak_bytes: int
    ok: bool
    detail: str


def cases(folder: Path, links: int) -> list[Case]:
    particles = folder / "particle_chain.yaml"
    particles.write_text(particle_chain(links))
    springs = folder / "spring_chain.yaml"
    springs.write_text(spring_chain(links))
    chain = f"n_link_pendulum:{links}"
    return [
        Case(f"{chain} (text)", ("derive", chain), f"theta{links}_ddot"),
        Case(f"{chain} (json)", ("derive", chain, "--format", "json"), f"theta{links}_ddot"),
        Case(f"particle chain file, {links} masses", ("derive", str(particles)), f"th{links}_ddot"),
        Case(f"spring chain file, {links} masses", ("derive", str(springs)), f"x{links}_ddot"),
    ]


def run_once(case: Case, folder: Path) -> Run:
    """One command in a fresh process: wall, CPU and peak memory of the child alone (its own
    resource usage, from ``os.wait4``)."""
    environment = {**os.environ, "PYTHONPATH": str(SRC)}
    output, errors = folder / "output.txt", folder / "errors.txt"
    with output.open("wb") as sink, errors.open("wb") as error_sink:
        started = time.perf_counter()
        child = subprocess.Popen(
            [sys.executable, "-m", "lagrangian", *case.argv],
            stdout=sink,
            stderr=error_sink,
            env=environment,
        )
        while True:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - started > KILL_SECONDS:
                child.kill()
                os.wait4(child.pid, 0)
                return Run(
                    KILL_SECONDS, KILL_SECONDS, 0, False, f"killed after {KILL_SECONDS:.0f} s"
                )
            time.sleep(0.05)
        wall = time.perf_counter() - started
    child.returncode = os.waitstatus_to_exitcode(status)
    text = output.read_text(errors="replace")
    ok = child.returncode == 0 and case.last_equation in text
    detail = "" if ok else f"exit {child.returncode}: {errors.read_text(errors='replace')[-300:]}"
    return Run(wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024, ok, detail)


def report(results: dict[str, list[Run]], repeat: int) -> str:
    lines = [
        f"Machine: {cpu_model()}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}; "
        f"Python {platform.python_version()}, SymPy {package_version('sympy')}, "
        f"SymEngine {package_version('symengine')}; median of {repeat}.",
        "",
        "| case | wall s | CPU s | peak MiB | wall / 30 s | result |",
        "|---|---|---|---|---|---|",
    ]
    for name, runs in results.items():
        wall = statistics.median(r.wall for r in runs)
        cpu = statistics.median(r.cpu for r in runs)
        peak = max(r.peak_bytes for r in runs) / (1 << 20)
        within = (
            all(r.ok for r in runs) and wall <= BOUND_SECONDS and peak * (1 << 20) <= BOUND_BYTES
        )
        verdict = "PASS" if within else "FAIL " + "; ".join(r.detail for r in runs if r.detail)
        share = wall / BOUND_SECONDS
        lines.append(f"| {name} | {wall:.1f} | {cpu:.1f} | {peak:.0f} | {share:.2f} | {verdict} |")
    return "\n".join(lines)


def record(text: str, note: str) -> None:
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M+00:00")
    title = (
        f"## Large inputs against the bound of 30 s and 1 GiB (benchmarks/large_inputs.py), {stamp}"
    )
    if note:
        title += f" ({note})"
    with RESULTS.open("a") as sink:
        sink.write(f"\n{title}\n\n{text}\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--links", type=int, default=LINKS, help="masses in each chain")
    parser.add_argument("--record", action="store_true", help=f"append results to {RESULTS.name}")
    parser.add_argument("--note", default="", help="a note for the recorded section's title")
    args = parser.parse_args(argv)
    results: dict[str, list[Run]] = {}
    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        for case in cases(folder, args.links):
            results[case.name] = [run_once(case, folder) for _ in range(args.repeat)]
            last = results[case.name][-1]
            print(f"{case.name}: {last.wall:.1f} s wall, {last.cpu:.1f} s CPU", file=sys.stderr)
    text = report(results, args.repeat)
    print(text)
    if args.record:
        record(text, args.note)
    return 0 if all(r.ok for runs in results.values() for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
