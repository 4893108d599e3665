"""SymEngine expressions that never call back into Python.

SymEngine holds a SymPy function it has no class of its own for (Heaviside, a Bessel function)
as a ``PyFunction``, and its C++ code calls SymPy to differentiate, evaluate, hash and compare
it.  Those calls are made without a way for a Python exception to come back through the C++:
when the time limit's exception (:mod:`lagrangian.limits`) lands in one, the process dies with
a segmentation fault (``Heaviside(x**999)``, whose SymPy derivative takes minutes, did it every
time).  They are slow as well: SymPy differentiates with complex symbols, and the derivative
``DiracDelta(x**999)`` splits ``x**999`` into real and imaginary parts.

So such a function goes into SymEngine as a plain function symbol of a reserved name, which
SymEngine differentiates by itself (``Subs(Derivative(f(_xi), _xi), _xi, u) * du``); the way
back (:func:`restore_functions`, which :func:`lagrangian.symbolic.objects.sympy_object` applies
to every SymEngine value) puts the SymPy function back, unevaluated.  The derivative left
unevaluated is then taken in SymPy with the rules of :mod:`lagrangian.symbolic.nonsmooth`
(d Heaviside(u) = 0).  With no callback, the time limit's exception only ever arrives between
two Python instructions.

>>> import sympy as sp
>>> x = sp.Symbol("x")
>>> step = sp.Heaviside(x**999, evaluate=False)  # as the model files' parser builds it
>>> fast = to_symengine(step)
>>> fast
_py_Heaviside(x**999, 1/2)
>>> fast.diff(x)
999*x**998*Subs(Derivative(_py_Heaviside(_xi_1, 1/2), _xi_1), (_xi_1), (x**999))
>>> restore_functions(sp.sympify(fast, strict=True)) == step
True
"""

from __future__ import annotations

from typing import Any

import symengine as se
import sympy as sp
from symengine.lib.symengine_wrapper import PyFunction
from sympy.core.function import AppliedUndef

#: Starts the name of the function symbol that stands for a SymPy function in SymEngine.
PREFIX = "_py_"

#: The SymPy class behind each reserved name met so far (a class per name, as SymPy has).
_CLASSES: dict[str, type] = {}


def to_symengine(expr: Any) -> Any:
    """``expr`` (SymPy, SymEngine or a number) as SymEngine, its SymPy-only functions as
    function symbols named :data:`PREFIX` + their name."""
    converted = se.sympify(expr)
    if not isinstance(converted, se.Basic):
        return converted
    wrapped = converted.atoms(PyFunction)
    if not wrapped:
        return converted
    return converted.xreplace({f: _stand_in(f) for f in wrapped})


def _stand_in(wrapped: Any) -> Any:
    function = wrapped._sympy_().func
    name = PREFIX + function.__name__
    if _CLASSES.setdefault(name, function) is not function:
        raise TypeError(f"two SymPy functions are both named {function.__name__}")
    return se.Function(name)(*wrapped.args)


def restore_functions(expr: Any) -> Any:
    """``expr`` (SymPy, converted from SymEngine) with the stand-ins of
    :func:`to_symengine` turned back into their SymPy functions, unevaluated (SymPy's own
    evaluation of Heaviside(x**999) expands (re(x) + i*im(x))**999)."""
    if not isinstance(expr, sp.Basic) or not _CLASSES:
        return expr

    def stands_in(e: sp.Basic) -> bool:
        return isinstance(e, AppliedUndef) and e.func.__name__ in _CLASSES

    if not any(stands_in(e) for e in expr.atoms(AppliedUndef)):
        return expr
    return expr.replace(stands_in, lambda e: _CLASSES[e.func.__name__](*e.args, evaluate=False))


def to_symengine_sharing(expr: Any, memo: dict[Any, Any]) -> Any:
    """:func:`to_symengine` of ``expr`` with each distinct subexpression converted once for
    all the calls that share ``memo``: an expression built by multiplying matrices out (a
    rotation matrix given whole, a rolling contact's constraint) repeats its parts many
    times over, and converting the tree would convert every copy."""
    known = memo.get(expr)
    if known is not None:
        return known
    if isinstance(expr, sp.Add):
        result = se.Add(*[to_symengine_sharing(a, memo) for a in expr.args])
    elif isinstance(expr, sp.Mul):
        result = se.Mul(*[to_symengine_sharing(a, memo) for a in expr.args])
    elif isinstance(expr, sp.Pow):
        result = se.Pow(to_symengine_sharing(expr.base, memo), to_symengine_sharing(expr.exp, memo))
    else:
        result = to_symengine(expr)
    memo[expr] = result
    return result
