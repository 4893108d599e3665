"""Animate a simulated System: its particles and bodies moving, planar or in 3-D, written to
GIF, MP4 (when ffmpeg is installed) or HTML, and shown in Jupyter.

What is drawn: every particle and body centre as a dot, with a fading trail; a rod between
consecutive points (the origin, then the points in order) whose distance never changes — the
pendulum's rods, found from the positions themselves (|r_b - r_a|^2 free of the coordinates);
springs and dampers as lines between their points, an end given as a position — (a, 0), a
wall at 3*a, a pivot moving with t — where the parameters and the state put it; the body axes
of every 3-D body (x red, y green, z blue: the columns of its rotation R), so a spin about its
own axis shows.  A system with nothing that moves in space (a circuit) is shown as gauges of
its coordinates and rates (:mod:`lagrangian.render.gauges`).  The title is the system's name.

>>> import lagrangian as lg
>>> system = lg.examples.simple_pendulum()
>>> trajectory = lg.simulate(system, t_span=1.0, samples=11)
>>> html = animation_html(system, trajectory, frames=5)
>>> "<script" in html
True
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import pairwise
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import sympy as sp

from lagrangian.model import System
from lagrangian.numerics.evaluate import NumericFunction
from lagrangian.numerics.points import PointPositions, compile_points
from lagrangian.render.gauges import gauge_scene
from lagrangian.simulation.trajectory import Trajectory
from lagrangian.symbolic.conversion import to_sympy
from lagrangian.symbolic.symbols import t

if TYPE_CHECKING:
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

MAX_FRAMES = 200
TRAIL = 40  # samples of trail behind each point
AXIS_LENGTH = 0.35  # a 3-D body's axes, as a fraction of the scene's half-width
AXIS_COLORS = ("C3", "C2", "C0")  # body x, y, z

#: A callback told the frames written so far and how many there are: (done, total).
Progress = Callable[[int, int], None]


def _constant_distance(a: Sequence[Any], b: Sequence[Any], coordinates: set[sp.Symbol]) -> bool:
    squared = sp.trigsimp(sp.expand(sum((to_sympy(x) - to_sympy(y)) ** 2 for x, y in zip(a, b))))
    return not (squared.free_symbols & coordinates) and squared != 0


def rods(system: System) -> list[tuple[str, str]]:
    """Pairs of consecutive points (origin first) at a fixed distance: rigid links to draw."""
    points = system.points()
    order = ["origin", *(n for n in points if n != "origin")]
    coordinates = set(system.coordinates)
    return [
        (a, b) for a, b in pairwise(order) if _constant_distance(points[a], points[b], coordinates)
    ]


def _links(system: System) -> list[tuple[Any, Any]]:
    """Rods, springs and dampers, each as a pair of point references."""
    pairs: list[tuple[Any, Any]] = list(rods(system))
    pairs += [tuple(s.between) for s in system.springs]  # type: ignore[misc]
    pairs += [tuple(d.between) for d in system.dampers]  # type: ignore[misc]
    return pairs


def _frames(trajectory: Trajectory, frames: int | None) -> np.ndarray:
    count = min(len(trajectory.t), frames or MAX_FRAMES)
    return np.unique(np.linspace(0, len(trajectory.t) - 1, count).round().astype(int))


def _positions(system: System, trajectory: Trajectory, points: PointPositions) -> np.ndarray:
    """(samples, points, 3) positions; planar and 1-D systems padded with zeros."""
    p = points.parameter_vector(dict(trajectory.parameters))
    values = np.asarray(points(trajectory.q, trajectory.t, p)).reshape(
        len(trajectory.t), len(points.names), points.dimension
    )
    padded = np.zeros((*values.shape[:2], 3))
    padded[..., : points.dimension] = values
    return padded


def _state_function(system: System, expressions: list[Any], shape: tuple[int, ...]) -> Any:
    """``expressions`` of (q, t, p) as one NumPy function, the arguments ordered as
    :func:`compile_points` orders them (so its parameter vector serves both)."""
    groups = (list(system.coordinates), t, list(system.parameters))
    return NumericFunction(groups, [to_sympy(e) for e in expressions], shape=shape)


def _fixed_ends(
    system: System, links: list[tuple[Any, Any]], trajectory: Trajectory, p: np.ndarray
) -> dict[tuple[Any, ...], np.ndarray]:
    """Each end of a link given as a position, e.g. (a, 0) or (3*a,): its place at every
    sample, (samples, 3), the parameters (and the coordinates or t, if it moves) put in."""
    ends = list(dict.fromkeys(ref for link in links for ref in link if not isinstance(ref, str)))
    if not ends:
        return {}
    dimension = len(ends[0])
    function = _state_function(system, [x for end in ends for x in end], (len(ends), dimension))
    values = np.asarray(function(trajectory.q, trajectory.t, p), dtype=float).reshape(
        len(trajectory.t), len(ends), dimension
    )
    padded = np.zeros((*values.shape[:2], 3))
    padded[..., :dimension] = values
    return {end: padded[:, i] for i, end in enumerate(ends)}


def _body_axes(
    system: System, trajectory: Trajectory, p: np.ndarray
) -> tuple[list[str], np.ndarray]:
    """The 3-D bodies' names and their rotations R (body axes -> world) at every sample,
    (samples, bodies, 3, 3): column k of R is body axis k in world axes."""
    bodies = [b for b in system.rigid_bodies if not b.planar and b.orientation is not None]
    if not bodies:
        return [], np.zeros((len(trajectory.t), 0, 3, 3))
    entries = [e for b in bodies for e in b.orientation.matrix]  # type: ignore[union-attr]
    function = _state_function(system, entries, (len(bodies), 3, 3))
    rotations = np.asarray(function(trajectory.q, trajectory.t, p), dtype=float)
    return [b.name for b in bodies], rotations.reshape(len(trajectory.t), len(bodies), 3, 3)


def _anchor(
    ref: Any,
    names: tuple[str, ...],
    positions: np.ndarray,
    fixed: dict[tuple[Any, ...], np.ndarray],
    frame: int,
) -> np.ndarray:
    if isinstance(ref, str):
        if ref == "origin":
            return np.zeros(3)
        return positions[frame, names.index(ref)]
    return fixed[ref][frame]


def animation_scene(
    system: System, trajectory: Trajectory, frames: int | None = None
) -> tuple[Figure, Callable[[int], list[Any]], np.ndarray]:
    """The figure, a function drawing frame ``index`` (returning the artists it changed), and
    the trajectory samples shown (at most ``frames``, default :data:`MAX_FRAMES`).  3-D
    systems are drawn with a 3-D axes, others in the plane, a circuit as gauges."""
    from matplotlib.figure import Figure

    chosen = _frames(trajectory, frames)
    if not [name for name in system.points() if name != "origin"]:
        return gauge_scene(system, trajectory, chosen)  # a circuit: nothing moves in space
    points = compile_points(system)
    p = points.parameter_vector(dict(trajectory.parameters))
    positions = _positions(system, trajectory, points)
    links = _links(system)
    fixed = _fixed_ends(system, links, trajectory, p)
    three_d = points.dimension == 3
    body_names, rotations = _body_axes(system, trajectory, p) if three_d else ([], None)
    figure = Figure(figsize=(5, 5))
    axes: Any = figure.add_subplot(projection="3d" if three_d else None)
    reach = [positions, *fixed.values()]
    span = max(float(np.nanmax(np.abs(r), initial=0.0)) for r in reach) * 1.1 or 1.0
    for set_limit in (axes.set_xlim, axes.set_ylim, *([axes.set_zlim] if three_d else [])):
        set_limit(-span, span)
    if not three_d:
        axes.set_aspect("equal")
    axes.set_title(system.name or "system")
    dims = 3 if three_d else 2
    link_lines = [
        axes.plot(*([[], []] if not three_d else [[], [], []]), "-", color="0.3")[0] for _ in links
    ]
    dots = [axes.plot(*([[]] * dims), "o", ms=8)[0] for _ in points.names]
    trails = [
        axes.plot(*([[]] * dims), "-", alpha=0.4, lw=1, color=dot.get_color())[0] for dot in dots
    ]
    body_lines = [
        [axes.plot([], [], [], "-", lw=2, color=color)[0] for color in AXIS_COLORS]
        for _ in body_names
    ]
    centres = [points.names.index(name) for name in body_names]
    clock = (
        axes.text2D(0.02, 0.95, "", transform=axes.transAxes)
        if three_d
        else axes.text(0.02, 0.95, "", transform=axes.transAxes)
    )

    def draw(index: int) -> list[Any]:
        frame = chosen[index]
        start = max(0, frame - TRAIL)
        for i, (dot, trail) in enumerate(zip(dots, trails)):
            here, path_ = positions[frame, i], positions[start : frame + 1, i]
            _set(dot, [[c] for c in here[:dims]], three_d)
            _set(trail, [path_[:, k] for k in range(dims)], three_d)
        for line, (a, b) in zip(link_lines, links):
            ends = np.array(
                [
                    _anchor(a, points.names, positions, fixed, frame),
                    _anchor(b, points.names, positions, fixed, frame),
                ]
            )
            _set(line, [ends[:, k] for k in range(dims)], three_d)
        for lines, centre, body in zip(body_lines, centres, range(len(body_names))):
            here = positions[frame, centre]
            for k, line in enumerate(lines):
                tip = here + AXIS_LENGTH * span * rotations[frame, body, :, k]  # type: ignore[index]
                _set(line, [[here[c], tip[c]] for c in range(3)], True)
        clock.set_text(f"t = {trajectory.t[frame]:.3g}")  # a 5 ms run is not t = 0.00
        return [
            *dots,
            *trails,
            *link_lines,
            *(line for lines in body_lines for line in lines),
            clock,
        ]

    return figure, draw, chosen


def animate(
    system: System,
    trajectory: Trajectory,
    path: str | Path | None = None,
    *,
    frames: int | None = None,
    fps: int = 30,
    progress: Progress | None = None,
) -> FuncAnimation:
    """A matplotlib animation of ``trajectory``; written to ``path`` (.gif, .mp4, .html) when
    given, ``progress(done, total)`` called after each frame written."""
    import matplotlib.animation as mpl_animation

    figure, draw, chosen = animation_scene(system, trajectory, frames)
    animation = mpl_animation.FuncAnimation(
        figure, draw, frames=len(chosen), interval=1000 / fps, blit=False
    )
    if path is not None:
        total = len(chosen)
        told = None if progress is None else (lambda i, _: progress(i + 1, total))
        _save(animation, Path(path), fps, told)
    return animation


def _set(line: Any, data: list[Any], three_d: bool) -> None:
    line.set_data(data[0], data[1])
    if three_d:
        line.set_3d_properties(data[2])


def _save(
    animation: FuncAnimation, path: Path, fps: int, told: Callable[[int, Any], None] | None
) -> None:
    import matplotlib.animation as mpl_animation

    if path.suffix == ".html" and told is None:
        path.write_text(animation.to_jshtml(fps=fps), encoding="utf-8")
        return
    writer: Any
    if path.suffix == ".html":  # the player to_jshtml makes, frame by frame
        writer = mpl_animation.HTMLWriter(fps=fps, embed_frames=True, default_mode="loop")
    elif path.suffix == ".mp4":
        writer = mpl_animation.FFMpegWriter(fps=fps)
    else:
        writer = mpl_animation.PillowWriter(fps=fps)
    animation.save(str(path), writer=writer, progress_callback=told)


def animation_frame(
    system: System, trajectory: Trajectory, path: str | Path, *, time: float | None = None
) -> None:
    """One frame of the animation (at ``time``, default the end) as a PNG picture."""
    figure, draw, chosen = animation_scene(system, trajectory, None)
    index = len(chosen) - 1 if time is None else int(np.argmin(np.abs(trajectory.t[chosen] - time)))
    draw(index)
    figure.savefig(str(path))


class Html(str):
    """HTML text that Jupyter displays as HTML (the animation's player)."""

    def _repr_html_(self) -> str:
        return str(self)


def animation_html(system: System, trajectory: Trajectory, *, frames: int | None = None) -> Html:
    """The animation as self-contained HTML (JavaScript player): a string for a web page,
    shown as the player when it is the last value of a Jupyter cell."""
    return Html(animate(system, trajectory, frames=frames).to_jshtml())
