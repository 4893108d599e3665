"""Fixes in the words of the web API: a Python keyword is said as the option of the request
body (``max_steps=...`` → ``options.max_steps``, ``project_initial=True`` →
``options.project_initial = true``, ``t_span=...`` → ``options.t_end``).

>>> from lagrangian.errors import Setting
>>> WEB.setting(Setting("project_initial", True)), WEB.setting(Setting("initial", entry="x"))
('options.project_initial = true', 'options.initial.x')
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from lagrangian.errors import Problem, Setting, Wording
from lagrangian.web.options import OPTIONS

#: The keywords whose option of the request has another name.
NAMES: Mapping[str, str] = MappingProxyType({"t_span": "t_end", "parameters": "set"})


@dataclass(frozen=True)
class WebWording(Wording):
    """Options as the web API's ``options.NAME``, values as JSON writes them; only the
    ``keywords`` the API has are options (another field stays as it is)."""

    keywords: frozenset[str]

    def option(self, keyword: str) -> str:
        name = NAMES.get(keyword, keyword)
        return f"options.{name}" if name in self.keywords else keyword

    def setting(self, setting: Setting) -> str:
        name = self.option(setting.keyword)
        if setting.entry is not None:
            name = f"{name}.{setting.entry}"
        if setting.value is None:
            return name
        return f"{name} = {json.dumps(setting.value)}"


#: The options of the API's commands: what a fix may ask to set.
WEB = WebWording(frozenset(name for readers in OPTIONS.values() for name in readers))


def problem_document(problem: Problem) -> dict[str, Any]:
    """A problem as the API gives it: field, line, column, message, fix (in the API's words).

    >>> problem_document(Problem("max_steps", "too few", "pass {}"))["field"]
    'options.max_steps'
    """
    worded = problem.worded(WEB)
    return {
        "field": worded.field,
        "line": worded.line,
        "column": worded.column,
        "message": worded.message,
        "fix": str(worded.fix),
    }
