"""eliminate(system, independent, parametrization) -> System in minimal coordinates.

Holonomic constraints h(q, t) = 0 are solved for the dependent coordinates, q_dep = f(s, t),
either by SymPy (``independent`` a subset of the coordinates) or from a ``parametrization``
the user gives (which may introduce new coordinates s, such as theta for x = l sin(theta),
y = -l cos(theta)).  Every piece of the System is then rewritten in s (a point transformation,
under which Lagrange's equations keep their form):

    q_dep -> f(s, t),     q_dep_dot -> sum_k df/ds_k s_dot_k + df/dt,
    Q_s_k = sum_q Q_q dq/ds_k                      (virtual work of the old generalized forces)

positions of particles and bodies, energies, springs, dampers, forces and circuit elements
alike.  The holonomic constraints hold identically and are dropped (checked); velocity and
unilateral constraints are rewritten.  The reduced equations agree with the multiplier form
(:mod:`lagrangian.constraints.multipliers`) along the constraint set.

>>> import lagrangian as lg, sympy as sp
>>> x, y, theta, m, g, l = sp.symbols("x y theta m g l")
>>> pendulum = lg.System(coordinates=[x, y], parameters=[m, g, l], gravity=(0, -g),
...     particles=[lg.Particle("bob", m, (x, y))],
...     constraints=[lg.Holonomic(x**2 + y**2 - l**2)])
>>> reduced = eliminate(pendulum, [theta], {x: l*sp.sin(theta), y: -l*sp.cos(theta)})
>>> lg.derive(reduced).equations[0]
g*l*m*sin(theta) + l**2*m*theta_ddot
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import fields, is_dataclass, replace
from typing import Any

import sympy as sp

from lagrangian.constraints.dependence import dependence
from lagrangian.errors import ConstraintError
from lagrangian.model import Holonomic, System, Unilateral, VelocityConstraint, VoltageSource, t
from lagrangian.model.constraints import Constraint, label, statement
from lagrangian.model.rotation import Orientation
from lagrangian.model.system import require_system
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import is_zero
from lagrangian.symbolic.symbols import as_coordinate, from_time_functions, velocity


def eliminate(
    system: System,
    independent: Sequence[Any],
    parametrization: Mapping[Any, Any] | None = None,
) -> System:
    """The System in the minimal coordinates ``independent`` (see the module docstring).

    Without ``parametrization`` the holonomic constraints are solved for the other
    coordinates; with several solution branches the one the initial state satisfies is used,
    else ConstraintError asks for a parametrization.  Raises ConstraintError when the
    parametrization violates a constraint or the count of independent coordinates is not the
    number of degrees of freedom."""
    require_system(system, "eliminate(system, ...)")
    new = _symbols(independent, "independent")
    old = tuple(system.coordinates)
    rule = _rule(system, new, parametrization)
    _check(system, new, rule)
    substitution = dict(rule)
    for q, f in rule.items():
        rate = f.diff(t) + sum((f.diff(s) * velocity(s) for s in new), sp.Integer(0))
        substitution[velocity(q)] = rate
    jacobian = {
        q: {s: (rule[q].diff(s) if q in rule else sp.Integer(1 if q == s else 0)) for s in new}
        for q in old
    }
    return _rewrite(system, new, substitution, jacobian)


def elimination_rule(
    system: System,
    independent: Sequence[Any],
    parametrization: Mapping[Any, Any] | None = None,
) -> dict[sp.Symbol, sp.Expr]:
    """The substitution :func:`eliminate` makes: each dependent coordinate as an expression
    in the independent ones (and t), checked against the constraints as there.

    >>> import lagrangian as lg, sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> line = lg.System(coordinates=[x, y], constraints=[lg.Holonomic(y - 2*x)])
    >>> elimination_rule(line, [x])
    {y: 2*x}
    """
    new = _symbols(independent, "independent")
    rule = _rule(system, new, parametrization)
    _check(system, new, rule)
    return rule


def _symbols(items: Sequence[Any], what: str) -> tuple[sp.Symbol, ...]:
    result = []
    for item in items:
        symbol = as_coordinate(item)
        if symbol is None:
            raise ConstraintError(f"{item!r} in {what} is not a coordinate name or Symbol.")
        result.append(symbol)
    return tuple(result)


def _canonical(expr: Any, system: System, new: Sequence[sp.Symbol]) -> sp.Expr:
    expr = from_time_functions(to_sympy(expr))
    names = {s.name: s for s in (*system.parameters, *new, t)}
    return expr.xreplace({s: names[s.name] for s in expr.free_symbols if s.name in names})


def _rule(
    system: System, new: tuple[sp.Symbol, ...], parametrization: Mapping[Any, Any] | None
) -> dict[sp.Symbol, sp.Expr]:
    """Dependent coordinate -> f(s, t)."""
    old = tuple(system.coordinates)
    if parametrization is not None:
        given = dict(
            zip(_symbols(list(parametrization), "parametrization"), parametrization.values())
        )
        rule = {q: _canonical(f, system, new) for q, f in given.items()}
        stray = [q for q in rule if q not in old]
        missing = [q for q in old if q not in rule and q not in new]
        if stray or missing:
            raise ConstraintError(
                f"The parametrization must give every coordinate not kept independent: "
                f"missing {[str(q) for q in missing]}, unknown {[str(q) for q in stray]}."
            )
        return rule
    unknown = [s for s in new if s not in old]
    if unknown:
        raise ConstraintError(
            f"{[str(s) for s in unknown]} are not coordinates; new coordinates need a "
            "parametrization {old_coordinate: expression in the new ones}."
        )
    dependent = [q for q in old if q not in new]
    equations = [c.expression for c in system.constraints if isinstance(c, Holonomic)]
    solutions = sp.solve(equations, dependent, dict=True) if dependent else [{}]
    solutions = [s for s in solutions if set(s) == set(dependent)]
    return _branch(system, dependent, solutions)


def _branch(
    system: System, dependent: list[sp.Symbol], solutions: list[dict[sp.Symbol, sp.Expr]]
) -> dict[sp.Symbol, sp.Expr]:
    """The one solution, or the one the initial state satisfies."""
    if len(solutions) == 1:
        return solutions[0]
    if not solutions:
        raise ConstraintError(
            f"The holonomic constraints cannot be solved for {[str(q) for q in dependent]}; "
            "give a parametrization {coordinate: expression}."
        )
    state = {**{p: v for p, v in system.parameters.items() if v is not None}, **system.initial}
    fitting = [
        s
        for s in solutions
        if all(q in state for q in dependent)
        and all(abs(complex(sp.N((q - f).xreplace(state)))) < 1e-9 for q, f in s.items())
    ]
    if len(fitting) == 1:
        return fitting[0]
    listing = "; ".join(", ".join(f"{q} = {f}" for q, f in s.items()) for s in solutions)
    raise ConstraintError(
        f"The constraints have {len(solutions)} solution branches ({listing}); choose one with "
        "parametrization={...} (or give initial values that pick one)."
    )


def _check(system: System, new: tuple[sp.Symbol, ...], rule: dict[sp.Symbol, sp.Expr]) -> None:
    for i, c in enumerate(system.constraints):
        if isinstance(c, Holonomic) and not is_zero(c.expression.xreplace(rule)):
            raise ConstraintError(
                f"The coordinates chosen do not satisfy {label(i, c)} ({statement(c)}): it "
                f"becomes {sp.simplify(c.expression.xreplace(rule))} = 0."
            )
    holonomic = [i for i, c in enumerate(system.constraints) if isinstance(c, Holonomic)]
    dof = len(system.coordinates) - dependence(system).rank_of(holonomic)
    if len(new) != dof:
        raise ConstraintError(
            f"{len(new)} independent coordinates given, but the holonomic constraints leave "
            f"{dof} degrees of freedom; give {dof}."
        )


def _rewrite(
    system: System,
    new: tuple[sp.Symbol, ...],
    substitution: dict[sp.Symbol, sp.Expr],
    jacobian: dict[sp.Symbol, dict[sp.Symbol, sp.Expr]],
) -> System:
    def sub(value: Any) -> Any:
        if isinstance(value, sp.Basic):
            return value.xreplace(substitution)
        if isinstance(value, tuple):
            return tuple(sub(v) for v in value)
        if isinstance(value, Orientation):  # a 3-D body's rotation, in the old coordinates
            return value.map(sub)
        return value

    def element(item: Any) -> Any:
        if not is_dataclass(item) or isinstance(item, type):
            return item
        changes = {f.name: sub(getattr(item, f.name)) for f in fields(item) if f.name != "name"}
        return replace(item, **changes)

    forces: dict[sp.Symbol, sp.Expr] = {s: sp.Integer(0) for s in new}
    applied = dict(system.generalized_forces)
    for source in system.circuit:  # a source on an eliminated charge becomes a force
        if isinstance(source, VoltageSource) and source.coordinate not in new:
            applied[source.coordinate] = applied.get(source.coordinate, 0) + source.voltage
    for q, value in applied.items():
        for s in new:
            forces[s] += sub(value) * jacobian[q][s]
    circuit = [
        element(e)
        for e in system.circuit
        if not (isinstance(e, VoltageSource) and e.coordinate not in new)
    ]
    kept = set(new) | {velocity(s) for s in new}
    return system.replace(
        coordinates=new,
        **{name: sub(getattr(system, name)) for name in _EXPRESSIONS},
        generalized_forces={s: f for s, f in forces.items() if f != 0},
        particles=[element(e) for e in system.particles],
        rigid_bodies=[element(e) for e in system.rigid_bodies],
        springs=[element(e) for e in system.springs],
        dampers=[element(e) for e in system.dampers],
        forces=[element(e) for e in system.forces],
        torques=[element(e) for e in system.torques],
        circuit=circuit,
        constraints=_remaining(system.constraints, sub, new),
        initial={k: v for k, v in system.initial.items() if k in kept},
    )


_EXPRESSIONS = ("kinetic", "potential", "lagrangian", "velocity_potential", "dissipation")


def _remaining(
    constraints: Sequence[Constraint], sub: Any, new: Sequence[sp.Symbol]
) -> list[Constraint]:
    """Velocity and unilateral constraints in the new coordinates (holonomic ones hold)."""
    velocities = {velocity(s) for s in new}
    kept: list[Constraint] = []
    for c in constraints:
        if isinstance(c, Holonomic):
            continue
        expression = sub(c.expression)
        if not expression.free_symbols & (set(new) | velocities) or is_zero(expression):
            continue  # now a constant: implied by the others (or for a unilateral one, fixed)
        if isinstance(c, VelocityConstraint) and not expression.free_symbols & velocities:
            kept.append(Holonomic(expression, c.name))
        elif isinstance(c, Unilateral):
            kept.append(Unilateral(expression, c.name))
        else:
            kept.append(VelocityConstraint(expression, c.name))
    return kept
