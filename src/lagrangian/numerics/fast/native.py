"""Expressions as one C function ``void f(double *out, const double *in, void *user_data)``.

The compiled integration loops (:mod:`lagrangian.numerics.fast.loops`) call the right-hand
side of every system through this one C signature, so they are compiled once per machine and
a new system costs only its own function:

- SymEngine's LLVM backend (``symengine.Lambdify(..., backend="llvm", cse=True)``) compiles
  the expressions in milliseconds (tens of them for a 10-link pendulum); ``as_ctypes()``
  gives the address of a C trampoline (the same for every function) and the ``user_data``
  pointer that selects this one.  Heaviside, which SymEngine's LLVM printer does not know, is
  rewritten as the equal Piecewise first.
- Only where SymEngine cannot compile an expression (a function its LLVM backend lacks, such
  as ``Mod``, or a SymEngine built without LLVM) the expressions are printed as Python
  (:mod:`lagrangian.numerics.fast.source`) and compiled by ``numba.cfunc`` with the same C
  signature: about 0.5 s for a double pendulum, 1.5 s for ten links, in every new process.

Either way the object that owns the machine code is kept in :class:`NativeFunction`, so the
addresses stay valid for as long as that value lives.

>>> import sympy as sp
>>> x, y = sp.symbols("x y")
>>> function = native_function([x, y], [y, -sp.sin(x)])
>>> function.compiler, function.address != 0
('llvm', True)
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from lagrangian.numerics.fast.llvm import CANNOT_COMPILE, llvm_lambdify
from lagrangian.numerics.fast.source import values_source

#: Whether to try SymEngine's LLVM backend (False: always numba; tests compare the two).
LLVM = True


@dataclass(frozen=True)
class NativeFunction:
    """``f(out, in, user_data)``: out[i] = expressions[i](in), compiled to machine code.

    Attributes
    ----------
    address, user_data:
        The C function's address and the pointer to pass as its third argument.
    inputs, outputs:
        The lengths of ``in`` and ``out``.
    compiler:
        "llvm" (SymEngine, milliseconds) or "numba" (the fallback, see the module docstring).
    """

    address: int
    user_data: int
    inputs: int
    outputs: int
    compiler: str
    owner: Any = field(repr=False, compare=False)


def native_function(symbols: Sequence[sp.Symbol], expressions: Sequence[sp.Expr]) -> NativeFunction:
    """``expressions`` as a C function of the vector ``symbols`` (module docstring).

    Raises SimulationError when neither SymEngine nor numba can compile them (the message
    names the function that has no numeric form).
    """
    compiled = llvm_function(symbols, expressions) if LLVM else None
    if compiled is not None:
        trampoline, user_data = compiled.as_ctypes()
        return NativeFunction(
            address=_address(trampoline),
            user_data=int(user_data.value or 0),
            inputs=len(symbols),
            outputs=len(expressions),
            compiler="llvm",
            owner=compiled,
        )
    return _numba_function(symbols, expressions)


def llvm_function(
    symbols: Sequence[sp.Symbol], expressions: Sequence[Any], *, backend: bool = False
) -> Any:
    """The ``symengine.Lambdify`` of ``expressions`` (SymPy, or SymEngine when ``backend``)
    compiled by LLVM with common subexpressions computed once
    (:func:`~lagrangian.numerics.fast.llvm.llvm_lambdify`), or None where SymEngine cannot
    compile them."""
    if not backend:
        try:
            expressions = [_without_heaviside(e) for e in expressions]
        except CANNOT_COMPILE:
            return None
    return llvm_lambdify(symbols, expressions)


def _without_heaviside(expr: sp.Expr) -> sp.Expr:
    """Heaviside(x, h0) as Piecewise((1, x > 0), (0, x < 0), (h0, True)), h0 = 1/2 unless
    given (SymPy's convention), which SymEngine's LLVM backend compiles."""
    if not isinstance(expr, sp.Basic) or not expr.has(sp.Heaviside):
        return expr

    def piecewise(x: sp.Expr, h0: sp.Expr = sp.S.Half) -> sp.Expr:
        return sp.Piecewise((1, x > 0), (0, x < 0), (h0, True))

    return expr.replace(sp.Heaviside, piecewise)


def _numba_function(symbols: Sequence[sp.Symbol], expressions: Sequence[sp.Expr]) -> NativeFunction:
    """The fallback: the expressions printed as Python and compiled by ``numba.cfunc``."""
    from numba import carray, cfunc, types

    source = values_source(symbols, expressions)
    namespace: dict[str, Any] = {"math": math, "carray": carray}
    exec(compile(source, "<right-hand side>", "exec"), namespace)
    double = types.CPointer(types.float64)
    signature = types.void(double, double, types.intp)
    compiled = cfunc(signature, error_model="numpy")(namespace["values"])
    return NativeFunction(
        address=int(compiled.address or 0),
        user_data=0,
        inputs=len(symbols),
        outputs=len(expressions),
        compiler="numba",
        owner=compiled,
    )


def _address(function: Any) -> int:
    return int(ctypes.cast(function, ctypes.c_void_p).value or 0)
