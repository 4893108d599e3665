"""SymEngine's LLVM compilation of expressions, kept on disk once it has cost something.

Every native function of the package (:mod:`~lagrangian.numerics.evaluate`'s NumPy
functions, :mod:`~lagrangian.numerics.fast.native`'s C functions of the loops) is one
``symengine.Lambdify(..., backend="llvm", cse=True)`` made here (:func:`llvm_lambdify`).
Compiling a large right-hand side takes a good part of a second (the Whipple bicycle's, 0.7 s
without LLVM's optimizer), paid again by every process that simulates the same model: each
command-line run.  A compiled function pickles as its object code, which loads in about a
millisecond, so a compilation that took at least :data:`KEEP_AFTER` seconds is kept:

- in the cache folder of the C loop (:func:`~lagrangian.numerics.fast.c_build.cache_folder`,
  ``~/.cache/lagrangian/llvm``), named by a hash of everything the machine code depends on:
  the arguments and expressions as SymEngine prints them, the optimization level,
  SymEngine's version and the processor (LLVM compiles for the host's instruction set);
- written atomically with its SHA-256 beside it, as the C loop's library is; a file whose
  digest does not match, or that does not load, is compiled again (and replaced);
- the folder holds at most :data:`MAX_BYTES`; the files used longest ago go first.

The files are read back with pickle, so they are trusted as the user's own cache folder is
(numba keeps its cache the same way); ``LAGRANGIAN_LLVM_CACHE=0`` keeps nothing and reads
nothing.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> f = llvm_lambdify([x, y], [x * y, sp.sin(x)])
>>> f([2.0, 3.0]).round(6).tolist()
[6.0, 0.909297]
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import pickle
import platform
import time
from collections.abc import Sequence
from functools import cache
from pathlib import Path
from typing import Any

import symengine as se

from lagrangian.numerics.fast.c_build import cache_folder, write_atomically

#: A compilation that took at least this many seconds is kept on disk (below it, the file's
#: name costs as much as the compilation saved).
KEEP_AFTER = 0.05
#: The most the kept compilations may take on disk, in bytes.
MAX_BYTES = 256 * 2**20
#: The errors by which SymEngine says it cannot compile an expression.
CANNOT_COMPILE = (RuntimeError, TypeError, ValueError, NotImplementedError, AttributeError)


def llvm_lambdify(symbols: Sequence[Any], expressions: Sequence[Any], opt_level: int = 3) -> Any:
    """``symengine.Lambdify`` of ``expressions`` (SymPy or SymEngine) in the vector
    ``symbols``, compiled by LLVM at ``opt_level`` with common subexpressions computed once,
    read from disk where it was kept (module docstring); None where SymEngine cannot compile
    them."""
    # SymEngine's CSE names its temporaries x0, x1, ...: a user's x1 would be taken for one,
    # so every argument gets a name no model can have
    renamed = {se.sympify(s): se.Symbol(f"_arg{i}_") for i, s in enumerate(symbols)}
    try:
        # one replacement over a column of every expression: per expression, the map of
        # every argument was converted again (a 200 x 200 mass matrix took half a minute to
        # rename, eight times the column's)
        column = se.DenseMatrix(len(expressions), 1, [se.sympify(e) for e in expressions])
        arguments, outputs = list(renamed.values()), column.xreplace(renamed)
    except CANNOT_COMPILE:
        return None
    path = _kept_path(len(arguments), outputs, opt_level)
    if path is not None:
        kept = _load(path)
        if kept is not None:
            return kept
    started = time.perf_counter()
    try:
        compiled = se.Lambdify(
            arguments, list(outputs), backend="llvm", cse=True, opt_level=opt_level
        )
    except CANNOT_COMPILE:
        return None
    if path is not None and time.perf_counter() - started >= KEEP_AFTER:
        _keep(path, compiled)
    return compiled


def _kept_path(arguments: int, outputs: Any, opt_level: int) -> Path | None:
    """Where the compilation of the column ``outputs`` in ``arguments`` renamed arguments is
    kept; None when nothing is kept."""
    folder = cache_folder()
    if folder is None or os.environ.get("LAGRANGIAN_LLVM_CACHE", "1") == "0":
        return None
    key = hashlib.sha256()
    for part in (_machine(), str(opt_level), str(arguments), str(outputs)):
        key.update(part.encode())
        key.update(b"\0")
    return folder / "llvm" / f"{key.hexdigest()[:32]}.pickle"


@cache
def _machine() -> str:
    """What the machine code depends on besides the expressions: SymEngine's version, the
    platform and the processor's model and instruction-set flags."""
    processor = platform.processor()
    with contextlib.suppress(OSError):
        lines = Path("/proc/cpuinfo").read_text(errors="replace").splitlines()
        wanted = [line for line in lines if line.startswith(("model name", "flags", "Features"))]
        processor = "\n".join(dict.fromkeys(wanted)) or processor  # each line once
    return f"{se.__version__} {platform.system()} {platform.machine()} {processor}"


def _load(path: Path) -> Any:
    """The kept compilation at ``path`` when it is whole (its digest matches); None else."""
    try:
        content = path.read_bytes()
        expected = path.with_name(path.name + ".sha256").read_text().strip()
    except OSError:
        return None
    if hashlib.sha256(content).hexdigest() != expected:
        return None
    try:
        compiled = pickle.loads(content)
    except Exception:  # a file of another SymEngine build: compiled again
        return None
    with contextlib.suppress(OSError):
        os.utime(path)  # used now: the last to go when the folder is trimmed
    return compiled


def _keep(path: Path, compiled: Any) -> None:
    """Write ``compiled`` to ``path`` atomically with its digest, then trim the folder;
    nothing when the folder cannot be written."""
    try:
        content = pickle.dumps(compiled)
    except Exception:  # a build of SymEngine whose functions do not pickle
        return
    with contextlib.suppress(OSError):
        path.parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, content)
        write_atomically(
            path.with_name(path.name + ".sha256"),
            (hashlib.sha256(content).hexdigest() + "\n").encode(),
        )
        _trim(path.parent)


def _trim(folder: Path) -> None:
    """Remove the files used longest ago until the folder holds at most MAX_BYTES."""
    kept = []
    for entry in os.scandir(folder):
        if entry.name.endswith(".pickle"):
            with contextlib.suppress(OSError):
                status = entry.stat()
                kept.append((status.st_mtime, status.st_size, Path(entry.path)))
    total = sum(size for _, size, _ in kept)
    for _, size, path in sorted(kept):
        if total <= MAX_BYTES:
            break
        for name in (path, path.with_name(path.name + ".sha256")):
            with contextlib.suppress(OSError):
                name.unlink()
        total -= size
