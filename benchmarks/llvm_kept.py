"""Benchmark: a model's first simulate in a fresh process, its LLVM compilations kept on disk
against compiled again (``LAGRANGIAN_LLVM_CACHE=0``), in alternating fresh processes.

What is measured
    The process CPU time of ``lg.simulate`` of a built-in example, and the part of it spent
    making the model's LLVM functions (``numerics/fast/llvm.py::llvm_lambdify``: converting
    the expressions to SymEngine, naming them, and compiling them or reading them back).
    The first round fills the cache folder (a folder of the benchmark's own); the rounds
    after alternate the two settings.

Usage
    python benchmarks/llvm_kept.py whipple_bicycle --t-end 1 --repeat 3
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def worker(model: str, t_end: float) -> dict[str, float]:
    """One simulate in this process: its CPU seconds and those of the LLVM functions."""
    import lagrangian as lg
    import lagrangian.numerics.evaluate as evaluate
    import lagrangian.numerics.fast.native as native

    spent = {"llvm": 0.0, "functions": 0}
    make = native.llvm_lambdify

    def timed(*arguments, **keywords):
        clock = time.process_time()
        made = make(*arguments, **keywords)
        spent["llvm"] += time.process_time() - clock
        spent["functions"] += 1
        return made

    evaluate.llvm_lambdify = native.llvm_lambdify = timed
    system = lg.examples.get(model)()
    clock = time.process_time()
    lg.simulate(system, t_span=t_end)
    return {"simulate": time.process_time() - clock, **spent}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("model", help="a built-in example (whipple_bicycle)")
    parser.add_argument("--t-end", type=float, default=1.0)
    parser.add_argument("--repeat", type=int, default=3, help="rounds (3)")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.model, args.t_end)))
        return 0
    folder = tempfile.mkdtemp(prefix="llvm-kept-")
    command = [sys.executable, __file__, args.model, "--t-end", str(args.t_end), "--worker"]

    def run(kept: bool) -> dict[str, float]:
        env = dict(os.environ, XDG_CACHE_HOME=folder, LAGRANGIAN_LLVM_CACHE="1" if kept else "0")
        done = subprocess.run(command, capture_output=True, text=True, env=env, check=True)
        return json.loads(done.stdout.strip().splitlines()[-1])

    run(True)  # fills the cache folder
    rounds: dict[bool, list[dict[str, float]]] = {True: [], False: []}
    for _ in range(args.repeat):
        for kept in (True, False):
            rounds[kept].append(run(kept))
    print(
        f"python benchmarks/llvm_kept.py {args.model} --t-end {args.t_end:g} --repeat {args.repeat}"
    )
    print("| LLVM compilations | simulate CPU s (median) | of which LLVM functions s | functions |")
    print("|---|---:|---:|---:|")
    for kept, label in ((True, "kept on disk"), (False, "compiled again")):
        runs = rounds[kept]
        total = statistics.median(r["simulate"] for r in runs)
        llvm = statistics.median(r["llvm"] for r in runs)
        print(f"| {label} | {total:.2f} | {llvm:.3f} | {int(runs[0]['functions'])} |")
    print(f"\n1-minute load average at the end: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
