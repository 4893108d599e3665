"""The constraints an analysis leaves out, said once per reason: a gas of four disks has 22
unilateral contacts, all taken as released, which one statement names together.

A constraint is left out when it is unilateral (g >= 0, taken as not in contact) or redundant
(its Jacobian row a combination of earlier ones).  One left out for a reason is said as
before, ``'floor' (constraints[1]) unilateral: taken as released (g > 0)``; several for one
reason are counted and named in one statement, their positions as a range when they follow
each other.

>>> import lagrangian as lg
>>> first, second = lg.Unilateral("x2 - x1", name="first"), lg.Unilateral("x3 - x2", name="second")
>>> items = [LeftOut(0, first, UNILATERAL), LeftOut(1, second, UNILATERAL)]
>>> (both,) = statements(items)
>>> for part in both.split(": "):
...     print(part)
2 unilateral constraints, taken as released (g > 0)
'first', 'second' (constraints[0] to constraints[1])
>>> statements(items[1:])
("'second' (constraints[1]) unilateral: taken as released (g > 0)",)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from lagrangian.model.constraints import Constraint, label


@dataclass(frozen=True)
class Reason:
    """Why a constraint is left out: its ``kind`` (unilateral, redundant) and what that means
    for one constraint (``one``) and for several (``several``)."""

    kind: str
    one: str
    several: str


UNILATERAL = Reason("unilateral", "taken as released (g > 0)", "taken as released (g > 0)")
REDUNDANT = Reason(
    "redundant",
    "its Jacobian row is a combination of earlier ones",
    "their Jacobian rows are combinations of earlier ones",
)


@dataclass(frozen=True)
class LeftOut:
    """``constraint``, at ``index`` in ``System.constraints``, left out of an analysis for
    ``reason``."""

    index: int
    constraint: Constraint
    reason: Reason

    @property
    def name(self) -> str:
        return getattr(self.constraint, "name", "") or ""


def statements(items: Sequence[LeftOut]) -> tuple[str, ...]:
    """One statement per reason, in the order the reasons first appear."""
    grouped: dict[Reason, list[LeftOut]] = {}
    for item in items:
        grouped.setdefault(item.reason, []).append(item)
    return tuple(_statement(reason, group) for reason, group in grouped.items())


def _statement(reason: Reason, group: list[LeftOut]) -> str:
    if len(group) == 1:
        (item,) = group
        return f"{label(item.index, item.constraint)} {reason.kind}: {reason.one}"
    return f"{len(group)} {reason.kind} constraints, {reason.several}: {_names(group)}"


def _names(group: list[LeftOut]) -> str:
    return constraint_names([(item.index, item.constraint) for item in group])


def constraint_names(constraints: Sequence[tuple[int, Constraint]]) -> str:
    """Constraints (index in ``System.constraints``, constraint) named together: one as
    ``'rod' (constraints[0])``; several by their names (when they all have one) and their
    positions, as a range when they follow each other: ``'a', 'b' (constraints[0] to
    constraints[1])``."""
    if len(constraints) == 1:
        return label(*constraints[0])
    indices = [i for i, _ in constraints]
    if indices == list(range(indices[0], indices[-1] + 1)):
        where = f"constraints[{indices[0]}] to constraints[{indices[-1]}]"
    else:
        where = ", ".join(f"constraints[{i}]" for i in indices)
    names = [getattr(c, "name", "") for _, c in constraints]
    if all(names):
        return ", ".join(repr(name) for name in names) + f" ({where})"
    return where
