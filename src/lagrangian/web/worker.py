"""A worker process of the playground's server: it caps its own memory, then answers one
request at a time on its pipe, with a CPU-time budget per request (:mod:`.limits`).

The server sends ``(command, model, format, options)`` and receives ``(status, body)``.  The
heavy modules are imported before the worker says it is ready, so no request pays for them.
SIGUSR1 from the server interrupts the request being worked on (its client no longer wants
it): the answer is then 409, and the worker is free for the next request.
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
#: The status of a request interrupted because its client no longer wants it.
CANCELLED = 409


class Cancelled(BaseException):
    """The server cancelled the request being worked on (SIGUSR1).  A BaseException, so that
    no ``except Exception`` inside a computation can swallow it."""


_working = False  # whether a request is being worked on (SIGUSR1 between requests is moot)


def _on_cancel(signum: int, frame: Any) -> None:
    if _working:
        raise Cancelled


def serve_requests(connection: Connection, cpu_seconds: float, memory_bytes: int) -> None:
    """The worker's life: limits, imports, then requests until the server closes the pipe."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the server's to handle
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(name, "1")  # one request, one core: the server runs several
    limit_memory(memory_bytes)
    watch_cpu_time()
    signal.signal(signal.SIGUSR1, _on_cancel)
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
    global _working
    from lagrangian.web.runs import UNPROCESSABLE, error_document

    command, model, fmt, options = request
    try:
        try:
            _working = True
            allow_cpu_seconds(cpu_seconds)
            return tuple(run(command, model, fmt, options, cpu_seconds))
        finally:
            _working = False
            release_cpu_limit()
    except TimeLimitExceeded:  # between the computation and the answer
        return UNPROCESSABLE, error_document(f"The work used its CPU time of {cpu_seconds:g} s")
    except Cancelled:
        fix = "nothing to do: the newer request is answered instead"
        return CANCELLED, error_document("The request was cancelled by a newer one", fix=fix)


def main(argv: list[str]) -> None:
    """``python -m lagrangian.web.worker FD CPU_SECONDS MEMORY_BYTES``: serve on socket FD."""
    descriptor, cpu_seconds, memory_bytes = argv
    serve_requests(Connection(int(descriptor)), float(cpu_seconds), int(memory_bytes))


if __name__ == "__main__":
    main(sys.argv[1:])
