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
#: The addresses meaning "every interface": no Host header names them.
EVERY_ADDRESS = ("0.0.0.0", "::", "[::]")


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
    """The Host-header names the server answers to: the address it listens on (the one it
    prints), the loopback names when it listens on this machine only, and ``extra``; for a
    shared server on every address (``0.0.0.0``) without ``extra``, any (None).

    >>> allowed_hosts("127.0.0.1")
    ('localhost', '127.0.0.1', '[::1]')
    >>> allowed_hosts("127.0.0.2")
    ('localhost', '127.0.0.1', '[::1]', '127.0.0.2')
    >>> allowed_hosts("0.0.0.0") is None, allowed_hosts("0.0.0.0", ["lab.example.org"])
    (True, ('lab.example.org',))
    >>> allowed_hosts("192.0.2.7")
    ('192.0.2.7',)
    """
    names = tuple(name.lower() for name in extra)
    listening = () if host in EVERY_ADDRESS else (_host_name(host),)
    if is_loopback(host):
        return tuple(dict.fromkeys(LOOPBACK_NAMES + listening + names))
    if not names and not listening:
        return None
    return tuple(dict.fromkeys(listening + names))


def _host_name(host: str) -> str:
    """``host`` as a Host header names it (an IPv6 address in brackets)."""
    host = host.lower()
    return f"[{host}]" if ":" in host and not host.startswith("[") else host


def page_address(host: str, port: int) -> str:
    """The page's URL (an IPv6 host in brackets).

    >>> page_address("::1", 8000)
    'http://[::1]:8000/'
    """
    return f"http://{_host_name(host)}:{port}/"


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
    from lagrangian.web.connections import server_config

    chosen = limits or Limits()
    address = page_address(host, port)
    if not is_loopback(host):
        sys.stderr.write(
            f"lagrangian: serving on {host}, reachable from other machines; each request is "
            "bounded in CPU time, memory and size\n"
        )
    app = create_app(chosen, allowed_hosts(host, hosts))
    server = uvicorn.Server(server_config(app, host, port, chosen))
    announcer = threading.Thread(
        target=_announce_when_started, args=(server, address, open_browser), daemon=True
    )
    announcer.start()
    with contextlib.suppress(KeyboardInterrupt):  # uvicorn stops cleanly, then re-raises it
        server.run()


def _announce_when_started(server: object, address: str, open_browser: bool) -> None:
    """Say where the page is once the server answers (its workers are ready by then), and
    open it in a browser if asked."""
    import time

    while not getattr(server, "started", False):
        if getattr(server, "should_exit", False):
            return
        time.sleep(0.05)
    sys.stderr.write(f"lagrangian: the playground is at {address} (Ctrl-C to stop)\n")
    sys.stderr.flush()
    if open_browser:
        webbrowser.open(address)
