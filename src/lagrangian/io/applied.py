"""The ``forces`` and ``torques`` sections of a model file, with the loads that are not one
System element each: a force at a body-fixed point (``offset``), a torque that one body or
frame exerts on another (``by``, with its reaction), and a torque on a massless frame
(``frame``).  They become plain forces, torques and generalized forces
(:mod:`lagrangian.model.loads`) once the orientations of the bodies and frames are composed.

    forces:
      - {at: rod, offset: [0, -l/2], force: [F, 0]}     # at the rod's tip (body axes)
      - {at: wheel_contact, force: [Fx, Fy, 0]}          # at a rolling disc's contact point
    torques:
      - {body: rotor, by: stator, torque: tau}           # and -tau on the stator
      - {frame: gimbal, torque: [tau, 0, 0]}             # on a massless frame

>>> import lagrangian as lg
>>> text = '''
... coordinates: [a]
... parameters: {l: 1.0, F: 1.0}
... rigid_bodies: [{name: rod, mass: 1, inertia: 1, position: [0, 0], angle: a}]
... forces: [{at: rod, offset: [l, 0], force: [0, F]}]
... '''
>>> lg.derive(lg.loads(text)).generalized_forces
Matrix([[F*l*cos(a)]])
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import sympy as sp

from lagrangian.errors import ModelError, Problem
from lagrangian.io.document import child
from lagrangian.io.model_schema import entry_keys
from lagrangian.io.reader import Reader, suggestion
from lagrangian.io.sections import read_fields
from lagrangian.model import Force, System, Torque
from lagrangian.model.elements import ORIGIN
from lagrangian.model.loads import force_at_point, frame_torque, torque_pair

#: The keys of a rigid body entry that make it a 3-D body.
_SPATIAL_KEYS = ("orientation", "parent", "rotations")
_TORQUE_EXAMPLE = "write {body: rod, torque: tau} or {frame: gimbal, torque: [tau, 0, 0]}"


@dataclass(frozen=True)
class PointForce:
    """A force (world axes) at the point ``offset`` (body axes, from the centre of mass) of
    the rigid body ``body``."""

    body: str
    offset: tuple[sp.Expr, ...]
    force: tuple[sp.Expr, ...]
    name: str = ""


@dataclass(frozen=True)
class AppliedTorque:
    """A torque on the body or frame ``on`` (``key`` says which the file wrote: body or
    frame), exerted by the body or frame ``by`` (None: from outside, no reaction)."""

    on: str
    key: str
    torque: Any
    by: str | None = None
    name: str = ""
    by_frame: bool = False

    @property
    def on_frames(self) -> bool:
        """True when the torque or its reaction acts on a frame."""
        return self.key == "frame" or self.by_frame


@dataclass
class Loads:
    """The entries of ``forces`` and ``torques`` in file order, each with its path."""

    forces: list[tuple[str, Force | PointForce]] = field(default_factory=list)
    torques: list[tuple[str, Torque | AppliedTorque]] = field(default_factory=list)


@dataclass(frozen=True)
class _Names:
    """What the file names: rigid bodies (name -> planar), frames, particles, contacts."""

    bodies: dict[str, bool]
    frames: set[str]
    particles: set[str]
    contacts: set[str]

    @classmethod
    def of(cls, data: dict[str, Any]) -> _Names:
        def entries(section: str) -> list[dict[str, Any]]:
            value = data.get(section)
            items = value if isinstance(value, list) else []
            return [item for item in items if isinstance(item, dict)]

        def named(section: str) -> list[dict[str, Any]]:
            return [e for e in entries(section) if isinstance(e.get("name"), str)]

        bodies = {e["name"]: not any(k in e for k in _SPATIAL_KEYS) for e in named("rigid_bodies")}
        contacts = set()
        for disc in entries("rolling"):
            name, body = disc.get("name"), disc.get("body")
            if isinstance(name, str):
                contacts.add(name)
            elif isinstance(body, str):
                contacts.add(f"{body}_contact")
        return cls(
            bodies,
            {e["name"] for e in named("frames")},
            {e["name"] for e in named("particles")},
            contacts,
        )

    def what(self, name: str) -> str:
        """How the name ``name`` is known, for messages: "the particle 'bob'"."""
        if name in self.bodies:
            return f"the rigid body {name!r}"
        if name in self.frames:
            return f"the frame {name!r}"
        if name in self.particles:
            return f"the particle {name!r}"
        return f"{name!r}"


def read_loads(reader: Reader, data: dict[str, Any], coordinates: list[str]) -> Loads:
    """The ``forces`` and ``torques`` of the file, every name and size checked."""
    names = _Names.of(data)
    loads = Loads()
    for path, entry in reader.entries(data.get("forces", []), "forces", "force"):
        values = read_fields(reader, entry, path, coordinates)
        if values is None or not {"at", "force"} <= set(values):
            continue
        name = values.get("name", "")
        if "offset" in values:
            point = PointForce(values["at"], values["offset"], values["force"], name)
            if _check_point_force(reader, point, path, names):
                loads.forces.append((path, point))
        elif _check_force(reader, values["at"], path, names):
            loads.forces.append((path, Force(**values)))
    for path, entry in reader.entries(data.get("torques", []), "torques", "torque"):
        values = read_fields(reader, entry, path, coordinates)
        if values is None:
            continue
        if not {"body", "frame"} & set(entry) and set(entry) - set(entry_keys("torque").allowed):
            continue  # a misspelt body: reported as an unknown key with a suggestion
        key = reader.one_of(entry, ("body", "frame"), path, "a torque", _TORQUE_EXAMPLE)
        if key is None or "torque" not in values:
            continue
        name, by = values.get("name", ""), values.get("by")
        applied = AppliedTorque(values[key], key, values["torque"], by, name, by in names.frames)
        if key == "body" and by is None:  # a plain torque: its size is the System's to check
            if _check_target(reader, applied, path, names):
                loads.torques.append((path, Torque(values["body"], values["torque"], name)))
        elif _check_torque(reader, applied, path, names):
            loads.torques.append((path, applied))
    return loads


def _check_force(reader: Reader, at: Any, path: str, names: _Names) -> bool:
    """A force at a named point names a particle, a rigid body, origin or a contact point."""
    known = {*names.particles, *names.bodies, *names.contacts, ORIGIN}
    if not isinstance(at, str) or at in known:
        return True
    where = child(path, "at")
    if at in names.frames:
        fix = "a frame has no position: name a particle, a rigid body or a contact point"
        reader.problem(where, f"{names.what(at)} is a frame", fix)
        return False
    fix = "name a particle, a rigid body, a contact point or origin, or give a position"
    reader.problem(where, f"unknown point {at!r}", suggestion(at, sorted(known), fix))
    return False


def _check_point_force(reader: Reader, point: PointForce, path: str, names: _Names) -> bool:
    """``at`` names a rigid body; the offset and the force have its dimension."""
    where = child(path, "at")
    if not isinstance(point.body, str):
        fix = "name the rigid body the point belongs to (at: rod), or leave out offset"
        reader.problem(where, "a force with an offset acts at a point of a rigid body", fix)
        return False
    if point.body not in names.bodies:
        if point.body in {*names.particles, *names.frames, *names.contacts, ORIGIN}:
            message = f"{names.what(point.body)} is not a rigid body (it has no body axes)"
            reader.problem(where, message, "name a rigid body, or leave out offset")
        else:
            fix = suggestion(point.body, sorted(names.bodies), "name one of the rigid_bodies")
            reader.problem(where, f"unknown rigid body {point.body!r}", fix)
        return False
    size = 2 if names.bodies[point.body] else 3
    kind = "a planar body" if size == 2 else "a 3-D body"
    example = "[dx, dy]" if size == 2 else "[dx, dy, dz]"
    fine = True
    if len(point.offset) != size:
        message = f"needs {size} components on {kind}, got {len(point.offset)}"
        reader.problem(child(path, "offset"), message, f"give {example} in body axes")
        fine = False
    if len(point.force) != size:
        message = f"needs {size} components on {kind}, got {len(point.force)}"
        reader.problem(child(path, "force"), message, "give the force in world axes")
        fine = False
    return fine


def _check_torque(reader: Reader, applied: AppliedTorque, path: str, names: _Names) -> bool:
    """What the torque acts on is a body (``body``) or a frame (``frame``), ``by`` another
    body or frame, and the torque a scalar between planar bodies, else 3 components."""
    fine = _check_target(reader, applied, path, names)
    by = applied.by
    if by is not None and by == applied.on:
        fix = "name the other body or frame that exerts the torque, or leave out by"
        message = f"a torque pair needs two bodies or frames, got {by!r} twice"
        reader.problem(child(path, "by"), message, fix)
        fine = False
    elif by is not None and by not in names.bodies and by not in names.frames:
        choices = sorted([*names.bodies, *names.frames])
        fix = suggestion(by, choices, "name one of the rigid_bodies or frames")
        if by in names.particles or by == ORIGIN:
            message = f"{names.what(by)} is not a rigid body or a frame"
        else:
            message = f"unknown rigid body or frame {by!r}"
        reader.problem(child(path, "by"), message, fix)
        fine = False
    if not fine:
        return False
    involved = [name for name in (applied.on, by) if name is not None]
    planar = [names.bodies.get(name, False) for name in involved]
    where = child(path, "torque")
    if any(planar) and not all(planar):
        fix = "a planar body exchanges torques with planar bodies only"
        reader.problem(child(path, "by"), "one body is planar, the other 3-D", fix)
        return False
    if all(planar) and isinstance(applied.torque, tuple):
        reader.problem(where, "a torque on a planar body is a scalar", "give one expression")
        return False
    if not all(planar) and not (isinstance(applied.torque, tuple) and len(applied.torque) == 3):
        fix = "give [tau_x, tau_y, tau_z] in world axes"
        reader.problem(where, "a torque on a 3-D body or a frame has 3 components", fix)
        return False
    return True


def _check_target(reader: Reader, applied: AppliedTorque, path: str, names: _Names) -> bool:
    on, where = applied.on, child(path, applied.key)
    if applied.key == "body" and on in names.bodies:
        return True
    if applied.key == "frame" and on in names.frames:
        return True
    if applied.key == "body" and on in names.frames:
        reader.problem(where, f"{on!r} is a frame", f"write frame: {on}")
    elif applied.key == "frame" and on in names.bodies:
        reader.problem(where, f"{on!r} is a rigid body", f"write body: {on}")
    elif applied.key == "body":
        fix = suggestion(on, sorted(names.bodies), "name one of the rigid_bodies")
        reader.problem(where, f"unknown rigid body {on!r}", fix)
    else:
        fix = suggestion(on, sorted(names.frames), "name one of the frames")
        reader.problem(where, f"unknown frame {on!r}", fix)
    return False


def apply_loads(fields: dict[str, Any], loads: Loads) -> dict[str, str]:
    """Put the ``loads`` into the System keyword arguments ``fields`` as ``forces``,
    ``torques`` and added ``generalized_forces``; the path in the file of each force and
    torque the System will hold (System path -> file path, the more specific first).

    The orientations of bodies and frames come from a System of the coordinates,
    parameters, frames and rigid bodies alone (cheap: no constraints, no rolling); a
    ModelError of that System names the rigid_bodies and frames as the file does."""
    probe = None
    if _needs_orientations(loads):
        probe = System(
            coordinates=fields["coordinates"],
            parameters=fields["parameters"],
            frames=fields["frames"],
            rigid_bodies=fields["rigid_bodies"],
        )
    forces: list[Force] = []
    torques: list[Torque] = []
    moments: list[tuple[str, Torque]] = []
    extra: dict[sp.Symbol, sp.Expr] = {}
    paths: dict[str, str] = {}
    for path, item in loads.forces:
        paths[f"forces[{len(forces)}]"] = path
        if isinstance(item, Force):
            forces.append(item)
            continue
        assert probe is not None  # a point force needs the body's orientation
        body = next(b for b in probe.rigid_bodies if b.name == item.body)
        force, moment = _located(path, force_at_point, body, item.offset, item.force, item.name)
        forces.append(force)
        moments.append((path, moment))
    for path, load in loads.torques:
        if isinstance(load, Torque):
            paths[f"torques[{len(torques)}]"] = path
            torques.append(load)
            continue
        made = _applied(path, load, probe, extra)
        for torque, key in made:
            where = f"torques[{len(torques)}]"
            paths[f"{where}.body"] = child(path, key)
            paths[where] = path
            torques.append(torque)
    for path, moment in moments:
        where = f"torques[{len(torques)}]"
        paths.update({f"{where}.body": child(path, "at"), f"{where}.torque": child(path, "force")})
        paths[where] = path
        torques.append(moment)
    fields["forces"], fields["torques"] = forces, torques
    if extra:
        given = dict(fields["generalized_forces"])
        for q, value in extra.items():
            given[q] = given.get(q, sp.Integer(0)) + value
        fields["generalized_forces"] = given
    return paths


def _needs_orientations(loads: Loads) -> bool:
    frames = any(isinstance(t, AppliedTorque) and t.on_frames for _, t in loads.torques)
    return frames or any(isinstance(f, PointForce) for _, f in loads.forces)


def _applied(
    path: str, load: AppliedTorque, probe: System | None, extra: dict[sp.Symbol, sp.Expr]
) -> list[tuple[Torque, str]]:
    """The Torque elements of ``load`` with the key each comes from (body, by); torques on
    frames are added to ``extra`` (coordinate -> generalized force)."""
    frames = {f.name: f for f in probe.frames} if probe is not None else {}
    on_frame, by_frame, label = load.key == "frame", load.by_frame, load.name
    if load.by is None:
        pair = (Torque(load.on, load.torque, label), None)
    else:
        pair = _located(path, torque_pair, load.on, load.by, load.torque, label)
    made: list[tuple[Torque, str]] = []
    for torque, is_frame, key in ((pair[0], on_frame, load.key), (pair[1], by_frame, "by")):
        if torque is None:
            continue
        if not is_frame:
            made.append((torque, key))
            continue
        assert probe is not None
        orientation = frames[torque.body].orientation
        found = _located(path, frame_torque, orientation, probe.coordinates, torque.torque)
        for q, value in found.items():
            extra[q] = extra.get(q, sp.Integer(0)) + value
    return made


def _located(path: str, function: Any, *args: Any) -> Any:
    """``function(*args)``, its ModelError's problems placed under ``path`` in the file."""
    try:
        return function(*args)
    except ModelError as error:
        problems = [Problem(child(path, p.field), p.message, p.fix) for p in error.problems]
        raise ModelError(str(error), problems) from error
