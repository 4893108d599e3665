"""The conversion of the derived equations from SymEngine builds, entry by entry, exactly
what SymPy's own conversion of the same SymEngine expression builds (``sympify``, SymPy's
constructors evaluating every sum, product and function): the same tree (``srepr``), the
same hash.  Checked on planar chains, 3-D bodies, a rolling body and circuits."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.symbolic.objects import sympy_object

EXAMPLES = [
    "double_pendulum",
    "heavy_symmetric_top",
    "physical_pendulum_3d",
    "asymmetric_body",
    "rolling_disc",
    "robot_arm",
    "two_mesh_circuit",
    "series_rlc",
    "charged_particle_em",
    "moving_pivot_pendulum",
]


def plain_conversion(entry: object, symbols: dict[str, sp.Symbol]) -> sp.Expr:
    """SymPy's own conversion of a SymEngine ``entry``, its symbols the user's objects."""
    converted = sympy_object(entry)
    swap = {s: symbols[s.name] for s in converted.free_symbols if s.name in symbols}
    return converted.xreplace(swap)


def assert_same_entries(system: lg.System) -> int:
    """Every entry of M and the forcing as SymPy converts it; the number compared."""
    equations = lg.derive(system)
    terms = euler_lagrange_terms(system)
    symbols = {s.name: s for s in terms.view.by_name.values()}
    n = len(terms.coordinates)
    pairs = [(equations.mass_matrix[j, k], terms.mass[j][k]) for j in range(n) for k in range(n)]
    pairs += [(equations.forcing[j], terms.forcing[j]) for j in range(n)]
    for fast, entry in pairs:
        plain = plain_conversion(entry, symbols)
        assert sp.srepr(fast) == sp.srepr(plain)
        assert hash(fast) == hash(plain)
    return len(pairs)


@pytest.mark.parametrize("name", EXAMPLES)
def test_built_in_examples_convert_as_sympy_does(name: str) -> None:
    assert assert_same_entries(lg.examples.get(name)()) > 0


@pytest.mark.parametrize("links", [3, 9])
def test_chains_convert_as_sympy_does(links: int) -> None:
    assert assert_same_entries(lg.examples.n_link_pendulum(links)) == links * links + links
