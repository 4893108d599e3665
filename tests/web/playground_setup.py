"""What the playground's tests share: the server's limits, a hostile model, and a real
uvicorn server in a thread."""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Iterator
from typing import Any

from lagrangian.web import Limits

#: Small limits, so that a hostile request is stopped within seconds.
TEST_LIMITS = Limits(workers=2, queue=32, cpu_seconds=4.0)
#: A model the parser accepts (under 100,000 terms multiplied out) whose derivation runs for
#: minutes: the kinetic energy is a polynomial of degree 30 in four symbols.
HOSTILE = "coordinates: [x, y]\nkinetic: (x_dot + y_dot + x + y + 1)**30/2\npotential: x**2\n"


def free_port() -> int:
    """A TCP port free on the loopback address."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextlib.contextmanager
def served(app: Any, limits: Limits) -> Iterator[int]:
    """``app`` served by uvicorn on 127.0.0.1 in a thread, configured as ``lagrangian serve``
    configures it for ``limits``, until the block ends; yields its port."""
    import uvicorn

    from lagrangian.web.connections import server_config

    port = free_port()
    server = uvicorn.Server(server_config(app, "127.0.0.1", port, limits))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    for _ in range(600):
        if server.started or not thread.is_alive():
            break
        time.sleep(0.1)
    assert server.started, "the server did not start"
    try:
        yield port
    finally:
        server.should_exit = True
        thread.join(timeout=30)
