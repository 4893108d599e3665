"""Symmetries on the constraint manifold: which Noether charges the constraints keep, and the
Jacobi integral of constraints that move by a symmetry.

With constraint forces A^T lambda, a point symmetry xi of L (no applied force along it) gives

    d/dt (p . xi) = lambda^T A xi,

so its charge is conserved when the constraints exert no force along xi (A xi = 0 on the
manifold).  The energy function changes at the rate dh/dt = -lambda^T b of the moving
constraints.  When the constraints move *by the symmetry*, b = kappa A xi with a constant
kappa (a hoop spinning at omega about the z axis: xi the rotation, kappa = -omega), the
combination

    J = h + kappa p . xi          (dJ/dt = lambda^T (kappa A xi - b) = 0)

is conserved: the Jacobi integral, the energy seen from the frame that moves with the
constraints (Goldstein §2.7, §8.2: h = E - omega L_z for a bead on a spinning hoop, whatever
the coordinates).

>>> import lagrangian as lg, sympy as sp
>>> x, y, m, w = sp.symbols("x y m omega")
>>> wire = lg.System(coordinates=[x, y], parameters={m: 1.0, w: 2.0},
...     particles=[lg.Particle("bead", m, (x, y))],
...     constraints=[lg.Holonomic(x * sp.sin(w * lg.t) - y * sp.cos(w * lg.t))])
>>> jacobi_integral(wire).expression
-m*omega*x*y_dot + m*omega*x_dot*y + m*x_dot**2/2 + m*y_dot**2/2
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from lagrangian.analysis.arguments import Subject, equations_of
from lagrangian.analysis.energy import EnergyConservation, energy_conservation
from lagrangian.analysis.integrals.noether import Symmetry, point_symmetries
from lagrangian.analysis.manifold.constraint_manifold import ConstraintManifold, constraint_manifold
from lagrangian.analysis.simplification import simplify_small
from lagrangian.symbolic.probe import is_zero


@dataclass(frozen=True)
class JacobiIntegral:
    """J = h + kappa p . xi, conserved because the constraints move by the symmetry xi at
    the rate -kappa (b = kappa A xi), and why."""

    expression: sp.Expr
    symmetry: Symmetry
    kappa: sp.Expr
    reason: str


def force_along(symmetry: Symmetry, manifold: ConstraintManifold) -> tuple[str, ...]:
    """Labels of the constraints that exert a force along ``symmetry`` (A xi != 0)."""
    along = manifold.jacobian * sp.Matrix(symmetry.generator)
    return tuple(label for label, a in zip(manifold.labels, along) if not is_zero(a))


def kept_symmetries(
    symmetries: Sequence[Symmetry], manifold: ConstraintManifold | None
) -> tuple[Symmetry, ...]:
    """The symmetries whose charges the constraints keep (no constraint force along xi)."""
    if manifold is None:
        return tuple(symmetries)
    return tuple(s for s in symmetries if not force_along(s, manifold))


def _rate(symmetry: Symmetry, manifold: ConstraintManifold, constants: set) -> sp.Expr | None:
    """kappa with b = kappa A xi on every row, kappa a constant; None when there is none."""
    along = manifold.jacobian * sp.Matrix(symmetry.generator)
    rows = [j for j in range(manifold.size) if not is_zero(along[j])]
    if not rows:
        return None
    kappa = sp.simplify(manifold.rates[rows[0]] / along[rows[0]])
    if not kappa.free_symbols <= constants:
        return None
    if all(is_zero(manifold.rates[j] - kappa * along[j]) for j in range(manifold.size)):
        return kappa
    return None


def jacobi_integral(
    subject: Subject,
    energy: EnergyConservation | None = None,
    symmetries: Sequence[Symmetry] | None = None,
) -> JacobiIntegral | None:
    """The Jacobi integral of a system whose only loss of energy conservation is the work
    of constraints that move by a symmetry of L (see the module docstring); None when there
    is none."""
    eom = equations_of(subject)
    manifold = constraint_manifold(eom)
    if manifold is None or not manifold.moving:
        return None
    energy = energy or energy_conservation(eom)
    if energy.conserved or not is_zero(energy.rate - energy.constraint_power):
        return None
    candidates = point_symmetries(eom) if symmetries is None else symmetries
    constants = set(eom.parameters)
    for symmetry in candidates:
        kappa = _rate(symmetry, manifold, constants)
        if kappa is None:
            continue
        moving = ", ".join(manifold.labels[row] for row in manifold.moving)
        return JacobiIntegral(
            expression=sp.expand(energy.energy_function + kappa * symmetry.conserved),
            symmetry=symmetry,
            kappa=kappa,
            reason=(
                f"Jacobi integral h + ({simplify_small(kappa)}) * ({symmetry.conserved}): the "
                f"constraint {moving} moves by the {symmetry.description} (b = kappa A xi, "
                "kappa constant), so the work of its force on h and on the Noether charge "
                "cancel; the energy seen from the frame that moves with the constraints"
            ),
        )
    return None
