"""The one error root of lagrangian.

Every error the library raises on purpose is a :class:`LagrangianError`; each subclass also
inherits the built-in exception a Python user would expect (``ModelError`` is a ``ValueError``),
so ``except ValueError`` keeps working.  Errors about user input carry every problem found at
once (``problems``), each naming the field and the fix.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass


@dataclass(frozen=True)
class Problem:
    """One thing wrong with the input: where it is, what is wrong, and how to fix it."""

    field: str
    message: str
    fix: str = ""
    line: int | None = None
    column: int | None = None
    source: str | None = None

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


class LagrangianError(Exception):
    """Root of every error raised by lagrangian."""

    def __init__(self, message: str = "", problems: Iterable[Problem] = ()) -> None:
        self.problems: tuple[Problem, ...] = tuple(problems)
        if not message:
            message = "\n".join(str(p) for p in self.problems)
        elif self.problems:
            message = message + "\n" + "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(message)


class ModelError(LagrangianError, ValueError):
    """The description of a system is wrong: unknown names, bad shapes, inconsistent pieces."""


class ExpressionError(ModelError):
    """An expression could not be parsed or uses something outside the allowed language."""


class DerivationError(LagrangianError, ArithmeticError):
    """The equations of motion cannot be formed as asked (for example a singular mass matrix)."""


class ConstraintError(LagrangianError, ValueError):
    """A constraint is malformed, redundant, inconsistent or violated by the given state."""


class AnalysisError(LagrangianError, ValueError):
    """An analysis cannot be carried out on this system (for example a singular Legendre map)."""


class SimulationError(LagrangianError, RuntimeError):
    """Numerical integration failed or was given an incomplete or inconsistent state."""


def raise_if_problems(problems: list[Problem], summary: str, kind: type[LagrangianError]) -> None:
    """Raise ``kind`` with every collected problem, or do nothing when there are none."""
    if problems:
        count = len(problems)
        noun = "problem" if count == 1 else "problems"
        raise kind(f"{summary} ({count} {noun}):", problems)
