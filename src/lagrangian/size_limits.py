"""Size limits for symbolic work: an expression that grows past a budget stops the work with
a message naming it.

A time limit (:mod:`lagrangian.limits`) says that the work took too long; a size limit says
which expression grew, before it is converted, printed or compiled (each of which costs time
and memory in proportion to its size, and far more than computing it).

- An expression's size is its number of operations counted over its tree, as it would be
  printed (SymEngine's ``count_ops``; a shared subexpression counts every time it appears).
- ``with size_limit(operations):`` sets the limit of a block; :func:`check_size` raises
  :class:`~lagrangian.errors.SizeLimitError` for an expression past it.  Limits nest: the
  smallest active one applies.
- Without a number, the limit is ``$LAGRANGIAN_SIZE_LIMIT`` (operations; ``none`` for no
  limit), else :data:`DEFAULT_OPERATIONS`, generous for real systems.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> operations(sp.sin(x) + x**2)
3
>>> with size_limit(2):
...     check_size(sp.sin(x) + x**2, "the potential")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
lagrangian.errors.SizeLimitError: the potential has 3 operations, more than the size limit of 2: ...
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import symengine as se

from lagrangian.errors import SizeLimitError
from lagrangian.limits import LimitStack, configured_limit

#: The environment variable that sets the size limit where no number is given.
ENVIRONMENT = "LAGRANGIAN_SIZE_LIMIT"
#: The most operations one derived expression may have when neither a keyword nor the
#: environment gives a limit: five million, four times the largest entry of a chain of five
#: rigid bodies turned by joint angles (1.2 million, nested as the rotations give it), three
#: hundred times the Whipple bicycle's and the 200-link pendulum's largest.
DEFAULT_OPERATIONS = 5_000_000
#: What the message of a limit reached advises first.
SIMPLIFY = (
    "simplify the model (fewer bodies, shorter expressions, coordinates that keep the "
    "energies short)"
)
#: How to raise the limit, by where it was set (the keyword, the command line's option, the
#: environment); a limit set nowhere is the default.
RAISE = {
    "size_limit": "pass a larger size_limit= (math.inf for no limit)",
    "--size-limit": "give a larger --size-limit (none for no limit)",
    ENVIRONMENT: f"raise {ENVIRONMENT} (none for no limit)",
    "playground": "run it with the lagrangian command, whose --size-limit raises the limit",
    "default": (
        f"raise the limit with size_limit= or the environment variable {ENVIRONMENT} "
        "(none for no limit)"
    ),
}


@dataclass(frozen=True)
class _Limit:
    operations: float  # math.inf: no limit
    where: str  # a key of RAISE


_active: LimitStack[_Limit] = LimitStack()


def configured_operations(operations: float | None = None, where: str = "size_limit") -> float:
    """The size limit in operations: ``operations`` when given, else
    ``$LAGRANGIAN_SIZE_LIMIT``, else :data:`DEFAULT_OPERATIONS`; ``math.inf`` means no limit
    (``math.inf`` given, or ``none`` in the environment).  ``where`` names the option in the
    message of a bad value.

    >>> configured_operations(1000), configured_operations(math.inf)
    (1000, inf)
    """
    return configured_limit(
        operations,
        environment=ENVIRONMENT,
        default=DEFAULT_OPERATIONS,
        unit="operations",
        whole=True,
        where=where,
    )


def active_operations() -> float:
    """The size limit that applies here: the smallest active one, else the configured one."""
    return _active_limit().operations


def _active_limit() -> _Limit:
    stack = _active.stack
    if stack:
        return min(stack, key=lambda limit: limit.operations)
    return _Limit(
        configured_operations(), ENVIRONMENT if os.environ.get(ENVIRONMENT) else "default"
    )


@contextlib.contextmanager
def size_limit(operations: float | None = None, *, where: str = "size_limit") -> Iterator[None]:
    """Apply a size limit of ``operations`` in the block (with ``None``: inside another limit,
    that limit unchanged; else the configured one, :func:`configured_operations`)."""
    if operations is None and _active.stack:
        yield
        return
    stack = _active.stack
    if operations is None and os.environ.get(ENVIRONMENT, "").strip():
        where = ENVIRONMENT  # the limit comes from there
    stack.append(_Limit(configured_operations(operations, where), where))
    try:
        yield
    finally:
        stack.pop()


def operations(expression: Any) -> int:
    """The number of operations in ``expression`` (SymEngine or SymPy) counted over its tree:
    n - 1 for a sum or product of n terms, one for a power or a function, none for an atom."""
    if isinstance(expression, se.Basic):
        return int(se.count_ops(expression))
    return _sympy_operations(expression, {})


def _sympy_operations(expression: Any, memo: dict[Any, int]) -> int:
    # counted once per distinct subexpression (its hash is cached), as SymEngine counts
    args = getattr(expression, "args", ())
    if not args:
        return 0
    known = memo.get(expression)
    if known is not None:
        return known
    own = len(args) - 1 if (expression.is_Add or expression.is_Mul) else 1
    count = own + sum(_sympy_operations(a, memo) for a in args)
    memo[expression] = count
    return count


def raise_advice() -> str:
    """How to raise the size limit that applies here, in the words of where it was set
    (``give a larger --size-limit (none for no limit)`` on the command line)."""
    return RAISE.get(_active_limit().where, RAISE["default"])


def check_size(expression: Any, what: str) -> None:
    """Raise :class:`~lagrangian.errors.SizeLimitError` when ``expression`` has more
    operations than the active limit (:func:`active_operations`); ``what`` names it in the
    message ("derive: the forcing of the equation of theta3")."""
    if not math.isinf(active_operations()):
        check_operations(operations(expression), what)


def check_operations(count: int, what: str) -> None:
    """:func:`check_size` of an expression of ``count`` operations, counted or predicted
    (before building it)."""
    limit = _active_limit()
    if count > limit.operations:
        raise SizeLimitError(
            f"{what} has {count:,} operations, more than the size limit of "
            f"{limit.operations:,.0f}: {SIMPLIFY}, or {raise_advice()}"
        )
