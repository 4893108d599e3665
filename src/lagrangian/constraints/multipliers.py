"""constrained_equations(system) -> ConstrainedEquations: the equations of motion with the
constraints enforced by Lagrange multipliers (Goldstein 3rd ed., §2.4; the sign convention of
docs/architecture.md).

    d/dt dL/dq_dot - dL/dq + dF/dq_dot = Q + sum_j lambda_j a_j,     a_j = dh_j/dq,

so lambda_j a_j is the force of constraint j.  With the unconstrained M q_ddot = forcing of
:func:`lagrangian.derive` and the constraints differentiated (holonomic twice, velocity once)
to A q_ddot = gamma (:mod:`lagrangian.constraints.pfaffian`):

    [ M  -A^T ] [ q_ddot ]   [ forcing ]
    [ A    0  ] [ lambda ] = [  gamma  ].

When M is regular and small (diagonal, or n <= 4) the system is solved symbolically, on
first request of :attr:`ConstrainedEquations.explicit` (a simulation never asks: it solves
the augmented system numerically):

    lambda = (A M^-1 A^T)^-1 (gamma - A M^-1 forcing),   q_ddot = M^-1 (forcing + A^T lambda).

The multiplier form is computed once per EquationsOfMotion object and set of constraints;
the augmented Lagrangian, which needs L (a derivation computes it only when asked), on first
request.

Holonomic constraints are also the augmented Lagrangian L + sum_j lambda_j h_j (Goldstein §2.4),
whose Euler–Lagrange equations are the first block row above.  Unilateral constraints are
treated as active (g = 0) holonomic ones; they are checked each on its own with the equality
constraints, and solved for only when they can all be in contact at once.
sympy.physics.mechanics.LagrangesMethod solved through ``mass_matrix_full`` /
``forcing_full`` gives the same multipliers; its ``eom`` expression has them with the
opposite sign (its ``lam_coeffs`` are -A; sympy issue #30215).

>>> import lagrangian as lg, sympy as sp
>>> x, y, m, g, l = sp.symbols("x y m g l")
>>> pendulum = lg.System(coordinates=[x, y], parameters=[m, g, l], gravity=(0, -g),
...     particles=[lg.Particle("bob", m, (x, y))],
...     constraints=[lg.Holonomic(x**2 + y**2 - l**2)])
>>> equations = constrained_equations(pendulum)
>>> equations.constraint_jacobian
Matrix([[2*x, 2*y]])
>>> equations.explicit[sp.Symbol("lambda_1")]
m*(g*y - x_dot**2 - y_dot**2)/(2*(x**2 + y**2))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import sympy as sp

from lagrangian.constraints.dependence import contact_dependence, dependence
from lagrangian.constraints.pfaffian import acceleration_terms, pfaffian_form
from lagrangian.derivation import EquationsOfMotion, derive, equations_of
from lagrangian.derivation.backend import cycle_collection_paused
from lagrangian.derivation.trig import combine_trig_sympy
from lagrangian.errors import ConstraintError, Problem, raise_if_problems
from lagrangian.model import System, Unilateral
from lagrangian.model.constraints import Constraint, VelocityConstraint, statement
from lagrangian.symbolic.caches import IdentityCache
from lagrangian.symbolic.frozen import FrozenMapping, frozen
from lagrangian.symbolic.probe import generic_rank

SMALL = 4  # n up to which a dense M is solved symbolically
#: Why the constraint forces are not solved symbolically, when they are not.
UNSOLVED = (
    f"not solved symbolically (M singular, dense with more than {SMALL} coordinates, or "
    "unilateral constraints that cannot all be in contact at once): they follow from the "
    "augmented system at each state, as simulate computes them"
)


@dataclass(frozen=True)
class ConstrainedEquations:
    """The equations of motion with multipliers (see the module docstring).

    Attributes
    ----------
    mass_matrix, forcing:
        The unconstrained M and forcing of :func:`lagrangian.derive`.
    constraint_jacobian:
        A (m x n): dh_j/dq for holonomic (and unilateral) constraints, a_j for velocity ones.
    gamma:
        The right side of A q_ddot = gamma.
    multipliers:
        lambda_1, ..., lambda_m, one per constraint in order.
    system:
        The System whose constraints these are.
    free_system:
        The System the unconstrained equations were derived from (its L).
    """

    coordinates: tuple[sp.Symbol, ...]
    velocities: tuple[sp.Symbol, ...]
    accelerations: tuple[sp.Symbol, ...]
    parameters: Mapping[sp.Symbol, float | None]
    time: sp.Symbol
    constraints: tuple[Constraint, ...]
    multipliers: tuple[sp.Symbol, ...]
    mass_matrix: sp.ImmutableMatrix
    forcing: sp.ImmutableMatrix
    constraint_jacobian: sp.ImmutableMatrix
    gamma: sp.ImmutableMatrix
    system: System = field(repr=False, compare=False)
    free_system: System = field(repr=False, compare=False)

    @property
    def explicit(self) -> Mapping[sp.Symbol, sp.Expr] | None:
        """q_ddot and lambda solved symbolically (computed on first request), or None when
        the system is left in augmented form (M singular, or dense with n > 4)."""
        return _SOLVED.get(self, _solve)

    @property
    def constraint_forces(self) -> Mapping[sp.Symbol, sp.Expr] | None:
        """Each multiplier solved as a function of the state and time (the rolling disk's
        friction lambda = -m g sin(alpha) / 3), or None where :attr:`explicit` is None
        (:data:`UNSOLVED`).  A unilateral constraint's is its force while in contact."""
        solved = self.explicit
        if solved is None:
            return None
        return FrozenMapping({lam: solved[lam] for lam in self.multipliers})

    @property
    def augmented_lagrangian(self) -> sp.Expr:
        """L + sum lambda_j h_j over the holonomic and unilateral constraints (velocity
        constraints have no h; their forces lambda_j a_j appear in the equations only);
        computed on first request."""
        return _AUGMENTED.get(self, _augmented_lagrangian)

    @property
    def unknowns(self) -> tuple[sp.Symbol, ...]:
        """(q_ddot, lambda), the unknowns of the augmented system."""
        return (*self.accelerations, *self.multipliers)

    @property
    def augmented_matrix(self) -> sp.ImmutableMatrix:
        """[[M, -A^T], [A, 0]]."""
        a, m = self.constraint_jacobian, len(self.multipliers)
        top = self.mass_matrix.row_join(-a.T)
        return sp.ImmutableMatrix(top.col_join(a.row_join(sp.zeros(m, m))))

    @property
    def augmented_rhs(self) -> sp.ImmutableMatrix:
        """[forcing; gamma]."""
        return sp.ImmutableMatrix(self.forcing.col_join(self.gamma))

    @property
    def generalized_constraint_forces(self) -> sp.ImmutableMatrix:
        """A^T lambda: the generalized force of the constraints on each coordinate."""
        return sp.ImmutableMatrix(self.constraint_jacobian.T * sp.Matrix(self.multipliers))

    @property
    def equations(self) -> sp.ImmutableMatrix:
        """Residuals (each = 0): M q_ddot - forcing - A^T lambda, then A q_ddot - gamma."""
        unknowns = sp.Matrix(self.unknowns)
        return sp.ImmutableMatrix(self.augmented_matrix * unknowns - self.augmented_rhs)


def multiplier_names(count: int) -> tuple[str, ...]:
    """lambda_1, ..., lambda_count (the names of the output contracts)."""
    return tuple(f"lambda_{j + 1}" for j in range(count))


def multiplier_symbols(count: int) -> tuple[sp.Symbol, ...]:
    """The symbols of :func:`multiplier_names` (a gas's thousands of contacts name their
    multipliers without making a symbol each)."""
    return tuple(map(sp.Symbol, multiplier_names(count)))


#: Per EquationsOfMotion object: constraints -> their multiplier form.
_FORMS: IdentityCache[EquationsOfMotion, dict[tuple[Constraint, ...], ConstrainedEquations]]
_FORMS = IdentityCache()
_SOLVED: IdentityCache[ConstrainedEquations, Mapping[sp.Symbol, sp.Expr] | None]
_SOLVED = IdentityCache()
_AUGMENTED: IdentityCache[ConstrainedEquations, sp.Expr] = IdentityCache()


def constrained_equations(
    subject: System | EquationsOfMotion, constraints: Sequence[Constraint] | None = None
) -> ConstrainedEquations:
    """The multiplier form of a System's equations (its own ``constraints``, or those given).

    An EquationsOfMotion (from :func:`lagrangian.derive`) is accepted with ``constraints``.
    The result is computed once per equations object and constraints.  Raises
    ConstraintError for inconsistent or redundant constraints (the multipliers of redundant
    ones are not determined: remove them).
    """
    eom = equations_of(subject, "constrained_equations(subject)")  # free of constraints
    if isinstance(subject, System):
        chosen = tuple(subject.constraints if constraints is None else constraints)
    elif constraints is None:
        raise ConstraintError(
            "An EquationsOfMotion does not carry constraints: pass constraints=[...] or "
            "give the System."
        )
    else:
        chosen = tuple(constraints)
    forms = _FORMS.get(eom, lambda _: {})
    try:
        known = forms.get(chosen)
    except TypeError:  # an unhashable expression: let the System's validation name it
        return _multiplier_form(eom, chosen)
    if known is None:
        # the redundancy check and gamma make expressions by the thousand and no cycle: the
        # collector paused, as for the derivation (lagrangian.derivation.backend)
        with cycle_collection_paused():
            known = forms[chosen] = _multiplier_form(eom, chosen)
    return known


def _multiplier_form(
    eom: EquationsOfMotion, constraints: tuple[Constraint, ...]
) -> ConstrainedEquations:
    """The multiplier form of ``eom`` with ``constraints`` (see the module docstring)."""
    own = eom.system
    system = own if tuple(own.constraints) == constraints else own.replace(constraints=constraints)
    _refuse_redundant(system)
    coordinates = tuple(system.coordinates)
    forms = [pfaffian_form(c, coordinates) for c in system.constraints]
    jacobian = sp.ImmutableMatrix(
        len(forms), len(coordinates), [a for f in forms for a in f.coefficients]
    )
    gamma = sp.ImmutableMatrix(len(forms), 1, acceleration_terms(forms, coordinates))
    return ConstrainedEquations(
        coordinates=coordinates,
        velocities=tuple(eom.velocities),
        accelerations=tuple(eom.accelerations),
        parameters=frozen(eom.parameters),
        time=eom.time,
        constraints=tuple(system.constraints),
        mass_matrix=eom.mass_matrix,
        forcing=eom.forcing,
        constraint_jacobian=jacobian,
        gamma=gamma,
        multipliers=_multipliers(system),
        system=system,
        free_system=own,
    )


def _augmented_lagrangian(equations: ConstrainedEquations) -> sp.Expr:
    """L + sum lambda_j h_j (the module docstring)."""
    holonomic = [
        lam * c.expression
        for lam, c in zip(equations.multipliers, equations.constraints)
        if not isinstance(c, VelocityConstraint)
    ]
    return derive(equations.free_system).lagrangian + sp.Add(*holonomic)


def _multipliers(system: System) -> tuple[sp.Symbol, ...]:
    symbols = multiplier_symbols(len(system.constraints))
    taken = {s.name for s in (*system.coordinates, *system.parameters)}
    clash = [s.name for s in symbols if s.name in taken]
    if clash:
        raise ConstraintError(
            f"The names {', '.join(clash)} are taken by coordinates or parameters; the "
            "multipliers are lambda_1, lambda_2, ...: rename those."
        )
    return symbols


def _refuse_redundant(system: System) -> None:
    """The equality constraints checked together, each unilateral one on its own with them
    (inequalities need not hold together: a gas's walls never all touch a disk at once)."""
    found = dependence(system)  # raises for inconsistent constraints
    problems = [
        Problem(
            f"constraints[{i}]",
            f"{statement(system.constraints[i])} is redundant: its Jacobian row is a "
            "combination of earlier ones, so the multipliers are not determined",
            "remove it (classify() lists the redundant constraints)",
        )
        for i in found.redundant
    ]
    problems += [
        Problem(
            f"constraints[{i}]",
            f"{statement(system.constraints[i])} is redundant in contact: its Jacobian row "
            "is a combination of the equality constraints' rows, so its multiplier is not "
            "determined",
            "remove it, or the equality constraints that imply it",
        )
        for i in contact_dependence(system, found)
    ]
    raise_if_problems(problems, "The constraints are redundant", ConstraintError)


def _in_contact_together(system: System) -> bool:
    """Whether every constraint, the unilateral ones closed (g = 0), can hold at once with
    independent Jacobian rows: only then is the multiplier form solved for them all."""
    if not any(isinstance(c, Unilateral) for c in system.constraints):
        return True
    if len(system.constraints) > len(system.coordinates):
        return False  # more rows than columns: dependent, or no configuration at all
    try:
        return not dependence(system, active=True).redundant
    except ConstraintError:
        return False


def _solve(equations: ConstrainedEquations) -> FrozenMapping[sp.Symbol, sp.Expr] | None:
    """lambda by the Schur complement, then q_ddot; None when not small or M is singular."""
    mass, forcing, n = equations.mass_matrix, equations.forcing, len(equations.coordinates)
    if not (mass.is_diagonal() or n <= SMALL) or generic_rank(mass) < n:
        return None
    if not _in_contact_together(equations.system):
        return None
    jacobian, gamma = equations.constraint_jacobian, equations.gamma
    free = _inverse_times(mass, forcing)  # M^-1 forcing
    pulled = _inverse_times(mass, jacobian.T)  # M^-1 A^T
    schur = (jacobian * pulled).applyfunc(_combined_fraction)
    try:
        lam = schur.LUsolve(sp.Matrix(gamma) - jacobian * free).applyfunc(_combined_fraction)
    except ValueError:  # a pivot SymPy cannot prove non-zero: keep the augmented form
        return None
    accelerations = (free + pulled * lam).applyfunc(_combined_fraction)
    solved = dict(zip(equations.multipliers, lam))
    solved.update(zip(equations.accelerations, accelerations))
    return FrozenMapping(solved)


def _inverse_times(mass: sp.MatrixBase, rhs: sp.MatrixBase) -> sp.Matrix:
    """M^-1 rhs: a diagonal M divides row by row, a small dense one is solved by LU."""
    if mass.is_diagonal():
        return sp.Matrix(rhs.rows, rhs.cols, lambda i, j: rhs[i, j] / mass[i, i])
    return sp.Matrix(mass).LUsolve(sp.Matrix(rhs))


def _combined_fraction(expr: sp.Expr) -> sp.Expr:
    """One fraction, cancelled, with sin^2 + cos^2 and the like combined in the numerator and
    the denominator (:func:`lagrangian.derivation.trig.combine_trig_sympy`); large
    expressions are left."""
    if sp.count_ops(expr) > 400:
        return expr
    numerator, denominator = sp.fraction(sp.cancel(expr))
    numerator, denominator = (combine_trig_sympy(e) for e in (numerator, denominator))
    return sp.factor_terms(sp.cancel(numerator / denominator))
