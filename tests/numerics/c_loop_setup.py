"""What the numerics tests share: a run on SciPy's solvers to compare the C loop with, and a
model SymEngine cannot compile."""

from __future__ import annotations

from typing import Any

import lagrangian as lg
from lagrangian.numerics.fast import c_build

#: A one-sided spring: SymEngine has no Heaviside to compile, the SymPy form rewrites it.
STOP = """
name: one-sided stop
coordinates: [x]
parameters: {m: 1.0, k: 4.0, K: 100.0}
kinetic: m*x_dot**2/2
potential: k*x**2/2 + K*Heaviside(x - 1)*(x - 1)**2/2
"""


def scipy_path(*arguments: Any, **keywords: Any) -> lg.Trajectory:
    """lg.simulate on SciPy's solvers: the C loop switched off, as on a machine without a C
    compiler."""
    original = c_build.find_compiler
    c_build.find_compiler = lambda: None
    c_build.loop_library.cache_clear()
    try:
        return lg.simulate(*arguments, **keywords)
    finally:
        c_build.find_compiler = original
        c_build.loop_library.cache_clear()
