"""Resting on a kink of the potential, one budget for a switched run, a state the equations
are not finite at.

References (hand derivations): in the V-shaped well V = k|x| at rest at x = 0 the force
-k sign(x) pushes towards the kink from both sides, so x = 0 is an equilibrium (Filippov's
solution of second order, u = x = 0 kept with du/dt = 0); under an added force F(t) = 2t
(k = m = 1) the mass stays until F reaches k at t = 1/2, then x_ddot = 2t - 1, so
x = (t - 1/2)^3 / 3.  From x0 = 1 at rest the well's half period is 2 sqrt(2): over 20 time
units the motion crosses the kink seven times, each crossing a piece of the run.
"""

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import SimulationInputError


def well(potential: str, x0: float = 0.0, extra: str = "") -> lg.System:
    return lg.loads(
        f"coordinates: [x]\nkinetic: x_dot**2/2\npotential: {potential}\n{extra}"
        f"initial: {{x: {x0}, x_dot: 0}}\n"
    )


@pytest.mark.parametrize(
    ("potential", "x0"), [("Abs(x)", 0.0), ("x*sign(x)", 0.0), ("Abs(x - 1)", 1.0)]
)
def test_rest_at_the_kink_of_a_v_shaped_well_stays_at_rest(potential, x0):
    run = lg.simulate(well(potential, x0), t_span=10, samples=11)
    assert run.status == "success"
    np.testing.assert_array_equal(run["x"], x0)
    np.testing.assert_array_equal(run["x_dot"], 0.0)
    assert run.events[0].name.endswith(": rest")


def test_a_force_below_the_kink_holds_it_and_above_it_leaves():
    held = lg.simulate(well("Abs(x) + x/2"), t_span=5, samples=6)
    np.testing.assert_array_equal(held["x"], 0.0)
    pushed = lg.simulate(well("Abs(x) + 3*x/2"), t_span=2, samples=5)
    # x_ddot = -sign(x) - 3/2 = 1 - 3/2 on the minus side: x = -t^2 / 4
    np.testing.assert_allclose(pushed["x"], -(pushed.t**2) / 4, atol=1e-9)


def test_a_growing_force_leaves_the_kink_when_it_exceeds_its_slope():
    system = well("Abs(x)", extra="generalized_forces: {x: 2*t}\n")
    run = lg.simulate(system, t_span=2, samples=21)
    expected = np.where(run.t > 0.5, (run.t - 0.5) ** 3 / 3, 0.0)
    np.testing.assert_allclose(run["x"], expected, atol=1e-9)
    leave = [event for event in run.events if event.name.endswith("plus")]
    assert leave and leave[0].t == pytest.approx(0.5, abs=1e-9)


def test_a_switched_run_spends_one_step_budget_over_all_its_pieces():
    system = well("Abs(x)", x0=1.0)
    whole = lg.simulate(system, t_span=20)
    crossings = [event for event in whole.events if event.name.startswith("switch")]
    assert len(crossings) == 7  # t = 2 sqrt(2) (2k + 1)/2 ... below 20
    steps = len(whole.t) - 1  # every step is a row without samples
    budget = steps // 2  # enough for a few pieces, not for all of them
    cut = lg.simulate(system, t_span=20, max_steps=budget, raise_on_failure=False)
    assert cut.status == "failed"
    assert f"step budget of {budget:,} steps" in cut.message
    assert len(cut.t) - 1 <= budget


def test_a_state_where_the_equations_are_not_finite_is_refused_by_name():
    with pytest.raises(SimulationInputError, match=r"at the initial state .* not a finite number"):
        lg.simulate(well("x**4/4"), {"x": 1e200}, t_span=1)  # x_ddot = -x**3
    with pytest.raises(SimulationInputError, match=r"division by zero"):
        lg.simulate(well("x**2/2 + x/(sqrt(x**2) - Abs(x))", x0=1.0), t_span=1, max_steps=1000)
