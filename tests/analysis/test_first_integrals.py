"""First integrals beyond cyclic coordinates and h, against textbook results (Goldstein
§§2.7, 3.9, 13.7; Olver ch. 4-5), each also checked along a simulated trajectory: a
conserved quantity must stay constant on a motion the integrator computed on its own."""

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.first_integrals import first_integrals
from lagrangian.analysis.lie_symmetries import lie_point_symmetries
from lagrangian.analysis.quadratic_integrals import quadratic_integrals
from lagrangian.render.analysis_json import analysis_document

x, y = lg.coordinates("x y")
x_dot, y_dot = lg.velocity(x), lg.velocity(y)
theta, phi = lg.coordinates("theta phi")
m, g, k, k1, k2, c, q, B, E, R, t = sp.symbols("m g k k1 k2 c q B E R t")


def plane(potential=0, extra=0, **parameters) -> lg.System:
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, **parameters},
        kinetic=m * (x_dot**2 + y_dot**2) / 2,
        potential=potential,
        lagrangian=extra,
    )


def sphere() -> lg.System:
    kinetic = m * R**2 / 2 * (lg.velocity(theta) ** 2 + sp.sin(theta) ** 2 * lg.velocity(phi) ** 2)
    return lg.System(coordinates=[theta, phi], parameters={m: 1.0, R: 1.0}, kinetic=kinetic)


def drift(system: lg.System, quantity: sp.Expr, initial: dict) -> float:
    """Largest change of ``quantity`` along a motion, relative to its size."""
    trajectory = lg.simulate(system, initial, 3.0, method="DOP853", rtol=1e-11, atol=1e-12)
    eom = lg.derive(system)
    values = {sp.Symbol(name): value for name, value in trajectory.parameters.items()}
    function = sp.lambdify(
        (t, *eom.coordinates, *eom.velocities), quantity.xreplace(values), modules="numpy"
    )
    along = np.broadcast_to(
        function(trajectory.t, *trajectory.q.T, *trajectory.q_dot.T), trajectory.t.shape
    )
    return float(np.max(np.abs(along - along[0])) / max(1.0, abs(along[0])))


STATE = {t, x, y, x_dot, y_dot, theta, phi, lg.velocity(theta), lg.velocity(phi)}


def proportional(found: sp.Expr, expected: sp.Expr) -> bool:
    """A constant multiple (a number times parameters) of ``expected``."""
    ratio = sp.simplify(found / expected)
    return ratio != 0 and not ratio.free_symbols & STATE


def test_a_particle_on_a_sphere_has_all_three_angular_momentum_components():
    # L_x, L_y are rotations that are not affine in (theta, phi): eta contains cot(theta)
    charges = [s.charge for s in lie_point_symmetries(sphere())]
    v_theta, v_phi = lg.velocity(theta), lg.velocity(phi)
    expected = [
        m * R**2 * v_phi * sp.sin(theta) ** 2,  # L_z
        m * R**2 * (v_theta * sp.sin(phi) + v_phi * sp.sin(theta) * sp.cos(theta) * sp.cos(phi)),
        m * R**2 * (v_theta * sp.cos(phi) - v_phi * sp.sin(theta) * sp.cos(theta) * sp.sin(phi)),
    ]
    for component in expected:
        assert any(proportional(charge, component) for charge in charges), component
        start = {"theta": 1.0, "phi": 0.3, "theta_dot": 0.4, "phi_dot": 0.9}
        assert drift(sphere(), component, start) < 1e-8


def test_a_projectile_has_the_galilean_boost_with_its_divergence_term():
    system = plane(m * g * y, g=9.81)
    symmetries = lie_point_symmetries(system)
    boost = next(s for s in symmetries if s.coordinates[0] == t and s.coordinates[1] == 0)
    assert sp.simplify(boost.divergence - m * x) == 0  # delta L = m x_dot = d(m x)/dt
    assert proportional(boost.charge, x - m * x_dot * t / m)  # x - (p_x/m) t
    assert drift(system, boost.charge, {"x": 0.2, "y": 1, "x_dot": 1.5, "y_dot": 3}) < 1e-8


def test_a_charge_in_crossed_fields_has_the_drifting_guiding_centre():
    # A = (0, B x), E along x: translation in x changes L by d(qBy + qEt)/dt
    system = plane(extra=q * B * x * y_dot + q * E * x, q=1.0, B=2.0, E=0.5)
    charges = [s.charge for s in lie_point_symmetries(system)]
    guiding = m * x_dot - q * B * y - q * E * t  # explicitly time dependent
    assert any(proportional(charge, guiding) for charge in charges)
    assert drift(system, guiding, {"x": 0.1, "y": 0.2, "x_dot": 0.5, "y_dot": -0.3}) < 1e-8


def test_kepler_in_cartesian_coordinates_has_the_laplace_runge_lenz_vector():
    system = plane(-k / sp.sqrt(x**2 + y**2), k=1.0)
    integrals = quadratic_integrals(system)
    r = sp.sqrt(x**2 + y**2)
    angular = x * y_dot - y * x_dot
    lenz = [m * y_dot * angular - k * x / r, -m * x_dot * angular - k * y / r]  # p x L - m k r/r
    for component in lenz:
        assert any(proportional(i, component) for i in integrals), component
        start = {"x": 1.0, "y": 0.0, "x_dot": 0.1, "y_dot": 1.2}
        assert drift(system, component, start) < 1e-8


def test_oscillators_have_their_separate_energies_and_the_fradkin_tensor():
    anisotropic = quadratic_integrals(plane((k1 * x**2 + k2 * y**2) / 2, k1=1.0, k2=2.0))
    for energy in (m * x_dot**2 + k1 * x**2, m * y_dot**2 + k2 * y**2):
        assert any(proportional(i, energy) for i in anisotropic)
    isotropic = plane(k * (x**2 + y**2) / 2, k=1.0)
    fradkin = m * x_dot * y_dot + k * x * y
    assert any(proportional(i, fradkin) for i in quadratic_integrals(isotropic))
    assert drift(isotropic, fradkin, {"x": 1, "y": 0.3, "x_dot": 0.2, "y_dot": -0.5}) < 1e-8


@pytest.mark.parametrize(
    "system",
    [
        lg.System(  # a damped oscillator
            coordinates=[x],
            parameters={m: 1.0, k: 1.0, c: 0.3},
            kinetic=m * x_dot**2 / 2,
            potential=k * x**2 / 2,
            dissipation=c * x_dot**2 / 2,
        ),
        lg.System(  # an oscillator driven at a frequency of its own
            coordinates=[x],
            parameters={m: 1.0, k: 1.0},
            kinetic=m * x_dot**2 / 2,
            potential=k * x**2 / 2,
            generalized_forces={x: sp.cos(3 * t) * x**2},
        ),
    ],
)
def test_nothing_is_reported_conserved_that_is_not(system):
    assert lie_point_symmetries(system) == ()
    assert quadratic_integrals(system) == ()
    assert lg.analyze(system).conserved == ()


def test_the_report_lists_independent_quantities_with_their_origin():
    kepler = plane(-k / sp.sqrt(x**2 + y**2), k=1.0)
    report = lg.analyze(kepler)
    # E, L_z and one component of the Lenz vector: A_x and A_y are bound by
    # A**2 = m**2 k**2 + 2 m E L**2, so only three are independent (2n - 1)
    assert len(report.conserved) == 3
    origins = {quantity.origin for quantity in report.conserved}
    assert "quadratic first integral" in origins and "energy" in origins
    assert report.searched  # what the search covered is said
    listed = analysis_document(report)["conserved_quantities"]
    assert {"origin", "explicit_time"} <= set(listed[0])


def test_the_heavy_symmetric_top_keeps_its_three_classical_integrals():
    report = lg.analyze(lg.examples.heavy_symmetric_top())
    assert [c.name for c in report.conserved][:3] == ["p_phi", "p_psi", "h"]
    assert len(report.conserved) == 3  # the top is integrable with exactly these (Goldstein §5.7)


def test_the_search_is_bounded_and_says_so():
    search = first_integrals(lg.examples.n_link_pendulum(6), known=())
    assert any("not searched" in line for line in search.searched)


def test_an_atwood_machine_has_a_time_dependent_momentum():
    # translating y changes L by g (m1 - m2) = d/dt[g (m1 - m2) t]: the coefficient is a sum of
    # parameters, not a monomial, and is fitted as a polynomial in them
    system = lg.examples.atwood_machine()
    y_, m1, m2 = sp.symbols("y m1 m2")
    momentum = (m1 + m2) * lg.velocity(y_) - g * (m1 - m2) * t
    found = [c.expression for c in lg.analyze(system).conserved]
    assert any(proportional(f, momentum) for f in found)
    assert drift(system, momentum, {"y": 0.5, "y_dot": 0.2}) < 1e-8


def test_the_search_can_be_bounded_or_switched_off():
    system = lg.examples.atwood_machine()
    assert [c.origin for c in lg.analyze(system, search_degree=0).conserved] == ["energy"]
    assert lg.analyze(system, search_degree=0).searched == ()
    with pytest.raises(lg.AnalysisError, match="search_degree"):
        lg.analyze(system, search_degree=-1)
    skipped = lg.analyze(system, search_seconds=-1.0).searched
    assert all("budget" in line for line in skipped)
