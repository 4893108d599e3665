"""LLVM compilations kept on disk: read back to the same numbers in this process and in a new
one, compiled again when garbled, none kept when switched off, the folder held to its size."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest
import sympy as sp

from lagrangian.numerics.fast import llvm

x, y, z = sp.symbols("x y z")
EXPRESSIONS = [sp.sin(x) * sp.exp(y) + z**3, sp.atan2(y, x) * sp.cos(z), x * y * z]
POINTS = np.array([[0.3, -1.2, 2.5], [1.0, 2.0, -0.5], [-2.0, 0.1, 0.0]])


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A cache folder of the test's own, every compilation kept."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("LAGRANGIAN_LLVM_CACHE", raising=False)
    monkeypatch.setattr(llvm, "KEEP_AFTER", 0.0)
    return tmp_path / "lagrangian" / "llvm"


def _closed_form(point):
    a, b, c = point
    return [np.sin(a) * np.exp(b) + c**3, np.arctan2(b, a) * np.cos(c), a * b * c]


def test_a_kept_compilation_is_read_back_and_gives_the_same_numbers(cache, monkeypatch):
    first = llvm.llvm_lambdify([x, y, z], EXPRESSIONS, opt_level=0)
    kept = sorted(cache.glob("*.pickle"))
    assert len(kept) == 1 and kept[0].with_name(kept[0].name + ".sha256").exists()

    def no_compiler(*args, **kwargs):
        raise AssertionError("compiled again instead of read back")

    monkeypatch.setattr(llvm.se, "Lambdify", no_compiler)
    again = llvm.llvm_lambdify([x, y, z], EXPRESSIONS, opt_level=0)
    for point in POINTS:
        assert np.array_equal(again(point), first(point))
        assert np.allclose(again(point), _closed_form(point), rtol=1e-14, atol=1e-14)


def test_other_expressions_levels_or_arguments_are_kept_apart(cache):
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS, opt_level=0)
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS, opt_level=3)
    llvm.llvm_lambdify([y, x, z], EXPRESSIONS, opt_level=0)  # the same expressions, other order
    swapped = llvm.llvm_lambdify([y, x, z], EXPRESSIONS, opt_level=0)
    assert len(list(cache.glob("*.pickle"))) == 3
    point = POINTS[0]
    assert np.allclose(swapped(point[[1, 0, 2]]), _closed_form(point), rtol=1e-14)


def test_a_garbled_file_is_compiled_again_and_replaced(cache):
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS)
    (kept,) = cache.glob("*.pickle")
    kept.write_bytes(b"not a compilation")
    again = llvm.llvm_lambdify([x, y, z], EXPRESSIONS)
    assert np.allclose(again(POINTS[1]), _closed_form(POINTS[1]), rtol=1e-14)
    assert kept.read_bytes() != b"not a compilation"  # replaced by a whole one


def test_nothing_is_kept_or_read_when_switched_off(cache, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_LLVM_CACHE", "0")
    f = llvm.llvm_lambdify([x, y, z], EXPRESSIONS)
    assert np.allclose(f(POINTS[2]), _closed_form(POINTS[2]), rtol=1e-14)
    assert not cache.exists()


def test_the_folder_is_held_to_its_size_the_least_recently_used_going_first(cache, monkeypatch):
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS[:1])
    (oldest,) = cache.glob("*.pickle")
    monkeypatch.setattr(llvm, "MAX_BYTES", 2 * oldest.stat().st_size + 10)
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS[1:2])
    assert oldest.exists()  # two fit
    llvm.llvm_lambdify([x, y, z], EXPRESSIONS[2:])
    names = {p.name for p in cache.glob("*.pickle")}
    assert oldest.name not in names and len(names) == 2
    assert not oldest.with_name(oldest.name + ".sha256").exists()


def test_a_new_process_reads_what_another_kept(cache, tmp_path):
    script = textwrap.dedent(
        """
        import sys, numpy as np, sympy as sp
        from lagrangian.numerics.fast import llvm
        llvm.KEEP_AFTER = 0.0
        compiled, compile = [], llvm.se.Lambdify
        llvm.se.Lambdify = lambda *a, **k: compiled.append(1) or compile(*a, **k)
        x, y, z = sp.symbols("x y z")
        f = llvm.llvm_lambdify([x, y, z], [sp.sin(x) * sp.exp(y) + z**3, x * y * z])
        print(len(compiled), repr(f(np.array([0.3, -1.2, 2.5])).tolist()))
        """
    )
    env = {"XDG_CACHE_HOME": str(tmp_path), "PATH": "/usr/bin:/bin"}
    runs = [
        subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env)
        for _ in range(2)
    ]
    assert [r.returncode for r in runs] == [0, 0], runs[0].stderr + runs[1].stderr
    (first, numbers), (second, again) = (r.stdout.split(" ", 1) for r in runs)
    assert (first, second) == ("1", "0")  # compiled once, then read back
    assert numbers == again
