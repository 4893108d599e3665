"""The compiled flights (numerics/fast/c_flight.c) against the NumPy path they replace: the
same impacts on the same contacts at the same times, the contacts they hand back (several at
once, a bounce coming to rest, the step budget) resolved as the NumPy path resolves them, and
the first crossings of gap polynomials against their roots found by NumPy's eigenvalues."""

from __future__ import annotations

import functools

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.examples.gas import hard_disk_gas
from lagrangian.numerics.fast import c_build, c_flight

needs_compiler = pytest.mark.skipif(not c_flight.available(), reason="no C compiler")


def both(run: functools.partial[lg.Trajectory], monkeypatch: pytest.MonkeyPatch) -> tuple:
    """The run compiled (checked to go through the compiled flights), then by NumPy alone."""
    calls: list[int] = []
    fly = c_flight.fly

    def counted(*args: object, **kwargs: object) -> c_flight.Flown:
        found = fly(*args, **kwargs)  # type: ignore[arg-type]
        calls.append(len(found.impact_t))
        return found

    with monkeypatch.context() as patch:
        patch.setattr(c_flight, "fly", counted)
        compiled = run()
    with monkeypatch.context() as patch:
        patch.setattr(c_flight, "available", lambda: False)
        plain = run()
    return compiled, plain, calls


def reference_crossing(c: np.ndarray) -> float:
    """The first s > 0 where the polynomial (ascending c) turns negative, from its roots."""
    if c[0] <= 0 and c[1] < 0:
        return 0.0
    roots = np.roots(np.trim_zeros(c[::-1], "f"))
    real = np.sort(roots[np.abs(roots.imag) < 1e-9].real)
    slope = np.polynomial.polynomial.polyder(c)
    for s in real[real > 0]:
        if np.polynomial.polynomial.polyval(s, slope) < 0:
            return float(s)
    return np.inf


@needs_compiler
def test_first_crossings_of_quadratics_cubics_and_quartics_are_their_roots() -> None:
    rng = np.random.default_rng(7)
    for degree in (2, 3, 4):
        c = rng.normal(size=(400, 5))
        c[:, degree + 1 :] = 0.0
        found = c_flight.crossings(c)
        for row, s in zip(c, found):
            expected = reference_crossing(row)
            if np.isinf(expected):
                assert np.isinf(s), row
                continue
            assert s == pytest.approx(expected, rel=1e-9, abs=1e-12), row
            if s > 0:  # g turns negative there: positive just before, negative just after
                p = np.polynomial.polynomial.polyval
                assert p(s * (1 - 1e-6), row) > 0 > p(s * (1 + 1e-6), row)


@needs_compiler
def test_a_double_root_touching_zero_is_no_crossing() -> None:
    # (s - 1)^2 (s + 2): touches 0 at s = 1 without turning negative for s > 0
    touching = np.polynomial.polynomial.polyfromroots([1.0, 1.0, -2.0])
    assert np.isinf(c_flight.crossings(np.append(touching, 0.0))[0])


@functools.cache
def gas() -> tuple[lg.System, lg.EquationsOfMotion]:
    system = hard_disk_gas(12, radius=0.05)
    return system, lg.derive(system)


@pytest.mark.parametrize("gravity", [0.0, 3.0])
def test_the_gas_meets_the_same_impacts_compiled_and_in_numpy(
    gravity: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    system, eom = gas()
    field = {"g_x": 0.0, "g_y": -gravity}
    run = functools.partial(lg.simulate, eom, dict(system.initial), 1.5, samples=7,
                            parameters=field)  # fmt: skip
    compiled, plain, calls = both(run, monkeypatch)
    assert compiled.success and plain.success
    assert sum(calls) >= 40  # the impacts went through the compiled step
    # chaos amplifies rounding from one collision to the next: compare the first forty
    for ours, theirs in zip(compiled.impacts[:40], plain.impacts[:40], strict=True):
        assert ours.constraints == theirs.constraints
        assert ours.t == pytest.approx(theirs.t, abs=1e-12)
        (name,) = ours.constraints
        assert ours.impulses[name] == pytest.approx(theirs.impulses[name], rel=1e-10)
        for velocity, value in theirs.after.items():
            assert ours.after[velocity] == pytest.approx(value, abs=1e-10)
        energy = sum(v * v for v in ours.before.values()) / 2
        assert abs(ours.energy_lost) <= 1e-13 * energy  # e = 1: nothing lost
    assert [e.name for e in compiled.events[:40]] == [e.name for e in plain.events[:40]]
    assert compiled.t.tolist() == plain.t.tolist()


@needs_compiler
def test_rows_and_end_state_are_the_numpy_path_s_over_a_few_collisions(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    system, eom = gas()
    run = functools.partial(lg.simulate, eom, dict(system.initial), 0.3, samples=31)
    compiled, plain, _ = both(run, monkeypatch)
    assert len(compiled.impacts) == len(plain.impacts) >= 3
    assert np.allclose(compiled.q, plain.q, atol=1e-11)
    assert np.allclose(compiled.q_dot, plain.q_dot, atol=1e-10)


def bouncing_ball(e: float) -> lg.System:
    return lg.loads(
        f"""
        coordinates: [y]
        parameters: {{m: 1.0, g: 9.81, e: {e}}}
        kinetic: m*y_dot**2/2
        potential: m*g*y
        constraints:
          - {{name: floor, unilateral: y, restitution: e}}
        initial: {{y: 1.0, y_dot: 0.0}}
        """
    )


@needs_compiler
def test_a_bounce_coming_to_rest_is_handed_back_and_rests_as_in_numpy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ball = bouncing_ball(0.5)
    run = functools.partial(lg.simulate, ball, t_span=3.0, samples=31)
    compiled, plain, calls = both(run, monkeypatch)
    assert sum(calls) >= 5
    assert [i.constraints for i in compiled.impacts] == [i.constraints for i in plain.impacts]
    assert compiled.impacts[-1].rest == plain.impacts[-1].rest == ("floor",)
    assert compiled.impacts[-1].t == pytest.approx(plain.impacts[-1].t, abs=1e-12)
    # the geometric series: t_k = t1 (1 + 2 e + ... + 2 e^(k-1)), t1 = sqrt(2 / g)
    t1 = np.sqrt(2 / 9.81)
    for k, impact in enumerate(compiled.impacts[:6]):
        expected = t1 * (1 + 2 * sum(0.5**j for j in range(1, k + 1)))
        assert impact.t == pytest.approx(expected, abs=1e-12)


@needs_compiler
def test_contacts_meeting_at_once_are_resolved_together_as_in_numpy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # three balls on a line, the outer two running into the middle one from equal gaps:
    # both contacts close at the same instant, a complementarity problem for Python
    x = sp.symbols("x1:4")
    system = lg.System(
        coordinates=list(x),
        parameters={},
        kinetic=sum(sp.Symbol(f"{s}_dot") ** 2 / 2 for s in x),
        constraints=[
            lg.Unilateral(x[1] - x[0], name="left", restitution=1),
            lg.Unilateral(x[2] - x[1], name="right", restitution=1),
            lg.Unilateral(x[0] + 3, name="wall_left", restitution=1),
            lg.Unilateral(3 - x[2], name="wall_right", restitution=1),
        ],
        initial={"x1": -1.0, "x2": 0.0, "x3": 1.0, "x1_dot": 1.0, "x2_dot": 0.0, "x3_dot": -1.0},
    )
    run = functools.partial(lg.simulate, system, t_span=6.0, samples=13)
    compiled, plain, calls = both(run, monkeypatch)
    assert calls  # the compiled step ran, and handed the double contact back
    assert compiled.impacts[0].constraints == ("left", "right")
    assert [i.constraints for i in compiled.impacts] == [i.constraints for i in plain.impacts]
    assert [i.t for i in compiled.impacts] == pytest.approx([i.t for i in plain.impacts])
    # momentum zero and energy 1 throughout (equal masses, e = 1)
    assert np.allclose(compiled.q_dot.sum(axis=1), 0.0, atol=1e-12)
    assert np.allclose((compiled.q_dot**2).sum(axis=1) / 2, 1.0, atol=1e-12)


@needs_compiler
def test_the_step_budget_ends_the_gas_at_the_same_impact(monkeypatch: pytest.MonkeyPatch) -> None:
    system, eom = gas()
    run = functools.partial(lg.simulate, eom, dict(system.initial), 5.0, samples=11,
                            max_steps=25, raise_on_failure=False)  # fmt: skip
    compiled, plain, _ = both(run, monkeypatch)
    assert not compiled.success and not plain.success
    assert compiled.message == plain.message and "max_steps" in compiled.message
    assert len(compiled.impacts) == len(plain.impacts) == 24
    assert compiled.impacts[-1].t == pytest.approx(plain.impacts[-1].t, abs=1e-12)


def test_without_a_c_compiler_the_gas_flies_in_numpy(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(c_build, "find_compiler", lambda: None)
    c_flight.flight_library.cache_clear()
    try:
        assert not c_flight.available()
        with pytest.raises(RuntimeError, match="no C compiler"):
            c_flight.crossings(np.zeros((1, 5)))
        system, eom = gas()
        run = lg.simulate(eom, dict(system.initial), 0.5, samples=3)
        assert run.success and len(run.impacts) >= 5
        energy = sum(v * v for v in run.impacts[0].before.values()) / 2
        assert all(abs(i.energy_lost) <= 1e-13 * energy for i in run.impacts)
    finally:
        monkeypatch.undo()
        c_flight.flight_library.cache_clear()


@needs_compiler
def test_a_ball_in_a_bowl_under_gravity_meets_quartic_contacts_as_in_numpy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # along a parabola the gap R^2 - x^2 - y^2 is a quartic in t: the compiled step's
    # bisection against NumPy's eigenvalue roots, impact after impact
    x, y = sp.symbols("x y")
    bowl = lg.System(
        coordinates=[x, y],
        parameters={"g": 9.81},
        kinetic=(sp.Symbol("x_dot") ** 2 + sp.Symbol("y_dot") ** 2) / 2,
        potential=sp.Symbol("g") * y,
        constraints=[lg.Unilateral(1 - x**2 - y**2, name="bowl", restitution=1)],
        initial={"x": -0.3, "y": 0.1, "x_dot": 2.0, "y_dot": 1.0},
    )
    run = functools.partial(lg.simulate, bowl, t_span=3.0, samples=31)
    compiled, plain, calls = both(run, monkeypatch)
    assert sum(calls) >= 5
    assert len(compiled.impacts) == len(plain.impacts)
    for ours, theirs in zip(compiled.impacts, plain.impacts, strict=True):
        assert ours.t == pytest.approx(theirs.t, abs=1e-9)
    energy = compiled["energy"]
    assert np.allclose(energy, energy[0], rtol=1e-9)
    assert np.all(compiled["x"] ** 2 + compiled["y"] ** 2 <= 1 + 1e-9)


@needs_compiler
def test_a_mass_matrix_coupling_the_coordinates_jumps_as_in_numpy(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # two carts whose kinetic energy couples them (M not diagonal): an impulse on one
    # contact moves both velocities, M^-1 a^T dense; walls at both ends, e = 0.9 between
    x1, x2 = sp.symbols("x1 x2")
    v1, v2 = sp.symbols("x1_dot x2_dot")
    system = lg.System(
        coordinates=[x1, x2],
        parameters={},
        kinetic=(2 * v1**2 + v2**2 + v1 * v2) / 2,
        constraints=[
            lg.Unilateral(x2 - x1, name="between", restitution=sp.Rational(9, 10)),
            lg.Unilateral(x1 + 1, name="left", restitution=1),
            lg.Unilateral(1 - x2, name="right", restitution=1),
        ],
        initial={"x1": -0.5, "x2": 0.5, "x1_dot": 1.0, "x2_dot": -0.3},
    )
    run = functools.partial(lg.simulate, system, t_span=4.0, samples=41)
    compiled, plain, calls = both(run, monkeypatch)
    assert sum(calls) >= 5
    assert [i.constraints for i in compiled.impacts] == [i.constraints for i in plain.impacts]
    for ours, theirs in zip(compiled.impacts, plain.impacts, strict=True):
        assert ours.t == pytest.approx(theirs.t, abs=1e-12)
        for velocity, value in theirs.after.items():
            assert ours.after[velocity] == pytest.approx(value, abs=1e-12)
        # Newton's law on the contact: its rate after is -e times its rate before
        (name,) = ours.constraints
        sign = {"between": (-1, 1), "left": (1, 0), "right": (0, -1)}[name]
        e = {"between": 0.9, "left": 1.0, "right": 1.0}[name]
        rate = [sum(s * side[f"x{k + 1}_dot"] for k, s in enumerate(sign))
                for side in (ours.before, ours.after)]  # fmt: skip
        assert rate[1] == pytest.approx(-e * rate[0], abs=1e-12)
