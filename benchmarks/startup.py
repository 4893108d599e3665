"""Benchmark: how long lagrangian takes to start, against ``import sympy.physics.mechanics``.

What is measured
    Each case is a fresh ``python`` process running one line; the wall time of the whole
    process (interpreter start included) is taken from outside, and for the import cases also
    the time of the import statement alone, from inside (``time.perf_counter`` around it):
        python              ``pass``: the interpreter alone;
        import lagrangian   ``import lagrangian``;
        ready to derive     ``import lagrangian; lagrangian.derive``: the verb's first use
                            loads SymPy, the model and the derivation;
        ready to simulate   ``import lagrangian; lagrangian.simulate``: also NumPy, SciPy's
                            integrators and the simulation layer;
        lagrangian --help   what the ``lagrangian`` entry point runs, with ``--help``;
        lagrangian --version
        sympy.physics.mechanics (the anchor)   ``import sympy.physics.mechanics``.
    Ratios are each case's process wall time over the anchor's: the anchor is the package a
    user of the field already waits for, and it scales with the machine as lagrangian does.
    The targets (issue 11): ``import lagrangian`` <= 1.0 s and ``lagrangian --help`` <= 0.5 s,
    process wall time, on a quiet machine (the 1-minute load average is reported).

How
    The checkout's ``src`` (or ``--src DIR``, e.g. an exported older revision) goes first on
    PYTHONPATH, so the code measured is that tree, installed or not (``--before DIR`` measures
    a second tree, e.g. ``git archive REV src | tar -x -C DIR``, alongside).  The cases (and
    the trees) run in turn, round after round, so a burst of load hits every case alike;
    tables show medians.

Usage
    python benchmarks/startup.py                  # 15 rounds
    python benchmarks/startup.py --rounds 5 --src /tmp/before/src
    python benchmarks/startup.py --before /tmp/before/src   # two trees, rounds interleaved
    python benchmarks/startup.py --record         # also append the results to RESULTS.md
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import cpu_model

HERE = Path(__file__).resolve()
SRC = HERE.parents[1] / "src"
RESULTS = HERE.parent / "RESULTS.md"
ANCHOR = "import sympy.physics.mechanics"
TARGETS = {"import lagrangian": 1.0, "lagrangian --help": 0.5}

#: Code timing one statement inside the process (it prints the seconds).
INSIDE = "import time; start = time.perf_counter(); {statement}; print(time.perf_counter() - start)"
#: What the ``lagrangian`` console script runs, with one flag.
ENTRY = (
    "import sys; from lagrangian.cli.main import main; sys.argv = ['lagrangian', '{flag}']; "
    "sys.exit(main())"
)
#: (tree, case) -> (median process wall time, median time of the import statement or None).
Results = dict[tuple[str, str], tuple[float, float | None]]
#: Case name -> the code a fresh process runs.
CASES = {
    "python": "pass",
    "import lagrangian": INSIDE.format(statement="import lagrangian"),
    "ready to derive": INSIDE.format(statement="import lagrangian; lagrangian.derive"),
    "ready to simulate": INSIDE.format(statement="import lagrangian; lagrangian.simulate"),
    "lagrangian --help": ENTRY.format(flag="--help"),
    "lagrangian --version": ENTRY.format(flag="--version"),
    ANCHOR: INSIDE.format(statement=ANCHOR),
}


def run_once(code: str, src: Path) -> tuple[float, float | None]:
    """(process wall time, the timed statement's own time or None) of one fresh process."""
    path = [str(src), *filter(None, [os.environ.get("PYTHONPATH")])]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path))
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode != 0 and not code.startswith("import sys"):  # the entry point may say 2
        raise RuntimeError(f"{code!r} failed:\n{done.stderr}")
    inside = float(done.stdout.strip()) if code.startswith("import time") else None
    return wall, inside


def measure(rounds: int, trees: dict[str, Path]) -> tuple[Results, float]:
    """Median wall and inside times of every case in every tree, over ``rounds`` rounds that
    interleave the cases and the trees; and the median 1-minute load average."""
    walls: dict[tuple[str, str], list[float]] = {}
    insides: dict[tuple[str, str], list[float]] = {}
    loads = []
    for _ in range(rounds):
        loads.append(os.getloadavg()[0])
        for tree, src in trees.items():
            for name, code in CASES.items():
                wall, inside = run_once(code, src)
                walls.setdefault((tree, name), []).append(wall)
                if inside is not None:
                    insides.setdefault((tree, name), []).append(inside)
    results: Results = {
        key: (statistics.median(values), _median_or_none(insides.get(key)))
        for key, values in walls.items()
    }
    return results, statistics.median(loads)


def _median_or_none(values: list[float] | None) -> float | None:
    return statistics.median(values) if values else None


def report(results: Results, load: float, rounds: int, trees: dict[str, Path]) -> str:
    """The table (per tree: process wall time, import statement time, ratio to the anchor's
    wall time in that tree's rounds) and the PASS/FAIL lines of the targets, for the last tree."""
    sources = ", ".join(f"{tree} `{_shown(src)}`" for tree, src in trees.items())
    header, rule = ["case"], ["---"]
    for tree in trees:
        header += [f"{tree}: process wall s", f"{tree}: import statement s", f"{tree}: / anchor"]
        rule += ["---:"] * 3
    lines = [
        f"Median of {rounds} fresh processes per case; code from {sources}; 1-minute load "
        f"average {load:.2f} (median over the rounds) on {os.cpu_count()} cores.",
        "",
        "| " + " | ".join(header) + " |",
        "|" + "|".join(rule) + "|",
    ]
    for name in CASES:
        row = [name]
        for tree in trees:
            wall, inside = results[(tree, name)]
            anchor = results[(tree, ANCHOR)][0]
            shown_inside = f"{inside:.3f}" if inside is not None else ""
            row += [f"{wall:.3f}", shown_inside, f"{wall / anchor:.2f}"]
        lines.append("| " + " | ".join(row) + " |")
    last = list(trees)[-1]
    lines += ["", "```"]
    for name, limit in TARGETS.items():
        wall = results[(last, name)][0]
        verdict = "PASS" if wall <= limit else "FAIL"
        lines.append(
            f"{verdict}  {last}: {name} {wall:.3f} s process wall time (target <= {limit} s)"
        )
    lines.append("```")
    return "\n".join(lines)


def _shown(src: Path) -> str:
    try:
        return str(src.resolve().relative_to(HERE.parents[1]))
    except ValueError:
        return str(src)


def record(text: str, note: str) -> None:
    """Append a dated section with the machine description and ``text`` to RESULTS.md."""
    versions = json.loads(
        subprocess.run(
            [
                sys.executable,
                "-c",
                "import json, importlib.metadata as m; print(json.dumps({n: m.version(n) for n "
                "in ('sympy', 'numpy', 'scipy', 'matplotlib')}))",
            ],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    )
    machine = [
        f"- platform: {platform.platform()}",
        f"- CPU: {cpu_model()} ({os.cpu_count()} cores)",
        f"- python {platform.python_version()}, "
        + ", ".join(f"{name} {version}" for name, version in versions.items()),
    ]
    now = datetime.datetime.now().astimezone().isoformat(timespec="minutes")
    title = f"## Start-up (benchmarks/startup.py), {now}" + (f" ({note})" if note else "")
    section = "\n".join([title, "", *machine, "", text])
    RESULTS.write_text(RESULTS.read_text().rstrip("\n") + "\n\n" + section + "\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=15, help="processes per case (15)")
    parser.add_argument("--src", type=Path, default=SRC, help="the source tree to measure")
    parser.add_argument(
        "--before", type=Path, help="also measure this source tree (an older revision), first"
    )
    parser.add_argument("--record", action="store_true", help=f"append results to {RESULTS.name}")
    parser.add_argument("--note", default="", help="a note for the recorded section's title")
    args = parser.parse_args(argv)
    trees = {"before": args.before, "after": args.src} if args.before else {"this": args.src}
    results, load = measure(args.rounds, trees)
    text = report(results, load, args.rounds, trees)
    print(text)
    if args.record:
        record(text, args.note)
        print(f"\nappended to {RESULTS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
