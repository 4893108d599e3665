"""The sweep's Dask cluster runs only the sweep's functions: the local cluster speaks TLS with
credentials of its own, so another process of the machine (another user) that connects to
its ports cannot have a function run; a running cluster is reached with its TLS files."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr

import lagrangian as lg
from lagrangian.cli.main import main
from lagrangian.errors import SimulationInputError
from lagrangian.sweeps import sweep
from lagrangian.sweeps.cluster import dask_client

#: Another user's attempt: connect to ADDRESS (with credentials of its own when asked) and
#: have a function run; prints what happened.
INTRUDER = """
import sys
from distributed import Client
from distributed.security import Security

security = Security.temporary() if sys.argv[2] == "own" else None
try:
    client = Client(sys.argv[1], timeout=5, security=security)
    print("ran", client.run(lambda: 1))
except Exception as error:
    print("refused", type(error).__name__)
"""


def intrude(address: str, credentials: str) -> str:
    run = subprocess.run(
        [sys.executable, "-c", INTRUDER, address, credentials],
        capture_output=True,
        text=True,
        timeout=120,
    )
    return run.stdout.strip()


@pytest.mark.slow
def test_another_process_cannot_run_code_on_the_local_cluster():
    with dask_client(workers=1) as client:
        assert client.submit(sum, [1, 2]).result() == 3  # the sweep's own client works
        scheduler = client.scheduler.address
        (worker,) = client.scheduler_info()["workers"]
        assert scheduler.startswith("tls://127.0.0.1:")
        for address in (scheduler, worker):
            plain = "tcp://" + address.removeprefix("tls://")
            assert intrude(plain, "none").startswith("refused"), plain
            assert intrude(address, "none").startswith("refused"), address
            assert intrude(address, "own").startswith("refused"), address


@pytest.mark.slow
def test_a_sweep_runs_on_its_tls_cluster(tmp_path: Path):
    out = tmp_path / "r.zarr"
    system = lg.examples.simple_pendulum()
    report = sweep(system, {"theta": [0.1, 0.2]}, 0.5, out=out, workers=1)
    assert report.computed == 2
    assert xr.open_zarr(out).sizes["theta_0"] == 2


def test_credentials_for_the_local_cluster_are_refused():
    with pytest.raises(SimulationInputError, match="security: applies to a running cluster"):
        sweep(lg.examples.simple_pendulum(), {"theta": [0.1]}, 1.0, out="r.zarr", security=1)


@pytest.mark.parametrize(
    ("flags", "named"),
    [
        (["--tls-cert", "CERT"], r"--tls-ca-file: missing.*applies to a running cluster only"),
        (["--tls-ca-file", "nowhere.pem", "--tls-cert", "CERT"], r"--tls-ca-file: cannot read"),
        (
            ["--tls-ca-file", "CERT", "--tls-cert", "CERT", "--scheduler", "tcp://h:8786"],
            r"--scheduler: TLS credentials need a tls:// address.*tls://HOST:PORT",
        ),
    ],
)
def test_tls_flags_are_checked_by_name(flags, named, tmp_path: Path, capsys) -> None:
    cert = tmp_path / "cert.pem"
    cert.write_text("not checked before the flags are\n")
    flags = [str(cert) if flag == "CERT" else flag for flag in flags]
    out = tmp_path / "r.zarr"
    code = main(
        ["sweep", "examples/simple_pendulum", "--vary", "theta=0,1", *flags, "--out", str(out)]
    )
    assert code == 2
    err = capsys.readouterr().err
    assert re.search(named, err, flags=re.DOTALL), err
    assert not out.exists()
