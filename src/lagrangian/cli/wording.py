"""Fixes in the words of the command line: a Python keyword is said as its flag
(``max_steps=...`` → ``--max-steps``, ``project_initial=True`` → ``--project-initial``,
``initial={'x': ...}`` → ``--initial x=VALUE``).

>>> from lagrangian.errors import Setting
>>> COMMAND_LINE.setting(Setting("max_steps")), COMMAND_LINE.setting(Setting("method", "RK4"))
('--max-steps', '--method RK4')
>>> COMMAND_LINE.setting(Setting("initial", entry="x")), COMMAND_LINE.option("t_span")
('--initial x=VALUE', '--t-end')

A command whose flags differ (``lagrangian sweep``) has its own wording, made the same way
(:data:`lagrangian.cli.sweep_command.SWEEP`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

from lagrangian.errors import Setting, Wording

#: The keywords whose flag is not the keyword with dashes.
FLAGS: Mapping[str, str] = MappingProxyType({"t_span": "--t-end", "parameters": "--set"})


@dataclass(frozen=True)
class CommandLineWording(Wording):
    """Options as the command's flags: a keyword's own flag (``--max-steps``) unless
    ``flags`` names another; only the ``keywords`` the command has are flags (another
    field, a constraint's name, stays as it is).  An entry's value the user chooses is
    ``VALUE`` unless ``placeholders`` names its form (``--vary NAME=START:STOP:COUNT``)."""

    keywords: frozenset[str]
    flags: Mapping[str, str] = field(default_factory=lambda: FLAGS, hash=False)
    placeholders: Mapping[str, str] = field(
        default_factory=lambda: MappingProxyType({}), hash=False
    )

    def option(self, keyword: str) -> str:
        if keyword in self.flags:
            return self.flags[keyword]
        if keyword in self.keywords:
            return "--" + keyword.replace("_", "-")
        return keyword

    def setting(self, setting: Setting) -> str:
        flag, value = self.option(setting.keyword), setting.value
        if setting.entry is not None:
            chosen = self.placeholders.get(setting.keyword, "VALUE")
            return f"{flag} {setting.entry}={chosen if value is None else value}"
        if value is None or value is True:
            return flag
        return f"{flag} {value}"


#: The options of the commands that take a model: what a fix may ask to set.
COMMAND_LINE = CommandLineWording(
    frozenset(
        {
            "set",
            "initial",
            "about",
            "project",
            "input",
            "method",
            "rtol",
            "atol",
            "samples",
            "dt",
            "max_steps",
            "max_wall_time",
            "project_initial",
            "t_span",
            "t_end",
            "parameters",
        }
    )
)
