"""Constraint declarations from Python: canonical values, and ill-formed constraints refused
by the System with the constraint named."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest
import sympy as sp

import lagrangian as lg
import lagrangian.constraints
from lagrangian.errors import ModelError

x, y, phi, l = sp.symbols("x y phi l")
x_dot, y_dot = sp.symbols("x_dot y_dot")


def system(*constraints: object) -> lg.System:
    return lg.System(coordinates=[x, y, phi], parameters={l: 1.0}, constraints=constraints)


def test_declarations_are_canonical_values() -> None:
    X = sp.Function("x")(lg.t)
    Y = sp.Function("y")(lg.t)
    length = sp.Symbol("l", positive=True)  # the parameter's own object is the canonical one
    built = lg.System(
        coordinates=[X, Y, phi],
        parameters=[length],
        constraints=[
            lg.Holonomic(sp.Eq(X**2 + Y**2, sp.Symbol("l") ** 2), name="rod"),
            lg.VelocityConstraint(X.diff(lg.t) * sp.sin(phi) - Y.diff(lg.t) * sp.cos(phi)),
            lg.Unilateral(Y + 2),
        ],
    )
    assert built.constraints == (
        lg.Holonomic(x**2 + y**2 - length**2, name="rod"),
        lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi)),
        lg.Unilateral(y + 2),
    )
    assert [c.kind for c in built.constraints] == ["holonomic", "velocity", "unilateral"]


def test_a_single_constraint_and_replace_keep_the_constraints() -> None:
    one = lg.System(coordinates=[x, y], constraints=lg.Holonomic(x - y))
    assert one.constraints == (lg.Holonomic(x - y),)
    assert one.replace(name="renamed").constraints == one.constraints
    assert lg.System(coordinates=[x]).constraints == ()


@pytest.mark.parametrize(
    ("constraint", "match"),
    [
        (
            lg.Holonomic(l - 1, name="loose"),
            r"constraint 'loose' \(l - 1 = 0\) involves no coordinate",
        ),
        (lg.Unilateral(l + 2), r"the constraint \(l \+ 2 >= 0\) involves no coordinate"),
        (lg.VelocityConstraint(x_dot**2 + y_dot), r"\(x_dot\*\*2 \+ y_dot = 0\) is not linear in"),
        (lg.VelocityConstraint(x_dot * y_dot), r"is not linear in the velocities"),
        (lg.VelocityConstraint(sp.sin(x_dot)), r"is not linear in the velocities"),
        (lg.VelocityConstraint(x - 1), r"uses no velocity .* declare it as one"),
        (lg.Holonomic(x * x_dot, name="h"), r"'h' is holonomic but uses the velocity x_dot"),
        (lg.Unilateral(x_dot + y_dot), r"is unilateral but uses the velocities x_dot, y_dot"),
        (lg.Holonomic(x - sp.Symbol("k")), r"unknown name 'k'"),
        (lg.Holonomic(sp.Symbol("x_ddot")), r"the acceleration x_ddot may not appear"),
        ("x - 1", r"str is not a constraint"),
    ],
)
def test_ill_formed_constraints_are_refused(constraint: object, match: str) -> None:
    with pytest.raises(ModelError, match=match) as caught:
        system(constraint)
    assert caught.value.problems[0].field.startswith("constraints[0]")


def test_every_problem_at_once_and_duplicate_names() -> None:
    with pytest.raises(ModelError, match=r"2 problems") as caught:
        system(lg.Holonomic(x, name="a"), lg.Holonomic(y, name="a"), lg.Holonomic(l))
    fields = [p.field for p in caught.value.problems]
    assert fields == ["constraints[1].name", "constraints[2].expression"]


def test_linear_velocity_constraints_with_time_and_coordinates_are_accepted() -> None:
    knife = system(lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi) + lg.t * x))
    assert knife.constraints[0].kind == "velocity"


def _modules() -> list[str]:
    package = lagrangian.constraints
    found = [f"{package.__name__}.{m.name}" for m in pkgutil.iter_modules(package.__path__)]
    return [package.__name__, "lagrangian.model.constraints", *found]


@pytest.mark.parametrize("name", _modules())
def test_the_docstring_examples_run(name: str) -> None:
    result = doctest.testmod(importlib.import_module(name))
    assert result.failed == 0
