"""Multipliers and constraint forces against results derived independently: Newton's second
law along the constraint (rod tension, the normal force on a bead, the skate and the rolling
disc), seed 003's dumbbell, and the unconstrained forms of the same systems among the examples.

Sign convention (DESIGN.md): M q_ddot = forcing + A^T lambda, so lambda_j dh_j/dq is the force
of constraint j."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from constraint_systems import (
    DUMBBELL_PARAMETERS,
    dumbbell,
    knife_edge,
    moving_pivot,
    numeric,
    pendulum,
    pendulum_state,
    rolling_disc,
    rotating_wire,
)

import lagrangian as lg
from lagrangian.constraints import constrained_equations, particle_constraint_forces
from lagrangian.errors import ConstraintError

LAMBDA = sp.Symbol("lambda_1")


def solved(equations, state: dict, name: str) -> float:
    """The explicit solution for ``name`` (an acceleration or multiplier) at ``state``."""
    values = {**{p.name: v for p, v in equations.parameters.items()}, "t": 0.0, **state}
    return numeric(equations.explicit[sp.Symbol(name)], values)


@pytest.mark.parametrize(("angle", "rate"), [(0.0, 0.0), (0.4, 1.3), (-2.1, -0.6), (3.0, 2.5)])
def test_pendulum_rod_tension_is_m_g_cos_theta_plus_m_l_theta_dot_squared(
    angle: float, rate: float
) -> None:
    m, g, l = 1.3, 9.81, 0.7
    equations = constrained_equations(pendulum())
    state = pendulum_state(angle, rate)
    tension = m * g * math.cos(angle) + m * l * rate**2  # Newton along the rod
    # The rod pulls the bob towards the pivot: F = lambda grad h = 2 lambda (x, y) = -T r/l.
    force = particle_constraint_forces(equations, solved=True)["bob"]
    fx, fy = (numeric(f, {"m": m, "g": g, "l": l, **state}) for f in force)
    assert (fx, fy) == pytest.approx((-tension * state["x"] / l, -tension * state["y"] / l))
    assert solved(equations, state, "lambda_1") == pytest.approx(-tension / (2 * l))


def test_pendulum_accelerations_are_the_circular_motion() -> None:
    equations = constrained_equations(pendulum())
    angle, rate = 0.8, -1.1
    state = pendulum_state(angle, rate)
    theta_ddot = -9.81 / 0.7 * math.sin(angle)  # the textbook pendulum
    x_ddot = 0.7 * (math.cos(angle) * theta_ddot - math.sin(angle) * rate**2)
    y_ddot = 0.7 * (math.sin(angle) * theta_ddot + math.cos(angle) * rate**2)
    assert solved(equations, state, "x_ddot") == pytest.approx(x_ddot)
    assert solved(equations, state, "y_ddot") == pytest.approx(y_ddot)


def test_bead_on_a_rotating_wire_feels_the_coriolis_normal_force() -> None:
    # Along the wire r_ddot = omega^2 r; across it the wire pushes with 2 m omega r_dot
    # (Newton in the rotating direction e_phi = (-sin wt, cos wt)).
    m, w = 0.8, 1.7
    equations = constrained_equations(rotating_wire())
    for time, radius, speed in [(0.0, 0.5, 0.3), (0.7, 1.2, -0.8), (2.0, 0.1, 1.5)]:
        c, s = math.cos(w * time), math.sin(w * time)
        state = {
            "t": time,
            "x": radius * c,
            "y": radius * s,
            "x_dot": speed * c - radius * w * s,
            "y_dot": speed * s + radius * w * c,
        }
        force = particle_constraint_forces(equations, solved=True)["bead"]
        values = {"m": m, "omega": w, **state}
        fx, fy = (numeric(f, values) for f in force)
        assert (fx, fy) == pytest.approx((-2 * m * w * speed * s, 2 * m * w * speed * c))
        # radial acceleration r_ddot - r omega^2 = 0, since r_ddot = omega^2 r along the wire
        radial = solved(equations, state, "x_ddot") * c + solved(equations, state, "y_ddot") * s
        assert radial == pytest.approx(0.0, abs=1e-12)


def test_seed_003_dumbbell_multiplier_force_and_motion() -> None:
    """Seed 003 writes the constraint force on particle 2 as f_t = lambda_seed (q1 - q2) and
    solves lambda_seed = -m1 m2/(m1 + m2) theta_dot^2 + ((m2 f1x - m1 f2x) cos(theta)
    + (m2 f1y - m1 f2y) sin(theta)) / (h (m1 + m2)); with h = |q1 - q2|^2 - h0^2 the gradient
    is 2 (q1 - q2), so here the force on particle 2 is -2 lambda (q1 - q2) and
    lambda_seed = 2 lambda."""
    system = dumbbell()
    equations = constrained_equations(system)
    reference = lg.derive(lg.examples.dumbbell())  # seed 003's (x1, y1, theta) form
    parameters = {p.name: v for p, v in system.parameters.items()}
    m1, m2, h = (DUMBBELL_PARAMETERS[k] for k in ("m1", "m2", "h"))
    f1x, f1y, f2x, f2y = (parameters[k] for k in ("f1x", "f1y", "f2x", "f2y"))
    forces = particle_constraint_forces(equations)
    for x1, y1, angle, vx, vy, rate in [
        (0.1, 0.2, 0.3, 1.0, -0.5, 2.0),
        (-1, 3, 2.5, 0, 0.4, -1.2),
    ]:
        c, s = math.cos(angle), math.sin(angle)
        cartesian = {  # q2 = q1 + h (cos(theta), sin(theta)), as in the seed
            "x1": x1, "y1": y1, "x2": x1 + h * c, "y2": y1 + h * s,
            "x1_dot": vx, "y1_dot": vy, "x2_dot": vx - h * s * rate, "y2_dot": vy + h * c * rate,
        }  # fmt: skip
        lam = solved(equations, cartesian, "lambda_1")
        seed = -m1 * m2 / (m1 + m2) * rate**2 + (
            (m2 * f1x - m1 * f2x) * c + (m2 * f1y - m1 * f2y) * s
        ) / (h * (m1 + m2))
        assert 2 * lam == pytest.approx(seed)
        f2 = [numeric(f.subs(LAMBDA, lam), cartesian) for f in forces["particle2"]]
        f1 = [numeric(f.subs(LAMBDA, lam), cartesian) for f in forces["particle1"]]
        d = (-h * c, -h * s)  # q1 - q2
        assert f2 == pytest.approx([-2 * lam * d[0], -2 * lam * d[1]])
        assert f1 == pytest.approx([-v for v in f2])  # action and reaction along the rod
        # Same motion as the (x1, y1, theta) form of lagrangian.examples.dumbbell().
        polar = {**parameters, "x1": x1, "y1": y1, "theta": angle}
        polar.update({"x1_dot": vx, "y1_dot": vy, "theta_dot": rate})
        mass = np.array(
            [[numeric(e, polar) for e in row] for row in reference.mass_matrix.tolist()]
        )
        forcing = np.array([numeric(e, polar) for e in reference.forcing])
        xdd1, ydd1, thdd = np.linalg.solve(mass, forcing)
        expected = {
            "x1_ddot": xdd1,
            "y1_ddot": ydd1,
            "x2_ddot": xdd1 - h * c * rate**2 - h * s * thdd,
            "y2_ddot": ydd1 - h * s * rate**2 + h * c * thdd,
        }
        for name, value in expected.items():
            assert solved(equations, cartesian, name) == pytest.approx(value)


def test_the_augmented_lagrangian_gives_the_first_block_of_equations() -> None:
    """Seed 003: the Euler-Lagrange equations of L + lambda h (with the forces f) are
    M q_ddot - forcing - A^T lambda = 0."""
    system = dumbbell()
    equations = constrained_equations(system)
    augmented = equations.augmented_lagrangian
    applied = lg.derive(system).generalized_forces
    for j, q in enumerate(equations.coordinates):
        v, a = equations.velocities[j], equations.accelerations[j]
        momentum = augmented.diff(v)
        rate = sum(
            momentum.diff(s) * sv + momentum.diff(sv) * sa
            for s, sv, sa in zip(
                equations.coordinates, equations.velocities, equations.accelerations
            )
        )
        euler_lagrange = rate - augmented.diff(q) - applied[j]
        assert sp.expand(euler_lagrange - equations.equations[j]) == 0, a


def test_moving_pivot_written_as_a_constraint_moves_like_the_example() -> None:
    """Seed 000's rheonomic constraint against lagrangian.examples.moving_pivot_pendulum
    (theta with the pivot at x0 cos(omega t))."""
    equations = constrained_equations(moving_pivot())
    reference = lg.derive(lg.examples.moving_pivot_pendulum())
    l, x0, w = 1.0, 0.1, 2.0
    for time, angle, rate in [(0.3, 0.5, 1.0), (1.9, -1.2, -0.3)]:
        pivot, pivot_rate = x0 * math.cos(w * time), -x0 * w * math.sin(w * time)
        pivot_acc = -x0 * w**2 * math.cos(w * time)
        state = {
            "t": time,
            "x": pivot + l * math.sin(angle),
            "y": -l * math.cos(angle),
            "x_dot": pivot_rate + l * math.cos(angle) * rate,
            "y_dot": l * math.sin(angle) * rate,
        }
        values = {"m": 1.0, "g": 9.81, "l": l, "x0": x0, "omega": w}
        values.update({"t": time, "theta": angle, "theta_dot": rate})
        thdd = numeric(reference.explicit_accelerations[0], values)
        x_ddot = pivot_acc + l * (math.cos(angle) * thdd - math.sin(angle) * rate**2)
        assert solved(equations, state, "x_ddot") == pytest.approx(x_ddot)
        y_ddot = l * (math.sin(angle) * thdd + math.cos(angle) * rate**2)
        assert solved(equations, state, "y_ddot") == pytest.approx(y_ddot)


def test_skate_on_an_incline_follows_newton_along_and_across_the_blade() -> None:
    """Velocity v along the blade e = (cos(phi), sin(phi)): m v_dot = -m g sin(alpha) cos(phi);
    across it (n = (sin(phi), -cos(phi))) the blade supplies lambda = -m v phi_dot +
    m g sin(alpha) sin(phi); phi_dot is constant."""
    m, g, alpha = 2.0, 9.81, 0.4
    equations = constrained_equations(knife_edge())
    for heading, speed, turn in [(0.3, 1.2, 0.7), (2.2, -0.4, -1.5)]:
        c, s = math.cos(heading), math.sin(heading)
        state = {"x": 0.5, "y": -1.0, "phi": heading}
        state.update({"x_dot": speed * c, "y_dot": speed * s, "phi_dot": turn})
        v_dot = -g * math.sin(alpha) * c
        assert solved(equations, state, "x_ddot") == pytest.approx(v_dot * c - speed * s * turn)
        assert solved(equations, state, "y_ddot") == pytest.approx(v_dot * s + speed * c * turn)
        assert solved(equations, state, "phi_ddot") == pytest.approx(0.0, abs=1e-12)
        lam = -m * speed * turn + m * g * math.sin(alpha) * s
        assert solved(equations, state, "lambda_1") == pytest.approx(lam)


def test_rolling_disc_spins_up_with_the_rolling_inertia() -> None:
    """(J_spin + m r^2) phi_ddot = tau, theta_ddot = 0, and the contact force is m times the
    contact point's acceleration: lambda = m (x_ddot, y_ddot)."""
    m, r, spin, tau = 1.5, 0.3, 0.07, 0.2
    equations = constrained_equations(rolling_disc())
    heading, turn, rate = 0.9, 0.4, 2.0
    state = {"x": 0.0, "y": 0.0, "theta": heading, "phi": 1.0}
    state.update({"theta_dot": turn, "phi_dot": rate})
    state.update({"x_dot": r * rate * math.cos(heading), "y_dot": r * rate * math.sin(heading)})
    phi_ddot = tau / (spin + m * r**2)
    assert solved(equations, state, "phi_ddot") == pytest.approx(phi_ddot)
    assert solved(equations, state, "theta_ddot") == pytest.approx(0.0, abs=1e-12)
    x_ddot = r * phi_ddot * math.cos(heading) - r * rate * turn * math.sin(heading)
    y_ddot = r * phi_ddot * math.sin(heading) + r * rate * turn * math.cos(heading)
    assert solved(equations, state, "x_ddot") == pytest.approx(x_ddot)
    assert solved(equations, state, "lambda_1") == pytest.approx(m * x_ddot)
    assert solved(equations, state, "lambda_2") == pytest.approx(m * y_ddot)


def test_constraint_forces_do_no_work_on_scleronomic_non_holonomic_systems() -> None:
    # q_dot . A^T lambda = lambda . (A q_dot) = 0 on the constraint set: energy is conserved.
    for system in (knife_edge(), rolling_disc()):
        equations = constrained_equations(system)
        power = (sp.Matrix(equations.velocities).T * equations.generalized_constraint_forces)[0]
        a_q_dot = equations.constraint_jacobian * sp.Matrix(equations.velocities)
        assert sp.expand(power - (sp.Matrix(equations.multipliers).T * a_q_dot)[0]) == 0


def test_the_augmented_system_and_its_pieces() -> None:
    equations = constrained_equations(pendulum())
    assert equations.augmented_matrix.shape == (3, 3)
    assert equations.augmented_matrix[:2, 2] == -equations.constraint_jacobian.T
    assert equations.unknowns == sp.symbols("x_ddot y_ddot lambda_1")
    residual = equations.equations.xreplace(equations.explicit)
    assert sp.simplify(residual) == sp.zeros(3, 1)


def test_an_eom_with_constraints_and_a_large_dense_system_left_augmented() -> None:
    system = pendulum()
    from_eom = constrained_equations(lg.derive(system), system.constraints)
    assert from_eom.explicit == constrained_equations(system).explicit
    with pytest.raises(ConstraintError, match=r"does not carry constraints"):
        constrained_equations(lg.derive(system))
    chain = lg.examples.n_link_pendulum(5)
    tied = chain.replace(constraints=[lg.Holonomic(chain.coordinates[0] - chain.coordinates[1])])
    assert constrained_equations(tied).explicit is None  # dense M, n = 5: augmented form only


def test_redundant_constraints_leave_the_multipliers_undetermined() -> None:
    system = pendulum()
    again = lg.Holonomic(system.constraints[0].expression, name="rod again")
    twice = system.replace(constraints=[*system.constraints, again])
    with pytest.raises(
        ConstraintError, match=r"constraints\[1\]: -l\*\*2 \+ x\*\*2 \+ y\*\*2 = 0 is redundant"
    ):
        constrained_equations(twice)


def test_forces_need_particles_at_cartesian_coordinates() -> None:
    theta = lg.examples.simple_pendulum()
    tied = theta.replace(constraints=[lg.Holonomic(theta.coordinates[0] - lg.t)])
    with pytest.raises(ConstraintError, match=r"particle 'bob' is at .* not at Cartesian"):
        particle_constraint_forces(constrained_equations(tied))


def test_multiplier_names_may_not_clash() -> None:
    system = pendulum()
    clash = system.replace(parameters={**system.parameters, sp.Symbol("lambda_1"): 1.0})
    with pytest.raises(ConstraintError, match=r"lambda_1 are taken"):
        constrained_equations(clash)


def test_a_unilateral_constraint_acts_like_a_holonomic_one_and_its_force_changes_sign() -> None:
    """A particle sliding from rest at the top of a smooth sphere (radius a): with
    v^2 = 2 g a (1 - cos(theta)) from energy, the normal force m g cos(theta) - m v^2/a
    vanishes at cos(theta) = 2/3, where the constraint g = x^2 + y^2 - a^2 >= 0 would start to
    pull (lambda < 0, force 2 lambda r inwards) and releases (textbook)."""
    x, y, m, g, a = sp.symbols("x y m g a")
    sphere = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81, a: 0.5},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Unilateral(x**2 + y**2 - a**2, name="surface")],
    )
    equations = constrained_equations(sphere)
    for cosine, sign in [(0.9, 1), (2 / 3, 0), (0.5, -1)]:
        angle = math.acos(cosine)  # from the top
        speed = math.sqrt(2 * 9.81 * 0.5 * (1 - cosine))
        state = {"x": 0.5 * math.sin(angle), "y": 0.5 * cosine}
        state.update({"x_dot": speed * cosine, "y_dot": -speed * math.sin(angle)})
        lam = solved(equations, state, "lambda_1")
        normal = 9.81 * cosine - speed**2 / 0.5  # m = 1: N = m g cos - m v^2 / a
        assert 2 * lam * 0.5 == pytest.approx(normal, abs=1e-12)
        assert lam == pytest.approx(0.0, abs=1e-12) if sign == 0 else math.copysign(1, lam) == sign
