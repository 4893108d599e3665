"""The shortcuts that make the Whipple bicycle derive fast give what the definitions give:
angular velocities composed in SymEngine against vee(R^T R_dot) differentiated in SymPy, the
bicycle's mass matrix (Jacobians turned by a heading or a wheel's spin before they are
multiplied) against sum m J^T J + J_w^T I J_w evaluated from the positions and rotation
matrices, and the factored coefficients of the grouped form whatever the order of their terms.
"""

from __future__ import annotations

import random

import numpy as np
import pytest
import symengine as se
import sympy as sp

import lagrangian as lg
from lagrangian.derivation.trig_polynomial import TrigAlgebra
from lagrangian.examples import BENCHMARKS
from lagrangian.model.rotation import (
    angular_velocity_terms,
    body_angular_velocity,
    rotation_sequence,
    spatial_angular_velocity,
    vee,
)
from lagrangian.symbolic.symbols import time_derivative, velocity

YAW, LEAN, PITCH, STEER = sp.symbols("yaw lean pitch steer")
LAM = sp.Symbol("lam", positive=True)
ANGLES = (YAW, LEAN, PITCH, STEER)


def _fork() -> lg.model.Orientation:
    """A bicycle's fork: heading, lean and pitch, then the steer about an axis tilted by lam."""
    frame = rotation_sequence([("z", YAW), ("x", LEAN), ("y", PITCH)])
    return rotation_sequence([("y", -LAM), ("z", -STEER), ("y", LAM)], frame)


def _at(values: dict, expressions) -> np.ndarray:
    return np.array([float(sp.sympify(e).xreplace(values)) for e in expressions])


def _random_state(seed: int) -> dict:
    rng = random.Random(seed)
    values = {s: rng.uniform(-1, 1) for s in (*ANGLES, LAM)}
    values.update({velocity(s): rng.uniform(-1, 1) for s in ANGLES})
    return values


@pytest.mark.parametrize("body", [True, False])
def test_a_composed_angular_velocity_is_that_of_its_rotation_matrix(body: bool) -> None:
    orientation = _fork()
    R = sp.Matrix(orientation.matrix)
    R_dot = R.applyfunc(lambda e: time_derivative(e, ANGLES))
    reference = vee(R.T * R_dot if body else R_dot * R.T)
    composed = (body_angular_velocity if body else spatial_angular_velocity)(orientation, ANGLES)
    for seed in range(3):
        values = _random_state(seed)
        assert np.allclose(_at(values, composed), _at(values, reference), atol=1e-12)
    # the user's symbol objects come back (SymEngine keeps no assumptions)
    assert LAM in sp.Matrix(composed).free_symbols
    # the SymEngine form for the derivation is the same expressions
    terms = angular_velocity_terms(orientation, ANGLES, body=body)
    assert all(e == se.sympify(c) for e, c in zip(terms, composed))


def test_the_bicycles_mass_matrix_is_the_sum_of_its_bodies_shares() -> None:
    """M = sum m J^T J + J_w^T I J_w, J = dp/dq and the columns of J_w vee(R^T dR/dq_j)."""
    system = BENCHMARKS["whipple_bicycle"]()
    q = list(system.coordinates)
    rng = random.Random(7)
    values = {s: rng.uniform(-0.5, 0.5) for s in q}
    values.update({p: v for p, v in system.parameters.items()})
    reference = np.zeros((len(q), len(q)))
    for body in system.rigid_bodies:
        R = sp.Matrix(body.orientation.matrix)
        position = sp.Matrix(body.position).jacobian(q)
        spin = sp.Matrix.hstack(*[vee(R.T * R.diff(s)) for s in q])
        J, J_w, R_at = (
            np.array(sp.Matrix(m).xreplace(values).evalf(), dtype=float)
            for m in (position, spin, R)
        )
        mass = float(sp.sympify(body.mass).xreplace(values))
        inertia = np.array(body.inertia_tensor.xreplace(values).evalf(), dtype=float)
        assert np.allclose(R_at.T @ R_at, np.eye(3))
        reference += mass * J.T @ J + J_w.T @ inertia @ J_w
    derived = np.array(lg.derive(system).mass_matrix.xreplace(values).evalf(), dtype=float)
    assert np.allclose(derived, reference, rtol=1e-10, atol=1e-12)


def test_a_grouped_coefficient_does_not_depend_on_the_order_of_its_terms() -> None:
    x, a, b, c = se.symbols("x a b c")
    algebra = TrigAlgebra([x])
    first = algebra.convert(a * b * se.sin(x) + a * c * se.sin(x) + b * se.cos(x))
    key = next(k for k in first if len(first[k]) == 2)
    swapped = {k: first[k] for k in reversed(list(first))}
    swapped[key] = dict(reversed(first[key].items()))
    grouped = algebra.grouped(algebra.finish(first))
    assert algebra.grouped(algebra.finish(swapped)) == grouped
    assert se.expand(grouped - (a * b * se.sin(x) + a * c * se.sin(x) + b * se.cos(x))) == 0
