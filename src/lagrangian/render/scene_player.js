// The drawing of a lagrangian scene on a canvas: Scene.to_dict() (format "lagrangian-scene",
// version 1, docs/animations.md), one frame at a time.  Every page that shows a run draws
// with this one file: the HTML animation inlines it, the playground loads it.  It needs no
// physics: each panel's lines, circles, dots and text, in the panel's own units.
//
//   LagrangianScene.drawFrame(canvas, scene, k)  draws frame k; returns what it drew
//   LagrangianScene.layout(scene, width, height) where each panel goes on the canvas
//   LagrangianScene.view(panel, box)             a panel's units -> the canvas's pixels
(function (root) {
  "use strict";
  if (root.LagrangianScene) return; // several animations on one page share one copy

  const TITLE = 22; // pixels above a panel's frame: its title
  const MARGIN = 10; // pixels between the frame and the drawing
  const REFERENCE = 400; // widths and sizes are pixels of a panel this large
  const INK = "#333";
  const FLASH = "#d62728";

  // Where each panel goes on a canvas of width x height: squares of one size, in the grid
  // that makes them largest (side by side when they fit, else stacked), the grid centred;
  // each {x, y, size}.
  function layout(scene, width, height) {
    const count = Math.max(1, scene.panels.length);
    let best = { columns: 1, rows: 1, size: 0 };
    for (let columns = 1; columns <= count; columns++) {
      const rows = Math.ceil(count / columns);
      const size = Math.min(width / columns, height / rows);
      if (size > best.size) best = { columns, rows, size };
    }
    const left = (width - best.columns * best.size) / 2;
    const top = (height - best.rows * best.size) / 2;
    return scene.panels.map((panel, p) => ({
      x: left + (p % best.columns) * best.size,
      y: top + Math.floor(p / best.columns) * best.size,
      size: best.size,
    }));
  }

  // The map from a panel's units to the canvas's pixels (the panel's y up, the canvas's down):
  // its bounds fill the square under the title, with one scale on both axes when ``equal``.
  function view(panel, box) {
    const [x0, x1, y0, y1] = panel.bounds;
    const w = box.size - 2 * MARGIN;
    const h = box.size - TITLE - 2 * MARGIN;
    let sx = w / (x1 - x0 || 1);
    let sy = h / (y1 - y0 || 1);
    if (panel.equal) sx = sy = Math.min(sx, sy);
    const ox = box.x + MARGIN + (w - sx * (x1 - x0)) / 2;
    const oy = box.y + TITLE + MARGIN + (h - sy * (y1 - y0)) / 2;
    return (x, y) => [ox + (x - x0) * sx, oy + (y1 - y) * sy];
  }

  // A shape's key at frame k: given per frame when it moves, else the same at every frame.
  function at(shape, key, k) {
    return shape.moving.includes(key) ? shape[key][k] : shape[key];
  }

  function polyline(ctx, map, points) {
    ctx.beginPath();
    points.forEach(([x, y], i) => {
      const [u, v] = map(x, y);
      if (i) ctx.lineTo(u, v);
      else ctx.moveTo(u, v);
    });
    ctx.stroke();
  }

  // One shape at frame k; ``scale`` turns the format's pixels (of a 400-pixel panel) into this
  // panel's.
  function drawShape(ctx, shape, map, k, scale) {
    ctx.strokeStyle = ctx.fillStyle = shape.color || INK;
    ctx.lineWidth = (shape.width || 1.5) * scale;
    ctx.setLineDash(shape.dash ? [5 * scale, 4 * scale] : []);
    if (shape.type === "line") {
      polyline(ctx, map, at(shape, "points", k));
    } else if (shape.type === "dot") {
      if (shape.trail && shape.moving.includes("at")) {
        ctx.globalAlpha = 0.45;
        ctx.lineWidth = scale;
        polyline(ctx, map, shape.at.slice(Math.max(0, k - shape.trail), k + 1));
        ctx.globalAlpha = 1;
      }
      const [u, v] = map(...at(shape, "at", k));
      ctx.beginPath();
      ctx.arc(u, v, ((shape.size || 8) * scale) / 2, 0, 2 * Math.PI);
      ctx.fill();
    } else if (shape.type === "circle") {
      const centre = at(shape, "centre", k);
      const [u, v] = map(centre[0], centre[1]);
      const [edge] = map(centre[0] + shape.radius, centre[1]);
      ctx.beginPath();
      ctx.arc(u, v, Math.abs(edge - u), 0, 2 * Math.PI);
      if (shape.fill) {
        ctx.fillStyle = shape.fill;
        ctx.fill();
      }
      ctx.stroke();
    } else if (shape.type === "text") {
      const [u, v] = map(...shape.at);
      ctx.font = `${Math.round(11 * Math.max(scale, 0.9))}px sans-serif`;
      ctx.textAlign = "center";
      ctx.fillText(at(shape, "text", k), u, v);
    }
  }

  // The frames that flash (an impact and the two frames after it), with what struck.
  const flashCache = new WeakMap();
  function flashes(scene) {
    if (!flashCache.has(scene)) {
      const found = {};
      for (const impact of scene.impacts || []) {
        for (let k = impact.frame; k < Math.min(impact.frame + 3, scene.times.length); k++) {
          found[k] = impact.label;
        }
      }
      flashCache.set(scene, found);
    }
    return flashCache.get(scene);
  }

  // Frame k of ``scene`` over the whole canvas: each panel in its square with its title, its
  // elements in order, the time, and a red frame with its label on an impact.  Returns what
  // was drawn: the frame, the flash and each element as {panel, kind, name, shapes}.
  function drawFrame(canvas, scene, k) {
    const ctx = canvas.getContext("2d");
    const frame = Math.max(0, Math.min(scene.times.length - 1, k | 0));
    const flash = flashes(scene)[frame];
    const drawn = { frame, time: scene.times[frame], flash: flash || null, elements: [] };
    ctx.setLineDash([]);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const boxes = layout(scene, canvas.width, canvas.height);
    scene.panels.forEach((panel, p) => {
      const box = boxes[p];
      const map = view(panel, box);
      ctx.setLineDash([]);
      ctx.strokeStyle = flash ? FLASH : "#ccc";
      ctx.lineWidth = flash ? 4 : 1;
      ctx.strokeRect(box.x + 2, box.y + TITLE, box.size - 4, box.size - TITLE - 2);
      ctx.fillStyle = INK;
      ctx.font = "12px sans-serif";
      ctx.textAlign = "center";
      ctx.fillText(panel.title, box.x + box.size / 2, box.y + 15, box.size - 8);
      const scale = box.size / REFERENCE;
      for (const element of panel.elements) {
        for (const shape of element.shapes) drawShape(ctx, shape, map, frame, scale);
        drawn.elements.push({
          panel: p,
          kind: element.kind,
          name: element.name,
          shapes: element.shapes.length,
        });
      }
    });
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
    ctx.fillStyle = INK;
    ctx.textAlign = "left";
    ctx.font = "11px sans-serif";
    const corner = boxes[0] || { x: 0, y: 0 }; // inside the first panel's frame
    const time = "t = " + Number(scene.times[frame]).toPrecision(3);
    ctx.fillText(time, corner.x + 6, corner.y + TITLE + 14);
    if (flash) {
      ctx.fillStyle = FLASH;
      ctx.fillText(flash, corner.x + 6, corner.y + TITLE + 28);
    }
    return drawn;
  }

  root.LagrangianScene = { drawFrame, layout, view, TITLE, MARGIN, REFERENCE };
})(typeof window !== "undefined" ? window : globalThis);
