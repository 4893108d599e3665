"""The numba-compiled right-hand side of one system, ``rates(t, x, p, matrix, vector, dx)``.

``fast_equations(eom)`` turns the state equations into Python source
(:mod:`lagrangian.numerics.fast.source`) and compiles it with ``numba.njit``, once per
EquationsOfMotion object and process.  It is never cached on disk: it is generated source run
through ``exec``, which numba cannot cache (about 0.5 s for a double pendulum, 1.5 s for ten
links).  The loops take it as a function value, so they are the same for every system.

>>> import lagrangian as lg
>>> fast = fast_equations(lg.derive(lg.examples.simple_pendulum()))  # doctest: +SKIP
>>> fast.state_names  # doctest: +SKIP
('theta', 'theta_dot')
"""

from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from typing import Any

from lagrangian.derivation.eom import EquationsOfMotion
from lagrangian.errors import SimulationError
from lagrangian.model.identity_cache import IdentityCache
from lagrangian.numerics.fast.source import RatesSource, rates_source

INSTALL_HINT = "pip install lagrangian[fast]"

_CACHE: IdentityCache[EquationsOfMotion, FastEquations] = IdentityCache()


def numba_available() -> bool:
    """Whether numba can be imported (without importing it)."""
    return importlib.util.find_spec("numba") is not None


def require_numba(feature: str = "backend='numba'") -> None:
    """Raise SimulationError, with the install command, when numba is not installed."""
    if not numba_available():
        raise SimulationError(
            f"{feature} needs numba, which is not installed: {INSTALL_HINT} "
            "(or use backend='numpy', the default)."
        )


@dataclass(frozen=True)
class FastEquations:
    """The compiled ``rates(t, x, p, matrix, vector, dx) -> ok`` of one system, and its source."""

    source: RatesSource
    rates: Any

    @property
    def coordinates(self) -> tuple[str, ...]:
        return self.source.coordinates

    @property
    def parameters(self) -> tuple[str, ...]:
        return self.source.parameters

    @property
    def state_names(self) -> tuple[str, ...]:
        return self.source.state_names


def fast_equations(eom: EquationsOfMotion) -> FastEquations:
    """The numba-compiled right-hand side of ``eom``, built once per EquationsOfMotion object.

    Raises SimulationError when numba is missing or an expression has no numeric form.
    """
    require_numba()
    return _CACHE.get(eom, _build)


def _build(eom: EquationsOfMotion) -> FastEquations:
    import math

    from numba import njit

    from lagrangian.numerics.fast.linear import solve_linear
    from lagrangian.numerics.fast.loops import RATES

    source = rates_source(eom)
    namespace: dict[str, Any] = {"math": math, "solve_linear": solve_linear}
    exec(compile(source.text, f"<rates of {eom.coordinates}>", "exec"), namespace)
    # called only from the compiled loops: no Python wrapper; x / 0 gives inf or nan (the
    # loops report a state that is no longer finite) instead of raising, which also halves
    # numba's compile time of the long generated function
    options: dict[str, Any] = {"no_cpython_wrapper": True, "error_model": "numpy", "nogil": True}
    return FastEquations(source, njit(RATES, cache=False, **options)(namespace["rates"]))
