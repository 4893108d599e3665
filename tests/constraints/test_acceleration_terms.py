"""gamma of A q_ddot = gamma in the multiplier form, built from each constraint's partial
derivatives, against -(dc/dt at q_ddot = 0) differentiated whole in SymPy, at random states:
a contact-point constraint of a body turned by three rotations written in world axes and in
body axes, one too large to tidy (left unexpanded), and constraints with radicals of the state
(differentiated through their bases), nested, in denominators and rheonomic; a number times
a sum distributed before converting, against SymPy's own product."""

from __future__ import annotations

import random

import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.constraints.pfaffian import TIDY_OPS, pfaffian_form
from lagrangian.derivation.backend import SympyView, to_backend
from lagrangian.model import rotation_sequence
from lagrangian.symbolic.symbols import acceleration, t, time_derivative, velocity

a, b, c, x, y, z = sp.symbols("a b c x y z")
r, m = sp.symbols("r m")
Q = [x, y, z, a, b, c]
R = rotation_sequence([("z", a), ("x", b), ("y", c)]).matrix
CENTRE = sp.Matrix([x, y, z])


def _system(constraints: list[lg.VelocityConstraint]) -> lg.System:
    ball = lg.RigidBody("ball", m, sp.diag(m, m, m), (x, y, z), rotations=[("z", a), ("x", b)])
    return lg.System(coordinates=Q, parameters=[r, m], rigid_bodies=[ball], constraints=constraints)


def _omega() -> sp.Matrix:
    """The spatial angular velocity of R, from R_dot R^T."""
    R_dot = R.applyfunc(lambda e: time_derivative(e, Q))
    W = R_dot * R.T
    return sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])


def _no_slip(world: bool) -> list[lg.VelocityConstraint]:
    """The velocity of the body point at -r R e_z (world axes), or the same in body axes."""
    point = -r * R * sp.Matrix([0, 0, 1])
    speed = CENTRE.applyfunc(lambda e: time_derivative(e, Q)) + _omega().cross(point)
    rows = speed if world else R.T * speed
    return [lg.VelocityConstraint(e) for e in rows[:2]]


def _assert_gamma_is_the_rate(system: lg.System) -> None:
    gamma = lg.constrained_equations(system).gamma
    rng = random.Random(7)
    for _ in range(3):
        values = {s: rng.uniform(-1.2, 1.2) for s in Q}
        values.update({velocity(s): rng.uniform(-1.5, 1.5) for s in Q})
        values.update({r: 0.7, m: 1.3, t: 0.2})
        for constraint, ours in zip(system.constraints, gamma):
            rate = time_derivative(constraint.expression, Q)
            exact = -rate.xreplace({acceleration(s): 0 for s in Q})
            difference = (ours - exact).xreplace(values).evalf(30)
            assert abs(difference) < 1e-12 * (1 + abs(exact.xreplace(values).evalf(30)))


def test_gamma_of_a_contact_constraint_in_world_axes() -> None:
    _assert_gamma_is_the_rate(_system(_no_slip(world=True)))


def test_gamma_of_the_same_constraint_in_body_axes() -> None:
    _assert_gamma_is_the_rate(_system(_no_slip(world=False)))


def test_gamma_of_a_constraint_too_large_to_tidy() -> None:
    (first, _) = _no_slip(world=True)
    big = sp.expand(first.expression * (1 + sp.sin(a) * sp.cos(b) + sp.cos(c)) ** 3)
    assert sp.count_ops(big.diff(a)) > TIDY_OPS
    _assert_gamma_is_the_rate(_system([lg.VelocityConstraint(big)]))


def test_gamma_of_constraints_with_radicals_of_the_state() -> None:
    """The rate of a contact height with sqrt(1 - s**2) (a torus wheel's), whose derivative
    has the radical in numerators and denominators, and a rheonomic nested radical."""
    s = sp.sin(b) * sp.cos(c) + sp.sin(a) * sp.sin(c) / 3
    height = z - r * sp.sqrt(1 - s**2) + x * sp.sqrt(1 - s**2) ** 3 / 5
    nested = sp.sqrt(2 + x**2 + sp.sqrt(1 + t**2 * y**2 + sp.sin(a) ** 2))
    constraints = [
        lg.VelocityConstraint(time_derivative(height, Q)),
        lg.VelocityConstraint(x * velocity(y) * nested + velocity(c) / nested + t * nested),
    ]
    _assert_gamma_is_the_rate(_system(constraints))


def test_the_constraint_jacobian_of_a_velocity_constraint_is_expanded() -> None:
    """a_k = dc/dq_dot_k expanded (as SymPy's expand writes it), and the form is made once
    per constraint expression and coordinates."""
    first = lg.VelocityConstraint(velocity(x) * (1 + sp.sin(a)) * (r + y) - velocity(y) * z)
    form = pfaffian_form(first, Q)
    assert form.coefficients[0] == sp.expand((1 + sp.sin(a)) * (r + y))
    assert form.coefficients[1] == -z and form.time_coefficient == 0
    assert pfaffian_form(lg.VelocityConstraint(first.expression, name="again"), Q) is form


def test_a_number_times_a_sum_converts_as_sympys_product() -> None:
    """SymPy distributes a rational number over a sum (``Mul.flatten``), SymEngine keeps the
    product: gamma's -(rate) converted must be SymPy's own product, term for term."""
    u, v, w = sp.symbols("u v w")
    sums = [
        u + v,
        2 * u * v - 3 * sp.sin(w) + 5,
        u * (v + w) - sp.sqrt(1 + u**2) * w / 2 + v**3,
        -u * v * (v - w) ** 2 + sp.cos(u) * sp.sin(v) - 1,
    ]
    view = SympyView([u, v, w])
    for total in sums:
        for number in (-1, 2, sp.Rational(-1, 2)):
            fast = se.Mul(to_backend(number), to_backend(total))
            assert fast.is_Mul  # SymEngine keeps the product
            expected = sp.Mul(number, total)
            assert sp.srepr(view(fast)) == sp.srepr(expected)
