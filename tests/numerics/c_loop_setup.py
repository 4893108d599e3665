"""What the C loop's tests share: a run on SciPy's solvers to compare the loop with."""

from __future__ import annotations

from typing import Any

import lagrangian as lg
from lagrangian.numerics.fast import c_build


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
