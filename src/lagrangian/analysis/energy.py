"""The energy function and when it is conserved (Goldstein, Classical Mechanics, 3rd ed., §2.7).

    h = sum_j q_dot_j dL/dq_dot_j - L
    dh/dt = -sum_j q_dot_j dF/dq_dot_j + sum_j Q_j q_dot_j - dL/dt|explicit

(from the Euler–Lagrange equations d/dt dL/dq_dot = dL/dq + Q - dF/dq_dot).  With constraints
the multiplier forces add sum_j lambda_j a_j . q_dot = -sum_j lambda_j b_j: constraints that do
not move (b = 0, scleronomic) do no work and keep h; rheonomic ones do work.  With
L = L2 + L1 + L0 homogeneous in the velocities, h = L2 - L0: it is T + V exactly when T is a
quadratic form in the velocities (scleronomic coordinates) and U at most linear in them.

>>> import lagrangian as lg
>>> energy_conservation(lg.examples.planet()).conserved
True
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, Values, equations_of, evaluate
from lagrangian.analysis.evaluation import (
    EvaluationContext,
    condition_text,
    evaluation_context,
    names_text,
    vanishes,
)
from lagrangian.analysis.manifold.constraint_manifold import (
    constraint_manifold,
    vanishes_on_manifold,
)
from lagrangian.analysis.names import OutputNames
from lagrangian.analysis.simplification import simplify_small
from lagrangian.derivation import EquationsOfMotion
from lagrangian.derivation.energies import energy_function as expanded_energy_function
from lagrangian.derivation.energies import kinetic_plus_potential
from lagrangian.model.constraints import Unilateral, label
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import depends_on, is_zero


def energy_function(subject: Subject) -> sp.Expr:
    """h = sum_j q_dot_j dL/dq_dot_j - L: T + V + U(q, 0, t) as the equations write T
    (1/2 q_dot^T M q_dot, its entries collected) when T is a quadratic form in the velocities
    and U at most linear in them (:func:`collected_energy_function`), expanded otherwise
    (computed once per System).

    >>> import lagrangian as lg
    >>> energy_function(lg.examples.simple_pendulum())
    -g*l*m*cos(theta) + l**2*m*theta_dot**2/2
    """
    return _energy_function(equations_of(subject))[0]


def _energy_function(eom: EquationsOfMotion) -> tuple[sp.Expr, bool]:
    """h of ``eom`` and whether it is the collected T + V + U(q, 0, t), made once."""
    return _ENERGY_FUNCTIONS.get(eom, _energy_function_of)


def _energy_function_of(eom: EquationsOfMotion) -> tuple[sp.Expr, bool]:
    collected = collected_energy_function(eom)
    if collected is None:
        return expanded_energy_function(eom.system), False
    return collected, True


#: h per EquationsOfMotion: the report's parts (energy, conserved quantities) share one.
_ENERGY_FUNCTIONS: IdentityCache[EquationsOfMotion, tuple[sp.Expr, bool]] = IdentityCache()


def collected_energy_function(eom: EquationsOfMotion) -> sp.Expr | None:
    """h = T + V + U(q, 0, t), nothing expanded, when T as written can only have terms of
    degree 2 in the velocities and U of degree 0 or 1 (read from the expressions as written,
    :func:`velocity_degrees`); None otherwise.

    With L = L2 + L1 + L0 homogeneous in the velocities, h = L2 - L0 (Euler's theorem on
    homogeneous functions: sum_j q_dot_j dL_d/dq_dot_j = d L_d); here L2 = T, L1 = -U1 and
    L0 = -V - U(q, 0, t).  A chain's T = 1/2 q_dot^T M q_dot keeps M's entries as the
    equations show them (sums of masses times a cosine): n^2 terms, where expanded h has
    n^3/6.
    """
    velocities = eom.velocities
    kinetic, potential, velocity_potential = (
        eom.kinetic_energy,
        eom.potential_energy,
        eom.velocity_potential,
    )
    if velocity_degrees(kinetic, velocities) != {2} or depends_on(potential, velocities):
        return None
    u_degrees = velocity_degrees(velocity_potential, velocities)
    if u_degrees is None or not u_degrees <= {0, 1}:
        return None
    scalar = velocity_potential.xreplace({v: 0 for v in velocities})
    return kinetic + potential + scalar


def homogeneous_parts(expr: sp.Expr, velocities: Sequence[sp.Symbol]) -> dict[int, sp.Expr] | None:
    """``expr`` split by total degree in the velocities, {2: T2, 1: T1, 0: T0}; None when it
    is not a polynomial in them."""
    expr = sp.expand(expr)
    if not depends_on(expr, velocities):
        return {0: expr} if expr != 0 else {}
    try:
        poly = sp.Poly(expr, *velocities)
    except sp.PolynomialError:
        return None
    if any(depends_on(c, velocities) for c in poly.coeffs()):
        return None
    parts: dict[int, sp.Expr] = {}
    for monomial, coefficient in poly.terms():
        degree = sum(monomial)
        term = coefficient * sp.Mul(*[v**k for v, k in zip(velocities, monomial)])
        parts[degree] = parts.get(degree, sp.Integer(0)) + term
    return {d: p for d, p in parts.items() if p != 0}


def velocity_degrees(expr: sp.Expr, velocities: Sequence[sp.Symbol]) -> frozenset[int] | None:
    """The degrees in the velocities that the terms of ``expr`` can have once expanded, read
    from ``expr`` as written (sums, products and whole powers; nothing is expanded); None
    when a velocity appears otherwise (in a function, a fractional or negative power).  A
    degree found may cancel out; one not found cannot appear.

    >>> x, v, w = sp.symbols("x v w")
    >>> sorted(velocity_degrees((x + 1) * (v * w + x * v**2) + 3, [v, w]))
    [0, 2]
    >>> velocity_degrees(sp.cos(v) * w, [v, w]) is None
    True
    """
    wanted = set(velocities)

    def degrees(node: sp.Basic) -> frozenset[int] | None:
        if wanted.isdisjoint(node.free_symbols):
            return frozenset({0})
        if node in wanted:
            return frozenset({1})
        if node.is_Add or node.is_Mul:
            found: frozenset[int] | None = frozenset() if node.is_Add else frozenset({0})
            for argument in node.args:
                inner = degrees(argument)
                if inner is None or found is None:
                    return None
                found = (
                    found | inner if node.is_Add else frozenset(a + b for a in found for b in inner)
                )
            return found
        if node.is_Pow and node.exp.is_Integer and node.exp > 0:
            base = degrees(node.base)
            if base is None:
                return None
            found = frozenset({0})
            for _ in range(int(node.exp)):
                found = frozenset(a + b for a in found for b in base)
            return found
        return None

    return degrees(to_sympy(expr))


@dataclass(frozen=True)
class EnergyConservation:
    """Whether h is a constant of the motion and whether it is T + V, each with its reason.

    ``rate`` is dh/dt along the motion; ``total_energy`` is T + V (+ U(q, 0, t), the scalar
    potential of a velocity-dependent potential such as q phi).  On a constraint manifold
    ``constraint_power`` is the work rate of the constraint forces, sum_j lambda_j a_j .
    q_dot = -sum_j lambda_j b_j (zero for constraints that do not move), part of ``rate``.
    """

    energy_function: sp.Expr
    conserved: bool
    reason: str
    rate: sp.Expr
    total_energy: sp.Expr
    equals_total_energy: bool
    total_energy_reason: str
    constraint_power: sp.Expr = sp.Integer(0)
    #: The parameter values under which h is conserved when dh/dt vanishes only at the
    #: values given (``Eq(F, 0)``: a force F given as 0); ``sp.true`` otherwise.
    condition: sp.Basic = sp.true


def _power_terms(eom: EquationsOfMotion) -> tuple[sp.Expr, list[str]]:
    """dh/dt and, for every contribution that does not vanish, why."""
    reasons = []
    pieces = (eom.kinetic_energy, eom.potential_energy, eom.velocity_potential)
    # L = T - V - U is rebuilt on every request (n^2 terms for a chain): asked only when t is in it
    in_time = any(eom.time in piece.free_symbols for piece in pieces)
    explicit = eom.lagrangian.diff(eom.time) if in_time else sp.Integer(0)
    if not is_zero(explicit):
        reasons.append(f"L depends explicitly on t (dL/dt|explicit = {simplify_small(explicit)})")
    friction = sum((-v * f for v, f in zip(eom.velocities, eom.dissipation_forces)), sp.Integer(0))
    if not is_zero(friction):
        f = eom.dissipation_function
        quadratic = is_zero(friction - 2 * f)
        reasons.append(
            f"the dissipation function F = {f} removes energy at the rate "
            + ("2F" if quadratic else "sum q_dot dF/dq_dot")
        )
    work = sp.Integer(0)
    for q, v, force in zip(eom.coordinates, eom.velocities, eom.generalized_forces):
        if is_zero(force):
            continue
        work += force * v
        timed = " (it depends on t)" if depends_on(force, [eom.time]) else ""
        reasons.append(
            f"the applied force Q_{q.name} = {force}{timed} does work at the rate {force * v}"
        )
    return sp.expand(work - friction - explicit), reasons


def _total_energy_reason(eom: EquationsOfMotion, equal: bool) -> str:
    velocities, h = eom.velocities, OutputNames.of(eom).energy
    u_parts = homogeneous_parts(eom.velocity_potential, velocities)
    scalar = " + U(q, 0, t)" if u_parts and 0 in u_parts else ""
    if equal:
        return (
            f"T is a quadratic form in the velocities and U at most linear in them, so "
            f"{h} = T + V{scalar}"
        )
    t_parts = _kinetic_parts(eom.kinetic_energy, velocities)
    if t_parts is None:
        return f"T is not a polynomial of degree 2 in the velocities, so {h} is not T + V"
    higher = [d for d in sorted(t_parts) if d > 2]
    if higher:
        degrees = ", ".join(str(d) for d in higher)
        return (
            f"T has terms of degree {degrees} in the velocities (not a quadratic form), "
            f"so {h} is not T + V"
        )
    causes = [f"degree {d} (T{d} = {simplify_small(t_parts[d])})" for d in (0, 1) if d in t_parts]
    if causes:
        return (
            "T has terms of " + " and ".join(causes) + " in the velocities (the coordinates "
            f"move with time: rheonomic), so {h} = T2 - T0 + V is not T + V"
        )
    if u_parts is None or any(d >= 2 for d in u_parts):
        return "the velocity-dependent potential U is not linear in the velocities"
    return f"{h} differs from T + V"


def _kinetic_parts(kinetic: sp.Expr, velocities: Sequence[sp.Symbol]) -> dict[int, sp.Expr] | None:
    """:func:`homogeneous_parts` of T, or, when T as written can only have terms quadratic in
    the velocities, {2: T} (the bulk of a large T, neither expanded nor made a polynomial:
    the reasons name only the parts of other degrees, and T has none)."""
    if velocity_degrees(kinetic, velocities) == {2}:
        return {2: kinetic}
    return homogeneous_parts(kinetic, velocities)


def _jumps(context: EvaluationContext) -> str:
    """What impacts and transitions do to a conserved h, at the values given: h holds between
    them; an impact with e = 1 keeps it, one with e < 1 loses energy, a transition's reset
    may change it."""
    system = context.eom.system
    by_coefficient: dict[str, list[str]] = {}  # e -> the constraints' labels, in order
    for index, c in enumerate(system.constraints):
        if not isinstance(c, Unilateral) or c.restitution is None:
            continue
        e = evaluate(c.restitution, context.values)
        key = "1" if vanishes(e - 1) else f"{float(e):g}"
        by_coefficient.setdefault(key, []).append(label(index, c))
    notes = [_impacts_note(labels, e) for e, labels in by_coefficient.items()]
    if system.transitions:
        names = ", ".join(t.name for t in system.transitions)
        notes.append(f"the resets of the transitions {names} may change it")
    return f"; between impacts and transitions only: {'; '.join(notes)}" if notes else ""


def _impacts_note(labels: list[str], e: str) -> str:
    """What impacts with coefficient ``e`` do to h, said once for all the constraints that
    have it: ``an impact on 'floor' (constraints[0]) (e = 0.8) loses energy``, or ``impacts
    on the 22 constraints 'left1' (constraints[0]), ... (e = 1) keep it too``."""
    if len(labels) == 1:
        verdict = "keeps it too" if e == "1" else "loses energy"
        return f"an impact on {labels[0]} (e = {e}) {verdict}"
    shown = names_text(labels)
    verdict = "keep it too" if e == "1" else "lose energy"
    return f"impacts on the {len(labels)} constraints {shown} (e = {e}) {verdict}"


def _constraint_power(eom: EquationsOfMotion) -> tuple[sp.Expr, list[str], list[str]]:
    """-sum_j lambda_j b_j over the moving constraints, why each works, and why the applied
    terms vanish on the manifold when they do (empty when there are no constraints)."""
    manifold = constraint_manifold(eom)
    if manifold is None:
        return sp.Integer(0), [], []
    power = sp.Integer(0)
    reasons = []
    for row in manifold.moving:
        lam, b = manifold.multipliers[row], manifold.rates[row]
        power += -lam * b
        reasons.append(
            f"the constraint {manifold.labels[row]} moves with time (rheonomic, b = "
            f"{simplify_small(b)}), so its force {lam}*a does work at the rate "
            f"{simplify_small(-lam * b)}"
        )
    # a manifold of no constraint (the unilateral ones left out, released) has none to name
    kept = manifold.labels
    still = [f"constraints {', '.join(kept)} do no work"] if kept and not reasons else []
    return power, reasons, still


def energy_conservation(subject: Subject, parameters: Values | None = None) -> EnergyConservation:
    """Is h conserved (no explicit t, no dissipation, no working applied force, no moving
    constraint), and is it T + V?  Each answer with its reason, and dh/dt as an expression
    (with the multipliers lambda_j of :mod:`lagrangian.analysis.manifold.constraint_manifold` on a
    constrained
    system; applied terms that vanish wherever the constraints hold are dropped).

    >>> import lagrangian as lg
    >>> energy_conservation(lg.examples.mass_spring_damper()).rate
    -B*x_dot**2 + f*x_dot
    """
    return energy_at_values(evaluation_context(subject, parameters))


def energy_at_values(context: EvaluationContext) -> EnergyConservation:
    """:func:`energy_conservation` at the parameter values of ``context``: a rate dh/dt
    that vanishes only there (a force F given as 0) keeps h, under that condition."""
    eom = context.eom
    h, collected = _energy_function(eom)
    name = OutputNames.of(eom).energy
    rate, reasons = _power_terms(eom)
    power, working, idle = _constraint_power(eom)
    if idle and reasons and vanishes_on_manifold(rate, eom):
        idle.append("the applied terms (" + "; ".join(reasons) + ") vanish on the manifold")
        rate, reasons = sp.Integer(0), []
    rate, reasons = sp.expand(rate + power), reasons + working
    conserved = is_zero(rate)
    if conserved:
        reason = (
            f"d{name}/dt = 0: L has no explicit time, and no dissipation or applied force works"
        )
        if reasons:
            reason += " (the contributions " + "; ".join(reasons) + " cancel)"
        if idle:
            reason += "; the " + "; ".join(idle) + " (scleronomic: b = 0, A q_dot = 0)"
    else:
        reason = f"{name} is not conserved: " + "; ".join(reasons)
    if conserved:
        reason += _jumps(context)
    condition = None if conserved else context.vanishing_condition(rate)
    if condition is not None:
        conserved = True
        reason = (
            f"d{name}/dt = {rate} vanishes at the given parameter values "
            f"({condition_text(condition)}), so {name} is conserved there (for other values "
            f"{reason})"
        )
    # h written as T + V + U(q, 0, t) is that total by construction
    total, equal = (h, True) if collected else _expanded_total_energy(eom, h)
    return EnergyConservation(
        energy_function=h,
        conserved=conserved,
        reason=reason,
        rate=rate,
        total_energy=total,
        equals_total_energy=equal,
        total_energy_reason=_total_energy_reason(eom, equal),
        constraint_power=sp.expand(power),
        condition=sp.true if condition is None else condition,
    )


def _expanded_total_energy(eom: EquationsOfMotion, h: sp.Expr) -> tuple[sp.Expr, bool]:
    """T + V + U(q, 0, t) expanded, and whether it is the expanded ``h``."""
    scalar = eom.velocity_potential.xreplace({v: 0 for v in eom.velocities})
    if scalar == 0:  # T + V, expanded once per System (a chain's has n^3/3 terms)
        total = kinetic_plus_potential(eom.system)
    else:
        total = sp.expand(eom.kinetic_energy + eom.potential_energy + scalar)
    # both expanded the same way: equal expressions need no difference built and probed
    return total, h == total or is_zero(h - total)
