"""Every constraint as a Pfaffian form, the constraint Jacobian and the acceleration terms.

A holonomic (or active unilateral) constraint h(q, t) = 0 holds along the motion when
its rate does, h_dot = dh/dq . q_dot + dh/dt = 0; a velocity constraint is a(q, t).q_dot +
b(q, t) = 0 already.  Either way the constraint at velocity level reads

    c(q, q_dot, t) = a(q, t) . q_dot + b(q, t) = 0,      the 1-form  omega = a.dq + b dt,

with a = dh/dq, b = dh/dt for a holonomic one.  The rows a_j make the constraint Jacobian A,
and differentiating c once more (holonomic: h twice) gives

    A q_ddot = gamma,    gamma_j = -(dc_j/dt with q_ddot = 0)    (chain rule, d/dt = sum
                                                                  q_dot d/dq + q_ddot d/dq_dot
                                                                  + d/dt).

The differentiation and expansion run in SymEngine; forms are cached per constraint
expression and coordinates, since every consumer of a System's constraints asks for them.

>>> import sympy as sp
>>> from lagrangian.model import Holonomic
>>> x, y = sp.symbols("x y")
>>> form = pfaffian_form(Holonomic(x**2 + y**2 - 1), (x, y))
>>> form.coefficients, form.time_coefficient
((2*x, 2*y), 0)
>>> acceleration_terms([form], (x, y))
[-2*x_dot**2 - 2*y_dot**2]
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

import symengine as se
import sympy as sp

from lagrangian.derivation.backend import Backend, SympyView, to_backend
from lagrangian.derivation.collect import collect_state
from lagrangian.derivation.trig import combine_trig, size
from lagrangian.model import VelocityConstraint, t, velocity
from lagrangian.model.constraints import Constraint
from lagrangian.model.contact import MADE
from lagrangian.size_limits import check_size
from lagrangian.symbolic.caches import RecentCache, remembered
from lagrangian.symbolic.expressions import distinct_parts, free_symbols
from lagrangian.symbolic.native import to_symengine_sharing

TIDY_OPS = 1000  # partial derivatives of a constraint's rate beyond this are not expanded
CACHED = 512  # constraint expressions whose form is kept, and coordinate tuples' conversions
ZERO = sp.Integer(0)
T = TypeVar("T")


@dataclass(frozen=True)
class FastForm:
    """The SymEngine images the SymPy parts of a :class:`PfaffianForm` were converted from:
    c, the a_k that can be non-zero (those of the coordinates c involves, by index) and b."""

    velocity_expression: Backend
    coefficients: tuple[tuple[int, Backend], ...]
    time_coefficient: Backend


@dataclass(frozen=True)
class PfaffianForm:
    """omega = sum_k a_k dq_k + b dt of one constraint, and c = a.q_dot + b (= 0)."""

    coefficients: tuple[sp.Expr, ...]
    time_coefficient: sp.Expr
    velocity_expression: sp.Expr
    #: The conversion back to SymPy that made the form (for a rolling contact's constraint,
    #: the one that made the constraint), which the acceleration term goes on with: the parts
    #: they share are converted once.
    view: SympyView = field(compare=False, repr=False)
    #: The form in SymEngine, which the acceleration term and the probes of
    #: :mod:`lagrangian.constraints.dependence` go on from (converting the SymPy parts back
    #: would walk a rolling wheel's rate of thousands of operations again).
    fast: FastForm = field(compare=False, repr=False)

    def depends_on_time(self) -> bool:
        """True when omega involves t (b != 0 or some a_k depends on t)."""
        return self.time_coefficient != 0 or any(t in free_symbols(a) for a in self.coefficients)


def pfaffian_form(constraint: Constraint, coordinates: Sequence[sp.Symbol]) -> PfaffianForm:
    """The Pfaffian form of ``constraint`` (holonomic and unilateral ones through h_dot)."""
    velocity_level = isinstance(constraint, VelocityConstraint)
    made = MADE.peek(constraint)
    made_by = None
    if made is not None:  # backend gives its expression for this one from now on
        made_by = made.conversion
        _CONVERTED.get(constraint.expression, lambda _: made.expression)
    key = (velocity_level, constraint.expression, tuple(coordinates), made_by)
    try:
        return _cached_form(*key)
    except TypeError:  # an unhashable expression: let the System's validation name it
        return _form(*key)


@remembered(maxsize=CACHED)
def _cached_form(
    velocity_level: bool,
    expr: sp.Expr,
    coordinates: tuple[sp.Symbol, ...],
    made_by: SympyView | None,
) -> PfaffianForm:
    return _form(velocity_level, expr, coordinates, made_by)


def _form(
    velocity_level: bool,
    expr: sp.Expr,
    coordinates: tuple[sp.Symbol, ...],
    made_by: SympyView | None,
) -> PfaffianForm:
    """The form of ``expr``, converted back to SymPy by ``made_by`` (the conversion that made
    a rolling contact's constraint) or by a conversion of its own."""
    c = backend(expr)
    free = c.free_symbols
    state = fast_state(coordinates)
    moving = [k for k, q in enumerate(state.coordinates) if q in free]
    view = made_by or _view(expr, coordinates, moving)
    # only the partial derivatives by the symbols the constraint involves are taken, the
    # others are 0: a chain's rod involves 4 of its 2n coordinates
    coefficients = [ZERO] * len(coordinates)
    if velocity_level:  # a = dc/dq_dot and b = c at q_dot = 0, each expanded
        rolling = [k for k, v in enumerate(state.speeds) if v in free]
        slopes = {k: se.expand(c.diff(state.speeds[k])) for k in rolling}
        for k, slope in slopes.items():
            coefficients[k] = view(slope)
        at_rest = se.expand(_at_rest(c, [state.speeds[k] for k in rolling]))
        fast = FastForm(c, tuple(slopes.items()), at_rest)
        return PfaffianForm(tuple(coefficients), view(at_rest), expr, view, fast)
    slopes = {k: c.diff(state.coordinates[k]) for k in moving}  # a = dh/dq, b = dh/dt
    for k, slope in slopes.items():
        coefficients[k] = view(slope)
    time_slope = c.diff(state.time)
    rate = se.Add(*[slope * state.speeds[k] for k, slope in slopes.items()], time_slope)
    fast = FastForm(rate, tuple(slopes.items()), time_slope)
    return PfaffianForm(tuple(coefficients), view(time_slope), view(rate), view, fast)


def _at_rest(c: Backend, speeds: list[Backend]) -> Backend:
    """c at ``speeds`` = 0.  A term with one of them among its factors is 0 there and is left
    out unvisited (substituting walks every part of it: a rolling wheel's no-slip constraint
    is its coefficients times the speeds, thousands of operations with no speed-free
    term); the other terms are substituted."""
    rest = dict.fromkeys(speeds, se.Integer(0))
    terms = c.args if c.is_Add else (c,)
    kept = [t for t in terms if not (t.is_Mul and any(f in rest for f in t.args))]
    return (c if len(kept) == len(terms) else se.Add(*kept)).xreplace(rest)


@dataclass(frozen=True)
class FastState:
    """The coordinates, their speeds and t in SymEngine, converted once per coordinates."""

    coordinates: tuple[Backend, ...]
    speeds: tuple[Backend, ...]
    time: Backend


@remembered(maxsize=CACHED)
def fast_state(coordinates: tuple[sp.Symbol, ...]) -> FastState:
    """The :class:`FastState` of ``coordinates`` (a chain's 400 coordinates and speeds were
    converted again for each of its 200 constraints)."""
    return FastState(
        tuple(to_backend(q) for q in coordinates),
        tuple(to_backend(velocity(q)) for q in coordinates),
        to_backend(t),
    )


def _view(expr: sp.Expr, coordinates: tuple[sp.Symbol, ...], moving: list[int]) -> SympyView:
    """The conversion back to SymPy of one constraint's form and acceleration term, with its
    own symbols, the speeds of the coordinates ``moving`` (those it involves: the rate of a
    holonomic constraint, the chain rule of gamma) and t: the conversion shared by the
    constraints on ``coordinates`` (a bicycle's front contact written by hand: the no-slip
    constraints and the contact's height have most of their parts in common), or, where a
    symbol's name is taken there by another symbol, one of its own."""
    symbols = {*free_symbols(expr), *(velocity(coordinates[k]) for k in moving), t}
    shared = _shared_conversion(coordinates)
    with _NAMING:  # checked and named at once: two threads never name a symbol two ways
        view = shared.next()
        names = view.by_name
        if any(names.get(s.name, s) != s for s in symbols):
            return SympyView(symbols)
        names.update((s.name, s) for s in symbols)
    return view


#: Constraints that one shared conversion serves at most: what it converts lives as long as
#: any of their cached forms (or the conversion is shared), so a process that converts
#: constraint after constraint (a server's models) keeps a bounded part of it.
SHARED_BY = 16


class _Shared(Generic[T]):
    """What consecutive constraints share (a conversion back to SymPy, or SymPy's
    subexpressions converted to SymEngine), a new one after every :data:`SHARED_BY`
    constraints."""

    def __init__(self, make: Callable[[], T]) -> None:
        self.make = make
        self.value = make()
        self.constraints = 0

    def next(self) -> T:
        """What one more constraint shares."""
        if self.constraints >= SHARED_BY:  # >=: two threads may both have counted
            self.value, self.constraints = self.make(), 0
        self.constraints += 1
        return self.value


@remembered(maxsize=CACHED)
def _shared_conversion(coordinates: tuple[sp.Symbol, ...]) -> _Shared[SympyView]:
    """The conversion :func:`_view` shares among the constraints on ``coordinates``."""
    return _Shared(lambda: SympyView([]))


_NAMING = threading.Lock()


#: The SymEngine images of the constraint expressions used last, by the identity of the
#: expression: a rolling contact's constraint is given the expression it was made from
#: (:data:`lagrangian.model.contact.MADE`, equal to its conversion).
_CONVERTED: RecentCache[Any, Backend] = RecentCache(CACHED)


def backend(expr: Any) -> Backend:
    """The SymEngine image of a constraint expression, converted once (a rolling contact's
    no-slip constraint has thousands of operations and several consumers)."""
    return _CONVERTED.get(expr, _converted_once)


def _converted_once(expr: Any) -> Backend:
    try:
        return _cached_backend(expr)
    except TypeError:
        return to_backend(expr)


@remembered(maxsize=CACHED)
def _cached_backend(expr: Any) -> Backend:
    # each distinct subexpression converted once, for this constraint and the next ones: a
    # rolling contact's constraint has the square root of its axle's tilt in most of its
    # terms (a bicycle's front wheel: 3165 nodes, 188 of them distinct; a tenth of the
    # time), and its other no-slip constraint and its height have those parts too
    return to_symengine_sharing(expr, _shared_subexpressions().next())


@remembered(maxsize=1)
def _shared_subexpressions() -> _Shared[dict[Any, Backend]]:
    """SymPy subexpressions -> SymEngine, shared by the conversions of consecutive
    constraint expressions (:func:`backend`)."""
    return _Shared(dict)


def acceleration_terms(
    forms: Sequence[PfaffianForm], coordinates: Sequence[sp.Symbol]
) -> list[sp.Expr]:
    """gamma_j = -(dc_j/dt at q_ddot = 0) of every constraint c_j = a_j . q_dot + b_j:

        gamma_j = -(sum_l dc_j/dq_l q_dot_l + dc_j/dt),

    each partial derivative expanded and its trigonometry tidied on its own in SymEngine
    (:func:`lagrangian.derivation.trig.combine_trig`), then the terms grouped by state
    monomial.  Never the product of whole sums expanded at once, so a constraint written with
    a rotation matrix in world axes costs about what it costs in body axes; a partial
    derivative of more than ``TIDY_OPS`` operations (a rolling wheel's contact point), or a
    chain term below whose factors' sizes multiply past it, is left as it is, and so is then
    gamma.

    A radical u**(p/q) of a state-dependent u (a torus wheel's contact point has
    sqrt(1 - s**2) in every term) is differentiated through its base by the chain rule,

        d/dt c(q, u(q, t)) = sum_l dc/dq_l q_dot_l + dc/dt + dc/du du/dt     (u held fixed
                                                                               in dc/dq, dc/dt),

    so du/dt appears once, not inside every partial derivative."""
    fast = fast_state(tuple(coordinates))
    variables = [*fast.coordinates, fast.time]
    rates = [*fast.speeds, se.Integer(1)]
    state = {*variables, *fast.speeds}
    base_rates: dict[Backend, Backend] = {}
    result = []
    for j, form in enumerate(forms):
        terms, held = _rate_terms(form.fast.velocity_expression, variables, rates, base_rates)
        tidied = all(size(slope) * max(1, size(rate)) <= TIDY_OPS for slope, rate in terms)
        if tidied:
            rate = se.expand(se.Add(*[combine_trig(slope) * rate for slope, rate in terms]))
            gamma = collect_state(-rate, state)
        else:
            gamma = -se.Add(*[slope * rate for slope, rate in terms])
        gamma = gamma.xreplace(held) if held else gamma
        result.append(_converted(form.view, gamma, j, tidied))
    return result


def _converted(view: SympyView, gamma: Backend, j: int, tidied: bool) -> sp.Expr:
    """Constraint j's ``gamma`` converted, SizeLimitError before converting it past the size
    limit (converting and printing cost far more than building it).  A tidied gamma is
    small and counted first; one left as built (a rolling wheel's: thousands of operations)
    is counted as it is converted, which counts it anyway, and stopped before the part past
    the limit."""
    name = f"the acceleration term gamma of constraints[{j}]"
    if tidied:
        check_size(gamma, name)
        return view(gamma)
    return view.vector([gamma], named=lambda _: name)[0]


def _rate_terms(
    c: Backend,
    variables: Sequence[Backend],
    rates: Sequence[Backend],
    base_rates: dict[Backend, Backend],
) -> tuple[list[tuple[Backend, Backend]], dict[Backend, Backend]]:
    """dc/dt (at q_ddot = 0) as a list of (partial derivative, rate) with the state-dependent
    radical bases u held as symbols, and those symbols -> u: the partial derivatives by
    ``variables`` times ``rates``, then dc/du times du/dt for each base, du/dt taken from
    ``base_rates`` or computed and kept there (a wheel's contact height and its two no-slip
    constraints share the square root of its axle's tilt)."""
    bases = {
        p.args[0]: se.Dummy("u")
        for p in distinct_parts(c)  # each shared part once (SymEngine's atoms walks the tree)
        if isinstance(p, se.Pow) and p.args[1].is_Number and not p.args[1].is_Integer
        if not p.args[0].is_Symbol
        if any(v in p.args[0].free_symbols for v in variables)
    }
    held = c.xreplace(bases) if bases else c
    free = held.free_symbols  # the other partial derivatives are 0 (a chain's rod: 4 of 2n)
    terms = [(held.diff(v), rate) for v, rate in zip(variables, rates) if v in free]
    for base, symbol in bases.items():
        base_rate = base_rates.get(base)
        if base_rate is None:
            inner, inner_held = _rate_terms(base, variables, rates, base_rates)
            base_rate = se.Add(*[slope * rate for slope, rate in inner])
            base_rate = base_rates[base] = (
                base_rate.xreplace(inner_held) if inner_held else base_rate
            )
        terms.append((held.diff(symbol), base_rate))
    return terms, {symbol: base for base, symbol in bases.items()}


def jacobian(forms: Sequence[PfaffianForm], n: int) -> sp.ImmutableMatrix:
    """The constraint Jacobian A, one row a_j per constraint (m x n)."""
    return sp.ImmutableMatrix(len(forms), n, [a for f in forms for a in f.coefficients])
