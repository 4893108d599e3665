"""Fixtures of the playground's tests: the application under Starlette's TestClient, and a
real uvicorn server on the loopback address in a thread (for the load and browser tests)."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from typing import Any

import pytest
from playground_setup import TEST_LIMITS, served


def _app() -> Any:
    """The application with the tests' limits (skip without the web extra)."""
    for module in ("starlette", "uvicorn", "httpx"):
        pytest.importorskip(module, reason=f"the playground's tests need {module}: .[test]")
    from lagrangian.web import create_app

    return create_app(TEST_LIMITS)


def testclient_class() -> Any:
    """Starlette's TestClient (Starlette 1.x warns when it runs on httpx, not httpx2, and
    either works for these tests)."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*httpx2.*")
        from starlette.testclient import TestClient
    return TestClient


@pytest.fixture(scope="session")
def client() -> Iterator[Any]:
    with testclient_class()(_app()) as test_client:
        yield test_client


@pytest.fixture(scope="session")
def live_server() -> Iterator[str]:
    """The playground served by uvicorn on 127.0.0.1 in a thread; its base URL."""
    with served(_app(), TEST_LIMITS) as port:
        yield f"http://127.0.0.1:{port}"
