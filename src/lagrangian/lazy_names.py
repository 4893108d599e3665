"""Public names that load on first use (PEP 562), for the packages whose ``__init__`` must not
import SymPy, SciPy or Dask: ``import lagrangian`` starts at once, and reading a Trajectory does
not load the integrators.

A package lists where each of its names is defined (its *homes*) and hands its module
``__getattr__`` to :func:`lazy_attribute`.  Imports nothing but :mod:`importlib`, so that any
``__init__`` may use it.

>>> homes = {"sqrt": "math", "pi": "math", "dumps": "json"}
>>> namespace = {}
>>> lazy_attribute(namespace, homes, "example", "sqrt")(16.0)
4.0
>>> sorted(namespace)  # every name of math in the table is bound now, json's not yet
['pi', 'sqrt']
>>> lazy_attribute(namespace, homes, "example", "tau")
Traceback (most recent call last):
...
AttributeError: module 'example' has no attribute 'tau'
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, MutableMapping
from typing import Any


def lazy_attribute(
    namespace: MutableMapping[str, Any], homes: Mapping[str, str], package: str, name: str
) -> Any:
    """The value of ``name``, imported from its home module ``homes[name]``; an
    AttributeError naming ``package`` for a name that is not in ``homes``.

    Every name of ``homes`` that the home module now holds is bound in ``namespace`` (the
    package's ``globals()``), as an eager ``from home import ...`` would: later uses skip
    this function, and a submodule that importing the home has just bound in the package
    under the same name (``action.py`` defining ``action``) gives way to the name itself.
    A name the home module loads lazily itself is bound on its first use, not before.
    """
    home = homes.get(name)
    if home is None:
        raise AttributeError(f"module {package!r} has no attribute {name!r}")
    module = importlib.import_module(home)
    value = getattr(module, name)
    loaded = vars(module)
    namespace.update(
        {
            other: loaded[other]
            for other, where in homes.items()
            if where == home and other in loaded
        }
    )
    namespace[name] = value
    return value
