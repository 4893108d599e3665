"""The paths that keep a long chain's derivation proportional to its output: the positions'
terms converted once, the potential's gradient taken term by term, the entries' sizes counted
once per shared sum; each checked against a closed form, SymEngine's own count, or
sympy.physics.mechanics."""

from __future__ import annotations

import threading

import pytest
import symengine as se
import sympy as sp
import sympy.physics.mechanics as me

import lagrangian as lg
from lagrangian.derivation.backend import vector_to_backend
from lagrangian.derivation.terms import euler_lagrange_terms
from lagrangian.derivation.trig import NESTED_CHECK_OPS, size
from lagrangian.size_limits import size_limit
from lagrangian.symbolic.native import to_symengine_sharing
from lagrangian.symbolic.sympy_view import SympyView, TreeOperations


def test_a_long_chains_gravity_is_its_closed_form() -> None:
    """G_j = g l_j (m_j + ... + m_n) sin(theta_j), taken from the expanded potential."""
    n = 40
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(n))
    assert size(terms.assembly.potential) > NESTED_CHECK_OPS  # the term-by-term path
    theta, m, ell = (
        sp.symbols(f"theta1:{n + 1}"),
        sp.symbols(f"m1:{n + 1}"),
        sp.symbols(f"l1:{n + 1}"),
    )
    g = sp.Symbol("g")
    for j in range(n):
        closed = g * ell[j] * sp.Add(*m[j:]) * sp.sin(theta[j])
        assert se.expand(terms.gravity[j] - se.sympify(closed)) == 0


def test_the_gradient_of_a_potential_is_its_derivative_either_way() -> None:
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(40))
    potential = terms.assembly.potential
    by_term = terms.potential_gradient(potential)
    whole = [potential.diff(q) for q in terms.assembly.q]
    assert all(se.expand(a - b) == 0 for a, b in zip(by_term, whole, strict=True))


def test_positions_converted_with_shared_parts_are_the_positions() -> None:
    """A chain's positions repeat the links above them: converted with one memo for all
    (as the assembly converts them), each is what converting it alone gives."""
    system = lg.examples.n_link_pendulum(15)
    shared: dict[object, object] = {}
    for particle in system.particles:
        alone = vector_to_backend(particle.position)
        assert [to_symengine_sharing(x, shared) for x in particle.position] == alone
    x = sp.Symbol("x")
    step = sp.Heaviside(x, evaluate=False) + x**2 + sp.sin(x)  # a function SymPy alone has
    assert to_symengine_sharing(step, {}) == vector_to_backend([step])[0]


@pytest.mark.parametrize("name", ["n_link_pendulum", "double_pendulum", "rolling_disc", "dumbbell"])
def test_operations_are_counted_as_symengine_counts_them(name: str) -> None:
    system = (
        lg.examples.n_link_pendulum(12) if name == "n_link_pendulum" else lg.examples.get(name)()
    )
    terms = euler_lagrange_terms(system)
    counted = TreeOperations()  # one memo for every entry
    entries = [e for row in terms.mass for e in row] + [*terms.forcing, terms.assembly.potential]
    for entry in entries:
        assert counted(entry) == int(se.count_ops(entry))
    # the size check's count, read off the conversion (one view, its memo shared)
    view = SympyView([], terms.view.by_name)
    for entry in entries:
        assert view.operations(entry) == int(se.count_ops(entry))


def test_a_size_limit_still_names_the_entry_past_it() -> None:
    with pytest.raises(lg.SizeLimitError, match="forcing of the equation of theta1"):
        lg.derive(lg.examples.n_link_pendulum(6), size_limit=60)


def _first_past(limit: int, terms) -> str | None:
    """The message's start for the first entry past ``limit`` (M's upper triangle row by
    row, then the forcing), from SymEngine's count of each entry."""
    q, n = terms.coordinates, len(terms.coordinates)
    for j in range(n):
        for k in range(j, n):
            count = int(se.count_ops(terms.mass[j][k]))
            if count > limit:
                return f"the mass matrix entry M[{q[j]}, {q[k]}] has {count:,} operations"
    for j, entry in enumerate(terms.forcing):
        count = int(se.count_ops(entry))
        if count > limit:
            return f"the forcing of the equation of {q[j]} has {count:,} operations"
    return None


@pytest.mark.parametrize("name", ["n_link_pendulum", "double_pendulum", "rolling_disc"])
def test_the_entry_named_is_the_first_past_the_limit_with_its_whole_count(name: str) -> None:
    # counted while converting, the check stops at a subexpression past the limit: the
    # entry it names and the count it gives are still the whole entry's, the first in order
    build = lg.examples.get(name)
    terms = euler_lagrange_terms(build(6) if name == "n_link_pendulum" else build())
    counts = sorted({int(se.count_ops(e)) for row in terms.mass for e in row})
    counts += sorted({int(se.count_ops(e)) for e in terms.forcing})
    for limit in sorted({max(c - 1, 1) for c in counts} | {max(counts)}):
        expected = _first_past(limit, terms)
        system = build(6) if name == "n_link_pendulum" else build()
        if expected is None:
            assert lg.derive(system, size_limit=limit).mass_matrix.shape[0] > 0
            continue
        with pytest.raises(lg.SizeLimitError) as stopped:
            lg.derive(system, size_limit=limit)
        assert f"derive: {expected}, more than the size limit of {limit:,}" in str(stopped.value)


def test_an_entry_converted_before_without_a_limit_is_still_checked() -> None:
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(4))
    view = terms.view
    view.vector(terms.forcing)  # converted, and remembered, without a limit
    count = int(se.count_ops(terms.forcing[0]))
    with size_limit(count - 1), pytest.raises(lg.SizeLimitError, match=f"has {count} operations"):
        view.vector(terms.forcing, lambda j: f"the forcing of the equation of {j}")
    assert view.vector(terms.forcing, lambda j: "unused")[0] == view(terms.forcing[0])


def test_a_size_limit_in_one_thread_does_not_stop_another_threads_conversion() -> None:
    # the view is shared by every derivation of the System, the size limits are per thread
    # (lagrangian.size_limits): a sized conversion under way in one thread neither stops an
    # unsized one in another nor has its limit reset by it
    terms = euler_lagrange_terms(lg.examples.n_link_pendulum(4))
    view = terms.view
    sized, done = threading.Event(), threading.Event()
    seen: list[float] = []

    def sized_conversion() -> None:
        view._sizing.limit = 1  # as SympyView._all sets it for a conversion under a limit
        sized.set()
        done.wait(10)
        seen.append(view._sizing.limit)

    other = threading.Thread(target=sized_conversion)
    other.start()
    assert sized.wait(10)
    converted = view.vector(terms.forcing)  # no limit in this thread: nothing raised
    done.set()
    other.join(10)
    assert seen == [1]
    assert converted == SympyView(view.by_name.values()).vector(terms.forcing)


def _lagranges_method(n: int) -> tuple[sp.Matrix, sp.Matrix]:
    """M and the forcing of the chain from sympy.physics.mechanics' LagrangesMethod, with
    q(t) as the symbol theta_i and q'(t) as theta_i_dot."""
    q = me.dynamicsymbols(f"theta1:{n + 1}")
    m, ell = sp.symbols(f"m1:{n + 1}"), sp.symbols(f"l1:{n + 1}")
    g = sp.Symbol("g")
    frame, origin = me.ReferenceFrame("N"), me.Point("O")
    origin.set_vel(frame, 0)
    previous, bobs = origin, []
    for i in range(n):
        link = frame.orientnew(f"A{i}", "Axis", (q[i], frame.z))
        point = previous.locatenew(f"P{i}", -ell[i] * link.y)
        point.v2pt_theory(previous, frame, link)
        bob = me.Particle(f"bob{i}", point, m[i])
        bob.potential_energy = m[i] * g * point.pos_from(origin).dot(frame.y)
        bobs.append(bob)
        previous = point
    method = me.LagrangesMethod(me.Lagrangian(frame, *bobs), q)
    method.form_lagranges_equations()
    t = me.dynamicsymbols._t
    plain = {qi.diff(t): sp.Symbol(f"theta{i + 1}_dot") for i, qi in enumerate(q)}
    plain.update({qi: sp.Symbol(f"theta{i + 1}") for i, qi in enumerate(q)})
    return method.mass_matrix.xreplace(plain), method.forcing.xreplace(plain)


def _zero(expr: sp.Expr) -> bool:
    return sp.expand(sp.expand_trig(expr)) == 0


@pytest.mark.parametrize(
    "n", [3, 4, pytest.param(5, marks=pytest.mark.slow), pytest.param(6, marks=pytest.mark.slow)]
)
def test_the_chain_is_lagranges_methods_chain(n: int) -> None:
    """M and the forcing equal LagrangesMethod's entry by entry once trigonometry is
    expanded (a chain's entries are polynomials in sines and cosines)."""
    eom = lg.derive(lg.examples.n_link_pendulum(n))
    mass, forcing = _lagranges_method(n)
    assert all(_zero(a - b) for a, b in zip(eom.mass_matrix, mass, strict=True))
    assert all(_zero(a - b) for a, b in zip(eom.forcing, forcing, strict=True))
