"""The multiplier form in the C loop, against SciPy's solve_ivp driving the NumPy multiplier
form (:mod:`lagrangian.numerics.constrained`) on the same systems, and the constraint
residuals it keeps.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.constraints import ConstrainedEquations, constrained_equations
from lagrangian.numerics.constrained import compile_constrained
from lagrangian.numerics.fast import c_loop
from lagrangian.numerics.fast.c_constrained import native_constrained
from lagrangian.numerics.fast.compiled_rates import FastEquations
from lagrangian.numerics.fast.constrained import BAUMGARTE
from lagrangian.numerics.fast.settings import Settings

if not c_loop.available():
    pytest.skip("no C compiler for the C loop", allow_module_level=True)

x, y, phi, m, g, inertia = sp.symbols("x y phi m g I")


def fast_constrained_equations(equations: ConstrainedEquations) -> FastEquations:
    """The multiplier form compiled for the C loop."""
    form = native_constrained(equations)
    assert form is not None
    return form.equations


def bead_on_ring() -> lg.System:
    """A bead on the unit circle under gravity: holonomic x^2 + y^2 = 1."""
    return lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("bead", m, (x, y))],
        constraints=[lg.Holonomic(x**2 + y**2 - 1)],
    )


def knife_edge() -> lg.System:
    """A sled on a tilted plane whose blade cannot slide sideways: x_dot sin(phi) = y_dot
    cos(phi) (Neimark & Fufaev, the Chaplygin sled on an incline)."""
    x_dot, y_dot, phi_dot = sp.symbols("x_dot y_dot phi_dot")
    return lg.System(
        coordinates=[x, y, phi],
        parameters={m: 1.0, g: 1.0, inertia: 0.5},
        kinetic=m * (x_dot**2 + y_dot**2) / 2 + inertia * phi_dot**2 / 2,
        potential=m * g * x,
        constraints=[lg.VelocityConstraint(x_dot * sp.sin(phi) - y_dot * sp.cos(phi))],
    )


CASES = {
    "ring": (bead_on_ring, [1.0, 0.0, 0.0, 0.5], [1.0, 9.81]),
    "knife edge": (knife_edge, [0.0, 0.0, 0.3, 0.0, 0.0, 1.0], [1.0, 1.0, 0.5]),
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("baumgarte", [(0.0, 0.0), (5.0, 5.0)])
def test_the_multiplier_form_integrates_as_solve_ivp_does(
    case: str, baumgarte: tuple[float, float]
) -> None:
    build, x0, p = CASES[case]
    equations = constrained_equations(build())
    reference_form = compile_constrained(equations)
    n = len(equations.coordinates)

    def rhs(t: float, state: np.ndarray) -> np.ndarray:
        q_ddot, _ = reference_form.accelerations(state[:n], state[n:], t, np.array(p), *baumgarte)
        return np.concatenate((state[n:], q_ddot))

    times = np.linspace(0.0, 3.0, 7)
    reference = solve_ivp(
        rhs, (0.0, 3.0), x0, method="DOP853", rtol=1e-11, atol=1e-11, t_eval=times
    )
    fast = fast_constrained_equations(equations)
    assert fast.parameters[-2:] == BAUMGARTE
    settings = Settings("DOP853", (0.0, 3.0), times, 1e-11, 1e-11)
    run = c_loop.integrate(fast, settings, np.array(x0), np.array([*p, *baumgarte]))
    assert np.max(np.abs(run.x - reference.y.T)) < 1e-9


def test_baumgarte_pulls_a_drifted_ring_back_onto_the_constraint() -> None:
    fast = fast_constrained_equations(constrained_equations(bead_on_ring()))
    start = np.array([1.01, 0.0, 0.0, 0.5])  # 1 % off the circle
    settings = Settings("DOP853", (0.0, 4.0), np.array([4.0]), 1e-10, 1e-10)
    radius = {}
    for alpha_beta in (0.0, 5.0):
        run = c_loop.integrate(fast, settings, start, np.array([1.0, 9.81, alpha_beta, alpha_beta]))
        radius[alpha_beta] = float(np.hypot(*run.x[-1, :2]))
    assert abs(radius[5.0] - 1.0) < 1e-5
    assert abs(radius[0.0] - 1.0) > 1e-3  # without it the index-1 form keeps the offset
