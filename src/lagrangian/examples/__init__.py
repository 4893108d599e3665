"""Built-in systems: the classic worked examples of analytical mechanics, shipped as model files
(``examples/models/NAME.yaml``), plus systems built in Python to a size (:data:`SCALABLE`:
the n-link pendulum, the gas of hard disks).

:data:`CATALOG` maps every example name to a function returning its System, and
``lagrangian.examples.NAME()`` works for each; :func:`model_text` gives the model file itself
(a scalable example's written from the System it builds, at its default size or the one asked).
:data:`BENCHMARKS` holds the field's benchmarks (the Whipple bicycle), reached the same way.

>>> import lagrangian as lg
>>> lg.examples.simple_pendulum().coordinates
(theta,)
"""

from __future__ import annotations

import difflib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache, lru_cache
from importlib.resources import files
from typing import Any

from lagrangian.errors import ModelError
from lagrangian.examples.gas import hard_disk_gas
from lagrangian.examples.scalable import n_link_pendulum
from lagrangian.io import loads
from lagrangian.io.dump import dumps
from lagrangian.model import System

MODELS = files("lagrangian.examples").joinpath("models")


@dataclass(frozen=True)
class Size:
    """The size a scalable example takes: what it ``counts`` (links, disks), its ``default``
    and the ``largest`` it is built with."""

    counts: str
    default: int
    largest: int


#: The examples built in Python to a size (``NAME:SIZE`` on the command line): a chain's
#: links, a gas's disks (n disks have n (n - 1) / 2 contacts).
SIZES: dict[str, Size] = {
    "n_link_pendulum": Size("links", 3, 200),
    "hard_disk_gas": Size("disks", 4, 100),
}
#: Scalable example -> its largest size.
SCALABLE: dict[str, int] = {name: size.largest for name, size in SIZES.items()}


def model_text(name: str, size: int | None = None) -> str:
    """The model file of example ``name`` (YAML, with its reference equations as comments).

    A scalable example (:data:`SIZES`) is written from the System it builds with ``size``
    (its default when None), headed by its description and how to ask for another size.

    >>> model_text("hard_disk_gas", 2).splitlines()[0]
    '# Gas of n elastic hard disks in a square box: every wall and disk contact unilateral, e = 1.'
    """
    get(name)  # a clear error for an unknown name
    scalable = SIZES.get(name)
    if scalable is None:
        if size is not None:
            raise ModelError(f"The example {name!r} has no size; {', '.join(SIZES)} take one.")
        return MODELS.joinpath(f"{name}.yaml").read_text(encoding="utf-8")
    chosen = scalable.default if size is None else size
    if not 1 <= chosen <= scalable.largest:
        raise ModelError(
            f"{name}: {chosen} {scalable.counts}; give a whole number from 1 to {scalable.largest}."
        )
    return _written(name, chosen)


@lru_cache(maxsize=16)
def _written(name: str, size: int) -> str:
    """The model file of the scalable example ``name`` built with ``size``."""
    counts = SIZES[name].counts
    header = (
        f"{describe(name)}\n"
        f"This file is the example built in Python with {size} {counts}, written as a model\n"
        f"file. Another number N of {counts}: {name}:N on the command line,\n"
        f'lagrangian.examples.model_text("{name}", N) in Python, the field beside the\n'
        "playground's example menu."
    )
    return dumps(CATALOG[name](size), header=header)


def _header(text: str) -> str:
    """The leading comment block of a model file, without the '# ' marks."""
    lines = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        lines.append(line[2:] if line.startswith("# ") else line[1:])
    return "\n".join(lines)


def _file_example(name: str) -> Callable[[], System]:
    @cache
    def build() -> System:
        return loads(model_text(name), format="yaml", source=f"examples/{name}.yaml")

    build.__name__ = build.__qualname__ = name
    build.__doc__ = _header(MODELS.joinpath(f"{name}.yaml").read_text(encoding="utf-8"))
    return build


#: The field's benchmarks: model files whose derivation takes minutes, so they are kept out
#: of :data:`CATALOG` (which every example-wide check walks) and reached by name.
BENCHMARK_NAMES = ("whipple_bicycle",)


def _catalog(benchmarks: bool = False) -> dict[str, Callable[..., System]]:
    catalog: dict[str, Callable[..., System]] = (
        {} if benchmarks else {"n_link_pendulum": n_link_pendulum, "hard_disk_gas": hard_disk_gas}
    )
    for resource in MODELS.iterdir():
        if resource.name.endswith(".yaml"):
            name = resource.name.removesuffix(".yaml")
            if (name in BENCHMARK_NAMES) == benchmarks:
                catalog[name] = _file_example(name)
    return dict(sorted(catalog.items()))


#: Example name -> function building the System (scalable ones take a size argument).
CATALOG: dict[str, Callable[..., System]] = _catalog()
#: Benchmark name -> function building the System (``examples/NAME`` on the command line).
BENCHMARKS: dict[str, Callable[..., System]] = _catalog(benchmarks=True)


def names() -> list[str]:
    """Every example's name, sorted."""
    return sorted(CATALOG)


def describe(name: str) -> str:
    """The one-line description of an example (the first line of its docstring)."""
    return (get(name).__doc__ or "").strip().splitlines()[0]


def get(name: str) -> Callable[..., System]:
    """The function building example ``name``."""
    try:
        return CATALOG[name] if name in CATALOG else BENCHMARKS[name]
    except KeyError:
        close = difflib.get_close_matches(name, [*CATALOG, *BENCHMARKS], n=3)
        hint = f" Did you mean {', '.join(close)}?" if close else ""
        raise ModelError(
            f"There is no example named {name!r}.{hint} `lagrangian examples` lists them "
            "(in Python, lagrangian.examples.names())."
        ) from None


def __getattr__(name: str) -> Any:
    if name in CATALOG or name in BENCHMARKS:
        return get(name)
    raise AttributeError(f"module 'lagrangian.examples' has no attribute {name!r}")


__all__ = [
    "BENCHMARKS",
    "CATALOG",
    "SCALABLE",
    "SIZES",
    "Size",
    "describe",
    "get",
    "model_text",
    "names",
    *CATALOG,
]
