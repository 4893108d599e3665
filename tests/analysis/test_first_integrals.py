"""First integrals beyond cyclic coordinates and h, against textbook results (Goldstein
§§2.7, 3.9, 13.7; Olver ch. 4-5), each also checked along a simulated trajectory: a
conserved quantity must stay constant on a motion the integrator computed on its own."""

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.integrals.conditional import candidate_relations
from lagrangian.analysis.integrals.lie_symmetries import lie_point_symmetries
from lagrangian.analysis.integrals.quadratic import cubic_integrals, quadratic_integrals
from lagrangian.analysis.integrals.search import first_integrals
from lagrangian.analysis.manifold.integrals import manifold_integrals
from lagrangian.render.analysis_json import analysis_document
from lagrangian.render.analysis_latex import analysis_latex
from lagrangian.render.analysis_text import analysis_text
from lagrangian.symbolic.symbols import time_derivative

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


# --- the parameter conditions under which a quantity is conserved


def oscillator(k1_value: float, k2_value: float) -> lg.System:
    return plane((k1 * x**2 + k2 * y**2) / 2, k1=k1_value, k2=k2_value)


ANGULAR = m * (x * y_dot - y * x_dot)
OSCILLATING = {"x": 1.0, "y": 0.3, "x_dot": 0.2, "y_dot": -0.5}


def test_the_angular_momentum_of_an_oscillator_holds_only_when_its_springs_are_equal():
    report = lg.analyze(oscillator(1.0, 2.0))
    [conditional] = [c for c in report.conserved if c.conditions]
    assert conditional.conditions == (sp.Eq(k1, k2),)
    assert proportional(conditional.expression, ANGULAR)
    assert not conditional.holds  # k1 = 1, k2 = 2: conserved only under its condition
    assert all(c.holds for c in report.conserved if not c.conditions)
    # dL_z/dt = (k1 - k2) x y: it changes for the values given, and is constant when equal
    assert drift(oscillator(1.0, 2.0), conditional.expression, OSCILLATING) > 1e-2
    assert drift(oscillator(1.5, 1.5), conditional.expression, OSCILLATING) < 1e-8


def test_a_condition_the_values_meet_is_reported_as_holding():
    report = lg.analyze(oscillator(1.5, 1.5))
    [conditional] = [c for c in report.conserved if c.conditions]
    assert conditional.holds and proportional(conditional.expression, ANGULAR)
    document = analysis_document(report)
    listed = {q["name"]: q for q in document["conserved_quantities"]}[conditional.name]
    assert listed["conditions"] == ["Eq(k1, k2)"] and listed["holds"] is True
    assert len(document["conserved"]) == len(report.conserved)
    assert "holds when k1 = k2, as here" in analysis_text(report)


def test_a_condition_the_values_miss_is_said_and_kept_out_of_the_conserved_list():
    report = lg.analyze(oscillator(1.0, 2.0))
    document = analysis_document(report)
    [listed] = [q for q in document["conserved_quantities"] if q["conditions"]]
    assert listed["holds"] is False and listed["expression"] not in document["conserved"]
    assert len(document["conserved"]) == len(report.conserved) - 1
    text = analysis_text(report)
    assert "holds when k1 = k2; not for the parameter values given" in text
    assert "holds when k1 = k2" in analysis_latex(report)


def test_the_fradkin_tensor_needs_equal_springs():
    fradkin = m * x_dot * y_dot + k1 * x * y
    found = quadratic_integrals(oscillator(1.0, 2.0), {"k2": "k1"})
    assert any(proportional(i, fradkin) for i in found)
    assert not any(proportional(i, fradkin) for i in quadratic_integrals(oscillator(1.0, 2.0)))
    # d/dt (m x_dot y_dot + k1 x y) = (k1 - k2) x_dot y on the equations of motion
    assert drift(oscillator(1.0, 2.0), fradkin, OSCILLATING) > 1e-2
    assert drift(oscillator(1.0, 1.0), fradkin, OSCILLATING) < 1e-8


def test_parameters_that_play_no_common_role_are_not_tied():
    assert candidate_relations(plane(-k / sp.sqrt(x**2 + y**2), k=1.0)) == ()  # m, k
    assert candidate_relations(oscillator(1.0, 2.0)) == (sp.Eq(k1, k2),)


# --- constrained systems: on the reduced system, or on the constrained equations

z = lg.coordinates("z")[0]
z_dot = lg.velocity(z)
STATE.update({z, z_dot})


def cartesian_sphere(weight: int) -> lg.System:
    """A particle on a sphere of radius R in x, y, z, gravity along -z when ``weight``."""
    return lg.System(
        coordinates=[x, y, z],
        parameters={m: 1.0, g: 9.81, R: 1.0},
        kinetic=m * (x_dot**2 + y_dot**2 + z_dot**2) / 2,
        potential=weight * m * g * z,
        constraints=[lg.Holonomic(x**2 + y**2 + z**2 - R**2)],
    )


ON_SPHERE = {"x": 0.6, "y": 0.0, "z": -0.8, "x_dot": 0.4, "y_dot": 0.9, "z_dot": 0.3}
ANGULAR_3D = [m * (y * z_dot - z * y_dot), m * (z * x_dot - x * z_dot), ANGULAR]


def test_the_constrained_equations_of_a_sphere_give_the_three_angular_momenta():
    # z = +-sqrt(R**2 - x**2 - y**2) is real on part of the plane only: the search runs on
    # the multiplier form in x, y, z, and must not take x**2 + y**2 + z**2 for an integral
    found = manifold_integrals(cartesian_sphere(0))
    for component in ANGULAR_3D:
        assert any(proportional(i, component) for i in found), component
        assert drift(cartesian_sphere(0), component, ON_SPHERE) < 1e-7
    assert not any(i.free_symbols <= {x, y, z, R} for i in found)


def test_a_heavy_particle_on_a_sphere_keeps_only_its_vertical_angular_momentum_and_energy():
    system = cartesian_sphere(1)
    report = lg.analyze(system)
    assert len(report.conserved) == 2
    assert any(proportional(c.expression, ANGULAR) for c in report.conserved)
    assert "energy" in {c.origin for c in report.conserved}
    assert "constrained equations" in report.searched[0]
    for quantity in report.conserved:
        assert drift(system, quantity.expression, ON_SPHERE) < 1e-7


def test_a_knife_edge_keeps_the_centre_of_its_circle():
    # x_dot sin(phi) = y_dot cos(phi) (Bloch, Nonholonomic Mechanics and Control, §1.6): the
    # blade turns at a constant rate and runs round a circle whose centre is conserved,
    # (x - y_dot/phi_dot, y + x_dot/phi_dot): integrals that come from no symmetry of L
    J = sp.Symbol("J")
    phi_dot = lg.velocity(phi)
    knife = lg.System(
        coordinates=[x, y, phi],
        parameters={m: 1.0, J: 0.5},
        kinetic=m * (x_dot**2 + y_dot**2) / 2 + J * phi_dot**2 / 2,
        constraints=[lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi))],
    )
    report = lg.analyze(knife)
    found = [c.expression for c in report.conserved]
    for centre in (x * phi_dot - y_dot, y * phi_dot + x_dot):
        assert any(proportional(f, centre) for f in found), centre
    assert "non-holonomic" in report.searched[0]
    start = {"x": 0.2, "y": -0.1, "phi": 0.3, "x_dot": np.cos(0.3), "y_dot": np.sin(0.3)}
    for quantity in found:  # none of them false
        assert drift(knife, quantity, {**start, "phi_dot": 0.7}) < 1e-7


@pytest.mark.slow  # the analysis of the disc takes its time, the search is not the cost
def test_a_rolling_disc_reports_its_energy_and_nothing_false():
    disc = lg.examples.rolling_disc()
    report = lg.analyze(disc)
    assert "energy" in {c.origin for c in report.conserved}
    coordinates = {"x": 0.0, "y": 0.0, "theta": 1.2, "psi": 0.0, "phi": 0.0}
    velocities = {"psi_dot": 2.0, "phi_dot": 3.0, "theta_dot": 0.1}
    start = lg.constraints.project_state(disc, {**coordinates, **velocities})
    names = {s.name for s in (*lg.derive(disc).coordinates, *lg.derive(disc).velocities)}
    start = {s.name: value for s, value in start.items() if s.name in names}
    for quantity in report.conserved:
        assert drift(disc, quantity.expression, start) < 1e-7


def test_a_constraint_solved_in_closed_form_is_searched_on_the_reduced_system():
    report = lg.analyze(lg.examples.cylinder_on_incline())
    assert report.searched[0].startswith("searched on the reduced system in x")


# --- integrals cubic in the velocities

q1, q2, q3 = lg.coordinates("q1 q2 q3")
TODA_VELOCITIES = [lg.velocity(s) for s in (q1, q2, q3)]
TODA = lg.System(  # the periodic Toda lattice of three particles, unit masses and springs
    coordinates=[q1, q2, q3],
    kinetic=sum(w**2 for w in TODA_VELOCITIES) / 2,
    potential=sp.exp(q1 - q2) + sp.exp(q2 - q3) + sp.exp(q3 - q1),
)
p1, p2, p3 = TODA_VELOCITIES
STATE.update({q1, q2, q3, *TODA_VELOCITIES})
# Hénon, Phys. Rev. B 9, 1921 (1974): the third integral, cubic in the momenta
HENON = p1 * p2 * p3 - p1 * sp.exp(q2 - q3) - p2 * sp.exp(q3 - q1) - p3 * sp.exp(q1 - q2)
TODA_START = {"q1": 0.3, "q2": -0.2, "q3": 0.1, "q1_dot": 0.5, "q2_dot": -0.1, "q3_dot": 0.2}


def test_henons_integral_is_constant_on_the_toda_equations():
    # the reference checked on its own: dI/dt = 0 with q_ddot_i = -dV/dq_i
    eom = lg.derive(TODA)
    accelerations = {a: -eom.gravity[i] for i, a in enumerate(eom.accelerations)}
    rate = time_derivative(HENON, eom.coordinates).xreplace(accelerations)
    assert sp.simplify(sp.expand(rate)) == 0


def test_the_toda_lattice_has_henons_cubic_integral():
    found = cubic_integrals(TODA, degree=1)
    assert any(proportional(i, HENON) for i in found)
    assert drift(TODA, HENON, TODA_START) < 1e-8


@pytest.mark.slow
def test_search_degree_3_reports_the_cubic_integral():
    report = lg.analyze(TODA, search_degree=3)
    [cubic] = [c for c in report.conserved if c.origin == "cubic first integral"]
    assert proportional(cubic.expression, HENON)
    assert any("cubic in the velocities" in line for line in report.searched)
    for quantity in report.conserved:
        assert drift(TODA, quantity.expression, TODA_START) < 1e-8


@pytest.mark.slow
def test_a_free_body_spins_steadily_about_its_axis_only_when_symmetric():
    # Euler's equation I3 omega3_dot = (I1 - I2) omega1 omega2 (Goldstein §5.6): omega3 is
    # conserved when I1 = I2, found with psi turned by a right angle exchanging I1 and I2
    body = lg.examples.asymmetric_body()
    report = lg.analyze(body)
    [conditional] = [c for c in report.conserved if c.conditions]
    theta_, psi_ = sp.symbols("theta psi")
    omega3 = lg.velocity(phi) * sp.cos(theta_) + lg.velocity(psi_)
    STATE.update({theta_, psi_, lg.velocity(theta_), lg.velocity(psi_)})
    assert proportional(conditional.expression, omega3)
    I1, I2 = sp.symbols("I1 I2")
    assert conditional.conditions == (sp.Eq(I1, I2),) and not conditional.holds
    start = {"phi": 0.1, "theta": 1.0, "psi": 0.2, "phi_dot": 1.0, "theta_dot": 0.5, "psi_dot": 0.3}
    assert drift(body, omega3, start) > 1e-2
    assert drift(body.with_parameters({I2: 2.0, I1: 2.0}), omega3, start) < 1e-8


def test_a_relativistic_particle_has_the_lorentz_boost_charge():
    # L = -m sqrt(1 - x_dot**2) (c = 1) is real only for |x_dot| < 1: the samples beyond are
    # left out.  The boost gives K = t p - x E = m (t x_dot - x) / sqrt(1 - x_dot**2)
    system = lg.System(coordinates=[x], parameters={m: 1.0}, lagrangian=-m * sp.sqrt(1 - x_dot**2))
    charges = [s.charge for s in lie_point_symmetries(system)]
    boost = m * (t * x_dot - x) / sp.sqrt(1 - x_dot**2)
    assert any(proportional(charge, boost) for charge in charges)
    assert drift(system, boost, {"x": 0.1, "x_dot": 0.6}) < 1e-8
