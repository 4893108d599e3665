"""A System with its parameters' values put in: what ``derive --substitute`` shows.

Every expression of the description (energies, elements, constraints, transitions, frames)
has the valued parameters replaced by their numbers; the parameters without a value stay
symbols.  Whole numbers are put in as integers (``2``, not ``2.0``), the rest as floats, so
the equations read as a student writes them with the numbers in.

>>> import lagrangian as lg
>>> pendulum = with_values(lg.examples.simple_pendulum().with_parameters({"m": 2}))
>>> pendulum.parameters
FrozenMapping({})
>>> str(lg.derive(pendulum).equations[0])
'2*theta_ddot + 19.62*sin(theta)'
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import sympy as sp

from lagrangian.model.system import System


def with_values(system: System) -> System:
    """``system`` with every parameter that has a value replaced by it (the others kept)."""
    values = {p: _number(v) for p, v in system.parameters.items() if v is not None}
    if not values:
        return system
    changed = {
        f.name: _put(getattr(system, f.name), values)
        for f in dataclasses.fields(system)
        if f.name not in ("parameters", "initial", "simulation", "units", "coordinates")
    }
    kept = {p: v for p, v in system.parameters.items() if p not in values}
    return system.replace(parameters=kept, **changed)


def _number(value: float) -> sp.Number:
    return sp.Integer(int(value)) if float(value).is_integer() else sp.Float(value)


def _put(value: Any, values: Mapping[sp.Symbol, sp.Number]) -> Any:
    """``value`` with the numbers put in, through elements (frozen dataclasses), mappings
    (their values; keys name coordinates) and sequences."""
    if isinstance(value, sp.Basic):
        return value.xreplace(values)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        changes = {
            f.name: _put(getattr(value, f.name), values)
            for f in dataclasses.fields(value)
            if f.init
        }
        return dataclasses.replace(value, **changes)
    if isinstance(value, Mapping):
        return {key: _put(item, values) for key, item in value.items()}
    if isinstance(value, (tuple, list)):
        return type(value)(_put(item, values) for item in value)
    return value
