"""First integrals whose coefficients are trigonometric in the angles, against textbook
results: |L|**2 = m**2 r**4 (theta_dot**2 + sin(theta)**2 phi_dot**2) of a particle in a
central potential in spherical coordinates (Goldstein §3.2 and ch. 3), and the
Laplace–Runge–Lenz components of the Kepler problem in polar coordinates (Goldstein §3.9).

Each textbook integral is first checked on its own: dI/dt along the Euler–Lagrange equations
that SymPy derives from L and solves for the accelerations in this file, nothing of
lagrangian's derivation involved."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.integrals.trigonometric import trigonometric_integrals
from lagrangian.cli.main import main
from lagrangian.symbolic.conversion import to_sympy

r, theta, phi = lg.coordinates("r theta phi")
r_dot, theta_dot, phi_dot = (lg.velocity(s) for s in (r, theta, phi))
m, k, c, e, t = sp.symbols("m k c e t")
STATE = {t, r, theta, phi, r_dot, theta_dot, phi_dot}

#: Goldstein (3.82) in polar coordinates, times m: A_x and A_y of the Kepler problem.
RUNGE_LENZ = (
    (m**2 * r**3 * theta_dot**2 - m * k) * sp.cos(theta)
    + m**2 * r**2 * r_dot * theta_dot * sp.sin(theta),
    (m**2 * r**3 * theta_dot**2 - m * k) * sp.sin(theta)
    - m**2 * r**2 * r_dot * theta_dot * sp.cos(theta),
)
#: |L|**2 in spherical coordinates.
ANGULAR_MOMENTUM_SQUARED = m**2 * r**4 * (theta_dot**2 + sp.sin(theta) ** 2 * phi_dot**2)


def rate_on_motions(lagrangian: sp.Expr, coordinates: list[sp.Symbol], quantity: sp.Expr):
    """dI/dt with the accelerations of d/dt dL/dq_dot - dL/dq = 0, solved by SymPy."""
    velocities = [lg.velocity(s) for s in coordinates]
    accelerations = [lg.acceleration(s) for s in coordinates]

    def rate(f: sp.Expr) -> sp.Expr:
        return sum(
            (
                f.diff(s) * v + f.diff(v) * a
                for s, v, a in zip(coordinates, velocities, accelerations)
            ),
            sp.Integer(0),
        )

    equations = [
        rate(lagrangian.diff(v)) - lagrangian.diff(s) for s, v in zip(coordinates, velocities)
    ]
    [solved] = sp.solve(equations, accelerations, dict=True)
    return sp.simplify(rate(quantity).subs(solved))


def polar(potential: sp.Expr) -> sp.Expr:
    return m * (r_dot**2 + r**2 * theta_dot**2) / 2 - potential


def spherical(potential: sp.Expr) -> sp.Expr:
    kinetic = m * (r_dot**2 + r**2 * theta_dot**2 + r**2 * sp.sin(theta) ** 2 * phi_dot**2) / 2
    return kinetic - potential


def system(lagrangian: sp.Expr, coordinates: list[sp.Symbol], **parameters) -> lg.System:
    return lg.System(coordinates=coordinates, parameters=parameters, lagrangian=lagrangian)


def proportional(found: sp.Expr, expected: sp.Expr) -> bool:
    """A constant multiple (a number times parameters) of ``expected``."""
    ratio = sp.simplify(found / expected)
    return ratio != 0 and not ratio.free_symbols & STATE


KEPLER = polar(-k / r)
PERTURBED = polar(-k / r + e / r**3)
CENTRAL = spherical(k * r**2 / 2 + c * r**4)


def test_the_textbook_integrals_are_constant_on_the_motions():
    for component in RUNGE_LENZ:
        assert rate_on_motions(KEPLER, [r, theta], component) == 0
    for lagrangian in (spherical(0), CENTRAL):
        assert rate_on_motions(lagrangian, [r, theta, phi], ANGULAR_MOMENTUM_SQUARED) == 0


def test_the_kepler_problem_in_polar_coordinates_has_both_runge_lenz_components():
    found = trigonometric_integrals(system(KEPLER, [r, theta], m=1.0, k=1.0))
    for component in RUNGE_LENZ:
        assert any(proportional(i, component) for i in found), component


@pytest.mark.parametrize("lagrangian", [spherical(0), CENTRAL], ids=["free", "central"])
def test_a_particle_in_a_central_potential_keeps_its_angular_momentum_squared(lagrangian):
    report = lg.analyze(system(lagrangian, [r, theta, phi], m=1.0, k=1.0, c=0.5))
    [squared] = [
        q for q in report.conserved if proportional(q.expression, ANGULAR_MOMENTUM_SQUARED)
    ]
    assert squared.origin == "quadratic first integral"
    assert "trigonometric" in squared.reason
    assert any("trigonometric in theta, phi" in line for line in report.searched)


def test_a_perturbed_kepler_problem_keeps_its_angular_momentum_but_no_runge_lenz_vector():
    # a 1/r**3 term turns the orbit's axis (Goldstein §3.9, exercise): A is not conserved
    assert all(rate_on_motions(PERTURBED, [r, theta], a) != 0 for a in RUNGE_LENZ)
    report = lg.analyze(system(PERTURBED, [r, theta], m=1.0, k=1.0, e=0.1))
    assert {q.name for q in report.conserved} == {"p_theta", "h"}
    found = trigonometric_integrals(system(PERTURBED, [r, theta], m=1.0, k=1.0, e=0.1))
    assert found and not any(i.has(sp.sin, sp.cos) for i in found)  # L_z and L_z**2 only


KEPLER_FILE = """\
name: kepler
coordinates: [r, theta]
parameters: {m: 1.0, k: 1.0}
kinetic: m*(r_dot**2 + r**2*theta_dot**2)/2
potential: -k/r
"""


@pytest.fixture
def kepler_file(tmp_path: Path) -> str:
    path = tmp_path / "kepler.yaml"
    path.write_text(KEPLER_FILE)
    return str(path)


def runge_lenz_in(text: str) -> bool:
    """Whether ``text`` (an expression as printed) is a Runge–Lenz component."""
    return any(proportional(to_sympy(text), a) for a in RUNGE_LENZ)


def test_the_command_line_shows_the_runge_lenz_vector_in_text_and_json(capsys, kepler_file):
    assert main(["analyze", kepler_file, "--format", "text"]) == 0
    out = capsys.readouterr().out
    conserved = out.split("Conserved:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    [line] = [x for x in conserved if "[quadratic first integral]" in x]
    assert runge_lenz_in(line.split(" = ", 1)[1].rsplit("  [", 1)[0])

    assert main(["analyze", kepler_file, "--format", "json"]) == 0
    document = json.loads(capsys.readouterr().out)
    [entry] = [q for q in document["conserved_quantities"] if q["name"].startswith("I_")]
    assert entry["origin"] == "quadratic first integral" and entry["conditions"] == []
    assert runge_lenz_in(entry["expression"])
    assert any("trigonometric in theta" in line for line in document["first_integral_search"])
