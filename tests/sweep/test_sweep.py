"""lagrangian.sweeps on a real local Dask cluster: the store against single simulations, closed
forms, failures, random samples and resuming."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import zarr

import lagrangian as lg
from lagrangian.errors import SimulationInputError
from lagrangian.sweeps import sweep

TOLERANCES = {"method": "DOP853", "rtol": 1e-10, "atol": 1e-10}

BLOW_UP = """
coordinates: [x]
parameters: {k: 1.0}
kinetic: x_dot**2/2
potential: -k*x**4/4
initial: {x: 0.1, x_dot: 0.0}
"""


def test_a_small_grid_equals_single_simulate_runs(cluster, tmp_path: Path) -> None:
    system = lg.examples.double_pendulum()
    angles, lengths = [0.3, 1.0, 2.0], [0.5, 1.5]
    out = tmp_path / "grid.zarr"
    report = sweep(
        system,
        {"theta": angles, "l2": lengths},
        3.0,
        out=out,
        samples=6,
        scheduler=cluster.scheduler_address,
        chunk_size=2,
        **TOLERANCES,
    )
    assert report.members == report.computed == 6 and report.status == {"success": 6}
    data = xr.open_zarr(out)
    assert data["theta"].dims == ("theta_0", "l2", "t")
    assert data["phi_dot"].dims == ("theta_0", "l2", "t")
    assert data["status"].dims == ("theta_0", "l2")
    np.testing.assert_array_equal(data["theta_0"], angles)
    np.testing.assert_array_equal(data["l2"], lengths)
    for i, angle in enumerate(angles):
        for j, length in enumerate(lengths):
            alone = lg.simulate(
                system, {"theta": angle}, 3.0, parameters={"l2": length}, samples=6, **TOLERANCES
            )
            np.testing.assert_allclose(data["t"], alone.t, rtol=0, atol=1e-12)
            for k, name in enumerate(("theta", "phi")):
                member = data[name][i, j].values
                np.testing.assert_allclose(member, alone.q[:, k], rtol=0, atol=1e-8)
                velocity = data[name + "_dot"][i, j].values
                np.testing.assert_allclose(velocity, alone.q_dot[:, k], rtol=0, atol=1e-8)
            np.testing.assert_allclose(data["energy"][i, j], alone.energy, rtol=0, atol=1e-8)
    assert bool(data["done"].all())
    assert float(data["energy_drift"].max()) < 1e-7


def test_a_member_that_cannot_be_integrated_is_recorded_as_failed(cluster, tmp_path: Path) -> None:
    # x_ddot = x^3 from rest at x0 = 1 reaches infinity at t = 1.854 (< 3); from 0.1 it does not
    out = tmp_path / "failed.zarr"
    report = sweep(
        lg.loads(BLOW_UP),
        {"x": [0.1, 1.0]},
        3.0,
        out=out,
        samples=3,
        scheduler=cluster.scheduler_address,
    )
    assert report.status == {"success": 1, "failed": 1}
    data = xr.open_zarr(out)
    assert list(data["status"].values) == ["success", "failed"]
    assert "failed" in str(data["message"].values[1]).lower()
    # samples at t = 0, 1.5, 3: the failed member keeps those before its blow-up at t = 1.854
    assert np.all(np.isfinite(data["x"].values[1][:2])) and np.isnan(data["x"].values[1][2])
    assert np.all(np.isfinite(data["x"].values[0]))


def test_random_names_share_the_sample_dimension(cluster, tmp_path: Path) -> None:
    out = tmp_path / "random.zarr"
    sweep(
        lg.examples.simple_pendulum(),
        {"theta": [0.1, 0.2]},
        1.0,
        out=out,
        random={"l": (1.0, 2.0, 5), "theta_dot": (-0.1, 0.1, 5)},
        seed=3,
        scheduler=cluster.scheduler_address,
    )
    data = xr.open_zarr(out)
    assert data["theta"].dims == ("theta_0", "sample", "t")
    assert data["l"].dims == ("sample",) and data["theta_dot_0"].dims == ("sample",)
    assert bool(((data["l"] >= 1) & (data["l"] < 2)).all())
    alone = lg.simulate(
        lg.examples.simple_pendulum(),
        {"theta": 0.2, "theta_dot": float(data["theta_dot_0"][4])},
        1.0,
        parameters={"l": float(data["l"][4])},
    )
    np.testing.assert_allclose(data["theta"][1, 4, -1], alone.q[-1, 0], atol=1e-7)


def test_resume_computes_only_the_blocks_not_done(cluster, tmp_path: Path) -> None:
    out = tmp_path / "resume.zarr"
    options = {
        "out": out,
        "samples": 4,
        "chunk_size": 2,
        "scheduler": cluster.scheduler_address,
    }
    system, vary = lg.examples.simple_pendulum(), {"theta": [0.1, 0.2, 0.3, 0.4, 0.5]}
    sweep(system, vary, 2.0, **options)
    clean = xr.open_zarr(out).load()
    group = zarr.open_group(str(out), mode="r+")  # a crash inside the second block
    group["theta"][2:4] = np.nan
    group["done"][2:3] = False
    with pytest.raises(SimulationInputError, match="already exists"):
        sweep(system, vary, 2.0, **options)
    report = sweep(system, vary, 2.0, resume=True, **options)
    assert (report.computed, report.skipped) == (2, 3)
    xr.testing.assert_identical(xr.open_zarr(out).load(), clean)


def test_resume_refuses_a_store_of_another_sweep(cluster, tmp_path: Path) -> None:
    out = tmp_path / "other.zarr"
    system = lg.examples.simple_pendulum()
    sweep(system, {"theta": [0.1]}, 1.0, out=out, scheduler=cluster.scheduler_address)
    with pytest.raises(SimulationInputError, match=r"different sweep.*grid_digest"):
        sweep(system, {"theta": [0.2]}, 1.0, out=out, resume=True)


def test_an_unreachable_scheduler_leaves_no_store_behind(tmp_path: Path) -> None:
    import socket

    with socket.socket() as probe:  # a port nothing listens on
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
    out = tmp_path / "never.zarr"
    system = lg.examples.simple_pendulum()
    with pytest.raises(lg.SimulationError, match="cannot reach the Dask scheduler"):
        sweep(system, {"theta": [0.1]}, 1.0, out=out, scheduler=address)
    assert not out.exists()  # the same command runs again without --resume


def test_bad_input_names_the_field_before_any_cluster_starts(tmp_path: Path) -> None:
    system = lg.examples.simple_pendulum()
    with pytest.raises(SimulationInputError, match=r"vary\['kk'\].*not a name"):
        sweep(system, {"kk": [1.0]}, 1.0, out=tmp_path / "a.zarr")
    with pytest.raises(SimulationInputError, match=r"random\['l'\].*bad range"):
        sweep(system, {}, 1.0, random={"l": (2.0, 1.0, 3)}, out=tmp_path / "a.zarr")
    with pytest.raises(SimulationInputError, match="method"):
        sweep(system, {"theta": [0.1]}, 1.0, method="nope", out=tmp_path / "a.zarr")
    with pytest.raises(SimulationInputError, match=r"stop_when.*unknown"):
        sweep(system, {"theta": [0.1]}, 1.0, stop_when="zz", out=tmp_path / "a.zarr")
    assert not (tmp_path / "a.zarr").exists()
