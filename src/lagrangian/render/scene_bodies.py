"""Rigid bodies in a scene, and the ground a round one rolls on.

A planar body is a disc turning with its angle, a radius line showing the rotation; its radius
is that of the uniform disc of the same mass and inertia, r = sqrt(2 I / m) (a pulley of an
Atwood machine takes the radius its strings give).  A 3-D body is drawn as its shape (disc,
ring, cylinder, sphere, box, rod) turned by its rotation R, a radius line on a round face, and
its body axes (x red, y green, z blue: the columns of R); a body given by an inertia tensor is
drawn as the box of the same principal moments, I_x = m (b^2 + c^2) / 12 ..., or, when two
moments are equal, the cylinder of the same moments (I_axis = m r^2 / 2,
I_across = m (3 r^2 + h^2) / 12), as a top is.

A round body rolls on a ground drawn beneath it: a line at its radius from a centre that moves
on a straight line (a cylinder down an incline), or the plane its rim's lowest point stays on
(a disc rolling on the floor, contact C = p + r d with d = (a (a . e_z) - e_z) / |a x e_z|,
:mod:`lagrangian.model.contact`), with the track of the contact point.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from lagrangian.model.elements import RigidBody
from lagrangian.model.inertia import Shape as BodyShape
from lagrangian.render.scene import Element, Shape, style
from lagrangian.render.scene_geometry import box_line, circle_points
from lagrangian.render.stage import Stage

#: A 3-D body's axes x, y, z (matplotlib's C3, C2, C0).
AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")
BODY = "#555555"
#: The radius line that shows a round body's rotation.
SPOKE = "#ff7f0e"
GROUND = "#8c6d46"
ROUND = ("disc", "ring", "cylinder", "solid_sphere", "hollow_sphere")
AXIS_INDEX = {"x": 0, "y": 1, "z": 2}


def rotations(stage: Stage, body: RigidBody) -> np.ndarray:
    """R (body axes -> world) at every frame, (F, 3, 3); a planar body turns about z."""
    if body.planar or body.orientation is None:
        if body.planar and body.angle is not None:
            angle = stage.evaluate([body.angle])[:, 0]
            c, s = np.cos(angle), np.sin(angle)
            R = np.zeros((stage.frames, 3, 3))
            R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
            return R
        return np.broadcast_to(np.eye(3), (stage.frames, 3, 3)).copy()
    entries = list(body.orientation.matrix)
    return stage.evaluate(entries).reshape(stage.frames, 3, 3)


def body_form(stage: Stage, body: RigidBody) -> tuple[str, dict[str, float], int]:
    """The shape a body is drawn as: its kind, its dimensions by name, and its axis of
    symmetry (0, 1, 2 for body x, y, z)."""
    mass = stage.number(body.mass)
    if isinstance(body.inertia, BodyShape):
        sizes = {name: stage.number(value) for name, value in body.inertia.dimensions}
        return body.inertia.kind, sizes, AXIS_INDEX[body.inertia.axis]
    if body.planar:
        inertia = stage.number(body.inertia)
        return "disc", {"radius": float(np.sqrt(max(2 * inertia / mass, 0.0)))}, 2
    tensor = np.array([[stage.number(x) for x in row] for row in body.inertia.tolist()])
    moments = np.diag(tensor)
    for axis in range(3):
        others = [moments[k] for k in range(3) if k != axis]
        if np.isclose(others[0], others[1], rtol=1e-6) and not np.isclose(others[0], moments[axis]):
            radius = np.sqrt(max(2 * moments[axis] / mass, 0.0))
            height = np.sqrt(max(12 * others[0] / mass - 3 * radius**2, 0.0))
            return "cylinder", {"radius": float(radius), "length": float(height)}, axis
    total = moments.sum()
    edges = np.sqrt(np.clip(6 * (total - 2 * moments) / mass, 0.0, None))
    return "box", dict(zip(("length_x", "length_y", "length_z"), map(float, edges))), 2


def body_elements(stage: Stage, pulley_radii: Mapping[str, float]) -> list[Element]:
    """Every rigid body as its shape; a body named in ``pulley_radii`` as a pulley of that
    radius."""
    made = []
    for body in stage.system.rigid_bodies:
        centre = stage.point(body.name)
        R = rotations(stage, body)
        kind, sizes, axis = body_form(stage, body)
        if body.name in pulley_radii:
            kind, sizes, axis = "disc", {"radius": pulley_radii[body.name]}, 2
        shapes = _outline(stage, centre, R, kind, sizes, axis)
        dot = Shape("dot", {"at": stage.flat(centre)}, {"color": BODY, "size": 4.0, "trail": 40},
                    moving=True)  # fmt: skip
        element_kind = "pulley" if body.name in pulley_radii else (
            "disc" if body.planar else "body")  # fmt: skip
        info: dict[str, Any] = {"shape": kind, **sizes}
        made.append(Element(element_kind, (*shapes, dot), body.name, info))
        if stage.three_d:
            made.append(Element("body_axes", tuple(_axes(stage, centre, R, sizes)), body.name))
    return made


def _outline(
    stage: Stage, centre: np.ndarray, R: np.ndarray, kind: str, sizes: dict[str, float], axis: int
) -> tuple[Shape, ...]:
    """The body's edges (F, N, 2) and, on a round face, the radius line along the first body
    axis across the symmetry axis, which turns as the body spins."""
    across = [k for k in range(3) if k != axis]
    first, second, along = R[:, :, across[0]], R[:, :, across[1]], R[:, :, axis]
    lines: list[np.ndarray] = []
    radius = sizes.get("radius", 0.0)
    if kind in ("disc", "ring"):
        lines.append(circle_points(centre, first, second, radius))
    elif kind == "cylinder":
        half = sizes.get("length", 0.0) / 2
        for end in (-half, half):
            lines.append(circle_points(centre + end * along, first, second, radius))
        for k in range(4):
            angle = k * np.pi / 2
            rim = radius * (np.cos(angle) * first + np.sin(angle) * second)
            lines.append(np.stack([centre + rim - half * along, centre + rim + half * along], 1))
    elif kind in ("solid_sphere", "hollow_sphere"):
        lines.append(_silhouette(stage, centre, radius))
        lines.append(circle_points(centre, first, second, radius))  # its equator turns with it
    elif kind == "box":
        edges = 0.5 * np.array([sizes["length_x"], sizes["length_y"], sizes["length_z"]])
        lines.append(box_line(centre, R, edges))
    elif kind == "rod":
        half = sizes.get("length", 0.0) / 2
        lines.append(np.stack([centre - half * along, centre + half * along], axis=1))
    shapes = [Shape("line", {"points": stage.flat(line)}, style(BODY, 1.5), moving=True)
              for line in lines]  # fmt: skip
    if kind in ROUND:
        spoke = np.stack([centre, centre + radius * first], axis=1)
        shapes.append(Shape("line", {"points": stage.flat(spoke)}, style(SPOKE, 2.0),
                            moving=True))  # fmt: skip
    return tuple(shapes)


def _silhouette(stage: Stage, centre: np.ndarray, radius: float) -> np.ndarray:
    """A sphere's outline in the view: the circle across the line of sight."""
    right, up = stage.view[0], stage.view[1]
    tile = np.broadcast_to
    return circle_points(centre, tile(right, centre.shape), tile(up, centre.shape), radius)


def _axes(stage: Stage, centre: np.ndarray, R: np.ndarray, sizes: dict[str, float]) -> list[Shape]:
    """The body axes from the centre, 1.5 times the body's size (at least 15 % of the scene)."""
    size = max([v for v in sizes.values() if np.isfinite(v)], default=0.0)
    length = max(1.5 * size, stage.pixels(0.15))
    return [
        Shape("line", {"points": stage.flat(np.stack([centre, centre + length * R[:, :, k]], 1))},
              style(color, 2.0), moving=True)
        for k, color in enumerate(AXIS_COLORS)
    ]  # fmt: skip


def ground_elements(stage: Stage) -> list[Element]:
    """The ground under every round body that rolls (see the module's docstring)."""
    made = []
    for body in stage.system.rigid_bodies:
        kind, sizes, axis = body_form(stage, body)
        if kind not in ROUND or not np.isfinite(sizes.get("radius", np.nan)):
            continue
        centre = stage.point(body.name)
        line = _straight_ground(stage, centre, sizes["radius"])
        if line is not None:
            shape = Shape("line", {"points": stage.flat(line)}, style(GROUND, 2.5))
            made.append(Element("ground", (shape,), body.name, {"curve": "line"}))
            continue
        if stage.three_d:
            made += _floor(stage, body, centre, rotations(stage, body)[:, :, axis], sizes["radius"])
    return made


def up_direction(stage: Stage) -> np.ndarray | None:
    """The unit vector against gravity in world axes; None without gravity."""
    gravity = stage.system.gravity
    if gravity is None:
        return None
    g = np.zeros(3)
    values = [stage.number(x) for x in gravity]
    if stage.vertical:
        g[1] = values[0]
    else:
        g[: len(values)] = values
    norm = np.linalg.norm(g)
    return -g / norm if norm > 0 and np.isfinite(norm) else None


def _straight_ground(stage: Stage, centre: np.ndarray, radius: float) -> np.ndarray | None:
    """The line a round body rolls on when its centre moves on a straight line: offset by
    the radius against gravity, as long as the run and a radius more each way."""
    up = up_direction(stage)
    finite = centre[np.all(np.isfinite(centre), axis=1)]
    if up is None or len(finite) < 2 or np.ptp(finite, axis=0).max() <= 1e-9 * stage.span:
        return None
    middle = finite.mean(axis=0)
    _, values, vectors = np.linalg.svd(finite - middle)
    if len(values) > 1 and values[1] > 1e-6 * values[0]:
        return None  # not a straight path
    direction = vectors[0]
    normal = up - (up @ direction) * direction
    if np.linalg.norm(normal) < 1e-9:
        return None  # falling straight down: nothing to roll on
    normal /= np.linalg.norm(normal)
    reach = np.abs((finite - middle) @ direction).max() + 2 * radius
    return np.stack([middle - reach * direction, middle + reach * direction]) - radius * normal


def _floor(
    stage: Stage, body: RigidBody, centre: np.ndarray, axle: np.ndarray, radius: float
) -> list[Element]:
    """The horizontal plane z = h a disc's rim touches all along (with the contact track)."""
    across = np.linalg.norm(axle[:, :2], axis=1)
    e_z = np.array([0.0, 0.0, 1.0])
    with np.errstate(invalid="ignore", divide="ignore"):
        down = (axle * axle[:, 2:3] - e_z) / across[:, None]
    contact = centre + radius * down
    heights = contact[:, 2]
    if not np.all(np.isfinite(heights)) or np.ptp(heights) > 1e-3 * max(radius, 1e-12):
        return []
    h = float(heights.mean())
    low, high = contact[:, :2].min(axis=0) - 2 * radius, contact[:, :2].max(axis=0) + 2 * radius
    corners = np.array([[low[0], low[1], h], [high[0], low[1], h], [high[0], high[1], h],
                        [low[0], high[1], h], [low[0], low[1], h]])  # fmt: skip
    plane = Shape("line", {"points": stage.flat(corners)}, style(GROUND, 1.5))
    track = Shape("dot", {"at": stage.flat(contact)},
                  {"color": GROUND, "size": 3.0, "trail": stage.frames}, moving=True)  # fmt: skip
    return [Element("ground", (plane, track), body.name, {"curve": "plane", "height": h})]
