"""The HTML animation: the scene's JSON and a small script that draws it on a canvas, frame
by frame (play, pause, a slider), so the page holds the numbers of the motion, not a picture
per frame.  The drawing is ``scene_player.js`` beside this module, inlined into the page: the
one drawing code of ``Scene.to_dict()``, which the playground serves to its page as well.

>>> import lagrangian as lg
>>> from lagrangian.render.scene import scene_of
>>> system = lg.examples.simple_pendulum()
>>> page = scene_html(scene_of(system, lg.simulate(system, t_span=1.0, samples=11), frames=4))
>>> "<canvas" in page and '"lagrangian-scene"' in page
True
"""

from __future__ import annotations

import html
import itertools
from functools import cache
from pathlib import Path

from lagrangian.render.scene import Scene

#: Pixels per panel side in the page.
PANEL = 360

_counter = itertools.count()

#: The drawing of a scene, shared with the playground (which serves the same file).
DRAWING = Path(__file__).with_name("scene_player.js")

#: The controls of one animation on its page: play/pause and a slider over the frames; each
#: frame is drawn by ``LagrangianScene.drawFrame`` (:data:`DRAWING`).
CONTROLS = r"""
(function () {
  const S = JSON.parse(document.getElementById("%(id)s-data").textContent);
  const root = document.getElementById("%(id)s");
  const canvas = root.querySelector("canvas");
  const slider = root.querySelector("input"), button = root.querySelector("button");
  const F = S.times.length;
  function frame(k) { LagrangianScene.drawFrame(canvas, S, k); slider.value = k; }
  let k = 0, playing = true, last = 0;
  function tick(now) {
    if (playing && now - last >= 1000 / S.fps) { last = now; frame(k); k = (k + 1) %% F; }
    requestAnimationFrame(tick);
  }
  slider.max = F - 1;
  slider.oninput = () => {
    playing = false; button.textContent = "play"; k = +slider.value; frame(k);
  };
  button.onclick = () => { playing = !playing; button.textContent = playing ? "pause" : "play"; };
  frame(0); requestAnimationFrame(tick);
})();
"""


@cache
def drawing_script() -> str:
    """The text of :data:`DRAWING` (the scene drawn on a canvas, frame by frame)."""
    return DRAWING.read_text(encoding="utf-8")


def scene_html(scene: Scene) -> str:
    """A self-contained HTML fragment playing ``scene`` (no file, no library to load)."""
    ident = f"lagrangian-scene-{next(_counter)}"
    data = scene.to_json().replace("</", "<\\/")  # no </script> inside the data
    width, height = PANEL * len(scene.panels), PANEL
    script = drawing_script() + CONTROLS % {"id": ident}
    return (
        f'<div id="{ident}" class="lagrangian-animation">'
        f'<canvas width="{width}" height="{height}" aria-label="{html.escape(scene.name)}">'
        "</canvas><div><button>pause</button> "
        '<input type="range" min="0" value="0" style="width:60%"></div>'
        f'<script type="application/json" id="{ident}-data">{data}</script>'
        f"<script>{script}</script></div>"
    )


def scene_page(scene: Scene) -> str:
    """:func:`scene_html` as a whole page, titled with the system's name."""
    title = html.escape(scene.name)
    return (
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{title}</title></head>'
        f"<body>{scene_html(scene)}</body></html>\n"
    )
