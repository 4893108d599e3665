"""A sweep of a system with impacts: each member bounces, loses energy at every impact and
comes to rest, against the bouncing ball's closed form (free fall y = h - g t^2/2 until
t1 = sqrt(2h/g), the bounce leaves at e g t1, the bounces accumulate at
t_inf = t1 (1 + e)/(1 - e), after which the floor holds the ball with lambda = m g)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.sweeps import sweep

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
