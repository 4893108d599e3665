"""CPU seconds of building a long chain's System, and of loading it from a model file.

    python benchmarks/chain_build.py --before /tmp/base/src --n 200 --rounds 7

Three ways of writing the n-link pendulum (``benchmarks/derive.py``'s chain workers):
``particles`` (``lg.examples.n_link_pendulum``), ``rods`` (``rod_chain``) and ``cartesian``
(``cartesian_chain``, each rod a holonomic constraint).  ``build`` times the builder as the
derive benchmark does; of it, ``System`` is the System's own normalization and validation
(``normalize_system``).  ``load`` times ``lg.load`` of the chain written by ``lg.dumps``
(YAML, and JSON for the particles); of it, ``compose`` is reading the file's tree and
``parse`` reading its expressions.  Each measure runs in a fresh process, this checkout's
``src`` and ``--before`` one after the other, alternating which goes first; the table gives
the medians.
"""

from __future__ import annotations

import argparse
import importlib
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
SRC = HERE.parent / "src"
BUILDS = ("particles", "rods", "cartesian")
FILES = (("particles", "yaml"), ("particles", "json"), ("rods", "yaml"), ("cartesian", "yaml"))


def builder(kind: str):
    import derive as bench
    import lagrangian as lg

    return {
        "particles": lg.examples.n_link_pendulum,
        "rods": bench.rod_chain,
        "cartesian": bench.cartesian_chain,
    }[kind]


def timed(module, name: str, spent: dict[str, float], key: str) -> None:
    """Wrap ``module.name`` so that its CPU seconds add up in ``spent[key]``."""
    function = getattr(module, name)

    def wrapper(*args, **kwargs):
        start = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            spent[key] = spent.get(key, 0.0) + time.process_time() - start

    setattr(module, name, wrapper)


def worker(src: str, task: str, what: str, n: int) -> None:
    """Time one build or load in this process; print its seconds as JSON."""
    sys.path[:0] = [src, str(HERE)]
    import derive as bench
    import lagrangian as lg

    lg.System, lg.RigidBody, lg.Holonomic, lg.load  # noqa: B018 (lazy imports, untimed)
    spent: dict[str, float] = {}
    timed(importlib.import_module("lagrangian.model.system"), "normalize_system", spent, "System")
    load = importlib.import_module("lagrangian.io.load")
    for reader in ("read_yaml", "read_json"):
        timed(load, reader, spent, "compose")
    timed(importlib.import_module("lagrangian.io.reader"), "parse_expression", spent, "parse")
    bench.warm_up_sympy()
    start = time.process_time()
    if task == "build":
        builder(what)(n)
    else:
        lg.load(what)
    spent["total"] = time.process_time() - start
    print(json.dumps(spent))


def write_files(n: int, folder: Path) -> dict[str, Path]:
    """The chains of ``FILES`` written as model files (with this checkout)."""
    sys.path[:0] = [str(SRC), str(HERE)]
    from lagrangian.io.dump import dumps

    paths = {}
    for kind, form in FILES:
        path = folder / f"{kind}-{n}.{form}"
        path.write_text(dumps(builder(kind)(n), form))
        paths[f"{kind}.{form}"] = path
    return paths


def run(src: str, task: str, what: str, n: int) -> dict[str, float]:
    command = [sys.executable, __file__, "--worker", src, task, what, "--n", str(n)]
    return json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", help="the source tree to compare with")
    parser.add_argument("--n", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument(
        "--worker", nargs=3, metavar=("SRC", "TASK", "WHAT"), help=argparse.SUPPRESS
    )
    args = parser.parse_args()
    if args.worker:
        worker(*args.worker, args.n)
        return
    trees = {"after": str(SRC), **({"before": args.before} if args.before else {})}
    with tempfile.TemporaryDirectory() as folder:
        paths = write_files(args.n, Path(folder))
        cases = [("build", kind, kind) for kind in BUILDS]
        cases += [("load", name, str(path)) for name, path in paths.items()]
        found: dict[tuple[str, str, str], list[dict[str, float]]] = {}
        for r in range(args.rounds):
            order = list(trees) if r % 2 == 0 else list(reversed(trees))
            for task, name, what in cases:
                for tree in order:
                    found.setdefault((task, name, tree), []).append(
                        run(trees[tree], task, what, args.n)
                    )
    print(f"n = {args.n}, {args.rounds} rounds, CPU seconds, medians")
    print("| task | chain | tree | total | System | compose | parse |")
    print("|---|---|---|---:|---:|---:|---:|")
    for (task, name, tree), runs in found.items():
        cells = [
            f"{statistics.median(run.get(key, 0.0) for run in runs):.3f}"
            for key in ("total", "System", "compose", "parse")
        ]
        print(f"| {task} | {name} | {tree} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
