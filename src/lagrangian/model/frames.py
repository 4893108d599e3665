"""Reference frames and relative orientations: a massless :class:`Frame`, and the resolution
of every body or frame oriented relative to a parent by simple rotations into one composed
rotation R = R_parent R1(a1) ... Rm(am) (:func:`~lagrangian.model.rotation.rotation_sequence`).

A gyroscope in a gimbal: the gimbal turns about the world z axis, the rotor about the
gimbal's x axis; the rotor's rotation is the product, its angular velocity the sum
omega_s = psi_dot z + R_gimbal x phi_dot:

>>> import sympy as sp
>>> import lagrangian as lg
>>> from lagrangian.model.frames import Frame
>>> psi, phi, m, A, C = sp.symbols("psi phi m A C")
>>> rotor = lg.RigidBody("rotor", m, sp.diag(C, A, A), (0, 0, 0),
...                      parent="gimbal", rotations=[("x", phi)])
>>> gyro = lg.System(coordinates=[psi, phi], parameters=[m, A, C],
...                  frames=[Frame("gimbal", [("z", psi)])], rigid_bodies=[rotor])
>>> lg.model.spatial_angular_velocity(gyro.rigid_bodies[0].orientation, [psi, phi]).T
Matrix([[phi_dot*cos(psi), phi_dot*sin(psi), psi_dot]])
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, replace
from typing import Any

import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.model.elements import ORIGIN, as_rotations, orientation_value
from lagrangian.model.rotation import Orientation, rotation_sequence
from lagrangian.model.validation import CONFIGURATION, NameScope
from lagrangian.symbolic.canonical import Builder


@dataclass(frozen=True)
class Frame:
    """A massless reference frame: no inertia, no position, only an orientation relative to
    a ``parent`` (a 3-D rigid body or another frame; the world when None) by ``rotations``,
    simple rotations ``[("z", psi), ("x", theta), ...]`` about its own successive axes, or
    (without parent and rotations) an ``orientation`` given in any form.

    Bodies and frames name it as their ``parent``; the System fills ``orientation`` with the
    composed rotation R = R_parent R1(a1) R2(a2) ... (frame axes -> world axes).
    """

    name: str
    rotations: tuple[tuple[Any, sp.Expr], ...] = ()
    parent: str | None = None
    orientation: Orientation | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "rotations", as_rotations(self.rotations))
        object.__setattr__(self, "orientation", orientation_value(self.orientation))

    @property
    def relative(self) -> bool:
        """True when the frame is oriented by ``rotations`` relative to a parent (or the world)."""
        return self.parent is not None or bool(self.rotations)


_IDENTITY = Orientation(sp.ImmutableMatrix(sp.eye(3)))
_FIX_PARENT = "name a 3-D rigid body or a frame, or leave parent out (relative to the world)"


class _Resolver:
    """Composes the orientation of every frame and relative body, parents first."""

    def __init__(self, values: dict[str, Any], problems: list[Problem]) -> None:
        self.problems = problems
        self.nodes: dict[str, tuple[str, int, Any]] = {}
        for group in ("frames", "rigid_bodies"):
            for i, item in enumerate(values[group]):
                self.nodes.setdefault(item.name, (group, i, item))
        self.scope = NameScope(values)
        self.builder = Builder()  # each frame's entries are the sums of its children's
        self.done: dict[str, Orientation | None] = {}
        self.stack: list[str] = []

    def orientation(self, name: str) -> Orientation | None:
        """The (composed) orientation of node ``name``; None after a problem."""
        if name in self.done:
            return self.done[name]
        group, i, item = self.nodes[name]
        if item.relative:
            result = self._compose(group, i, item)
        elif isinstance(item, Frame) and item.orientation is None:
            result = _IDENTITY  # a frame given nothing is the world's
        else:
            result = item.orientation  # given directly (None: a planar body)
        self.done[name] = result
        return result

    def _compose(self, group: str, i: int, item: Any) -> Orientation | None:
        field, who = f"{group}[{i}]", _who(group, item.name)
        # an orientation of form "rotations" is a composition made here before
        if item.orientation is not None and item.orientation.form != "rotations":
            fix = "give either orientation or parent and rotations, not both"
            self.problems.append(Problem(f"{field}.orientation", f"{who} has both", fix))
            return None
        parent = None
        if item.parent is not None:
            parent = self._parent(field, who, item)
            if parent is None:
                return None
        if not isinstance(item.rotations, tuple):
            fix = "give a list of [axis, angle] pairs, e.g. [[z, psi], [x, theta]]"
            self.problems.append(Problem(f"{field}.rotations", f"{who}: not a list", fix))
            return None
        before = len(self.problems)
        for k, turn in enumerate(item.rotations):
            if isinstance(turn, tuple) and len(turn) == 2 and isinstance(turn[1], sp.Expr):
                where = f"{field}.rotations[{k}]"
                self.scope.check(turn[1], where, CONFIGURATION, self.problems)
        if len(self.problems) > before:
            return None
        try:
            return rotation_sequence(item.rotations, parent, builder=self.builder)
        except ModelError as error:
            for p in error.problems:
                message = f"{who}: {p.message}"
                self.problems.append(Problem(f"{field}.{p.field}", message, p.fix))
            return None

    def _parent(self, field: str, who: str, item: Any) -> Orientation | None:
        name = item.parent
        where = f"{field}.parent"
        if name not in self.nodes:
            close = difflib.get_close_matches(str(name), sorted(self.nodes), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            message = f"{who}: unknown parent {name!r}"
            self.problems.append(Problem(where, message, hint + _FIX_PARENT))
            return None
        chain = [*self.stack, item.name]
        if name in chain:
            loop = " -> ".join([*chain[chain.index(name) :], name])
            fix = "make one of them relative to the world (leave out its parent)"
            message = f"{who}: the parents form a cycle ({loop})"
            self.problems.append(Problem(where, message, fix))
            return None
        self.stack.append(item.name)
        try:
            parent = self.orientation(name)
        finally:
            self.stack.pop()
        if parent is None and name not in self._failed_parents():
            message = f"{who}: the parent {name!r} is a planar body (it has no 3-D orientation)"
            self.problems.append(Problem(where, message, _FIX_PARENT))
        return parent

    def _failed_parents(self) -> set[str]:
        """Nodes whose own composition failed (already reported)."""
        return {
            name
            for name, (_, _, item) in self.nodes.items()
            if self.done.get(name) is None and item.relative
        }


def _who(group: str, name: str) -> str:
    return f"frame {name!r}" if group == "frames" else f"body {name!r}"


def resolve_orientations(values: dict[str, Any]) -> list[Problem]:
    """Fill the ``orientation`` of every frame and of every rigid body given ``parent`` or
    ``rotations`` in the canonical System ``values`` with its composed rotation; the problems
    found (unknown parent, a cycle of parents, an unknown axis, a name taken)."""
    problems: list[Problem] = []
    _check_frame_names(values, problems)
    resolver = _Resolver(values, problems)
    for group in ("frames", "rigid_bodies"):
        items = list(values[group])
        for i, item in enumerate(items):
            if item.relative or isinstance(item, Frame):
                composed = resolver.orientation(item.name)
                if resolver.nodes[item.name][2] is not item:
                    continue  # a duplicate name, reported
                items[i] = replace(item, orientation=composed or _IDENTITY)
        values[group] = tuple(items)
    return problems


def _check_frame_names(values: dict[str, Any], problems: list[Problem]) -> None:
    taken = {item.name for group in ("particles", "rigid_bodies") for item in values[group]}
    taken.add(ORIGIN)
    for i, frame in enumerate(values["frames"]):
        field = f"frames[{i}].name"
        if not isinstance(frame.name, str) or not frame.name:
            problems.append(Problem(field, "missing name", "give each frame a name"))
        elif frame.name in taken:
            message = f"name {frame.name!r} is taken"
            problems.append(Problem(field, message, "give each frame, particle and body its own"))
        taken.add(frame.name)
