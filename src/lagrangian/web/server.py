"""``lagrangian serve`` and ``lagrangian.web.serve()``: the playground on uvicorn, on the
loopback address unless told otherwise, the browser opened on the page once it answers."""

from __future__ import annotations

import contextlib
import ipaddress
import sys
import threading
import webbrowser
from collections.abc import Sequence

from lagrangian.web.limits import Limits

LOOPBACK = "127.0.0.1"
#: The names this machine answers to on its loopback addresses, as a Host header gives them.
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "[::1]")


def is_loopback(host: str) -> bool:
    """Whether ``host`` is reachable from this machine only.

    >>> is_loopback("127.0.0.1"), is_loopback("localhost"), is_loopback("0.0.0.0")
    (True, True, False)
    """
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def allowed_hosts(host: str, extra: Sequence[str] = ()) -> tuple[str, ...] | None:
    """The Host-header names the server answers to: the loopback names (and ``extra``) when
    it listens on this machine only; ``extra`` alone when given for a shared server; any
    (None) for a shared server without them.

    >>> allowed_hosts("127.0.0.1")
    ('localhost', '127.0.0.1', '[::1]')
    >>> allowed_hosts("0.0.0.0") is None, allowed_hosts("0.0.0.0", ["lab.example.org"])
    (True, ('lab.example.org',))
    """
    names = tuple(name.lower() for name in extra)
    if is_loopback(host):
        return LOOPBACK_NAMES + names
    return names or None


def page_address(host: str, port: int) -> str:
    """The page's URL (an IPv6 host in brackets).

    >>> page_address("::1", 8000)
    'http://[::1]:8000/'
    """
    shown = f"[{host}]" if ":" in host and not host.startswith("[") else host
    return f"http://{shown}:{port}/"


def serve(
    host: str = LOOPBACK,
    port: int = 8000,
    *,
    open_browser: bool = True,
    limits: Limits | None = None,
    hosts: Sequence[str] = (),
) -> None:
    """Serve the playground at ``http://host:port/`` until Ctrl-C.

    The server binds to the loopback address by default: only this machine reaches it.  Give
    another ``host`` (``0.0.0.0``) to share it; every request still runs in a worker process
    with the CPU-time, memory, size and queue bounds of ``limits``.  Requests must name the
    server by one of its loopback names, or by one of ``hosts`` (:func:`allowed_hosts`).
    """
    import uvicorn

    from lagrangian.web.app import create_app

    address = page_address(host, port)
    if not is_loopback(host):
        sys.stderr.write(
            f"lagrangian: serving on {host}, reachable from other machines; each request is "
            "bounded in CPU time, memory and size\n"
        )
    sys.stderr.write(f"lagrangian: the playground is at {address} (Ctrl-C to stop)\n")
    config = uvicorn.Config(
        create_app(limits, allowed_hosts(host, hosts)), host=host, port=port, log_level="warning"
    )
    server = uvicorn.Server(config)
    if open_browser:
        threading.Thread(target=_open_when_started, args=(server, address), daemon=True).start()
    with contextlib.suppress(KeyboardInterrupt):  # uvicorn stops cleanly, then re-raises it
        server.run()


def _open_when_started(server: object, address: str) -> None:
    """Open the page once the server answers (its workers are ready by then)."""
    import time

    for _ in range(600):
        if getattr(server, "started", False):
            webbrowser.open(address)
            return
        time.sleep(0.1)
