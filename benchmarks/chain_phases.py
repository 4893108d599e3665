"""CPU seconds of each phase of deriving a long chain (the System built first, untimed):
the terms in SymEngine, the size check, M and the forcing converted to SymPy (the size check
counted while converting where the source tree does so: ``check`` is then 0); and of
analyzing and exporting it (the derivation first, untimed).

    PYTHONPATH=src python benchmarks/chain_phases.py particles 200
    PYTHONPATH=src python benchmarks/chain_phases.py rods 200
    PYTHONPATH=src python benchmarks/chain_phases.py particles 100 analyze
    PYTHONPATH=src python benchmarks/chain_phases.py particles 100 export c
    PYTHONPATH=src python benchmarks/chain_phases.py particles 200 whole
    python benchmarks/chain_phases.py --before /work/main/src --ns 50 100 200 --repeat 3

CPU time (``time.process_time``), the steadier measure on a shared machine; compare two
versions by pointing PYTHONPATH at each in turn.  ``whole`` is ``lg.derive`` as a user calls it
(the System built first, untimed).  ``--before SRC`` runs ``whole`` and the derivation's
phases in fresh processes, this checkout's ``src`` and ``SRC`` one after the other for each
chain, size and round (a load that comes and goes falls on both alike), and prints the
median CPU seconds of each and after / before.  ``analyze`` prints the report's parts
that failed (each within its share of the time limit) and the CPU seconds; ``export``
prints the size of the files written.
"""

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import derive as bd
import lagrangian as lg
from lagrangian.derivation import lagrange as L
from lagrangian.derivation.terms import euler_lagrange_terms

c = time.process_time


def derive_phases(kind: str, n: int, system: lg.System) -> None:
    t0 = c()
    terms = euler_lagrange_terms(system)
    t1 = c()
    if hasattr(L, "converted_mass_matrix"):  # the size check counted while converting
        t2 = c()
        L.converted_mass_matrix(terms)
        t3 = c()
        L.converted_forcing(terms)
    else:  # a separate size check first (source trees before it was counted while converting)
        L._check_sizes(terms)
        t2 = c()
        terms.view.symmetric_matrix(terms.mass)
        t3 = c()
        terms.view.vector(terms.forcing)
    t4 = c()
    print(
        f"{kind} {n}: terms {t1 - t0:.2f} check {t2 - t1:.2f} M->sympy {t3 - t2:.2f} "
        f"f->sympy {t4 - t3:.2f} total {t4 - t0:.2f}"
    )


def whole_phase(kind: str, n: int, system: lg.System) -> None:
    t0 = c()
    lg.derive(system)
    print(f"{kind} {n}: whole {c() - t0:.2f}")


def analyze_phase(kind: str, n: int, system: lg.System) -> None:
    t0 = c()
    eom = lg.derive(system)
    t1 = c()
    report = lg.analyze(eom)
    t2 = c()
    failed = ", ".join(f.part for f in report.failures) or "none"
    print(f"{kind} {n}: derive {t1 - t0:.2f} analyze {t2 - t1:.2f} (failed parts: {failed})")


def export_phase(kind: str, n: int, system: lg.System, language: str) -> None:
    t0 = c()
    eom = lg.derive(system)
    t1 = c()
    files = lg.export(eom, language)
    t2 = c()
    chars = sum(len(text) for text in files.values())
    print(f"{kind} {n}: derive {t1 - t0:.2f} export {language} {t2 - t1:.2f} ({chars} characters)")


def main(argv: list[str]) -> None:
    kind, n = argv[0], int(argv[1])
    build = {"particles": lg.examples.n_link_pendulum, "rods": bd.rod_chain}[kind]
    system = build(n)
    phase = argv[2] if len(argv) > 2 else "derive"
    if phase == "derive":
        derive_phases(kind, n, system)
    elif phase == "whole":
        whole_phase(kind, n, system)
    elif phase == "analyze":
        analyze_phase(kind, n, system)
    elif phase == "export":
        export_phase(kind, n, system, argv[3] if len(argv) > 3 else "c")
    else:
        raise SystemExit(f"phase {phase!r}: choose derive, whole, analyze or export")


def _fresh(src: str, kind: str, n: int, phase: str) -> dict[str, float]:
    """The CPU seconds a fresh process running this script with ``src`` prints, by name."""
    printed = subprocess.run(
        [sys.executable, __file__, kind, str(n), phase],
        env={**os.environ, "PYTHONPATH": str(Path(src).resolve())},
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    words = printed.split(":", 1)[1].split()
    return {words[i]: float(words[i + 1]) for i in range(0, len(words) - 1, 2)}


def compare(before: str, ns: list[int], repeat: int) -> None:
    """``whole`` and the phases of this checkout (after) and ``before``, alternately."""
    after = str(Path(__file__).resolve().parent.parent / "src")
    runs: dict[tuple[str, int, str], list[dict[str, float]]] = {}
    for _ in range(repeat):
        for kind in ("particles", "rods"):
            for n in ns:
                for label, src in (("before", before), ("after", after)):
                    for phase in ("whole", "derive"):
                        found = _fresh(src, kind, n, phase)
                        runs.setdefault((kind, n, label), []).append(found)
                        print(f"{label} {kind} {n} {phase}: {found}", file=sys.stderr)
    print("| chain | n | before whole s | after whole s | after / before | after phases s |")
    print("|---|---:|---:|---:|---:|---|")
    for kind in ("particles", "rods"):
        for n in ns:
            medians = {}
            for label in ("before", "after"):
                found = runs[(kind, n, label)]
                names = {name for f in found for name in f}
                medians[label] = {
                    name: statistics.median(f[name] for f in found if name in f) for name in names
                }
            b, a = medians["before"]["whole"], medians["after"]["whole"]
            phases = ", ".join(
                f"{name} {medians['after'][name]:.2f}"
                for name in ("terms", "check", "M->sympy", "f->sympy")
            )
            print(f"| {kind} | {n} | {b:.2f} | {a:.2f} | {a / b:.2f} | {phases} |")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--before"]:
        parser = argparse.ArgumentParser()
        parser.add_argument("--before", required=True, help="the src directory to compare with")
        parser.add_argument("--ns", type=int, nargs="+", default=[50, 100, 200])
        parser.add_argument("--repeat", type=int, default=3)
        options = parser.parse_args()
        compare(options.before, options.ns, options.repeat)
    else:
        main(sys.argv[1:])
