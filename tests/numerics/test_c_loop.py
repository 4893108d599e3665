"""The C integration loop of the default backend (numerics/fast/c_loop.c): the same results as
SciPy's solvers and a closed form; the same failures and messages; its library
compiled once per machine, reused by a later process, rebuilt when corrupt; and SciPy's solvers
when there is no C compiler."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest
from c_loop_setup import scipy_path
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.io.load import loads
from lagrangian.numerics.compile import compile_equations
from lagrangian.numerics.fast import c_build, c_loop
from lagrangian.numerics.fast.settings import Settings
from lagrangian.simulation.integrators.compiled import NativeIntegrator
from lagrangian.simulation.integrators.loop import SolverIntegrator
from lagrangian.simulation.run import plan
from lagrangian.simulation.setup import prepare

pytestmark = pytest.mark.skipif(not c_loop.available(), reason="no C compiler")

DRIVEN = """
name: damped driven oscillator
coordinates: [x]
parameters: {m: 1.5, k: 4.0, b: 0.3, F0: 0.7, w: 1.3}
kinetic: m*x_dot**2/2
potential: k*x**2/2
dissipation: b*x_dot**2/2
generalized_forces: {x: F0*cos(w*t)}
initial: {x: 0.2, x_dot: -0.1}
"""
DRIVEN_VALUES = {"m": 1.5, "k": 4.0, "b": 0.3, "F0": 0.7, "w": 1.3}
DOUBLE_START = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
TOL = {"rtol": 1e-10, "atol": 1e-10}


def driven_exact(t: np.ndarray, x0: float = 0.2, v0: float = -0.1) -> np.ndarray:
    """m x'' + b x' + k x = F0 cos(w t): the steady response A cos(w t) + B sin(w t) plus the
    underdamped transient exp(-gamma t)(C1 cos(wd t) + C2 sin(wd t)) meeting x0, v0."""
    m, k, b, F0, w = DRIVEN_VALUES.values()
    A, B = np.linalg.solve([[k - m * w**2, b * w], [-b * w, k - m * w**2]], [F0, 0.0])
    gamma = b / (2 * m)
    wd = np.sqrt(k / m - gamma**2)
    C1 = x0 - A
    C2 = (v0 - w * B + gamma * C1) / wd
    transient = np.exp(-gamma * t) * (C1 * np.cos(wd * t) + C2 * np.sin(wd * t))
    return A * np.cos(w * t) + B * np.sin(w * t) + transient


@pytest.fixture
def no_compiler(monkeypatch: pytest.MonkeyPatch):
    """A machine without a C compiler (the library forgotten before and after)."""
    monkeypatch.setattr(c_build, "find_compiler", lambda: None)
    c_build.loop_library.cache_clear()
    yield
    c_build.loop_library.cache_clear()


@pytest.fixture
def fresh_cache(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """An empty cache folder (``XDG_CACHE_HOME``) for this test; its library folder."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    c_build.loop_library.cache_clear()
    yield tmp_path / "lagrangian"
    c_build.loop_library.cache_clear()


# --- the same numbers ------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
@pytest.mark.parametrize("samples", [201, None])
def test_the_double_pendulum_matches_scipy_and_solve_ivp(method: str, samples: int | None) -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    options = {"method": method, "samples": samples, **TOL}
    native = lg.simulate(eom, DOUBLE_START, 10.0, **options)
    scipy = scipy_path(eom, DOUBLE_START, 10.0, **options)
    assert isinstance(plan(prepare(eom, DOUBLE_START, 10.0, options))[1], NativeIntegrator)
    assert native.success and scipy.success and native.message == scipy.message
    assert len(native.t) == len(scipy.t)
    compiled = compile_equations(eom)
    p = np.array([1.0, 1.0, 1.0, 1.0, 9.81])
    reference = solve_ivp(
        lambda t, x: compiled.rhs(t, x, p),
        (0.0, 10.0),
        [1.0, 0.5, 0.0, 0.0],
        method=method,
        t_eval=native.t if samples else None,
        **TOL,
    )
    for other in (np.column_stack([scipy.q, scipy.q_dot]), reference.y.T):
        x = np.column_stack([native.q, native.q_dot])
        if samples:  # the same output times: the same states
            np.testing.assert_allclose(x, other, rtol=0, atol=1e-9)
        else:  # every step: the same steps, whose sizes differ by the rounding of the error
            # estimate (a sum that cancels), so compare where all end, at t = 10
            np.testing.assert_allclose(x[-1], other[-1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(native.t, scipy.t, rtol=0, atol=1e-6)
    np.testing.assert_allclose(native.t, reference.t, rtol=0, atol=1e-6)


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_the_damped_driven_oscillator_meets_its_closed_form(method: str) -> None:
    system = loads(DRIVEN)
    native = lg.simulate(system, t_span=20.0, method=method, samples=401, rtol=1e-11, atol=1e-12)
    scipy = scipy_path(system, t_span=20.0, method=method, samples=401, rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(native["x"], scipy["x"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(native["x"], driven_exact(native.t), rtol=0, atol=1e-8)
    assert "energy not conserved" in native.drift_summary()  # dissipation and forcing


def test_first_order_coordinates_run_in_the_loop_too() -> None:
    circuit = lg.examples.rc_rl_circuit()
    options = {"method": "DOP853", "samples": 51, "rtol": 1e-10, "atol": 1e-12}
    native = lg.simulate(circuit, **options)
    scipy = scipy_path(circuit, **options)
    assert native.success
    np.testing.assert_allclose(native.q, scipy.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(native.q_dot, scipy.q_dot, rtol=0, atol=1e-9)


def test_every_step_output_grows_past_its_first_rows() -> None:
    pendulum = lg.derive(lg.examples.simple_pendulum())  # no samples from the System
    run = lg.simulate(pendulum, {"theta": 1.0, "theta_dot": 0.0}, 50.0, method="RK45", rtol=1e-10)
    assert len(run.t) > 4 * c_loop.FIRST_ROWS
    assert np.all(np.diff(run.t) > 0) and run.t[-1] == 50.0
    assert run.drift()["energy_relative"] < 1e-7


def test_progress_is_called_after_every_step() -> None:
    seen: list[float] = []
    pendulum = lg.derive(lg.examples.simple_pendulum())
    run = lg.simulate(pendulum, {"theta": 1.0, "theta_dot": 0.0}, 5.0, progress=seen.append)
    assert seen == list(run.t[1:])  # every step is an output row, and a progress call


# --- the same failures -----------------------------------------------------------------------

RUNAWAY = "name: runaway\ncoordinates: [x]\nkinetic: x_dot**2/2\npotential: -x**3/3\n"


@pytest.mark.parametrize(
    ("system", "initial", "t_end", "keywords", "words"),
    [
        (RUNAWAY, {"x": 1.0, "x_dot": 0.0}, 10.0, {}, "step size is less than spacing"),
        ("robot_arm", {"r": 0.0}, 1.0, {}, "mass matrix is singular at t = 0, theta=0, r=0"),
        ("simple_pendulum", {"theta": 1.0}, 100.0, {"max_steps": 50}, "budget of 50 steps is used"),
        ("simple_pendulum", {"theta": 1.0}, 1e3, {"max_wall_time": 1e-9}, "wall-time budget"),
        (
            "name: fall\ncoordinates: [x]\nkinetic: x_dot**2/2\npotential: -1/x\n",
            {"x": 1.0, "x_dot": 0.0},
            3.0,
            {"samples": 31},
            "step size is less than spacing",
        ),
    ],
)
def test_failures_end_as_on_scipys_path(system, initial, t_end, keywords, words) -> None:
    built = loads(system) if "\n" in system else lg.examples.get(system)()
    run = lg.simulate(built, initial, t_end, raise_on_failure=False, **keywords)
    scipy = scipy_path(built, initial, t_end, raise_on_failure=False, **keywords)
    assert run.status == scipy.status == "failed" and words in run.message
    assert np.all(np.isfinite(run.q)) and len(run.t) == len(scipy.t)
    if "wall-time" not in words:
        assert run.message == scipy.message or words.startswith("step size")
    with pytest.raises(lg.SimulationError, match=words):
        lg.simulate(built, initial, t_end, **keywords)


def test_a_stiff_problem_is_stopped_with_scipys_message() -> None:
    van_der_pol = loads(
        "name: vdp\ncoordinates: [x]\nparameters: {mu: 10000}\nkinetic: x_dot**2/2\n"
        "potential: x**2/2\ngeneralized_forces: {x: mu*(1 - x**2)*x_dot}\n"
    )
    start = {"x": 2.0, "x_dot": 0.0}
    run = lg.simulate(van_der_pol, start, 3000.0, raise_on_failure=False)
    scipy = scipy_path(van_der_pol, start, 3000.0, raise_on_failure=False)
    assert "stiff for RK45" in run.message and run.message == scipy.message
    np.testing.assert_allclose(run.t, scipy.t, rtol=0, atol=1e-12)


def test_the_loop_itself_reports_its_status_codes() -> None:
    fast = c_loop.native_equations(lg.derive(lg.examples.simple_pendulum()))
    assert fast is not None
    settings = Settings("DOP853", (0.0, 10.0), np.zeros(0), 1e-9, 1e-9)
    x0, p = np.array([1.0, 0.0]), np.array([1.0, 9.81, 1.0])
    done = c_loop.integrate(fast, settings, x0, p)
    assert done.status == 0 and done.t[-1] == 10.0 and done.steps == len(done.t) - 1
    budget = c_loop.integrate(fast, settings, x0, p, c_loop.Limits(max_steps=3))
    assert budget.status == 5 and budget.steps == 3 and len(budget.t) == 4
    assert "max_steps" in budget.status.message
    with pytest.raises(ValueError, match="no tableau for 'RK23'"):
        c_loop.integrate(fast, Settings("RK23", (0.0, 1.0), np.zeros(0)), x0, p)
    with pytest.raises(ValueError, match="RK4 in the C loop needs its step"):
        c_loop.integrate(fast, Settings("RK4", (0.0, 1.0), np.zeros(0)), x0, p)


# --- no compiler: SciPy's solvers ------------------------------------------------------------


@pytest.mark.usefixtures("no_compiler")
def test_without_a_c_compiler_scipys_solvers_run() -> None:
    assert not c_loop.available()
    eom = lg.derive(lg.examples.double_pendulum())
    options = {"method": "DOP853", "samples": 11, **TOL}
    _, integrator = plan(prepare(eom, DOUBLE_START, 2.0, options))
    assert isinstance(integrator, SolverIntegrator)
    run = lg.simulate(eom, DOUBLE_START, 2.0, **options)
    assert run.success and len(run.t) == 11


def test_a_compiler_that_fails_means_scipys_solvers(monkeypatch, fresh_cache: Path) -> None:
    monkeypatch.setattr(c_build, "find_compiler", lambda: sys.executable)  # not a C compiler
    assert c_build.loop_library() is None and not c_loop.available()
    run = lg.simulate(lg.examples.simple_pendulum(), {"theta": 0.5}, 1.0, samples=3)
    assert run.success


# --- the library on disk ---------------------------------------------------------------------

LOAD = (
    "from lagrangian.numerics.fast import c_build; "
    "library = c_build.loop_library(); print(library._name if library else None)"
)


def _load_in_a_new_process(cache: Path) -> str:
    environment = {**os.environ, "XDG_CACHE_HOME": str(cache)}
    done = subprocess.run(
        [sys.executable, "-c", LOAD], capture_output=True, text=True, env=environment, timeout=600
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def test_the_library_is_built_once_and_reused_by_another_process(fresh_cache: Path) -> None:
    library = c_build.loop_library()
    assert library is not None
    path = Path(library._name)
    assert path.parent == fresh_cache and path.with_name(path.name + ".sha256").exists()
    before = path.stat()
    assert _load_in_a_new_process(fresh_cache.parent) == str(path)
    after = path.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)
    assert [p.suffix for p in sorted(fresh_cache.iterdir())] == [".so", ".sha256"]  # no leftovers


@pytest.mark.parametrize("damage", ["garbled", "cut short"])
def test_a_corrupt_library_is_rebuilt(fresh_cache: Path, damage: str) -> None:
    library = c_build.loop_library()
    assert library is not None
    path = Path(library._name)
    whole = path.read_bytes()
    broken = b"\0" * len(whole) if damage == "garbled" else whole[: len(whole) // 3]
    # a new file in its place: rewriting the library this process has mapped would change the
    # code under it (and crash the process at exit), which is not the damage being tested
    damaged = path.with_name(path.name + ".damaged")
    damaged.write_bytes(broken)
    os.replace(damaged, path)
    assert _load_in_a_new_process(fresh_cache.parent) == str(path)
    assert path.read_bytes() != broken and len(path.read_bytes()) == len(whole)


def test_an_unwritable_cache_folder_falls_back_to_a_temporary_one(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")  # no folder can be made below a file, even by root
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    (tmp_path / "temporary").mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "temporary"))
    c_build.loop_library.cache_clear()
    try:
        library = c_build.loop_library()
        assert library is not None and c_loop.available()
        folder = Path(library._name).parent
        assert folder.parent == tmp_path / "temporary" and folder.name.startswith("lagrangian-")
    finally:
        c_build.loop_library.cache_clear()
