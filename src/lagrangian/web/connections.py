"""The server's connections: uvicorn's HTTP/1.1 protocol (h11) with a deadline for a request's
headers, and the uvicorn configuration that caps the connections open at once.

A client that opens a connection and sends its headers a byte at a time ("slowloris") would
otherwise hold it open for ever; each connection must send a complete set of headers within
``Limits.header_seconds`` of opening (or of its previous answer), else it is closed.  The body
has its own deadline, checked where it is read (:func:`lagrangian.web.app.read_body`).
"""

from __future__ import annotations

import asyncio
from typing import Any

import h11
from uvicorn import Config
from uvicorn.protocols.http.h11_impl import H11Protocol

from lagrangian.web.limits import Limits


def header_deadline_protocol(header_seconds: float) -> type[H11Protocol]:
    """The h11 protocol of uvicorn, closing a connection whose request headers are not all
    there ``header_seconds`` after it opened or after its previous answer."""

    class HeaderDeadlineProtocol(H11Protocol):
        header_timer: asyncio.TimerHandle | None = None

        def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self.arm_header_timer()

        def data_received(self, data: bytes) -> None:
            super().data_received(data)
            if self.conn.their_state is not h11.IDLE:  # the headers are in
                self.disarm_header_timer()

        def on_response_complete(self) -> None:
            super().on_response_complete()
            if not self.transport.is_closing() and self.conn.their_state is h11.IDLE:
                self.arm_header_timer()

        def connection_lost(self, exc: Exception | None) -> None:
            self.disarm_header_timer()
            super().connection_lost(exc)

        def arm_header_timer(self) -> None:
            self.disarm_header_timer()
            self.header_timer = self.loop.call_later(header_seconds, self.headers_too_late)

        def disarm_header_timer(self) -> None:
            if self.header_timer is not None:
                self.header_timer.cancel()
                self.header_timer = None

        def headers_too_late(self) -> None:
            self.header_timer = None
            if self.conn.their_state is h11.IDLE and not self.transport.is_closing():
                self.transport.close()

    return HeaderDeadlineProtocol


def server_config(app: Any, host: str, port: int, limits: Limits) -> Config:
    """The uvicorn configuration of the playground: the header deadline, at most
    ``limits.max_connections`` connections served at once (a request on one more gets 503),
    and idle connections closed after five seconds."""
    return Config(
        app,
        host=host,
        port=port,
        log_level="warning",
        http=header_deadline_protocol(limits.header_seconds),
        limit_concurrency=limits.max_connections,
        timeout_keep_alive=5,
    )
