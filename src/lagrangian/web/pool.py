"""The worker processes of the server and the queue in front of them.

Every request's work runs in one of ``Limits.workers`` processes (:mod:`.worker`), one
request at a time each; up to ``Limits.queue`` more requests wait for a worker, and one more
is refused at once (:class:`PoolBusy`, HTTP 503).  A worker that does not answer within the
wall-clock backstop, or dies (its memory or CPU time exhausted in C code that never returned
to Python), is killed and replaced; only its own request gets the error.

The waiting requests are queued per client and served in turn (round robin), and one address
holds at most ``Limits.client_workers`` workers at once, whatever clients (pages) it names: a
client's heavy requests wait behind each other, never in front of another client's, and
naming more clients does not take more workers.  A request is a :class:`Ticket`; one
cancelled (its client went away, or sent a newer request of the same kind) leaves the queue,
or, running, has its work interrupted (SIGUSR1, :mod:`.worker`) so that its worker is free.
"""

from __future__ import annotations

import asyncio
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from collections import deque
from dataclasses import dataclass, field
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


class Superseded(Exception):
    """The request was cancelled before a worker took it: its client went away or sent a
    newer request of the same kind."""


Request = tuple[str, str, str, dict[str, Any]]


@dataclass(eq=False)
class Ticket:
    """One request: what it asks, whose it is, and whether it is still wanted.

    client: who sent it (requests are queued per client).
    kind: what it is for (the command); a newer request of the same client and kind
        supersedes this one.
    address: where it came from, as the connection says (the client by default): the
        workers held at once are bounded per address, since a client names itself.
    """

    request: Request
    client: str = ""
    kind: str = ""
    address: str = ""
    cancelled: threading.Event = field(default_factory=threading.Event)
    granted: asyncio.Future[Worker] | None = None


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
        self,
        request: Request,
        seconds: float,
        cpu_seconds: float,
        cancelled: threading.Event | None = None,
    ) -> Any:
        """Send ``request`` and wait for its answer at most ``seconds``, and while the worker
        has used at most ``cpu_seconds`` of CPU time on it (a backstop for work stuck in C
        code, where the worker's own limit cannot interrupt it); else raise WorkerLost.  Once
        ``cancelled`` is set the work is interrupted, and given GRACE_SECONDS to answer."""
        if not self.ready:
            self.receive(START_SECONDS)
            self.ready = True
        start = cpu_time(self.process.pid)
        self.connection.send(request)
        deadline = time.monotonic() + seconds
        interrupted = False
        while time.monotonic() < deadline:
            if self.connection.poll(POLL_SECONDS):
                return self.receive(0.0)
            used = cpu_time(self.process.pid)
            if used is not None and start is not None and used - start > cpu_seconds:
                raise WorkerLost(f"the work used more than {cpu_seconds:g} s of CPU time")
            if cancelled is not None and cancelled.is_set() and not interrupted:
                interrupted = True
                self.process.send_signal(signal.SIGUSR1)
                deadline = min(deadline, time.monotonic() + GRACE_SECONDS)
        if interrupted:
            raise WorkerLost("the request was cancelled")
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
    """Worker processes behind a bounded queue, fair between clients; :meth:`run` answers
    one request."""

    def __init__(self, limits: Limits) -> None:
        self.limits = limits
        self.admitted = 0  # running or waiting
        self.replaced = 0  # workers killed and started anew
        self.superseded = 0  # requests cancelled, waiting or running
        self._workers: list[Worker] = []
        self._idle: list[Worker] = []
        self._started = False
        # client -> its waiting tickets; the dict's order is the turn (round robin)
        self._waiting: dict[str, deque[Ticket]] = {}
        self._running: dict[str, int] = {}
        self._latest: dict[tuple[str, str], Ticket] = {}

    def start(self) -> None:
        """Start the workers (they import the library in the background)."""
        self._started = True
        for _ in range(self.limits.workers):
            worker = Worker.start(self.limits)
            self._workers.append(worker)
            self._idle.append(worker)

    def close(self) -> None:
        for worker in self._workers:
            worker.stop()
        self._workers.clear()

    async def run(self, request: Request | Ticket) -> tuple[int, bytes]:
        """The status and body answering ``request``; PoolBusy when the queue is full,
        Superseded when it was cancelled while waiting, WorkerLost when its worker had to be
        killed."""
        if not self._started:
            raise RuntimeError("the worker pool is not started")
        ticket = request if isinstance(request, Ticket) else Ticket(request)
        if self.admitted >= self.limits.workers + self.limits.queue:
            raise PoolBusy
        if ticket.kind:
            older = self._latest.get((ticket.client, ticket.kind))
            if older is not None:
                self.cancel(older)
            self._latest[(ticket.client, ticket.kind)] = ticket
        self.admitted += 1
        ticket.granted = asyncio.get_running_loop().create_future()
        self._waiting.setdefault(ticket.client, deque()).append(ticket)
        self._dispatch()
        try:
            worker = await ticket.granted
        except BaseException:
            self._leave(ticket)
            raise
        # shielded: a request abandoned by its client still gives its worker back, once done
        return await asyncio.shield(self._use(worker, ticket))

    def cancel(self, ticket: Ticket) -> None:
        """Cancel ``ticket``: out of the queue if it waits, its work interrupted if it runs."""
        if ticket.cancelled.is_set():
            return
        ticket.cancelled.set()
        self.superseded += 1
        self._unqueue(ticket)
        granted = ticket.granted
        if granted is not None and not granted.done():
            granted.set_exception(Superseded())

    def _leave(self, ticket: Ticket) -> None:
        """``ticket`` gave up waiting: out of the queue (a worker granted meanwhile goes back)."""
        self.admitted -= 1
        self._unqueue(ticket)
        granted = ticket.granted
        done = granted is not None and granted.done() and not granted.cancelled()
        if done and granted is not None and granted.exception() is None:
            self._release(ticket)
            self._idle.append(granted.result())
        self._forget(ticket)
        self._dispatch()

    def _unqueue(self, ticket: Ticket) -> None:
        """Take ``ticket`` out of its client's queue, if it is there."""
        queue = self._waiting.get(ticket.client)
        if queue is not None and ticket in queue:
            queue.remove(ticket)
            if not queue:
                del self._waiting[ticket.client]

    def _release(self, ticket: Ticket) -> None:
        holder = ticket.address or ticket.client
        self._running[holder] -= 1
        if not self._running[holder]:
            del self._running[holder]

    def _forget(self, ticket: Ticket) -> None:
        if self._latest.get((ticket.client, ticket.kind)) is ticket:
            del self._latest[(ticket.client, ticket.kind)]

    def _dispatch(self) -> None:
        """Give idle workers to waiting tickets: clients in turn, each under its share."""
        while self._idle:
            ticket = self._next_ticket()
            if ticket is None:
                return
            holder = ticket.address or ticket.client
            self._running[holder] = self._running.get(holder, 0) + 1
            assert ticket.granted is not None
            ticket.granted.set_result(self._idle.pop())

    def _next_ticket(self) -> Ticket | None:
        for client, waiting in list(self._waiting.items()):
            holder = waiting[0].address or client
            if self._running.get(holder, 0) >= self.limits.client_workers:
                continue
            queue = self._waiting.pop(client)
            ticket = queue.popleft()
            if queue:
                self._waiting[client] = queue  # back of the turn
            return ticket
        return None

    async def _use(self, worker: Worker, ticket: Ticket) -> tuple[int, bytes]:
        try:
            status, body = await asyncio.to_thread(
                worker.call,
                ticket.request,
                self.limits.wall_seconds,
                self.limits.cpu_seconds + GRACE_SECONDS,
                ticket.cancelled,
            )
            return int(status), bytes(body)
        except WorkerLost:
            worker = await asyncio.to_thread(self._replace, worker)
            raise
        finally:
            self._release(ticket)
            self._idle.append(worker)
            self.admitted -= 1
            self._forget(ticket)
            self._dispatch()

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
