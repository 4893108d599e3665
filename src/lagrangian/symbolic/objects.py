"""sympy_object: a value that is not text as a SymPy object, without ever running text.

``sympy.sympify(value, strict=True)`` converts numbers, SymPy and SymEngine objects and refuses
everything else, strings included (strict mode never parses text); lists and tuples are
converted element by element and numeric NumPy arrays become matrices.  Text has its own door,
:func:`lagrangian.symbolic.conversion.to_sympy`, which reads it with the model files' parser.
The symbolic tools below that door (the probe, the almost-everywhere derivatives) take their
arguments through this function, so they need neither the parser nor the door.

>>> sympy_object([1, 2.5])
[1, 2.50000000000000]
>>> sympy_object("__import__('os')")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
sympy.core.sympify.SympifyError: ...
"""

from __future__ import annotations

from typing import Any

import numpy as np
import symengine as se
import sympy as sp

# SymPy's Add imports its tensor module on first use (tens of milliseconds); doing it with the
# other imports keeps that cost out of the first model built or derived.
import sympy.tensor.tensor

from lagrangian.symbolic.native import restore_functions


def sympy_object(value: Any) -> Any:
    """``value`` (not text) as SymPy: lists and tuples element by element, numeric NumPy arrays
    as matrices or arrays, and numbers, SymPy and SymEngine objects by ``sympify(strict=True)``
    (which refuses text and anything else); SymEngine's stand-ins for SymPy functions become
    those functions again (:func:`lagrangian.symbolic.native.restore_functions`)."""
    if isinstance(value, (list, tuple)):
        return type(value)(sympy_object(item) for item in value)
    if isinstance(value, np.ndarray) and value.dtype.kind in "biuf":
        return sp.sympify(value.tolist(), strict=False)  # numbers only: nothing to evaluate
    converted = sp.sympify(value, strict=True)
    return restore_functions(converted) if isinstance(value, se.Basic) else converted
