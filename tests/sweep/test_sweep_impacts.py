"""A sweep of a system with impacts: each member bounces, loses energy at every impact and
comes to rest, against the bouncing ball's closed form (free fall y = h - g t^2/2 until
t1 = sqrt(2h/g), the bounce leaves at e g t1, the bounces accumulate at
t_inf = t1 (1 + e)/(1 - e), after which the floor holds the ball with lambda = m g).

Each member's number of impacts and the time it came to rest are stored too, equal to those
of the single run of the same member, and checked against the series by hand: the k-th impact
is at t_k = t1 (1 + 2 e (1 - e^(k-1))/(1 - e)), the bounce after it rises e^(2k) h, and the
run declares the contact at rest at the first impact whose bounce would rise no higher than
the re-contact tolerance (the remaining bounces, 2 t1 e^k/(1 - e) of time, are not flown)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.simulation.unilateral import RECONTACT_TOLERANCE
from lagrangian.sweeps import sweep
from lagrangian.sweeps.chunk_run import ChunkSettings, run_chunk
from lagrangian.sweeps.stop_condition import stop_expression
from lagrangian.sweeps.variables import sweep_variables

xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")


def test_a_sweep_over_the_restitution_bounces_each_member_to_rest(tmp_path: Path) -> None:
    ball = lg.examples.bouncing_ball()
    restitutions = [0.3, 0.5]
    out = tmp_path / "bounces.zarr"
    report = sweep(ball, {"e": restitutions}, 6.0, out=out, samples=601)
    assert report.status == {"success": 2}
    data = xr.open_zarr(out)
    t = data["t"].values
    g, h, m = 9.81, 1.0, 1.0
    t1 = math.sqrt(2 * h / g)
    for i, e in enumerate(restitutions):
        y = data["y"].values[i]
        falling = t < t1
        np.testing.assert_allclose(y[falling], h - g * t[falling] ** 2 / 2, atol=1e-7)
        second = t1 * (1 + 2 * e)  # the second impact
        flying = (t > t1) & (t < second)
        up = e * g * t1 * (t[flying] - t1) - g * (t[flying] - t1) ** 2 / 2
        np.testing.assert_allclose(y[flying], up, atol=1e-7)
        resting = t > t1 * (1 + e) / (1 - e) + 0.05
        assert np.all(np.abs(y[resting]) < 1e-7)
        np.testing.assert_allclose(data["lambda_1"].values[i][resting], m * g, rtol=1e-6)
        assert "impacts (e < 1)" in str(data["not_conserved"].values[i])
        assert abs(float(data["energy"].values[i][-1])) < 1e-6


def test_each_member_records_its_impacts_and_rest_time(cluster, tmp_path: Path) -> None:
    ball = lg.examples.bouncing_ball()
    restitutions = [0.3, 0.5, 0.7]
    out = tmp_path / "rest.zarr"
    options: dict = {"samples": 61}
    sweep(ball, {"e": restitutions}, 6.0, out=out, scheduler=cluster.scheduler_address, **options)
    data = xr.open_zarr(out)
    assert data["impacts"].dims == ("e",) and data["rest_time"].dims == ("e",)
    assert "impacts" in data["impacts"].attrs["long_name"]
    assert "rest" in data["rest_time"].attrs["long_name"]
    g, h = 9.81, 1.0
    t1 = math.sqrt(2 * h / g)
    for i, e in enumerate(restitutions):
        count, rest = int(data["impacts"].values[i]), float(data["rest_time"].values[i])
        single = lg.simulate(ball, None, 6.0, parameters={"e": e}, **options)
        resting = [impact.t for impact in single.impacts if impact.rest]
        assert count == len(single.impacts) and rest == resting[0]
        # the first impact whose bounce, e^(2k) h, is within the re-contact tolerance
        k = math.ceil(math.log(RECONTACT_TOLERANCE / h) / (2 * math.log(e)))
        assert count == k
        t_k = t1 * (1 + 2 * e * (1 - e ** (k - 1)) / (1 - e))
        assert rest == pytest.approx(t_k, abs=1e-9)  # a free fall is stepped exactly
        # the geometric series of the bounces, less those too low to fly (under 3e-4 s here)
        t_inf = t1 * (1 + e) / (1 - e)
        assert t_inf - rest == pytest.approx(2 * t1 * e**k / (1 - e), abs=1e-9)
        assert t_inf - rest < 3e-4


def test_a_system_without_impacts_stores_no_impact_variables(cluster, tmp_path: Path) -> None:
    out = tmp_path / "pendulum.zarr"
    pendulum = lg.examples.simple_pendulum()
    sweep(pendulum, {"l": [1.0, 2.0]}, 1.0, out=out, scheduler=cluster.scheduler_address)
    data = xr.open_zarr(out)
    assert "impacts" not in data and "rest_time" not in data
    assert not sweep_variables(pendulum).impacts


def test_a_member_stopped_at_its_start_met_no_impact() -> None:
    """y - 2 is negative at the start (y = 1): the member stops at t = 0, before any bounce;
    the member beside it, started at y = 3, runs until it falls past y = 2."""
    ball = lg.examples.bouncing_ball()
    stop = stop_expression(ball, "y - 2")
    settings = ChunkSettings(2.0, sweep_variables(ball), (0.0, 1.0, 2.0), stop_when=stop)
    result = run_chunk(ball, {"y": np.array([1.0, 3.0])}, {}, settings)
    assert result.status == ("stopped", "stopped")
    assert result.stop_time[0] == 0.0
    assert result.stop_time[1] == pytest.approx(math.sqrt(2 / 9.81), abs=1e-6)
    assert result.impacts.tolist() == [0, 0]
    assert np.isnan(result.rest_time).all()
