"""A hostile request is stopped at its CPU-time limit while other requests are answered; the
queue in front of the workers is bounded; a worker's own limits turn into errors."""

from __future__ import annotations

import asyncio
import subprocess
import sys
import textwrap
import threading
import time
from typing import Any

from playground_setup import HOSTILE, TEST_LIMITS

from lagrangian import examples
from lagrangian.web import Limits
from lagrangian.web.pool import PoolBusy, WorkerLost, WorkerPool

SIMPLE = examples.model_text("simple_pendulum")


def test_a_hostile_request_is_refused_while_others_are_answered(client: Any) -> None:
    answers: dict[str, Any] = {}

    def hostile() -> None:
        start = time.monotonic()
        answers["hostile"] = client.post("/api/derive", json={"model": HOSTILE})
        answers["hostile_seconds"] = time.monotonic() - start

    thread = threading.Thread(target=hostile)
    thread.start()
    time.sleep(0.5)  # the hostile request holds one worker; the other serves the rest
    others = [client.post("/api/derive", json={"model": SIMPLE}) for _ in range(5)]
    thread.join()
    assert [answer.status_code for answer in others] == [200] * 5
    refused = answers["hostile"]
    assert refused.status_code == 422
    (problem,) = refused.json()["problems"]
    assert "CPU time" in problem["message"] and problem["fix"]
    # stopped by its CPU-time limit, well before the server's wall-clock backstop
    assert answers["hostile_seconds"] < TEST_LIMITS.wall_seconds
    health = client.get("/api/health").json()
    assert health["workers"] == TEST_LIMITS.workers
    assert client.post("/api/derive", json={"model": SIMPLE}).status_code == 200


def test_a_full_queue_is_refused_at_once() -> None:
    async def scenario() -> list[Any]:
        pool = WorkerPool(Limits(workers=1, queue=0, cpu_seconds=1.0))
        pool.start()
        await asyncio.to_thread(pool.wait_ready)
        try:
            busy = asyncio.ensure_future(pool.run(("derive", HOSTILE, "yaml", {})))
            await asyncio.sleep(0.2)
            second = await asyncio.gather(
                pool.run(("derive", SIMPLE, "yaml", {})), return_exceptions=True
            )
            (first,) = await asyncio.gather(busy, return_exceptions=True)
            after = await pool.run(("derive", SIMPLE, "yaml", {}))
            return [second[0], first, after[0], pool.replaced]
        finally:
            pool.close()

    refused, hostile, after_status, replaced = asyncio.run(scenario())
    assert isinstance(refused, PoolBusy)
    # stopped by the worker's own limit (an answer), or, stuck in C code, killed and replaced
    if isinstance(hostile, WorkerLost):
        assert "CPU time" in str(hostile) and replaced == 1
    else:
        assert hostile[0] == 422 and b"CPU time" in hostile[1] and replaced == 0
    assert after_status == 200


def test_the_api_answers_503_when_the_queue_is_full(client: Any) -> None:
    pool = client.app.state.pool
    admitted = pool.admitted
    pool.admitted = pool.limits.workers + pool.limits.queue  # as if every place were taken
    try:
        answer = client.post("/api/derive", json={"model": SIMPLE})
    finally:
        pool.admitted = admitted
    assert answer.status_code == 503 and answer.headers["retry-after"] == "2"
    assert answer.json()["problems"][0]["fix"] == "try again"


WORKER_LIMITS = textwrap.dedent(
    """
    import sys
    from lagrangian.web.limits import (
        TimeLimitExceeded, allow_cpu_seconds, limit_memory, watch_cpu_time,
    )
    watch_cpu_time()
    allow_cpu_seconds(1)
    try:
        while True:
            pass
    except TimeLimitExceeded:
        print("time")
    limit_memory(1 << 30)
    try:
        block = bytearray(2 << 30)
    except MemoryError:
        print("memory")
    """
)


def test_a_worker_turns_its_limits_into_errors() -> None:
    done = subprocess.run(
        [sys.executable, "-c", WORKER_LIMITS], capture_output=True, text=True, timeout=60
    )
    assert done.stdout.split() == ["time", "memory"], done.stderr


def test_an_expression_past_the_size_limit_is_refused_in_the_words_of_the_page(
    monkeypatch: Any,
) -> None:
    import json

    from lagrangian.web import runs

    monkeypatch.setattr("lagrangian.size_limits.DEFAULT_OPERATIONS", 30)
    monkeypatch.delenv("LAGRANGIAN_SIZE_LIMIT", raising=False)
    model = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: " + "cos(" * 8 + "x" + ")" * 8
    status, body = runs.run("derive", model, "yaml", {})
    message = json.dumps(json.loads(body))
    assert status == runs.UNPROCESSABLE, message
    assert "the forcing of the equation of x has 44 operations" in message
    assert "lagrangian command" in message and "size_limit=" not in message
