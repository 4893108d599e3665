"""eliminate(): the System in minimal coordinates, checked against the textbook equations of
the same systems and against the multiplier form along the constraint set."""

from __future__ import annotations

import math

import pytest
import sympy as sp
from constraint_systems import (
    dumbbell,
    hoop_state,
    numeric,
    pendulum,
    pendulum_state,
    rotating_hoop,
    rotating_wire,
)

import lagrangian as lg
from lagrangian.constraints import constrained_equations, eliminate
from lagrangian.errors import ConstraintError

x, y, z, phi, theta, rho, s = sp.symbols("x y z phi theta rho s")
m, g, l, r, omega, R = sp.symbols("m g l r omega R")
theta_ddot, rho_ddot = sp.symbols("theta_ddot rho_ddot")
t = lg.t


def equation(system: lg.System) -> sp.Expr:
    (residual,) = lg.derive(system).equations
    return residual


def test_cartesian_pendulum_reduces_to_the_textbook_pendulum() -> None:
    reduced = eliminate(pendulum(), [theta], {x: l * sp.sin(theta), y: -l * sp.cos(theta)})
    assert reduced.coordinates == (theta,) and reduced.constraints == ()
    expected = m * l**2 * theta_ddot + m * g * l * sp.sin(theta)
    assert sp.simplify(equation(reduced) - expected) == 0


def test_reduced_and_multiplier_forms_give_the_same_motion() -> None:
    reduced = lg.derive(
        eliminate(pendulum(), ["theta"], {"x": "l*sin(theta)", "y": "-l*cos(theta)"})
    )
    multipliers = constrained_equations(pendulum())
    parameters = {"m": 1.3, "g": 9.81, "l": 0.7}
    for angle, rate in [(0.3, 0.0), (-1.4, 2.2), (2.9, -0.7)]:
        thdd = numeric(reduced.explicit_accelerations[0], {**parameters, "theta": angle})
        state = {**parameters, **pendulum_state(angle, rate)}
        x_ddot = 0.7 * (math.cos(angle) * thdd - math.sin(angle) * rate**2)
        y_ddot = 0.7 * (math.sin(angle) * thdd + math.cos(angle) * rate**2)
        assert numeric(multipliers.explicit[sp.Symbol("x_ddot")], state) == pytest.approx(x_ddot)
        assert numeric(multipliers.explicit[sp.Symbol("y_ddot")], state) == pytest.approx(y_ddot)


def test_cylinder_rolling_down_an_incline_solved_for_the_spin() -> None:
    # (m + I/r^2) x_ddot = m g sin(alpha): the textbook rolling cylinder.
    inertia, alpha = sp.symbols("I alpha")
    x_dot, phi_dot = sp.symbols("x_dot phi_dot")
    rolling = lg.System(
        coordinates=[x, phi],
        parameters=[m, g, r, inertia, alpha],
        kinetic=m * x_dot**2 / 2 + inertia * phi_dot**2 / 2,
        potential=-m * g * sp.sin(alpha) * x,
        constraints=[lg.Holonomic(x - r * phi, name="no slip")],
    )
    reduced = eliminate(rolling, [x])
    x_ddot = sp.Symbol("x_ddot")
    assert (
        sp.simplify(equation(reduced) - ((m + inertia / r**2) * x_ddot - m * g * sp.sin(alpha)))
        == 0
    )


def test_bead_on_a_rotating_wire_is_flung_outwards() -> None:
    # rho_ddot = omega^2 rho along a wire turning at omega (rheonomic point transformation)
    wire = {x: rho * sp.cos(omega * t), y: rho * sp.sin(omega * t)}
    reduced = eliminate(rotating_wire(), [rho], wire)
    assert sp.simplify(equation(reduced) - (m * rho_ddot - m * omega**2 * rho)) == 0


def test_bead_on_a_rotating_hoop_textbook_equation_and_the_multiplier_form() -> None:
    hoop = {
        x: R * sp.sin(theta) * sp.cos(omega * t),
        y: R * sp.sin(theta) * sp.sin(omega * t),
        z: -R * sp.cos(theta),
    }
    reduced = eliminate(rotating_hoop(), [theta], hoop)
    expected = (
        m * R**2 * theta_ddot
        + m * g * R * sp.sin(theta)
        - m * R**2 * omega**2 * (sp.sin(theta) * sp.cos(theta))
    )
    assert sp.simplify(equation(reduced) - expected) == 0
    multipliers = constrained_equations(rotating_hoop())
    parameters = {"m": 0.5, "g": 9.81, "R": 0.4, "omega": 3.0}
    for angle, rate, time in [(0.7, 0.5, 0.2), (2.0, -1.0, 1.3)]:
        thdd = (9.0 * math.cos(angle) - 9.81 / 0.4) * math.sin(angle)
        dt = 1e-4  # second difference of the parametrized position: independent of both forms
        states = [
            hoop_state(
                angle + k * rate * dt + (k * dt) ** 2 * thdd / 2,
                rate + k * dt * thdd,
                time + k * dt,
            )
            for k in (-1, 0, 1)
        ]
        for name in ("x", "y", "z"):
            expected_acc = (states[2][name] - 2 * states[1][name] + states[0][name]) / dt**2
            got = numeric(
                multipliers.explicit[sp.Symbol(f"{name}_ddot")], {**parameters, **states[1]}
            )
            assert got == pytest.approx(expected_acc, rel=1e-4, abs=1e-5)


def test_the_dumbbell_reduces_to_seed_003s_form_with_the_forces_by_virtual_work() -> None:
    h = sp.Symbol("h")
    x1, y1, x2, y2 = sp.symbols("x1 y1 x2 y2")
    reduced = eliminate(
        dumbbell(), ["x1", "y1", "theta"], {x2: x1 + h * sp.cos(theta), y2: y1 + h * sp.sin(theta)}
    )
    reference = lg.derive(lg.examples.dumbbell().replace(parameters=dumbbell().parameters))
    assert sp.simplify(lg.derive(reduced).equations - reference.equations) == sp.zeros(3, 1)


def test_generalized_forces_of_eliminated_coordinates_act_by_virtual_work() -> None:
    push = sp.Symbol("F")
    pushed = pendulum().replace(
        parameters={**pendulum().parameters, push: 0.5}, generalized_forces={x: push}
    )
    reduced = eliminate(pushed, [theta], {x: l * sp.sin(theta), y: -l * sp.cos(theta)})
    assert reduced.generalized_forces == {theta: push * l * sp.cos(theta)}  # F dx/dtheta


def test_solution_branches_are_chosen_by_the_initial_state_or_refused() -> None:
    ring = lg.System(
        coordinates=[x, y], parameters={l: 1.0}, constraints=[lg.Holonomic(x**2 + y**2 - l**2)]
    )
    with pytest.raises(ConstraintError, match=r"2 solution branches .* parametrization"):
        eliminate(ring, [y])
    right = eliminate(ring.replace(initial={x: 0.6, y: 0.8}), [y])
    assert right.initial == {y: 0.8}
    assert lg.derive(right).coordinates == (y,)


def test_velocity_constraints_are_carried_into_the_new_coordinates() -> None:
    x_dot, y_dot = sp.symbols("x_dot y_dot")
    skate = lg.System(
        coordinates=[x, y, phi, s],
        constraints=[
            lg.Holonomic(s - 2 * x, name="shadow"),
            lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi), name="blade"),
        ],
    )
    reduced = eliminate(skate, [x, y, phi])
    assert reduced.constraints == (
        lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi), name="blade"),
    )
    kept = eliminate(skate, [s, y, phi])  # x = s/2: the blade in s
    (blade,) = kept.constraints
    assert (
        sp.simplify(blade.expression - (sp.Symbol("s_dot") / 2 * sp.sin(phi) - y_dot * sp.cos(phi)))
        == 0
    )


@pytest.mark.parametrize(
    ("independent", "parametrization", "match"),
    [
        (
            [theta],
            {x: l * sp.cos(theta), y: l * sp.cos(theta)},
            r"do not satisfy 'rod' \(constraints\[0\]\)",
        ),
        ([theta], {x: l * sp.sin(theta)}, r"must give every coordinate .* missing \['y'\]"),
        (
            [theta, phi],
            {x: l * sp.sin(theta), y: -l * sp.cos(theta)},
            r"2 independent coordinates given, but .* leave 1",
        ),
        ([theta], None, r"not coordinates; new coordinates need a parametrization"),
    ],
)
def test_bad_eliminations_are_refused(
    independent: list, parametrization: dict | None, match: str
) -> None:
    with pytest.raises(ConstraintError, match=match):
        eliminate(pendulum(), independent, parametrization)


def test_a_3d_body_orientation_is_rewritten_in_the_new_coordinates() -> None:
    """A box hanging from a spherical joint (ZYX angles a, b) constrained to b = a / 2: the
    reduced system equals the one built directly with b = a / 2 (the orientation matrix, its
    angular velocity and the gimbal-lock expression all follow the substitution)."""
    a, b, c = sp.symbols("a b c")
    shape = lg.model.inertia.box(m, 1, 2, 3)

    def top(
        angles: tuple[sp.Expr, ...], coordinates: list[sp.Symbol], **extra: object
    ) -> lg.System:
        rotation = lg.model.rotation.euler_rotation("ZYX", angles)
        centre = rotation.matrix * sp.Matrix([0, 0, -l])
        return lg.System(
            coordinates=coordinates,
            parameters={m: 1.0, g: 9.81, l: 1.0},
            gravity=(0, 0, -g),
            rigid_bodies=[lg.RigidBody("box", m, shape, tuple(centre), orientation=rotation)],
            **extra,  # type: ignore[arg-type]
        )

    constrained = top((a, b, c), [a, b, c], constraints=[lg.Holonomic(b - a / 2)])
    reduced = eliminate(constrained, [a, c])
    direct = top((a, a / 2, c), [a, c])
    assert reduced.rigid_bodies[0].orientation.gimbal_lock == sp.cos(a / 2)
    difference = lg.derive(reduced).mass_matrix - lg.derive(direct).mass_matrix
    assert sp.simplify(difference) == sp.zeros(2, 2)
