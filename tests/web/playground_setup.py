"""What the playground's tests share: the server's limits and a hostile model."""

from __future__ import annotations

import socket

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
