"""CPU seconds of each phase of deriving a long chain (the System built first, untimed):
the terms in SymEngine, the size check, M and the forcing converted to SymPy.

    PYTHONPATH=src python benchmarks/chain_phases.py particles 200
    PYTHONPATH=src python benchmarks/chain_phases.py rods 200

CPU time (``time.process_time``), the steadier measure on a shared machine; compare two
versions by pointing PYTHONPATH at each in turn.
"""

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import derive as bd
import lagrangian as lg
from lagrangian.derivation import lagrange as L
from lagrangian.derivation.terms import euler_lagrange_terms

kind, n = sys.argv[1], int(sys.argv[2])
build = {"particles": lg.examples.n_link_pendulum, "rods": bd.rod_chain}[kind]
system = build(n)
c = time.process_time
t0 = c()
terms = euler_lagrange_terms(system)
m = terms.mass
f = terms.forcing
t1 = c()
L._check_sizes(terms)
t2 = c()
M = terms.view.symmetric_matrix(terms.mass)
t3 = c()
F = terms.view.vector(terms.forcing)
t4 = c()
print(
    f"{kind} {n}: terms {t1 - t0:.2f} check {t2 - t1:.2f} M->sympy {t3 - t2:.2f} "
    f"f->sympy {t4 - t3:.2f} total {t4 - t0:.2f}"
)
