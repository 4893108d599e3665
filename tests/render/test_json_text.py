"""The expressions of the JSON documents (derive's and analyze's) are written by one writer:
the text is SymPy's own ``sstr(expr, order="none")`` character for character (the reference),
and an expression met twice in a document is written once (the same string)."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import analyze
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.json import ExpressionWriter, eom_document


def _sstr(expr: sp.Basic) -> str:
    return sp.sstr(expr, order="none")


@pytest.mark.parametrize("name", ["planet", "moving_pivot_pendulum", "cylinder_on_incline"])
def test_the_analysis_json_writes_sympys_text(name: str) -> None:
    report = analyze(lg.examples.get(name)())
    document = analysis_document(report)
    assert report.momenta is not None and report.energy is not None
    momenta = report.momenta.by_name()
    assert document["momenta"] == {q: _sstr(p) for q, p in momenta.items()}
    assert document["energy_function"] == _sstr(report.energy.energy_function)
    assert document["energy"]["total_energy"] == _sstr(report.energy.total_energy)
    expressions = [c["expression"] for c in document["conserved_quantities"]]
    assert expressions == [_sstr(c.expression) for c in report.conserved]
    if report.hamiltonian is not None:
        assert document["hamiltonian"] == _sstr(report.hamiltonian.hamiltonian)


def test_an_expression_met_twice_is_written_once() -> None:
    """Kepler: p_theta is a momentum, a cyclic coordinate's and a conserved quantity; h is the
    energy function, a conserved quantity and T + V."""
    document = analysis_document(analyze(lg.examples.planet()))
    p_theta = document["momenta"]["theta"]
    assert document["cyclic_coordinates"][0]["momentum"] is p_theta
    by_name = {c["name"]: c["expression"] for c in document["conserved_quantities"]}
    assert by_name["p_theta"] is p_theta
    h = document["energy_function"]
    assert by_name["h"] is h and document["energy"]["total_energy"] is h
    assert document["conserved"][:2] == [p_theta, h]


def test_the_derive_json_shares_the_writer() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    document = eom_document(eom, steps=True)
    mass = document["mass_matrix"]
    assert mass[0][1] is mass[1][0] and mass[0][1] == _sstr(eom.mass_matrix[0, 1])
    assert document["steps"][1]["equation"] is document["equations"][1]


def test_the_writer_keeps_one_text_per_expression() -> None:
    x, m = sp.symbols("x m")
    text = ExpressionWriter()
    first = text(m * x**2 / 2 + sp.Float(0.5) * x)
    assert first == _sstr(m * x**2 / 2 + sp.Float(0.5) * x)
    assert text(x**2 * m / 2 + sp.Float(0.5) * x) is first
    # a Float and the Rational of the same value are different expressions, each its text
    assert text(sp.Float(0.5) * x) == "0.5*x" and text(x / 2) == "x/2"
