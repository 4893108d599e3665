"""backend="numba", kept for one release as another name of the default backend: the same
trajectory as the default (the C loop runs RK45, DOP853 and RK4), a message that says so, and
the refusals of what no backend does."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.numerics.fast.source import values_source

SPRING = {"x": 0.1, "x_dot": 0.0}
ALIAS = "backend='numba' is another name of the default backend"


@pytest.mark.parametrize(
    "options",
    [
        {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10},
        {"method": "RK4", "dt": 0.01},
        {"method": "Radau"},  # SciPy's solver, as with the default backend
    ],
)
def test_backend_numba_runs_as_the_default_and_says_so(options: dict[str, object]) -> None:
    spring = lg.examples.mass_on_spring()
    default = lg.simulate(spring, SPRING, 2.0, samples=21, **options)
    alias = lg.simulate(spring, SPRING, 2.0, samples=21, backend="numba", **options)
    np.testing.assert_array_equal(alias.q, default.q)
    assert ALIAS in alias.message and ALIAS not in default.message


def test_backend_numba_takes_events_and_constraints_now() -> None:
    x, y, l = sp.symbols("x y l")
    pendulum = lg.System(
        coordinates=[x, y],
        parameters={l: 1.0},
        particles=[lg.Particle("bob", 1, (x, y))],
        gravity=(0, -9.81),
        constraints=[lg.Holonomic(x**2 + y**2 - l**2)],
    )
    start = {"x": 1.0, "y": 0.0, "x_dot": 0.0, "y_dot": 0.0}
    run = lg.simulate(pendulum, start, 1.0, events=[lambda t, q, v: q[1] + 0.5], backend="numba")
    reference = lg.simulate(pendulum, start, 1.0, events=[lambda t, q, v: q[1] + 0.5])
    assert [e.t for e in run.events] == [e.t for e in reference.events]


def test_a_batch_with_backend_numba_is_the_default_batch() -> None:
    spring = lg.examples.mass_on_spring()
    initial = {"x": [0.1, 0.2], "x_dot": 0.0}
    default = lg.simulate_batch(spring, initial, 1.0, method="RK4", dt=0.01, samples=5)
    alias = lg.simulate_batch(
        spring, initial, 1.0, method="RK4", dt=0.01, samples=5, backend="numba", workers=2
    )
    np.testing.assert_array_equal(alias.q, default.q)
    assert alias.backend == "numba" and alias.status == default.status


def test_unknown_backends_and_the_variational_alias_are_refused_by_name() -> None:
    spring = lg.examples.mass_on_spring()
    with pytest.raises(lg.SimulationError, match="unknown backend 'cuda'"):
        lg.simulate(spring, SPRING, 1.0, backend="cuda")
    with pytest.raises(lg.SimulationError, match="remove backend='numba'"):
        lg.simulate(spring, SPRING, 1.0, method="variational", dt=0.01, backend="numba")


def test_the_generated_source_refuses_a_function_without_numeric_form() -> None:
    x = sp.Symbol("x")
    with pytest.raises(lg.SimulationError, match=r"besselj.*backend='numpy'"):
        values_source([x], [sp.besselj(0, x)])
