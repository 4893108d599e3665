"""The playground's ASGI application (Starlette): the page at ``/``, its assets under
``/static/``, and the JSON API that mirrors the command line (shared/DESIGN.md):

- ``POST /api/derive``, ``/api/analyze``, ``/api/simulate`` with ``{"model": TEXT, "format":
  "yaml|toml|json", "options": {...}}``: the command's JSON; a bad model or option is 422
  with ``{"problems": [{"field", "line", "column", "message", "fix"}]}``, a body over
  ``Limits.max_body_bytes`` 413, a full queue 503, a body not sent as JSON 415, a body
  not sent within ``Limits.body_seconds`` 408, a request from a page of another site 403;
- ``POST /api/export`` with ``{"options": {"language": "numpy|c|matlab|julia"}}``: the
  generated code as ``{"language", "files": {NAME: TEXT}}``;
- ``GET /api/examples``: the built-in examples (the Whipple bicycle among them), with a line
  each; those built in Python to a size (the gas of hard disks) with ``size``: what it
  counts, its default and the largest the page offers;
- ``GET /api/examples/NAME[?size=N]``: ``{"name", "description", "format", "model"}``, a
  scalable example's model written at its default size or N;
- ``GET /api/health``: the workers running and the requests admitted.

The work runs in worker processes (:mod:`.pool`); the server itself only reads, checks and
forwards, so one slow request never stalls another.  Requests are queued per client: the
page names itself in the ``X-Lagrangian-Client`` header (else the client's address counts),
and its newer request of a kind (derive, analyze, ...) cancels the older one, as does a
client that goes away before its answer (409 for a request so cancelled).  The workers held
at once are bounded per address, which the connection gives and a page cannot choose: a page
that names itself many times still leaves a worker to the others.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
from collections.abc import AsyncIterator, Sequence
from contextlib import asynccontextmanager
from functools import cache
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

from starlette.applications import Starlette
from starlette.datastructures import MutableHeaders
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from lagrangian.errors import LagrangianError, Problem
from lagrangian.web.limits import Limits
from lagrangian.web.options import OPTIONS, read_request
from lagrangian.web.pool import PoolBusy, Superseded, Ticket, WorkerLost, WorkerPool
from lagrangian.web.wording import problem_document

STATIC = Path(__file__).resolve().parent / "static"
#: The drawing of a scene: one file, which the HTML animations inline and the page loads as
#: ``/static/scene_player.js`` (found by its path: the server never imports the render layer).
SCENE_DRAWING = Path(__file__).resolve().parents[1] / "render" / "scene_player.js"
#: The page may load its own scripts, styles and fonts only (KaTeX sets inline styles).
HEADERS = {
    "Content-Security-Policy": (
        "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
        "font-src 'self'; object-src 'none'; base-uri 'none'; frame-ancestors 'none'"
    ),
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
}


def problems_response(status: int, problems: list[Problem], summary: str = "") -> JSONResponse:
    """An error answer: ``{"error": summary, "problems": [...]}``."""
    listed = [problem_document(p) for p in problems]
    return JSONResponse({"error": summary or problems[0].message, "problems": listed}, status)


#: The header naming the client (one page): its requests are queued and superseded together.
CLIENT_HEADER = "x-lagrangian-client"


class BodyTooLarge(Exception):
    """The request's body is over the limit."""


def client_of(request: Request) -> str:
    """Who sent ``request``: its address, and the page's own name for itself if it gives one
    (several pages on one machine share an address)."""
    address = request.client.host if request.client else ""
    return f"{address} {request.headers.get(CLIENT_HEADER, '')[:64]}".strip()


def origin_allowed(request: Request) -> bool:
    """Whether a browser sent ``request`` from the playground's own page: its ``Origin`` (a
    browser always sends one with a POST) names this server, as the Host header does, or one
    of the allowed hosts; a request without ``Origin`` is not a browser's (curl, a script)."""
    origin = request.headers.get("origin")
    if origin is None:
        return True
    parts = urlsplit(origin)
    if parts.scheme not in ("http", "https") or not parts.netloc:
        return False  # "null": a sandboxed frame, a file
    if parts.netloc.lower() == request.headers.get("host", "").lower():
        return True
    allowed = request.app.state.allowed_hosts
    return allowed is not None and (parts.hostname or "") in allowed


async def until_disconnected(request: Request) -> None:
    """Return when the client closes its connection (after the body has been read)."""
    while (await request.receive())["type"] != "http.disconnect":
        pass


async def read_body(request: Request, limit: int) -> bytes:
    """The body, refused (BodyTooLarge) as soon as it passes ``limit`` bytes."""
    declared = request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > limit:
        raise BodyTooLarge
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise BodyTooLarge
        chunks.append(chunk)
    return b"".join(chunks)


async def command(request: Request) -> Response:
    """``POST /api/{derive,analyze,simulate}``."""
    name = request.path_params["command"]
    limits: Limits = request.app.state.limits
    if name not in OPTIONS:
        fix = "POST to /api/derive, /api/analyze, /api/simulate or /api/export"
        return problems_response(404, [Problem("path", f"no command {name!r}", fix)])
    # the media type itself, not a substring: "text/plain;charset=json" is a cross-site
    # "simple" request a browser sends without asking, application/json never is
    media = request.headers.get("content-type", "").split(";", 1)[0].strip().lower()
    if media != "application/json":
        fix = "send the body as JSON with Content-Type: application/json"
        return problems_response(415, [Problem("body", "the body is not JSON", fix)])
    if not origin_allowed(request):
        fix = "use the playground's own page, or call the API without a browser"
        return problems_response(403, [Problem("origin", "a page of another site sent it", fix)])
    try:
        raw = await asyncio.wait_for(read_body(request, limits.max_body_bytes), limits.body_seconds)
    except TimeoutError:
        fix = "send the whole body at once"
        message = f"the body did not arrive within {limits.body_seconds:g} s"
        return problems_response(408, [Problem("body", message, fix)])
    except BodyTooLarge:
        size = f"{limits.max_body_bytes // 1000} kB"
        fix = "send a smaller model; large systems run with the lagrangian command"
        return problems_response(413, [Problem("body", f"the request is over {size}", fix)])
    try:
        body = json.loads(raw)
    except (ValueError, RecursionError) as error:
        fix = '{"model": "coordinates: [x] ...", "format": "yaml", "options": {}}'
        return problems_response(400, [Problem("body", f"not valid JSON: {error}", fix)])
    try:
        checked = read_request(name, body, limits.max_samples)
    except LagrangianError as error:
        return problems_response(422, list(error.problems), str(error).splitlines()[0])
    pool: WorkerPool = request.app.state.pool
    page_named = CLIENT_HEADER in request.headers  # only a page's requests supersede
    ticket = Ticket(
        (name, checked.model, checked.format, checked.options),
        client_of(request),
        name if page_named else "",
        address=request.client.host if request.client else "",
    )
    try:
        status, answer = await answer_unless_gone(request, pool, ticket)
    except Superseded:
        problem = Problem("request", "a newer request replaced this one", "nothing to do")
        return problems_response(409, [problem])
    except PoolBusy:
        problem = Problem("server", "every worker is busy and the queue is full", "try again")
        response = problems_response(503, [problem])
        response.headers["Retry-After"] = "2"
        return response
    except WorkerLost as lost:
        fix = "make the model smaller or simpler, or run it with the lagrangian command"
        problem = Problem("model", f"{lost} and was stopped", fix)
        return problems_response(422, [problem])
    return Response(answer, status, media_type="application/json")


async def answer_unless_gone(
    request: Request, pool: WorkerPool, ticket: Ticket
) -> tuple[int, bytes]:
    """The pool's answer to ``ticket``, cancelled (its worker freed) if the client goes away
    before it."""
    work = asyncio.ensure_future(pool.run(ticket))
    gone = asyncio.ensure_future(until_disconnected(request))
    try:
        await asyncio.wait({work, gone}, return_when=asyncio.FIRST_COMPLETED)
        if not work.done():
            pool.cancel(ticket)
        return await work
    finally:
        gone.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await gone


#: The largest size the page offers of each example built to a size: its derivation,
#: analysis and run each well inside the default CPU bound of a request (20 s).  Measured
#: (CPU s, one core): the gas of 25 disks (400 contacts) derives in 7.4, analyzes in 3.8 and
#: simulates in 1.9; the pendulum of 4 links analyzes in 4.1 (6 links: 11 s and 23 MB of
#: answer).
PAGE_LARGEST = {"hard_disk_gas": 25, "n_link_pendulum": 4}


@cache
def example_list() -> list[dict[str, Any]]:
    """Every example, the field's benchmarks (large, last) among them: name, one line,
    whether it is a benchmark, and for one built to a size (``size``) what the size counts,
    its default and the largest the page offers."""
    from lagrangian import examples

    listed = []
    for name in [*examples.names(), *examples.BENCHMARKS]:
        entry: dict[str, Any] = {
            "name": name,
            "description": examples.describe(name),
            "benchmark": name in examples.BENCHMARKS,
        }
        if name in examples.SIZES:
            size = examples.SIZES[name]
            largest = min(size.largest, PAGE_LARGEST.get(name, size.default))
            entry["size"] = {"counts": size.counts, "default": size.default, "largest": largest}
        listed.append(entry)
    return listed


def requested_size(request: Request, entry: dict[str, Any]) -> int | Problem | None:
    """The ``size`` asked in the query (None when not asked), or the problem with it."""
    asked = request.query_params.get("size")
    if asked is None:
        return None
    bounds = entry.get("size")
    if bounds is None:
        fix = "leave out ?size=: this example is a model file of its own size"
        return Problem("size", f"the example {entry['name']!r} takes no size", fix)
    if not asked.isdigit() or not 1 <= int(asked) <= bounds["largest"]:
        fix = f"give a whole number of {bounds['counts']} from 1 to {bounds['largest']}"
        if asked.isdigit() and int(asked) > bounds["largest"]:
            fix += f" (more with the lagrangian command: {entry['name']}:{asked})"
        return Problem("size", f"{asked!r} {bounds['counts']}", fix)
    return int(asked)


async def list_examples(request: Request) -> Response:
    return JSONResponse({"examples": await asyncio.to_thread(example_list)})


async def example(request: Request) -> Response:
    """``GET /api/examples/NAME[?size=N]``: the model file of one example."""
    name = request.path_params["name"]
    known = {entry["name"]: entry for entry in await asyncio.to_thread(example_list)}
    if name not in known:
        fix = "GET /api/examples lists them"
        return problems_response(404, [Problem("name", f"no example {name!r}", fix)])
    size = requested_size(request, known[name])
    if isinstance(size, Problem):
        return problems_response(422, [size])
    from lagrangian import examples

    text = await asyncio.to_thread(examples.model_text, name, size)
    return JSONResponse({**known[name], "format": "yaml", "model": text})


async def health(request: Request) -> Response:
    pool: WorkerPool = request.app.state.pool
    return JSONResponse(
        {
            "workers": pool.alive(),
            "admitted": pool.admitted,
            "replaced": pool.replaced,
            "superseded": pool.superseded,
        }
    )


async def page(request: Request) -> Response:
    return FileResponse(STATIC / "index.html", media_type="text/html")


async def scene_drawing(request: Request) -> Response:
    return FileResponse(SCENE_DRAWING, media_type="text/javascript")


def create_app(
    limits: Limits | None = None, allowed_hosts: Sequence[str] | None = None
) -> Starlette:
    """The playground application; its worker processes start with the app (lifespan) and
    are stopped with it.

    ``allowed_hosts`` are the names the page may be asked for in the Host header (any when
    None): a page served on this machine only answers to its loopback names, so a web page
    elsewhere cannot reach it through a name of its own that resolves here (DNS rebinding).
    """
    chosen = limits or Limits()

    @asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        pool = WorkerPool(chosen)
        pool.start()
        app.state.pool = pool
        await asyncio.to_thread(pool.wait_ready)
        try:
            yield
        finally:
            await asyncio.to_thread(pool.close)

    app = Starlette(
        routes=[
            Route("/", page),
            Route("/api/examples", list_examples),
            Route("/api/examples/{name}", example),
            Route("/api/health", health),
            Route("/api/{command}", command, methods=["POST"]),
            Route("/static/scene_player.js", scene_drawing),
            Mount("/static", StaticFiles(directory=STATIC), name="static"),
        ],
        lifespan=lifespan,
    )
    app.state.limits = chosen
    app.state.allowed_hosts = None if allowed_hosts is None else tuple(allowed_hosts)
    app.add_middleware(SecurityHeaders)
    if allowed_hosts is not None:
        app.add_middleware(TrustedHostMiddleware, allowed_hosts=list(allowed_hosts))
    return app


class SecurityHeaders:
    """ASGI middleware adding :data:`HEADERS` to every HTTP answer."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                for key, value in HEADERS.items():
                    headers[key] = value
            await send(message)

        await self.app(scope, receive, send_with_headers)
