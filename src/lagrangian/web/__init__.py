"""The playground: ``lagrangian serve`` (or :func:`serve`) serves a page where a model is
typed and its equations, analysis and motion are shown, and the JSON API behind it
(:mod:`lagrangian.web.app`).

Every request's work runs in worker processes bounded in CPU time and memory; request bodies
and the queue are bounded too (:class:`Limits`).
"""

from lagrangian.web.limits import Limits
from lagrangian.web.server import serve

__all__ = ["Limits", "create_app", "serve"]


def __getattr__(name: str) -> object:
    if name == "create_app":  # Starlette loads only when the application is built
        from lagrangian.web.app import create_app

        return create_app
    raise AttributeError(f"module 'lagrangian.web' has no attribute {name!r}")
