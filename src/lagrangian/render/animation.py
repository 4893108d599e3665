"""Animate a simulated System: its scene (:mod:`lagrangian.render.scene`: rods, springs as
coils, discs turning, wires, pulleys and strings, 3-D bodies with their axes, a circuit's
schematic with its currents, coordinates without geometry as moving points or bars) written
to GIF, MP4 (when ffmpeg is installed) or HTML, and shown in Jupyter.

The pictures are drawn fast (:mod:`lagrangian.render.scene_draw`: the still parts once, the
moving ones per frame) and written straight to the file (:mod:`lagrangian.render.frames_writer`);
the HTML animation is the scene's numbers replayed by a small script
(:mod:`lagrangian.render.scene_player`), not a picture per frame.  By default the number of
frames follows the motion's time scale (:func:`lagrangian.render.timing.frame_count`) and
the playback runs at :data:`~lagrangian.render.timing.FPS` frames per second.  Impacts flash
the frame they happen in (a red border and what struck).

>>> import lagrangian as lg
>>> system = lg.examples.simple_pendulum()
>>> trajectory = lg.simulate(system, t_span=1.0, samples=11)
>>> html = animation_html(system, trajectory, frames=5)
>>> "<script" in html
True
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from lagrangian.errors import Problem, SimulationInputError, raise_if_problems
from lagrangian.model import System
from lagrangian.render.frames_writer import write_gif, write_mp4, write_png
from lagrangian.render.scene import Scene, scene_of
from lagrangian.render.scene_bodies import AXIS_COLORS
from lagrangian.render.scene_draw import SceneFigure, scene_colors
from lagrangian.render.scene_mechanics import rods
from lagrangian.render.scene_player import scene_html, scene_page
from lagrangian.simulation.trajectory import Trajectory

#: A callback told the frames written so far and how many there are: (done, total).
Progress = Callable[[int, int], None]

#: The animation formats by suffix.
FORMATS = (".gif", ".mp4", ".html")

__all__ = [
    "AXIS_COLORS",
    "FORMATS",
    "Animation",
    "Html",
    "animate",
    "animation_frame",
    "animation_html",
    "rods",
]


class Html(str):
    """HTML text that Jupyter displays as HTML (the animation's player)."""

    def _repr_html_(self) -> str:
        return str(self)


@dataclass(frozen=True)
class Animation:
    """An animation of a run: its :class:`~lagrangian.render.scene.Scene`; shown as the
    player in Jupyter, written with :meth:`save`."""

    scene: Scene

    def frames(self, progress: Progress | None = None) -> Iterator[np.ndarray]:
        """Every frame as RGB pixels (H, W, 3), ``progress(done, total)`` told after each."""
        figure = SceneFigure(self.scene)
        total = self.scene.frames
        for k in range(total):
            yield figure.pixels(k)
            if progress is not None:
                progress(k + 1, total)

    def save(self, path: str | Path, progress: Progress | None = None) -> Path:
        """Write the animation to ``path`` in the format of its suffix (:data:`FORMATS`)."""
        target = Path(path)
        suffix = target.suffix.lower()
        if suffix == ".html":
            target.write_text(scene_page(self.scene), encoding="utf-8")
            if progress is not None:
                progress(self.scene.frames, self.scene.frames)
        elif suffix == ".mp4":
            write_mp4(self.frames(progress), target, self.scene.fps)
        elif suffix == ".gif":
            write_gif(self.frames(progress), target, self.scene.fps, scene_colors(self.scene))
        else:
            known = ", ".join(FORMATS)
            raise ValueError(f"{str(target)!r}: animations are written as {known}, not {suffix!r}")
        return target

    def html(self) -> Html:
        """The player as an HTML fragment."""
        return Html(scene_html(self.scene))

    def _repr_html_(self) -> str:
        return scene_html(self.scene)


def _checked(frames: int | None, fps: float | None) -> None:
    problems = []
    if frames is not None and (
        isinstance(frames, bool) or not isinstance(frames, int) or frames < 1
    ):
        problems.append(Problem("frames", f"{frames!r} is not a number of frames",
                                "pass frames= a whole number, 1 or more"))  # fmt: skip
    if fps is not None and not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
        problems.append(Problem("fps", f"{fps!r} is not a frame rate",
                                "pass fps= a positive number of frames per second"))  # fmt: skip
    raise_if_problems(problems, "Cannot animate", SimulationInputError)


def animate(
    system: System,
    trajectory: Trajectory,
    path: str | Path | None = None,
    *,
    frames: int | None = None,
    fps: float | None = None,
    projection: str = "auto",
    progress: Progress | None = None,
) -> Animation:
    """The animation of ``trajectory`` with ``frames`` frames (default: from the motion's
    time scale) played at ``fps``, a 3-D system seen in ``projection`` ("auto", "xy", "xz",
    "yz", "isometric"); written to ``path`` (.gif, .mp4, .html) when given,
    ``progress(done, total)`` called after each frame."""
    _checked(frames, fps)
    animation = Animation(scene_of(system, trajectory, frames=frames, fps=fps,
                                   projection=projection))  # fmt: skip
    if path is not None:
        animation.save(path, progress)
    return animation


def animation_frame(
    system: System,
    trajectory: Trajectory,
    path: str | Path,
    *,
    time: float | None = None,
    projection: str = "auto",
) -> None:
    """One frame of the animation (at ``time``, default the end) as a PNG picture."""
    scene = scene_of(system, trajectory, projection=projection)
    index = scene.frames - 1 if time is None else int(np.argmin(np.abs(scene.times - time)))
    write_png(SceneFigure(scene).pixels(index), Path(path))


def animation_html(
    system: System,
    trajectory: Trajectory,
    *,
    frames: int | None = None,
    fps: float | None = None,
    projection: str = "auto",
) -> Html:
    """The animation as self-contained HTML (the scene and a small player script): a string
    for a web page, shown as the player when it is the last value of a Jupyter cell."""
    return animate(system, trajectory, frames=frames, fps=fps, projection=projection).html()
