"""Rigid motions in 3-D (Murray, Li & Sastry 1994, ch. 2): the pose g = (R, p) of a body frame, its
twists and the adjoint that relates them.  Twists are ordered (v, omega):

    body:     g^-1 g_dot = [[hat(omega_b), v_b], [0, 0]],  V_b = (R^T p_dot, vee(R^T R_dot))
    spatial:  g_dot g^-1 = [[hat(omega_s), v_s], [0, 0]],  V_s = (p_dot - omega_s x p, omega_s)
    V_s = Ad_g V_b,   Ad_g = [[R, hat(p) R], [0, R]]

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> body_twist(sp.eye(3), [x, 0, 0], [x]).T
Matrix([[x_dot, 0, 0, 0, 0, 0]])
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import sympy as sp

from lagrangian.model.rotation import (
    as_orientation,
    body_angular_velocity,
    hat,
    spatial_angular_velocity,
)
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import time_derivative


def adjoint(rotation: Any, position: Sequence[Any]) -> sp.ImmutableMatrix:
    """Ad_g of the pose g = (R, p), twists ordered (v, omega) as in MLS94 ch. 2:

        Ad_g = [[R, hat(p) R], [0, R]],   V_s = Ad_g V_b.

    >>> adjoint(sp.eye(3), [0, 0, 1])[0, 4]
    -1
    """
    R = sp.ImmutableMatrix(as_orientation(rotation).matrix)
    return sp.ImmutableMatrix(
        sp.BlockMatrix([[R, hat(position) * R], [sp.zeros(3), R]]).as_explicit()
    )


def adjoint_inverse(rotation: Any, position: Sequence[Any]) -> sp.ImmutableMatrix:
    """Ad_g^-1 = Ad_(g^-1) = [[R^T, -R^T hat(p)], [0, R^T]].

    >>> (adjoint_inverse(sp.eye(3), [1, 2, 3]) * adjoint(sp.eye(3), [1, 2, 3])).is_Identity
    True
    """
    R = sp.ImmutableMatrix(as_orientation(rotation).matrix)
    return sp.ImmutableMatrix(
        sp.BlockMatrix([[R.T, -R.T * hat(position)], [sp.zeros(3), R.T]]).as_explicit()
    )


def body_twist(
    orientation: Any, position: Sequence[Any], coordinates: Iterable[sp.Symbol]
) -> sp.ImmutableMatrix:
    """V_b = (v_b, omega_b) = (R^T p_dot, vee(R^T R_dot)) of the body frame at ``position``.

    >>> x = sp.Symbol("x")
    >>> body_twist(sp.eye(3), [x, 0, 0], [x]).T
    Matrix([[x_dot, 0, 0, 0, 0, 0]])
    """
    q = tuple(coordinates)
    R = as_orientation(orientation).matrix
    p_dot = sp.Matrix([time_derivative(to_sympy(x), q) for x in position])
    return sp.ImmutableMatrix.vstack(
        sp.ImmutableMatrix(R.T * p_dot), body_angular_velocity(orientation, q)
    )


def spatial_twist(
    orientation: Any, position: Sequence[Any], coordinates: Iterable[sp.Symbol]
) -> sp.ImmutableMatrix:
    """V_s = (v_s, omega_s) = (p_dot - omega_s x p, vee(R_dot R^T)) (MLS94 ch. 2: v_s is the
    velocity of the body point that passes through the world origin).  A body turning about
    the world z axis:

    >>> from lagrangian.model.rotation import axis_angle
    >>> x = sp.Symbol("x")
    >>> spatial_twist(axis_angle([0, 0, 1], x), [sp.cos(x), sp.sin(x), 0], [x]).T
    Matrix([[0, 0, 0, 0, 0, x_dot]])
    """
    q = tuple(coordinates)
    omega = spatial_angular_velocity(orientation, q)
    p = sp.Matrix(list(position))
    p_dot = p.applyfunc(lambda e: time_derivative(e, q))
    return sp.ImmutableMatrix.vstack(
        sp.ImmutableMatrix((p_dot - omega.cross(p)).applyfunc(sp.expand)), omega
    )
