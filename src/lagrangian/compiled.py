"""Modules compiled to C at install, run in place of their Python source while they match it.

The trigonometric algebra of the 3-D derivation (:mod:`lagrangian.derivation.trig_polynomial`)
works term by term: deriving the Whipple bicycle takes some 50,000 additions and products of
coefficients, each a few dict operations, and the interpreter's overhead per operation is
most of their cost.  ``pip install`` compiles the modules of :data:`COMPILED` from their
unchanged Python source with Cython when Cython and a C compiler are at hand (``setup.py``;
where either is missing the install goes on and the modules run as Python, with the same
results).  A compiled module is kept as ``lagrangian/_compiled/<name>__<digest><suffix>``: the
digest is that of the Python source it was compiled from, and :class:`CompiledFinder` loads it
only while the source beside it has the same digest.  A source edited since (a checkout, a
change not compiled again) runs as Python: never a stale binary.  ``LAGRANGIAN_PURE_PYTHON=1``
in the environment runs every module as Python (and makes ``pip install`` compile none).

This module imports nothing of lagrangian's: ``setup.py`` loads it on its own, for the list
and the file names.

>>> binary_stem("lagrangian.derivation.trig_polynomial", b"")
'derivation__trig_polynomial__e3b0c44298fc1c14'
>>> sorted(modules()) == sorted(COMPILED)
True
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence
    from types import ModuleType

# ``import lagrangian`` installs the finder, and the command line starts at once: no hashlib
# or pathlib until a compiled module is looked for.

#: The modules compiled at install: the term-by-term polynomial arithmetic of the 3-D
#: derivation, and the walks over expressions whose own Python work (loops, dict lookups,
#: calls) is a large part of their time: collecting by monomial, the conversion to SymPy
#: and its canonical order, the safe parser, the rolling contacts, the Pfaffian forms.
#: (The modules that mostly call SymPy and SymEngine gain nothing: their time is spent
#: inside those libraries.)  Cython computes with C integers where both operands are C's:
#: ``1 << len(bits)`` wraps past 63 bits.  None of these modules shifts or raises a length
#: or an index; the kinetic form's bit sets of holders (a chain's points) do, so it stays
#: Python.
COMPILED = (
    "lagrangian.derivation.trig_polynomial",
    "lagrangian.derivation.collect",
    "lagrangian.symbolic.sympy_view",
    "lagrangian.symbolic.canonical",
    "lagrangian.symbolic.native",
    "lagrangian.symbolic.expressions",
    "lagrangian.model.contact",
    "lagrangian.constraints.pfaffian",
)
#: The folder of the compiled modules, inside the package.
FOLDER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_compiled")
#: The environment variable that runs every module as Python.
PURE_PYTHON = "LAGRANGIAN_PURE_PYTHON"
#: Hex digits of the source's SHA-256 in a compiled module's file name.
DIGEST_DIGITS = 16


def binary_stem(module: str, source: bytes) -> str:
    """The file name, without the platform's extension suffix, of ``module`` compiled from
    ``source`` (the bytes of its Python file)."""
    import hashlib

    digest = hashlib.sha256(source).hexdigest()[:DIGEST_DIGITS]
    return f"{module.removeprefix('lagrangian.').replace('.', '__')}__{digest}"


def source_path(module: str) -> str:
    """The Python source of ``module`` (one of :data:`COMPILED`) in this package."""
    parts = module.split(".")[1:]
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), *parts) + ".py"


def pure_python() -> bool:
    """Whether the environment asks for every module to run as Python."""
    return os.environ.get(PURE_PYTHON, "") not in ("", "0")


def compiled_binary(
    module: str,
    folder: str | os.PathLike[str] = FOLDER,
    source: str | os.PathLike[str] | None = None,
) -> str | None:
    """The path of the compiled file of ``module`` that matches its Python source now, or
    None (not compiled, compiled from another version of the source, or pure Python asked
    for)."""
    if pure_python() or module not in COMPILED:
        return None
    try:
        with open(source or source_path(module), "rb") as file:
            text = file.read()
    except OSError:  # no source to vouch for the binary
        return None
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        binary = os.path.join(folder, binary_stem(module, text) + suffix)
        if os.path.isfile(binary):
            return binary
    return None


class CompiledLoader(importlib.machinery.ExtensionFileLoader):
    """Loads a compiled module, and names the Python source it was compiled from (the same
    bytes, by its digest) as the module's ``__file__``: tracebacks, ``inspect.getsource`` and
    the doctests find that source; ``__spec__.origin`` stays the binary."""

    def __init__(self, fullname: str, binary: str, source: str) -> None:
        super().__init__(fullname, binary)
        self.source = source

    def exec_module(self, module: ModuleType) -> None:
        super().exec_module(module)
        module.__file__ = self.source


class CompiledFinder:
    """Finds the modules of :data:`COMPILED` in their compiled form (see the module's
    docstring); every other module, and a compiled one whose source changed, is left to the
    import system's usual finders."""

    @staticmethod
    def find_spec(
        fullname: str, path: Sequence[str] | None = None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname not in COMPILED:
            return None
        binary = compiled_binary(fullname)
        if binary is None:
            return None
        loader = CompiledLoader(fullname, binary, source_path(fullname))
        return importlib.util.spec_from_file_location(fullname, binary, loader=loader)


def install() -> None:
    """Put :class:`CompiledFinder` first among the import system's finders (once)."""
    if not any(isinstance(finder, CompiledFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, CompiledFinder())


def modules() -> dict[str, str]:
    """How each module of :data:`COMPILED` runs in this process, or would once imported:
    ``"compiled"`` or ``"python"``."""
    forms = {}
    for module in COMPILED:
        loaded = sys.modules.get(module)
        if loaded is not None:
            compiled = isinstance(getattr(loaded, "__loader__", None), CompiledLoader)
        else:
            compiled = compiled_binary(module) is not None
        forms[module] = "compiled" if compiled else "python"
    return forms


__all__ = [
    "COMPILED",
    "FOLDER",
    "PURE_PYTHON",
    "CompiledFinder",
    "CompiledLoader",
    "binary_stem",
    "compiled_binary",
    "install",
    "modules",
    "pure_python",
    "source_path",
]
