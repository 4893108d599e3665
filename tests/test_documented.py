"""Every command and model of the README and docs/model-file.md, run as written: the tour's
commands, the model-file example (it is the Python System of the README), the sweeps, the
web API's request body.  A new user follows them line by line; they must not drift.

Run with changes, each said where it is made: the flip-map sweep on a 3 x 3 grid (as written
it is 40,000 runs, the benchmark of benchmarks/flip_map.py); the TLS cluster commands are
parsed, not run (they need certificates and machines)."""

from __future__ import annotations

import re
import shlex
import warnings
from pathlib import Path
from typing import Any

import pytest
import sympy as sp
import yaml

import lagrangian as lg
from lagrangian.cli.main import build_parser, main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
MODEL_FILE_DOC = (ROOT / "docs" / "model-file.md").read_text(encoding="utf-8")


def blocks(text: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", text, re.S)


def commands(block: str) -> list[list[str]]:
    """Each command of a shell block: continuation lines joined, comments dropped."""
    joined = block.replace("\\\n", " ")
    return [argv for line in joined.splitlines() if (argv := shlex.split(line, comments=True))]


def lagrangian_commands(text: str) -> list[list[str]]:
    return [
        argv[1:]
        for block in blocks(text, "bash")
        for argv in commands(block)
        if argv[0] == "lagrangian"
    ]


TOUR = [argv for argv in lagrangian_commands(README) if argv[0] not in ("serve", "sweep")]


def _slow_if_drawn(argv: list[str]) -> Any:
    marks = [pytest.mark.slow] if "--animate" in argv else []
    return pytest.param(argv, marks=marks, id=" ".join(argv[:2]))


@pytest.mark.parametrize("argv", [_slow_if_drawn(argv) for argv in TOUR])
def test_every_command_of_the_tour_runs_as_written(
    argv: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: Any
) -> None:
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    assert code == 0, capsys.readouterr().err
    for option in ("--out", "--plot", "--animate"):
        if option in argv and argv[0] == "simulate":
            assert (tmp_path / argv[argv.index(option) + 1]).stat().st_size > 0


def test_the_tour_is_what_the_readme_shows() -> None:
    # The parametrization above is not empty by accident: the tour has its dozen commands.
    verbs = {argv[0] for argv in TOUR}
    assert {"examples", "derive", "analyze", "simulate", "export"} <= verbs
    assert len(TOUR) >= 12


def test_the_model_file_of_the_readme_is_its_python_system() -> None:
    (model,) = blocks(README, "yaml")
    from_file = lg.derive(lg.loads(model, format="yaml"))
    python = lg.derive(lg.examples.double_pendulum())
    assert from_file.coordinates == python.coordinates
    for a, b in zip(from_file.equations, python.equations, strict=True):
        assert sp.simplify(a - b) == 0


def test_the_model_file_guide_runs_as_written(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: Any
) -> None:
    pendulum, *fragments = blocks(MODEL_FILE_DOC, "yaml")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pendulum.yaml").write_text(pendulum)
    eom = lg.derive(lg.load(tmp_path / "pendulum.yaml"))
    m, l, g, theta = sp.symbols("m l g theta")
    theta_ddot = sp.Symbol("theta_ddot")
    # A bob on a rod: m l^2 theta'' + m g l sin(theta) = 0.
    assert sp.simplify(eom.equations[0] - (m * l**2 * theta_ddot + m * g * l * sp.sin(theta))) == 0
    keys = set(lg.loads(pendulum, format="yaml").__dataclass_fields__) | {"simulate"}
    for fragment in fragments:
        assert set(yaml.safe_load(fragment)) <= keys, fragment
    ((argv, *_),) = [lagrangian_commands(MODEL_FILE_DOC)]
    drawn = [a for a in argv if a not in ("--animate", "pendulum.gif")]  # drawn in the slow run
    assert main(drawn) == 0, capsys.readouterr().err
    assert (tmp_path / "pendulum.png").stat().st_size > 0


def test_a_bouncing_ball_with_the_guides_unilateral_constraint() -> None:
    fragment = next(b for b in blocks(MODEL_FILE_DOC, "yaml") if "unilateral" in b)
    ball = (
        "coordinates: [y]\nparameters: {m: 1, g: 9.81, e: 0.5}\n"
        "kinetic: m*y_dot**2/2\npotential: m*g*y\ninitial: {y: 1, y_dot: 0}\n" + fragment
    )
    trajectory = lg.simulate(lg.loads(ball, format="yaml"), t_span=0.6, samples=50)
    # Falling from 1 m: the floor is reached at t = sqrt(2/g) and the ball leaves at e times
    # the speed sqrt(2 g).
    (first, *_) = trajectory.impacts
    assert first.t == pytest.approx((2 / 9.81) ** 0.5, rel=1e-6)
    assert first.after["y_dot"] == pytest.approx(0.5 * (2 * 9.81) ** 0.5, rel=1e-6)


def test_the_tls_cluster_commands_name_real_options() -> None:
    (tls,) = [b for b in blocks(README, "bash") if "--tls-ca-file" in b]
    (argv,) = [a[1:] for a in commands(tls) if a[0] == "lagrangian"]
    arguments = build_parser().parse_args(argv)
    assert arguments.tls_ca_file == "ca.pem" and arguments.scheduler == "tls://HOST:8786"


def test_the_web_api_body_of_the_readme_is_answered() -> None:
    pytest.importorskip("starlette")
    pytest.importorskip("httpx")
    with warnings.catch_warnings():  # Starlette 1.x warns when it runs on httpx
        warnings.filterwarnings("ignore", message=".*httpx2.*")
        from starlette.testclient import TestClient

    from lagrangian.web import create_app

    (body,) = re.findall(r"`(\{\"model\": TEXT.*?\})`", README)
    extras = re.findall(r"`(\"(?:t_end|initial)\": [^`]*)`", README)
    assert len(extras) == 2
    model = "coordinates: [theta]\\nparameters: {m: 1, l: 1, g: 9.81}\\n"
    model += "kinetic: m*l**2*theta_dot**2/2\\npotential: -m*g*l*cos(theta)\\n"
    model += "initial: {theta: 0, theta_dot: 0}"
    request = body.replace("TEXT", f'"{model}"')
    with TestClient(create_app()) as client:
        for verb in ("derive", "analyze", "export"):
            answer = client.post(f"/api/{verb}", content=request, headers=_JSON)
            assert answer.status_code == 200, (verb, answer.text)
        simulated = request.replace('"options": {', '"options": {' + ", ".join(extras) + ", ")
        answer = client.post("/api/simulate", content=simulated, headers=_JSON)
        assert answer.status_code == 200, answer.text
        assert answer.json()["summary"]


_JSON = {"Content-Type": "application/json"}


@pytest.mark.slow
def test_the_sweeps_of_the_readme_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: Any
) -> None:
    pytest.importorskip("dask.distributed")
    xr = pytest.importorskip("xarray")
    monkeypatch.chdir(tmp_path)
    flips, incline, bounces = [a for a in lagrangian_commands(README) if a[0] == "sweep"][:3]
    small = [a.replace(":200", ":3") for a in flips]  # 3 x 3 of the 200 x 200 map
    assert main([*small, "--workers", "1"]) == 0, capsys.readouterr().err
    reading, bouncing = blocks(README, "py")
    namespace: dict[str, Any] = {}
    exec(compile(reading, "README.md", "exec"), namespace)  # the README's own code
    assert namespace["flips"]["stop_time"].shape == (3, 3)
    assert main([*incline, "--workers", "1"]) == 0, capsys.readouterr().err
    assert xr.open_zarr("incline.zarr")["x"].shape[0] == 8
    few = [a.replace("0.1:0.9:9", "0.3:0.7:3") for a in bounces]  # 3 of the 9 restitutions
    assert main([*few, "--workers", "1"]) == 0, capsys.readouterr().err
    exec(compile(bouncing, "README.md", "exec"), namespace)  # after the first block: xr
    stored = namespace["bounces"]
    # each bounce lasts e times the one before: more of them before rest as e grows
    counts = [int(c) for c in stored["impacts"].values]
    assert 0 < counts[0] < counts[1] < counts[2]
    assert all(0 < float(t) < 10 for t in stored["rest_time"].values)
