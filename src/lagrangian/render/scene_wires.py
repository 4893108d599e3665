"""Wires a bead runs on, and the pulleys and strings of Atwood machines.

A particle whose position depends on one coordinate s (and perhaps on t) is a bead on the
curve r(s, t): the wire is that curve drawn at each frame's t.  It is a ``circle`` when s
enters only through sin(s) and cos(s) (drawn for s in [0, 2 pi]), a ``line`` when r is
affine in s, a ``parabola`` when it is quadratic (drawn over the run's range of s and a
quarter more each way).  A bead on a fixed circle about a point it is linked to by a rod is a
pendulum: the rod is drawn, not the circle; a bead on a wire that moves with t (a hoop turning
about its diameter) is held by the wire, so no rod is drawn to it.

Two masses hang from one pulley when, along gravity, their heights add up to a constant
(the string's length) while each keeps its place across gravity: the pulley sits midway
between them, its radius half their distance, at the height of a fixed body there (the
pulley itself, which then takes that radius) or else above both masses, 0 when they stay
below it.  Each string runs straight up from its mass and over the top of the pulley; a
pulley with no body of its own turns with the string (angle = string travel / radius).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from lagrangian.render.scene import Element, Shape, style
from lagrangian.render.scene_bodies import SPOKE
from lagrangian.render.stage import Stage
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t

WIRE = "#9a9a9a"
STRING = "#6b4f2a"
#: Points along a wire.
SAMPLES = 64


def curve_kind(position: list[Any], s: sp.Symbol) -> str | None:
    """ "circle", "line" or "parabola" for a path r(s), None for other curves.

    >>> s, R = sp.symbols("s R")
    >>> curve_kind([R * sp.sin(s), -R * sp.cos(s)], s), curve_kind([s, s**2], s)
    ('circle', 'parabola')
    """
    expressions = [to_sympy(x) for x in position]
    if all(sp.diff(x, s, 2) == 0 for x in expressions):
        return "line"
    if all(x.is_polynomial(s) and sp.degree(x, s) <= 2 for x in expressions):
        return "parabola"
    trig = {f for x in expressions for f in x.atoms(sp.sin, sp.cos) if s in f.free_symbols}
    arguments_linear = all(sp.diff(f.args[0], s, 2) == 0 and sp.diff(f.args[0], s) in (1, -1)
                           for f in trig)  # fmt: skip
    hidden = sp.Dummy("hidden")
    outside = [x.subs({f: hidden for f in trig}) for x in expressions]
    if trig and arguments_linear and not any(s in x.free_symbols for x in outside):
        return "circle"
    return None


def wire_elements(stage: Stage, exclude: set[str]) -> tuple[list[Element], set[str]]:
    """The wire of every bead but those in ``exclude`` (masses a string holds), and the beads
    held by a moving wire (no rod to them)."""
    from lagrangian.render.scene_mechanics import rods

    system = stage.system
    if not (stage.three_d or system.dimension == 2):
        return [], set()
    coordinates = set(system.coordinates)
    linked = {name for pair in rods(system) for name in pair}
    made, moving_beads = [], set()
    for particle in system.particles:
        symbols = set().union(*(to_sympy(x).free_symbols for x in particle.position))
        used = symbols & coordinates
        if len(used) != 1 or particle.name in exclude:
            continue
        s = used.pop()
        kind = curve_kind(list(particle.position), s)
        moving = t in symbols
        if kind is None or (kind == "circle" and not moving and particle.name in linked):
            continue
        points = _wire_points(stage, particle.position, s, kind, moving)
        if kind == "circle" and moving and _turns_flat(points):
            made.append(_pivot_rod(stage, particle.name, points))
            moving_beads.add(particle.name)
            continue  # a pendulum whose pivot moves: a rod from the moving centre
        shape = Shape("line", {"points": stage.flat(points)}, style(WIRE, 2.0), moving=moving)
        made.append(Element("wire", (shape,), particle.name, {"curve": kind, "moving": moving}))
        if moving:
            moving_beads.add(particle.name)
    return made, moving_beads


def _turns_flat(circles: np.ndarray) -> bool:
    """Whether moving circles (F, N, 3) keep the plane they lie in (only their centre moves)."""
    centres = circles.mean(axis=1)
    quarter = circles.shape[1] // 4
    normals = np.cross(circles[:, 0] - centres, circles[:, quarter] - centres)
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    if not np.all(lengths > 0):
        return False
    normals = normals / lengths
    return bool(np.all(np.abs(np.abs(normals @ normals[0]) - 1.0) < 1e-9))


def _pivot_rod(stage: Stage, name: str, circles: np.ndarray) -> Element:
    """The rod from the moving centre of a bead's circle (a pivot moving with t) to it."""
    centres = circles[:, :-1].mean(axis=1)  # the last point repeats the first
    ends = np.stack([centres, stage.point(name)], axis=1)
    length = float(np.nanmean(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=-1)))
    rod = Shape("line", {"points": stage.flat(ends)}, style("#4d4d4d", 2.0), moving=True)
    pivot = Shape("dot", {"at": stage.flat(centres)}, {"color": "#4d4d4d", "size": 5.0,
                                                        "trail": 0}, moving=True)  # fmt: skip
    return Element("rod", (rod, pivot), f"pivot-{name}", {"length": length, "pivot": "moving"})


def _wire_points(stage: Stage, position: Any, s: sp.Symbol, kind: str, moving: bool) -> np.ndarray:
    """The wire in world points: (F, SAMPLES, 3) when it moves, else (SAMPLES, 3)."""
    index = list(stage.system.coordinates).index(s)
    if kind == "circle":
        values = np.linspace(0.0, 2 * np.pi, SAMPLES)
    else:
        run = stage.states.q[:, index]
        low, high = float(np.nanmin(run)), float(np.nanmax(run))
        pad = 0.25 * (high - low) or 1.0
        values = np.linspace(low - pad, high + pad, SAMPLES)
    frames = stage.frames if moving else 1
    q = np.repeat(stage.states.q[:frames], SAMPLES, axis=0)
    q[:, index] = np.tile(values, frames)
    times = np.repeat(stage.states.t[:frames], SAMPLES)
    points = stage.lift(stage.at_states(list(position), q, times))
    points = points.reshape(frames, SAMPLES, 3)
    return points if moving else points[0]


def _hanging(stage: Stage, up: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Points that keep their place across gravity: (name, place across, height) each."""
    found = []
    for name in stage.names:
        r = stage.point(name)
        height = r @ up
        across = r - height[:, None] * up
        if np.all(np.isfinite(r)) and np.ptp(across, axis=0).max() <= 1e-9 * stage.span:
            found.append((name, across[0], height))
    return found


def atwood_elements(stage: Stage) -> tuple[list[Element], list[Element], dict[str, float]]:
    """Pulleys without a body of their own, the strings, and the bodies that are pulleys
    (name -> radius): see the module's docstring."""
    from lagrangian.render.scene_bodies import up_direction

    up = up_direction(stage)
    if up is None:
        return [], [], {}
    hanging = _hanging(stage, up)
    moving = [h for h in hanging if np.ptp(h[2]) > 1e-9 * stage.span]
    still = [h for h in hanging if np.ptp(h[2]) <= 1e-9 * stage.span]
    pulleys: list[Element] = []
    strings: list[Element] = []
    bodies: dict[str, float] = {}
    particles = {p.name for p in stage.system.particles}
    for i, (a, place_a, z_a) in enumerate(moving):
        for b, place_b, z_b in moving[i + 1 :]:
            total = z_a + z_b
            gap = float(np.linalg.norm(place_b - place_a))
            if a not in particles or b not in particles or gap == 0.0:
                continue
            if np.ptp(total) > 1e-9 * stage.span:
                continue
            middle, radius = (place_a + place_b) / 2, gap / 2
            holder = [h for h in still if np.linalg.norm(h[1] - middle) <= 1e-9 * stage.span]
            if holder:
                height = float(holder[0][2][0])
                bodies[holder[0][0]] = radius
            else:
                top = float(max(z_a.max(), z_b.max()))
                height = 0.0 if top < -radius else top + 0.2 * stage.span
            centre = middle + height * up
            strings.append(_string(stage, (a, b), centre, radius, up, place_a, place_b))
            if not holder:
                pulleys.append(_pulley(stage, centre, radius, up, z_a, place_b - place_a))
    return pulleys, strings, bodies


def _string(
    stage: Stage, names: tuple[str, str], centre: np.ndarray, radius: float, up: np.ndarray,
    place_a: np.ndarray, place_b: np.ndarray,
) -> Element:  # fmt: skip
    """From mass a up to the pulley, over its top half, down to mass b: (F, N, 2)."""
    across = (place_b - place_a) / np.linalg.norm(place_b - place_a)
    angles = np.linspace(np.pi, 0.0, 17)  # from a's side over the top to b's
    arc = centre + radius * (np.cos(angles)[:, None] * across + np.sin(angles)[:, None] * up)
    a, b = stage.point(names[0]), stage.point(names[1])
    path = np.concatenate(
        [a[:, None], np.broadcast_to(arc, (stage.frames, *arc.shape)), b[:, None]], axis=1
    )
    shape = Shape("line", {"points": stage.flat(path)}, style(STRING, 1.5), moving=True)
    length = float(np.linalg.norm(path[0, 1:] - path[0, :-1], axis=1).sum())
    return Element(
        "string", (shape,), f"{names[0]}-{names[1]}", {"length": length, "masses": list(names)}
    )


def _pulley(
    stage: Stage, centre: np.ndarray, radius: float, up: np.ndarray, z_a: np.ndarray,
    across: np.ndarray,
) -> Element:  # fmt: skip
    """A pulley of no body: its rim, and a radius line turned by the string's travel."""
    across = across / np.linalg.norm(across)
    angle = (z_a - z_a[0]) / radius
    spoke_end = centre + radius * (np.cos(angle)[:, None] * up + np.sin(angle)[:, None] * across)
    centres = np.broadcast_to(centre, spoke_end.shape)
    rim = Shape("circle", {"centre": stage.flat(centre), "radius": radius}, style("#555555", 1.5))
    spoke = Shape("line", {"points": stage.flat(np.stack([centres, spoke_end], axis=1))},
                  style(SPOKE, 2.0), moving=True)  # fmt: skip
    return Element("pulley", (rim, spoke), "pulley", {"radius": radius})
