"""The modules compiled at install (lagrangian.compiled): loaded only while they match their
source, and giving the same equations as the Python source they were compiled from."""

from __future__ import annotations

import importlib
import importlib.machinery
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian import compiled
from lagrangian.examples import BENCHMARKS, CATALOG

MODULE = "lagrangian.derivation.trig_polynomial"
SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]

# Every example's M and forcing (and, with constraints, the constrained form's), written
# exactly: every example is derived in each form, the algebra runs in most (3-D bodies,
# rolling contacts, polar coordinates, the bicycle).
EQUATIONS = """
import json, sys
import sympy as sp
import lagrangian as lg
from lagrangian.examples import BENCHMARKS, CATALOG

def written(system):
    eom = lg.derive(system)
    parts = [eom.mass_matrix, eom.forcing]
    if system.constraints:
        eq = lg.constrained_equations(system)
        parts += [eq.constraint_jacobian, eq.gamma]
    return sp.srepr(tuple(parts))

json.dump({name: written(build()) for name, build in {**CATALOG, **BENCHMARKS}.items()},
          sys.stdout)
"""


def _equations(environment: dict[str, str]) -> dict[str, str]:
    done = subprocess.run(
        [sys.executable, "-c", EQUATIONS],
        capture_output=True,
        text=True,
        env=environment,
        check=True,
    )
    return json.loads(done.stdout)


def test_a_binary_is_used_only_while_its_source_is_unchanged(tmp_path: Path) -> None:
    source = tmp_path / "trig_polynomial.py"
    source.write_text("x = 1\n")
    assert compiled.compiled_binary(MODULE, tmp_path, source) is None  # none compiled
    binary = tmp_path / (compiled.binary_stem(MODULE, source.read_bytes()) + SUFFIX)
    binary.write_bytes(b"")
    assert compiled.compiled_binary(MODULE, tmp_path, source) == str(binary)
    source.write_text("x = 2\n")  # edited since: the binary is another version's
    assert compiled.compiled_binary(MODULE, tmp_path, source) is None


def test_pure_python_is_asked_for_by_the_environment(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    source = tmp_path / "trig_polynomial.py"
    source.write_text("x = 1\n")
    (tmp_path / (compiled.binary_stem(MODULE, source.read_bytes()) + SUFFIX)).write_bytes(b"")
    monkeypatch.setenv(compiled.PURE_PYTHON, "1")
    assert compiled.compiled_binary(MODULE, tmp_path, source) is None
    monkeypatch.setenv(compiled.PURE_PYTHON, "0")
    assert compiled.compiled_binary(MODULE, tmp_path, source) is not None


def test_only_the_listed_modules_are_looked_for() -> None:
    assert "lagrangian.derivation.lagrange" not in compiled.COMPILED
    assert compiled.CompiledFinder.find_spec("lagrangian.derivation.lagrange") is None
    assert compiled.compiled_binary("lagrangian.derivation.lagrange") is None
    assert Path(compiled.source_path(MODULE)) == Path(lg.__file__).parent / "derivation" / (
        "trig_polynomial.py"
    )


@pytest.mark.parametrize("name", compiled.COMPILED)
def test_the_loaded_form_is_the_one_reported(name: str) -> None:
    module = importlib.import_module(name)
    origin = Path(module.__spec__.origin)
    ran = "python" if origin.suffix == ".py" else "compiled"
    assert compiled.modules()[name] == ran
    # the source is the module's file either way (tracebacks, doctests, inspect read it)
    assert Path(module.__file__) == Path(compiled.source_path(name))
    if ran == "compiled":  # the binary of the source beside it, under the module's own name
        assert origin.parent == Path(compiled.FOLDER)
        assert module.__name__ == name
        assert Path(compiled.compiled_binary(name) or "") == origin


@pytest.mark.skipif(
    compiled.compiled_binary(MODULE) is None,
    reason="the algebra is not compiled in this install (no Cython or C compiler at install)",
)
def test_compiled_and_python_derive_the_same_equations() -> None:
    environment = {**os.environ, compiled.PURE_PYTHON: ""}
    as_compiled = _equations(environment)
    as_python = _equations({**environment, compiled.PURE_PYTHON: "1"})
    assert set(as_compiled) == {*CATALOG, *BENCHMARKS}
    differ = [name for name in as_compiled if as_compiled[name] != as_python[name]]
    assert not differ, f"compiled and Python forms differ on {differ}"
    # and the equations are the bicycle's, not empty ones
    assert sp.srepr(sp.cos(sp.Symbol("lean"))) in as_compiled["whipple_bicycle"]
