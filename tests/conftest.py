"""Fixtures every test folder shares: headless Chromium (Debian's, from the system's packages)
driven by Playwright, for the browser tests of the playground and of the HTML animations."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from typing import Any

import pytest

#: The system's Chromium (apt-get install chromium), or None: the browser tests then skip.
CHROMIUM = next(
    (path for name in ("chromium", "chromium-browser") if (path := shutil.which(name))), None
)


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    """One headless Chromium for the whole run (skip without Playwright or Chromium)."""
    playwright_api = pytest.importorskip(
        "playwright.sync_api", reason="Playwright for Python is not installed"
    )
    if CHROMIUM is None:
        pytest.skip("Chromium is not installed (apt-get install chromium)")
    with playwright_api.sync_playwright() as playwright:
        launched = playwright.chromium.launch(
            executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"]
        )
        yield launched
        launched.close()
