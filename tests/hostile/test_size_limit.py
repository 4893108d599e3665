"""``lagrangian.size_limits``: an expression that grows past the size limit stops the work
with a SizeLimitError naming it and saying what to do; limits nest, come from a keyword, the
command line or the environment; the count agrees with SymEngine's own."""

from __future__ import annotations

import io
import math

import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.errors import ArgumentError, LagrangianError, SizeLimitError
from lagrangian.size_limits import (
    DEFAULT_OPERATIONS,
    ENVIRONMENT,
    active_operations,
    check_size,
    operations,
    size_limit,
)

x = sp.Symbol("x")
# The potential cos(cos(...cos(x))) has 8 operations; its force, a product of the sines of
# every inner level, has 1 + 7 + (1 + 2 + ... + 8) = 44: the expression that grows is the
# forcing, not anything the user wrote.
NESTED = "cos(" * 8 + "x" + ")" * 8
MODEL = f"coordinates: [x]\nkinetic: x_dot**2/2\npotential: {NESTED}\n"


def nested_system() -> lg.System:
    return lg.loads(MODEL)


def test_a_derived_expression_past_the_limit_is_named_with_the_fix():
    system = nested_system()
    with pytest.raises(SizeLimitError) as stopped:
        lg.derive(system, size_limit=30)
    message = str(stopped.value)
    assert "derive: the forcing of the equation of x has 44 operations" in message
    assert "size limit of 30" in message and "size_limit=" in message
    assert isinstance(stopped.value, (LagrangianError, MemoryError))
    assert stopped.value.exit_code == 1
    # nothing was remembered by the refused derivation: the default limit derives it
    eom = lg.derive(system)
    assert operations(eom.forcing[0]) == 44
    assert operations(lg.loads(MODEL).potential) == 8


def test_the_count_is_symengines_count_of_operations():
    y, z = sp.symbols("y z")
    corpus = [
        x - y,
        x / y,
        sp.sqrt(x) * sp.Rational(3, 2),
        1 / (x + y) ** 2,
        x * y * z + 2 * x - 3,
        (x + y) * (x - y),
        sp.sin(x - y) * sp.cos(x) ** 2 - sp.exp(-x / 2),
        sp.parse_expr(NESTED).diff(x),
    ]
    for expr in corpus:
        assert operations(expr) == se.count_ops(se.sympify(expr)), expr
        assert operations(se.sympify(expr)) == se.count_ops(se.sympify(expr)), expr


def test_limits_nest_and_the_smallest_applies():
    assert active_operations() == DEFAULT_OPERATIONS
    with size_limit(100):
        with size_limit():
            assert active_operations() == 100  # no number: the outer limit as it is
        with size_limit(1000):
            assert active_operations() == 100
        with size_limit(10):
            assert active_operations() == 10
            with pytest.raises(SizeLimitError, match="the kinetic energy has 11 operations"):
                check_size(sp.Add(*sp.symbols("a:12")), "the kinetic energy")
    with size_limit(math.inf):
        check_size(sp.Add(*sp.symbols("a:12")), "anything")


@pytest.mark.parametrize("value", [0, -5, math.nan, "big", True])
def test_a_limit_that_is_not_a_positive_number_is_refused(value):
    with pytest.raises(ArgumentError, match="size_limit"):
        lg.derive(nested_system(), size_limit=value)


def test_the_environment_sets_the_limit_and_its_message_names_it(monkeypatch):
    monkeypatch.setenv(ENVIRONMENT, "30")
    with pytest.raises(SizeLimitError, match=f"raise {ENVIRONMENT}"):
        lg.derive(nested_system())
    monkeypatch.setenv(ENVIRONMENT, "none")
    assert active_operations() == math.inf
    lg.derive(nested_system())
    monkeypatch.setenv(ENVIRONMENT, "lots")
    with pytest.raises(ArgumentError, match=ENVIRONMENT):
        active_operations()


@pytest.mark.parametrize(
    "argv",
    [["derive", "-", "--size-limit", "30"], ["--size-limit", "30", "derive", "-"]],
    ids=["after the command", "before it"],
)
def test_the_command_line_option_stops_the_command_with_a_message(argv, capsys, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO(MODEL))
    assert main(argv) == 1
    error = capsys.readouterr().err
    assert "the forcing of the equation of x has 44 operations" in error
    assert "give a larger --size-limit" in error and "size_limit=" not in error
    assert "internal error" not in error


@pytest.mark.parametrize(("value", "code"), [("0", 2), ("many", 2), ("none", 0), ("44", 0)])
def test_the_option_takes_a_positive_whole_number_or_none(value, code, capsys, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO(MODEL))
    if code == 2:  # a usage error, as argparse ends it
        with pytest.raises(SystemExit) as ended:
            main(["derive", "-", "--size-limit", value])
        assert ended.value.code == 2
        assert "--size-limit" in capsys.readouterr().err
    else:
        assert main(["derive", "-", "--size-limit", value]) == 0


def test_a_command_past_the_default_time_limit_speaks_of_the_option(capsys, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_TIME_LIMIT", "0.5")
    assert main(["derive", "examples/n_link_pendulum:150"]) == 1
    error = capsys.readouterr().err
    assert "--timeout" in error and "time_limit=" not in error, error


def test_a_constraint_acceleration_term_past_the_limit_is_named():
    # a System of its own: derivations and multiplier forms are remembered per System object
    system = lg.examples.get("rolling_disc")().replace(description="a fresh copy")
    lg.derive(system)  # within the default limit
    with size_limit(4), pytest.raises(SizeLimitError) as stopped:
        lg.constrained_equations(system)
    assert "the acceleration term gamma of constraints[0] has 5 operations" in str(stopped.value)
    gamma = lg.constrained_equations(system).gamma  # nothing kept of the refused attempt
    assert operations(gamma[0]) == 5
