"""A load test on the loopback address: 16 users at once and one hostile request against a
real uvicorn server; every request is answered and the server stays up."""

from __future__ import annotations

import statistics
import time
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import pytest
from playground_setup import HOSTILE, TEST_LIMITS

from lagrangian import examples

USERS = 16
#: What each user does: load an example, derive it, simulate it (as the page does).
SESSION = ("simple_pendulum", "double_pendulum", "series_rlc", "mass_spring_damper")


def _user(base: str, number: int) -> list[tuple[int, float]]:
    import httpx

    name = SESSION[number % len(SESSION)]
    results = []
    with httpx.Client(base_url=base, timeout=120) as http:
        start = time.monotonic()
        model = http.get(f"/api/examples/{name}").json()["model"]
        for command, options in (("derive", {}), ("simulate", {"t_end": 5, "samples": 500})):
            answer = http.post(f"/api/{command}", json={"model": model, "options": options})
            results.append((answer.status_code, time.monotonic() - start))
    return results


def _hostile(base: str) -> tuple[int, str, float]:
    import httpx

    start = time.monotonic()
    answer = httpx.post(f"{base}/api/derive", json={"model": HOSTILE}, timeout=120)
    return answer.status_code, answer.json()["problems"][0]["message"], time.monotonic() - start


@pytest.mark.slow
def test_sixteen_users_and_a_hostile_request(live_server: str, capsys: Any) -> None:
    import httpx

    with ThreadPoolExecutor(USERS + 1) as pool:
        hostile = pool.submit(_hostile, live_server)
        users = [pool.submit(_user, live_server, number) for number in range(USERS)]
        sessions = [user.result() for user in users]
        status, message, hostile_seconds = hostile.result()
    statuses = [code for session in sessions for code, _ in session]
    assert statuses == [200] * (2 * USERS)
    assert status == 422 and "CPU time" in message
    health = httpx.get(f"{live_server}/api/health", timeout=30).json()
    assert health["workers"] == TEST_LIMITS.workers and health["admitted"] == 0
    model = examples.model_text("simple_pendulum")
    after = httpx.post(f"{live_server}/api/derive", json={"model": model}, timeout=60)
    assert after.status_code == 200  # the server is still up and answering
    finished = [session[-1][1] for session in sessions]
    with capsys.disabled():
        print(
            f"\nload: {USERS} users, each derive + simulate; session seconds median "
            f"{statistics.median(finished):.2f}, max {max(finished):.2f}; hostile refused "
            f"after {hostile_seconds:.2f} s"
        )
