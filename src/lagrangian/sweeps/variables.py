"""What a sweep stores for a System, decided once on the client: the series and the drifts.

* the coordinates, their ``NAME_dot`` and, with constraints, the multipliers ``lambda_j``,
  each over (dims..., t);
* ``energy``: the energy the system conserves when anything does.  That is the energy
  function h = sum q_dot dL/dq_dot - L (the Jacobi integral) where it differs from T + V (a
  bead on a rotating hoop, a velocity-dependent potential), else T + V: the variable's
  ``quantity`` attribute says which;
* per member the drift of each quantity a run conserves, as :meth:`Trajectory.drift
  <lagrangian.simulation.trajectory.Trajectory.drift>` decides (``energy_drift``, ``p_NAME_drift``
  for the momentum of each cyclic coordinate), and with constraints ``constraint_drift``, the
  largest constraint residual;
* with unilateral constraints that have a coefficient of restitution (a bouncing ball), per
  member ``impacts``, how many impacts the run met, and ``rest_time``, when a contact came to
  rest (its bounces accumulated, as the single run's ``Impact.rest`` records).

Constrained systems run in the multiplier form, in smaller blocks (a member the batch
refuses, such as one with unilateral constraints, runs alone through :func:`lagrangian.simulate`):
``per_member``.

>>> import lagrangian as lg
>>> sweep_variables(lg.examples.planet()).drifts
('energy_drift', 'p_theta_drift')
>>> sweep_variables(lg.examples.cylinder_on_incline()).multipliers
('lambda_1',)
>>> sweep_variables(lg.examples.bouncing_ball()).impacts
True
"""

from __future__ import annotations

from dataclasses import dataclass

from lagrangian.constraints import multiplier_names
from lagrangian.derivation import derive
from lagrangian.model import System
from lagrangian.model.constraints import Unilateral
from lagrangian.numerics.compile import compile_equations
from lagrangian.simulation.conserved import conserved_expressions
from lagrangian.simulation.trajectory import DOT

#: The ``quantity`` attribute of ``energy``, and its ``long_name``, by whether it holds h.
ENERGY_LABELS = {
    True: ("energy function h", "h = sum q_dot dL/dq_dot - L"),
    False: ("T + V", "E = T + V"),
}


@dataclass(frozen=True)
class SweepVariables:
    """The names a sweep stores for one System (module docstring)."""

    coordinates: tuple[str, ...]
    multipliers: tuple[str, ...] = ()
    momenta: tuple[str, ...] = ()
    energy_function: bool = False
    per_member: bool = False
    impacts: bool = False

    @property
    def series(self) -> tuple[str, ...]:
        """The variables over (dims..., t) besides ``energy``."""
        velocities = tuple(name + DOT for name in self.coordinates)
        return (*self.coordinates, *velocities, *self.multipliers)

    @property
    def drifts(self) -> tuple[str, ...]:
        """The per-member drift variables."""
        constraint = ("constraint_drift",) if self.multipliers else ()
        return ("energy_drift", *(f"{name}_drift" for name in self.momenta), *constraint)

    @property
    def energy_quantity(self) -> str:
        """What ``energy`` holds: ``energy function h`` or ``T + V``."""
        return ENERGY_LABELS[self.energy_function][0]


def sweep_variables(system: System) -> SweepVariables:
    """What a sweep of ``system`` stores (derives and compiles it: cached per System)."""
    eom = derive(system)
    constraints = system.constraints
    return SweepVariables(
        coordinates=tuple(q.name for q in system.coordinates),
        multipliers=multiplier_names(len(constraints)),
        momenta=tuple(conserved_expressions(eom, system, {})),
        energy_function=compile_equations(eom).energy_function_differs,
        # blocks of constrained members are kept small: one the batch refuses runs member
        # by member (Batch.trajectory carries the multipliers the store reads)
        per_member=bool(constraints),
        impacts=has_impacts(system),
    )


def has_impacts(system: System) -> bool:
    """Whether runs of ``system`` record impacts: it has a unilateral constraint with a
    coefficient of restitution (without one, a run that reaches an impact stops there)."""
    return any(isinstance(c, Unilateral) and c.restitution is not None for c in system.constraints)
