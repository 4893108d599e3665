"""Rolling contact: a thin disc (a wheel) of a 3-D rigid body rolling without slipping on the
horizontal plane z = 0, and the constraints it makes (Greenwood, Advanced Dynamics, 2003, §3.4;
Neimark & Fufaev, Dynamics of Nonholonomic Systems, ch. 1).

With the centre p(q, t), the unit axle a = R n (n the axle in body axes) and the disc's radius
r, the lowest point of the rim is C = p + r d, d the unit vector of the disc's plane that points
most downward:

    d = (a (a . e_z) - e_z) / s,   s = sqrt(a_x^2 + a_y^2) = |a x e_z|,   so  d_z = -s.

A force applied at the contact point (``at: BODY_contact``) acts on the disc's material point
there: the System moves it to the centre with its moment (r d) x F as a torque, so that
Q_j = F . d(v_C)/d(q_dot_j) by virtual work.

The disc touches the plane when C_z = p_z - r s = 0 (holonomic; left out when it holds
identically, when the centre height is written as r s already), and rolls without slipping when
the disc's material point at C is at rest:

    v_C = p_dot + omega_s x (r d) = 0,

whose x and y components are velocity (Pfaffian) constraints; the z component is the time
derivative of the holonomic one (the rim's tangent at its lowest point is horizontal).  The
multipliers of the three constraints are the contact force's components in world axes.

s = sqrt(1 - a_z^2), found from the form of a_z rather than by simplifying: a wheel turned
about the vertical, then leaned by u (its axle e.g. Rz(psi) Rx(u) e_y), has a_z = sin(u) and
s = cos(u), the root on the branch s > 0 (the disc not lying flat); a_z = cos(u) gives
s = sin(u).  Any other a_z (a steered wheel) keeps s = sqrt(1 - a_z^2), which stands for
itself while the constraints are expanded (SymEngine), so no expansion reaches under the root,
and each velocity's coefficient is written over s where that is shorter.

A wheel with a round tyre (a torus: ``radius`` R from the centre to the circle through the
tyre's centres, ``tyre_radius`` r_t) touches the plane at the lowest point of that tyre,

    C = p + R d - r_t e_z,

and a sphere of radius r (:func:`rolling_sphere`) is the torus with R = 0: C = p - r e_z, no
axle needed.  The constraints are the same with this C: C_z = 0 and the x and y components of
v_C = p_dot + omega_s x (C - p) = 0.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Any, ClassVar, NamedTuple

import symengine as se
import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.model.constraints import Holonomic, VelocityConstraint
from lagrangian.model.elements import Force, RigidBody, Torque, as_expression
from lagrangian.model.inertia import Shape
from lagrangian.model.rotation import angular_velocity_terms, rotation_axis, unit_axis
from lagrangian.model.validation import CONFIGURATION, NameScope
from lagrangian.symbolic.caches import IdentityCache, remembered
from lagrangian.symbolic.expressions import distinct_parts, free_symbols
from lagrangian.symbolic.native import to_symengine, to_symengine_sharing
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.symbols import t, velocity
from lagrangian.symbolic.sympy_view import SympyView

#: The powers whose form in cosines (:func:`_in_cosines`) is remembered.
SINE_POWERS = 1024
#: Shapes whose axis of symmetry is a wheel's axle.
WHEEL_SHAPES = ("disc", "ring", "cylinder")


class Made(NamedTuple):
    """How a constraint of a rolling contact was made: its expression in SymEngine before
    the conversion back to SymPy (the same expression as the SymPy one converted again),
    which the constraint's Pfaffian form starts from instead of converting it again, and that
    conversion, which the form and the acceleration term go on with
    (:mod:`lagrangian.constraints.pfaffian`): the parts they share with the constraint (the
    axle's tilt, its square root, the sines and cosines) are converted once."""

    expression: Any
    conversion: SympyView


#: How each constraint of a rolling contact was made, by the constraint's identity.
MADE: IdentityCache[Any, Made] = IdentityCache()


@dataclass(frozen=True)
class RollingDisc:
    """A thin disc of radius ``radius`` on the rigid body ``body`` (centred at the body's
    centre of mass, its axle along ``axis`` in body axes: ``"x"``, ``"y"``, ``"z"`` or a
    vector; by default the axis of the body's disc, ring or cylinder shape) rolling without
    slipping on the plane z = 0.  ``name`` names the contact point (default ``BODY_contact``).
    With ``tyre_radius`` r_t the wheel is a torus: a round tyre of radius r_t whose centres
    lie on the circle of radius ``radius`` (the module docstring).
    """

    body: str
    radius: sp.Expr
    axis: Any = None
    name: str = ""
    tyre_radius: sp.Expr = sp.Integer(0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", as_expression(self.radius))
        object.__setattr__(self, "tyre_radius", as_expression(self.tyre_radius))

    @property
    def contact(self) -> str:
        """The name of the contact point."""
        return self.name or f"{self.body}_contact"


@dataclass(frozen=True)
class ContactHeight(Holonomic):
    """The holonomic constraint C_z = 0 of a :class:`RollingDisc` (made by the System)."""

    contact: str = ""


@dataclass(frozen=True)
class NoSlip(VelocityConstraint):
    """A no-slip constraint (one world component of v_C = 0) of a :class:`RollingDisc`."""

    contact: str = ""
    #: Made as the sum of (dp/dq_j + omega_j x (C - p)) q_dot_j and a rate free of velocities
    #: (:func:`rolling_constraints`), each coefficient a function of q and t (omega is linear
    #: in the velocities, omega_j its derivative by q_dot_j): linear in the velocities always
    #: (the body's position and orientation are checked free of velocities, and the System
    #: replaces any NoSlip it is given by those it makes).
    linear_by_construction: ClassVar[bool] = True


GENERATED = (ContactHeight, NoSlip)


def rolling_sphere(body: str, radius: Any, name: str = "") -> RollingDisc:
    """A ball of radius ``radius`` (the rigid body ``body``, centred at its centre of mass)
    rolling without slipping on the plane z = 0: the torus with no hole, so its contact point
    is C = p - r e_z whatever its orientation.

    >>> rolling_sphere("ball", 2).tyre_radius
    2
    """
    return RollingDisc(body, 0, name=name, tyre_radius=radius)


def contact_offset(disc: RollingDisc, body: RigidBody) -> sp.ImmutableMatrix:
    """C - p = R d - r_t e_z, the contact point relative to the centre in world axes (the
    module docstring).

    >>> import lagrangian as lg
    >>> psi, theta, r = sp.symbols("psi theta r")
    >>> wheel = lg.RigidBody("w", 1, sp.eye(3), (0, 0, 0),
    ...                      orientation=lg.model.euler_rotation("ZXY", (psi, theta, 0)))
    >>> contact_offset(RollingDisc("w", r, "y"), wheel).T
    Matrix([[-r*sin(psi)*sin(theta), r*sin(theta)*cos(psi), -r*cos(theta)]])
    """
    geometry = _wheel_geometry(disc, body)
    back = _sympy_view(body, disc)
    return sp.ImmutableMatrix([back(geometry.rooted(e)) for e in geometry.offset])


@dataclass(frozen=True)
class _HorizontalLength:
    """s = |a x e_z| = sqrt(1 - a_z^2) of the unit axle a, in SymEngine: ``value`` is its
    closed form, or the placeholder ``_HorizontalLength.SYMBOL`` that keeps the square root out
    of every expansion; ``root`` is what the placeholder stands for, sqrt(1 - a_z^2)."""

    value: Any
    root: Any
    a_z: Any

    #: Stands for s in expressions until :meth:`rooted`; not a name a System can declare.
    SYMBOL: ClassVar[Any] = se.Symbol("s of the contact")

    @property
    def closed(self) -> bool:
        """True when s has a closed form (no square root)."""
        return self.value != self.SYMBOL

    def rooted(self, expr: Any) -> Any:
        """``expr`` with the placeholder replaced by sqrt(1 - a_z^2)."""
        return expr if self.closed else expr.xreplace({self.SYMBOL: self.root})


def _length_of(a_z: Any) -> _HorizontalLength:
    """s for the axle's vertical component a_z, found from its form: a number gives a number;
    a_z = +-sin(u) gives s = cos(u) and a_z = +-cos(u) gives s = sin(u) (a wheel leaning by u,
    or tilted from the vertical by u: the branch on which the wheel stands, s > 0, as
    sqrt(cos(u)^2) = cos(u) takes it); any other a_z keeps s = sqrt(1 - a_z^2) as a
    placeholder."""
    root = se.sqrt(1 - a_z**2)
    unsigned = -a_z if a_z.is_Mul and a_z.args[0] == -1 else a_z
    if a_z.is_Number:
        return _HorizontalLength(root, root, a_z)
    if isinstance(unsigned, se.sin):
        return _HorizontalLength(se.cos(unsigned.args[0]), root, a_z)
    if isinstance(unsigned, se.cos):
        return _HorizontalLength(se.sin(unsigned.args[0]), root, a_z)
    return _HorizontalLength(_HorizontalLength.SYMBOL, root, a_z)


@dataclass(frozen=True)
class _WheelGeometry:
    """A wheel's contact geometry in SymEngine, expanded, with s kept as
    ``_HorizontalLength.SYMBOL`` when it has no closed form: the offset C - p (world axes), and
    whether the wheel lies flat (s = 0: its axle vertical, C undefined; the offset is then
    that of the tyre alone)."""

    offset: tuple[Any, Any, Any]
    length: _HorizontalLength
    flat: bool = False
    #: The offset's entries as the products they were expanded from (the offset itself when
    #: it is not a product), whose degrees in sines and cosines bound the expansion's
    #: (:func:`_sine_powers`) from a few factors instead of every term.
    products: tuple[Any, Any, Any] | None = None

    def rooted(self, expr: Any) -> Any:
        """``expr`` with s written out."""
        return self.length.rooted(expr)


def _wheel_geometry(disc: RollingDisc, body: RigidBody) -> _WheelGeometry:
    """C - p = R d - r_t e_z with d = (a a_z - e_z) / s (the module docstring); a sphere
    (R = 0) has no axle and C - p = -r_t e_z."""
    tyre, radius = to_symengine(disc.tyre_radius), to_symengine(disc.radius)
    below = (se.Integer(0), se.Integer(0), -tyre)
    # the user's radius probed as given: its symbols' assumptions may decide it
    if not _plainly_not_zero(radius) and is_zero(disc.radius):
        one = se.Integer(1)
        return _WheelGeometry(below, _HorizontalLength(one, one, se.Integer(0)))
    a = _axle_in_world(disc, body)
    s = _length_of(a[2])
    if s.value == 0 or (
        not _plainly_not_zero(s.value) and is_zero(s.value if s.closed else s.root)
    ):
        return _WheelGeometry(below, s, flat=True)
    inverse = 1 / s.value
    products = (radius * a[0] * a[2] * inverse, radius * a[1] * a[2] * inverse)
    offset = (se.expand(products[0]), se.expand(products[1]), se.expand(-radius * s.value - tyre))
    return _WheelGeometry(offset, s, products=(*products, offset[2]))


def _plainly_not_zero(expr: Any) -> bool:
    """True for a SymEngine ``expr`` that is not identically zero at sight, as
    :func:`is_zero`'s probe finds it (a value above zero at its first point): a symbol (a
    radius rR), a number other than 0, the sine or cosine of an angle holding a symbol (the
    closed s of a leaning or tilted wheel); False where the probe decides."""
    if expr.is_Symbol:
        return True
    if expr.is_Number:
        return expr != 0
    return isinstance(expr, (se.sin, se.cos)) and bool(expr.args[0].free_symbols)


def _axle_in_world(disc: RollingDisc, body: RigidBody) -> tuple[Any, Any, Any]:
    """a = R n / |n|, expanded (SymEngine)."""
    n = unit_axis(_axle(disc, body))
    R = body.orientation.matrix  # type: ignore[union-attr]
    used = [(k, to_symengine(n[k])) for k in range(3) if n[k] != 0]
    memo: dict[Any, Any] = {}  # the entries of a product of rotations share their parts
    x, y, z = (
        se.expand(se.Add(*[to_symengine_sharing(R[i, k], memo) * n_k for k, n_k in used]))
        for i in range(3)
    )
    return x, y, z


def _axle(disc: RollingDisc, body: RigidBody) -> tuple[sp.Expr, ...]:
    if disc.axis is not None:
        return rotation_axis(disc.axis, "axis")
    if isinstance(body.inertia, Shape) and body.inertia.kind in WHEEL_SHAPES:
        return rotation_axis(body.inertia.axis, "axis")
    fix = "give its axle, axis: x, y or z (body axes), or give the body a disc, ring or cylinder"
    raise ModelError("no axle", [Problem("axis", f"the body {body.name!r} has no wheel axle", fix)])


def contact_point(disc: RollingDisc, body: RigidBody) -> tuple[sp.Expr, ...]:
    """C = p + r d, the lowest point of the disc's rim (world axes)."""
    geometry = _wheel_geometry(disc, body)
    back = _sympy_view(body, disc)
    return tuple(
        back(geometry.rooted(se.expand(to_symengine(p) + e)))
        for p, e in zip(body.position, geometry.offset)
    )


def rolling_constraints(disc: RollingDisc, body: RigidBody, coordinates: Any) -> tuple[Any, ...]:
    """The constraints of ``disc`` on ``body``: C_z = 0 (unless it holds identically), then
    the x and y components of v_C = p_dot + omega_s x (C - p) = 0, each the sum over the
    velocities of (dp/dq_j + omega_j x (C - p)) q_dot_j (omega_j = d omega_s / d q_dot_j) and
    of the explicit rate dp/dt + omega_t x (C - p)."""
    q = tuple(coordinates)
    back = _sympy_view(body, disc, q, [velocity(x) for x in q])
    return _constraints(disc, body, q, _wheel_geometry(disc, body), back)


def _constraints(
    disc: RollingDisc,
    body: RigidBody,
    q: tuple[sp.Symbol, ...],
    geometry: _WheelGeometry,
    back: SympyView,
) -> tuple[Any, ...]:
    """:func:`rolling_constraints` from the wheel's ``geometry``, converted back by ``back``
    (:func:`_sympy_view` of the wheel, the coordinates and their rates at least)."""
    rates = [to_symengine(velocity(x)) for x in q]
    memo: dict[Any, Any] = {}  # a steered wheel's centre repeats the fork's offsets
    position = [to_symengine_sharing(e, memo) for e in body.position]
    offset = geometry.offset
    height = se.expand(position[2] + offset[2])
    omega = angular_velocity_terms(body.orientation, q, body=False)  # world axes
    at_rest = {v: 0 for v in rates}
    turns = [[se.diff(w, v) for w in omega] for v in rates]
    turns.append([w.xreplace(at_rest) for w in omega])  # omega_t, of a rheonomic orientation
    variables = [to_symengine(x) for x in (*q, t)]
    sines = _sine_powers(position[:2], omega, geometry)
    slip = []
    # each velocity's coefficient times the velocity, summed in SymEngine and converted
    # once: SymPy's constructors give the same sum of the same products as converting the
    # coefficients and multiplying and summing them there (no two terms share a velocity)
    fast_rates = [*rates, se.Integer(1)]
    for k in (0, 1):  # the x and y components of omega_j x (C - p): rows of the cross product
        i, j = (k + 1) % 3, (k + 2) % 3
        terms = []
        for rate, variable, w in zip(fast_rates, variables, turns):
            part = se.diff(position[k], variable) + w[i] * offset[j] - w[j] * offset[i]
            terms.append(_tidy(part, geometry.length, sines) * rate)
        slip.append(geometry.rooted(se.Add(*terms)))  # s written out once per sum
    name = disc.contact
    made: list[tuple[Any, Any]] = []  # (constraint, its expression in SymEngine)
    if height != 0:
        rooted = geometry.rooted(height)
        if not is_zero(rooted):
            made.append((ContactHeight(back(rooted), f"{name} height", name), rooted))
    for k, axis in ((0, "x"), (1, "y")):
        made.append((NoSlip(back(slip[k]), f"{name} slip {axis}", name), slip[k]))
    for constraint, fast in made:
        MADE.get(constraint, lambda _: Made(fast, back))  # noqa: B023 (called at once)
    return tuple(constraint for constraint, _ in made)


def _tidy(expr: Any, length: _HorizontalLength, sines: dict[Any, Any] | None) -> Any:
    """``expr`` expanded and reduced by sin(u)^2 = 1 - cos(u)^2 where that makes it shorter;
    with s as a placeholder also over the common denominator s (s^2 = 1 - a_z^2), where that
    is shorter (the spin's coefficient a x (C - p) is -R (a x e_z) / s so written, not
    -R (a x e_z) (s + a_z^2 / s)).  ``sines``: every sine power the expansions can hold with
    its form in cosines (:func:`_sine_powers`), or None to find them in each."""
    plain, plain_terms = _shorter_counted(se.expand(expr), sines)
    if length.closed or not plain.has(length.SYMBOL):
        return plain
    numerator, numerator_terms = _shorter_counted(_over_s(plain, length), sines)
    shorter = (numerator_terms or _terms(numerator)) < (plain_terms or _terms(plain))
    return numerator / length.SYMBOL if shorter else plain


def _over_s(plain: Any, length: _HorizontalLength) -> Any:
    """s ``plain``, expanded with s^2 = 1 - a_z^2, for an expanded coefficient of a wheel's
    constraints: plain = A / s + B + C s, the offset C - p holding s only as 1 / s (its
    horizontal entries) and as s (its vertical one), and the centre's derivatives and the
    angular velocity none, so s plain = A + B s + C (1 - a_z^2).  Only C's products are
    expanded: A and B s are expanded already (the same sum as expanding s plain with s^2
    replaced, without rebuilding and expanding again the terms that do not change)."""
    s = length.SYMBOL
    A, B, C = (plain.coeff(s, k) for k in (-1, 0, 1))
    return se.Add(A, se.expand(B * s, deep=False), se.expand(C * (1 - length.a_z**2)))


def _shorter_counted(expr: Any, sines: dict[Any, Any] | None) -> tuple[Any, int | None]:
    """The expanded ``expr`` with each sin(u)^k, k >= 2, written sin(u)^(k mod 2)
    (1 - cos(u)^2)^(k div 2) (a normal form of polynomials in sines and cosines), where that
    gives fewer terms, and its number of terms when it was counted (else None).  ``sines``:
    those forms for every sine power ``expr`` can hold (a superset: the powers it does not
    hold replace nothing), or None to find its powers."""
    table = _found_sine_powers(expr) if sines is None else sines
    if not table:
        return expr, None
    written = expr.xreplace(table)
    if sines is not None and written == expr:  # it holds none of the powers
        return expr, None
    reduced = se.expand(written)
    reduced_terms, terms = _terms(reduced), _terms(expr)
    return (reduced, reduced_terms) if reduced_terms < terms else (expr, terms)


def _found_sine_powers(expr: Any) -> dict[Any, Any]:
    """The sine powers sin(u)^k, k >= 2, in ``expr`` with their forms in cosines."""
    table = {}
    for power in _powers(expr):
        written = _in_cosines(power)
        if written is not None:
            table[power] = written
    return table


@remembered(maxsize=SINE_POWERS)
def _in_cosines(power: Any) -> Any:
    """sin(u)^k, k >= 2, as sin(u)^(k mod 2) (1 - cos(u)^2)^(k div 2); None for any other
    power (the same few recur in every coefficient of a wheel's constraints)."""
    base, exponent = power.args
    if not (isinstance(base, se.sin) and exponent.is_Integer and int(exponent) >= 2):
        return None
    k, rest = divmod(int(exponent), 2)
    return base**rest * (1 - se.cos(base.args[0]) ** 2) ** k


def _powers(expr: Any) -> list[Any]:
    """The powers in ``expr``, from a walk that enters each shared part once (SymEngine's
    ``atoms`` walks the whole tree)."""
    return [part for part in distinct_parts(expr) if isinstance(part, se.Pow)]


def _sine_powers(position: Any, omega: Any, geometry: _WheelGeometry) -> dict[Any, Any] | None:
    """Every sine power sin(u)^k, k >= 2, that the expanded coefficients of a wheel's no-slip
    constraints (and their numerators over s) can hold, with its form in cosines: for each
    angle u, k up to the degree bound below; None when the inputs are not polynomials in
    sines and cosines of angles free of functions (the powers are then found in each).

    With D_u the total degree in sin(u) and cos(u) together (:func:`_trig_degrees`), a
    coefficient dp/dq_j + omega_j x (C - p) has D_u <= max(D_u(p), D_u(omega) + D_u(C - p)):
    d/dq_j keeps D_u (d sin(u) = cos(u) du, du free of sines), as does d/d q_dot_j of omega;
    expanding never raises it; writing sin^2 as 1 - cos^2 keeps it; a numerator over s gains
    2 D_u(a_z) where s^2 becomes 1 - a_z^2.  D_u(C - p) is read off the products the offset
    was expanded from where it can be (a product's D_u is its factors' sum; expanding never
    raises it), else off the expanded offset (a product with 1 / cos(u) in it)."""
    memo: dict[Any, dict[Any, int] | None] = {}
    found = [_trig_degrees(e, memo) for e in (*position, *omega)]
    for product, expanded in zip(geometry.products or geometry.offset, geometry.offset):
        degrees = _trig_degrees(product, memo)
        found.append(_trig_degrees(expanded, memo) if degrees is None else degrees)
    found.append(_trig_degrees(geometry.length.a_z, memo))
    parts = [degrees for degrees in found if degrees is not None]
    if len(parts) < len(found):
        return None
    p, w, c, a_z = parts[:2], parts[2:5], parts[5:8], parts[8]
    bounds: dict[Any, int] = {}
    for u in set().union(*parts):
        turning = max(d.get(u, 0) for d in w) + max(d.get(u, 0) for d in c)
        plain = max(turning, *(d.get(u, 0) for d in p))
        bounds[u] = plain + 2 * a_z.get(u, 0)
    return {
        se.sin(u) ** k: _in_cosines(se.sin(u) ** k)
        for u, bound in bounds.items()
        for k in range(2, bound + 1)
    }


def _trig_degrees(expr: Any, memo: dict[Any, dict[Any, int] | None]) -> dict[Any, int] | None:
    """For ``expr`` (SymEngine) a polynomial in sines and cosines of angles free of functions,
    with coefficients rational in symbols: angle u -> the highest total degree in sin(u) and
    cos(u) together of a product in its expansion (a bound); None for anything else
    (``memo``: the parts found before; the dicts are shared, never changed)."""
    if expr.is_Symbol or expr.is_Number:
        return _NO_ANGLES
    known = memo.get(expr, _UNSEEN)
    if known is not _UNSEEN:
        return known  # type: ignore[return-value]
    found: dict[Any, int] | None = {}
    if expr.is_Add or expr.is_Mul:
        merged: dict[Any, int] = {}
        add = expr.is_Add
        for arg in expr.args:
            degrees = _trig_degrees(arg, memo)
            if degrees is None:
                memo[expr] = None
                return None
            for u, d in degrees.items():
                merged[u] = max(merged.get(u, 0), d) if add else merged.get(u, 0) + d
        found = merged
    elif expr.is_Pow:
        base, exponent = expr.args
        degrees = _trig_degrees(base, memo)
        if degrees is None or not exponent.is_Number:
            found = None
        elif exponent.is_Integer and exponent > 0:
            found = {u: d * int(exponent) for u, d in degrees.items()}
        elif degrees:  # a sine under a root or in a denominator
            found = None
    elif isinstance(expr, (se.sin, se.cos)):
        angle = expr.args[0]
        found = {angle: 1} if _trig_degrees(angle, memo) == {} else None
    else:
        found = None
    memo[expr] = found
    return found


#: The degrees of a symbol or a number (:func:`_trig_degrees`), and of no part found yet.
_NO_ANGLES: dict[Any, int] = {}
_UNSEEN = object()


def _terms(expr: Any) -> int:
    return len(expr.args) if expr.is_Add else 1


def _sympy_view(body: RigidBody, disc: RollingDisc, *more: Any) -> SympyView:
    """SymEngine results back as SymPy with the symbol objects of the body and the disc (which
    may carry assumptions SymEngine does not keep), each distinct part once for all the
    constraints of the disc (the square root of a steered wheel's tilt is in most of their
    terms), sums and products that are canonical already made without SymPy's general
    evaluation (``more``: further symbols)."""
    symbols: set[sp.Symbol] = {t}
    matrix = body.orientation.matrix  # type: ignore[union-attr]
    for value in (*body.position, *matrix, disc.radius, disc.tyre_radius):
        symbols |= free_symbols(value)  # the entries of a product of rotations share parts
    for group in more:
        symbols.update(group)
    return SympyView(s for s in symbols if isinstance(s, sp.Symbol))


def add_rolling_constraints(values: dict[str, Any]) -> list[Problem]:
    """Replace the constraints made by rolling discs in the canonical System ``values`` with
    those of its ``rolling`` discs now (after the bodies' orientations are resolved); the
    problems found (an unknown body, a planar one, no axle, a disc lying flat)."""
    problems: list[Problem] = []
    kept = [c for c in values["constraints"] if not isinstance(c, GENERATED)]
    bodies = {b.name: b for b in values["rigid_bodies"]}
    scope = NameScope(values)
    made: list[Any] = []
    q = tuple(values["coordinates"])
    # one conversion for all the wheels (the sines of the frames they share converted once),
    # with the System's own symbols: its expressions hold no others (canonical objects of
    # each name; a name not declared is refused by the validator)
    back = SympyView([t, *q, *values["parameters"], *(velocity(x) for x in q)])
    for i, disc in enumerate(values["rolling"]):
        field = f"rolling[{i}]"
        if not _rolls(disc, bodies):
            problems.append(_body_problem(disc, field, bodies))
            continue
        body = bodies[disc.body]
        before = len(problems)
        scope.check(disc.radius, f"{field}.radius", CONFIGURATION, problems)
        scope.check(disc.tyre_radius, f"{field}.tyre_radius", CONFIGURATION, problems)
        if len(problems) > before:
            continue
        try:
            made += _made_by(disc, body, q, field, problems, back)
        except ModelError as error:
            problems += [Problem(f"{field}.{p.field}", p.message, p.fix) for p in error.problems]
        except se.SympifyError as error:  # a function SymEngine does not know
            fix = "write the body's position and orientation with the model language's functions"
            problems.append(Problem(field, f"the body {disc.body!r}: {error}", fix))
    values["constraints"] = (*kept, *made)
    return problems


def _made_by(
    disc: RollingDisc,
    body: RigidBody,
    q: tuple[sp.Symbol, ...],
    field: str,
    problems: list,
    back: SympyView,
) -> tuple[Any, ...]:
    """The constraints of ``disc``, or none and a problem when it lies flat."""
    geometry = _wheel_geometry(disc, body)
    if geometry.flat:
        fix = "orient the body so that its axle is not vertical"
        message = f"the disc of body {disc.body!r} lies flat on the plane"
        problems.append(Problem(field, message, fix))
        return ()
    return _constraints(disc, body, q, geometry, back)


def move_contact_forces(values: dict[str, Any]) -> None:
    """In the canonical System ``values``, replace every force applied at the contact point
    of a rolling disc by the same force at the body's centre and the torque (r d) x F (world
    axes): together they do the virtual work F . delta r_C of the material point at C."""
    bodies = {b.name: b for b in values["rigid_bodies"]}
    contacts = {}
    for disc in values["rolling"]:
        body = bodies.get(disc.body)
        if body is not None and not body.planar and _spatial(body):
            contacts[disc.contact] = (disc, body)
    forces, torques = [], list(values["torques"])
    for force in values["forces"]:
        if not (isinstance(force.at, str) and force.at in contacts):
            forces.append(force)
            continue
        disc, body = contacts[force.at]
        forces.append(Force(body.name, force.force, force.name))
        if not (isinstance(force.force, tuple) and len(force.force) == 3):
            continue  # the validator reports its shape
        arm, push = sp.Matrix(contact_offset(disc, body)), sp.Matrix(force.force)
        moment = tuple(sp.expand(e) for e in arm.cross(push))
        torques.append(Torque(body.name, moment, force.name or f"{force.at} moment"))
    values["forces"], values["torques"] = tuple(forces), tuple(torques)


def _rolls(disc: RollingDisc, bodies: dict[str, RigidBody]) -> bool:
    """Whether ``disc`` is on a 3-D rigid body of ``bodies`` (else a problem)."""
    body = bodies.get(disc.body)
    return body is not None and not body.planar and _spatial(body)


def _spatial(body: RigidBody) -> bool:
    position = body.position
    return isinstance(position, tuple) and len(position) == 3 and body.orientation is not None


def _body_problem(disc: RollingDisc, field: str, bodies: dict[str, RigidBody]) -> Problem:
    if disc.body in bodies:
        message = f"the body {disc.body!r} is not a 3-D rigid body"
        return Problem(f"{field}.body", message, "give it a 3-D position and an orientation")
    close = difflib.get_close_matches(str(disc.body), sorted(bodies), n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    message = f"unknown rigid body {disc.body!r}"
    return Problem(f"{field}.body", message, hint + "name one of the rigid_bodies")
