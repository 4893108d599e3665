"""``lagrangian serve``: its flags, the loopback default, and a real server started by the
command answering the page and the API until Ctrl-C stops it."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request

from playground_setup import free_port

from lagrangian.cli.main import build_parser
from lagrangian.web.server import allowed_hosts, is_loopback

SERVE = [sys.executable, "-m", "lagrangian", "serve", "--no-browser"]
SIMPLE = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"


def test_the_flags_and_the_loopback_default() -> None:
    args = build_parser().parse_args(["serve"])
    assert (args.host, args.port, args.no_browser) == ("127.0.0.1", 8000, False)
    assert is_loopback(args.host)
    args = build_parser().parse_args(["serve", "--host", "::1", "--port", "9000", "--no-browser"])
    assert (args.host, args.port, args.no_browser) == ("::1", 9000, True)
    assert is_loopback("::1") and not is_loopback("0.0.0.0") and not is_loopback("example.org")


def test_the_names_the_server_answers_to() -> None:
    args = build_parser().parse_args(["serve", "--allowed-host", "Lab.Example.org"])
    assert args.allowed_host == ["Lab.Example.org"]
    on_loopback = allowed_hosts("127.0.0.1", args.allowed_host)
    assert on_loopback is not None and {"localhost", "[::1]", "lab.example.org"} <= set(on_loopback)
    assert allowed_hosts("0.0.0.0") is None  # shared without names: any Host, as told
    assert allowed_hosts("0.0.0.0", ["lab.example.org"]) == ("lab.example.org",)


def _get(
    url: str, body: dict[str, object] | None = None, host: str | None = None
) -> tuple[int, bytes]:
    data = json.dumps(body).encode() if body is not None else None
    headers = {"Content-Type": "application/json", **({"Host": host} if host else {})}
    request = urllib.request.Request(url, data=data, headers=headers)
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            return response.status, response.read()
    except urllib.error.HTTPError as error:
        return error.code, error.read()


def test_the_command_serves_until_interrupted() -> None:
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "lagrangian", "serve", "--no-browser", "--port", str(port)],
        stderr=subprocess.PIPE,
        text=True,
    )
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            try:
                status, page = _get(base + "/")
                break
            except OSError:
                time.sleep(0.2)
        assert status == 200 and b'data-testid="editor"' in page
        status, answer = _get(base + "/api/derive", {"model": SIMPLE})
        assert status == 200 and json.loads(answer)["equations"] == ["x + x_ddot"]
        # a page elsewhere whose name resolves here (DNS rebinding) is not answered
        status, _ = _get(base + "/api/derive", {"model": SIMPLE}, host=f"evil.example:{port}")
        assert status == 400
        assert _get(base + "/", host=f"localhost:{port}")[0] == 200
    finally:
        server.send_signal(signal.SIGINT)
        _, stderr = server.communicate(timeout=60)
    assert server.returncode == 0, stderr
    assert f"the playground is at http://127.0.0.1:{port}/" in stderr


#: The command line's time limit in the server's test, and how long the test uses the server.
LIMIT_SECONDS, AFTER_SECONDS = 3, 10


def test_the_server_outlives_the_command_time_limit() -> None:
    """``serve`` is a long-running command: no time limit for the command as a whole (each
    request keeps its own bound), so a short $LAGRANGIAN_TIME_LIMIT never stops it.  It says
    where it is only once it answers there, and answers to the very address it prints (a
    loopback address other than 127.0.0.1 included)."""
    port = free_port()
    started = time.monotonic()
    server = subprocess.Popen(
        [*SERVE, "--host", "127.0.0.2", "--port", str(port)],
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "LAGRANGIAN_TIME_LIMIT": str(LIMIT_SECONDS)},
    )
    base = f"http://127.0.0.2:{port}"
    try:
        assert server.stderr is not None
        announced = server.stderr.readline()
        assert f"the playground is at {base}/" in announced
        status, page = _get(base + "/")  # at once: the address is printed once it answers
        assert status == 200 and b'data-testid="editor"' in page
        time.sleep(max(0.0, started + AFTER_SECONDS - time.monotonic()))
        assert server.poll() is None, "the server stopped"
        status, page = _get(base + "/")
        assert status == 200 and b'data-testid="editor"' in page
        status, answer = _get(base + "/api/derive", {"model": SIMPLE})
        assert status == 200 and json.loads(answer)["equations"] == ["x + x_ddot"]
    finally:
        server.send_signal(signal.SIGINT)
        _, stderr = server.communicate(timeout=60)
    assert time.monotonic() - started > AFTER_SECONDS
    assert server.returncode == 0 and "time limit" not in stderr, stderr
