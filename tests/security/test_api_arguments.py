"""Every public function refuses an argument of the wrong kind with a LagrangianError naming
the argument and the fix (never an AttributeError from deep inside), and a System refuses
values that are not finite real numbers: nan, infinities, I, numbers beyond a double."""

import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ArgumentError, LagrangianError
from lagrangian.numerics.export import export

x = sp.Symbol("x")
x_dot = sp.Symbol("x_dot")
m = sp.Symbol("m")


def pendulum() -> lg.System:
    return lg.examples.simple_pendulum()


@pytest.mark.parametrize(
    ("call", "argument"),
    [
        (lambda: lg.derive(None), "derive(system)"),
        (lambda: lg.derive(5), "derive(system)"),
        (lambda: lg.classify(None), "classify(system)"),
        (lambda: lg.eliminate(None, ["x"]), "eliminate(system"),
        (lambda: lg.project_state(None, {}), "project_state(system"),
        (lambda: lg.newton_euler("pendulum"), "newton_euler(system)"),
        (lambda: lg.nielsen_equations(None), "nielsen_equations(subject)"),
        (lambda: lg.constrained_equations(None), "constrained_equations(subject)"),
        (lambda: lg.reaction_wrenches(None, {}), "reaction_wrenches(system"),
        (lambda: lg.particle_constraint_forces(None), "particle_constraint_forces(equations)"),
        (lambda: lg.analyze(None), "an analysis"),
        (lambda: export(None, "c"), "export(subject, language)"),
        (lambda: export(pendulum(), None), "export(subject, language)"),
        (lambda: lg.coordinates(5), "coordinates(names)"),
        (lambda: lg.coordinates([1, 2]), "coordinates(names)"),
        (lambda: lg.velocity(3), "velocity(coordinate)"),
        (lambda: lg.analyze(pendulum(), about=5), "state"),
        (lambda: lg.analyze(pendulum(), parameters=["m"]), "parameters"),
    ],
)
def test_a_wrong_argument_is_an_argument_error_naming_it(call, argument):
    with pytest.raises(ArgumentError) as refused:
        call()
    assert argument in str(refused.value)
    assert isinstance(refused.value, TypeError)  # what Python raises for a wrong argument
    assert refused.value.exit_code == 2  # bad input, to the command line


def test_functions_of_equations_also_take_the_system():
    system = pendulum()
    assert lg.nielsen_equations(system) == lg.nielsen_equations(lg.derive(system))
    assert export(system, "numpy") == export(lg.derive(system), "numpy")
    assert lg.velocity("theta") == sp.Symbol("theta_dot")


@pytest.mark.parametrize(
    ("changes", "field", "message"),
    [
        ({"coordinates": 5}, "coordinates", "not a list of coordinates"),
        ({"particles": [1]}, "particles[0]", "int is not a particle"),
        ({"springs": ["k"]}, "springs[0]", "str is not a spring"),
        ({"circuit": [lg.Particle("p", 1, [x])]}, "circuit[0]", "not a circuit element"),
        ({"parameters": 5}, "parameters", "not a mapping of parameters"),
        ({"initial": [1, 2]}, "initial", "not a mapping"),
        ({"simulation": "fast"}, "simulation", "not a mapping"),
        ({"generalized_forces": [x]}, "generalized_forces", "not a mapping"),
        ({"kinetic": sp.nan}, "kinetic", "undefined or infinite"),
        ({"kinetic": float("nan") * x_dot**2}, "kinetic", "undefined or infinite"),
        ({"kinetic": sp.zoo * x_dot**2}, "kinetic", "undefined or infinite"),
        ({"potential": sp.oo * x**2}, "potential", "undefined or infinite"),
        ({"kinetic": sp.I * x_dot**2}, "kinetic", "complex"),
        ({"potential": sp.Integer(10) ** 400 * x**2}, "potential", "too large for a double"),
        ({"parameters": {m: 10**400}}, "parameters.m", "not a real number"),
        ({"parameters": {m: math.inf}}, "parameters.m", "not a real number"),
        ({"springs": [lg.Spring(None, 1)]}, "springs[0].between", "two points"),
    ],
)
def test_a_system_refuses_values_that_are_not_finite_reals_or_of_the_wrong_kind(
    changes, field, message
):
    values = {"coordinates": [x], "parameters": {m: 1}, "kinetic": m * x_dot**2 / 2}
    values.update(changes)
    with pytest.raises(lg.ModelError, match=message) as refused:
        lg.System(**values)
    assert any(problem.field.startswith(field) for problem in refused.value.problems)


@pytest.mark.parametrize(
    ("arguments", "field"),
    [
        ({"initial": [1, 2]}, "initial"),
        ({"parameters": [1]}, "parameters"),
        ({"t_eval": "a"}, "t_eval"),
        ({"t_eval": [0.0, math.nan]}, "t_eval"),
        ({"t_eval": []}, "t_eval"),
    ],
)
def test_simulate_names_the_wrong_argument(arguments, field):
    with pytest.raises(lg.SimulationInputError) as refused:
        lg.simulate(pendulum(), t_span=1.0, **arguments)
    assert field in {problem.field for problem in refused.value.problems}


@pytest.mark.parametrize(
    "about", [{"theta": math.nan}, {"theta": math.inf}, {"theta": 1j}, {"theta": object()}]
)
def test_analysis_refuses_a_state_that_is_not_real_and_finite(about):
    with pytest.raises(lg.AnalysisError, match=r"state\.theta"):
        lg.analyze(pendulum(), about=about)


def test_an_unknown_name_in_analysis_is_raised_not_buried_in_the_report():
    with pytest.raises(lg.AnalysisError, match="no coordinate, velocity or time named 'foo'"):
        lg.analyze(pendulum(), about={"foo": 1})
    with pytest.raises(lg.AnalysisError, match="no parameter named 'mass'"):
        lg.analyze(pendulum(), parameters={"mass": 1})


def test_every_refusal_is_a_lagrangian_error():
    assert issubclass(ArgumentError, LagrangianError)
