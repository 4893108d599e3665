"""Impacts on unilateral constraints with a coefficient of restitution, against closed forms:
the bouncing ball's impact times and rest time (a geometric series), two carts colliding
(momentum for any e, Newton's law, energy at e = 1), Newton's cradle with gaps (sequential
impacts pass the velocity down the row), a particle in a circular box (angular momentum about
the centre through every impact); and the model-file contract of ``restitution``."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError, SimulationError, SimulationInputError
from lagrangian.simulation.unilateral import RECONTACT_TOLERANCE

G = 9.81
TIGHT = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-12}


def bouncing_ball(e: float) -> lg.System:
    return lg.loads(
        f"""
        coordinates: [y]
        parameters: {{m: 1.0, g: {G}, e: {e}}}
        kinetic: m*y_dot**2/2
        potential: m*g*y
        constraints:
          - {{name: floor, unilateral: y, restitution: e}}
        initial: {{y: 1.0, y_dot: 0.0}}
        """
    )


@pytest.mark.parametrize("e", [0.5, 0.8])
def test_a_bouncing_ball_lands_at_the_geometric_series_and_comes_to_rest(e: float) -> None:
    run = lg.simulate(bouncing_ball(e), t_span=3 / (1 - e), samples=301, **TIGHT)
    assert run.success, run.message
    t1 = np.sqrt(2 * 1.0 / G)  # the first fall from y = 1
    times = np.array([impact.t for impact in run.impacts])
    # each flight lasts e times the one before: t_k = t1 (1 + 2 (e + ... + e^(k-1)))
    expected = t1 * (1 + 2 * np.concatenate(([0.0], np.cumsum(e ** np.arange(1, len(times))))))
    assert np.allclose(times[:10], expected[:10], rtol=1e-8, atol=1e-8)
    for impact in run.impacts[:-1]:  # Newton's law, and the kinetic energy lost: (1 - e^2) T-
        assert impact.after["y_dot"] == pytest.approx(-e * impact.before["y_dot"], rel=1e-9)
        lost = (1 - e**2) * impact.before["y_dot"] ** 2 / 2
        assert impact.energy_lost == pytest.approx(lost, rel=1e-9)
    # the bounces accumulate at t_inf = t1 (1 + e) / (1 - e); the run switches the contact to
    # persistent at the bounce that would rise less than the contact tolerance, so it comes to
    # rest before t_inf by at most the flights left: 2 v / (g (1 - e)), v = sqrt(2 g tol)
    rest = run.impacts[-1]
    assert rest.rest == ("floor",) and [e.name for e in run.events][-1] == "rest floor"
    t_inf = t1 * (1 + e) / (1 - e)
    left = 2 * np.sqrt(2 * G * RECONTACT_TOLERANCE) / (G * (1 - e))
    assert t_inf - left <= rest.t <= t_inf
    after = run.t > rest.t
    # at rest on the floor: y = 0 to rounding (the landing is a root of the flight's parabola)
    assert np.all(np.abs(run["y"][after]) <= 1e-15) and np.all(np.abs(run["y_dot"][after]) <= 1e-15)
    assert np.allclose(run["lambda_1"][after], 1.0 * G)  # resting: the floor holds m g
    assert run.drift()["energy_not_conserved"] == "impacts (e < 1)"


def two_carts(m1: float, m2: float, e: float) -> lg.System:
    x1, x2, a, b = sp.symbols("x1 x2 m1 m2")
    v1, v2 = sp.symbols("x1_dot x2_dot")
    return lg.System(
        coordinates=[x1, x2],
        parameters={a: m1, b: m2},
        kinetic=a * v1**2 / 2 + b * v2**2 / 2,
        constraints=[lg.Unilateral(x2 - x1, name="bumpers", restitution=e)],
        initial={"x1": 0.0, "x2": 1.0, "x1_dot": 2.0, "x2_dot": -0.5},
    )


@pytest.mark.parametrize(("m1", "m2", "e"), [(1, 1, 1), (1, 3, 1), (2, 1, 0.5), (1, 4, 0.0)])
def test_two_carts_collide_as_the_closed_form_says(m1: float, m2: float, e: float) -> None:
    run = lg.simulate(two_carts(m1, m2, e), t_span=1.0, samples=11, **TIGHT)
    (impact,) = run.impacts
    v1, v2 = 2.0, -0.5
    # met where the gap closes to -tol, the contact band that absorbs integration error
    assert 0 <= impact.t - 1.0 / (v1 - v2) <= RECONTACT_TOLERANCE / (v1 - v2) + 1e-12
    # momentum conserved and Newton's law v2+ - v1+ = -e (v2 - v1): the closed form
    after1 = (m1 * v1 + m2 * v2 + m2 * e * (v2 - v1)) / (m1 + m2)
    after2 = (m1 * v1 + m2 * v2 + m1 * e * (v1 - v2)) / (m1 + m2)
    assert impact.after["x1_dot"] == pytest.approx(after1, abs=1e-9)
    assert impact.after["x2_dot"] == pytest.approx(after2, abs=1e-9)
    assert impact.impulses["bumpers"] == pytest.approx(m2 * (after2 - v2), rel=1e-9)
    momentum = m1 * run["x1_dot"] + m2 * run["x2_dot"]
    assert np.allclose(momentum, m1 * v1 + m2 * v2, atol=1e-9)
    if e == 1:
        assert run.drift()["energy_relative"] < 1e-9
    if e == 0:  # plastic: they move on together, the bumpers in contact
        assert np.allclose(run["x2"][-3:] - run["x1"][-3:], 0, atol=1e-9)


def test_newtons_cradle_with_gaps_passes_the_velocity_down_the_row() -> None:
    # three equal balls on a line, 1 mm apart: the first hits the second, the second the
    # third, one after the other; elastic and equal, each stops and the last leaves with v
    x = sp.symbols("x1:4")
    gap = 1e-3
    system = lg.System(
        coordinates=list(x),
        parameters={},
        kinetic=sum(sp.Symbol(f"{s}_dot") ** 2 / 2 for s in x),
        constraints=[
            lg.Unilateral(x[1] - x[0], name="first", restitution=1),
            lg.Unilateral(x[2] - x[1], name="second", restitution=1),
        ],
        initial={"x1": -1.0, "x2": 0.0, "x3": gap, "x1_dot": 1.0, "x2_dot": 0.0, "x3_dot": 0.0},
    )
    run = lg.simulate(system, t_span=2.0, samples=21, **TIGHT)
    assert [i.constraints for i in run.impacts] == [("first",), ("second",)]
    assert run.impacts[1].t - run.impacts[0].t == pytest.approx(gap, abs=2 * RECONTACT_TOLERANCE)
    assert np.allclose(run.q_dot[-1], [0.0, 0.0, 1.0], atol=1e-9)


def test_a_particle_in_a_round_box_keeps_its_angular_momentum_through_every_impact() -> None:
    x, y, r = sp.symbols("x y R")
    system = lg.System(
        coordinates=[x, y],
        parameters={r: 1.0},
        kinetic=(sp.Symbol("x_dot") ** 2 + sp.Symbol("y_dot") ** 2) / 2,
        constraints=[lg.Unilateral(r**2 - x**2 - y**2, name="wall", restitution=1)],
        initial={"x": 0.2, "y": -0.1, "x_dot": 1.3, "y_dot": 0.7},
    )
    run = lg.simulate(system, t_span=10.0, samples=201, **TIGHT)
    assert len(run.impacts) >= 5
    momentum = run["x"] * run["y_dot"] - run["y"] * run["x_dot"]
    assert np.allclose(momentum, 0.2 * 0.7 + 0.1 * 1.3, atol=1e-9)
    assert run.drift()["energy_relative"] < 1e-9
    assert np.all(run["x"] ** 2 + run["y"] ** 2 <= 1 + 1e-7)


def test_a_contact_without_restitution_still_stops_the_run() -> None:
    run = lg.simulate(
        two_carts(1, 1, 1).replace(constraints=[lg.Unilateral(sp.Symbol("x2") - sp.Symbol("x1"))]),
        t_span=1.0,
        raise_on_failure=False,
    )
    assert run.status == "failed" and "no coefficient of restitution" in run.message
    with pytest.raises(SimulationError, match=r"give it one, e\.g\. restitution: 1"):
        lg.simulate(
            two_carts(1, 1, 1).replace(
                constraints=[lg.Unilateral(sp.Symbol("x2") - sp.Symbol("x1"))]
            ),
            t_span=1.0,
        )


def test_restitution_in_a_model_file_round_trips_and_bad_ones_are_refused() -> None:
    from lagrangian.io.dump import dumps

    ball = bouncing_ball(0.8)
    assert ball.constraints[0].restitution == sp.Symbol("e")
    assert "restitution: e" in dumps(ball)
    with pytest.raises(ModelError, match=r"constraints\[0\].restitution.*no impacts"):
        lg.loads("coordinates: [y]\nconstraints: [{holonomic: y, restitution: 1}]")
    y = sp.Symbol("y")
    with pytest.raises(ModelError, match=r"restitution: the coefficient of restitution 3/2"):
        lg.System(coordinates=[y], kinetic=y**2, constraints=[lg.Unilateral(y, restitution=1.5)])
    with pytest.raises(ModelError, match=r"restitution: y_dot varies with the motion"):
        lg.System(
            coordinates=[y],
            kinetic=y**2,
            constraints=[lg.Unilateral(y, restitution=sp.Symbol("y_dot"))],
        )


@pytest.mark.parametrize("seed", range(5))
def test_many_simultaneous_contacts_are_solved_by_pivoting_as_by_enumeration(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Twelve contacts touching at once (more than the active sets enumerated): Lemke's
    method gives the impulses the enumeration of every active set gives (the problem with a
    positive definite Delassus matrix has one solution), and they meet the conditions: each
    pushes, each contact leaves at least at -e times its closing rate, complementarity."""
    from lagrangian.simulation import impacts

    rng = np.random.default_rng(seed)
    n, k = 30, 12
    root = rng.normal(size=(n, n))
    mass = root @ root.T + n * np.eye(n)
    jacobian = rng.normal(size=(k + 1, n))  # the last row bilateral
    v = rng.normal(size=n)
    rates = jacobian @ v
    rates[-1] = 0.0
    v = v - np.linalg.solve(mass, jacobian[-1]) * (jacobian[-1] @ v) / (
        jacobian[-1] @ np.linalg.solve(mass, jacobian[-1])
    )  # on the bilateral constraint
    rates = jacobian @ v
    e = rng.uniform(0, 1, k)
    touching = list(range(k))
    pivoted = impacts.resolve(mass, jacobian, rates, [k], touching, e, v)
    monkeypatch.setattr(impacts, "ENUMERATED_CONTACTS", k)
    enumerated = impacts.resolve(mass, jacobian, rates, [k], touching, e, v)
    assert np.allclose(pivoted[0], enumerated[0], atol=1e-9)
    assert np.allclose(pivoted[1], enumerated[1], atol=1e-9)
    after, impulses = pivoted
    leaving = jacobian[:k] @ after + e * rates[:k]
    assert np.all(impulses[:k] >= -1e-10) and np.all(leaving >= -1e-9)
    assert np.allclose(impulses[:k] * leaving, 0, atol=1e-8)
    assert abs(jacobian[k] @ after) < 1e-10  # the bilateral constraint is kept
    assert np.allclose(mass @ (after - v), jacobian.T @ impulses, atol=1e-9)


@pytest.mark.parametrize("gap", ["x2 - x1", "x2 - x1 + sin(x1)/10"])  # closed form, stepped
def test_a_start_closing_on_a_contact_is_refused_by_name(gap: str) -> None:
    carts = lg.loads(
        f"""
        coordinates: [x1, x2]
        kinetic: (x1_dot**2 + x2_dot**2)/2
        constraints:
          - {{name: bumpers, unilateral: "{gap}", restitution: 1}}
        initial: {{x1: 0.0, x2: 0.0, x1_dot: 1.0, x2_dot: 0.0}}
        """
    )
    with pytest.raises(SimulationError, match=r"'bumpers'.*an impact at the start"):
        lg.simulate(carts, t_span=1.0)


def test_a_contact_under_a_constant_force_is_the_root_of_a_quartic() -> None:
    """A particle thrown inside a circular bowl x^2 + y^2 <= R^2 under gravity: along the
    parabola the gap R^2 - x^2 - y^2 is a quartic in t, found in closed form; its first zero
    against SciPy's brentq on the same parabola, and the bounce against the reflection
    about the bowl's normal (e = 1)."""
    from scipy.optimize import brentq

    bowl = lg.loads(
        """
        coordinates: [x, y]
        parameters: {g: 9.81, R: 1.0}
        kinetic: (x_dot**2 + y_dot**2)/2
        potential: g*y
        constraints:
          - {name: bowl, unilateral: R**2 - x**2 - y**2, restitution: 1}
        initial: {x: 0.1, y: 0.2, x_dot: 1.5, y_dot: 2.0}
        """
    )
    run = lg.simulate(bowl, t_span=0.6, samples=7)
    first = run.impacts[0]
    x0, v0, a = np.array([0.1, 0.2]), np.array([1.5, 2.0]), np.array([0.0, -G])

    def gap(s: float) -> float:
        p = x0 + v0 * s + a * s * s / 2
        return 1.0 - p @ p

    expected = brentq(gap, 0.01, 0.6, xtol=1e-15)
    assert first.t == pytest.approx(expected, abs=1e-12)
    p = x0 + v0 * expected + a * expected**2 / 2
    v = v0 + a * expected
    normal = p / np.linalg.norm(p)
    reflected = v - 2 * (v @ normal) * normal
    after = np.array([first.after["x_dot"], first.after["y_dot"]])
    assert np.allclose(after, reflected, atol=1e-9)


def test_what_a_run_keeps_per_system_follows_the_parameters() -> None:
    """The coefficients of restitution at the run's parameters and the System of the start's
    active contacts are kept per System: a second run with e = 0.5 bounces as e = 0.5 says,
    e = 1.5 is refused (on every run), the first parameters still give the first run."""
    ball = bouncing_ball(0.8)
    first = lg.simulate(ball, {"y": 1.0, "y_dot": 0.0}, 1.0, samples=3)
    half = lg.simulate(ball, {"y": 1.0, "y_dot": 0.0}, 1.0, samples=3, parameters={"e": 0.5})
    for run, e in ((first, 0.8), (half, 0.5)):
        hit = run.impacts[0]
        assert hit.after["y_dot"] == pytest.approx(-e * hit.before["y_dot"], rel=1e-12)
    for _ in range(2):
        with pytest.raises(
            SimulationInputError, match=r"restitution of .* 1\.5, is not in \[0, 1\]"
        ):
            lg.simulate(ball, {"y": 1.0, "y_dot": 0.0}, 1.0, parameters={"e": 1.5})
    again = lg.simulate(ball, {"y": 1.0, "y_dot": 0.0}, 1.0, samples=3)
    assert [i.t for i in again.impacts] == [i.t for i in first.impacts]
