"""Compiled equations: the numbers equal the symbolic expressions evaluated by SymPy (no
lambdify), the seed notes' equations written by hand, and each other on batches.
"""

from __future__ import annotations

import gc
import weakref

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.derivation import forget_derivations
from lagrangian.numerics.compile import compile_equations
from lagrangian.symbolic.caches import IdentityCache

RNG = np.random.default_rng(6)


def _random_values(
    eom: lg.EquationsOfMotion,
) -> tuple[dict, np.ndarray, np.ndarray, float, np.ndarray]:
    """A random state and random positive parameters, as a subs dict and as arrays."""
    n = len(eom.coordinates)
    q, qd = RNG.uniform(-1.5, 1.5, n), RNG.uniform(-1.5, 1.5, n)
    t = float(RNG.uniform(0, 2))
    p = RNG.uniform(0.5, 2.0, len(eom.parameters))
    subs = dict(zip(eom.coordinates, q)) | dict(zip(eom.velocities, qd))
    subs |= dict(zip(eom.parameters, p)) | {eom.time: t}
    return subs, q, qd, t, p


def _evalf(matrix: sp.Matrix, subs: dict) -> np.ndarray:
    return np.array(matrix.subs(subs).evalf(), dtype=float)


@pytest.mark.parametrize("example", ["double_pendulum", "robot_arm", "moving_pivot_pendulum"])
def test_mass_matrix_and_forcing_equal_the_symbolic_ones(example: str) -> None:
    eom = lg.derive(lg.examples.get(example)())
    compiled = compile_equations(eom)
    for _ in range(3):
        subs, q, qd, t, p = _random_values(eom)
        np.testing.assert_allclose(
            compiled.mass_matrix(q, t, p), _evalf(eom.mass_matrix, subs), rtol=1e-12, atol=1e-12
        )
        np.testing.assert_allclose(
            compiled.forcing(q, qd, t, p),
            _evalf(eom.forcing, subs).ravel(),
            rtol=1e-12,
            atol=1e-12,
        )


def test_double_pendulum_accelerations_satisfy_the_seed_equations() -> None:
    # Seed 000, written by hand (a1, a2 the angular accelerations, s = sin(th - ph)):
    #   (m1 + m2) l1 a1 + m2 l2 a2 cos(th - ph) + m2 l2 ph_d^2 s + (m1 + m2) g sin(th) = 0
    #   m2 l2 a2 + m2 l1 a1 cos(th - ph) - m2 l1 th_d^2 s + m2 g sin(ph) = 0
    eom = lg.derive(lg.examples.double_pendulum())
    compiled = compile_equations(eom)
    assert compiled.parameters == ("m1", "m2", "l1", "l2", "g")
    m1, m2, l1, l2, g = p = np.array([1.3, 0.7, 1.1, 0.9, 9.81])
    th, ph, th_d, ph_d = x = np.array([0.4, -1.2, 0.8, -0.3])
    _, _, a1, a2 = compiled.rhs(0.0, x, p)
    s, c = np.sin(th - ph), np.cos(th - ph)
    first = (
        (m1 + m2) * l1 * a1 + m2 * l2 * a2 * c + m2 * l2 * ph_d**2 * s + (m1 + m2) * g * np.sin(th)
    )
    second = m2 * l2 * a2 + m2 * l1 * a1 * c - m2 * l1 * th_d**2 * s + m2 * g * np.sin(ph)
    assert abs(first) < 1e-12 and abs(second) < 1e-12


def test_energy_is_the_hand_written_t_plus_v() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    compiled = compile_equations(eom)
    m1, m2, l1, l2, g = p = np.array([1.3, 0.7, 1.1, 0.9, 9.81])
    th, ph, th_d, ph_d = 0.4, -1.2, 0.8, -0.3
    kinetic = (m1 + m2) * l1**2 * th_d**2 / 2 + m2 * l2**2 * ph_d**2 / 2
    kinetic += m2 * l1 * l2 * th_d * ph_d * np.cos(th - ph)
    potential = -(m1 + m2) * g * l1 * np.cos(th) - m2 * g * l2 * np.cos(ph)
    energy = compiled.energy([th, ph], [th_d, ph_d], 0.0, p)
    assert energy == pytest.approx(kinetic + potential, rel=1e-13)
    assert not compiled.energy_function_differs  # T is quadratic in the velocities


def test_energy_function_of_the_moving_pivot_differs_from_t_plus_v() -> None:
    # h = sum q_dot dL/dq_dot - L = T2 - T0 + V, T = T2 + T1 + T0 with the pivot at x0 cos(w t):
    # T2 = m l^2 th_d^2 / 2, T0 = m x0^2 w^2 sin(w t)^2 / 2, V = -m g l cos(th).
    compiled = compile_equations(lg.derive(lg.examples.moving_pivot_pendulum()))
    assert compiled.parameters == ("m", "g", "l", "x0", "omega")
    m, g, l, x0, w = p = np.array([1.5, 9.81, 0.8, 0.1, 2.0])
    th, th_d, t = 0.3, 0.7, 0.9
    h = m * l**2 * th_d**2 / 2 - m * x0**2 * w**2 * np.sin(w * t) ** 2 / 2 - m * g * l * np.cos(th)
    assert compiled.energy_function_differs
    assert compiled.energy_function([th], [th_d], t, p) == pytest.approx(h, rel=1e-13)


def test_batches_equal_single_states() -> None:
    eom = lg.derive(lg.examples.double_pendulum())
    compiled = compile_equations(eom)
    p = np.array(compiled.defaults)
    states = RNG.uniform(-2, 2, (7, 4))
    times = RNG.uniform(0, 1, 7)
    batch = compiled.rhs(times, states, p)
    assert batch.shape == (7, 4)
    for row, t, x in zip(batch, times, states):
        np.testing.assert_allclose(row, compiled.rhs(t, x, p), rtol=1e-14)
    q, qd = states[:, :2], states[:, 2:]
    assert compiled.mass_matrix(q, 0.0, p).shape == (7, 2, 2)
    energies = compiled.energy(q, qd, 0.0, p)
    assert energies.shape == (7,)
    assert energies[3] == pytest.approx(float(compiled.energy(q[3], qd[3], 0.0, p)))
    # a batch of parameter sets with one state
    p_batch = np.tile(p, (3, 1)) * np.array([[1.0], [2.0], [0.5]])
    assert compiled.rhs(0.0, np.tile(states[0], (3, 1)), p_batch).shape == (3, 4)


def test_parameters_are_arguments_not_recompiled() -> None:
    # theta_ddot = -(g/l) sin(theta): doubling l halves the acceleration, same compiled object.
    eom = lg.derive(lg.examples.simple_pendulum())
    compiled = compile_equations(eom)
    x = np.array([0.5, 0.0])
    short = compiled.rhs(0.0, x, np.array([1.0, 9.81, 1.0]))[1]
    long = compiled.rhs(0.0, x, np.array([1.0, 9.81, 2.0]))[1]
    assert short == pytest.approx(-9.81 * np.sin(0.5))
    assert long == pytest.approx(short / 2)
    assert compile_equations(eom) is compiled


def test_compilation_is_cached_per_equations_object_and_released_with_it() -> None:
    # Two equal Systems that are distinct objects: derive caches per System object.
    eom = lg.derive(lg.examples.simple_pendulum().replace())
    other = lg.derive(lg.examples.simple_pendulum().replace())
    compiled = compile_equations(eom)
    assert compile_equations(eom) is compiled
    assert compile_equations(other) is not compiled
    alive = weakref.ref(eom)
    del eom
    forget_derivations()  # derive's own cache of recent Systems holds them strongly
    gc.collect()
    assert alive() is None  # the cache does not keep the equations alive


def test_identity_cache_forgets_collected_keys() -> None:
    class Key:
        pass

    cache: IdentityCache[Key, int] = IdentityCache()
    keys = [Key() for _ in range(3)]
    for i, key in enumerate(keys):
        assert cache.get(key, lambda _k, i=i: i) == i
    assert cache.get(keys[1], lambda _k: -1) == 1  # cached, not recomputed
    del keys[0]
    gc.collect()
    assert len(cache) == 2


def test_rc_rl_circuit_state_and_rates_follow_the_notes() -> None:
    # Seed 001 "Another Example": q1_dot = (u_a - (q1 - q2)/C)/R,
    # q2_ddot = (-R_L q2_dot + (q1 - q2)/C)/L; the state is (q1, q2, q2_dot).
    compiled = compile_equations(lg.derive(lg.examples.rc_rl_circuit()))
    assert compiled.orders == (1, 2)
    assert compiled.state_names == ("q1", "q2", "q2_dot")
    assert compiled.parameters == ("L", "C", "R", "R_L", "u_a")
    L, C, R, R_L, u_a = p = np.array([0.2, 2e-3, 5.0, 0.5, 3.0])
    q1, q2, i_L = x = np.array([1e-3, 4e-4, 0.05])
    q1_dot = (u_a - (q1 - q2) / C) / R
    q2_ddot = (-R_L * i_L + (q1 - q2) / C) / L
    np.testing.assert_allclose(compiled.rhs(0.0, x, p), [q1_dot, i_L, q2_ddot], rtol=1e-13)
    np.testing.assert_allclose(compiled.velocities(0.0, x, p), [q1_dot, i_L], rtol=1e-13)
    batch = compiled.rhs(0.0, np.array([x, 2 * x]), p)
    np.testing.assert_allclose(batch[1], compiled.rhs(0.0, 2 * x, p), rtol=1e-13)
    np.testing.assert_allclose(compiled.state([q1, q2], [9.0, i_L]), x)


def test_singular_mass_matrix_at_a_configuration_names_time_and_state() -> None:
    # The polar robot arm has M = diag(m r^2, m): singular at r = 0.
    compiled = compile_equations(lg.derive(lg.examples.robot_arm()))
    p = np.array(compiled.defaults)
    with pytest.raises(lg.SimulationError, match=r"singular at t = 0\.5, theta=0\.1, r=0,"):
        compiled.rhs(0.5, np.array([0.1, 0.0, 0.0, 0.0]), p)


x, y, x_dot, y_dot = sp.symbols("x y x_dot y_dot")
m, k, big_r = sp.symbols("m k R")


def test_algebraic_coordinates_are_refused() -> None:
    # y has neither inertia nor dissipation: its equation k (2 y - x) = 0 is a constraint.
    system = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, k: 1.0},
        kinetic=m * x_dot**2 / 2,
        potential=k * (x - y) ** 2 / 2 + k * y**2 / 2,
    )
    with pytest.raises(lg.SimulationError, match="The coordinate y is algebraic"):
        compile_equations(lg.derive(system))


def test_nonlinear_first_order_equations_are_refused() -> None:
    system = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, k: 1.0, big_r: 1.0},
        kinetic=m * x_dot**2 / 2,
        potential=k * (x - y) ** 2 / 2,
        dissipation=big_r * y_dot**4 / 4,
    )
    with pytest.raises(lg.SimulationError, match=r"first-order coordinates \(y\) are not linear"):
        compile_equations(lg.derive(system))


def test_systems_the_state_equations_cannot_take_are_bad_input() -> None:
    algebraic = lg.System(
        coordinates=[x, y],
        parameters={m: 1.0, k: 1.0},
        kinetic=m * x_dot**2 / 2,
        potential=k * (x - y) ** 2 / 2 + k * y**2 / 2,
    )
    with pytest.raises(lg.SimulationInputError, match="algebraic") as caught:
        compile_equations(lg.derive(algebraic))
    assert isinstance(caught.value, ValueError) and caught.value.exit_code == 2


# --- the native (SymEngine LLVM) evaluation against sympy.lambdify ---------------------------


def test_native_evaluation_agrees_with_lambdify_even_with_names_like_cse_temporaries() -> None:
    """SymEngine's CSE calls its temporaries x0, x1, ...: the coordinates x1, y1, x2, y2 of a
    Cartesian double pendulum were once mistaken for them (a wrong energy); checked against
    the energy written by hand."""
    x1, y1, x2, y2, m1, m2, g = sp.symbols("x1 y1 x2 y2 m1 m2 g")
    system = lg.System(
        coordinates=[x1, y1, x2, y2],
        parameters={m1: 1.5, m2: 2.5, g: 9.81},
        gravity=(0, -g),
        particles=[lg.Particle("a", m1, (x1, y1)), lg.Particle("b", m2, (x2, y2))],
    )
    compiled = compile_equations(lg.derive(system))
    rng = np.random.default_rng(3)
    q, q_dot, t = rng.random((7, 4)), rng.random((7, 4)), rng.random(7)
    p = np.array([1.5, 2.5, 9.81])
    by_hand = (
        1.5 * (q_dot[:, 0] ** 2 + q_dot[:, 1] ** 2) / 2
        + 2.5 * (q_dot[:, 2] ** 2 + q_dot[:, 3] ** 2) / 2
        + 9.81 * (1.5 * q[:, 1] + 2.5 * q[:, 3])
    )
    np.testing.assert_allclose(compiled.energy(q, q_dot, t, p), by_hand, rtol=1e-14)
    np.testing.assert_allclose(compiled.energy(q[2], q_dot[2], t[2], p), by_hand[2], rtol=1e-14)
    assert compiled._energy._native is not None


def test_functions_symengine_cannot_compile_fall_back_to_lambdify() -> None:
    from lagrangian.numerics.evaluate import NumericFunction

    x = sp.Symbol("x")
    # Mod is a function SymEngine's compiler does not take (Heaviside now compiles, written
    # with sign: tests/numerics/test_evaluate_tiers.py).
    function = NumericFunction(([x],), [sp.Mod(x, 1) * x, x + 1], (2,))
    assert function._native is None
    np.testing.assert_allclose(function([2.5]), [1.25, 3.5])
    np.testing.assert_allclose(function([[-0.5], [0.0]]), [[-0.25, 0.5], [0.0, 1.0]])
