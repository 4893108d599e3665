"""The variational integrators on the compiled path (numba loops calling the system's LLVM
functions) give the NumPy marches' trajectories to rounding, on free, forced and damped, and
constrained systems; the midpoint rule keeps its energy error bounded over 10^5 steps; the
compiled march reports progress, stops on Ctrl-C keeping its rows, fails with the NumPy
march's message, and gives way to the NumPy march where numba is missing.  The collocation
steps' Newton iteration (stopped at a small correction, the forces at it from their Jacobian)
solves its stage equations to rounding: against the equations evaluated afresh, SciPy's root
finder and the constraints, most steps in one evaluation of every stage from the corrected
guess, which changes the iterations, not the solution (the stages solved again from the plain
extrapolation; the trajectory recorded before it)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import root

import lagrangian as lg
from lagrangian.numerics.discrete_lagrangian import (
    RESIDUAL_GUARD,
    DiscreteMechanics,
    compile_discrete_mechanics,
)
from lagrangian.numerics.stage_prediction import NEWTON_RESIDUAL_GUARD
from lagrangian.simulation import simulate
from lagrangian.simulation.variational import midpoint as variational
from lagrangian.simulation.variational.collocation import Tableau, gauss, lobatto
from lagrangian.simulation.variational.collocation_march import collocation_march
from lagrangian.simulation.variational.collocation_step import stage_step
from lagrangian.simulation.variational.march import march
from lagrangian.simulation.variational.stepper import CollocationStepper

pytest.importorskip("numba")

from lagrangian.simulation.variational import compiled as variational_fast


def forced_double_pendulum() -> lg.System:
    """The double pendulum with Rayleigh dissipation and a time-dependent torque."""
    theta_dot, phi_dot, c, tau, t = sp.symbols("theta_dot phi_dot c tau t")
    pendulum = lg.examples.double_pendulum()
    return pendulum.replace(
        parameters={**pendulum.parameters, c: 0.3, tau: 0.5},
        dissipation=c * (theta_dot**2 + theta_dot * phi_dot + phi_dot**2),
        generalized_forces={sp.Symbol("theta"): tau * sp.cos(t) * sp.Symbol("phi")},
    )


def cartesian_double_pendulum() -> lg.System:
    x1, y1, x2, y2, m1, m2, l1, l2, g = sp.symbols("x1 y1 x2 y2 m1 m2 l1 l2 g")
    return lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={m1: 1.0, m2: 1.0, l1: 1.0, l2: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bob1", m1, (x1, y1)), lg.Particle("bob2", m2, (x2, y2))],
        constraints=[
            lg.Holonomic(x1**2 + y1**2 - l1**2, name="upper rod"),
            lg.Holonomic((x2 - x1) ** 2 + (y2 - y1) ** 2 - l2**2, name="lower rod"),
        ],
    )


def cartesian_start(theta: float = 1.0, phi: float = 0.5) -> dict[str, float]:
    """The Cartesian double pendulum at rest at the angles theta, phi."""
    x1, y1 = np.sin(theta), -np.cos(theta)
    position = {"x1": x1, "y1": y1, "x2": x1 + np.sin(phi), "y2": y1 - np.cos(phi)}
    return {**position, **{f"{name}_dot": 0.0 for name in position}}


ANGLES = {"theta": 1.0, "phi": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
CASES = {
    "double pendulum": (lg.examples.double_pendulum, ANGLES),
    "forced, damped": (forced_double_pendulum, {**ANGLES, "phi_dot": 0.3}),
    "Cartesian, two rods": (cartesian_double_pendulum, cartesian_start()),
}


@pytest.fixture
def spy(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The names of the compiled marches called."""
    called: list[str] = []
    for name in ("fast_march", "fast_collocation_march"):
        original = getattr(variational_fast, name)

        def wrapped(*args: object, _original=original, _name=name, **kwargs: object) -> object:
            called.append(_name)
            return _original(*args, **kwargs)

        monkeypatch.setattr(variational_fast, name, wrapped)
    return called


@pytest.mark.parametrize("case", CASES)
def test_the_compiled_midpoint_rule_gives_the_numpy_trajectory(
    case: str, spy: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    make, start = CASES[case]
    eom = lg.derive(make())
    compiled = simulate(eom, start, 5.0, method="variational", dt=0.01)
    assert spy == ["fast_march"]
    monkeypatch.setattr(variational, "COMPILED", False)
    reference = simulate(eom, start, 5.0, method="variational", dt=0.01)
    assert spy == ["fast_march"] and len(compiled.t) == len(reference.t) == 501
    np.testing.assert_allclose(compiled.q, reference.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(compiled.q_dot, reference.q_dot, rtol=0, atol=1e-10)
    if eom.system.constraints:
        np.testing.assert_allclose(compiled.multipliers, reference.multipliers, atol=1e-9)


@pytest.mark.parametrize(
    "tableau", [gauss(2), gauss(3), lobatto(3), lobatto(4)], ids=lambda tableau: tableau.name
)
def test_the_compiled_collocation_march_gives_the_numpy_trajectory(tableau: object) -> None:
    constrained = tableau.lobatto  # type: ignore[attr-defined]
    system = cartesian_double_pendulum() if constrained else forced_double_pendulum()
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, [c.expression for c in system.constraints])
    p = np.array([float(eom.system.parameters[s]) for s in eom.parameters])
    start = cartesian_start() if constrained else ANGLES
    x0 = np.array([start[s.name] for s in (*eom.coordinates, *eom.velocities)])
    grid, outputs = np.linspace(0.0, 2.0, 101), np.arange(0, 101, 10)
    compiled = variational_fast.fast_collocation_march(mechanics, tableau, x0, p, grid, outputs)
    reference = collocation_march(mechanics, tableau, x0, p, grid, outputs)
    assert compiled.failure is None and reference.failure is None
    assert compiled.evaluations == reference.evaluations
    np.testing.assert_allclose(compiled.q, reference.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(compiled.q_dot, reference.q_dot, rtol=0, atol=1e-10)


REFERENCE = Path(__file__).with_name("data") / "gauss_reference.json"


@pytest.mark.parametrize("method", ["gauss4", "gauss6"])
def test_the_gauss_trajectories_are_those_of_the_simplified_newton_march(method: str) -> None:
    # the trajectory recorded from the march before the corrected guess (one Jacobian a
    # step, two or three evaluations of every stage): 2 x 10^4 steps of the double pendulum,
    # the same to the rounding that chaotic motion grows (5e-13 in q, 1.7e-12 in q_dot
    # measured), the same energy error
    reference = json.loads(REFERENCE.read_text())
    pendulum = lg.examples.double_pendulum()
    run = simulate(lg.derive(pendulum), pendulum.initial, reference["t_end"], method=method,
                   dt=reference["dt"], samples=reference["samples"])  # fmt: skip
    assert run.success
    recorded = reference[method]
    np.testing.assert_allclose(run.t, recorded["t"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.q, recorded["q"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(run.q_dot, recorded["q_dot"], rtol=0, atol=1e-10)
    error = np.abs(run.energy / run.energy[0] - 1).max()
    assert error == pytest.approx(recorded["energy_error"], rel=0.05)


def test_the_energy_error_stays_bounded_over_100000_steps() -> None:
    # chaotic motion, t = 1000 s: the largest error over the last tenth of the run is that of
    # the first tenth (a drift would grow with t)
    pendulum = lg.examples.double_pendulum()
    run = simulate(lg.derive(pendulum), pendulum.initial, 1000.0, method="variational", dt=0.01)
    assert run.success and len(run.t) == 100_001
    error = np.abs(run.energy / run.energy[0] - 1)
    tenth = len(error) // 10
    first, last = error[1:tenth].max(), error[-tenth:].max()
    assert error.max() < 1e-4
    assert last < 1.05 * first, (first, last)


def test_progress_is_reported_and_ctrl_c_keeps_the_rows() -> None:
    pendulum = lg.examples.double_pendulum()
    eom, reached = lg.derive(pendulum), []

    def progress(t: float) -> None:
        reached.append(t)
        if len(reached) == 2:
            raise KeyboardInterrupt

    run = simulate(
        eom, pendulum.initial, 200.0, method="variational", dt=0.01, progress=progress,
        raise_on_failure=False,
    )  # fmt: skip
    assert run.status == "interrupted"
    assert reached[0] < reached[1] < 200.0
    assert run.t[-1] == pytest.approx(reached[1])
    full = simulate(eom, pendulum.initial, run.t[-1], method="variational", dt=0.01)
    np.testing.assert_allclose(run.q, full.q, atol=1e-12)


def test_a_failed_step_keeps_the_rows_with_the_numpy_message(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # a rod twice around in one step: Newton's method cannot find the next position
    system = cartesian_double_pendulum()
    start = {**cartesian_start(), "x2_dot": 40.0, "y2_dot": 40.0}
    kwargs = {"method": "variational", "dt": 0.5, "raise_on_failure": False}
    compiled = simulate(system, start, 20.0, project_initial=True, **kwargs)
    monkeypatch.setattr(variational, "COMPILED", False)
    reference = simulate(system, start, 20.0, project_initial=True, **kwargs)
    assert compiled.status == reference.status == "failed"
    assert compiled.message == reference.message
    np.testing.assert_allclose(compiled.q, reference.q, atol=1e-10)


def test_without_numba_the_numpy_march_runs(
    spy: list[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(variational, "numba_available", lambda: False)
    run = simulate(lg.examples.simple_pendulum(), {"theta": 0.5}, 1.0, method="variational")
    assert run.success and spy == []


def test_terms_without_a_compiled_form_fall_back_to_numpy(monkeypatch: pytest.MonkeyPatch) -> None:
    from lagrangian.errors import SimulationError

    def refuse(*args: object, **kwargs: object) -> None:
        raise SimulationError("no compiled form")

    monkeypatch.setattr(variational_fast, "native_mechanics", refuse)
    eom = lg.derive(lg.examples.simple_pendulum())
    run = simulate(eom, {"theta": 0.5, "theta_dot": 0.0}, 1.0, method="variational", dt=0.01)
    mechanics = compile_discrete_mechanics(eom)
    grid = np.linspace(0.0, 1.0, 101)
    numpy_run = march(
        mechanics, np.array([0.5, 0.0]), np.array([1.0, 9.81, 1.0]), grid, np.array([0, 100])
    )
    assert run.success
    assert run.q[-1, 0] == pytest.approx(numpy_run.q[-1, 0], abs=1e-12)


# ------------------------------------------------------------------ the stage Newton iteration

DT = 0.01


def setup(system: lg.System) -> tuple[DiscreteMechanics, np.ndarray]:
    eom = lg.derive(system)
    mechanics = compile_discrete_mechanics(eom, [c.expression for c in system.constraints])
    return mechanics, np.array([float(eom.system.parameters[s]) for s in eom.parameters])


def stage_residual(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    q0: np.ndarray,
    p0: np.ndarray,
    t0: float,
    p: np.ndarray,
    V: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The stage equations L_v(Q_i, V_i) - p0 - dt sum_j a_ij F_j (no constraints) evaluated
    afresh at V, and the momentum p0 + dt sum_i b_i F_i."""
    Q = q0 + DT * tableau.a @ V
    terms = [mechanics.midpoint(Qi, Vi, t0 + ci * DT, p) for Qi, Vi, ci in zip(Q, V, tableau.c)]
    F = np.array([L_q + Q_f for L_q, _, Q_f, *_ in terms])
    L_v = np.array([term[1] for term in terms])
    return L_v - p0 - DT * tableau.a @ F, p0 + DT * tableau.b @ F


def assert_as_scipy_root(
    mechanics: DiscreteMechanics,
    tableau: Tableau,
    start: tuple[np.ndarray, np.ndarray, float],
    p: np.ndarray,
    guess: np.ndarray,
    V: np.ndarray,
) -> None:
    """The stages V are those SciPy's root finder finds from ``guess`` on the same
    equations (no Jacobian given) from ``start`` = (q0, p0, t0), at a tight tolerance."""
    q0, p0, t0 = start
    found = root(
        lambda x: stage_residual(mechanics, tableau, q0, p0, t0, p, x.reshape(-1, 2))[0].ravel(),
        guess.ravel(),
        method="hybr",
        options={"xtol": 1e-13},
    )
    assert found.success and np.abs(found.fun).max() < 1e-12
    np.testing.assert_allclose(V.ravel(), found.x, rtol=0, atol=1e-11)


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_a_gauss_step_solves_its_stage_equations_to_rounding(tableau: Tableau) -> None:
    mechanics, p = setup(forced_double_pendulum())
    q0, v0, t0 = np.array([1.0, 0.5]), np.array([0.7, -1.3]), 0.4
    p0 = np.array(mechanics.legendre(q0, v0, t0, p)[0], dtype=float)
    guess = np.tile(v0, (tableau.stages, 1))
    step = stage_step(mechanics, tableau, q0, p0, t0, DT, p, guess, np.zeros((0, 0)))
    rows, momentum = stage_residual(mechanics, tableau, q0, p0, t0, p, step.V)
    # the equations hold at the returned stages to rounding of their terms (about 10)
    assert np.abs(rows).max() < 1e-13
    # the momentum taken from the Jacobian is the one evaluated at the stages
    np.testing.assert_allclose(step.momentum, momentum, rtol=0, atol=1e-13)
    np.testing.assert_allclose(step.q, q0 + DT * tableau.b @ step.V, rtol=0, atol=1e-15)
    assert_as_scipy_root(mechanics, tableau, (q0, p0, t0), p, guess, step.V)
    # a guess this far off takes more corrections; every one is counted
    assert step.evaluations % tableau.stages == 0 and step.evaluations >= 2 * tableau.stages


@pytest.mark.parametrize("tableau", [lobatto(3), lobatto(4)], ids=lambda t: t.name)
def test_a_lobatto_step_ends_on_the_constraints_with_their_values_there(tableau: Tableau) -> None:
    mechanics, p = setup(cartesian_double_pendulum())
    start = cartesian_start()
    names = ("x1", "y1", "x2", "y2")
    q0 = np.array([start[name] for name in names])
    x1, y1, x2, y2 = q0
    v0 = 1.1 * np.array([-y1, x1, -y2, x2])  # turning rigidly about the pivot: on both rods
    p0 = np.array(mechanics.legendre(q0, v0, 0.0, p)[0], dtype=float)
    guess = np.tile(v0, (tableau.stages, 1))
    multipliers = np.zeros((tableau.stages - 1, 2))
    step = stage_step(mechanics, tableau, q0, p0, 0.0, DT, p, guess, multipliers)
    # every stage after the first on both rods, q1 among them
    Q = q0 + DT * tableau.a @ step.V
    upper = Q[1:, 0] ** 2 + Q[1:, 1] ** 2 - 1
    lower = (Q[1:, 2] - Q[1:, 0]) ** 2 + (Q[1:, 3] - Q[1:, 1]) ** 2 - 1
    assert max(np.abs(upper).max(), np.abs(lower).max()) < 1e-14
    np.testing.assert_allclose(step.q, Q[-1], rtol=0, atol=1e-15)
    # h, A and dh/dt returned are those at the corrected q1
    fresh = mechanics.constraints(step.q, DT, p)
    for returned, expected in zip((step.h, step.jacobian, step.rate), fresh):
        np.testing.assert_allclose(returned, expected, rtol=0, atol=1e-15)


@pytest.mark.parametrize(
    ("tableau", "bound"), [(gauss(2), 1.2), (gauss(3), 1.12)], ids=["gauss4", "gauss6"]
)
def test_a_smooth_motion_evaluates_each_stage_about_once_a_step(
    tableau: Tableau, bound: float
) -> None:
    # the guess (the extrapolated stages corrected by the extrapolated errors of the steps
    # before) is within SMALL_CORRECTION in most steps, its residual within the square root
    # of RESIDUAL_GUARD: Newton's first correction ends them, one evaluation of every stage
    # (1.13 and 1.07 measured; 1.35 and 1.20 when the residual before that correction had to
    # be within RESIDUAL_GUARD itself); the others take a second (gauss4, whose extrapolation
    # is of lower order, more often); the first steps, started from v0 at every stage, more
    mechanics, p = setup(lg.examples.double_pendulum())
    x0, steps = np.array([1.0, 0.5, 0.0, 0.0]), 1000
    grid = np.linspace(0.0, steps * DT, steps + 1)
    run = collocation_march(mechanics, tableau, x0, p, grid, np.array([0, steps]))
    assert run.failure is None
    per_step = (run.evaluations - 2) / steps / tableau.stages  # less the Legendre maps
    assert 1.0 <= per_step < bound, per_step


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_newtons_step_from_a_residual_above_the_guard_ends_the_step_at_the_solution(
    tableau: Tableau,
) -> None:
    # a guess off the solution by 1e-7 of the stage velocities has a residual of about 1e-7
    # of its terms: above RESIDUAL_GUARD, within NEWTON_RESIDUAL_GUARD (1e-4).  Newton's
    # correction by the Jacobian at the guess ends the step (one evaluation of every stage),
    # and what it returns is SciPy's root of the stage equations to rounding
    mechanics, p = setup(forced_double_pendulum())
    q0, v0, t0 = np.array([1.0, 0.5]), np.array([0.7, -1.3]), 0.4
    p0 = np.array(mechanics.legendre(q0, v0, t0, p)[0], dtype=float)
    solved = stage_step(mechanics, tableau, q0, p0, t0, DT, p, np.tile(v0, (tableau.stages, 1)),
                        np.zeros((0, 0)))  # fmt: skip
    near = solved.V * (1 + 1e-7 * np.array([[1.0, -1.0]]))
    rows, _ = stage_residual(mechanics, tableau, q0, p0, t0, p, near)
    relative = np.abs(rows).max() / np.abs(p0).max()
    assert RESIDUAL_GUARD < relative < NEWTON_RESIDUAL_GUARD, relative
    step = stage_step(mechanics, tableau, q0, p0, t0, DT, p, near, np.zeros((0, 0)))
    assert step.evaluations == tableau.stages
    np.testing.assert_allclose(DT * step.V, DT * solved.V, rtol=0, atol=1e-15)
    np.testing.assert_allclose(step.q, solved.q, rtol=0, atol=1e-15)
    np.testing.assert_allclose(step.momentum, solved.momentum, rtol=0, atol=1e-13)
    assert_as_scipy_root(mechanics, tableau, (q0, p0, t0), p, near, step.V)
    # off by 1e-3 (a residual above NEWTON_RESIDUAL_GUARD) it takes more corrections
    far = solved.V * (1 + 1e-3 * np.array([[1.0, -1.0]]))
    again = stage_step(mechanics, tableau, q0, p0, t0, DT, p, far, np.zeros((0, 0)))
    assert again.evaluations > tableau.stages
    np.testing.assert_allclose(DT * again.V, DT * solved.V, rtol=0, atol=1e-15)


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_the_corrected_guess_changes_the_iterations_not_the_solution(tableau: Tableau) -> None:
    # over 300 steps of a chaotic motion, each step solved again from the plain extrapolation
    # gives the stages of the corrected guess to the rounding the iteration stops at (a few
    # units of the stage positions), in more iterations
    mechanics, p = setup(lg.examples.double_pendulum())
    x0 = np.array([1.0, 0.5, 0.0, 0.0])
    stepper = CollocationStepper(mechanics, tableau, x0, p, np.linspace(0.0, 3.0, 301),
                                 np.zeros(301, dtype=bool))  # fmt: skip
    E = tableau.extrapolation(1.0)
    guessed = plain = 0
    while stepper.status == "running":
        q, momentum, t, V = stepper.q, stepper.momentum, stepper.t, stepper.stage_velocities
        dt, before = float(stepper.grid[stepper.k + 1]) - t, stepper.evaluations
        assert stepper.step() is None
        again = stage_step(mechanics, tableau, q, momentum, t, dt, p, E @ V, np.zeros((0, 0)))
        # the stage positions' increments dt V, and q1, to the iteration's rounding
        np.testing.assert_allclose(dt * stepper.stage_velocities, dt * again.V, rtol=0, atol=1e-14)
        np.testing.assert_allclose(stepper.q, again.q, rtol=0, atol=1e-14)
        guessed += stepper.evaluations - before
        plain += again.evaluations
    assert guessed < 0.8 * plain, (guessed, plain)


@pytest.mark.parametrize("tableau", [gauss(2), gauss(3)], ids=lambda t: t.name)
def test_a_step_from_the_extrapolated_stages_solves_them_to_rounding(tableau: Tableau) -> None:
    # the second step of a march starts from the first one's stages extrapolated: its
    # Jacobian, factored once at that guess, is reused by the corrections after it; the
    # stages it returns are those of Newton's method run to convergence (SciPy's root)
    mechanics, p = setup(forced_double_pendulum())
    q0, v0, t0 = np.array([1.0, 0.5]), np.array([0.7, -1.3]), 0.4
    p0 = np.array(mechanics.legendre(q0, v0, t0, p)[0], dtype=float)
    first = stage_step(mechanics, tableau, q0, p0, t0, DT, p, np.tile(v0, (tableau.stages, 1)),
                       np.zeros((0, 0)))  # fmt: skip
    guess = tableau.extrapolation(1.0) @ first.V
    q1, p1, t1 = first.q, first.momentum, t0 + DT
    step = stage_step(mechanics, tableau, q1, p1, t1, DT, p, guess, np.zeros((0, 0)))
    rows, momentum = stage_residual(mechanics, tableau, q1, p1, t1, p, step.V)
    assert np.abs(rows).max() < 1e-13
    np.testing.assert_allclose(step.momentum, momentum, rtol=0, atol=1e-13)
    assert_as_scipy_root(mechanics, tableau, (q1, p1, t1), p, guess, step.V)
    assert step.evaluations <= 3 * tableau.stages


def test_the_marches_compile_with_loops_neither_vectorized_nor_unrolled():
    # loops of two to six entries: LLVM's overlap checks and eightfold unrolling cost more
    # than the loops (gauss6 a quarter, then a fifth, faster without each); the options are
    # restored for every other compilation
    llvm = pytest.importorskip("llvmlite.binding")
    from numba.core import config as numba_config

    from lagrangian.numerics.fast.discrete_loops import scalar_loops

    if not hasattr(llvm, "create_pipeline_tuning_options"):
        pytest.skip("numba < 0.61: LLVM's legacy pass manager, unrolled as before")
    vectorize = numba_config.LOOP_VECTORIZE
    with scalar_loops():
        assert numba_config.LOOP_VECTORIZE is False
        assert llvm.create_pipeline_tuning_options().loop_unrolling is False
    assert numba_config.LOOP_VECTORIZE is vectorize
    assert llvm.create_pipeline_tuning_options().loop_unrolling is True
