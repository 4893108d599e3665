"""Fixtures of the playground's tests: the application under Starlette's TestClient, and a
real uvicorn server on the loopback address in a thread (for the load and browser tests)."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from typing import Any

import pytest
from playground_setup import TEST_LIMITS, served


def _app(limits: Any = TEST_LIMITS) -> Any:
    """The application with the tests' limits (skip without the web extra)."""
    for module in ("starlette", "uvicorn", "httpx"):
        pytest.importorskip(module, reason=f"the playground's tests need {module}: .[test]")
    from lagrangian.web import create_app

    return create_app(limits)


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
    """The playground served by uvicorn on 127.0.0.1 in a thread, with the tests' small
    limits (a hostile request is stopped within seconds); its base URL."""
    with served(_app(), TEST_LIMITS) as port:
        yield f"http://127.0.0.1:{port}"


@pytest.fixture(scope="session")
def page_server() -> Iterator[str]:
    """The playground as ``lagrangian serve`` runs it (its default limits, two workers), for
    the browser tests of what a user sees: a run bounded by the tests' 4 s, measured on the
    wall clock of a loaded machine, stopped short (the servo's two panels, once)."""
    from lagrangian.web import Limits

    with served(_app(Limits(workers=2)), Limits(workers=2)) as port:
        yield f"http://127.0.0.1:{port}"
