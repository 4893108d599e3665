"""analyze() stays bounded as a system grows: each part is computed or listed among the
failures with a reason naming what grew and what to do, and the renderings say so.

References: the explicit Hamiltonian's size predicted from the mass matrix alone is checked
against the size of the expressions built; Hamilton's equations of a long H against central
differences of H (q_dot = dH/dp, p_dot = -dH/dq); the per-part time share against a part
that never ends.  No assertion is about speed: parts fail by a small size limit, or by a
share of a generous time limit.
"""

from __future__ import annotations

import json
import random
import time

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis import analyze, hamilton_equations, hamiltonian, point_symmetries
from lagrangian.analysis import attempts as attempts_module
from lagrangian.analysis import parts as parts_module
from lagrangian.analysis.hamiltonian import elimination_sizes, velocity_hessian
from lagrangian.analysis.simplification import SIMPLIFIED_ENTRIES, simplify_small_matrix
from lagrangian.errors import AnalysisError, SizeLimitError
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.analysis_text import analysis_text
from lagrangian.size_limits import operations, size_limit


@pytest.fixture(scope="module")
def four_links() -> lg.EquationsOfMotion:
    return lg.derive(lg.examples.n_link_pendulum(4))


def test_the_explicit_inverse_is_refused_before_it_is_built(four_links) -> None:
    with size_limit(1000), pytest.raises(SizeLimitError, match=r"W\^-1 for the 4 x 4 mass"):
        hamiltonian(four_links)
    with size_limit(1000), pytest.raises(SizeLimitError, match=r"about [\d,]+ operations"):
        hamiltonian(four_links)


@pytest.mark.parametrize("links", [4, 5])
def test_the_predicted_size_bounds_the_built_one(links: int) -> None:
    # the prediction from the entries of W alone, against the velocities LUsolve writes
    eom = lg.derive(lg.examples.n_link_pendulum(links))
    legendre = hamiltonian(eom)
    built = [operations(v) for v in legendre.velocities.values()]
    w = velocity_hessian(eom)
    predicted = elimination_sizes(w, sp.Matrix(legendre.momenta))
    assert all(b <= p <= 3 * b for b, p in zip(built, predicted))


def test_hamilton_equations_of_a_long_hamiltonian_are_its_derivatives(four_links) -> None:
    legendre = hamiltonian(four_links)
    equations = hamilton_equations(four_links, legendre)
    names = sorted(legendre.hamiltonian.free_symbols, key=str)
    h = sp.lambdify(names, legendre.hamiltonian)
    rng = random.Random(5)
    point = {s: rng.uniform(0.5, 1.5) for s in names}

    def slope(s: sp.Symbol) -> float:
        step = 1e-6
        up, down = dict(point), dict(point)
        up[s] += step
        down[s] -= step
        return (h(*up.values()) - h(*down.values())) / (2 * step)

    for p, rate in zip(legendre.momenta, equations.coordinate_rates):
        assert float(rate.xreplace(point)) == pytest.approx(slope(p), rel=1e-6, abs=1e-8)
    for q, rate in zip(legendre.coordinates, equations.momentum_rates):
        assert float(rate.xreplace(point)) == pytest.approx(-slope(q), rel=1e-6, abs=1e-8)


def test_a_large_symmetry_search_is_refused_with_its_size() -> None:
    with pytest.raises(AnalysisError, match=r"42 unknown constants.*max_unknowns=42"):
        point_symmetries(lg.examples.n_link_pendulum(6))


def test_a_large_matrix_is_not_simplified_entry_by_entry() -> None:
    x = sp.Symbol("x")
    side = int(SIMPLIFIED_ENTRIES**0.5) + 1
    matrix = sp.Matrix(side, side, lambda i, j: sp.sin(x) ** 2 + sp.cos(x) ** 2)
    assert simplify_small_matrix(matrix)[0, 0] == sp.sin(x) ** 2 + sp.cos(x) ** 2
    assert simplify_small_matrix(matrix[:2, :2])[0, 0] == 1


@pytest.fixture(scope="module")
def limited_report(four_links) -> lg.AnalysisReport:
    return analyze(four_links, search_degree=0, size_limit=1000)


def test_a_part_past_the_size_limit_is_a_failure_the_others_computed(limited_report) -> None:
    report = limited_report
    assert "W^-1 for the 4 x 4 mass matrix" in (report.failure("hamiltonian") or "")
    assert "--size-limit" in (report.failure("hamiltonian") or "")
    assert report.hamiltonian is None and report.hamilton_equations is None
    assert report.energy is not None and report.momenta is not None
    assert report.equilibria is not None and report.normal_modes is not None


def test_the_renderings_say_which_parts_were_not_computed(limited_report) -> None:
    document = analysis_document(limited_report)
    json.dumps(document)
    assert document["hamiltonian"] is None and document["hamilton_equations"] is None
    assert "W^-1" in document["failures"]["hamiltonian"]
    text = analysis_text(limited_report)
    assert "none: the Hamiltonian written out needs W^-1" in text
    assert "Not computed:\n  hamiltonian: the reason is under Hamiltonian" in text
    latex = analysis_latex(limited_report)
    assert r"not computed: hamiltonian: the Hamiltonian written out" in latex


def test_a_part_past_its_share_of_the_time_is_a_failure(monkeypatch) -> None:
    def forever(*args, **kwargs):
        while True:
            time.sleep(0.01)

    monkeypatch.setattr(parts_module, "point_symmetries", forever)
    monkeypatch.setattr(attempts_module, "PART_SHARE", 0.05)
    report = analyze(lg.examples.simple_pendulum(), search_degree=0, time_limit=60)
    reason = report.failure("symmetries") or ""
    assert "symmetries stopped after" in reason and "its share (5%)" in reason
    assert "--timeout" in reason
    assert report.hamiltonian is not None and report.equilibria is not None
    assert report.failures == (report.failures[0],)  # the other parts ran in their time
