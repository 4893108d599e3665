"""Hybrid transitions: where the state jumps by a rule that no single constraint expresses.

A walker's heel strike swaps the stance and swing legs: the coordinates are relabelled and the
velocities jump by the angular momentum balance about the new contact (Garcia, Chatterjee,
Ruina & Coleman, *J. Biomech. Eng.* 120, 1998, eq. 4).  A :class:`Transition` says so
directly: when its ``guard`` G(q, t) crosses zero (in its ``direction``) and its condition
``when`` holds there, every coordinate and velocity named in ``reset`` takes the value of its
expression evaluated at the state just before (the others keep theirs).

>>> import sympy as sp
>>> theta, phi = sp.symbols("theta phi")
>>> heel = Transition("heel_strike", phi - 2 * theta, {"theta": -theta, "phi": -2 * theta},
...                   direction="rising", when=sp.Lt(theta, 0))
>>> heel.reset
((theta, -theta), (phi, -2*theta))
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import sympy as sp

from lagrangian.errors import Problem
from lagrangian.model.elements import as_expression
from lagrangian.symbolic.expressions import free_symbols

if TYPE_CHECKING:
    from lagrangian.model.validation import NameScope

#: The directions of a guard's crossing: from negative to positive, the reverse, or either.
DIRECTIONS: Mapping[str, float] = {"rising": 1.0, "falling": -1.0, "both": 0.0}
#: The comparisons a condition ``when`` may make.
COMPARISONS = (sp.StrictLessThan, sp.LessThan, sp.StrictGreaterThan, sp.GreaterThan)


@dataclass(frozen=True)
class Transition:
    """A jump of the state where ``guard`` crosses zero (module docstring).

    ``reset`` maps coordinates and velocities (names or symbols) to their values after the
    jump, expressions of the state before it; ``direction`` is ``"rising"``, ``"falling"`` or
    ``"both"``; ``when`` an optional comparison of the state (``theta < 0``) that must hold at
    the crossing, else the crossing is passed by.
    """

    name: str
    guard: sp.Expr
    reset: Any
    direction: str = "both"
    when: Any = None
    kind: ClassVar[str] = "transition"

    def __post_init__(self) -> None:
        object.__setattr__(self, "guard", as_expression(self.guard))
        pairs = self.reset.items() if isinstance(self.reset, Mapping) else self.reset
        try:
            reset = tuple((_as_symbol(key), as_expression(value)) for key, value in pairs)
        except (TypeError, ValueError):
            reset = self.reset  # the validator says what is wrong with it
        object.__setattr__(self, "reset", reset)


def _as_symbol(key: Any) -> Any:
    return sp.Symbol(key) if isinstance(key, str) else key


def check_transitions(
    transitions: tuple[Transition, ...], scope: NameScope, problems: list[Problem]
) -> None:
    """Every problem of the transitions: names, guards of the configuration, resets of known
    coordinates and velocities to expressions of the state, directions, conditions."""
    names: set[str] = set()
    for i, item in enumerate(transitions):
        where = f"transitions[{i}]"
        if not item.name or item.name in names:
            problems.append(
                Problem(
                    f"{where}.name",
                    "each transition needs its own name",
                    "name it, e.g. heel_strike",
                )
            )
        names.add(item.name)
        scope.check(item.guard, f"{where}.guard", "state", problems)
        if item.direction not in DIRECTIONS:
            problems.append(
                Problem(
                    f"{where}.direction",
                    f"unknown direction {item.direction!r}",
                    f"use one of {', '.join(DIRECTIONS)}",
                )
            )
        _check_reset(item, where, scope, problems)
        _check_when(item, where, scope, problems)


def _check_reset(item: Transition, where: str, scope: NameScope, problems: list[Problem]) -> None:
    if not isinstance(item.reset, tuple) or not item.reset:
        problems.append(
            Problem(
                f"{where}.reset",
                "the reset says nothing",
                "map coordinates and NAME_dot velocities to their new values",
            )
        )
        return
    for key, value in item.reset:
        if key not in scope.coordinates and key not in scope.velocities:
            problems.append(
                Problem(
                    f"{where}.reset.{key}",
                    f"{key} is not a coordinate or velocity",
                    "reset coordinates and NAME_dot velocities only",
                )
            )
        scope.check(value, f"{where}.reset.{key}", "state", problems)


def _check_when(item: Transition, where: str, scope: NameScope, problems: list[Problem]) -> None:
    if item.when is None:
        return
    if not isinstance(item.when, COMPARISONS):
        problems.append(
            Problem(
                f"{where}.when",
                f"{item.when} is not a comparison",
                "write one comparison of the state, e.g. theta < 0",
            )
        )
        return
    scope.check(item.when.lhs - item.when.rhs, f"{where}.when", "state", problems)


def used_symbols(item: Transition) -> set[sp.Basic]:
    """The symbols a transition's guard, reset and condition use."""
    parts = [item.guard, *(value for _, value in item.reset)]
    if item.when is not None:
        parts.append(item.when.lhs - item.when.rhs)
    return set().union(*(free_symbols(p) for p in parts))
