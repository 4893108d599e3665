"""Conjugate momenta and cyclic coordinates (seed 000, "Conserved Quantities").

    p_j = dL/dq_dot_j,       d/dt p_j = dL/dq_j + Q_j - dF/dq_dot_j,

so a coordinate that L does not contain, on which no applied or dissipative force acts, is
cyclic: its momentum is a constant of the motion.

>>> import lagrangian as lg
>>> [c.coordinate for c in cyclic_coordinates(lg.examples.planet())]
[theta]
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, equations_of
from lagrangian.derivation import EquationsOfMotion
from lagrangian.errors import AnalysisError
from lagrangian.model.probe import is_zero


def momentum_symbol(coordinate: sp.Symbol) -> sp.Symbol:
    """The symbol of the momentum conjugate to ``coordinate``: ``theta`` -> ``p_theta``."""
    return sp.Symbol("p_" + coordinate.name)


def momentum_symbols(eom: EquationsOfMotion) -> tuple[sp.Symbol, ...]:
    """``p_q`` for every coordinate; refused when such a name is already taken."""
    symbols = tuple(momentum_symbol(q) for q in eom.coordinates)
    taken = {s.name for s in (*eom.coordinates, *eom.velocities, *eom.parameters)}
    clashes = sorted(s.name for s in symbols if s.name in taken)
    if clashes:
        raise AnalysisError(
            f"The momentum names {', '.join(clashes)} are already used by the system; "
            "rename those parameters or coordinates."
        )
    return symbols


@dataclass(frozen=True)
class ConjugateMomenta:
    """p_j = dL/dq_dot_j for every coordinate, in the order of ``coordinates``."""

    coordinates: tuple[sp.Symbol, ...]
    momenta: sp.ImmutableMatrix

    def __getitem__(self, coordinate: sp.Symbol | str) -> sp.Expr:
        names = [q.name for q in self.coordinates]
        key = coordinate if isinstance(coordinate, str) else coordinate.name
        return self.momenta[names.index(key)]

    def by_name(self) -> dict[str, sp.Expr]:
        return {q.name: p for q, p in zip(self.coordinates, self.momenta)}


@dataclass(frozen=True)
class CyclicCoordinate:
    """A coordinate absent from L with no force on it, and its conserved momentum."""

    coordinate: sp.Symbol
    momentum: sp.Expr
    reason: str


def conjugate_momenta(subject: Subject) -> ConjugateMomenta:
    """The generalized momenta p_j = dL/dq_dot_j (the first step of each derivation).

    >>> import lagrangian as lg
    >>> conjugate_momenta(lg.examples.planet())["theta"]
    m*r**2*theta_dot
    """
    eom = equations_of(subject)
    return ConjugateMomenta(
        coordinates=tuple(eom.coordinates),
        momenta=sp.ImmutableMatrix([s.dL_dvelocity for s in eom.steps]),
    )


def cyclic_coordinates(subject: Subject) -> tuple[CyclicCoordinate, ...]:
    """Coordinates q_j with dL/dq_j = 0, Q_j = 0 and dF/dq_dot_j = 0: p_j is conserved.

    >>> import lagrangian as lg
    >>> cyclic_coordinates(lg.examples.spherical_pendulum())[0].momentum
    l**2*m*phi_dot*sin(theta)**2
    """
    eom = equations_of(subject)
    found = []
    for j, (q, step) in enumerate(zip(eom.coordinates, eom.steps)):
        if q in eom.lagrangian.free_symbols and not is_zero(step.dL_dcoordinate):
            continue
        if not (is_zero(eom.generalized_forces[j]) and is_zero(eom.dissipation_forces[j])):
            continue
        found.append(
            CyclicCoordinate(
                coordinate=q,
                momentum=step.dL_dvelocity,
                reason=(
                    f"{q.name} does not appear in L and no applied or dissipative force acts "
                    f"on it, so d/dt p_{q.name} = dL/d{q.name} = 0"
                ),
            )
        )
    return tuple(found)
