"""A worker process of the playground's server: it caps its own memory, then answers one
request at a time on its pipe, with a CPU-time budget per request (:mod:`.limits`).

The server sends ``(command, model, format, options)`` and receives ``(status, body)``.  The
heavy modules are imported before the worker says it is ready, so no request pays for them.
"""

from __future__ import annotations

import os
import signal
import sys
from multiprocessing.connection import Connection
from typing import Any

from lagrangian.web.limits import (
    TimeLimitExceeded,
    allow_cpu_seconds,
    limit_memory,
    release_cpu_limit,
    watch_cpu_time,
)

READY = "ready"


def serve_requests(connection: Connection, cpu_seconds: float, memory_bytes: int) -> None:
    """The worker's life: limits, imports, then requests until the server closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")  # one request, one core: the server runs several
    limit_memory(memory_bytes)
    watch_cpu_time()
    from lagrangian.web.runs import run  # SymPy, NumPy and SciPy load here, once

    try:
        connection.send(READY)
    except OSError:  # the server stopped while this worker was starting
        return
    while True:
        try:
            request: Any = connection.recv()
        except (EOFError, OSError):
            return
        try:
            connection.send(_answer(run, request, cpu_seconds))
        except OSError:
            return


def _answer(run: Any, request: Any, cpu_seconds: float) -> tuple[int, bytes]:
    command, model, fmt, options = request
    try:
        allow_cpu_seconds(cpu_seconds)
        return tuple(run(command, model, fmt, options, cpu_seconds))
    except TimeLimitExceeded:  # between the computation and the answer
        from lagrangian.web.runs import UNPROCESSABLE, error_document

        return UNPROCESSABLE, error_document(f"The work used its CPU time of {cpu_seconds:g} s")
    finally:
        release_cpu_limit()


def main(argv: list[str]) -> None:
    """``python -m lagrangian.web.worker FD CPU_SECONDS MEMORY_BYTES``: serve on socket FD."""
    descriptor, cpu_seconds, memory_bytes = argv
    serve_requests(Connection(int(descriptor)), float(cpu_seconds), int(memory_bytes))


if __name__ == "__main__":
    main(sys.argv[1:])
