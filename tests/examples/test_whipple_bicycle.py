"""The Whipple bicycle example against the benchmark of Meijaard, Papadopoulos, Ruina and
Schwab, "Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and
review", Proc. R. Soc. A 463 (2007) 1955-1982.

The example is the full nonlinear bicycle (4 bodies, 8 coordinates, the front contact's height
and 4 no-slip constraints); its linearization on the constraint manifold about upright straight
running at speed v gives the lean and steer equations

    M q_ddot + v C1 q_dot + (g K0 + v^2 K2) q = [Tlean, Tsteer],   q = (lean, steer),

whose matrices are read off the reduced state space x_dot = A x + B u: the rows of lean_ddot
and steer_ddot are B = M^-1 (inputs Tlean, Tsteer), A_q = -M^-1 (g K0 + v^2 K2) and
A_q_dot = -M^-1 v C1.  The reference values are the paper's (its benchmark matrices and Table 2);
the weave and capsize speeds follow from the characteristic polynomial det(M s^2 + v C1 s +
g K0 + v^2 K2): capsize where its constant term vanishes, weave where its Hurwitz determinant
does.  The tests that build the bicycle are slow ones."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

import lagrangian as lg
from lagrangian.model.contact import contact_point

slow = pytest.mark.slow

G = 9.81
R_REAR, R_FRONT = 0.3, 0.35
#: The paper's lean/steer matrices and its weave and capsize speeds.
PAPER = {
    "M": [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]],
    "C1": [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]],
    "K0": [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]],
    "K2": [[0.0, 76.59734589573222], [0.0, 2.65431523794604]],
}
WEAVE_SPEED, CAPSIZE_SPEED = 4.29238253634111, 6.02426201538837
#: Table 2: the eigenvalues of the lean/steer equations at the published speeds.
TABLE_2 = {
    0.0: [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    4.0: [
        -12.15861426576447,
        -1.42944427361326,
        0.41325331521125 - 3.07910818603206j,
        0.41325331521125 + 3.07910818603206j,
    ],
    5.0: [
        -14.07838969279822,
        -0.32286642900409,
        -0.77534188219585 - 4.46486771378823j,
        -0.77534188219585 + 4.46486771378823j,
    ],
    10.0: [
        -24.62459635017404,
        0.16105338653172,
        -3.72016840437287 - 10.90681139476287j,
        -3.72016840437287 + 10.90681139476287j,
    ],
}
#: Kept at the linear level: every coordinate but the pitch, and the lean, steer and rear
#: wheel rates (the paper's degrees of freedom).
INDEPENDENT = ["x", "y", "yaw", "lean", "steer", "thetaR", "thetaF"]
INDEPENDENT += ["lean_dot", "steer_dot", "thetaR_dot"]


@cache
def _equations() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.whipple_bicycle())


@cache
def _linearization(speed: float):
    eom = _equations()
    values = {p.name: v for p, v in eom.parameters.items() if p.name not in ("Tlean", "Tsteer")}
    about = {"x_dot": speed, "thetaR_dot": speed / R_REAR, "thetaF_dot": speed / R_FRONT}
    return lg.analysis.linearize(
        eom, about, inputs=["Tlean", "Tsteer"], parameters=values, independent=INDEPENDENT
    )


def _lean_steer(speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, the stiffness g K0 + v^2 K2 and the damping v C1 at ``speed``, from the reduced
    state space (rows and columns of lean, steer and their rates)."""
    lin = _linearization(speed)
    names = [s.name for s in lin.state_vector]
    rows = [names.index("lean_dot"), names.index("steer_dot")]
    positions = [names.index("lean"), names.index("steer")]
    a = np.array(sp.Matrix(lin.A).evalf(30), dtype=float)
    b = np.array(sp.Matrix(lin.B).evalf(30), dtype=float)
    mass = np.linalg.inv(b[rows, :])
    return mass, -mass @ a[np.ix_(rows, positions)], -mass @ a[np.ix_(rows, rows)]


@cache
def _matrices() -> dict[str, np.ndarray]:
    mass, stiffness_0, _ = _lean_steer(0.0)
    _, stiffness_1, damping_1 = _lean_steer(1.0)
    return {
        "M": mass,
        "C1": damping_1,
        "K0": stiffness_0 / G,
        "K2": stiffness_1 - stiffness_0,
    }


def _characteristic(matrices: dict[str, np.ndarray], speed: float) -> np.ndarray:
    """Coefficients (highest first) of det(M s^2 + v C1 s + g K0 + v^2 K2)."""
    m, c, k = matrices["M"], speed * matrices["C1"], G * matrices["K0"] + speed**2 * matrices["K2"]
    p = np.polynomial.Polynomial
    entries = [[p([k[i, j], c[i, j], m[i, j]]) for j in range(2)] for i in range(2)]
    det = entries[0][0] * entries[1][1] - entries[0][1] * entries[1][0]
    return det.coef[::-1]


def _eigenvalues(matrices: dict[str, np.ndarray], speed: float) -> np.ndarray:
    return _sorted(np.roots(_characteristic(matrices, speed)))


def _sorted(values) -> np.ndarray:
    """Eigenvalues in a fixed order, by real part (rounded, so that the two of a complex pair
    compare equal) and then imaginary part."""
    found = [complex(v) for v in values]
    return np.array(sorted(found, key=lambda v: (round(v.real, 6), v.imag)))


def _weave_and_capsize_speeds(matrices: dict[str, np.ndarray]) -> tuple[float, float]:
    """Weave: the Hurwitz determinant a3 a2 a1 - a4 a1^2 - a3^2 a0 of the quartic changes
    sign (a complex pair crosses the imaginary axis); capsize: a0 = det(g K0 + v^2 K2) = 0
    (a real eigenvalue crosses zero)."""

    def hurwitz(speed: float) -> float:
        a4, a3, a2, a1, a0 = _characteristic(matrices, speed)
        return float(a3 * a2 * a1 - a4 * a1**2 - a3**2 * a0)

    def constant(speed: float) -> float:
        return float(_characteristic(matrices, speed)[-1])

    return (
        brentq(hurwitz, 3.0, 5.0, xtol=1e-15, rtol=1e-15),
        brentq(constant, 5.0, 7.0, xtol=1e-15, rtol=1e-15),
    )


def test_the_method_reproduces_the_papers_speeds_from_its_own_matrices() -> None:
    paper = {name: np.array(value) for name, value in PAPER.items()}
    weave, capsize = _weave_and_capsize_speeds(paper)
    assert weave == pytest.approx(WEAVE_SPEED, abs=1e-10)
    assert capsize == pytest.approx(CAPSIZE_SPEED, abs=1e-10)
    for speed, expected in TABLE_2.items():
        np.testing.assert_allclose(_eigenvalues(paper, speed), _sorted(expected), atol=1e-10)


def test_the_example_has_the_benchmarks_structure() -> None:
    """8 coordinates; the front contact's height and 4 no-slip constraints (the rear
    contact's height holds identically): 7 configuration dimensions, 3 velocities."""
    system = lg.examples.whipple_bicycle()
    assert len(system.coordinates) == 8
    names = [type(c).__name__ for c in system.constraints]
    assert sorted(names) == ["ContactHeight", *["NoSlip"] * 4]
    assert [c.contact for c in system.constraints].count("front_wheel_contact") == 3


def test_the_written_out_positions_move_with_their_bodies() -> None:
    """Each centre is a material point of its body (offsets of Table 1 turned by the body's
    composed rotation), and upright the wheels touch the ground at 0 and at the wheelbase."""
    system = lg.examples.whipple_bicycle()
    bodies = {body.name: body for body in system.rigid_bodies}
    p = {name: sp.Matrix(body.position) for name, body in bodies.items()}
    rotation = {name: body.orientation.matrix for name, body in bodies.items()}
    w, rR, rF, xB, zB, xH, zH = sp.symbols("w rR rF xB zB xH zH")
    expected = {
        "rear_frame": p["rear_wheel"] + rotation["rear_frame"] * sp.Matrix([xB, 0, -zB - rR]),
        "front_wheel": p["fork"] + rotation["fork"] * sp.Matrix([w - xH, 0, rF + zH]),
    }
    rng = np.random.default_rng(3)
    for _ in range(3):
        values = {q: rng.uniform(-0.5, 0.5) for q in system.coordinates}
        values.update({s: v for s, v in system.parameters.items()})
        for name, position in expected.items():
            gap = np.array((p[name] - position).xreplace(values).evalf(30), dtype=float)
            np.testing.assert_allclose(gap, 0.0, atol=1e-12)
    upright = {q: 0 for q in system.coordinates}
    upright.update(system.parameters)
    for disc, where in zip(system.rolling, (0.0, 1.02)):
        point = contact_point(disc, bodies[disc.body])
        found = [float(e.xreplace(upright).evalf(30)) for e in point]
        np.testing.assert_allclose(found, [where, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("name", ["M", "C1", "K0", "K2"])
@slow
def test_the_linearized_lean_and_steer_equations_match_the_paper(name: str) -> None:
    np.testing.assert_allclose(_matrices()[name], PAPER[name], rtol=0, atol=1e-10)


@slow
def test_the_speed_enters_as_the_paper_says() -> None:
    """M constant, damping v C1, stiffness g K0 + v^2 K2: checked at a third speed."""
    mass, stiffness, damping = _lean_steer(5.0)
    found = _matrices()
    np.testing.assert_allclose(mass, found["M"], atol=1e-10)
    np.testing.assert_allclose(damping, 5.0 * found["C1"], atol=1e-9)
    np.testing.assert_allclose(stiffness, G * found["K0"] + 25.0 * found["K2"], atol=1e-9)


@pytest.mark.parametrize("speed", sorted(TABLE_2))
@slow
def test_the_eigenvalues_match_table_2(speed: float) -> None:
    np.testing.assert_allclose(_eigenvalues(_matrices(), speed), _sorted(TABLE_2[speed]), atol=1e-8)


@slow
def test_the_linearization_at_5_m_s_has_the_published_eigenvalues() -> None:
    """lagrangian's own eigenvalues of the 10-state reduced system: the four of Table 2 and
    zeros (position, heading, wheel angles and the rear wheel's rate are neutral)."""
    lin = _linearization(5.0)
    assert lin.is_solution, lin.note
    found = np.array([complex(e) for e in lin.eigenvalues])
    moving = _sorted(found[np.abs(found) > 1e-9])
    np.testing.assert_allclose(moving, _sorted(TABLE_2[5.0]), atol=1e-8)


@slow
def test_the_weave_and_capsize_speeds_match_the_paper() -> None:
    weave, capsize = _weave_and_capsize_speeds(_matrices())
    assert weave == pytest.approx(WEAVE_SPEED, abs=1e-8)
    assert capsize == pytest.approx(CAPSIZE_SPEED, abs=1e-8)


@slow
def test_at_5_m_s_the_bicycle_rights_itself() -> None:
    """The nonlinear bicycle, pushed into a lean at 5 m/s (between the weave and capsize
    speeds, where the paper's linearization is stable), rights itself: the weave decays as
    exp(-0.775 t) (Table 2), the energy and the rolling constraints hold."""
    run = lg.simulate(lg.examples.whipple_bicycle(), t_span=4.0, samples=401)
    assert run.success, run.message
    lean = np.abs(run.columns()["lean"])
    first, last = lean[run.t <= 1.0].max(), lean[run.t >= 3.0].max()
    assert first > 0.05 and last < 0.25 * first  # e^(-0.775 * 2.5) = 0.14
    drift = run.drift()
    assert drift["energy_relative"] < 1e-7
    assert drift["constraint_residual_max"] < 1e-7
