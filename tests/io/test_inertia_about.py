"""``inertia_about`` in a model file: a rigid body's inertia given about a body point, moved to
the centre of mass by the parallel-axis theorem (a rod about its end: m L^2/3 -> m L^2/12)."""

from __future__ import annotations

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError

m, g, L, theta = sp.symbols("m g L theta")

COMPOUND_PENDULUM = """
coordinates: [theta]
parameters: {m: 2.0, g: 9.81, L: 1.5}
gravity: [0, -g]
rigid_bodies:
  - name: rod
    mass: m
    inertia: m*L**2/3          # about the pivot, the rod's end
    inertia_about: [0, L/2]    # the pivot, from the centre in body axes
    position: [L/2*sin(theta), -L/2*cos(theta)]
    angle: theta
"""

ROD_3D = """
coordinates: [a]
parameters: {m: 1.0, L: 2.0}
rigid_bodies:
  - name: rod
    mass: m
    inertia: [[m*L**2/3, 0, 0], [0, m*L**2/3, 0], [0, 0, 0]]
    inertia_about: [0, 0, -L/2]
    position: [0, 0, 0]
    orientation: {euler: zxz, angles: [a, 0, 0]}
"""


def test_a_compound_pendulum_from_the_inertia_about_its_pivot() -> None:
    system = lg.loads(COMPOUND_PENDULUM)
    assert sp.simplify(system.rigid_bodies[0].inertia - m * L**2 / 12) == 0
    (equation,) = lg.derive(system).equations
    theta_ddot = sp.Symbol("theta_ddot")
    # Goldstein / any course: (m L^2/3) theta_ddot + m g (L/2) sin(theta) = 0
    assert sp.simplify(equation - (m * L**2 / 3 * theta_ddot + m * g * L / 2 * sp.sin(theta))) == 0


def test_a_3d_rod_about_its_end() -> None:
    inertia = lg.loads(ROD_3D).rigid_bodies[0].inertia
    assert sp.simplify(inertia - sp.diag(m * L**2 / 12, m * L**2 / 12, 0)) == sp.zeros(3, 3)


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (("inertia_about: [0, 0, -L/2]", "inertia_about: [0, -L/2]"), "three values"),
        (
            (
                "inertia: [[m*L**2/3, 0, 0], [0, m*L**2/3, 0], [0, 0, 0]]",
                "inertia: {shape: rod, length: L}",
            ),
            "leave out inertia_about",
        ),
    ],
    ids=["a 3-D inertia with a planar point", "a shape"],
)
def test_bad_points_are_refused_by_field(change: tuple[str, str], words: str) -> None:
    text = ROD_3D.replace(*change)
    assert text != ROD_3D
    with pytest.raises(ModelError) as refused:
        lg.loads(text)
    problem = refused.value.problems[0]
    assert problem.field.endswith("inertia_about") and words in problem.fix


def test_a_shape_that_is_not_a_name_is_refused() -> None:
    text = ROD_3D.replace(
        "inertia: [[m*L**2/3, 0, 0], [0, m*L**2/3, 0], [0, 0, 0]]", "inertia: {shape: []}"
    ).replace("    inertia_about: [0, 0, -L/2]\n", "")
    with pytest.raises(ModelError) as refused:  # found by the fuzz run of the loader
        lg.loads(text)
    assert refused.value.problems[0].field.endswith("inertia.shape")
