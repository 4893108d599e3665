"""NumericFunction: SymPy expressions as one NumPy function, for one state or a batch of states.

The expressions are compiled once with ``sympy.lambdify(..., modules="numpy", cse=True)``
(common subexpressions computed once).  The arguments come in groups, each a list of symbols
(q, q_dot, p) or a single symbol (t).  A group is given as an array of shape (len,) for one
state, or (k, len) for a batch of k states; a scalar group as a float or an array (k,).  The
result has shape ``shape`` for one state and (k, *shape) for a batch.

>>> import sympy as sp
>>> x, v, t = sp.symbols("x v t")
>>> f = NumericFunction(([x, v], t), [x * v, sp.sin(t)], shape=(2,))
>>> f([2.0, 3.0], 0.0)
array([6., 0.])
>>> f([[2.0, 3.0], [1.0, 1.0]], 0.0).shape
(2, 2)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cached_property
from typing import Any, TypeAlias

import numpy as np
import sympy as sp

#: An argument group: a list of symbols (an array argument) or one symbol (a scalar argument).
Group: TypeAlias = "Sequence[sp.Symbol] | sp.Symbol"


class NumericFunction:
    """``expressions`` as a NumPy function of the argument ``groups``, reshaped to ``shape``.

    ``raw`` is the lambdified function itself (it returns a list of numbers), for callers that
    have already unpacked one state and want no overhead beyond that one call.  It is built on
    first use, so functions nobody calls cost nothing.
    """

    def __init__(
        self, groups: Sequence[Group], expressions: Sequence[sp.Expr], shape: tuple[int, ...]
    ) -> None:
        self._args: list[Any] = [list(g) if isinstance(g, Sequence) else g for g in groups]
        self._expressions = list(expressions)
        self.shape = shape
        # the number of dimensions of each argument when it carries a batch
        self._batch_ndim = tuple(2 if isinstance(g, list) else 1 for g in self._args)

    @cached_property
    def raw(self) -> Callable[..., list[Any]]:
        return sp.lambdify(self._args, self._expressions, modules="numpy", cse=True)

    def __call__(self, *arguments: Any) -> np.ndarray:
        size: int | None = None
        prepared = []
        for argument, batch_ndim in zip(arguments, self._batch_ndim):
            array = np.asarray(argument, dtype=float)
            if array.ndim == batch_ndim:
                size = array.shape[0]
                array = array.T  # one row per symbol, so lambdify unpacks columns of the batch
            prepared.append(array)
        values = self.raw(*prepared)
        if size is None:
            return np.array(values, dtype=float).reshape(self.shape)
        columns = [np.broadcast_to(np.asarray(v, dtype=float), (size,)) for v in values]
        return np.stack(columns, axis=-1).reshape((size, *self.shape))
