"""Poincaré sections against independent references: the crossing times of SciPy's solve_ivp
with an event on the same equations, the energy surface every point lies on, and the closed
form of two uncoupled oscillators (each point on an ellipse, at a time known exactly)."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ExpressionError, SimulationInputError

TIGHT = {"method": "DOP853", "rtol": 1e-12, "atol": 1e-12}
ENERGY = 1 / 8  # the Hénon–Heiles example's start is on this energy surface


def henon_heiles_rates(t: float, state: np.ndarray) -> np.ndarray:
    """x_ddot = -x - 2 x y, y_ddot = -y - x^2 + y^2: the gradient of V written out here."""
    x, y, x_dot, y_dot = state
    return np.array([x_dot, y_dot, -x - 2 * x * y, -y - x**2 + y**2])


def henon_heiles_energy(x, y, x_dot, y_dot):
    return (x_dot**2 + y_dot**2) / 2 + (x**2 + y**2) / 2 + x**2 * y - y**3 / 3


def test_the_crossing_times_are_those_of_solve_ivp_with_an_event() -> None:
    system = lg.examples.henon_heiles()
    section = lg.poincare_section(system, "x", t_span=40.0, **TIGHT)
    start = {s.name: value for s, value in system.initial.items()}
    x0 = [start[name] for name in ("x", "y", "x_dot", "y_dot")]

    def plane(t: float, state: np.ndarray) -> float:
        return state[0]

    plane.direction = 1.0  # type: ignore[attr-defined]
    reference = solve_ivp(henon_heiles_rates, (0.0, 40.0), x0, events=plane, **TIGHT)
    assert len(section.t) == len(reference.t_events[0]) > 5
    assert np.allclose(section.t, reference.t_events[0], rtol=0, atol=1e-8)
    assert np.allclose(section.points, reference.y_events[0], rtol=0, atol=1e-8)


def test_every_point_lies_on_the_section_and_on_the_energy_surface() -> None:
    section = lg.poincare_section(lg.examples.henon_heiles(), "x", t_span=400.0, **TIGHT)
    assert len(section.t) > 50
    assert np.max(np.abs(section["x"])) < 1e-10
    assert np.all(section["x_dot"] > 0)  # crossed rising
    energy = henon_heiles_energy(*(section[n] for n in ("x", "y", "x_dot", "y_dot")))
    assert np.max(np.abs(energy - ENERGY)) < 1e-9
    falling = lg.poincare_section(
        lg.examples.henon_heiles(), "x", t_span=100.0, direction="falling", **TIGHT
    )
    assert np.all(falling["x_dot"] < 0)


UNCOUPLED = """
coordinates: [x, y]
parameters: {w: 1.4142135623730951}
kinetic: (x_dot**2 + y_dot**2)/2
potential: (x**2 + w**2*y**2)/2
initial: {x: 0.5, y: 0.3, x_dot: 0.0, y_dot: 0.2}
"""


def test_two_uncoupled_oscillators_cross_where_their_closed_form_says() -> None:
    # x = 0.5 cos t rises through 0 at t_k = 3 pi / 2 + 2 pi k; y = 0.3 cos(w t) +
    # (0.2 / w) sin(w t) keeps its own energy, so the points lie on the ellipse
    # w^2 y^2 + y_dot^2 = w^2 0.3^2 + 0.2^2, spread over it as w is incommensurate with 1
    w = np.sqrt(2.0)
    section = lg.poincare_section(lg.loads(UNCOUPLED), "x", t_span=200.0, **TIGHT)
    k = np.arange(len(section.t))
    times = 1.5 * np.pi + 2 * np.pi * k
    assert len(section.t) == np.sum(times <= 200.0) > 25
    assert np.allclose(section.t, times, rtol=0, atol=1e-9)
    y = 0.3 * np.cos(w * times) + (0.2 / w) * np.sin(w * times)
    y_dot = -0.3 * w * np.sin(w * times) + 0.2 * np.cos(w * times)
    assert np.allclose(section["y"], y, atol=1e-9)
    assert np.allclose(section["y_dot"], y_dot, atol=1e-9)
    assert np.allclose(w**2 * section["y"] ** 2 + section["y_dot"] ** 2, 2 * 0.09 + 0.04)
    assert section.axes == ("y", "y_dot")


def test_a_section_that_is_no_expression_of_the_state_is_refused() -> None:
    system = lg.examples.henon_heiles()
    with pytest.raises(ExpressionError, match="unknown name 'q'"):
        lg.poincare_section(system, "x + q", t_span=1.0)
    with pytest.raises(SimulationInputError, match="unknown direction 'up'"):
        lg.poincare_section(system, "x", t_span=1.0, direction="up")


def test_simulate_writes_and_plots_the_section(tmp_path, capsys) -> None:
    from lagrangian.cli.main import main

    out, plot = tmp_path / "run.csv", tmp_path / "run.png"
    code = main(["simulate", "examples/henon_heiles", "--t-end", "100", "--poincare", "x",
                 "--out", str(out), "--plot", str(plot)])  # fmt: skip
    said = capsys.readouterr()
    assert code == 0, said.err
    assert "Poincaré section points (x = 0, rising) written to" in said.out
    with open(tmp_path / "run.poincare.csv", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert list(rows[0]) == ["t", "x", "y", "x_dot", "y_dot"] and len(rows) > 10
    energies = [henon_heiles_energy(*(float(r[n]) for n in ("x", "y", "x_dot", "y_dot")))
                for r in rows]  # fmt: skip
    assert max(abs(e - ENERGY) for e in energies) < 1e-7
    assert (tmp_path / "run.poincare.png").stat().st_size > 0
    code = main(["simulate", "examples/henon_heiles", "--poincare", "x", "--poincare-axes",
                 "y,z", "--out", str(out)])  # fmt: skip
    assert code == 2 and "z: not a column of the section" in capsys.readouterr().err
    code = main(["simulate", "examples/henon_heiles", "--poincare-axes", "y,y_dot"])
    assert code == 2 and "add --poincare EXPR" in capsys.readouterr().err
    code = main(["simulate", "examples/henon_heiles", "--poincare", "x + q"])
    said = capsys.readouterr().err
    assert code == 2 and "--poincare (line 1, column 5): unknown name 'q'" in said
