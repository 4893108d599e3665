"""lagrangian.sweeps of constrained systems (multipliers, member by member), the energy it
stores (h where it differs from T + V) with the drift of each conserved quantity, and stop
times on every backend, on a real local Dask cluster, against closed forms and single
simulations."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.sweeps import sweep

TOLERANCES = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}

# x^2 + y^2 = l^2 held by a multiplier: m x_ddot = 2 lambda x, m y_ddot = -m g + 2 lambda y,
# so 2 lambda l = -(tension) = -(m v^2 / l - m g y / l)
CARTESIAN_PENDULUM = """
name: cartesian_pendulum
coordinates: [x, y]
parameters: {m: 1.0, g: 9.81, l: 1.0}
kinetic: m*(x_dot**2 + y_dot**2)/2
potential: m*g*y
constraints:
  - {holonomic: "x**2 + y**2 - l**2"}
initial: {x: 0.0, y: -1.0, x_dot: 1.0, y_dot: 0.0}
"""

# a skate: the blade cannot move sideways (non-holonomic).  From phi = 0 at speed v and turn
# rate w: phi = w t, x = v sin(w t) / w, y = v (1 - cos(w t)) / w, and m x_ddot = lambda
# sin(phi), m y_ddot = -lambda cos(phi) give lambda = -m v w
SKATE = """
name: skate
coordinates: [x, y, phi]
parameters: {m: 2.0, I: 0.5}
kinetic: m*(x_dot**2 + y_dot**2)/2 + I*phi_dot**2/2
constraints:
  - {velocity: "x_dot*sin(phi) - y_dot*cos(phi)"}
initial: {x: 0.0, y: 0.0, phi: 0.0, x_dot: 1.0, y_dot: 0.0, phi_dot: 1.0}
"""

# a bead on a hoop of radius R turning at w about the vertical: T has a part of degree 0 in
# theta_dot, so h = m R^2 (theta_dot^2 - w^2 sin^2 theta)/2 - m g R cos(theta) is conserved and
# T + V is not
HOOP = """
name: bead_on_rotating_hoop
coordinates: [theta]
parameters: {m: 1.0, R: 1.0, w: 5.0, g: 9.81}
kinetic: m*R**2*(theta_dot**2 + w**2*sin(theta)**2)/2
potential: -m*g*R*cos(theta)
initial: {theta: 0.5, theta_dot: 0.0}
"""


def test_a_constrained_pendulum_sweep_equals_single_simulate_runs(cluster, tmp_path: Path) -> None:
    system = lg.loads(CARTESIAN_PENDULUM)
    speeds, gravities = [0.5, 1.5, 3.0], [9.81, 4.0]
    out = tmp_path / "constrained.zarr"
    report = sweep(
        system,
        {"x_dot": speeds, "g": gravities},
        2.0,
        out=out,
        samples=5,
        chunk_size=4,
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    assert report.status == {"success": 6}
    data = xr.open_zarr(out)
    assert data["lambda_1"].dims == ("x_dot_0", "g", "t")
    assert data["constraint_drift"].dims == ("x_dot_0", "g")
    for i, speed in enumerate(speeds):
        for j, g in enumerate(gravities):
            alone = lg.simulate(
                system, {"x_dot": speed}, 2.0, parameters={"g": g}, samples=5, **TOLERANCES
            )
            for name in ("x", "y", "x_dot", "y_dot", "lambda_1", "energy"):
                np.testing.assert_allclose(data[name][i, j], alone[name], rtol=0, atol=1e-8)
            drift = alone.drift()
            stored = float(data["constraint_drift"][i, j])
            assert stored == pytest.approx(drift["constraint_residual_max"], abs=1e-12)
            assert float(data["energy_drift"][i, j]) == pytest.approx(drift["energy_absolute"])
    # the multiplier against the tension of a pendulum (module comment), from the stored states
    x, y, u, v = (data[name].values for name in ("x", "y", "x_dot", "y_dot"))
    g = np.broadcast_to(data["g"].values[None, :, None], x.shape)
    tension = (u**2 + v**2) - g * y
    np.testing.assert_allclose(data["lambda_1"], -tension / 2, rtol=0, atol=1e-7)
    np.testing.assert_allclose(x**2 + y**2, 1.0, rtol=0, atol=1e-8)
    assert float(data["constraint_drift"].max()) < 1e-8
    assert data["energy"].attrs["quantity"] == "T + V"
    assert set(data["not_conserved"].values.ravel()) == {""}


def test_a_nonholonomic_skate_has_its_closed_form_motion_and_multiplier(
    cluster, tmp_path: Path
) -> None:
    out = tmp_path / "skate.zarr"
    speeds, turns = np.array([0.5, 2.0]), np.array([-1.0, 0.7, 3.0])
    sweep(
        lg.loads(SKATE),
        {"x_dot": speeds, "phi_dot": turns},
        3.0,
        out=out,
        samples=7,
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    data = xr.open_zarr(out)
    t = data["t"].values
    v, w = np.meshgrid(speeds, turns, indexing="ij")
    v, w = v[..., None], w[..., None]
    np.testing.assert_allclose(data["phi"], w * t, rtol=0, atol=1e-8)
    np.testing.assert_allclose(data["x"], v * np.sin(w * t) / w, rtol=0, atol=1e-8)
    np.testing.assert_allclose(data["y"], v * (1 - np.cos(w * t)) / w, rtol=0, atol=1e-8)
    np.testing.assert_allclose(data["lambda_1"], -2.0 * v * w * np.ones_like(t), atol=1e-7)
    assert list(data["status"].values.ravel()) == ["success"] * 6
    assert float(data["constraint_drift"].max()) < 1e-8


def test_initial_states_off_the_constraints(cluster, tmp_path: Path) -> None:
    system = lg.loads(CARTESIAN_PENDULUM)
    options = {"scheduler": cluster.scheduler_address, "samples": 3}
    # the first member is checked before the cluster works: the fix is a keyword
    with pytest.raises(SimulationInputError, match=r"violates the constraints.*project_initial="):
        sweep(system, {"x": [0.5, 0.0]}, 1.0, out=tmp_path / "refused.zarr", **options)
    assert not (tmp_path / "refused.zarr").exists()
    # a later member off the constraints is recorded as failed, with why
    out = tmp_path / "later.zarr"
    report = sweep(system, {"x": [0.0, 0.5]}, 1.0, out=out, **options)
    assert report.status == {"success": 1, "failed": 1}
    data = xr.open_zarr(out)
    assert "violates the constraints" in str(data["message"].values[1])
    # projected: each member starts on the circle, x_dot along it
    out = tmp_path / "projected.zarr"
    sweep(system, {"x": [0.3, 0.6]}, 1.0, out=out, project_initial=True, **options)
    data = xr.open_zarr(out)
    x, y = data["x"].values, data["y"].values
    np.testing.assert_allclose(x**2 + y**2, 1.0, atol=1e-8)
    assert list(data["status"].values) == ["success"] * 2


def test_h_is_stored_where_it_differs_from_t_plus_v(cluster, tmp_path: Path) -> None:
    out = tmp_path / "hoop.zarr"
    angles, rates = np.array([0.5, 1.0, 2.0]), np.array([1.0, 5.0])
    sweep(
        lg.loads(HOOP),
        {"theta": angles, "w": rates},
        3.0,
        out=out,
        samples=31,
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    data = xr.open_zarr(out)
    assert data["energy"].attrs["quantity"] == "energy function h"
    theta, theta_dot = data["theta"].values, data["theta_dot"].values
    w = np.broadcast_to(rates[None, :, None], theta.shape)
    h = (theta_dot**2 - w**2 * np.sin(theta) ** 2) / 2 - 9.81 * np.cos(theta)
    np.testing.assert_allclose(data["energy"], h, rtol=0, atol=1e-10)
    energy = data["energy"].values
    drift = np.max(np.abs(energy - energy[..., :1]), axis=-1)
    assert float(drift.max()) < 1e-8  # constant along every member
    np.testing.assert_allclose(data["energy_drift"], drift, rtol=0, atol=1e-14)
    total = (theta_dot**2 + w**2 * np.sin(theta) ** 2) / 2 - 9.81 * np.cos(theta)
    assert float(np.ptp(total, axis=-1).min()) > 1e-2  # T + V changes: it is not what is kept
    assert set(data["not_conserved"].values.ravel()) == {""}


def test_the_drift_of_what_is_not_conserved_is_a_reason(cluster, tmp_path: Path) -> None:
    out = tmp_path / "damped.zarr"
    sweep(
        lg.examples.mass_spring_damper(),
        {"B": [0.0, 0.5]},
        2.0,
        out=out,
        samples=3,
        scheduler=cluster.scheduler_address,
    )
    data = xr.open_zarr(out)
    assert float(data["energy_drift"][0]) < 1e-6 and np.isnan(data["energy_drift"][1])
    assert list(data["not_conserved"].values) == ["", "energy: dissipation"]
    planet = tmp_path / "planet.zarr"
    sweep(
        lg.examples.planet(),
        {"r_dot": [0.0, 0.1]},
        2.0,
        out=planet,
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    data = xr.open_zarr(planet)
    assert float(data["p_theta_drift"].max()) < 1e-8  # the momentum of the cyclic angle


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_stop_times_of_text_conditions_on_each_batch_backend(
    backend, cluster, tmp_path: Path
) -> None:
    # released at rest from theta0 > 0, theta turns negative at T/4 = sqrt(l/g) K(m),
    # m = sin^2(theta0/2)
    angles = np.array([0.2, 1.0, 2.5])
    out = tmp_path / f"stops-{backend}.zarr"
    sweep(
        lg.examples.simple_pendulum(),
        {"theta": angles},
        5.0,
        out=out,
        stop_when="theta",
        backend=backend,
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    data = xr.open_zarr(out)
    expected = math.sqrt(1.0 / 9.81) * ellipk(np.sin(angles / 2) ** 2)
    np.testing.assert_allclose(data["stop_time"], expected, rtol=1e-8)
    assert list(data["status"].values) == ["stopped"] * 3


def test_stop_times_of_constrained_members(cluster, tmp_path: Path) -> None:
    # from the bottom at speed v, x turns negative after half a period, 2 sqrt(l/g) K(m) with
    # m = v^2 / (4 g l); a member whose condition is negative at the start stops there
    speeds = np.array([0.5, 2.0, 5.0])
    out = tmp_path / "constrained-stops.zarr"
    sweep(
        lg.loads(CARTESIAN_PENDULUM),
        {"x_dot": speeds},
        5.0,
        out=out,
        samples=11,
        stop_when="x + 0.0*t",
        scheduler=cluster.scheduler_address,
        **TOLERANCES,
    )
    data = xr.open_zarr(out)
    expected = 2 * math.sqrt(1.0 / 9.81) * ellipk(speeds**2 / (4 * 9.81))
    np.testing.assert_allclose(data["stop_time"], expected, rtol=1e-8)
    assert list(data["status"].values) == ["stopped"] * 3
    after = data["t"].values[None, :] > expected[:, None]
    assert np.all(np.isnan(data["x"].values[after])) and np.all(
        np.isfinite(data["x"].values[~after])
    )
    out = tmp_path / "at-start.zarr"
    sweep(
        lg.loads(CARTESIAN_PENDULUM),
        {"x_dot": [1.0]},
        1.0,
        out=out,
        samples=3,
        stop_when="y",  # y = -1 at the start
        scheduler=cluster.scheduler_address,
    )
    data = xr.open_zarr(out)
    assert float(data["stop_time"][0]) == 0.0 and str(data["status"].values[0]) == "stopped"
    assert np.isfinite(data["lambda_1"][0, 0]) and np.all(np.isnan(data["lambda_1"][0, 1:]))


def test_python_messages_name_keywords(cluster, tmp_path: Path) -> None:
    incline = lg.examples.cylinder_on_incline()
    out = tmp_path / "a.zarr"
    with pytest.raises(SimulationInputError, match=r"remove project_initial=True"):
        sweep(lg.examples.simple_pendulum(), {"l": [1.0]}, 1.0, project_initial=True, out=out)
    with pytest.raises(SimulationInputError, match=r"stop_when: the method 'variational' does"):
        sweep(incline, {"alpha": [0.1]}, 1.0, method="variational", dt=0.1, stop_when="x", out=out)
    assert not out.exists()
