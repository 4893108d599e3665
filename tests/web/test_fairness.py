"""Fair to every user: requests are queued per client, one client's heavy requests never hold
every worker, and a request its client replaced or abandoned frees its worker."""

from __future__ import annotations

import asyncio
import statistics
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import pytest
from playground_setup import HOSTILE, served

from lagrangian import examples
from lagrangian.web import Limits
from lagrangian.web.pool import Ticket, WorkerLost, WorkerPool

SIMPLE = examples.model_text("simple_pendulum")


def test_a_newer_request_of_the_same_kind_frees_the_worker_of_the_older() -> None:
    async def scenario() -> tuple[Any, Any, int, int]:
        pool = WorkerPool(Limits(workers=1, queue=4, cpu_seconds=60.0))
        pool.start()
        await asyncio.to_thread(pool.wait_ready)
        try:
            older = Ticket(("derive", HOSTILE, "yaml", {}), "page", "derive")
            running = asyncio.ensure_future(pool.run(older))
            await asyncio.sleep(1.0)  # the heavy derivation is being worked on
            newer = Ticket(("derive", SIMPLE, "yaml", {}), "page", "derive")
            answer = await pool.run(newer)
            (first,) = await asyncio.gather(running, return_exceptions=True)
            return first, answer, pool.superseded, pool.replaced
        finally:
            pool.close()

    first, answer, superseded, replaced = asyncio.run(scenario())
    assert superseded == 1
    # interrupted in Python (409 and the same worker), or, stuck in C, killed and replaced
    if isinstance(first, WorkerLost):
        assert "cancelled" in str(first) and replaced == 1
    else:
        assert first[0] == 409 and b"cancelled by a newer one" in first[1] and replaced == 0
    assert answer[0] == 200


def test_a_waiting_request_replaced_by_a_newer_one_never_runs() -> None:
    from lagrangian.web.pool import Superseded

    async def scenario() -> list[Any]:
        pool = WorkerPool(Limits(workers=1, queue=4, cpu_seconds=2.0))
        pool.start()
        await asyncio.to_thread(pool.wait_ready)
        try:
            other = asyncio.ensure_future(pool.run(Ticket(("derive", HOSTILE, "yaml", {}), "a")))
            await asyncio.sleep(0.2)
            waiting = asyncio.ensure_future(
                pool.run(Ticket(("derive", HOSTILE, "yaml", {}), "b", "derive"))
            )
            await asyncio.sleep(0.2)
            newer = pool.run(Ticket(("derive", SIMPLE, "yaml", {}), "b", "derive"))
            return list(await asyncio.gather(waiting, newer, other, return_exceptions=True))
        finally:
            pool.close()

    replaced, newer, _ = asyncio.run(scenario())
    assert isinstance(replaced, Superseded)
    assert newer[0] == 200


def test_a_client_naming_itself_many_times_still_leaves_a_worker_to_the_others() -> None:
    """Two heavy requests from one address under two page names (a name is the client's own
    word) hold one worker, not both: another address's light request is answered while both
    are still unanswered."""

    async def scenario() -> tuple[Any, int]:
        pool = WorkerPool(Limits(workers=2, queue=8, cpu_seconds=4.0))
        pool.start()
        await asyncio.to_thread(pool.wait_ready)
        try:
            heavy = [
                asyncio.ensure_future(
                    pool.run(
                        Ticket(
                            ("derive", HOSTILE, "yaml", {}),
                            f"10.0.0.1 page-{n}",
                            "derive",
                            address="10.0.0.1",
                        )
                    )
                )
                for n in range(2)
            ]
            await asyncio.sleep(0.5)  # both heavy requests are in first
            light = Ticket(("derive", SIMPLE, "yaml", {}), "10.0.0.2 page", "derive", "10.0.0.2")
            answer = await pool.run(light)
            unanswered = sum(not request.done() for request in heavy)
            await asyncio.gather(*heavy, return_exceptions=True)
            return answer, unanswered
        finally:
            pool.close()

    answer, unanswered = asyncio.run(scenario())
    assert answer[0] == 200
    assert unanswered == 2  # one heavy request running, the other waiting behind it


FAIR = Limits(workers=2, queue=32, cpu_seconds=8.0)


@pytest.fixture(scope="module")
def fair_server() -> Iterator[str]:
    for module in ("starlette", "uvicorn", "httpx"):
        pytest.importorskip(module)
    from lagrangian.web import create_app

    with served(create_app(FAIR), FAIR) as port:
        yield f"http://127.0.0.1:{port}"


def _post(
    base: str, client: str, command: str, model: str, address: str = "127.0.0.1"
) -> tuple[int, float, float]:
    """POST from the loopback ``address`` (each user of the load test its own machine)."""
    import httpx

    start = time.monotonic()
    with httpx.Client(transport=httpx.HTTPTransport(local_address=address)) as http:
        answer = http.post(
            f"{base}/api/{command}",
            json={"model": model},
            headers={"X-Lagrangian-Client": client},
            timeout=120,
        )
    return answer.status_code, start, time.monotonic()


@pytest.mark.slow
def test_two_heavy_requests_of_one_client_leave_a_worker_to_the_others(
    fair_server: str, capsys: Any
) -> None:
    with ThreadPoolExecutor(10) as threads:
        heavy = [
            threads.submit(_post, fair_server, "heavy", command, HOSTILE)
            for command in ("derive", "analyze")  # two kinds: neither replaces the other
        ]
        time.sleep(0.5)  # both heavy requests are in before the light ones
        light = [
            threads.submit(_post, fair_server, f"light-{n}", "derive", SIMPLE, f"127.0.0.{n + 2}")
            for n in range(8)
        ]
        light_answers = [future.result() for future in light]
        heavy_answers = [future.result() for future in heavy]
    assert [status for status, _, _ in light_answers] == [200] * 8
    assert [status for status, _, _ in heavy_answers] == [422, 422]  # cut at the CPU bound
    waits = [end - start for _, start, end in light_answers]
    first_heavy_done = min(end for _, _, end in heavy_answers)
    # every light request is answered while the heavy ones still run, not after them
    assert max(end for _, _, end in light_answers) < first_heavy_done
    with capsys.disabled():
        print(
            f"\nfairness: 8 light requests beside 2 heavy ones of one client: answered in "
            f"median {statistics.median(waits):.2f} s, max {max(waits):.2f} s; the heavy ones "
            f"cut after {first_heavy_done - heavy_answers[0][1]:.1f} s"
        )
