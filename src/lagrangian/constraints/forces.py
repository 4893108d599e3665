"""The Cartesian force each constraint exerts on each particle.

The generalized constraint force is A^T lambda (:mod:`lagrangian.constraints.multipliers`).
When a particle's position is made of coordinates of its own, r_i = (x_i, y_i[, z_i]), the
virtual work sum_k Q_k dq_k of those coordinates is F_i . dr_i, so the Cartesian force on the
particle is exactly the matching components of A^T lambda:

    F_i = sum_j lambda_j grad_{r_i} h_j     (velocity constraints: lambda_j a_j restricted to r_i).

A dumbbell (two particles a rigid distance h0 apart), h = |q1 - q2|^2 - h0^2:
F_1 = 2 lambda (q1 - q2) = -F_2.  In any other coordinates the force on a particle is
m_i r_i_ddot minus the applied forces on it, which needs every force on the particle by name
(energies given as expressions cannot be attributed to particles), so only the exact
Cartesian case is provided: write such a particle at coordinates of its own and tie them with
constraints to get its constraint force.

>>> import lagrangian as lg, sympy as sp
>>> from lagrangian.constraints import constrained_equations
>>> x, y, m, g, l = sp.symbols("x y m g l")
>>> pendulum = lg.System(coordinates=[x, y], parameters=[m, g, l], gravity=(0, -g),
...     particles=[lg.Particle("bob", m, (x, y))],
...     constraints=[lg.Holonomic(x**2 + y**2 - l**2)])
>>> particle_constraint_forces(constrained_equations(pendulum))["bob"].T
Matrix([[2*lambda_1*x, 2*lambda_1*y]])
"""

from __future__ import annotations

from collections import Counter

import sympy as sp

from lagrangian.constraints.multipliers import ConstrainedEquations
from lagrangian.errors import ConstraintError, Problem, raise_if_problems, require
from lagrangian.symbolic.conversion import to_sympy


def particle_constraint_forces(
    equations: ConstrainedEquations, solved: bool = False
) -> dict[str, sp.ImmutableMatrix]:
    """Particle name -> Cartesian constraint force F_i = sum_j lambda_j grad_{r_i} h_j, in the
    multipliers, or with ``solved`` in the state (the explicit multipliers substituted).

    Every particle's position must be coordinates of its own (no other particle or body uses
    them); ConstraintError names the particles that are not."""
    require(
        equations,
        ConstrainedEquations,
        "particle_constraint_forces(equations)",
        "make them with lagrangian.constrained_equations(system)",
    )
    system = equations.system
    positions = [p.position for p in system.particles] + [b.position for b in system.rigid_bodies]
    used = Counter(
        s
        for position in positions
        for x in position
        for s in to_sympy(x).free_symbols
        if s in system.coordinates
    )
    index = {q: k for k, q in enumerate(system.coordinates)}
    generalized = equations.generalized_constraint_forces
    if solved:
        if equations.explicit is None:
            raise ConstraintError(
                "The multipliers were not solved symbolically (large or singular mass "
                "matrix); use solved=False and the augmented system."
            )
        generalized = generalized.xreplace(dict(equations.explicit))
    forces: dict[str, sp.ImmutableMatrix] = {}
    problems = []
    for i, particle in enumerate(system.particles):
        position = particle.position
        own = all(x in index and used[x] == 1 for x in position) and len(set(position)) == len(
            position
        )
        if not own:
            problems.append(
                Problem(
                    f"particles[{i}].position",
                    f"particle {particle.name!r} is at {list(position)}, not at Cartesian "
                    "coordinates of its own",
                    "give it coordinates of its own (x, y) and constraints that tie them; its "
                    "constraint force is then sum_j lambda_j grad h_j",
                )
            )
            continue
        forces[particle.name] = sp.ImmutableMatrix([generalized[index[x]] for x in position])
    raise_if_problems(problems, "Cartesian constraint forces are not defined", ConstraintError)
    return forces
