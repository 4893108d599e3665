"""The build's one addition to pyproject.toml: the modules of ``lagrangian.compiled.COMPILED``
compiled from their Python source with Cython, where Cython and a C compiler are at hand.

Each becomes an optional extension (a failed compile leaves that module to run as Python, and
the install goes on) kept under ``lagrangian/_compiled/`` with the digest of its source in its
name; ``lagrangian.compiled`` loads it only while the source still has that digest.  Cython
is named in ``[build-system] requires``; without it (a build with no isolation, say) nothing
is compiled.  ``LAGRANGIAN_PURE_PYTHON=1`` compiles nothing.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

from setuptools import Extension, setup

HERE = Path(__file__).parent
SOURCE = HERE / "src"
#: Cython's directives: Python 3 semantics, and the annotations left as documentation (a
#: parameter annotated ``dict`` must still accept a defaultdict, as in Python); the doctests
#: are collected from the source, not again from a table in the binary.
DIRECTIVES = {"language_level": 3, "annotation_typing": False, "autotestdict": False}


def _compiled_module():  # type: ignore[no-untyped-def]
    """``lagrangian/compiled.py`` loaded on its own (the package's dependencies may not be
    installed while it builds)."""
    spec = importlib.util.spec_from_file_location(
        "_lagrangian_compiled", SOURCE / "lagrangian" / "compiled.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def extensions() -> list[Extension]:
    """The optional extensions of the compiled modules (none without Cython)."""
    compiled = _compiled_module()
    if compiled.pure_python():
        return []
    try:
        from Cython.Build import cythonize
    except ImportError:
        return []
    out = []
    for module in compiled.COMPILED:
        source = SOURCE.joinpath(*module.split(".")).with_suffix(".py")
        # the C source is generated under the module's own name (its init function, its
        # classes' __module__), then built under the name that keeps it apart from the source
        [generated] = cythonize(
            [Extension(module, [str(source.relative_to(HERE))])],
            compiler_directives=DIRECTIVES,
            build_dir="build/cython",
            quiet=True,
        )
        stem = compiled.binary_stem(module, source.read_bytes())
        out.append(Extension(f"lagrangian._compiled.{stem}", generated.sources, optional=True))
    return out


setup(ext_modules=extensions())
