"""The server's connections on a real uvicorn server: a request whose headers or body never
finish is cut off, the connections open at once are capped, and a page of another site
cannot run the API (its Origin)."""

from __future__ import annotations

import socket
import time
from collections.abc import Iterator
from typing import Any

import pytest
from playground_setup import served

from lagrangian import examples
from lagrangian.web import Limits

#: Short deadlines and few connections, so that the test sees each bound at work.
SHORT = Limits(
    workers=1, queue=4, cpu_seconds=4.0, header_seconds=1.0, body_seconds=1.0, max_connections=4
)
SIMPLE = examples.model_text("simple_pendulum")


@pytest.fixture(scope="module")
def short_server() -> Iterator[tuple[str, int]]:
    for module in ("starlette", "uvicorn", "httpx"):
        pytest.importorskip(module)
    from lagrangian.web import create_app

    with served(create_app(SHORT), SHORT) as port:
        yield "127.0.0.1", port


def _connect(address: tuple[str, int]) -> socket.socket:
    connection = socket.create_connection(address, timeout=30)
    return connection


def _closed_by_server(connection: socket.socket) -> bytes:
    """What the server sent before it closed the connection (waits for the close)."""
    received = b""
    while chunk := connection.recv(4096):
        received += chunk
    return received


def test_headers_that_never_finish_are_cut_off(short_server: tuple[str, int]) -> None:
    with _connect(short_server) as connection:
        connection.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # ... and nothing more
        assert _closed_by_server(connection) == b""
    with _connect(short_server) as idle:  # a connection that sends nothing at all
        assert _closed_by_server(idle) == b""


def test_a_body_that_never_finishes_is_408(short_server: tuple[str, int]) -> None:
    with _connect(short_server) as connection:
        connection.sendall(
            b"POST /api/derive HTTP/1.1\r\nHost: 127.0.0.1\r\n"
            b"Content-Type: application/json\r\nContent-Length: 500\r\n\r\n"
            b'{"model": "coordin'
        )
        answer = _closed_by_server(connection)
    assert answer.startswith(b"HTTP/1.1 408"), answer[:200]
    assert b"did not arrive within 1 s" in answer


def test_connections_past_the_cap_are_refused_until_the_idle_ones_are_cut(
    short_server: tuple[str, int],
) -> None:
    import httpx

    host, port = short_server
    base = f"http://{host}:{port}"
    hanging = [_connect(short_server) for _ in range(SHORT.max_connections)]
    try:
        for connection in hanging:
            connection.sendall(b"GET / HTTP/1.1\r\n")
        time.sleep(0.2)
        refused = httpx.get(base + "/api/health", timeout=30)
        assert refused.status_code == 503
    finally:
        for connection in hanging:
            assert _closed_by_server(connection) == b""  # cut at the header deadline
            connection.close()
    assert httpx.get(base + "/api/health", timeout=30).status_code == 200


def test_a_page_of_another_site_cannot_run_the_api(client: Any) -> None:
    body = {"model": SIMPLE}
    elsewhere = client.post("/api/derive", json=body, headers={"Origin": "http://evil.example"})
    assert elsewhere.status_code == 403
    assert elsewhere.json()["problems"][0]["field"] == "origin"
    sandboxed = client.post("/api/derive", json=body, headers={"Origin": "null"})
    assert sandboxed.status_code == 403
    own = client.post("/api/derive", json=body, headers={"Origin": "http://testserver"})
    assert own.status_code == 200
    assert client.post("/api/derive", json=body).status_code == 200  # no browser, no Origin


def test_the_address_the_server_listens_on_is_always_allowed() -> None:
    from lagrangian.web.server import allowed_hosts, page_address

    for host in ("127.0.0.2", "::1", "192.0.2.7"):
        names = allowed_hosts(host) or ()
        shown = page_address(host, 8000).split("//")[1].rsplit(":", 1)[0]
        assert shown in names, (host, names)
