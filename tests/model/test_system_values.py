"""A System is a value: its mappings are read-only, it survives pickling, and the caches keyed
by identity behave as documented (symbolic/frozen.py, symbolic/caches.py)."""

from __future__ import annotations

import gc
import pickle
import weakref

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.symbolic.caches import RecentCache
from lagrangian.symbolic.frozen import FrozenMapping, frozen


def pendulum() -> lg.System:
    theta, m, g, l = sp.symbols("theta m g l")
    return lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, l: 1.0},
        particles=[lg.Particle("bob", m, (l * sp.sin(theta), -l * sp.cos(theta)))],
        gravity=(0, -g),
        generalized_forces={theta: 0},
        initial={"theta": 0.1},
        simulation={"t_end": 2.0},
    )


@pytest.mark.parametrize("field", ["parameters", "generalized_forces", "initial", "simulation"])
def test_every_mapping_of_a_system_is_read_only(field: str) -> None:
    system = pendulum()
    mapping = getattr(system, field)
    key = next(iter(mapping))
    with pytest.raises(TypeError, match="does not support item assignment"):
        mapping[key] = 1
    with pytest.raises(AttributeError):
        mapping.update({key: 1})  # type: ignore[attr-defined]


def test_the_system_mappings_keep_their_values() -> None:
    system = pendulum()
    m = sp.Symbol("m")
    assert system.parameters[m] == 1.0 and dict(system.simulation) == {"t_end": 2.0}
    assert system.with_parameters({"m": 2.0}).parameters[m] == 2.0
    assert system.parameters[m] == 1.0  # the original is unchanged


def test_a_system_survives_pickling() -> None:
    system = pendulum()
    copy = pickle.loads(pickle.dumps(system))
    assert copy == system and isinstance(copy.parameters, FrozenMapping)


def test_a_frozen_mapping_compares_hashes_and_prints_as_a_value() -> None:
    mapping = FrozenMapping({"a": 1, "b": 2})
    assert mapping == {"b": 2, "a": 1}
    assert {"a": 1, "b": 2} == mapping  # noqa: SIM300 -- the dict first: the reflected test
    assert mapping != {"a": 1} and mapping != [("a", 1), ("b", 2)]
    assert hash(mapping) == hash(FrozenMapping([("b", 2), ("a", 1)]))
    assert repr(mapping) == "FrozenMapping({'a': 1, 'b': 2})"
    assert frozen(mapping) is mapping and frozen({"a": 1}) == {"a": 1}
    with pytest.raises(TypeError, match="does not support item deletion"):
        del mapping["a"]  # type: ignore[attr-defined]


def test_a_frozen_mapping_owns_its_items() -> None:
    source = {"a": 1}
    mapping = FrozenMapping(source)
    source["a"] = 2
    assert mapping["a"] == 1


def test_the_recent_cache_keeps_the_last_keys_by_identity() -> None:
    calls: list[list[int]] = []

    def compute(key: list[int]) -> int:
        calls.append(key)
        return len(calls)

    cache: RecentCache[list[int], int] = RecentCache(2)
    a, b, c = [1], [1], [1]  # equal by value, distinct objects
    assert [cache.get(a, compute), cache.get(b, compute), cache.get(a, compute)] == [1, 2, 1]
    assert cache.get(c, compute) == 3  # evicts b, the least recently used
    assert cache.get(b, compute) == 4 and len(cache) == 2
    cache.clear()
    assert len(cache) == 0


def test_the_recent_cache_holds_its_keys_until_they_are_pushed_out() -> None:
    class Key:
        pass

    cache: RecentCache[Key, int] = RecentCache(1)
    key = Key()
    alive = weakref.ref(key)
    cache.get(key, lambda _k: 0)
    del key
    gc.collect()
    assert alive() is not None  # held: its id cannot be reused while cached
    cache.get(Key(), lambda _k: 1)
    gc.collect()
    assert alive() is None


@pytest.mark.parametrize(
    "value", [9.81, 0.1, 1 / 3, -2.5, 0.0, -0.0, 5e-324, 1.7976931348623157e308, 1e-300]
)
def test_a_float_default_is_the_double_sympy_reads_it_as(value: float) -> None:
    """A parameter's float default is kept as float(sp.Float(value)) gives it (one zero,
    no sign), without forming the SymPy number."""
    theta, m = sp.symbols("theta m")
    system = lg.System(coordinates=[theta], parameters={m: value}, kinetic=m * theta**2)
    kept, read = system.parameters[m], float(sp.Float(value))
    assert kept == read and str(kept) == str(read)


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_a_float_default_that_is_not_finite_is_refused(value: float) -> None:
    theta, m = sp.symbols("theta m")
    with pytest.raises(lg.ModelError, match=r"parameters\.m: value .* is not a real number"):
        lg.System(coordinates=[theta], parameters={m: value}, kinetic=m * theta**2)
