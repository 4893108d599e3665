"""Runs that cannot end in reasonable time, or stop being finite, end with a reason and their
rows: step and wall-time budgets, stiffness on an explicit method, steps too small to finish,
NaN or inf in a column."""

import numpy as np
import pytest
from scipy.integrate import DOP853, RK45

import lagrangian as lg
from lagrangian.errors import SimulationError, SimulationInputError
from lagrangian.io.load import loads
from lagrangian.simulation.integrators.budget import Budget, step_eigenvalue

VAN_DER_POL = """
name: van der Pol oscillator
coordinates: [x]
parameters: {mu: 10000}
kinetic: x_dot**2/2
potential: x**2/2
generalized_forces: {x: mu*(1 - x**2)*x_dot}
initial: {x: 2, x_dot: 0}
"""


def test_a_stiff_problem_on_an_explicit_method_stops_with_the_advice():
    system = loads(VAN_DER_POL)
    with pytest.raises(SimulationError, match=r"stiff for RK45.*Radau"):
        lg.simulate(system, t_span=3000.0)
    kept = lg.simulate(system, t_span=3000.0, raise_on_failure=False)
    assert kept.status == "failed" and len(kept.t) > 1
    assert np.all(np.isfinite(kept.q))
    # the implicit method the message names does the run (van der Pol's relaxation period
    # is about (3 - 2 ln 2) mu = 1.61e4 for large mu, so x stays on the slow branch near 2)
    done = lg.simulate(system, t_span=3000.0, method="Radau")
    assert done.success and 1.0 < done["x"][-1] < 2.0


def test_a_long_smooth_run_is_not_taken_for_stiff():
    pendulum = lg.examples.simple_pendulum()
    run = lg.simulate(pendulum, {"theta": 1.0}, 2000.0, method="DOP853", rtol=1e-10)
    assert run.success and "stiff" not in run.message
    run = lg.simulate(pendulum, {"theta": 1.0}, 300.0, method="RK45")
    assert run.success and "stiff" not in run.message


def test_the_step_budget_and_the_wall_time_budget():
    pendulum = lg.examples.simple_pendulum()
    used_up = "the step budget of 50 steps is used up — pass max_steps=500 to allow more steps."
    with pytest.raises(SimulationError, match=used_up):
        lg.simulate(pendulum, {"theta": 1.0}, 100.0, max_steps=50)
    kept = lg.simulate(pendulum, {"theta": 1.0}, 100.0, max_steps=50, raise_on_failure=False)
    assert kept.status == "failed" and 0 < kept.t[-1] < 100.0 and used_up in kept.message
    with pytest.raises(
        SimulationError, match=r"wall-time budget .* pass a larger max_wall_time=\.\.\."
    ):
        lg.simulate(pendulum, {"theta": 1.0}, 1000.0, max_wall_time=1e-9)


@pytest.mark.parametrize(
    ("keywords", "field"),
    [
        ({"method": "RK4", "dt": 1e-300}, "dt"),
        ({"max_step": 1e-300}, "max_step"),
        ({"max_steps": "many"}, "max_steps"),
        ({"max_steps": 0}, "max_steps"),
        ({"max_wall_time": -1.0}, "max_wall_time"),
        ({"samples": 10**12}, "samples"),  # refused before numpy allocates anything
        ({"samples": 2**70}, "samples"),
        ({"samples": 30_000_000}, "GiB"),  # the memory estimate of the rows
        ({"rtol": 1e-300}, "rtol"),  # SciPy would clip it with a warning only
    ],
)
def test_budgets_that_cannot_work_are_refused_before_the_run(keywords, field):
    with pytest.raises(SimulationInputError, match=field):
        lg.simulate(lg.examples.simple_pendulum(), {"theta": 1.0}, 10.0, **keywords)


def test_a_column_that_stops_being_finite_ends_the_run_there():
    # exp(-x**2) underflows to 0 once x > 27, and log(0) makes the energy infinite
    system = loads(
        "name: overflow\ncoordinates: [x]\nparameters: {m: 1}\nkinetic: m*x_dot**2/2\n"
        "potential: x**2 + log(exp(-x**2))\n"
    )
    with pytest.raises(SimulationError, match="energy E = T \\+ V is not a finite number"):
        lg.simulate(system, {"x": 0.0, "x_dot": 100.0}, 1.0, samples=101)
    kept = lg.simulate(system, {"x": 0.0, "x_dot": 100.0}, 1.0, samples=101, raise_on_failure=False)
    assert kept.status == "failed"
    assert np.all(np.isfinite(kept.energy)) and 0.25 < kept.t[-1] < 0.3


def test_a_collapsed_step_size_stops_the_run_at_the_singularity():
    # a particle falling from rest at x = 1 into -k/x hits x = 0 at t = pi / (2 sqrt(2 k/m));
    # LSODA creeps towards it at ever smaller steps instead of failing
    system = loads(
        "name: fall\ncoordinates: [x]\nparameters: {m: 1, k: 1}\nkinetic: m*x_dot**2/2\n"
        "potential: -k/x\n"
    )
    kept = lg.simulate(
        system, {"x": 1.0, "x_dot": 0.0}, 3.0, method="LSODA", raise_on_failure=False
    )
    assert kept.status == "failed" and "collapsed" in kept.message
    assert kept.t[-1] == pytest.approx(np.pi / (2 * np.sqrt(2)), rel=1e-6)


@pytest.mark.parametrize("solver", [RK45, DOP853])
def test_the_step_eigenvalue_is_h_lambda_on_a_scalar_linear_problem(solver):
    # x' = -lam x: f(y1) - f(y_j) = -lam (y1 - y_j) exactly, so the estimate is h lam
    lam = 50.0
    stepping = solver(lambda t, x: -lam * x, 0.0, np.array([1.0]), 1.0, rtol=1e-6, atol=1e-9)
    for _ in range(5):
        t_old, y_old = stepping.t, stepping.y.copy()
        stepping.step()
        h = stepping.t - t_old
        assert step_eigenvalue(stepping, t_old, y_old) == pytest.approx(h * lam, rel=1e-9)


def test_the_stiffness_window_counts_the_steps_near_the_edge_as_they_come_and_go():
    # the running count of steps near the edge equals a recount of the window, step by step
    A = np.array([[-1000.0, 0.0], [0.0, -1.0]])
    stepping = RK45(lambda t, x: A @ x, 0.0, np.array([1.0, 1.0]), 50.0, rtol=1e-6, atol=1e-9)
    budget = Budget("RK45")
    for _ in range(200):
        t_old, y_old = stepping.t, stepping.y.copy()
        stepping.step()
        budget.spend(stepping, t_old, y_old, stepping.t_bound)
        if budget.stiff_since is not None:
            break
        assert budget._near == sum(budget._recent)
    assert budget.stiff_since is not None  # |h lambda| held near 3.3 by stability
