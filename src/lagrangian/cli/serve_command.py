"""``lagrangian serve``: the playground page and its JSON API on this machine.

The parser part imports neither Starlette nor SymPy (``lagrangian --help`` stays fast); the
server (:func:`lagrangian.web.serve`) loads when the command runs.
"""

from __future__ import annotations

import argparse
import importlib.util
from typing import Any

from lagrangian.errors import ArgumentError, LagrangianError

SUMMARY = "the playground: a page to type a model, see its equations and watch it move"
EXAMPLE = "lagrangian serve --port 8000"
#: What the server needs beyond the library, by module name.
NEEDS = ("starlette", "uvicorn")


def add_serve_parser(sub: Any) -> argparse.ArgumentParser:
    """The ``serve`` subcommand and its flags."""
    command: argparse.ArgumentParser = sub.add_parser(
        "serve", help=SUMMARY, description=SUMMARY, epilog=f"example: {EXAMPLE}"
    )
    command.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default 127.0.0.1: this machine only; 0.0.0.0 shares it)",
    )
    command.add_argument("--port", type=int, default=8000, help="port (default 8000)")
    command.add_argument(
        "--allowed-host",
        action="append",
        default=[],
        metavar="NAME",
        help="a name the page may be reached by besides localhost (repeatable; on a shared "
        "server, only these names are answered)",
    )
    command.add_argument(
        "--no-browser", action="store_true", help="do not open the page in a browser"
    )
    command.add_argument(
        "--workers", type=int, default=2, help="processes doing the work (default 2)"
    )
    command.add_argument(
        "--cpu-seconds",
        type=float,
        default=20.0,
        metavar="SECONDS",
        help="CPU time one request may use (default 20)",
    )
    command.add_argument(
        "--debug", action="store_true", default=argparse.SUPPRESS, help="show tracebacks"
    )
    return command


def run_serve(args: argparse.Namespace) -> str:
    """Serve until Ctrl-C; the text printed after."""
    missing = [name for name in NEEDS if importlib.util.find_spec(name) is None]
    if missing:
        raise LagrangianError(
            f"lagrangian serve needs {' and '.join(missing)}, which come with lagrangian: "
            "reinstall it (pip install lagrangian)"
        )
    if args.workers < 1 or args.cpu_seconds <= 0:
        raise ArgumentError("--workers is at least 1 and --cpu-seconds more than 0")
    from lagrangian.web import Limits, serve

    limits = Limits(workers=args.workers, cpu_seconds=args.cpu_seconds)
    serve(
        args.host,
        args.port,
        open_browser=not args.no_browser,
        limits=limits,
        hosts=args.allowed_host,
    )
    return "the playground stopped"
