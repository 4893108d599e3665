"""One registry of caches: every cache of the package registers itself, and forget_all empties
them all (the derivations, compiled functions, constraint forms and remembered rotations)."""

from __future__ import annotations

import gc

import lagrangian as lg
from lagrangian.numerics.compile import compile_equations
from lagrangian.symbolic import caches
from lagrangian.symbolic.caches import IdentityCache, RecentCache, forget_all


def _sizes() -> dict[str, int]:
    """The size of every registered cache, by where it was made."""
    sized = [c for c in caches._REGISTRY if hasattr(c, "__len__")]
    functions = {
        f"{h.function.__module__}.{h.function.__qualname__}": h.function.cache_info().currsize
        for h in caches._FUNCTIONS
    }
    return {**{f"cache {id(c)}": len(c) for c in sized}, **functions}


def test_forget_all_empties_every_cache_the_package_filled() -> None:
    system = lg.examples.heavy_symmetric_top()  # rotations remembered, derivation cached
    eom = lg.derive(system)
    compile_equations(eom)
    lg.simulate(lg.examples.dumbbell(), t_span=0.1)  # constraint forms compiled
    assert any(_sizes().values())
    emptied = forget_all()
    assert emptied >= 20  # the module-level caches of the package, all registered
    assert not any(_sizes().values()), {k: v for k, v in _sizes().items() if v}
    # the derivation is made afresh, and equal
    again = lg.derive(system)
    assert again is not eom and again.mass_matrix == eom.mass_matrix


def test_a_cache_made_and_dropped_leaves_the_registry() -> None:
    before = len(caches._REGISTRY)
    made = [IdentityCache(), RecentCache(2)]
    assert len(caches._REGISTRY) == before + 2
    del made
    gc.collect()
    assert len(caches._REGISTRY) == before
