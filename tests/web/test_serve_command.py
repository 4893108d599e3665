"""``lagrangian serve``: its flags, the loopback default, and a real server started by the
command answering the page and the API until Ctrl-C stops it."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request

from playground_setup import free_port

from lagrangian.cli.main import build_parser
from lagrangian.web.server import is_loopback

SIMPLE = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**2/2\n"


def test_the_flags_and_the_loopback_default() -> None:
    args = build_parser().parse_args(["serve"])
    assert (args.host, args.port, args.no_browser) == ("127.0.0.1", 8000, False)
    assert is_loopback(args.host)
    args = build_parser().parse_args(["serve", "--host", "::1", "--port", "9000", "--no-browser"])
    assert (args.host, args.port, args.no_browser) == ("::1", 9000, True)
    assert is_loopback("::1") and not is_loopback("0.0.0.0") and not is_loopback("example.org")


def _get(url: str, body: dict[str, object] | None = None) -> tuple[int, bytes]:
    data = json.dumps(body).encode() if body is not None else None
    request = urllib.request.Request(url, data=data, headers={"Content-Type": "application/json"})
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
    finally:
        server.send_signal(signal.SIGINT)
        _, stderr = server.communicate(timeout=60)
    assert server.returncode == 0, stderr
    assert f"the playground is at http://127.0.0.1:{port}/" in stderr
