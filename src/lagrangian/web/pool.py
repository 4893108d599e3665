"""The worker processes of the server and the queue in front of them.

Every request's work runs in one of ``Limits.workers`` processes (:mod:`.worker`), one
request at a time each; up to ``Limits.queue`` more requests wait for a worker, and one more
is refused at once (:class:`PoolBusy`, HTTP 503).  A worker that does not answer within the
wall-clock backstop, or dies (its memory or CPU time exhausted in C code that never returned
to Python), is killed and replaced; only its own request gets the error.
"""

from __future__ import annotations

import asyncio
import os
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any

from lagrangian.web.limits import Limits
from lagrangian.web.worker import READY

#: How long a new worker may take to import the library before it is given up.
START_SECONDS = 120.0
#: How often the server looks at a busy worker's CPU time.
POLL_SECONDS = 0.25
#: CPU time a worker gets past its own limit to answer with an error before it is killed.
GRACE_SECONDS = 3.0
_TICKS = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100


def cpu_time(pid: int) -> float | None:
    """CPU seconds (user + system) used by process ``pid``, from /proc; None elsewhere."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            fields = stat.read().rpartition(")")[2].split()
    except OSError:
        return None
    return (int(fields[11]) + int(fields[12])) / _TICKS


class PoolBusy(Exception):
    """Every worker is busy and the queue is full."""


class WorkerLost(Exception):
    """A worker died or overran its time: it was killed and replaced.  The message says
    which, in words for the person who sent the request."""


@dataclass
class Worker:
    """One worker process and the server's end of its pipe."""

    process: subprocess.Popen[bytes]
    connection: Connection
    ready: bool = False

    @classmethod
    def start(cls, limits: Limits) -> Worker:
        """A new interpreter running :mod:`lagrangian.web.worker` (no fork of a threaded
        server, and no re-run of the caller's main module as multiprocessing's spawn does)."""
        ours, theirs = socket.socketpair()
        arguments = [str(theirs.fileno()), repr(limits.cpu_seconds), str(limits.memory_bytes)]
        process = subprocess.Popen(
            [sys.executable, "-m", "lagrangian.web.worker", *arguments],
            pass_fds=[theirs.fileno()],
            stdin=subprocess.DEVNULL,
        )
        theirs.close()
        return cls(process, Connection(ours.detach()))

    def alive(self) -> bool:
        return self.process.poll() is None

    def call(
        self, request: tuple[str, str, str, dict[str, Any]], seconds: float, cpu_seconds: float
    ) -> Any:
        """Send ``request`` and wait for its answer at most ``seconds``, and while the worker
        has used at most ``cpu_seconds`` of CPU time on it (a backstop for work stuck in C
        code, where the worker's own limit cannot interrupt it); else raise WorkerLost."""
        if not self.ready:
            self.receive(START_SECONDS)
            self.ready = True
        start = cpu_time(self.process.pid)
        self.connection.send(request)
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            if self.connection.poll(POLL_SECONDS):
                return self.receive(0.0)
            used = cpu_time(self.process.pid)
            if used is not None and start is not None and used - start > cpu_seconds:
                raise WorkerLost(f"the work used more than {cpu_seconds:g} s of CPU time")
        raise WorkerLost(f"the work did not finish within {seconds:g} s")

    def receive(self, seconds: float) -> Any:
        try:
            if self.connection.poll(seconds):
                return self.connection.recv()
        except (EOFError, OSError):
            raise WorkerLost("the work ended its process (out of memory or time)") from None
        raise WorkerLost(f"the worker did not answer within {seconds:g} s")

    def stop(self) -> None:
        """End the process (kill it if it does not leave at once)."""
        self.connection.close()
        try:
            self.process.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait(timeout=5.0)


class WorkerPool:
    """Worker processes behind a bounded queue; :meth:`run` answers one request."""

    def __init__(self, limits: Limits) -> None:
        self.limits = limits
        self.admitted = 0  # running or waiting
        self.replaced = 0  # workers killed and started anew
        self._workers: list[Worker] = []
        self._idle: asyncio.Queue[Worker] | None = None

    def start(self) -> None:
        """Start the workers (they import the library in the background)."""
        self._idle = asyncio.Queue()
        for _ in range(self.limits.workers):
            worker = Worker.start(self.limits)
            self._workers.append(worker)
            self._idle.put_nowait(worker)

    def close(self) -> None:
        for worker in self._workers:
            worker.stop()
        self._workers.clear()

    async def run(self, request: tuple[str, str, str, dict[str, Any]]) -> tuple[int, bytes]:
        """The status and body answering ``request``; PoolBusy when the queue is full,
        WorkerLost when its worker had to be killed."""
        if self._idle is None:
            raise RuntimeError("the worker pool is not started")
        if self.admitted >= self.limits.workers + self.limits.queue:
            raise PoolBusy
        self.admitted += 1
        try:
            worker = await self._idle.get()
        except BaseException:
            self.admitted -= 1
            raise
        # shielded: a request abandoned by its client still gives its worker back, once done
        return await asyncio.shield(self._use(worker, request))

    async def _use(
        self, worker: Worker, request: tuple[str, str, str, dict[str, Any]]
    ) -> tuple[int, bytes]:
        assert self._idle is not None
        try:
            status, body = await asyncio.to_thread(
                worker.call,
                request,
                self.limits.wall_seconds,
                self.limits.cpu_seconds + GRACE_SECONDS,
            )
            return int(status), bytes(body)
        except WorkerLost:
            worker = await asyncio.to_thread(self._replace, worker)
            raise
        finally:
            self._idle.put_nowait(worker)
            self.admitted -= 1

    def _replace(self, worker: Worker) -> Worker:
        worker.process.kill()
        worker.stop()
        fresh = Worker.start(self.limits)
        self._workers[self._workers.index(worker)] = fresh
        self.replaced += 1
        return fresh

    def wait_ready(self, seconds: float = START_SECONDS) -> bool:
        """Block until every worker has imported the library (call it before serving)."""
        deadline = time.monotonic() + seconds
        for worker in self._workers:
            if not worker.ready:
                remaining = max(0.0, deadline - time.monotonic())
                try:
                    worker.ready = worker.receive(remaining) == READY
                except WorkerLost:
                    worker.ready = False
        return all(worker.ready for worker in self._workers)

    def alive(self) -> int:
        """How many worker processes are running."""
        return sum(worker.alive() for worker in self._workers)
