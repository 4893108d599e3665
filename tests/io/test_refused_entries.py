"""Entries refused with their reason: a frame given a mass, an energy with a kink in the
velocities (while the same kink in a dissipation function is Coulomb friction)."""

import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.io.load import loads

FRAME = """coordinates: [theta]
frames:
  - {name: arm, %s}
kinetic: theta_dot**2/2
"""


@pytest.mark.parametrize("key", ["mass: 1", "inertia: 1", "position: [0, 0, 0]"])
def test_a_frame_given_a_mass_says_frames_have_no_mass(key):
    with pytest.raises(ModelError, match=r"frames\[0\]\.\w+.*frames have no \w+.*rigid body"):
        loads(FRAME % key)


@pytest.mark.parametrize(
    ("field", "text"),
    [
        ("kinetic", "x_dot**2/2 + Abs(x_dot)"),
        ("kinetic", "x_dot**2*(1 + Heaviside(x_dot))/2"),
        ("kinetic", "Abs(x_dot)**2"),
        ("lagrangian", "x_dot**2/2 - x**2/2 + sign(x_dot)*x"),
        ("velocity_potential", "x*Abs(x_dot)"),
    ],
)
def test_an_energy_not_smooth_in_the_velocities_is_refused_by_field(field, text):
    model = f"coordinates: [x]\n{field}: {text}\n"
    if field != "kinetic" and field != "lagrangian":
        model += "kinetic: x_dot**2/2\n"
    with pytest.raises(ModelError, match=rf"{field}.*not smooth in the velocities.*dissipation"):
        loads(model)


def test_a_kink_in_the_coordinates_is_accepted_in_the_kinetic_energy():
    # T = (1 + |x|) x_dot**2 / 2: M = 1 + |x|, dT/dx = sign(x) x_dot**2 / 2, so
    # (1 + |x|) x_ddot + sign(x) x_dot**2 - sign(x) x_dot**2 / 2 = 0
    system = loads("coordinates: [x]\nkinetic: (1 + Abs(x))*x_dot**2/2\n")
    x, v, a = sp.symbols("x x_dot x_ddot")
    expected = (1 + sp.Abs(x)) * a + sp.sign(x) * v**2 / 2
    assert sp.simplify(lg.derive(system).equations[0] - expected) == 0


def test_coulomb_friction_as_a_dissipation_function_is_still_accepted():
    system = loads("coordinates: [x]\nkinetic: x_dot**2/2\ndissipation: Abs(x_dot)\n")
    equation = lg.derive(system).equations[0]
    assert sp.simplify(equation - (sp.Symbol("x_ddot") + sp.sign(sp.Symbol("x_dot")))) == 0
