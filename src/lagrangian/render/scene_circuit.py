"""A circuit's schematic in a scene: a loop per mesh charge, the elements drawn by their
symbols (resistor zigzag, inductor coil, capacitor plates, source circle), an element whose
current is a difference of two mesh currents (q1_dot - q2_dot) on the branch the two loops
share, a mutual inductance as a dashed link between its coils; and the motion: each mesh's
current as an arrow in the loop, its length the current over the largest of the run (its
direction the current's sign), with the value written beside it, and each capacitor's charge
written beside its plates.

Mesh k is the box [4k, 4k + 4] x [0, 3] (narrowed by a gap where it shares nothing with its
neighbour); its own elements go on its top edge, then the sides it shares with no other
mesh, then its bottom.

>>> import lagrangian as lg
>>> from lagrangian.render.scene import scene_of
>>> system = lg.examples.series_rlc()
>>> scene = scene_of(system, lg.simulate(system, t_span=0.01, samples=11), frames=5)
>>> sorted(set(scene.panels[0].kinds()))
['capacitor', 'current', 'inductor', 'resistor', 'source', 'wire_circuit']
"""

from __future__ import annotations

from itertools import pairwise
from typing import Any

import numpy as np

from lagrangian.model import System
from lagrangian.model.circuit import Capacitor, Inductor, MutualInductance, Resistor
from lagrangian.render.scene import PALETTE, Element, Panel, Shape, style
from lagrangian.render.scene_geometry import coil_line
from lagrangian.render.stage import frame_values
from lagrangian.render.timing import FrameStates
from lagrangian.symbolic.conversion import to_sympy

WIDTH, HEIGHT = 4.0, 3.0
#: The space between the loops of meshes that share no branch, from their boundary.
GAP = 0.4
INK = "#333333"


def _meshes_of(expression: Any) -> list[str]:
    return sorted({s.name.removesuffix("_dot") for s in to_sympy(expression).free_symbols})


def _kind(element: Any) -> str:
    return {Inductor: "inductor", Capacitor: "capacitor", Resistor: "resistor",
            MutualInductance: "mutual"}.get(type(element), "source")  # fmt: skip


def _branch(element: Any) -> Any:
    for key in ("current", "charge"):
        if hasattr(element, key):
            return getattr(element, key)
    return element.coordinate


def _value(element: Any) -> str:
    for key in ("inductance", "capacitance", "resistance", "voltage"):
        if hasattr(element, key):
            return str(getattr(element, key))
    return ""


def circuit_panel(system: System, states: FrameStates) -> Panel | None:
    """The schematic of ``system.circuit`` moving with the currents; None without one."""
    parts = [e for e in system.circuit if not isinstance(e, MutualInductance)]
    if not parts:
        return None
    names = [q.name for q in system.coordinates]
    meshes = sorted({m for e in parts for m in _meshes_of(_branch(e)) if m in names},
                    key=names.index)  # fmt: skip
    own: dict[str, list[Any]] = {m: [] for m in meshes}
    shared: dict[int, list[Any]] = {}
    for element in parts:
        its = [m for m in _meshes_of(_branch(element)) if m in own]
        if len(its) == 1:
            own[its[0]].append(element)
        elif its:
            shared.setdefault(max(meshes.index(m) for m in its), []).append(element)
    elements: list[Element] = []
    placed: dict[int, np.ndarray] = {}  # id(element) -> its centre (for mutual links)
    charges = _charges(system, states, parts)
    for k, mesh in enumerate(meshes):
        slots = _slots(k, len(meshes), set(shared))
        elements += _on_edges(own[mesh], slots, placed, charges)
    for k, branch in shared.items():
        edge = (np.array([WIDTH * k, HEIGHT]), np.array([WIDTH * k, 0.0]))
        elements += _on_edges(branch, [edge], placed, charges)
    elements += _mutual(system, placed)
    elements += [_current(states, mesh, k) for k, mesh in enumerate(meshes)]
    bounds = (-0.8, WIDTH * len(meshes) + 0.8, -0.8, HEIGHT + 0.8)
    return Panel("circuit", bounds, tuple(elements))


def _charges(system: System, states: FrameStates, parts: list[Any]) -> dict[int, np.ndarray]:
    """Each capacitor's charge at every frame, by ``id`` of the capacitor."""
    capacitors = [e for e in parts if isinstance(e, Capacitor)]
    if not capacitors:
        return {}
    values = frame_values(system, states, [e.charge for e in capacitors])
    return {id(e): values[:, i] for i, e in enumerate(capacitors)}


def _slots(k: int, count: int, shared: set[int]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The edges of mesh k in drawing order: top, its own sides, bottom.  A side it shares
    with its neighbour (``shared`` holds the boundaries k with a branch of both meshes k - 1
    and k) is the neighbour's too and left to the shared branch; meshes that share nothing are
    drawn apart, :data:`GAP` from the boundary."""
    left_shared, right_shared = k in shared, k + 1 in shared
    x0 = WIDTH * k + (GAP if k > 0 and not left_shared else 0.0)
    x1 = WIDTH * (k + 1) - (GAP if k < count - 1 and not right_shared else 0.0)
    edges = [(np.array([x0, HEIGHT]), np.array([x1, HEIGHT]))]
    if not left_shared:
        edges.append((np.array([x0, 0.0]), np.array([x0, HEIGHT])))
    if not right_shared:
        edges.append((np.array([x1, HEIGHT]), np.array([x1, 0.0])))
    edges.append((np.array([x1, 0.0]), np.array([x0, 0.0])))
    return edges


def _on_edges(
    parts: list[Any],
    edges: list[tuple[np.ndarray, np.ndarray]],
    placed: dict[int, np.ndarray],
    charges: dict[int, np.ndarray],
) -> list[Element]:
    """``parts`` spread over ``edges`` in order, the rest of each edge a plain wire; a
    capacitor with its charge at every frame (``charges`` by ``id``)."""
    per_edge = [parts[i :: len(edges)] for i in range(len(edges))]
    made = []
    for (start, end), group in zip(edges, per_edge):
        cuts = np.linspace(0.0, 1.0, len(group) + 1)
        wire = []
        for element, (u0, u1) in zip(group, pairwise(cuts)):
            a = start + (end - start) * (u0 + 0.3 * (u1 - u0))
            b = start + (end - start) * (u1 - 0.3 * (u1 - u0))
            wire.append((start + (end - start) * u0, a))
            wire.append((b, start + (end - start) * u1))
            placed[id(element)] = (a + b) / 2
            made.append(_symbol(element, a, b, charges.get(id(element))))
        if not group:
            wire.append((start, end))
        lines = tuple(Shape("line", {"points": np.array(seg)}, style(INK, 1.5)) for seg in wire)
        made.append(Element("wire_circuit", lines))
    return made


def _symbol(element: Any, a: np.ndarray, b: np.ndarray, charge: np.ndarray | None) -> Element:
    """The symbol of one element between ``a`` and ``b``, with its value written beside (and
    across from it a capacitor's ``charge`` at every frame)."""
    kind = _kind(element)
    along = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-along[1], along[0]])
    centre = (a + b) / 2
    size = float(np.linalg.norm(b - a))
    lines: list[np.ndarray] = []
    circles: list[Shape] = []
    if kind == "resistor":
        lines.append(coil_line(a[None], b[None], 4, 0.12 * size)[0])
    elif kind == "inductor":
        angles = np.linspace(0.0, np.pi, 9)
        bumps = []
        for j in range(4):
            middle = a + (j + 0.5) / 4 * (b - a)
            r = size / 8
            bumps += [middle - r * np.cos(x) * along + r * np.sin(x) * normal for x in angles]
        lines.append(np.array([a, *bumps, b]))
    elif kind == "capacitor":
        gap, plate = 0.08 * size, 0.3 * size
        lines += [np.array([a, centre - gap * along]), np.array([centre + gap * along, b])]
        for side in (-gap, gap):
            mid = centre + side * along
            lines.append(np.array([mid - plate * normal, mid + plate * normal]))
    else:  # a voltage source
        radius = min(0.3 * size, 0.35)
        lines += [np.array([a, centre - radius * along]), np.array([centre + radius * along, b])]
        circles.append(Shape("circle", {"centre": centre, "radius": radius},
                             style(INK, 1.5, fill=None)))  # fmt: skip
    label_at = centre + 0.45 * normal * max(size, 1.0) * (1 if normal[1] >= 0 else -1)
    shapes = (
        *(Shape("line", {"points": line}, style(INK, 1.5)) for line in lines),
        *circles,
        Shape("text", {"at": label_at, "text": _value(element)}, {"color": INK}),
    )
    if charge is not None:
        words = [f"q = {value:.3g}" for value in charge]
        charge_at = 2 * centre - label_at + 0.45 * along  # across from the label, off the arrow
        shapes += (Shape("text", {"at": charge_at, "text": words}, {"color": INK},
                         moving=True),)  # fmt: skip
    info = {"value": _value(element), "branch": str(_branch(element))}
    return Element(kind, shapes, element.name or kind, info)


def _mutual(system: System, placed: dict[int, np.ndarray]) -> list[Element]:
    """A dashed link between the coils a mutual inductance couples, its value beside."""
    made = []
    inductors = [e for e in system.circuit if isinstance(e, Inductor)]
    for mutual in (e for e in system.circuit if isinstance(e, MutualInductance)):
        ends = []
        for current in mutual.currents:
            coil = next((c for c in inductors if to_sympy(c.current) == to_sympy(current)), None)
            if coil is not None and id(coil) in placed:
                ends.append(placed[id(coil)])
        if len(ends) != 2:
            continue
        line = Shape("line", {"points": np.array(ends)}, style(INK, 1.0, dash=True))
        text = Shape("text", {"at": (ends[0] + ends[1]) / 2 + [0.0, 0.3],
                              "text": "M = " + str(mutual.inductance)}, {"color": INK})  # fmt: skip
        made.append(Element("mutual", (line, text), mutual.name or "mutual",
                            {"value": str(mutual.inductance)}))  # fmt: skip
    return made


def _current(states: FrameStates, mesh: str, k: int) -> Element:
    """Mesh k's current: an arrow through the loop's centre, over the largest of the run."""
    current = states.column(mesh + "_dot")
    largest = float(np.nanmax(np.abs(current), initial=0.0)) or 1.0
    share = np.nan_to_num(current / largest)
    centre = np.array([WIDTH * (k + 0.5), HEIGHT / 2])
    half = 1.2 * share[:, None] * np.array([1.0, 0.0])
    tail, tip = centre - half, centre + half
    head = 0.25 * np.sign(share)[:, None]
    barbs = np.stack([tip + head * np.array([-1.0, 0.4]), tip, tip + head * np.array([-1.0, -0.4])],
                     axis=1)  # fmt: skip
    color = PALETTE[k % len(PALETTE)]
    text = [f"i = {value:.3g}" for value in current]
    shapes = (
        Shape("line", {"points": np.stack([tail, tip], axis=1)}, style(color, 2.5), moving=True),
        Shape("line", {"points": barbs}, style(color, 2.5), moving=True),
        Shape("text", {"at": centre + np.array([-0.8, -0.6]), "text": text}, {"color": color},
              moving=True),
    )  # fmt: skip
    return Element("current", shapes, mesh + "_dot", {"mesh": mesh, "largest": largest})
