"""The analysis of long chains read from their structure: equilibria of static equations that
separate, the equations at rest term by term, W read off the momenta, modes of large pencils.

References: the n-link pendulum by hand (V = -g sum_i l_i (m_i + ... + m_n) cos(theta_i), so
dV/dtheta_i = g l_i M_i sin(theta_i): theta_i = 0 or pi, 2^n equilibria, K diagonal with
K_ii = g l_i M_i cos(theta_i)); SymPy's own substitution and Jacobian; mpmath's 30-digit
generalized eigensolver.
"""

from __future__ import annotations

import math

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import equilibria, spectrum
from lagrangian.analysis.at_rest import forcing_at_rest, velocity_jacobian_at_rest
from lagrangian.analysis.hamiltonian import velocity_hessian
from lagrangian.analysis.separable import LISTED, separate_equations
from lagrangian.analysis.stability import stability_of
from lagrangian.symbolic.nonsmooth import jacobian


def _hand_stiffness(n: int, state: dict) -> list[float]:
    """K_ii = g l_i (m_i + ... + m_n) cos(theta_i) at unit masses and lengths, g = 9.81."""
    coordinates = list(state)
    return [9.81 * (n - i) * math.cos(float(state[q])) for i, q in enumerate(coordinates)]


def test_every_equilibrium_of_a_five_link_pendulum_is_listed_exactly() -> None:
    n = 5
    eom = lg.derive(lg.examples.n_link_pendulum(n))
    values = dict(eom.parameters)
    found = equilibria(eom)
    assert len(found) == 2**n and found.count is None and found.method == "symbolic"
    states = {tuple(e.state.values()) for e in found}
    assert len(states) == 2**n and all(set(s) <= {0, sp.pi} for s in states)
    stable = [e for e in found if e.stable]
    assert len(stable) == 1 and set(stable[0].state.values()) == {0}
    for e in found:
        k = [float(e.stiffness[i, i].xreplace(values)) for i in range(n)]
        assert k == pytest.approx(_hand_stiffness(n, dict(e.state)))
        ups = sum(1 for v in e.state.values() if v == sp.pi)
        if ups:
            assert e.stable is False and f"K has {ups} negative eigenvalue" in e.reason


def test_a_long_chain_lists_its_minimum_and_maximum_and_counts_the_rest() -> None:
    n = 8
    found = equilibria(lg.examples.n_link_pendulum(n))
    assert 2**n > LISTED and found.count == 2**n
    assert [set(e.state.values()) for e in found] == [{0}, {sp.pi}]
    assert [e.stable for e in found] == [True, False]
    assert "256 equilibria" in found.reason and "saddle" in found.reason
    assert "unstable: no force linear in the velocities acts at rest" in found.reason
    static = found.static_equations.xreplace(dict(found.equilibria[1].state))
    assert all(e == 0 for e in static)


def test_coupled_static_equations_are_solved_whole() -> None:
    x, y = sp.symbols("x y")
    assert separate_equations(sp.Matrix([sp.sin(x) - y, y]), [x, y]) is None
    assert separate_equations(sp.Matrix([sp.sin(x), y - 2]), [x, y]) == {x: sp.sin(x), y: y - 2}


@pytest.mark.parametrize(
    "system",
    [
        lg.examples.charged_particle_em(),
        lg.examples.heavy_symmetric_top(),
        lg.examples.mass_spring_damper(),
        lg.examples.n_link_pendulum(4),
        lg.examples.quartic_lagrangian(),
    ],
    ids=lambda s: s.name,
)
def test_the_equations_at_rest_read_term_by_term_match_substitution(system) -> None:
    eom = lg.derive(system)
    rest = {v: 0 for v in eom.velocities}
    substituted = sp.ImmutableMatrix([f.xreplace(rest) for f in eom.forcing])
    assert forcing_at_rest(eom) == substituted
    reference = jacobian(sp.Matrix(eom.forcing), eom.velocities).xreplace(rest)
    read = velocity_jacobian_at_rest(eom.forcing, eom.velocities)
    assert all(sp.simplify(a - b) == 0 for a, b in zip(reference, read))


def test_gyroscopic_terms_at_rest_are_found() -> None:
    eom = lg.derive(lg.examples.charged_particle_em())
    read = velocity_jacobian_at_rest(eom.forcing, eom.velocities)
    assert any(e != 0 for e in read)  # q v x B is linear in the velocities


@pytest.mark.parametrize(
    "system",
    [lg.examples.n_link_pendulum(6), lg.examples.charged_particle_em()],
    ids=lambda s: s.name,
)
def test_w_read_off_the_momenta_is_their_derivative(system) -> None:
    eom = lg.derive(system)
    reference = sp.Matrix([[s.dL_dvelocity.diff(v) for v in eom.velocities] for s in eom.steps])
    assert velocity_hessian(eom) == reference


def test_a_diagonal_stiffness_is_judged_as_by_its_eigenvalues() -> None:
    for entries in ([2, 3, 5], [2, -3, 5], [-2, -3, -5], [0, 1, 2]):
        diagonal = sp.diag(*[sp.Float(e) for e in entries])
        rotated = sp.Matrix([[1, 1e-30, 0], [1e-30, 1, 0], [0, 0, 1]])  # not diagonal
        dense = diagonal + (rotated - sp.eye(3))
        assert stability_of(diagonal) == stability_of(dense)


def test_large_pencils_in_double_precision_agree_with_30_digits(monkeypatch) -> None:
    n = 30
    eom = lg.derive(lg.examples.n_link_pendulum(n))
    report = lg.analysis.normal_modes(eom)
    assert n > spectrum.EXTENDED_PRECISION_SIZE and len(report.frequencies) == n
    values = {p: sp.Float(v, 30) for p, v in eom.parameters.items()}
    k = report.stiffness_matrix.xreplace(values).evalf(30)
    m = report.mass_matrix.xreplace(values).evalf(30)
    monkeypatch.setattr(spectrum, "EXTENDED_PRECISION_SIZE", n)
    reference = spectrum.generalized_modes(k, m)
    for w2, (r2, _) in zip(report.squared_frequencies, reference):
        assert float(w2) == pytest.approx(r2, rel=1e-9)
    for ours, (_, shape) in zip(report.shapes, reference):
        assert [float(x) for x in ours] == pytest.approx([float(x) for x in shape], abs=1e-8)


def test_every_output_says_how_many_equilibria_a_long_chain_has() -> None:
    """Only the minimum and the maximum of 2^7 = 128 are listed: text, LaTeX and JSON each
    say that there are 128 and how they were found (a user reading two would think that is
    all)."""
    from lagrangian.render.analysis_json import analysis_document
    from lagrangian.render.analysis_latex import analysis_latex
    from lagrangian.render.analysis_text import analysis_text

    report = lg.analyze(lg.examples.n_link_pendulum(7), search_seconds=0.5)
    assert len(report.equilibria.equilibria) == 2 and report.equilibria.count == 128
    document = analysis_document(report)
    assert document["equilibria_count"] == 128 and len(document["equilibria"]) == 2
    assert "128 equilibria" in document["equilibria_reason"]
    text = analysis_text(report)
    listed = text.split("Equilibria:")[1].split("\n\n")[0]
    assert "128 equilibria" in listed and "saddle" in listed
    assert "128 equilibria" in analysis_latex(report)


def test_a_short_chain_counts_what_it_lists() -> None:
    from lagrangian.render.analysis_json import analysis_document

    document = analysis_document(lg.analyze(lg.examples.n_link_pendulum(2), search_seconds=0.5))
    assert document["equilibria_count"] == len(document["equilibria"]) == 4
