"""Generated code (NumPy, C, MATLAB/Octave, Julia) against the symbolic equations of motion.

The reference is SymPy itself: the EquationsOfMotion's own M, C qd, G, Q and forcing,
lambdified with NumPy and evaluated at random states, times and parameters. Octave and Julia
run only where installed; otherwise their files are checked as text.
"""

from __future__ import annotations

import ctypes
import dataclasses
import functools
import importlib.util
import inspect
import re
import shutil
import subprocess
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.numerics.export import export, export_c, export_julia, export_matlab, export_numpy

PIECES = ("mass_matrix", "coriolis", "time_terms", "gravity", "generalized_forces", "forcing")
# Holonomic, robot (dissipation, inputs), explicit time, velocity potential, M(q_dot).
SYSTEMS = (
    "double_pendulum",
    "robot_arm",
    "moving_pivot_pendulum",
    "charged_particle_em",
    "quartic_lagrangian",
)
x, y, x_dot, y_dot, m, k = sp.symbols("x y x_dot y_dot m k")


@functools.cache
def _eom(name: str) -> lg.EquationsOfMotion:
    if name == "cross_coupled":  # M = [[0, m], [m, 0]]: regular, but needs a row swap
        system = lg.System(
            coordinates=[x, y],
            parameters={m: 2.0, k: None},
            kinetic=m * x_dot * y_dot,
            potential=k * (x**2 + 2 * y**2) / 2 + sp.pi * sp.E * sp.sqrt(2) * sp.EulerGamma * x,
            name="Cross-coupled (pivoting) test!",
        )
        return lg.derive(system)
    if name == "no_parameters":
        return lg.derive(lg.System(coordinates=[x], kinetic=x_dot**2 / 2, potential=x**4 / 4))
    return lg.derive(getattr(lg.examples, name)())


def _states(eom: lg.EquationsOfMotion, count: int = 3) -> list[dict[str, Any]]:
    """Random q, qd, t (away from 0) and positive parameters."""
    rng = np.random.default_rng(len(eom.coordinates) * 7 + len(eom.parameters))
    n = len(eom.coordinates)
    return [
        {
            "q": rng.uniform(-1.5, 1.5, n),
            "qd": rng.uniform(-2.0, 2.0, n),
            "t": float(rng.uniform(0.5, 3.0)),
            "p": rng.uniform(0.5, 2.0, len(eom.parameters)),
        }
        for _ in range(count)
    ]


def _reference(eom: lg.EquationsOfMotion, state: dict[str, Any]) -> dict[str, np.ndarray]:
    """SymPy's own values of every piece, row-major and flat, plus rhs = [qd, M^-1 f]."""
    arguments = [list(eom.coordinates), list(eom.velocities), eom.time, list(eom.parameters)]
    values = {}
    for piece in PIECES:
        function = sp.lambdify(arguments, getattr(eom, piece), modules="numpy")
        result = function(state["q"], state["qd"], state["t"], state["p"])
        values[piece] = np.asarray(result, dtype=float).ravel()
    if eom.mass_matrix_is_regular:
        n = len(eom.coordinates)
        q_ddot = np.linalg.solve(values["mass_matrix"].reshape(n, n), values["forcing"])
        values["rhs"] = np.concatenate([state["qd"], q_ddot])
    return values


def _assert_close(actual: Any, expected: np.ndarray) -> None:
    actual = np.asarray(actual, dtype=float).ravel()
    scale = max(1.0, float(np.abs(expected).max(initial=0.0)))
    np.testing.assert_allclose(actual, expected, rtol=1e-10, atol=1e-10 * scale)


def _arguments(state: dict[str, Any], names: list[str]) -> list[Any]:
    x_state = np.concatenate([state["q"], state["qd"]])
    return [x_state if name == "x" else state[name] for name in names]


# --- numpy ---------------------------------------------------------------------------------


def _load(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"exported_{path.stem}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _numpy_module(eom: lg.EquationsOfMotion, tmp_path: Path) -> ModuleType:
    ((file_name, source),) = export(eom, "numpy").items()
    assert source == export_numpy(eom)
    (tmp_path / file_name).write_text(source)
    return _load(tmp_path / file_name)


@pytest.mark.parametrize("name", [*SYSTEMS, "cross_coupled", "no_parameters"])
def test_numpy_module_matches_sympy(name: str, tmp_path: Path) -> None:
    eom = _eom(name)
    module = _numpy_module(eom, tmp_path)
    assert tuple(q.name for q in eom.coordinates) == module.COORDINATES
    assert tuple(s.name for s in eom.parameters) == module.PARAMETERS
    defaults = [np.nan if v is None else v for v in eom.parameters.values()]
    np.testing.assert_array_equal(module.DEFAULTS, defaults)
    for state in _states(eom):
        expected = _reference(eom, state)
        for piece in (*PIECES, "rhs"):
            function = getattr(module, piece)
            names = list(inspect.signature(function).parameters)
            _assert_close(function(*_arguments(state, names)), expected[piece])


def test_time_terms_of_a_pendulum_on_a_shaken_pivot(tmp_path: Path) -> None:
    # By hand: the pivot at x0 cos(omega t) adds m l x_s'' cos(theta) to the theta equation,
    # x_s'' = -x0 omega^2 cos(omega t); the forcing is what is left of Lagrange's equation.
    module = _numpy_module(_eom("moving_pivot_pendulum"), tmp_path)
    m, g, l, x0, omega = (
        module.DEFAULTS[module.PARAMETERS.index(s)] for s in ["m", "g", "l", "x0", "omega"]
    )
    for theta, theta_dot, t in ((0.3, -1.2, 0.7), (2.0, 0.5, 1.9)):
        q, qd, p = np.array([theta]), np.array([theta_dot]), np.asarray(module.DEFAULTS)
        shaking = -m * l * x0 * omega**2 * np.cos(omega * t) * np.cos(theta)
        np.testing.assert_allclose(module.time_terms(q, qd, t, p), [shaking], rtol=1e-12)
        weight = m * g * l * np.sin(theta)
        np.testing.assert_allclose(module.forcing(q, qd, t, p), [-shaking - weight], rtol=1e-12)


def test_velocity_dependent_mass_matrix_takes_qd(tmp_path: Path) -> None:
    module = _numpy_module(_eom("quartic_lagrangian"), tmp_path)
    assert list(inspect.signature(module.mass_matrix).parameters) == ["q", "qd", "t", "p"]
    assert "mass_matrix depends on the velocities" in (module.__doc__ or "")
    assert list(inspect.signature(module.gravity).parameters) == ["q", "t", "p"]


# --- C -------------------------------------------------------------------------------------

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not installed")


def _compile(eom: lg.EquationsOfMotion, tmp_path: Path) -> tuple[ctypes.CDLL, str, str]:
    files = export(eom, "c")
    for file_name, text in files.items():
        (tmp_path / file_name).write_text(text)
    source = next(n for n in files if n.endswith(".c"))
    library = tmp_path / "exported.so"
    command = ["gcc", "-O2", "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
    command += ["-shared", "-fPIC", source, "-o", str(library), "-lm"]
    result = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    return ctypes.CDLL(str(library)), source[:-2], files[source[:-2] + ".h"]


def _call_c(library: ctypes.CDLL, header: str, function: str, state: dict[str, Any], size: int):
    """Call ``function`` with the arguments its header declaration names; returns (status, out)."""
    declaration = re.search(rf"(\w+) {function}\((.*?)\);", header)
    assert declaration is not None, function
    names = [argument.split()[-1].lstrip("*") for argument in declaration[2].split(", ")]
    values = _arguments(state, names[:-1])
    arrays = [np.ascontiguousarray(v, dtype=float) for v in values if not isinstance(v, float)]
    out = np.zeros(size)
    pointer = ctypes.POINTER(ctypes.c_double)
    arguments = [
        ctypes.c_double(v) if isinstance(v, float) else arrays.pop(0).ctypes.data_as(pointer)
        for v in values
    ]
    c_function = getattr(library, function)
    c_function.restype = ctypes.c_int if declaration[1] == "int" else None
    status = c_function(*arguments, out.ctypes.data_as(pointer))
    return status, out


@needs_gcc
@pytest.mark.parametrize("name", [*SYSTEMS, "cross_coupled", "no_parameters"])
def test_c_matches_sympy(name: str, tmp_path: Path) -> None:
    eom = _eom(name)
    library, prefix, header = _compile(eom, tmp_path)
    n = len(eom.coordinates)
    sizes = {piece: n for piece in PIECES} | {"mass_matrix": n * n, "rhs": 2 * n}
    for state in _states(eom):
        expected = _reference(eom, state)
        for piece in (*PIECES, "rhs"):
            status, out = _call_c(library, header, f"{prefix}_{piece}", state, sizes[piece])
            assert status in (None, 0)
            _assert_close(out, expected[piece])


@needs_gcc
def test_c_rhs_reports_a_singular_mass_matrix(tmp_path: Path) -> None:
    library, prefix, header = _compile(_eom("double_pendulum"), tmp_path)
    state = {"q": np.zeros(2), "qd": np.zeros(2), "t": 0.0, "p": np.array([1, 0, 1, 1, 9.81])}
    assert _call_c(library, header, f"{prefix}_rhs", state, 4)[0] == -1  # m2 = 0


def test_c_names_files_and_functions_from_the_system_or_the_argument() -> None:
    eom = _eom("cross_coupled")
    assert sorted(export(eom, "c")) == [
        "cross_coupled_pivoting_test.c",
        "cross_coupled_pivoting_test.h",
    ]
    source, header = export_c(eom, name="arm")
    assert '#include "arm.h"' in source and "#ifndef ARM_H" in header
    assert "void arm_mass_matrix(const double *q, double t, const double *p, double *M);" in header
    assert "#define M_PI" in source and "#define M_E" in source  # strict C99 lacks them
    assert sorted(export(_eom("no_parameters"), "numpy")) == ["model.py"]


# --- MATLAB / Octave and Julia ---------------------------------------------------------------


def _references(text: str, pattern: str, shift: int) -> set[tuple[str, int]]:
    return {(base, int(i) - shift) for base, i in re.findall(pattern, text)}


def _numpy_bodies(eom: lg.EquationsOfMotion) -> dict[str, str]:
    return {b.split("(")[0]: b for b in export_numpy(eom).split("\ndef ")[1:]}


def _script_values(output: str) -> dict[str, np.ndarray]:
    """Parse ``== name`` blocks of numbers printed by an Octave or Julia script."""
    blocks = output.split("== ")[1:]
    return {b.split()[0]: np.array([float(v) for v in b.split()[1:]]) for b in blocks}


def _vector(values: np.ndarray, language: str) -> str:
    numbers = [repr(float(v)) for v in values]
    if language == "julia":
        return f"[{', '.join(numbers)}]" if numbers else "Float64[]"
    return f"[{'; '.join(numbers)}]" if numbers else "zeros(0, 1)"


def _run_and_compare(
    eom: lg.EquationsOfMotion, language: str, lines: list[str], command: list[str], cwd: Path
) -> None:
    """Run a script that sets q, qd, p, x, t, then ``lines`` (printing ``== name`` blocks)."""
    script = cwd / ("check_script.jl" if language == "julia" else "check_script.m")
    for state in _states(eom, count=2):
        values = [f"{s} = {_vector(state[s], language)};" for s in ("q", "qd", "p")]
        stack = "vcat(q, qd)" if language == "julia" else "[q; qd]"
        values.append(f"x = {stack}; t = {state['t']!r};")
        script.write_text("\n".join([*lines[:2], *values, *lines[2:]]) + "\n")
        result = subprocess.run(
            [*command, script.name], cwd=cwd, capture_output=True, text=True, check=False
        )
        assert result.returncode == 0, result.stderr
        printed = _script_values(result.stdout)
        for piece, expected in _reference(eom, state).items():
            _assert_close(printed[piece], expected)


@pytest.mark.parametrize("name", ["double_pendulum", "moving_pivot_pendulum", "quartic_lagrangian"])
def test_matlab_files_have_the_layout(name: str) -> None:
    eom = _eom(name)
    files = export(eom, "matlab")
    assert files == export_matlab(eom)
    qd = "qd, " if name == "quartic_lagrangian" else ""
    assert files["mass_matrix.m"].startswith(f"function M = mass_matrix(q, {qd}t, p)\n")
    assert files["coriolis.m"].startswith("function Cqd = coriolis(q, qd, t, p)\n")
    assert files["gravity.m"].startswith("function G = gravity(q, t, p)\n")
    assert files["forcing.m"].startswith("function f = forcing(q, qd, t, p)\n")
    assert files["rhs.m"].startswith("function dx = rhs(t, x, p)\n")
    assert "M \\ forcing(q, qd, t, p)" in files["rhs.m"]
    assert f"%     q(1)  {eom.coordinates[0]}" in files["forcing.m"]
    # Same expressions as the NumPy module, every index shifted to count from 1.
    for piece, body in _numpy_bodies(eom).items():
        if piece in PIECES:
            python = _references(body, r"\b(qd|q|p)\[(\d+)\]", 0)
            code = re.sub(r"(?m)^%.*$", "", files[f"{piece}.m"])  # the header lists p(1)...
            matlab = _references(code, r"\b(qd|q|p)\((\d+)\)", 1)
            assert python == matlab, piece


@pytest.mark.skipif(shutil.which("octave-cli") is None, reason="octave not installed")
@pytest.mark.parametrize("name", ["double_pendulum", "moving_pivot_pendulum", "quartic_lagrangian"])
def test_octave_matches_sympy(name: str, tmp_path: Path) -> None:
    eom = _eom(name)
    lines = ["", ""]  # nothing to load: the function files are on Octave's path (cwd)
    for file_name, text in export_matlab(eom).items():
        (tmp_path / file_name).write_text(text)
        call = re.match(r"function \w+ = (\w+\(.*?\))", text)
        assert call is not None
        if not call[1].startswith("default_parameters"):
            name = call[1].split("(")[0]
            lines.append(f"v = {call[1]}; printf('== {name}\\n'); printf('%.17g\\n', v.');")
    _run_and_compare(eom, "matlab", lines, ["octave-cli", "--quiet"], tmp_path)


@pytest.mark.parametrize("name", ["double_pendulum", "charged_particle_em", "quartic_lagrangian"])
def test_julia_module_has_the_layout(name: str) -> None:
    eom = _eom(name)
    ((file_name, source),) = export(eom, "julia").items()
    assert file_name == f"{name}.jl" and source == export_julia(eom)
    module = "".join(part.capitalize() for part in name.split("_"))
    assert f"\nmodule {module}\n" in source and source.rstrip().endswith("end # module")
    assert (
        "export mass_matrix, coriolis, time_terms, gravity, generalized_forces, forcing, rhs"
        in (source)
    )
    assert "\nfunction forcing(q, qd, t, p)\n" in source
    assert "\nfunction rhs(t, x, p)\n" in source and "M \\ forcing(q, qd, t, p)" in source
    for piece, body in _numpy_bodies(eom).items():
        if piece in PIECES:
            julia_body = source.split(f"\nfunction {piece}(")[1].split("\nend")[0]
            python = _references(body, r"\b(qd|q|p)\[(\d+)\]", 0)
            assert python == _references(julia_body, r"\b(qd|q|p)\[(\d+)\]", 1), piece


@pytest.mark.skipif(shutil.which("julia") is None, reason="julia not installed")
@pytest.mark.parametrize("name", ["double_pendulum", "moving_pivot_pendulum", "quartic_lagrangian"])
def test_julia_matches_sympy(name: str, tmp_path: Path) -> None:
    eom = _eom(name)
    ((file_name, source),) = export(eom, "julia").items()
    (tmp_path / file_name).write_text(source)
    module = re.search(r"^module (\w+)$", source, re.MULTILINE)
    assert module is not None
    lines = [f'include("{file_name}")', f"using .{module[1]}"]
    for piece, arguments in re.findall(r"^function (\w+)\((.*?)\)$", source, re.MULTILINE):
        value = f"{piece}({arguments})"
        flat = f"vec(permutedims({value}))" if piece == "mass_matrix" else value
        lines.append(f'println("== {piece}"); foreach(println, {flat})')
    _run_and_compare(eom, "julia", lines, ["julia", "--startup-file=no"], tmp_path)


# --- singular mass matrix, bad input -----------------------------------------------------------


def test_singular_mass_matrix_exports_everything_but_rhs(tmp_path: Path) -> None:
    eom = _eom("rc_rl_circuit")
    assert not eom.mass_matrix_is_regular
    module = _numpy_module(eom, tmp_path)
    assert not hasattr(module, "rhs")
    with pytest.raises(AttributeError, match=r"rhs is not generated\. The mass matrix is singular"):
        module.rhs  # noqa: B018
    assert "NO rhs IS GENERATED" in (module.__doc__ or "")
    for state in _states(eom):
        expected = _reference(eom, state)
        assert "rhs" not in expected
        for piece in PIECES:
            function = getattr(module, piece)
            names = list(inspect.signature(function).parameters)
            _assert_close(function(*_arguments(state, names)), expected[piece])
    source, header = export_c(eom)
    assert "_rhs(" not in source + header and "NO rhs IS GENERATED" in header
    assert "No rhs: the mass matrix is singular" in header
    files = export_matlab(eom)
    assert "rhs.m" not in files and "NO rhs IS GENERATED" in files["forcing.m"]
    julia = export_julia(eom)
    assert "function rhs" not in julia and "NO rhs IS GENERATED" in julia


@needs_gcc
def test_singular_mass_matrix_c_compiles_without_rhs(tmp_path: Path) -> None:
    library, prefix, _ = _compile(_eom("rc_rl_circuit"), tmp_path)
    assert hasattr(library, f"{prefix}_forcing") and not hasattr(library, f"{prefix}_rhs")


def test_unknown_language_names_the_allowed_ones() -> None:
    with pytest.raises(ModelError, match="choose one of numpy, c, matlab, julia"):
        export(_eom("double_pendulum"), "fortran")


def test_undeclared_symbols_and_unknown_functions_are_refused() -> None:
    eom = _eom("double_pendulum")
    stray = dataclasses.replace(eom, forcing=eom.forcing + sp.Matrix([sp.Symbol("b"), 0]))
    with pytest.raises(ModelError, match=r"the equations use b, .*Declare them as parameters"):
        export_numpy(stray)
    unknown = sp.Function("u")(eom.time)
    opaque = dataclasses.replace(eom, forcing=eom.forcing + sp.Matrix([unknown, 0]))
    with pytest.raises(ModelError, match=r"Cannot export to C: .*Use the functions"):
        export_c(opaque)
