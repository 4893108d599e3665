"""The discrete mechanics of the variational integrators as C functions, for loops compiled
once per machine.

:func:`native_mechanics` compiles the three groups of terms of a
:class:`~lagrangian.numerics.discrete_lagrangian.DiscreteMechanics` (its
:class:`~lagrangian.numerics.discrete_lagrangian.DiscreteTerms`) into C functions of the one
signature of :mod:`lagrangian.numerics.fast.native`, ``f(out, in, user_data)``:

    midpoint     in = [q, v, t, p]   out = [L_q, L_v, Q, L_qq, L_qv, L_vv, Q_q, Q_v]
    legendre     in = [q, v, t, p]   out = [L_v, L_vv]
    constraints  in = [q, t, p]      out = [h, A, dh/dt, d2h/dq2]   ([0] without constraints)

The loops of :mod:`lagrangian.numerics.fast.midpoint` and
:mod:`lagrangian.numerics.fast.collocation` take them as function values, so they are the same
machine code for every system and a new system costs only these functions (milliseconds with
SymEngine's LLVM backend).

>>> import lagrangian as lg
>>> from lagrangian.numerics.discrete_lagrangian import compile_discrete_mechanics
>>> mechanics = compile_discrete_mechanics(lg.derive(lg.examples.simple_pendulum()))
>>> native = native_mechanics(mechanics)  # doctest: +SKIP
>>> native.midpoint.outputs, native.constraints.outputs  # doctest: +SKIP
(8, 1)
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagrangian.numerics.discrete_lagrangian import DiscreteMechanics
from lagrangian.numerics.fast.compiled_rates import require_numba
from lagrangian.numerics.fast.native import NativeFunction, native_function
from lagrangian.symbolic.caches import IdentityCache


@dataclass(frozen=True)
class NativeMechanics:
    """The C functions of one system's discrete mechanics (module docstring), and its sizes:
    n coordinates, m holonomic constraints, and whether the Legendre map is affine in v."""

    midpoint: NativeFunction
    legendre: NativeFunction
    constraints: NativeFunction
    coordinates: int
    constraint_count: int
    legendre_linear: bool


_CACHE: IdentityCache[DiscreteMechanics, NativeMechanics] = IdentityCache()


def native_mechanics(mechanics: DiscreteMechanics) -> NativeMechanics:
    """The C functions of ``mechanics``, compiled once per DiscreteMechanics object.

    Raises SimulationError when numba is missing or an expression has no numeric form.
    """
    require_numba("the compiled variational integrators")
    return _CACHE.get(mechanics, _compile)


def _compile(mechanics: DiscreteMechanics) -> NativeMechanics:
    terms = mechanics.terms
    q, v, t, p = terms.coordinates, terms.velocities, terms.time, terms.parameters
    # a C function needs at least one output: a system without constraints gets a constant
    constraints = terms.constraints or (sp.S.Zero,)
    return NativeMechanics(
        midpoint=native_function([*q, *v, t, *p], terms.midpoint),
        legendre=native_function([*q, *v, t, *p], terms.legendre),
        constraints=native_function([*q, t, *p], constraints),
        coordinates=len(q),
        constraint_count=mechanics.constraint_count,
        legendre_linear=mechanics.legendre_linear,
    )
