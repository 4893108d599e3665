"""The gas's collisions against the benchmark's own event-driven simulation (a priority queue
of collision times in NumPy, written without the library): the first fifty collisions the
same, at the same times to 1e-10, with no field and in a uniform field (balls bouncing in
a box, every flight a parabola); energy and momentum kept at every impact."""

from __future__ import annotations

import functools
import runpy
from pathlib import Path
from types import SimpleNamespace

import pytest

import lagrangian as lg
from lagrangian.examples.gas import hard_disk_gas

DISKS, RADIUS = 9, 0.06


@functools.cache
def benchmark() -> SimpleNamespace:
    """benchmarks/impacts.py (not part of the package), its names."""
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "impacts.py"
    return SimpleNamespace(**runpy.run_path(str(path)))


@functools.cache
def gas() -> tuple[lg.System, lg.EquationsOfMotion]:
    system = hard_disk_gas(DISKS, radius=RADIUS)
    return system, lg.derive(system)


def disks_hit(name: str) -> tuple[int, ...]:
    """The disks (0-based) of a contact's name: a pair "disks3_7", a wall "left3"."""
    if name.startswith("disks"):
        return tuple(int(k) - 1 for k in name.removeprefix("disks").split("_"))
    return (int(name.lstrip("leftrighbomp")) - 1,)


def runs(gravity: float, t_end: float) -> tuple[lg.Trajectory, list[tuple[float, int, int]]]:
    system, eom = gas()
    field = {"g_x": 0.0, "g_y": -gravity}
    run = lg.simulate(eom, dict(system.initial), t_end, samples=11, parameters=field)
    assert run.success, run.message
    x, v = benchmark().start_of(system)
    reference = benchmark().EventDrivenGas(x, v, RADIUS, 1.0, (0.0, -gravity))
    reference.run(t_end)
    return run, reference.collisions


@pytest.mark.parametrize("gravity", [0.0, 3.0])
def test_the_first_fifty_collisions_are_the_reference_s(gravity: float) -> None:
    run, expected = runs(gravity, 2.5)
    assert len(run.impacts) >= 50 and len(expected) >= 50
    pairs = 0
    for impact, (t, i, j) in zip(run.impacts[:50], expected[:50]):
        (name,) = impact.constraints
        assert disks_hit(name) == (tuple(sorted((i, j))) if j >= 0 else (i,)), (t, name)
        assert impact.t == pytest.approx(t, abs=1e-10)
        pairs += j >= 0
    assert 10 <= pairs <= 40  # disk contacts and walls both


@pytest.mark.parametrize("gravity", [0.0, 3.0])
def test_energy_and_momentum_are_kept_at_every_impact(gravity: float) -> None:
    run, _ = runs(gravity, 2.5)
    energy = run.drift()
    assert energy["energy_relative"] < 1e-12, energy
    for impact in run.impacts:
        assert abs(impact.energy_lost) < 1e-13
        disks = disks_hit(impact.constraints[0])
        before, after = impact.before, impact.after
        for axis in "xy":
            total = [sum(side[f"{axis}{k + 1}_dot"] for k in disks) for side in (before, after)]
            if len(disks) == 2:  # a pair: each axis's momentum kept
                assert total[1] == pytest.approx(total[0], abs=1e-14)
        others = [f"{a}{k + 1}_dot" for k in range(DISKS) if k not in disks for a in "xy"]
        assert all(after[name] == before[name] for name in others)  # only the two jump
