"""The conserved quantities of a report, gathered from the parts that find them.

In this order: the momenta p_j of cyclic coordinates that are conserved (with the parameter
values under which they are), the Noether charges of the other point symmetries (Noether:
L invariant under q -> q + eps xi(q) gives d/dt (xi . dL/dq_dot) = 0), the energy function
h when dh/dt = 0, the Jacobi integral of constraints that move by a symmetry, and the
independent first integrals of the search (:mod:`lagrangian.analysis.integrals.search`).

>>> import lagrangian as lg
>>> from lagrangian.analysis import cyclic_coordinates, energy_conservation
>>> planet = lg.examples.planet()
>>> found = conserved_quantities(cyclic_coordinates(planet), energy_conservation(planet))
>>> [c.name for c in found]
['p_theta', 'h']
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import sympy as sp

from lagrangian.analysis.energy import EnergyConservation
from lagrangian.analysis.integrals.noether import Symmetry
from lagrangian.analysis.integrals.search import ConservedQuantity, FirstIntegralSearch
from lagrangian.analysis.manifold.symmetries import JacobiIntegral
from lagrangian.analysis.momenta import CyclicCoordinate
from lagrangian.analysis.names import TEXTBOOK_NAMES, OutputNames
from lagrangian.symbolic.probe import is_zero


def conserved_quantities(
    cyclic: Sequence[CyclicCoordinate],
    energy: EnergyConservation | None,
    symmetries: Sequence[Symmetry] = (),
    jacobi: JacobiIntegral | None = None,
    search: FirstIntegralSearch | None = None,
    names: OutputNames = TEXTBOOK_NAMES,
) -> tuple[ConservedQuantity, ...]:
    """The momenta of cyclic coordinates that are conserved (with their conditions), the
    Noether charges of the other point symmetries, h when it is conserved, the Jacobi
    integral of constraints that move by a symmetry, and the independent first integrals of
    the ``search``; each named by ``names`` (none a name of the model)."""
    kept = [c for c in cyclic if c.conserved]
    found = [
        ConservedQuantity(
            names.momentum(c.coordinate), c.momentum, c.reason, c.condition, "cyclic coordinate"
        )
        for c in kept
    ]
    known = [c.momentum for c in kept]
    for symmetry in symmetries:
        if is_zero(symmetry.conserved):
            continue  # a coordinate without inertia: nothing to conserve
        if any(sp.simplify(symmetry.conserved / p).is_number for p in known if p != 0):
            continue  # the momentum of a cyclic coordinate, found again
        found.append(
            ConservedQuantity(
                names.fresh(f"noether_{len(found) + 1}"),
                symmetry.conserved,
                f"Noether: L is invariant under the {symmetry.description}",
                origin="point symmetry",
            )
        )
    if energy is not None and energy.conserved:
        found.append(
            ConservedQuantity(
                names.energy, energy.energy_function, energy.reason, energy.condition, "energy"
            )
        )
    if jacobi is not None:
        found.append(
            ConservedQuantity(
                names.fresh("jacobi"), jacobi.expression, jacobi.reason, origin="Jacobi integral"
            )
        )
    if search is not None:
        found += [_named(q, names) for q in search.found]
    return tuple(found)


def _named(quantity: ConservedQuantity, names: OutputNames) -> ConservedQuantity:
    """A first integral of the search (I_k) renamed J_k when the model has an I_k."""
    if quantity.name not in names.taken:
        return quantity
    return replace(quantity, name=names.fresh(quantity.name, "J" + quantity.name[1:]))
