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
import os
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

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
    sources = {
        module: SOURCE.joinpath(*module.split(".")).with_suffix(".py")
        for module in compiled.COMPILED
    }
    # the C sources are generated under the modules' own names (their init functions, their
    # classes' __module__), then built under the names that keep them apart from the sources
    try:
        generated = cythonize(
            [Extension(module, [str(path.relative_to(HERE))]) for module, path in sources.items()],
            compiler_directives=DIRECTIVES,
            build_dir="build/cython",
            nthreads=os.cpu_count() or 1,
            quiet=True,
        )
    except Exception as error:  # a Cython that cannot read the source: it runs as Python
        print(f"lagrangian: not compiled ({error}); the modules run as Python", file=sys.stderr)
        return []
    out = []
    for ext in generated:
        stem = compiled.binary_stem(ext.name, sources[ext.name].read_bytes())
        out.append(Extension(f"lagrangian._compiled.{stem}", ext.sources, optional=True))
    return out


class BuildSideBySide(build_ext):
    """Compiles the extensions in parallel, one per core (each is a large C file)."""

    def finalize_options(self) -> None:
        super().finalize_options()
        if not self.parallel:
            self.parallel = os.cpu_count() or 1


setup(ext_modules=extensions(), cmdclass={"build_ext": BuildSideBySide})
