"""Exported multiplier form of constrained systems, run against lagrangian's own simulate, the
angle form of the pendulum, and each language against the NumPy module."""

import ctypes
import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.io.load import loads
from lagrangian.numerics.export import export
from lagrangian.numerics.export.common import camel_case

PENDULUM = """name: Cartesian pendulum
coordinates: [x, y]
parameters: {m: 1.5, g: 9.81, l: 0.8}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: x**2 + y**2 - l**2}
"""
DOUBLE = """name: Cartesian double pendulum
coordinates: [x1, y1, x2, y2]
parameters: {m1: 1, m2: 2, g: 9.81, l1: 1, l2: 0.7}
kinetic: m1*(x1_dot**2 + y1_dot**2)/2 + m2*(x2_dot**2 + y2_dot**2)/2
potential: m1*g*y1 + m2*g*y2
constraints:
  - {holonomic: x1**2 + y1**2 - l1**2}
  - {holonomic: (x2 - x1)**2 + (y2 - y1)**2 - l2**2}
"""


def _module(system, tmp_path):
    files = export(lg.derive(system), "numpy")
    ((name, text),) = files.items()
    path = tmp_path / name
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _pendulum_start(angle, l=0.8):
    return {"x": l * np.sin(angle), "y": -l * np.cos(angle), "x_dot": 0.0, "y_dot": 0.0}


def _double_start():
    a, b = 0.7, -0.4
    x1, y1 = np.sin(a), -np.cos(a)
    return {
        "x1": x1,
        "y1": y1,
        "x2": x1 + 0.7 * np.sin(b),
        "y2": y1 - 0.7 * np.cos(b),
        "x1_dot": 0.0,
        "y1_dot": 0.0,
        "x2_dot": 0.0,
        "y2_dot": 0.0,
    }


def _cases():
    disc = lg.examples.rolling_disc()
    return [
        ("pendulum", loads(PENDULUM), _pendulum_start(0.6)),
        ("double", loads(DOUBLE), _double_start()),
        ("rolling_disc", disc, dict(disc.initial)),
    ]


@pytest.mark.parametrize("case", range(3))
def test_the_exported_numpy_rhs_moves_as_simulate(case, tmp_path):
    _, system, start = _cases()[case]
    module = _module(system, tmp_path)
    eom = lg.derive(system)
    names = [q.name for q in eom.coordinates]
    initial = {str(k): float(v) for k, v in start.items()}
    x0 = np.array([initial[n] for n in names] + [initial.get(n + "_dot", 0.0) for n in names])
    p = np.array(module.DEFAULTS)
    run = solve_ivp(module.rhs, (0, 1.5), x0, args=(p,), method="DOP853", rtol=1e-11, atol=1e-12)
    reference = lg.simulate(
        system, initial, 1.5, method="DOP853", rtol=1e-11, atol=1e-12, samples=2
    )
    assert np.allclose(run.y[: len(names), -1], reference.q[-1], atol=1e-8)
    multipliers = module.multipliers(0.0, x0, p)
    assert np.allclose(multipliers, reference.multipliers[0], atol=1e-8)


def test_the_cartesian_pendulum_swings_as_the_angle_form(tmp_path):
    module = _module(loads(PENDULUM), tmp_path)
    p = np.array(module.DEFAULTS)
    start = _pendulum_start(0.6)
    x0 = np.array([start["x"], start["y"], 0.0, 0.0])
    run = solve_ivp(module.rhs, (0, 3), x0, args=(p,), method="DOP853", rtol=1e-12, atol=1e-13)
    g, l = 9.81, 0.8
    angle = solve_ivp(
        lambda t, y: [y[1], -g / l * np.sin(y[0])],
        (0, 3),
        [0.6, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
    )
    x, y = run.y[0, -1], run.y[1, -1]
    assert abs(np.arctan2(x, -y) - angle.y[0, -1]) < 1e-8
    # the rod's tension at rest at the start: lambda = -m g cos(theta0) / (2 l) in this sign
    assert module.multipliers(0.0, x0, p)[0] == pytest.approx(-1.5 * g * np.cos(0.6) / (2 * l))


def test_baumgarte_gains_hold_the_constraint_against_drift(tmp_path):
    module = _module(loads(PENDULUM), tmp_path)
    start = _pendulum_start(1.2)
    x0 = np.array([start["x"], start["y"], 0.0, 0.0])
    drift = []
    for gains in ((0.0, 0.0), (10.0, 10.0)):
        p = np.array([*module.DEFAULTS[:3], *gains])
        run = solve_ivp(module.rhs, (0, 60), x0, args=(p,), method="RK45", rtol=1e-5, atol=1e-7)
        drift.append(abs(run.y[0, -1] ** 2 + run.y[1, -1] ** 2 - 0.8**2))
    assert drift[1] < drift[0] / 100


def _states(module, count=3):
    rng = np.random.default_rng(7)
    n = len(module.COORDINATES)
    return [(float(rng.uniform(0, 1)), rng.uniform(-1, 1, 2 * n)) for _ in range(count)]


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not installed")
@pytest.mark.parametrize("case", range(3))
def test_c_agrees_with_the_numpy_module(case, tmp_path):
    _, system, _ = _cases()[case]
    module = _module(system, tmp_path)
    files = export(lg.derive(system), "c")
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    source = next(name for name in files if name.endswith(".c"))
    command = [
        "gcc",
        "-O2",
        "-std=c99",
        "-Wall",
        "-Wextra",
        "-Werror",
        "-pedantic",
        "-shared",
        "-fPIC",
        source,
        "-o",
        "exported.so",
        "-lm",
    ]
    result = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    library = ctypes.CDLL(str(tmp_path / "exported.so"))
    base = source[:-2]
    pointer = ctypes.POINTER(ctypes.c_double)
    p = np.array(module.DEFAULTS)
    m = len(module.multipliers(0.0, _states(module)[0][1], p))
    for t, x in _states(module):
        dx, lam = np.zeros(len(x)), np.zeros(m)
        for function, out in (("rhs", dx), ("multipliers", lam)):
            call = getattr(library, f"{base}_{function}")
            call.restype = ctypes.c_int
            status = call(
                ctypes.c_double(t),
                x.ctypes.data_as(pointer),
                p.ctypes.data_as(pointer),
                out.ctypes.data_as(pointer),
            )
            assert status == 0
        assert np.allclose(dx, module.rhs(t, x, p), rtol=1e-12, atol=1e-12)
        assert np.allclose(lam, module.multipliers(t, x, p), rtol=1e-12, atol=1e-12)


def _literal(values, language):
    separator = "; " if language == "matlab" else ", "
    return "[" + separator.join(repr(float(v)) for v in values) + "]"


@pytest.mark.parametrize(("language", "program"), [("matlab", "octave-cli"), ("julia", "julia")])
def test_matlab_and_julia_agree_with_the_numpy_module(language, program, tmp_path):
    if shutil.which(program) is None:
        pytest.skip(f"{program} not installed")
    system = loads(DOUBLE)
    module = _module(system, tmp_path)
    files = export(lg.derive(system), language)
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    p = np.array(module.DEFAULTS)
    t, x = _states(module, 1)[0]
    values = f"x = {_literal(x, language)}; p = {_literal(p, language)};"
    if language == "matlab":
        lines = [
            values,
            f"disp(sprintf('%.17g ', rhs({t!r}, x, p)));",
            f"disp(sprintf('%.17g ', multipliers({t!r}, x, p)));",
        ]
        command = [program, "--quiet", "check.m"]
    else:
        source = next(iter(files))
        lines = [
            f'include("{source}")',
            f"using .{camel_case(source[:-3])}",
            values,
            f"println(join(rhs({t!r}, x, p), ' '))",
            f"println(join(multipliers({t!r}, x, p), ' '))",
        ]
        command = [program, "check.jl"]
    (tmp_path / command[-1]).write_text("\n".join(lines) + "\n")
    result = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr
    rhs_line, multipliers_line = result.stdout.strip().splitlines()[-2:]
    assert np.allclose([float(v) for v in rhs_line.split()], module.rhs(t, x, p), rtol=1e-10)
    expected = module.multipliers(t, x, p)
    assert np.allclose([float(v) for v in multipliers_line.split()], expected, rtol=1e-10)


def test_a_unilateral_constraint_is_refused():
    system = loads(
        PENDULUM.replace("{holonomic: x**2 + y**2 - l**2}", "{unilateral: l**2 - x**2 - y**2}")
    )
    for language in ("numpy", "c", "matlab", "julia"):
        with pytest.raises(ModelError, match="unilateral"):
            export(lg.derive(system), language)


def test_the_minimal_form_in_chosen_coordinates(tmp_path, capsys):
    from lagrangian.cli.main import main

    model = tmp_path / "pendulum.yaml"
    start = _pendulum_start(0.6)
    model.write_text(
        PENDULUM + f"initial: {{x: {float(start['x'])!r}, y: {float(start['y'])!r}}}\n"
    )
    out = tmp_path / "minimal"
    assert main(["export", str(model), "--independent", "x", "--out", str(out)]) == 0
    (path,) = out.iterdir()
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.COORDINATES == ("x",)
    # at rest at angle theta, the bob's horizontal acceleration is -g sin(theta) cos(theta)
    p = np.array(module.DEFAULTS)
    acceleration = module.rhs(0.0, np.array([start["x"], 0.0]), p)[1]
    assert acceleration == pytest.approx(-9.81 * np.sin(0.6) * np.cos(0.6), rel=1e-12)
    capsys.readouterr()
    disc = ["export", "rolling_disc", "--independent", "x,y", "--out", str(tmp_path / "d")]
    assert main(disc) == 2
    assert "only holonomic constraints" in capsys.readouterr().err
