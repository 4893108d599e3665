"""The linearization gives A with the parameter values in it, beside the symbolic A, and the
frequencies reported are those of that numeric matrix."""

import numpy as np
import sympy as sp

import lagrangian as lg
from lagrangian.analysis.linearize import linearize


def test_a_is_also_given_at_the_parameter_values():
    pendulum = lg.examples.spherical_pendulum()
    lin = linearize(pendulum, {"theta": 0.5, "phi_dot": 2.0})
    assert lin.A.free_symbols  # g and l kept in A
    assert lin.A_at_values is not None and not lin.A_at_values.free_symbols
    values = {sp.Symbol(name): value for name, value in {"g": 9.81, "l": 1.0}.items()}
    expected = np.array(lin.A.xreplace(values).evalf(), dtype=float)
    numeric = np.array(lin.A_at_values, dtype=float)
    assert np.allclose(numeric, expected, rtol=1e-12)
    # the frequencies reported are those of the numeric matrix (numpy's own eigenvalues)
    omegas = sorted({round(abs(w.imag), 9) for w in np.linalg.eigvals(numeric) if w.imag > 1e-9})
    assert np.allclose(sorted(float(f) for f in lin.frequencies), omegas)


def test_without_parameters_there_is_nothing_to_substitute():
    x = sp.Symbol("x")
    oscillator = lg.System(coordinates=[x], kinetic=lg.velocity(x) ** 2 / 2, potential=2 * x**2)
    assert linearize(oscillator, {"x": 0}).A_at_values is None
