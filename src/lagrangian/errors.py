"""The one error root of lagrangian, and the exit code each error means.

Every error the library raises on purpose is a :class:`LagrangianError`; each subclass also
inherits the built-in exception a Python user would expect (``ModelError`` is a ``ValueError``),
so ``except ValueError`` keeps working.  Errors about user input carry every problem found at
once (``problems``), each naming the field and the fix.

The class decides what the error means to a shell (``exit_code``, as click's
``ClickException.exit_code``): bad input — every error that is also a ``ValueError``, and a
wrong argument (:class:`ArgumentError`) — is :data:`BAD_INPUT` (2) wherever it is found;
anything else, a computation that failed, is :data:`FAILURE` (1).  The command line prints
the message and returns ``error.exit_code``.

>>> ModelError("unknown name 'kk'").exit_code, SimulationError("step size too small").exit_code
(2, 1)
>>> isinstance(SimulationInputError("no end time"), (SimulationError, ValueError))
True
"""

from __future__ import annotations

import string
from collections.abc import Iterable
from dataclasses import dataclass, replace
from typing import ClassVar, TypeVar

#: Exit code of a command that failed: the input was fine, the computation was not.
FAILURE = 1
#: Exit code of a command given bad input: a model, a file, an option or a value to fix.
BAD_INPUT = 2


@dataclass(frozen=True)
class Setting:
    """An option a fix suggests, as click's ``BadParameter`` keeps its parameter: the
    ``keyword`` as Python spells it, the ``value`` suggested (None: one the user chooses) and,
    for a keyword that maps names to values, the ``entry`` (``initial={'x': ...}``).  Each
    interface words it its own way (:class:`Wording`): ``max_steps=...`` in Python,
    ``--max-steps`` on the command line, ``options.max_steps`` in the web API.

    >>> str(Setting("method", "DOP853")), str(Setting("initial", entry="x"))
    ("method='DOP853'", "initial={'x': ...}")
    """

    keyword: str
    value: str | float | bool | None = None
    entry: str | None = None

    def __str__(self) -> str:
        return Wording().setting(self)


@dataclass(frozen=True)
class Fix:
    """How to fix a problem when the fix sets options: ``text`` with a ``{}`` for each of
    the ``settings`` (``{0.name}``: the option alone, without a value), filled in the words
    of the interface the user is in.

    >>> fix = Fix("use a larger {0.name}, or pass {1}", (Setting("dt"), Setting("max_steps")))
    >>> str(fix)
    'use a larger dt, or pass max_steps=...'
    """

    text: str
    settings: tuple[Setting, ...] = ()

    def worded(self, wording: Wording) -> str:
        """The fix with each setting as ``wording`` names it."""
        return self.text.format(
            *(_Worded(wording.option(s.keyword), wording.setting(s)) for s in self.settings)
        )

    def __str__(self) -> str:
        return self.worded(Wording())

    def __add__(self, other: str | Fix) -> Fix:
        """This fix followed by plain text or another fix, as strings are added: a sentence
        that says a fix keeps its settings for each interface to word.

        >>> str("the step budget is used up — " + Fix("pass {}", (Setting("max_steps"),)))
        'the step budget is used up — pass max_steps=...'
        """
        other = other if isinstance(other, Fix) else Fix(_literal(other))
        text = _numbered(self.text, 0) + _numbered(other.text, len(self.settings))
        return Fix(text, self.settings + other.settings)

    def __radd__(self, other: str) -> Fix:
        return Fix(_literal(other)) + self


def _literal(text: str) -> str:
    """``text`` as a fix's text that says it as it is (its braces are not placeholders)."""
    return text.replace("{", "{{").replace("}", "}}")


def _numbered(text: str, offset: int) -> str:
    """``text`` with each placeholder numbered, from ``offset`` on (``{}`` and ``{0.name}``
    of a fix that follows another name its own settings, not the first one's)."""
    parts, automatic = [], 0
    for literal, name, spec, conversion in string.Formatter().parse(text):
        parts.append(_literal(literal))
        if name is None:
            continue
        index, dot, rest = name.partition(".")
        if index:
            number = int(index)
        else:
            number, automatic = automatic, automatic + 1
        field = f"{number + offset}{dot}{rest}"
        field += f"!{conversion}" if conversion else ""
        field += f":{spec}" if spec else ""
        parts.append("{" + field + "}")
    return "".join(parts)


@dataclass(frozen=True)
class _Worded:
    """A setting in an interface's words: ``{}`` in a fix's text gives the ``setting``,
    ``{0.name}`` the option's ``name`` alone."""

    name: str
    setting: str

    def __format__(self, spec: str) -> str:
        return format(self.setting, spec)


@dataclass(frozen=True)
class Wording:
    """How an interface names its options; this one is Python's (keywords and values as
    a call writes them).  The command line and the web API have their own
    (:mod:`lagrangian.cli.wording`, :mod:`lagrangian.web.wording`)."""

    def option(self, keyword: str) -> str:
        """The option ``keyword`` as this interface names it."""
        return keyword

    def setting(self, setting: Setting) -> str:
        """``setting`` with its value as this interface writes it."""
        value = "..." if setting.value is None else repr(setting.value)
        if setting.entry is not None:
            value = f"{{{setting.entry!r}: {value}}}"
        return f"{self.option(setting.keyword)}={value}"


@dataclass(frozen=True)
class Problem:
    """One thing wrong with the input: where it is, what is wrong, and how to fix it (text,
    or a :class:`Fix` that names the options to set, worded by each interface)."""

    field: str
    message: str
    fix: str | Fix = ""
    line: int | None = None
    column: int | None = None
    source: str | None = None

    def worded(self, wording: Wording) -> Problem:
        """This problem with an option's field and the fix in the words of ``wording``."""
        fix = self.fix.worded(wording) if isinstance(self.fix, Fix) else self.fix
        return replace(self, field=wording.option(self.field), fix=fix)

    def __str__(self) -> str:
        where = self.field
        if self.source:
            where = f"{self.source}: {where}"
        if self.line is not None:
            where += f" (line {self.line}" + (
                f", column {self.column})" if self.column is not None else ")"
            )
        text = f"{where}: {self.message}"
        if self.fix:
            text += f" — {self.fix}"
        return text


E = TypeVar("E", bound="LagrangianError")


class LagrangianError(Exception):
    """Root of every error raised by lagrangian; ``exit_code`` is what it means to a shell."""

    exit_code: ClassVar[int] = FAILURE

    def __init__(self, message: str = "", problems: Iterable[Problem] = ()) -> None:
        self.problems: tuple[Problem, ...] = tuple(problems)
        self.summary = message
        if not message:
            message = "\n".join(str(p) for p in self.problems)
        elif self.problems:
            message = message + "\n" + "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(message)

    def worded(self: E, wording: Wording) -> E:
        """This error with its problems' options and fixes in the words of ``wording`` (the
        command line's flags, the web API's option names); itself when it has none."""
        if not self.problems:
            return self
        error = type(self)(self.summary, [p.worded(wording) for p in self.problems])
        error.__cause__, error.__traceback__ = self.__cause__, self.__traceback__
        return error


class ModelError(LagrangianError, ValueError):
    """The description of a system is wrong: unknown names, bad shapes, inconsistent pieces."""

    exit_code = BAD_INPUT


class ExpressionError(ModelError):
    """An expression could not be parsed or uses something outside the allowed language."""


class DerivationError(LagrangianError, ArithmeticError):
    """The equations of motion cannot be formed as asked (for example a singular mass matrix)."""


class ConstraintError(LagrangianError, ValueError):
    """A constraint is malformed, redundant, inconsistent or violated by the given state."""

    exit_code = BAD_INPUT


class AnalysisError(LagrangianError, ValueError):
    """An analysis cannot be carried out on this system (for example a singular Legendre map):
    the question does not fit the system asked about, so it is bad input."""

    exit_code = BAD_INPUT


class ArgumentError(LagrangianError, TypeError):
    """A public function was called with an argument of the wrong kind (``derive(None)``, a
    list where a mapping of names belongs): also a ``TypeError``, as Python raises for a wrong
    argument, and bad input to the command line."""

    exit_code = BAD_INPUT


class OutputError(LagrangianError, ValueError):
    """An output cannot be written where it was asked: a folder given for a file, a file in
    a folder that does not exist or cannot be written, a file given for a folder.  Bad
    input, found before any work."""

    exit_code = BAD_INPUT


class TimeLimitError(LagrangianError, TimeoutError):
    """A command ran past the time it was given (``lagrangian --timeout``): the input may be
    fine, the work was too large for the budget."""


class SizeLimitError(LagrangianError, MemoryError):
    """An expression grew past the size limit (``lagrangian --size-limit``,
    :mod:`lagrangian.size_limits`): the input may be fine, its expressions are too large for
    the budget.  Also a ``MemoryError``, which it prevents."""


class SimulationError(LagrangianError, RuntimeError):
    """Numerical integration failed (a step size underflow, a singular mass matrix on the way,
    a solution that blew up); bad input to a simulation is a :class:`SimulationInputError`."""


class SimulationInputError(SimulationError, ValueError):
    """A simulation was asked wrongly: missing or unknown initial values, a bad time span,
    method or option, a state it cannot start from.  Also a ``SimulationError``, so
    ``except SimulationError`` still catches it, and a ``ValueError``, as all bad input."""

    exit_code = BAD_INPUT


def require(value: object, kinds: type | tuple[type, ...], argument: str, fix: str) -> None:
    """Raise :class:`ArgumentError` naming ``argument`` unless ``value`` is one of ``kinds``.

    >>> require(None, int, "f(n)", "give a count")
    Traceback (most recent call last):
    ...
    lagrangian.errors.ArgumentError: f(n) takes int, not NoneType: give a count
    """
    if not isinstance(value, kinds):
        wanted = kinds if isinstance(kinds, tuple) else (kinds,)
        names = " or ".join(kind.__name__ for kind in wanted)
        raise ArgumentError(f"{argument} takes {names}, not {type(value).__name__}: {fix}")


def raise_if_problems(problems: list[Problem], summary: str, kind: type[LagrangianError]) -> None:
    """Raise ``kind`` with every collected problem, or do nothing when there are none."""
    if problems:
        count = len(problems)
        noun = "problem" if count == 1 else "problems"
        raise kind(f"{summary} ({count} {noun}):", problems)


def decode_text(data: bytes, source: str, kind: type[LagrangianError]) -> str:
    """``data`` read as UTF-8 text, or raise ``kind`` naming the ``source``, the first byte
    that is not UTF-8 (or a NUL byte: binary data, or UTF-16 text), its position, line and
    column, and the fix.

    >>> decode_text("caf\\xe9: 1".encode("latin-1"), "m.yaml", ModelError)
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: m.yaml is not UTF-8 text (1 problem):
      - m.yaml: encoding (line 1, column 4): byte 0xe9 at position 3 is not UTF-8 (invalid \
continuation byte) — save the file as UTF-8 (an editor's Save As, encoding UTF-8)
    """
    nul = data.find(b"\0")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        start, reason = error.start, f"is not UTF-8 ({error.reason})"
    else:
        if nul < 0:
            return text
        start = len(data)
    if 0 <= nul < start:  # the first wrong byte is said
        start, reason = nul, "is a NUL byte: binary data, not text"
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        reason += "; the file is UTF-16 (it starts with a UTF-16 byte-order mark)"
    line = data.count(b"\n", 0, start) + 1
    column = start - data.rfind(b"\n", 0, start)
    message = f"byte 0x{data[start]:02x} at position {start} {reason}"
    fix = "save the file as UTF-8 (an editor's Save As, encoding UTF-8)"
    problem = Problem("encoding", message, fix, line, column, source)
    raise kind(f"{source} is not UTF-8 text (1 problem):", [problem])
