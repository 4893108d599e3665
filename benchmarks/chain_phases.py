"""CPU seconds of each phase of deriving a long chain (the System built first, untimed):
the terms in SymEngine, the size check, M and the forcing converted to SymPy; and of
analyzing and exporting it (the derivation first, untimed).

    PYTHONPATH=src python benchmarks/chain_phases.py particles 200
    PYTHONPATH=src python benchmarks/chain_phases.py rods 200
    PYTHONPATH=src python benchmarks/chain_phases.py particles 100 analyze
    PYTHONPATH=src python benchmarks/chain_phases.py particles 100 export c

CPU time (``time.process_time``), the steadier measure on a shared machine; compare two
versions by pointing PYTHONPATH at each in turn.  ``analyze`` prints the report's parts
that failed (each within its share of the time limit) and the CPU seconds; ``export``
prints the size of the files written.
"""

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
    elif phase == "analyze":
        analyze_phase(kind, n, system)
    elif phase == "export":
        export_phase(kind, n, system, argv[3] if len(argv) > 3 else "c")
    else:
        raise SystemExit(f"phase {phase!r}: choose derive, analyze or export")


if __name__ == "__main__":
    main(sys.argv[1:])
