"""A :class:`~lagrangian.render.scene.Scene` drawn with matplotlib, fast: what stands still
is drawn once as the background, then each frame restores it and draws only the moving
artists (blitting), and the picture is read straight from the Agg canvas as RGB pixels.

>>> import lagrangian as lg
>>> from lagrangian.render.scene import scene_of
>>> system = lg.examples.simple_pendulum()
>>> picture = SceneFigure(scene_of(system, lg.simulate(system, t_span=1.0, samples=11), frames=4))
>>> picture.pixels(2).shape[2]
3
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lagrangian.render.scene import Scene, Shape

#: Pixels per panel side, and the resolution (a width of 1 px is 0.75 pt at 96 dpi).
PANEL_PIXELS = 400
DPI = 80
POINTS_PER_PIXEL = 0.75
IMPACT = "#d62728"
#: Frames an impact stays flashed.
FLASH = 3


class SceneFigure:
    """The matplotlib figure of a scene, one axes per panel; :meth:`pixels` gives a frame
    as an (H, W, 3) array of bytes, :meth:`update` poses the artists at a frame."""

    def __init__(self, scene: Scene, panel_pixels: int = PANEL_PIXELS) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.scene = scene
        side = panel_pixels / DPI
        count = len(scene.panels)
        self.figure = Figure(figsize=(side * count, side), dpi=DPI, layout="constrained")
        self.canvas = FigureCanvasAgg(self.figure)
        self.movers: list[tuple[Shape, list[Any]]] = []
        self.axes = [self._panel(k, count) for k in range(count)]
        self.clock = self.figure.text(0.01, 0.985, "", va="top", fontsize=9, animated=True)
        self.flash = self.figure.text(0.99, 0.985, "", va="top", ha="right", fontsize=9,
                                      color=IMPACT, animated=True)  # fmt: skip
        self.impacts = _flashes(scene)
        self.background: Any = None

    def _panel(self, k: int, count: int) -> Any:
        panel = self.scene.panels[k]
        axes = self.figure.add_subplot(1, count, k + 1)
        xmin, xmax, ymin, ymax = panel.bounds
        axes.set_xlim(xmin, xmax)
        axes.set_ylim(ymin, ymax)
        if panel.equal:
            axes.set_aspect("equal", adjustable="box")
        axes.set_title(panel.title, fontsize=10, wrap=True)
        if panel.labels:
            axes.set_xlabel(panel.labels[0])
            axes.set_ylabel(panel.labels[1])
        else:
            axes.tick_params(labelsize=7)
        for element in panel.elements:
            for shape in element.shapes:
                artists = _artists(axes, shape)
                if shape.moving:
                    for artist in artists:
                        artist.set_animated(True)
                    self.movers.append((shape, artists))
                else:
                    _pose(shape, artists, 0)
        return axes

    def update(self, frame: int) -> list[Any]:
        """Pose every moving artist at ``frame``; the artists changed."""
        changed = []
        for shape, artists in self.movers:
            _pose(shape, artists, frame)
            changed += artists
        self.clock.set_text(f"t = {self.scene.times[frame]:.3g}")  # a 5 ms run is not t = 0.00
        self.flash.set_text(self.impacts.get(frame, ""))
        return [*changed, self.clock, self.flash]

    def pixels(self, frame: int) -> np.ndarray:
        """The picture at ``frame``: (height, width, 3) bytes (RGB)."""
        if self.background is None:
            self.canvas.draw()
            self.background = self.canvas.copy_from_bbox(self.figure.bbox)
        self.canvas.restore_region(self.background)
        for artist in self.update(frame):
            if artist.axes is not None:
                artist.axes.draw_artist(artist)
            else:
                self.figure.draw_artist(artist)
        if self.impacts.get(frame):
            self._flash_border()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()

    def _flash_border(self) -> None:
        """A red frame round every panel while an impact is flashed."""
        from matplotlib.patches import Rectangle

        for axes in self.axes:
            ring = Rectangle((0, 0), 1, 1, transform=axes.transAxes, fill=False,
                             edgecolor=IMPACT, linewidth=4, animated=True)  # fmt: skip
            axes.add_patch(ring)
            axes.draw_artist(ring)
            ring.remove()


def scene_colors(scene: Scene) -> list[str]:
    """Every colour the scene's shapes are drawn in, and the impact's flash (hex)."""
    colors = {IMPACT, "#000000", "#ffffff"}
    for panel in scene.panels:
        for element in panel.elements:
            colors |= {shape.style.get("color", "#333333") for shape in element.shapes}
    return sorted(colors)


def _flashes(scene: Scene) -> dict[int, str]:
    """The frames an impact is shown on (its own and :data:`FLASH` - 1 after), and its label."""
    shown: dict[int, str] = {}
    for frame, label in scene.impacts:
        for k in range(frame, min(frame + FLASH, scene.frames)):
            shown.setdefault(k, label)
    return shown


def _artists(axes: Any, shape: Shape) -> list[Any]:
    style = shape.style
    color = style.get("color", "#333333")
    width = float(style.get("width", 1.5)) * POINTS_PER_PIXEL
    if shape.type == "line":
        dash = "--" if style.get("dash") else "-"
        return [axes.plot([], [], dash, color=color, lw=width, solid_capstyle="round")[0]]
    if shape.type == "dot":
        size = float(style.get("size", 8.0)) * POINTS_PER_PIXEL
        trail = axes.plot([], [], "-", color=color, lw=1.0, alpha=0.45)[0]
        return [trail, axes.plot([], [], "o", color=color, ms=size)[0]]
    if shape.type == "circle":
        from matplotlib.patches import Circle

        fill = style.get("fill")
        circle = Circle((0.0, 0.0), 1.0, fill=fill is not None, facecolor=fill or "none",
                        edgecolor=color, lw=width)  # fmt: skip
        axes.add_patch(circle)
        return [circle]
    return [axes.text(0.0, 0.0, "", color=color, fontsize=8, ha="center", va="center")]


def _pose(shape: Shape, artists: list[Any], frame: int) -> None:
    if shape.type == "line":
        points = np.asarray(shape.at("points", frame), dtype=float)
        artists[0].set_data(points[:, 0], points[:, 1])
    elif shape.type == "dot":
        at = np.asarray(shape.at("at", frame), dtype=float)
        artists[1].set_data([at[0]], [at[1]])
        trail = int(shape.style.get("trail", 0))
        if trail and "at" in shape.moving_keys:
            past = np.asarray(shape.data["at"][max(0, frame - trail) : frame + 1], dtype=float)
            artists[0].set_data(past[:, 0], past[:, 1])
    elif shape.type == "circle":
        artists[0].set_center(tuple(np.asarray(shape.at("centre", frame), dtype=float)))
        artists[0].set_radius(float(np.asarray(shape.at("radius", frame))))
    else:
        at = np.asarray(shape.at("at", frame), dtype=float)
        artists[0].set_position((at[0], at[1]))
        artists[0].set_text(str(shape.at("text", frame)))
