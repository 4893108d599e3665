"""One integrator protocol: options that do not apply are refused by name, method names live in
one table, and bad input anywhere in the simulation layer is a SimulationInputError (a
ValueError, exit code 2) while a failed integration stays a SimulationError."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.simulation.methods import METHODS, TABLE, names_where, suggest_method
from lagrangian.simulation.options import Options

SPRING = {"x": 0.1, "x_dot": 0.0}


def cartesian_pendulum(*extra: lg.Constraint) -> lg.System:
    x, y, l = sp.symbols("x y l")
    return lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        particles=[lg.Particle("bob", 1, (x, y))],
        gravity=(0, -9.81),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2), *extra],
    )


ON_THE_CIRCLE = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}


def refused(match: str, *args: object, **kwargs: object) -> SimulationInputError:
    """The SimulationInputError of simulate(*args, **kwargs), checked to be bad input."""
    with pytest.raises(SimulationInputError, match=match) as caught:
        lg.simulate(*args, **kwargs)  # type: ignore[arg-type]
    assert isinstance(caught.value, ValueError) and caught.value.exit_code == 2
    return caught.value


# --- options that do not apply ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("options", "match"),
    [
        (
            {"method": "RK4", "dt": 0.01, "rtol": 1e-9},
            r"rtol: rtol steers .* not RK4 — remove rtol, or",
        ),
        ({"method": "variational", "dt": 0.01, "atol": 1e-9}, r"atol: .* not variational"),
        ({"method": "RK4", "dt": 0.01, "max_step": 0.1}, r"max_step: .* not RK4"),
        ({"method": "DOP853", "dt": 0.01}, r"dt: dt is the step of the fixed-step RK4, not"),
        ({"baumgarte": (1.0, 1.0)}, r"baumgarte: .*this system has none — remove baumgarte="),
        ({"project_initial": True}, r"project_initial: .* has none — remove project_initial"),
        ({"project_steps": True}, r"project_steps: .* has none — remove project_steps"),
    ],
)
def test_an_option_that_does_not_apply_is_refused_by_name(options: dict, match: str) -> None:
    refused(match, lg.examples.mass_on_spring(), SPRING, 1.0, **options)


def test_constraint_options_that_do_not_apply_to_the_method_are_refused() -> None:
    refused(
        r"baumgarte: the method 'variational' holds the constraints exactly",
        cartesian_pendulum(),
        ON_THE_CIRCLE,
        0.1,
        method="variational",
        dt=0.01,
        baumgarte=(5.0, 5.0),
    )
    refused(
        r"project_steps works with the methods RK45, RK23, DOP853, RK4, not variational",
        cartesian_pendulum(),
        ON_THE_CIRCLE,
        0.1,
        method="variational",
        dt=0.01,
        project_steps=True,
    )


def test_every_problem_of_options_and_inputs_is_reported_at_once() -> None:
    error = refused(
        r"Cannot simulate \(3 problems\)",
        lg.examples.mass_on_spring(),
        {"xx": 1.0, "x_dot": 0.0},
        1.0,
        method="RK4",
        dt=0.01,
        rtol=1e-9,
        baumgarte=(1, 1),
    )
    assert sorted(p.field for p in error.problems) == ["baumgarte", "initial", "rtol"]


def test_settings_of_the_system_that_do_not_apply_are_left_out() -> None:
    # the model's tolerances belong to its adaptive default; a call choosing RK4 is not wrong
    system = lg.examples.mass_on_spring().replace(simulation={"t_end": 1.0, "rtol": 1e-9})
    run = lg.simulate(system, SPRING, method="RK4", samples=101)
    assert run.success and run.method == "RK4"


def test_an_unknown_step_keyword_is_a_type_error_with_the_closest_name() -> None:
    with pytest.raises(TypeError, match=r"simulate\(\) got an unexpected keyword .*'rtl'.*'rtol'"):
        lg.simulate(lg.examples.mass_on_spring(), SPRING, 1.0, rtl=1e-9)  # type: ignore[call-arg]
    with pytest.raises(
        TypeError, match=r"simulate_batch\(\) got an unexpected keyword argument 'sample'"
    ):
        lg.simulate_batch(lg.examples.mass_on_spring(), SPRING, 1.0, sample=3)  # type: ignore[call-arg]


def test_options_are_a_frozen_record_checked_at_construction() -> None:
    options = Options(method="DOP853", constraints=tuple(cartesian_pendulum().constraints))
    assert options.gains == (0.0, 0.0) and options.spec.takes_tolerances
    with pytest.raises(AttributeError):
        options.method = "RK4"  # type: ignore[misc]
    with pytest.raises(SimulationInputError, match=r"unknown backend 'gpu'"):
        Options(backend="gpu")
    with pytest.raises(SimulationInputError, match=r"method: unknown method 'DOP54'.*'DOP853'"):
        Options(method="DOP54")


# --- one table of methods ---------------------------------------------------------------------


def test_the_method_table_is_the_one_list_of_names() -> None:
    assert set(METHODS) | {"variational", "gauss4", "gauss6"} == set(TABLE)
    assert names_where("compiled") == ("RK45", "DOP853", "RK4")
    assert names_where("explicit") == ("RK45", "RK23", "DOP853", "RK4")
    assert names_where("takes_step") == ("RK4", "variational", "gauss4", "gauss6")
    assert "did you mean 'variational'" in suggest_method("Variational")


@pytest.mark.parametrize("name", list(TABLE))
def test_every_method_of_the_table_simulates(name: str) -> None:
    step = {"dt": 1e-3} if TABLE[name].takes_step else {}
    run = lg.simulate(lg.examples.mass_on_spring(), SPRING, 1.0, method=name, samples=5, **step)
    omega = np.sqrt(10.0)  # k = 10, m = 1
    np.testing.assert_allclose(run["x"], 0.1 * np.cos(omega * run.t), atol=1e-5)
    assert run.method == name and run.success


def test_a_batch_takes_the_methods_of_its_loops_and_no_unilateral_constraints() -> None:
    with pytest.raises(SimulationInputError, match=r"simulate_batch has no method 'Radau'"):
        lg.simulate_batch(lg.examples.mass_on_spring(), SPRING, 1.0, method="Radau")
    y = sp.Symbol("y")
    floor = cartesian_pendulum(lg.Unilateral(y + 0.5, name="floor"))
    with pytest.raises(SimulationInputError, match=r"does not integrate unilateral constraints"):
        lg.simulate_batch(floor, {**ON_THE_CIRCLE, "x": [1.0, 1.0]}, 1.0)
    batch = lg.simulate_batch(cartesian_pendulum(), {**ON_THE_CIRCLE, "x": [1.0, 1.0]}, 1.0)
    assert batch.multiplier_names == ("lambda_1",)


# --- bad input is a SimulationInputError everywhere -----------------------------------------


def test_bad_input_on_every_path_is_a_simulation_input_error() -> None:
    refused("needs a System or the EquationsOfMotion", "spring", {}, 1.0)
    refused(r"gimbal lock .* at the start", lg.examples.heavy_symmetric_top(), {"theta": 0.0}, 1.0)
    refused(r"violates the constraints", cartesian_pendulum(), {**ON_THE_CIRCLE, "x": 2.0}, 0.1)
    refused(
        r"violates the constraints",
        cartesian_pendulum(),
        {**ON_THE_CIRCLE, "x": 2.0},
        0.1,
        method="variational",
        dt=0.01,
    )
    y = sp.Symbol("y")
    floor = cartesian_pendulum(lg.Unilateral(y + 0.5, name="floor"))
    refused(r"violates the unilateral constraint .*floor", floor, {**ON_THE_CIRCLE, "y": -0.9}, 0.1)
    refused(
        r"does not locate events",
        lg.examples.mass_on_spring(),
        SPRING,
        1.0,
        method="variational",
        dt=0.01,
        events=[lambda t, q, v: q[0]],
    )
    refused(r"conserved\.L", lg.examples.mass_on_spring(), SPRING, 1.0, conserved={"L": "q**"})
    with pytest.raises(SimulationInputError, match=r"has 3 values, but"):
        lg.simulate_batch(lg.examples.mass_on_spring(), {"x": [0.1, 0.2], "x_dot": [0, 0, 0]}, 1.0)
    with pytest.raises(SimulationInputError, match=r"discrete action of a constrained system"):
        lg.simulation.stationary_path(cartesian_pendulum(), [1.0, 0.0], [0.0, -1.0], 1.0)
    with pytest.raises(SimulationInputError, match=r"nodes: 1 is not an integer >= 2"):
        lg.simulation.stationary_path(lg.examples.mass_on_spring(), [0.1], [0.0], 1.0, nodes=1)


def test_a_failed_integration_is_not_bad_input() -> None:
    x, x_dot = sp.symbols("x x_dot")
    runaway = lg.System(coordinates=[x], kinetic=x_dot**2 / 2, potential=-(x**4))
    with pytest.raises(lg.SimulationError, match="Integration failed") as caught:
        lg.simulate(runaway, {"x": 1.0, "x_dot": 0.0}, 5.0)
    assert not isinstance(caught.value, ValueError) and caught.value.exit_code == 1


@pytest.mark.parametrize(
    ("keywords", "pattern"),
    [
        ({"rtol": 1.0}, r"rtol: rtol=1 lets each step's error be as large as the values"),
        ({"rtol": 1e300}, r"rtol: rtol=1e\+300 .* pass a value below 1, such as rtol=1e-08"),
        ({"atol": 1e300}, r"atol: atol=1e\+300 lets each step's error be as large as the state"),
        ({"method": "RK4", "dt": 2.0}, r"dt: dt=2 is longer than the time span, 1"),
    ],
    ids=["rtol 1", "rtol 1e300", "atol 1e300", "dt past the span"],
)
def test_meaningless_tolerances_and_steps_are_refused_by_name(keywords, pattern):
    with pytest.raises(lg.SimulationInputError, match=pattern):
        lg.simulate(lg.examples.mass_on_spring(), {"x": 0.1, "x_dot": 0.0}, 1.0, **keywords)


def test_atol_is_measured_against_the_scale_of_the_state():
    # atol has the units of the state: a state of size 1e6 may take atol = 10
    run = lg.simulate(lg.examples.mass_on_spring(), {"x": 1e6, "x_dot": 0.0}, 1.0, atol=10.0)
    assert run.success
    with pytest.raises(lg.SimulationInputError, match=r"its scale, .* is 1e\+06"):
        lg.simulate(lg.examples.mass_on_spring(), {"x": 1e6, "x_dot": 0.0}, 1.0, atol=1e6)
