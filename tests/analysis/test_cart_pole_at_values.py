"""A cart-pole whose horizontal force F is given as 0: every part of the analysis decides at
that value.

The cart (mass M, position x) carries a pendulum (mass m on a massless rod of length l,
angle theta from the downward vertical); the force F acts along x.  With F = 0, x is cyclic
and p_x = (M + m) x_dot + m l cos(theta) theta_dot is conserved, h = T + V is conserved, and
the pole rests hanging (theta = 0, stable) or upright (theta = pi, unstable) anywhere along
the track: families in x.  Linearized about the hanging pole (Ogata, *Modern Control
Engineering*, the inverted pendulum on a cart with the sign of g reversed), the pole swings
at omega^2 = (M + m) g / (M l) and the cart drifts freely (omega = 0).  For F != 0 the cart
accelerates at any angle: no rest, p_x and h change.
"""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.evaluation import evaluation_context

x, theta, M, m, l, g, F = sp.symbols("x theta M m l g F")
VALUES = {M: 1.0, m: 0.1, l: 0.5, g: 9.81, F: 0.0}


def cart_pole(force: float = 0.0) -> lg.System:
    return lg.System(
        name="cart_pole",
        coordinates=[x, theta],
        parameters={**VALUES, F: force},
        particles=[
            lg.Particle("cart", M, (x, 0)),
            lg.Particle("bob", m, (x + l * sp.sin(theta), -l * sp.cos(theta))),
        ],
        gravity=(0, -g),
        generalized_forces={x: F},
    )


@pytest.fixture(scope="module")
def report() -> lg.AnalysisReport:
    return lg.analyze(cart_pole(), search_degree=0)


def test_the_pole_hangs_stable_and_stands_unstable_anywhere_along_the_track(report) -> None:
    assert report.equilibria is not None
    found = [(dict(e.state), e.stable, e.free) for e in report.equilibria]
    assert found == [
        ({x: x, theta: 0}, True, (x,)),
        ({x: x, theta: sp.pi}, False, (x,)),
    ]
    assert all(e.condition == sp.Eq(F, 0) for e in report.equilibria)
    assert "neutral along x" in report.equilibria.equilibria[0].reason


def test_the_equilibria_say_that_a_nonzero_force_allows_no_rest(report) -> None:
    assert report.equilibria is not None
    assert report.equilibria.general.startswith("for F ≠ 0:")
    assert "no rest" in report.equilibria.general
    assert "at the given parameter values (F = 0)" in report.equilibria.reason


def test_momentum_energy_and_rest_are_all_decided_at_f_zero(report) -> None:
    (cyclic,) = report.cyclic
    assert cyclic.coordinate == x and cyclic.conserved and cyclic.condition == sp.Eq(F, 0)
    assert report.energy is not None and report.energy.conserved
    assert report.energy.condition == sp.Eq(F, 0)
    assert "vanishes at the given parameter values (F = 0)" in report.energy.reason
    names = [c.name for c in report.conserved if c.holds]
    assert names[:2] == ["p_x", "h"]


def test_the_hanging_pole_swings_at_the_textbook_frequency(report) -> None:
    modes = report.normal_modes
    assert modes is not None and dict(modes.about) == {x: 0, theta: 0}
    slow, swing = (float(w.subs(VALUES)) for w in modes.frequencies)
    assert slow == pytest.approx(0.0, abs=1e-12)
    expected = ((VALUES[M] + VALUES[m]) * VALUES[g] / (VALUES[M] * VALUES[l])) ** 0.5
    assert swing == pytest.approx(expected, rel=1e-12)


def test_a_cart_pushed_by_a_nonzero_force_never_rests() -> None:
    pushed = lg.analyze(cart_pole(force=1.0), search_degree=0)
    assert pushed.equilibria is not None and len(pushed.equilibria) == 0
    assert "do not depend on the coordinates: no rest" in pushed.equilibria.reason
    assert pushed.equilibria.general == ""
    assert not pushed.cyclic[0].conserved
    assert pushed.energy is not None and not pushed.energy.conserved
    assert "No stable equilibrium" in (pushed.failure("normal_modes") or "")


def test_a_force_set_to_zero_in_the_call_counts_as_given() -> None:
    pushed_then_released = lg.analyze(cart_pole(force=1.0), parameters={"F": 0}, search_degree=0)
    assert pushed_then_released.equilibria is not None
    assert [e.stable for e in pushed_then_released.equilibria] == [True, False]


def test_the_context_tells_zero_at_the_values_from_zero_in_general() -> None:
    context = evaluation_context(cart_pole())
    assert context.is_zero_at_values(F) and not context.is_zero_in_general(F)
    assert not context.is_zero_at_values(m * g)
    assert context.vanishing_condition(F * sp.Symbol("x_dot")) == sp.Eq(F, 0)
    assert context.vanishing_condition(m * g) is None
    assert context.numbered == frozenset({M, m, l, g, F})
    released = evaluation_context(cart_pole(force=1.0), {"F": "m - m"})
    assert released.is_zero_in_general(F) and released.values[F] == 0
