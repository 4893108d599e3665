"""analyze(): the whole report, robust part by part, and its JSON (DESIGN.md output contract).

Values checked against hand results: Kepler conserves p_theta = m r^2 theta_dot and
h = T + V; the pendulum's small-oscillation frequency is sqrt(g/l) and about the bottom its
linearization has eigenvalues +-i sqrt(g/l).
"""

from __future__ import annotations

import json
import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import AnalysisReport, analyze
from lagrangian.render.analysis_json import analysis_document

CONTRACT_KEYS = {
    "dof",
    "constraints",
    "momenta",
    "cyclic",
    "conserved",
    "energy_function",
    "energy_conserved",
    "hamiltonian",
    "equilibria",
    "normal_modes",
}


def _parse(text: str) -> sp.Basic:
    return sp.sympify(text)


def test_planet_report() -> None:
    report = analyze(lg.examples.planet())
    m, r, theta_dot = sp.symbols("m r theta_dot")
    assert report.dof == 2 and report.constraints == ()
    names = [c.name for c in report.conserved]
    assert names == ["p_theta", "h", "I_1"]
    assert sp.simplify(report.conserved[0].expression - m * r**2 * theta_dot) == 0
    # a component of the Laplace–Runge–Lenz vector (Goldstein §3.9), trigonometric in theta
    assert report.conserved[2].origin == "quadratic first integral"
    assert report.conserved[2].expression.has(sp.sin(sp.Symbol("theta")))
    assert report.energy is not None and report.energy.equals_total_energy
    assert report.normal_modes is None
    assert "No stable equilibrium" in (report.failure("normal_modes") or "")


def test_a_failing_part_does_not_stop_the_report() -> None:
    report = analyze(lg.examples.rc_rl_circuit(), about={})
    assert report.hamiltonian is None and report.hamilton_equations is None
    assert "singular Legendre transform" in (report.failure("hamiltonian") or "")
    assert report.energy is not None and report.momenta is not None
    assert report.failure("linearization") is not None


def test_json_document_follows_the_contract() -> None:
    report = analyze(lg.examples.simple_pendulum(), about={"theta": 0})
    document = analysis_document(report)
    json.dumps(document)
    assert set(document) >= CONTRACT_KEYS
    assert document["dof"] == 1 and document["constraints"] == []
    assert _parse(document["momenta"]["theta"]) == sp.sympify("l**2*m*theta_dot")
    assert document["energy_conserved"] is True
    g, l = sp.symbols("g l")
    assert sp.simplify(_parse(document["normal_modes"]["frequencies"][0]) ** 2 - g / l) == 0
    states = [e["state"] for e in document["equilibria"]]
    assert states == [{"theta": "0"}, {"theta": "pi"}]
    assert [e["stable"] for e in document["equilibria"]] == [True, False]
    linear = document["linearization"]
    assert [[_parse(e) for e in row] for row in linear["A"]] == [[0, 1], [-g / l, 0]]
    assert [float(_parse(w)) for w in linear["frequencies"]] == pytest.approx([math.sqrt(9.81)])
    assert linear["growth_rates"] == []
    for text in (document["hamiltonian"], document["energy_function"], *document["conserved"]):
        _parse(text)


def test_json_of_a_failed_part_is_null_with_its_reason() -> None:
    document = analysis_document(analyze(lg.examples.rc_rl_circuit()))
    json.dumps(document)
    assert document["hamiltonian"] is None
    assert "singular Legendre transform" in document["failures"]["hamiltonian"]
    assert "linearization" not in document


def test_json_equilibrium_conditions_parse() -> None:
    m, g, R, omega, theta = sp.symbols("m g R omega theta")
    hoop = lg.System(
        coordinates=[theta],
        parameters={m: 1.0, g: 9.81, R: 1.0, omega: 5.0},
        kinetic=m * R**2 / 2 * (sp.Symbol("theta_dot") ** 2 + omega**2 * sp.sin(theta) ** 2),
        potential=-m * g * R * sp.cos(theta),
    )
    document = analysis_document(analyze(hoop))
    json.dumps(document)
    conditions = {e["state"]["theta"]: _parse(e["condition"]) for e in document["equilibria"]}
    assert conditions["0"] == sp.true
    assert conditions["acos(g/(R*omega**2))"].subs({g: 9.81, R: 1, omega: 2}) == sp.false


def test_analyze_accepts_equations_of_motion() -> None:
    eom = lg.derive(lg.examples.two_masses_three_springs())
    report = analyze(eom, parameters={"m2": "m1", "k2": "k1", "k3": "k1"})
    assert isinstance(report, AnalysisReport)
    k1, m1 = sp.symbols("k1 m1")
    assert report.normal_modes is not None
    assert report.normal_modes.squared_frequencies == (k1 / m1, 3 * k1 / m1)


@pytest.mark.slow
@pytest.mark.parametrize("name", lg.examples.names())
def test_every_example_gives_a_json_report(name: str) -> None:
    # the gas's state of zeros puts every disk at the corner, through the walls and each
    # other: an operating state off its contacts is refused by name (ConstraintError, as
    # test_a_state_off_the_contacts_is_refused checks); its report is about no state
    about = None if name == "hard_disk_gas" else {}
    report = analyze(lg.examples.get(name)(), about=about)
    document = analysis_document(report)
    json.dumps(document)
    assert not any("internal error" in reason for reason in document["failures"].values())


def test_a_state_off_the_contacts_is_refused() -> None:
    """An operating state through the walls of the gas is refused naming each contact it
    violates, with its residual (h = x - r = -0.1 at x = 0, r = 0.1)."""
    with pytest.raises(lg.ConstraintError) as refused:
        analyze(lg.examples.get("hard_disk_gas")(), about={})
    message = str(refused.value)
    assert "'left1' (constraints[0])" in message and "h(q, t) = -0.1" in message
