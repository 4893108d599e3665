"""The gas of hard disks in a box: its collisions against an event-driven reference written
here (brute force, every pair's collision time from the quadratic of its distance), energy
and momentum exact at e = 1, and the pressure on the walls against the kinetic theory of a
gas of hard disks."""

from __future__ import annotations

import csv
import functools
import json

import numpy as np
import pytest
import sympy as sp

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.examples.gas import hard_disk_gas


@functools.cache
def gas_eom(n: int, radius: float) -> lg.EquationsOfMotion:
    return lg.derive(hard_disk_gas(n, radius=radius))


def run_gas(n: int, radius: float, t_end: float, samples: int) -> lg.Trajectory:
    initial = dict(hard_disk_gas(n, radius=radius).initial)
    return lg.simulate(gas_eom(n, radius), initial, t_end, samples=samples)


def start(n: int, radius: float) -> tuple[np.ndarray, np.ndarray]:
    initial = {str(k): v for k, v in hard_disk_gas(n, radius=radius).initial.items()}
    x = np.array([[initial[f"x{i + 1}"], initial[f"y{i + 1}"]] for i in range(n)])
    v = np.array([[initial[f"x{i + 1}_dot"], initial[f"y{i + 1}_dot"]] for i in range(n)])
    return x, v


def brute_force(
    x: np.ndarray, v: np.ndarray, radius: float, t_end: float
) -> list[tuple[float, tuple[int, ...]]]:
    """Every collision up to t_end: (time, the disks (one for a wall))."""
    x, v, t, found = x.copy(), v.copy(), 0.0, []
    n = len(x)
    while True:
        best, what = np.inf, None
        for i in range(n):
            for axis in range(2):
                if v[i, axis] > 0:
                    s = (1 - radius - x[i, axis]) / v[i, axis]
                elif v[i, axis] < 0:
                    s = (radius - x[i, axis]) / v[i, axis]
                else:
                    continue
                if s < best:
                    best, what = s, ("wall", i, axis)
            for j in range(i + 1, n):
                dx, dv = x[j] - x[i], v[j] - v[i]
                b, a, c = dx @ dv, dv @ dv, dx @ dx - 4 * radius**2
                disc = b * b - a * c
                if b < 0 and disc > 0:
                    s = c / (-b + np.sqrt(disc))  # the smaller root, written stably
                    if s < best:
                        best, what = s, ("pair", i, j)
        if t + best > t_end or what is None:
            return found
        x += v * best
        t += best
        if what[0] == "wall":
            v[what[1], what[2]] *= -1
            found.append((t, (what[1],)))
        else:
            i, j = what[1], what[2]
            normal = (x[j] - x[i]) / np.linalg.norm(x[j] - x[i])
            exchange = ((v[j] - v[i]) @ normal) * normal
            v[i] += exchange
            v[j] -= exchange
            found.append((t, (i, j)))


def disks_of(impact: lg.Impact) -> tuple[int, ...]:
    (name,) = impact.constraints
    return disks_of_name(name)


def disks_of_name(name: str) -> tuple[int, ...]:
    if name.startswith("disks"):
        i, j = name.removeprefix("disks").split("_")
        return (int(i) - 1, int(j) - 1)
    return (int(name.lstrip("leftrighbomp")) - 1,)


def test_the_collisions_are_those_of_an_event_driven_reference() -> None:
    n, radius, t_end = 6, 0.08, 3.0
    run = run_gas(n, radius, t_end, 31)
    assert run.success, run.message
    expected = brute_force(*start(n, radius), radius, t_end)
    assert len(run.impacts) == len(expected) > 20
    assert any(len(disks) == 2 for _, disks in expected)  # disk contacts, not walls alone
    for impact, (t, disks) in zip(run.impacts, expected):
        assert disks_of(impact) == disks
        assert impact.t == pytest.approx(t, abs=1e-9)
    # roots, not a stepped search (which meets a contact 1e-8 inside it): the first times
    # agree to rounding (later ones less: every collision amplifies a difference)
    for impact, (t, _) in zip(run.impacts[:10], expected[:10]):
        assert impact.t == pytest.approx(t, abs=1e-13)


def test_energy_and_momentum_are_exact_at_every_elastic_impact() -> None:
    n, radius = 6, 0.08
    run = run_gas(n, radius, 3.0, 31)
    assert run.drift()["energy_relative"] < 1e-13
    assert "energy_not_conserved" not in run.drift()
    for impact in run.impacts:
        assert abs(impact.energy_lost) < 1e-13
        before, after = impact.before, impact.after
        disks = disks_of(impact)
        if len(disks) == 2:  # a pair: the total momentum is kept, each axis
            for axis in "xy":
                total = [sum(side[f"{axis}{k + 1}_dot"] for k in disks) for side in (before, after)]
                assert total[1] == pytest.approx(total[0], abs=1e-14)
        else:  # a wall: the normal velocity reverses, the tangential one is kept
            (k,) = disks
            name = impact.constraints[0]
            normal, tangent = ("x", "y") if name.startswith(("left", "right")) else ("y", "x")
            assert after[f"{normal}{k + 1}_dot"] == pytest.approx(-before[f"{normal}{k + 1}_dot"])
            assert after[f"{tangent}{k + 1}_dot"] == before[f"{tangent}{k + 1}_dot"]
        untouched = [k for k in range(n) if k not in disks]
        assert all(after[f"x{k + 1}_dot"] == before[f"x{k + 1}_dot"] for k in untouched)


def test_the_wall_pressure_is_that_of_kinetic_theory_with_the_excluded_area() -> None:
    """P A = N k T Z(eta) with k T the mean kinetic energy per disk (two degrees of freedom,
    k T / 2 each) and A = l^2 the area the centres reach (l = L - 2 r); Z of hard disks by
    Henderson's equation of state, Z = (1 + eta^2/8) / (1 - eta)^2, eta = N pi r^2 / A.  The
    force on the walls is their impulses per time: sum Lambda / T = 4 l P (|grad g| = 1 for
    a wall, so Lambda is the momentum it takes)."""
    n, radius, t_end = 16, 0.035, 120.0
    run = run_gas(n, radius, t_end, 3)
    assert run.success, run.message
    walls = ("left", "right", "bottom", "top")
    impulse = sum(
        value for i in run.impacts for name, value in i.impulses.items() if name.startswith(walls)
    )
    hits = sum(1 for i in run.impacts if i.constraints[0].startswith(walls))
    side = 1.0 - 2 * radius
    kinetic = float(run["energy"][0])  # no potential: E = T = N k T
    eta = n * np.pi * radius**2 / side**2
    z = (1 + eta**2 / 8) / (1 - eta) ** 2
    measured = impulse / t_end / (4 * side)
    ideal = kinetic / side**2
    assert hits > 2000
    # the time average over ~2600 wall hits scatters by about 1/sqrt(hits) ~ 2 %
    assert measured == pytest.approx(ideal * z, rel=0.06)
    # the excluded area is seen: an ideal gas (Z = 1) would be 1 within that scatter
    assert measured / ideal - 1 > (z - 1) / 2


# The built-in example on the command line: four disks of radius 0.1, t_end = 2.
EXAMPLE = hard_disk_gas()
EXAMPLE_RADIUS = 0.1


def cli(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    code = main(list(argv))
    said = capsys.readouterr()
    assert code == 0, said.err
    return said.out


def test_derive_gives_free_flight_and_every_contact_with_its_multiplier(capsys) -> None:
    """By hand: T = m/2 sum (x_i_dot^2 + y_i_dot^2), V = -m (g_x x_i + g_y y_i), so each
    equation is m q_ddot - m g_q = 0; the walls' gradients are unit vectors, a pair's is
    2 (x_i - x_j, y_i - y_j) on disk i and the opposite on disk j."""
    document = json.loads(cli(capsys, "derive", "examples/hard_disk_gas", "--format", "json"))
    names = [*document["coordinates"], *document["velocities"], *document["accelerations"]]
    local = {name: sp.Symbol(name) for name in [*names, *document["parameters"]]}
    m, g_x, g_y = local["m"], local["g_x"], local["g_y"]
    expected = [m * local[f"{q}_ddot"] - m * (g_x if q[0] == "x" else g_y) for q in names[:8]]
    parsed = [sp.parse_expr(e, local_dict=local) for e in document["equations"]]
    assert [sp.expand(a - b) for a, b in zip(parsed, expected, strict=True)] == [0] * 8
    assert document["parameters"]["r"] == EXAMPLE_RADIUS
    rows = [
        [sp.parse_expr(e, local_dict=local) for e in row] for row in document["constraint_jacobian"]
    ]
    assert len(rows) == len(document["multipliers"]) == 4 * 4 + 6  # walls, then pairs
    column = {q: k for k, q in enumerate(names[:8])}
    assert rows[0][column["x1"]] == 1 and rows[1][column["x1"]] == -1  # left1, right1
    x1, x2, y1, y2 = (local[s] for s in ("x1", "x2", "y1", "y2"))
    pair = rows[16]  # disks1_2
    assert sp.expand(pair[column["x1"]] - 2 * (x1 - x2)) == 0
    assert sp.expand(pair[column["y2"]] + 2 * (y1 - y2)) == 0
    # the contacts cannot all close at once, so no joint solution is printed
    assert document["constraint_forces"]["solved"] is None
    assert "cannot all be in contact at once" in document["constraint_forces"]["reason"]


def test_analyze_counts_the_freedom_and_keeps_the_energy(capsys) -> None:
    document = json.loads(cli(capsys, "analyze", "examples/hard_disk_gas", "--format", "json"))
    # unilateral constraints remove no freedom: 2 per disk
    assert document["dof"] == document["configuration_dimension"] == 8
    kinds = {c["kind"] for c in document["constraints"]}
    assert kinds == {"unilateral"} and len(document["constraints"]) == 22
    assert document["energy_conserved"] is True
    local = {s: sp.Symbol(s) for s in ("m", "g_x", "g_y")}
    speeds = [f"{a}{k}" for a in "xy" for k in range(1, 5)]
    local.update({s: sp.Symbol(s) for s in speeds})
    local.update({f"{s}_dot": sp.Symbol(f"{s}_dot") for s in speeds})
    energy = sp.parse_expr(document["energy_function"], local_dict=local)
    m = local["m"]
    by_hand = sum(
        m * local[f"{s}_dot"] ** 2 / 2 - m * local["g_x" if s[0] == "x" else "g_y"] * local[s]
        for s in speeds
    )
    assert sp.expand(energy - by_hand) == 0


def test_simulate_meets_the_reference_collisions_with_the_energy_kept(capsys, tmp_path) -> None:
    out = tmp_path / "gas.csv"
    said = cli(capsys, "simulate", "examples/hard_disk_gas", "--out", str(out))
    x, v = start(4, EXAMPLE_RADIUS)
    expected = brute_force(x, v, EXAMPLE_RADIUS, float(EXAMPLE.simulation["t_end"]))
    with open(tmp_path / "gas.impacts.csv", encoding="utf-8") as stream:
        impacts = list(csv.DictReader(stream))
    assert f"{len(expected)} impacts" in said
    assert len(impacts) == len(expected) > 10
    assert any(len(disks) == 2 for _, disks in expected)
    for row, (t, disks) in zip(impacts, expected):
        assert float(row["t"]) == pytest.approx(t, abs=1e-12)
        (name,) = row["constraints"].split(";")
        assert disks_of_name(name) == disks
        assert abs(float(row["energy_lost"])) < 1e-14  # e = 1: nothing lost but rounding
    with open(out, encoding="utf-8") as stream:
        energy = [float(row["energy"]) for row in csv.DictReader(stream)]
    speeds = sum(v[k] @ v[k] for k in range(4)) / 2
    assert len(energy) == 201 and max(abs(e - speeds) for e in energy) < 1e-14


def test_a_gas_of_any_size_on_the_command_line(capsys, tmp_path) -> None:
    out = tmp_path / "gas9.csv"
    said = cli(capsys, "simulate", "hard_disk_gas:9", "--t-end", "0.5", "--out", str(out))
    x, v = start(9, 1 / 3 / 5)
    expected = brute_force(x, v, 1 / 3 / 5, 0.5)
    assert f"{len(expected)} impacts" in said
    code = main(["derive", "hard_disk_gas:101"])
    assert code == 2 and "from 1 to 100" in capsys.readouterr().err


def test_every_column_of_a_gas_is_found_by_name_and_survives_csv(tmp_path) -> None:
    """A column per contact (10 disks: 40 walls and 45 pairs): each by its name is the
    multiplier of its constraint (NaN in flight, no contact persists in an elastic gas), each
    coordinate and velocity its own, and the CSV round trip keeps every one."""
    run = run_gas(10, 0.05, 0.5, 6)
    assert len(run.multiplier_names) == 85
    for k, name in enumerate(run.multiplier_names):
        np.testing.assert_array_equal(run[name], run.multipliers[:, k])
    assert np.all(np.isnan(run.multipliers))
    for k, name in enumerate(run.coordinates):
        np.testing.assert_array_equal(run[name], run.q[:, k])
        np.testing.assert_array_equal(run[f"{name}_dot"], run.q_dot[:, k])
    assert tuple(run.columns()) == run.names
    run.to_csv(tmp_path / "gas.csv")
    again = lg.Trajectory.from_csv(tmp_path / "gas.csv")
    assert again.names == run.names
    for name in run.names:
        np.testing.assert_array_equal(again[name], run[name])
