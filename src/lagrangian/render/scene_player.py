"""The HTML animation: the scene's JSON and a small script that draws it on a canvas, frame
by frame (play, pause, a slider), so the page holds the numbers of the motion, not a picture
per frame.  The script draws the shapes of ``Scene.to_dict()`` as that format describes them.

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

from lagrangian.render.scene import Scene

#: Pixels per panel side in the page.
PANEL = 360

_counter = itertools.count()

PLAYER = r"""
(function () {
  const S = JSON.parse(document.getElementById("%(id)s-data").textContent);
  const root = document.getElementById("%(id)s");
  const canvas = root.querySelector("canvas"), ctx = canvas.getContext("2d");
  const slider = root.querySelector("input"), button = root.querySelector("button");
  const P = %(panel)d, TOP = 22, M = 10, F = S.times.length;
  const flashes = {};
  for (const i of S.impacts) {
    for (let k = i.frame; k < Math.min(i.frame + 3, F); k++) flashes[k] = i.label;
  }
  function view(panel, p) {
    const [x0, x1, y0, y1] = panel.bounds, w = P - 2 * M, h = P - TOP - 2 * M;
    let sx = w / ((x1 - x0) || 1), sy = h / ((y1 - y0) || 1);
    if (panel.equal) { sx = sy = Math.min(sx, sy); }
    const ox = p * P + M + (w - sx * (x1 - x0)) / 2, oy = TOP + M + (h - sy * (y1 - y0)) / 2;
    return (x, y) => [ox + (x - x0) * sx, oy + (y1 - y) * sy];
  }
  function at(shape, key, k) { return shape.moving.includes(key) ? shape[key][k] : shape[key]; }
  function polyline(map, points, close) {
    ctx.beginPath();
    points.forEach(([x, y], i) => {
      const [u, v] = map(x, y);
      i ? ctx.lineTo(u, v) : ctx.moveTo(u, v);
    });
    if (close) ctx.closePath();
    ctx.stroke();
  }
  function draw(shape, map, k) {
    ctx.strokeStyle = ctx.fillStyle = shape.color || "#333";
    ctx.lineWidth = shape.width || 1.5;
    ctx.setLineDash(shape.dash ? [5, 4] : []);
    if (shape.type === "line") polyline(map, at(shape, "points", k), false);
    else if (shape.type === "dot") {
      if (shape.trail && shape.moving.includes("at")) {
        ctx.globalAlpha = 0.45; ctx.lineWidth = 1;
        polyline(map, shape.at.slice(Math.max(0, k - shape.trail), k + 1), false);
        ctx.globalAlpha = 1;
      }
      const [u, v] = map(...at(shape, "at", k));
      ctx.beginPath(); ctx.arc(u, v, (shape.size || 8) / 2, 0, 2 * Math.PI); ctx.fill();
    } else if (shape.type === "circle") {
      const c = at(shape, "centre", k), [u, v] = map(c[0], c[1]);
      const [u2] = map(c[0] + shape.radius, c[1]);
      ctx.beginPath(); ctx.arc(u, v, Math.abs(u2 - u), 0, 2 * Math.PI);
      if (shape.fill) { ctx.fillStyle = shape.fill; ctx.fill(); }
      ctx.stroke();
    } else if (shape.type === "text") {
      const [u, v] = map(...shape.at);
      ctx.font = "11px sans-serif"; ctx.textAlign = "center";
      ctx.fillText(at(shape, "text", k), u, v);
    }
  }
  function frame(k) {
    ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, canvas.width, canvas.height);
    S.panels.forEach((panel, p) => {
      const map = view(panel, p);
      ctx.strokeStyle = flashes[k] ? "#d62728" : "#ccc"; ctx.lineWidth = flashes[k] ? 4 : 1;
      ctx.setLineDash([]); ctx.strokeRect(p * P + 2, TOP, P - 4, P - TOP - 2);
      ctx.fillStyle = "#333"; ctx.font = "12px sans-serif"; ctx.textAlign = "center";
      ctx.fillText(panel.title, p * P + P / 2, 15);
      for (const element of panel.elements) for (const shape of element.shapes) draw(shape, map, k);
    });
    ctx.fillStyle = "#333"; ctx.textAlign = "left"; ctx.font = "11px sans-serif";
    ctx.fillText("t = " + S.times[k].toPrecision(3), 6, TOP + 14);
    if (flashes[k]) { ctx.fillStyle = "#d62728"; ctx.fillText(flashes[k], 6, TOP + 28); }
    slider.value = k;
  }
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


def scene_html(scene: Scene) -> str:
    """A self-contained HTML fragment playing ``scene`` (no file, no library to load)."""
    ident = f"lagrangian-scene-{next(_counter)}"
    data = scene.to_json().replace("</", "<\\/")  # no </script> inside the data
    width, height = PANEL * len(scene.panels), PANEL
    script = PLAYER % {"id": ident, "panel": PANEL}
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
