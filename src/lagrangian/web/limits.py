"""What one request may use: the size of its body, the CPU time and memory of its work, and
how many requests may wait for a worker.  The worker processes hold themselves to these with
``setrlimit``: an address-space cap (RLIMIT_AS) for memory, a soft CPU-time cap (RLIMIT_CPU)
raised before each request, and the server kills a worker that outlives its wall-clock backstop.

>>> Limits().cpu_seconds, Limits().max_body_bytes
(20.0, 200000)
"""

from __future__ import annotations

import math
import resource
import signal
from dataclasses import dataclass
from types import FrameType


@dataclass(frozen=True)
class Limits:
    """The bounds of the playground's server.

    workers: processes doing the symbolic and numeric work, one request at a time each.
    queue: requests that may wait for a worker; one more is answered 503.
    cpu_seconds: CPU time of one request's work; over it the request gets a 422 error.
    memory_bytes: address space of a worker process (RLIMIT_AS).
    max_body_bytes: size of a request's body; over it the request gets a 413 error.
    max_samples: output times of one simulation.
    header_seconds: time a connection has to send a request's headers; then it is closed.
    body_seconds: time a request has to send its body; then it gets a 408 error.
    max_connections: connections open at once; a request on one more gets a 503 error.
    """

    workers: int = 2
    queue: int = 32
    cpu_seconds: float = 20.0
    memory_bytes: int = 4 << 30
    max_body_bytes: int = 200_000
    max_samples: int = 20_000
    header_seconds: float = 10.0
    body_seconds: float = 30.0
    max_connections: int = 64

    @property
    def client_workers(self) -> int:
        """How many workers one client's requests may hold at once: all but one, so that a
        client's heavy requests always leave a worker to the others."""
        return max(1, self.workers - 1)

    @property
    def wall_seconds(self) -> float:
        """How long the server waits for one request's answer before it kills the worker: the
        CPU budget, with room for a machine shared by every worker, and a worker's start."""
        return 3 * self.cpu_seconds + 30.0


class TimeLimitExceeded(BaseException):
    """The work of one request used its CPU time (raised by SIGXCPU).  A BaseException, so
    that no ``except Exception`` inside a computation can swallow it."""


def limit_memory(memory_bytes: int) -> None:
    """Cap this process's address space (a computation over it gets MemoryError)."""
    _, hard = resource.getrlimit(resource.RLIMIT_AS)
    if hard != resource.RLIM_INFINITY:
        memory_bytes = min(memory_bytes, hard)
    resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, hard))


def _cpu_used() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _on_cpu_limit(signum: int, frame: FrameType | None) -> None:
    release_cpu_limit()  # SIGXCPU repeats every second past the soft limit: stop it first
    raise TimeLimitExceeded


def watch_cpu_time() -> None:
    """Turn SIGXCPU, sent when the soft CPU limit is passed, into :class:`TimeLimitExceeded`."""
    signal.signal(signal.SIGXCPU, _on_cpu_limit)


def allow_cpu_seconds(seconds: float) -> None:
    """Let this process use ``seconds`` more CPU time from now (the soft RLIMIT_CPU)."""
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    soft = math.ceil(_cpu_used() + seconds)
    if hard != resource.RLIM_INFINITY:
        soft = min(soft, hard)
    resource.setrlimit(resource.RLIMIT_CPU, (soft, hard))


def release_cpu_limit() -> None:
    """No soft CPU limit (the hard one, if any, stays)."""
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    resource.setrlimit(resource.RLIMIT_CPU, (hard, hard))
