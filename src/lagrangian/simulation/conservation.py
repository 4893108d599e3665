"""Which columns of a Trajectory are constants of the motion, and why the others change.

A drift report compares a quantity with its start only when the system conserves it; a
number for a quantity the physics changes would read as an integration error.  The energy
function

    h = sum_j q_dot_j dL/dq_dot_j - L,
    dh/dt = sum_j Q_j q_dot_j - sum_j q_dot_j dF/dq_dot_j - dL/dt|explicit - sum_j lambda_j b_j

(:func:`lagrangian.analysis.energy.energy_conservation`, Goldstein §2.7) is conserved unless
one of its terms remains at the run's parameter values; each term is a reason, in the words
of :data:`REASONS`: ``forcing``, ``dissipation``, ``explicit time dependence``, ``constraints
that do work``.  When h is conserved but differs from T + V (a bead on a rotating hoop: h is
the Jacobi integral), T + V is not conserved, and the reason says why it differs.  The
momentum of a cyclic coordinate is conserved unless a force, dissipation or a constraint acts
along it (:func:`lagrangian.analysis.cyclic_coordinates`).

The result maps each column that is *not* conserved to its reason; the other columns are
conserved.

>>> import lagrangian as lg
>>> eom = lg.derive(lg.examples.mass_spring_damper())
>>> not_conserved(eom, {"m": 1.0, "k": 1.0, "B": 0.5, "f": 0.0}, has_energy_function=False)
{'energy': 'dissipation'}
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy as sp

from lagrangian.analysis.energy import energy_conservation, homogeneous_parts
from lagrangian.derivation import EquationsOfMotion
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.probe import is_zero

#: The reasons an energy is not conserved, each naming a term of dh/dt.
REASONS = ("forcing", "dissipation", "explicit time dependence", "constraints that do work")
#: What changes the momentum of a cyclic coordinate (analysis.momenta's obstructions).
MOMENTUM_REASONS = {"force": "forcing", "dissipation": "dissipation", "constraint": "constraints"}

_RATES: IdentityCache[EquationsOfMotion, dict[str, sp.Expr] | None] = IdentityCache()


def not_conserved(
    eom: EquationsOfMotion,
    parameters: Mapping[str, float],
    has_energy_function: bool,
    momenta: Mapping[str, Sequence[str]] | None = None,
) -> dict[str, str]:
    """The columns that are not conserved, with why: ``energy`` (T + V), ``energy_function``
    (h, when it is a column of its own: ``has_energy_function``) and the momenta ``momenta``
    names (column -> what changes it: analysis.momenta's ``obstructions``)."""
    reasons = energy_reasons(eom, parameters)
    found: dict[str, str] = {}
    if reasons:
        found["energy"] = ", ".join(reasons)
        if has_energy_function:
            found["energy_function"] = found["energy"]
    elif has_energy_function:
        found["energy"] = total_energy_reason(eom)
    for name, kinds in (momenta or {}).items():
        found[name] = ", ".join(MOMENTUM_REASONS.get(kind, kind) for kind in kinds)
    return found


def energy_reasons(eom: EquationsOfMotion, parameters: Mapping[str, float]) -> tuple[str, ...]:
    """The terms of dh/dt that do not vanish at the ``parameters`` (by name), in the words of
    :data:`REASONS`; empty when h is conserved."""
    rates = _RATES.get(eom, _rates)
    if rates is None:
        return ()
    numbers = {s: parameters[s.name] for s in eom.parameters if s.name in parameters}
    if is_zero(rates["total"].xreplace(numbers)):
        return ()
    return tuple(r for r in REASONS if not is_zero(rates[r].xreplace(numbers)))


def total_energy_reason(eom: EquationsOfMotion) -> str:
    """Why T + V is not conserved although h is: h differs from it (T not a quadratic form
    in the velocities, or a velocity-dependent potential)."""
    parts = homogeneous_parts(eom.kinetic_energy, eom.velocities)
    if parts is not None and (0 in parts or 1 in parts):
        return "constraints that do work (the coordinates move with time)"
    if eom.velocity_potential != 0:
        return "the velocity-dependent potential U (h = T + V + U(q, 0, t))"
    return "T is not quadratic in the velocities"


def _rates(eom: EquationsOfMotion) -> dict[str, sp.Expr] | None:
    """Each term of dh/dt by reason, and their sum ``total``; None when no term can be there
    (the analysis's answer without its cost: it derives every Euler-Lagrange step)."""
    if _nothing_changes_h(eom):
        return None
    verdict = energy_conservation(eom)
    if verdict.conserved:
        return None
    velocities = eom.velocities
    return {
        "forcing": sum((q * v for q, v in zip(eom.generalized_forces, velocities)), sp.S.Zero),
        "dissipation": sum((f * v for f, v in zip(eom.dissipation_forces, velocities)), sp.S.Zero),
        "explicit time dependence": eom.lagrangian.diff(eom.time),
        "constraints that do work": verdict.constraint_power,
        "total": verdict.rate,
    }


def _nothing_changes_h(eom: EquationsOfMotion) -> bool:
    """Whether every term of dh/dt is absent as written: no t in L, no dissipation, no
    applied force, and constraints that neither move with time nor have a velocity-free term
    (b = 0: they do no work)."""
    if eom.time in eom.lagrangian.free_symbols:
        return False
    if any(f != 0 for f in eom.dissipation_forces) or any(q != 0 for q in eom.generalized_forces):
        return False
    at_rest = {v: 0 for v in eom.velocities}
    for constraint in eom.system.constraints:
        expression = constraint.expression
        if eom.time in expression.free_symbols:
            return False
        if constraint.kind == "velocity" and expression.xreplace(at_rest) != 0:
            return False
    return True
