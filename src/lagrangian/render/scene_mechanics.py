"""The mechanical panel of a scene: particles with their trails, rods (consecutive points at a
fixed distance, found from the positions), springs as coils between their ends (the rest
length kept), dampers as dashpots, then the bodies, wires, pulleys and ground
(:mod:`~lagrangian.render.scene_bodies`, :mod:`~lagrangian.render.scene_wires`), and the disks
and walls that unilateral constraints describe (:mod:`~lagrangian.render.scene_contacts`: a
gas's disks at their radius in their box).

A spring and a damper between the same two points are drawn side by side, as they are built.

>>> import lagrangian as lg
>>> from lagrangian.render.scene import scene_of
>>> system = lg.examples.mass_spring_damper()
>>> scene = scene_of(system, lg.simulate(system, t_span=1.0, samples=11), frames=5)
>>> scene.panels[0].kinds()
['spring', 'damper', 'particle']
"""

from __future__ import annotations

import dataclasses
import random
from collections import defaultdict
from collections.abc import Mapping, Sequence
from itertools import pairwise
from typing import Any

import numpy as np
import sympy as sp

from lagrangian.model import System
from lagrangian.render.scene import PALETTE, Element, Panel, Shape, style
from lagrangian.render.scene_contacts import Contacts, contacts_of, wall_segments
from lagrangian.render.scene_geometry import across, coil_line, dashpot_line
from lagrangian.render.stage import Stage, stage_of
from lagrangian.render.timing import FrameStates
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.probe import PROBES, SEED, ZERO, evaluate, random_values

#: Frames of trail behind each particle.
TRAIL = 40
#: The coil's turns, and its half-width and a dashpot's as fractions of the scene's half-width.
TURNS = 8
COIL_WIDTH = 0.035
#: The grey of rods, wires, strings and walls.
STRUCTURE = "#4d4d4d"
#: The opacity (hex, of 255) of a disk's fill in its particle's colour.
DISK_FILL = "40"


def _constant_distance(a: Sequence[Any], b: Sequence[Any], coordinates: set[sp.Symbol]) -> bool:
    """Whether the points a and b keep one non-zero distance whatever the coordinates: the
    squared distance takes one value at random configurations (the probe's points and
    precision, :mod:`lagrangian.symbolic.probe`), the parameters held at random values.  No
    simplification: a bicycle's points would keep ``trigsimp`` busy for minutes."""
    squared = sp.Add(*[(to_sympy(x) - to_sympy(y)) ** 2 for x, y in zip(a, b)])
    free = squared.free_symbols
    rng = random.Random(SEED)
    held = random_values(free - coordinates, rng)
    values = [
        evaluate(squared, {**held, **random_values(free & coordinates, rng)})
        for _ in range(PROBES if free & coordinates else 1)
    ]
    if any(v is None for v in values):
        return False
    numbers = np.array(values, dtype=float)
    return bool(numbers[0] > ZERO and np.ptp(numbers) <= 1e-12 * max(1.0, abs(numbers[0])))


def rods(system: System) -> list[tuple[str, str]]:
    """Pairs of consecutive points (origin first) at a fixed distance: rigid links to draw.

    >>> import lagrangian as lg
    >>> rods(lg.examples.double_pendulum())
    [('origin', 'bob1'), ('bob1', 'bob2')]
    """
    points = system.points()
    order = ["origin", *(n for n in points if n != "origin")]
    coordinates = set(system.coordinates)
    return [
        (a, b) for a, b in pairwise(order) if _constant_distance(points[a], points[b], coordinates)
    ]


def mechanics_panel(system: System, states: FrameStates, projection: str) -> Panel | None:
    """The panel of everything that moves in space; None when nothing does (a circuit, a
    model given by its energies alone)."""
    from lagrangian.render.scene_bodies import body_elements, ground_elements
    from lagrangian.render.scene_wires import atwood_elements, wire_elements

    if not [name for name in system.points() if name != "origin"]:
        return None
    stage = stage_of(system, states, projection)
    stage = _spanning_anchors(stage)
    pulleys, strings, hung = atwood_elements(stage)
    held = {name for string in strings for name in string.info["masses"]}
    wires, beads = wire_elements(stage, exclude=held)
    bodies = body_elements(stage, hung)
    contacts = Contacts({}, ()) if stage.three_d or stage.vertical else contacts_of(system)
    elements = [
        *ground_elements(stage),
        *_wall_elements(stage, contacts),
        *wires,
        *strings,
        *_rod_elements(stage, exclude=beads),
        *_link_elements(stage),
        *pulleys,
        *bodies,
        *_particle_elements(stage, contacts.radii),
    ]
    title = system.name or "system"
    if stage.three_d:
        title += f" ({stage.view_name} view)"
    return Panel(title, _bounds(elements, stage), tuple(elements))


def _spanning_anchors(stage: Stage) -> Stage:
    """The stage with its span grown to reach the fixed ends of springs and dampers."""
    reach = [stage.span]
    links: list[Any] = [*stage.system.springs, *stage.system.dampers]
    for link in links:
        for ref in link.between:
            ends = stage.anchor(ref)
            finite = ends[np.isfinite(ends)]
            reach.append(float(np.max(np.abs(finite), initial=0.0)))
    return dataclasses.replace(stage, span=max(reach))


def _rod_elements(stage: Stage, exclude: set[str]) -> list[Element]:
    made = []
    for a, b in rods(stage.system):
        if a in exclude or b in exclude:
            continue  # a bead on a moving wire: the wire holds it, not a rod
        ends = np.stack([stage.point(a), stage.point(b)], axis=1)  # (F, 2, 3)
        length = float(np.nanmean(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=-1)))
        shape = Shape("line", {"points": stage.flat(ends)}, style(STRUCTURE, 2.0), moving=True)
        made.append(Element("rod", (shape,), f"{a}-{b}", {"length": length}))
    return made


def _ref_name(ref: Any) -> str:
    return ref if isinstance(ref, str) else "(" + ", ".join(str(x) for x in ref) + ")"


def _link_elements(stage: Stage) -> list[Element]:
    """Springs (coils) and dampers (dashpots), side by side where they share their ends."""
    system = stage.system
    links: list[tuple[str, Any]] = [("spring", s) for s in system.springs]
    links += [("damper", d) for d in system.dampers]
    groups: dict[tuple[str, ...], list[int]] = defaultdict(list)
    for k, (_, link) in enumerate(links):
        groups[_ends_key(link)].append(k)
    width = stage.pixels(COIL_WIDTH)
    made = []
    for k, (kind, link) in enumerate(links):
        a, b = (stage.flat(stage.anchor(ref)) for ref in link.between)
        group = groups[_ends_key(link)]
        shift = (group.index(k) - (len(group) - 1) / 2) * 3.0 * width
        a, b = _shifted(a, b, shift)
        name = link.name or f"{_ref_name(link.between[0])}-{_ref_name(link.between[1])}"
        info: dict[str, Any] = {"ends": np.stack([a, b], axis=1)}
        if kind == "spring":
            line = coil_line(a, b, TURNS, width)
            info |= {
                "rest_length": stage.number(link.rest_length),
                "stiffness": str(link.stiffness),
            }
        else:
            line = dashpot_line(a, b, width)
            info |= {"coefficient": str(link.coefficient)}
        shape = Shape("line", {"points": line}, style(STRUCTURE, 1.5), moving=True)
        made.append(Element(kind, (shape,), name, info))
    return made


def _ends_key(link: Any) -> tuple[str, ...]:
    """The two ends of a spring or damper, in either order."""
    return tuple(sorted(_ref_name(ref) for ref in link.between))


def _shifted(a: np.ndarray, b: np.ndarray, shift: float) -> tuple[np.ndarray, np.ndarray]:
    """Both ends moved ``shift`` across the line a -> b (side by side links)."""
    if shift == 0.0:
        return a, b
    _, _, normal = across(a, b)
    return a + shift * normal, b + shift * normal


def _particle_elements(stage: Stage, radii: Mapping[str, float]) -> list[Element]:
    """Each particle as a dot of its colour with a trail of its last :data:`TRAIL` frames; one
    with a radius (a hard disk) also as its disk, outlined and lightly filled."""
    particles = {p.name for p in stage.system.particles}
    made = []
    for name in stage.names:
        if name not in particles:
            continue  # a body's centre: drawn with the body
        mass = next(p.mass for p in stage.system.particles if p.name == name)
        colour = point_color(stage, name)
        centre = stage.flat(stage.point(name))
        dot = Shape("dot", {"at": centre}, {"color": colour, "size": 9.0, "trail": TRAIL},
                    moving=True)  # fmt: skip
        info: dict[str, Any] = {"mass": stage.number(mass)}
        shapes: tuple[Shape, ...] = (dot,)
        if name in radii:
            info["radius"] = radii[name]
            disk = Shape("circle", {"centre": centre, "radius": radii[name]},
                         style(colour, 1.5, fill=colour + DISK_FILL), moving=True)  # fmt: skip
            shapes = (disk, dot)
        made.append(Element("particle", shapes, name, info))
    return made


def _wall_elements(stage: Stage, contacts: Contacts) -> list[Element]:
    """The walls the unilateral constraints put the particles behind, each drawn once."""
    centres = {name: stage.flat(stage.point(name)) for name in contacts.radii}
    for wall in contacts.walls:
        centres.setdefault(wall.particle, stage.flat(stage.point(wall.particle)))
    made: list[Element] = []
    for wall, segment in wall_segments(contacts, centres):
        shape = Shape("line", {"points": segment}, style(STRUCTURE, 2.5))
        info = {"normal": list(wall.normal), "offset": wall.offset}
        made.append(Element("wall", (shape,), f"wall {len(made) + 1}", info))
    return made


def point_color(stage: Stage, name: str) -> str:
    """The colour of a named point: its place among the points in :data:`PALETTE`."""
    return PALETTE[stage.names.index(name) % len(PALETTE)]


def _bounds(elements: list[Element], stage: Stage) -> tuple[float, float, float, float]:
    """The box holding every shape at every frame, 10 % more on each side, never empty."""
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    for element in elements:
        for shape in element.shapes:
            points = _extent_points(shape)
            xs.append(points[..., 0].ravel())
            ys.append(points[..., 1].ravel())
    x = np.concatenate(xs) if xs else np.zeros(1)
    y = np.concatenate(ys) if ys else np.zeros(1)
    x, y = x[np.isfinite(x)], y[np.isfinite(y)]
    low = np.array([x.min(initial=0.0), y.min(initial=0.0)])
    high = np.array([x.max(initial=0.0), y.max(initial=0.0)])
    size = max(float(np.max(high - low)), 1e-3 * stage.span, 1e-12)
    pad = 0.1 * size
    low, high = low - pad, high + pad
    return (float(low[0]), float(high[0]), float(low[1]), float(high[1]))


def _extent_points(shape: Shape) -> np.ndarray:
    if shape.type == "line":
        return np.asarray(shape.data["points"], dtype=float)
    if shape.type == "circle":
        centre = np.asarray(shape.data["centre"], dtype=float)
        radius = np.asarray(shape.data["radius"], dtype=float)
        r = radius[..., None] if radius.ndim else radius
        return np.stack([centre - r, centre + r])
    if shape.type == "dot":
        return np.asarray(shape.data["at"], dtype=float)
    return np.zeros((0, 2))
