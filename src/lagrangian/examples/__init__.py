"""Built-in systems: the classic worked examples of analytical mechanics, shipped as model files
(``examples/models/NAME.yaml``), plus systems built in Python to a size (:data:`SCALABLE`:
the n-link pendulum, the gas of hard disks).

:data:`CATALOG` maps every example name to a function returning its System, and
``lagrangian.examples.NAME()`` works for each; :func:`model_text` gives the model file itself.
:data:`BENCHMARKS` holds the field's benchmarks (the Whipple bicycle), reached the same way.

>>> import lagrangian as lg
>>> lg.examples.simple_pendulum().coordinates
(theta,)
"""

from __future__ import annotations

import difflib
from collections.abc import Callable
from functools import cache
from importlib.resources import files
from typing import Any

from lagrangian.errors import ModelError
from lagrangian.examples.gas import hard_disk_gas
from lagrangian.examples.scalable import n_link_pendulum
from lagrangian.io import loads
from lagrangian.model import System

MODELS = files("lagrangian.examples").joinpath("models")


def model_text(name: str) -> str:
    """The model file of example ``name`` (YAML, with its reference equations as comments)."""
    get(name)  # a clear error for an unknown name
    resource = MODELS.joinpath(f"{name}.yaml")
    if not resource.is_file():
        raise ModelError(
            f"The example {name!r} is built in Python (it takes a size), so it has no model file."
        )
    return resource.read_text(encoding="utf-8")


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


#: The examples built in Python to a size (``NAME:SIZE`` on the command line) -> the largest
#: size: a chain's links, a gas's disks (n disks have n (n - 1) / 2 contacts).
SCALABLE: dict[str, int] = {"n_link_pendulum": 200, "hard_disk_gas": 100}


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


__all__ = ["BENCHMARKS", "CATALOG", "SCALABLE", "describe", "get", "model_text", "names", *CATALOG]
