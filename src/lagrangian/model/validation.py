"""Check a canonical System description and collect every problem (STYLE: validate at the
boundary, collect all problems, raise once, name the field and the fix)."""

from __future__ import annotations

import math
import random
import sys
from collections.abc import Iterable, Mapping
from types import MappingProxyType
from typing import Any

import sympy as sp

from lagrangian.errors import Problem
from lagrangian.model.circuit import (
    Capacitor,
    Inductor,
    MutualInductance,
    Resistor,
    VoltageSource,
)
from lagrangian.model.constraints import check_constraints
from lagrangian.model.elements import ORIGIN
from lagrangian.model.inertia import Shape, check_inertia
from lagrangian.model.rotation import Orientation, check_rotation
from lagrangian.model.transitions import check_transitions
from lagrangian.symbolic.caches import remembered
from lagrangian.symbolic.expressions import (
    closest_name,
    distinct_parts,
    free_symbols,
    is_plain,
)
from lagrangian.symbolic.names import name_problem
from lagrangian.symbolic.nonsmooth import kinks_in
from lagrangian.symbolic.probe import PROBES, SEED, random_values
from lagrangian.symbolic.symbols import DDOT_SUFFIX, DOT_SUFFIX, acceleration, t, velocity

#: The most generalized coordinates a System may have: the equations hold n-by-n matrices,
#: and a chain of a few hundred links already takes minutes to derive.
MAX_COORDINATES = 1000
#: The most parameters a System may have: two and a half times the largest chain's (a mass
#: and a length per link of MAX_COORDINATES links, and g); a file declaring more is refused
#: before its names are read.
MAX_PARAMETERS = 5000

CONFIGURATION = "configuration"  # may depend on q, t and parameters
STATE = "state"  # may also depend on the velocities
CONSTANT = "constant"  # parameters and numbers only


class NameScope:
    """The names an expression may use, and the diagnosis of a name it may not."""

    def __init__(self, values: dict[str, Any]) -> None:
        q = values["coordinates"]
        self.coordinates = set(q)
        self.velocities = {velocity(c) for c in q}
        self.accelerations = {acceleration(c) for c in q}
        self.parameters = set(values["parameters"])
        self.configuration = self.coordinates | self.parameters | {t}
        self.state = self.configuration | self.velocities
        self.names = sorted(s.name for s in self.state)
        # each kind's allowed names, and the parts found free of problems for it, shared by
        # the checks of every field: the positions of a chain share most of their terms
        self._scopes: dict[str, tuple[set[sp.Basic], set[sp.Basic]]] = {
            CONFIGURATION: (self.configuration, set()),
            CONSTANT: (self.parameters, set()),
            STATE: (self.state, set()),
        }

    def check(self, value: Any, field: str, kind: str, problems: list[Problem]) -> None:
        if isinstance(value, (sp.MatrixBase, list, tuple)):
            problems.append(
                Problem(
                    field,
                    "must be a scalar expression, got a vector or matrix",
                    "give one expression (sum the components yourself)",
                )
            )
            return
        if not isinstance(value, sp.Expr):
            problems.append(
                Problem(
                    field, f"{value!r} is not an expression", "give a SymPy expression or a number"
                )
            )
            return
        if self._is_fine(value, kind):
            return
        try:
            parts, free = _parts(value)  # one walk for the checks below
        except TypeError:  # an unhashable part
            parts, free = value.atoms(sp.Atom, sp.Derivative), value.free_symbols
        found = _not_finite(value, parts)
        if found is not None:
            problems.append(
                Problem(field, found, "energies, forces and positions are real numbers")
            )
        allowed = self._scope(kind)[0]
        for symbol in sorted(free - allowed, key=str):
            problems.append(self._diagnose(symbol, field, kind))
        for derivative in (p for p in parts if isinstance(p, sp.Derivative)):
            problems.append(
                Problem(
                    field,
                    f"{derivative} is not allowed",
                    "write velocities as NAME_dot; higher derivatives are not "
                    "part of a Lagrangian model",
                )
            )

    def _scope(self, kind: str) -> tuple[set[sp.Basic], set[sp.Basic]]:
        """(the names allowed in a value of ``kind``, the parts found fine for it); any other
        kind is the state's."""
        return self._scopes.get(kind, self._scopes[STATE])

    def _is_fine(self, value: sp.Expr, kind: str) -> bool:
        """Whether :meth:`check` would find nothing wrong with ``value``, from a walk that
        skips the parts found fine before (each other part is a name allowed for ``kind``, a
        number a double holds, or a sum, product, power or function of such parts); False
        also when the walk cannot tell (the full check then decides)."""
        return self._fine_parts(value, kind, enter_fine=False) is not None

    def symbols_if_fine(self, value: Any, kind: str) -> set[sp.Basic] | None:
        """The free symbols of ``value`` when :meth:`check` would find nothing wrong with
        it, else None: one walk of its parts for both (every other part is a number or a
        sum, product, power or function of parts, none binding a symbol)."""
        if not isinstance(value, sp.Expr):
            return None
        parts = self._fine_parts(value, kind, enter_fine=True)
        return None if parts is None else {part for part in parts if part.is_Symbol}

    def _fine_parts(self, value: sp.Expr, kind: str, enter_fine: bool) -> set[sp.Basic] | None:
        """The distinct parts of ``value`` the walk of :meth:`_is_fine` enters (with
        ``enter_fine``, the parts found fine before too), or None where it finds a part not
        fine or cannot tell."""
        allowed, fine = self._scope(kind)
        seen: set[sp.Basic] = set()
        stack = [value]
        try:
            while stack:
                part = stack.pop()
                if part in fine:  # first: most repeated parts were found fine before
                    if not enter_fine or part in seen:
                        continue
                elif part in seen:
                    continue
                elif not _fine_alone(part, allowed):
                    return None
                seen.add(part)
                stack.extend(part.args)
        except TypeError:  # an unhashable part
            return None
        fine.update(seen)
        return seen

    def _diagnose(self, symbol: Any, field: str, kind: str) -> Problem:
        name = str(symbol)
        if kind == CONSTANT and symbol in self.state:
            return Problem(
                field,
                f"{name} varies with the motion, but this is a constant",
                "use numbers and parameters only",
            )
        if symbol in self.velocities:
            return Problem(
                field,
                f"the velocity {name} may not appear here",
                "positions and potentials depend on coordinates and time only; put "
                "velocity-dependent terms in kinetic, velocity_potential or dissipation",
            )
        if symbol in self.accelerations:
            return Problem(
                field,
                f"the acceleration {name} may not appear in a model",
                "energies and forces depend on q, q_dot and t only",
            )
        close = closest_name(name, self.names)
        hint = f"did you mean {close!r}? " if close else ""
        return Problem(
            field, f"unknown name {name!r}", hint + "declare it in parameters (or coordinates)"
        )


def _parts(value: sp.Basic) -> tuple[set[sp.Basic], set[sp.Basic]]:
    """``value.atoms(sp.Atom, sp.Derivative)`` and ``value.free_symbols``, from one walk that
    visits each distinct subexpression once (a rolling contact's constraint has the square
    root of its axle's tilt in most terms: 3165 nodes, 188 of them distinct)."""
    distinct = distinct_parts(value)
    parts = {node for node in distinct if isinstance(node, (sp.Atom, sp.Derivative))}
    return parts, free_symbols(value, distinct)


def _fine_alone(part: sp.Basic, allowed: set[sp.Basic]) -> bool:
    """Whether ``part`` itself (not its arguments) passes every check of
    :meth:`NameScope.check`: an allowed Symbol, a rational or float a double holds, a
    constant such as pi, or a sum, product, power or function (:func:`is_plain`)."""
    if part.is_Symbol:
        return part in allowed
    if isinstance(part, sp.Atom):
        if isinstance(part, (sp.Rational, sp.Float)):
            return bool(abs(part) <= LARGEST_DOUBLE)
        return isinstance(part, sp.NumberSymbol)
    return is_plain(part)


#: The largest magnitude a double holds: a number beyond it is infinite in every computation.
LARGEST_DOUBLE = sp.Float(sys.float_info.max)
_NOT_FINITE = (sp.nan, sp.zoo, sp.oo, sp.S.NegativeInfinity)


def not_finite_real(value: sp.Expr) -> str | None:
    """Why ``value`` cannot be a real, finite quantity (it holds nan, an infinity, the
    imaginary unit or a number too large for a double), or None."""
    return _not_finite(value, value.atoms())


def _not_finite(value: sp.Expr, atoms: set[sp.Basic]) -> str | None:
    """:func:`not_finite_real` of ``value`` from its ``atoms`` (a superset is fine)."""
    if any(a in atoms for a in _NOT_FINITE):
        return f"{value} holds an undefined or infinite value (nan, oo or zoo)"
    if sp.I in atoms:
        return f"{value} is complex (holds I)"
    for number in (a for a in atoms if isinstance(a, sp.Number)):
        if abs(number) > LARGEST_DOUBLE:
            return f"the number {sp.Float(number, 3)} is too large for a double (beyond 1.8e308)"
    return None


def identifier_problem(name: str, field: str) -> Problem | None:
    """Why ``name`` cannot name a coordinate or parameter, or None: the one rule of
    :mod:`lagrangian.symbolic.names` (ASCII identifiers or Greek letters, no Python keyword;
    a lookalike letter is refused with the ASCII name it looks like)."""
    found = name_problem(name)
    return None if found is None else Problem(field, *found)


def _check_names(values: dict[str, Any], problems: list[Problem]) -> None:
    for kind in ("coordinates", "parameters"):
        for symbol in values[kind]:
            found = identifier_problem(symbol.name, f"{kind}.{symbol.name!r}")
            if found is not None:
                problems.append(found)
    coordinates = values["coordinates"]
    if not coordinates:
        problems.append(
            Problem("coordinates", "no generalized coordinates", "list at least one coordinate")
        )
    if len(coordinates) > MAX_COORDINATES:
        problems.append(
            Problem(
                "coordinates",
                f"{len(coordinates):,} coordinates, more than the {MAX_COORDINATES:,} a system "
                f"may have (its mass matrix alone would have {len(coordinates) ** 2:,} entries)",
                "model fewer degrees of freedom, or split the system into parts",
            )
        )
    if len(values["parameters"]) > MAX_PARAMETERS:
        problems.append(too_many_parameters(len(values["parameters"])))
    seen: set[str] = set()
    for q in coordinates:
        if q.name in seen:
            problems.append(Problem(f"coordinates.{q.name}", "listed twice", "list it once"))
        seen.add(q.name)
        if q.name == "t":
            problems.append(Problem("coordinates.t", "t is time", "rename the coordinate"))
    reserved = {velocity(q).name for q in coordinates}
    reserved |= {acceleration(q).name for q in coordinates}
    for q in coordinates:
        if q.name in reserved:
            problems.append(
                Problem(
                    f"coordinates.{q.name}",
                    "clashes with a velocity name",
                    f"names ending in {DOT_SUFFIX} or {DDOT_SUFFIX} are velocities",
                )
            )
    for p in values["parameters"]:
        if p.name in seen:
            problems.append(
                Problem(
                    f"parameters.{p.name}",
                    "is also a coordinate",
                    "a name is either a coordinate or a parameter; rename one of them",
                )
            )
        elif p.name in reserved:
            problems.append(
                Problem(
                    f"parameters.{p.name}", "clashes with a velocity name", "rename the parameter"
                )
            )
        elif p.name == "t":
            problems.append(Problem("parameters.t", "t is time", "rename the parameter"))


def too_many_parameters(count: int) -> Problem:
    """The problem of a System declaring ``count`` parameters, more than MAX_PARAMETERS."""
    return Problem(
        "parameters",
        f"{count:,} parameters, more than the {MAX_PARAMETERS:,} a system may have",
        "write numbers in the expressions for values that never change, or split the system",
    )


def _vector(
    value: Any, field: str, kind: str, scope: NameScope, problems: list[Problem]
) -> int | None:
    if not isinstance(value, tuple) or not 1 <= len(value) <= 3:
        problems.append(
            Problem(
                field,
                f"{value!r} is not a vector of 1 to 3 components",
                "give a list of expressions such as [l*sin(theta), -l*cos(theta)]",
            )
        )
        return None
    for i, component in enumerate(value):
        scope.check(component, f"{field}[{i}]", kind, problems)
    return len(value)


def _check_points(values: dict[str, Any], scope: NameScope, problems: list[Problem]) -> set[str]:
    names: set[str] = set()
    dims: dict[str, int] = {}
    for group in ("particles", "rigid_bodies"):
        for i, item in enumerate(values[group]):
            field = f"{group}[{i}]"
            if not isinstance(item.name, str) or not item.name:
                problems.append(Problem(f"{field}.name", "missing name", "give each a name"))
            elif item.name in names or item.name == ORIGIN:
                problems.append(
                    Problem(
                        f"{field}.name",
                        f"name {item.name!r} is taken",
                        "give each particle and body its own name",
                    )
                )
            names.add(item.name)
            scope.check(item.mass, f"{field}.mass", CONFIGURATION, problems)
            dim = _vector(item.position, f"{field}.position", CONFIGURATION, scope, problems)
            if dim is not None:
                dims[f"{field}.position"] = dim
            if group == "rigid_bodies":
                _check_rigid_body(item, field, dim, scope, values, problems)
    if values["gravity"] is not None:
        dim = _vector(values["gravity"], "gravity", CONFIGURATION, scope, problems)
        if dim is not None:
            dims["gravity"] = dim
    if len(set(dims.values())) > 1:
        listing = ", ".join(f"{k} has {v}" for k, v in dims.items())
        problems.append(
            Problem(
                "positions",
                f"inconsistent dimensions: {listing}",
                "give every position and the gravity vector the same number of components",
            )
        )
    return names | {ORIGIN}


def _check_rigid_body(
    item: Any, field: str, dim: int | None, scope: NameScope, values: dict, problems: list[Problem]
) -> None:
    """A planar body has a scalar inertia, an angle and 2 components; a 3-D one an
    orientation, a 3x3 inertia or a shape, and 3 components."""
    if (item.angle is None) == (item.orientation is None):
        given = "both an angle and" if item.angle is not None else "neither an angle nor"
        fix = "give angle (a planar body) or orientation (a 3-D body), not both"
        problems.append(Problem(field, f"body {item.name!r} has {given} an orientation", fix))
        return
    size, example = (2, "[x_c, y_c]") if item.planar else (3, "[x_c, y_c, z_c]")
    if dim is not None and dim != size:
        kind = "planar" if item.planar else "3-D"
        message = f"a {kind} rigid body needs {size} components"
        problems.append(Problem(f"{field}.position", message, f"give {example}"))
    if item.planar:
        scope.check(item.inertia, f"{field}.inertia", CONFIGURATION, problems)
        scope.check(item.angle, f"{field}.angle", CONFIGURATION, problems)
        return
    _check_orientation(item, f"{field}.orientation", scope, values, problems)
    _check_inertia(item, f"{field}.inertia", scope, values, problems)


def _entries_checked(
    entries: Iterable[Any], field: str, scope: NameScope, problems: list[Problem]
) -> bool:
    """Scope-check every entry, each problem once; True when all were fine."""
    found: list[Problem] = []
    for entry in entries:
        scope.check(entry, field, CONFIGURATION, found)
    problems.extend(dict.fromkeys(found))
    return not found


def _check_orientation(
    body: Any, field: str, scope: NameScope, values: dict, problems: list[Problem]
) -> None:
    orientation = body.orientation
    if not isinstance(orientation, Orientation) or orientation.matrix.shape != (3, 3):
        fix = "give a 3x3 matrix, or use euler_rotation, axis_angle or quaternion_rotation"
        problems.append(Problem(field, f"{orientation!r} is not a rotation", fix))
    elif _entries_checked(orientation.matrix, field, scope, problems) and _given(orientation):
        subject = f"the orientation of body {body.name!r}"
        problems.extend(check_rotation(orientation.matrix, field, _samples(values), subject))


def _given(orientation: Orientation) -> bool:
    """True when ``orientation`` is, or its rotations are relative to, a matrix given as
    such: Euler angles, an axis and angle, a quaternion and simple rotations make a rotation
    for every real value of their (finite, real: checked) entries, so only a given matrix
    needs the numerical check of R^T R = 1 and det R = 1."""
    while orientation.form == "rotations" and orientation.parent is not None:
        orientation = orientation.parent
    return orientation.form == "matrix"


def _check_inertia(
    body: Any, field: str, scope: NameScope, values: dict, problems: list[Problem]
) -> None:
    inertia = body.inertia
    if isinstance(inertia, Shape):
        entries = [value for _, value in inertia.dimensions]
    elif isinstance(inertia, sp.MatrixBase) and inertia.shape == (3, 3):
        entries = list(inertia)
    else:
        fix = "give a 3x3 matrix about the centre of mass in body axes, or a shape"
        problems.append(Problem(field, "a 3-D rigid body needs a 3x3 inertia", fix))
        return
    if _entries_checked([body.mass, *entries], field, scope, problems):
        parameters = values["parameters"]
        subject = f"the inertia of body {body.name!r}"
        tensor = body.inertia_tensor
        # the check reads the tensor's own symbols only: each sample is cut to those with a
        # known value (a parameter without a default is drawn afresh by the check), and one
        # that gives them the values of one checked already (an inertia of parameters only)
        # is passed over
        used = [s for s in tensor.free_symbols if parameters.get(s, 0.0) is not None]
        checked = set()
        for sample in _samples(values):
            known = {s: sample[s] for s in used if s in sample}
            seen = frozenset(known.items())
            if seen in checked:
                continue
            checked.add(seen)
            found = check_inertia(tensor, field, known, subject)
            if found:
                problems.extend(found)
                return


def _samples(values: dict) -> tuple[Mapping[sp.Symbol, float], ...]:
    """A few configurations for the numerical checks: coordinates and t drawn at random in
    (0.3, 1.3), parameters at their defaults (drawn too when they have none)."""
    return _samples_of(tuple(values["coordinates"]), tuple(values["parameters"].items()))


@remembered(maxsize=8)
def _samples_of(
    coordinates: tuple[sp.Symbol, ...], parameters: tuple[tuple[sp.Symbol, float | None], ...]
) -> tuple[Mapping[sp.Symbol, float], ...]:
    """:func:`_samples`, drawn once for the checks of every body (read-only)."""
    rng = random.Random(SEED)
    samples = []
    for _ in range(PROBES):
        point = random_values([*coordinates, t, *(p for p, _ in parameters)], rng)
        point.update((p, v) for p, v in parameters if v is not None)
        samples.append(MappingProxyType(point))
    return tuple(samples)


def _check_point_ref(
    ref: Any, field: str, points: set[str], scope: NameScope, problems: list[Problem]
) -> None:
    if isinstance(ref, str):
        if ref not in points:
            close = closest_name(ref, points)
            hint = f"did you mean {close!r}? " if close else ""
            problems.append(
                Problem(
                    field,
                    f"unknown point {ref!r}",
                    hint + "name a particle, a rigid body or 'origin', or give a position vector",
                )
            )
    else:
        _vector(ref, field, CONFIGURATION, scope, problems)


def _check_elements(
    values: dict[str, Any], scope: NameScope, points: set[str], problems: list[Problem]
) -> None:
    for group, attr in (("springs", "stiffness"), ("dampers", "coefficient")):
        for i, item in enumerate(values[group]):
            field = f"{group}[{i}]"
            if not isinstance(item.between, tuple) or len(item.between) != 2:
                problems.append(
                    Problem(
                        f"{field}.between", "needs exactly two points", "give [point_a, point_b]"
                    )
                )
                continue
            for j, ref in enumerate(item.between):
                _check_point_ref(ref, f"{field}.between[{j}]", points, scope, problems)
            scope.check(getattr(item, attr), f"{field}.{attr}", CONFIGURATION, problems)
            if group == "springs":
                scope.check(item.rest_length, f"{field}.rest_length", CONFIGURATION, problems)
    for i, item in enumerate(values["forces"]):
        _check_point_ref(item.at, f"forces[{i}].at", points, scope, problems)
        _vector(item.force, f"forces[{i}].force", STATE, scope, problems)
    bodies = {b.name: b for b in values["rigid_bodies"]}
    for i, item in enumerate(values["torques"]):
        if item.body not in bodies:
            problems.append(
                Problem(
                    f"torques[{i}].body",
                    f"unknown rigid body {item.body!r}",
                    "name one of the rigid_bodies",
                )
            )
        field = f"torques[{i}].torque"
        if item.body in bodies and not bodies[item.body].planar:
            if _vector(item.torque, field, STATE, scope, problems) not in (None, 3):
                fix = "give [tau_x, tau_y, tau_z] in world axes"
                problems.append(Problem(field, "a torque on a 3-D body has 3 components", fix))
        else:
            scope.check(item.torque, field, STATE, problems)


def _check_circuit(values: dict[str, Any], scope: NameScope, problems: list[Problem]) -> None:
    for i, item in enumerate(values["circuit"]):
        field = f"circuit[{i}]"
        if isinstance(item, Inductor):
            scope.check(item.inductance, f"{field}.inductance", CONFIGURATION, problems)
            scope.check(item.current, f"{field}.current", STATE, problems)
        elif isinstance(item, MutualInductance):
            scope.check(item.inductance, f"{field}.inductance", CONFIGURATION, problems)
            for j, current in enumerate(item.currents):
                scope.check(current, f"{field}.currents[{j}]", STATE, problems)
        elif isinstance(item, Capacitor):
            scope.check(item.capacitance, f"{field}.capacitance", CONFIGURATION, problems)
            scope.check(item.charge, f"{field}.charge", CONFIGURATION, problems)
        elif isinstance(item, Resistor):
            scope.check(item.resistance, f"{field}.resistance", CONFIGURATION, problems)
            scope.check(item.current, f"{field}.current", STATE, problems)
        elif isinstance(item, VoltageSource):
            scope.check(item.voltage, f"{field}.voltage", STATE, problems)
            if item.coordinate not in scope.coordinates:
                problems.append(
                    Problem(
                        f"{field}.coordinate",
                        f"unknown coordinate {item.coordinate!s}",
                        "name one of the coordinates (a charge)",
                    )
                )
        else:
            problems.append(
                Problem(
                    field,
                    f"{type(item).__name__} is not a circuit element",
                    "use Inductor, MutualInductance, Capacitor, Resistor or VoltageSource",
                )
            )


def validate(values: dict[str, Any]) -> Iterable[Problem]:
    """Every problem of a canonical System description, in field order."""
    problems: list[Problem] = []
    _check_names(values, problems)
    scope = NameScope(values)
    for name in ("kinetic", "lagrangian", "velocity_potential", "dissipation"):
        scope.check(values[name], name, STATE, problems)
    for name in ("kinetic", "lagrangian", "velocity_potential"):
        _check_smooth_in_velocities(values[name], name, scope, problems)
    scope.check(values["potential"], "potential", CONFIGURATION, problems)
    for key, value in values["generalized_forces"].items():
        if key not in scope.coordinates:
            problems.append(
                Problem(
                    f"generalized_forces.{key}",
                    f"unknown coordinate {key!s}",
                    "generalized forces are keyed by coordinate",
                )
            )
        scope.check(value, f"generalized_forces.{key}", STATE, problems)
    points = _check_points(values, scope, problems)
    _check_elements(values, scope, points, problems)
    _check_circuit(values, scope, problems)
    check_constraints(values, scope, problems)
    check_transitions(values["transitions"], scope, problems)
    for key, value in values["initial"].items():
        if key not in scope.coordinates and key not in scope.velocities:
            problems.append(
                Problem(
                    f"initial.{key}",
                    f"{key!s} is not a coordinate or velocity",
                    "give initial values of coordinates and NAME_dot velocities",
                )
            )
        found = _not_finite_value(value)
        if found is not None:
            problems.append(Problem(f"initial.{key}", found, "give a finite real number"))
    return problems


_LETTER = {"kinetic": "T", "lagrangian": "L", "velocity_potential": "U"}


def _check_smooth_in_velocities(
    value: Any, field: str, scope: NameScope, problems: list[Problem]
) -> None:
    """An energy whose momentum dT/dq_dot would jump (|x_dot| in T) is refused with the
    reason (:func:`lagrangian.symbolic.nonsmooth.kinks_in`)."""
    if not isinstance(value, sp.Expr):
        return  # reported by the scope's check
    kinks = kinks_in(value, scope.velocities)
    if kinks:
        parts = ", ".join(map(str, kinks[:3]))
        problems.append(
            Problem(
                field,
                f"{parts} is not smooth in the velocities: the momentum "
                f"d{_LETTER[field]}/dq_dot "
                "would jump where its argument changes sign, and the mass matrix hold an "
                "impulse there, which no equations of motion describe",
                "a force by the sign of a velocity (Coulomb friction) is a dissipation "
                "function, such as dissipation: mu*N*Abs(x_dot); an energy is smooth in the "
                "velocities (x_dot**2, not Abs(x_dot) nor Abs(x_dot)**2)",
            )
        )


def _not_finite_value(value: Any) -> str | None:
    """Why an initial value is not a finite real number (nan, inf, complex), or None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, float)):
        return None if math.isfinite(value) else f"{value!r} is not a finite number"
    if isinstance(value, sp.Expr):
        return not_finite_real(value)
    return None
