// The playground page: an editor for a model file, the equations and the analysis typeset
// with KaTeX, and the simulation drawn on a canvas. Everything it needs comes from the
// server's JSON API (/api/derive, /api/analyze, /api/simulate, /api/examples).
"use strict";

const $ = (id) => document.getElementById(id);
const editor = $("editor");
const gutter = $("gutter");
const state = {
  derived: null, // the derive answer
  analysis: null, // the analyze answer
  run: null, // the simulate answer
  settings: {}, // slider values: name -> number (options.set)
  frame: 0,
  animation: null,
  started: 0,
};

// ---- the model in the URL: #model=<base64url of the UTF-8 text>&format=yaml
function encodeText(text) {
  const bytes = new TextEncoder().encode(text);
  let binary = "";
  for (const b of bytes) binary += String.fromCharCode(b);
  return btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function decodeText(code) {
  const binary = atob(code.replace(/-/g, "+").replace(/_/g, "/"));
  return new TextDecoder().decode(Uint8Array.from(binary, (c) => c.charCodeAt(0)));
}

function saveToUrl() {
  const params = new URLSearchParams({ model: encodeText(editor.value), format: $("format").value });
  history.replaceState(null, "", "#" + params.toString());
}

function readUrl() {
  const params = new URLSearchParams(location.hash.slice(1));
  if (!params.get("model")) return false;
  try {
    editor.value = decodeText(params.get("model"));
  } catch (error) {
    return false;
  }
  $("format").value = params.get("format") || "yaml";
  return true;
}

// ---- the editor's line numbers and the errors
let badLines = new Set();

function drawGutter() {
  const count = editor.value.split("\n").length;
  const lines = [];
  for (let i = 1; i <= count; i++) {
    lines.push(badLines.has(i) ? `<span class="bad">${i}</span>` : String(i));
  }
  gutter.innerHTML = lines.join("\n") + "\n";
  gutter.scrollTop = editor.scrollTop;
}

function goToLine(line, column) {
  const lines = editor.value.split("\n");
  let offset = 0;
  for (let i = 0; i < line - 1 && i < lines.length; i++) offset += lines[i].length + 1;
  offset += Math.max(0, (column || 1) - 1);
  editor.focus();
  editor.setSelectionRange(offset, offset);
}

function showProblems(problems) {
  const list = $("errors");
  list.innerHTML = "";
  badLines = new Set();
  for (const p of problems || []) {
    const item = document.createElement("li");
    const where = document.createElement("span");
    where.className = "where";
    const place = p.line ? `line ${p.line}` + (p.column ? `, column ${p.column}` : "") : "";
    where.textContent = [place, p.field].filter(Boolean).join(" · ") + ": ";
    item.appendChild(where);
    item.appendChild(document.createTextNode(p.message));
    if (p.fix) {
      const fix = document.createElement("span");
      fix.className = "fix";
      fix.textContent = " — " + p.fix;
      item.appendChild(fix);
    }
    if (p.line) {
      item.dataset.line = p.line;
      badLines.add(p.line);
      item.addEventListener("click", () => goToLine(p.line, p.column));
    }
    list.appendChild(item);
  }
  drawGutter();
}

// ---- talking to the server
let busy = 0;

function setStatus(text) {
  $("status").textContent = text;
}

async function call(command, options) {
  const body = { model: editor.value, format: $("format").value, options: options || {} };
  busy += 1;
  setStatus(`${command}…`);
  try {
    const response = await fetch(`/api/${command}`, {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body),
    });
    const answer = await response.json();
    if (!response.ok) {
      showProblems(answer.problems || [{ field: "", message: `HTTP ${response.status}` }]);
      setStatus(`${command}: ${answer.error || "error"}`);
      return null;
    }
    showProblems([]);
    setStatus(`${command}: done`);
    return answer;
  } catch (error) {
    showProblems([{ field: "server", message: String(error), fix: "is lagrangian serve running?" }]);
    setStatus("no answer");
    return null;
  } finally {
    busy -= 1;
  }
}

// ---- LaTeX with KaTeX: each align* block typeset on its own
function typeset(target, latex) {
  target.innerHTML = "";
  const blocks = latex.split(/(?<=\\end\{align\*\})/).map((b) => b.trim()).filter(Boolean);
  for (const block of blocks) {
    const item = document.createElement("div");
    item.className = "item";
    if (window.katex) {
      window.katex.render(block, item, { displayMode: true, throwOnError: false });
    } else {
      item.textContent = block;
    }
    target.appendChild(item);
  }
}

async function derive() {
  const answer = await call("derive", { steps: true, set: settingsList() });
  if (!answer) return false;
  state.derived = answer;
  typeset($("equations"), answer.latex);
  return true;
}

async function analyze() {
  const answer = await call("analyze", { set: settingsList() });
  if (!answer) return;
  state.analysis = answer;
  const target = $("analysis");
  typeset(target, answer.latex);
  const notes = [];
  for (const c of answer.conserved_quantities || []) {
    const when = (c.conditions || []).join(", ");
    const verdict = c.holds === false ? `is conserved only when ${when}` : "is conserved";
    notes.push(`${c.name} ${verdict} (${c.origin}): ${c.reason}`);
  }
  if (notes.length) {
    const list = document.createElement("ul");
    for (const note of notes) {
      const li = document.createElement("li");
      li.textContent = note;
      list.appendChild(li);
    }
    target.appendChild(list);
  }
}

// ---- sliders: every parameter and initial value, re-running the simulation at once
function settingsList() {
  return Object.entries(state.settings).map(([name, value]) => `${name}=${value}`);
}

function sliderRange(value) {
  if (value > 0) return [0, 3 * value];
  if (value < 0) return [3 * value, -value];
  return [-1, 1];
}

function addSlider(name, value, kind) {
  const label = document.createElement("label");
  label.title = kind;
  const [low, high] = sliderRange(value);
  const input = document.createElement("input");
  Object.assign(input, { type: "range", min: low, max: high, step: (high - low) / 200, value });
  input.dataset.name = name;
  const shown = document.createElement("output");
  shown.textContent = Number(value).toPrecision(3);
  const text = document.createElement("span");
  text.textContent = name;
  label.append(text, input, shown);
  let timer = null;
  input.addEventListener("input", () => {
    shown.textContent = Number(input.value).toPrecision(3);
    state.settings[name] = Number(input.value);
    clearTimeout(timer);
    timer = setTimeout(() => simulate(false), 250);
  });
  $("sliders").appendChild(label);
}

function buildSliders(run) {
  $("sliders").innerHTML = "";
  for (const [name, value] of Object.entries(run.summary.parameters || {})) {
    addSlider(name, state.settings[name] ?? value, "parameter");
  }
  const coordinates = (state.derived && state.derived.coordinates) || [];
  for (const q of coordinates) {
    for (const name of [q, q + "_dot"]) {
      const column = run.columns[name];
      if (column) addSlider(name, state.settings[name] ?? column[0], "initial value");
    }
  }
}

async function simulate(rebuild = true) {
  const options = { set: settingsList() };
  const answer = await call("simulate", options);
  if (!answer) return;
  state.run = answer;
  if (rebuild) buildSliders(answer);
  buildPlotMenu();
  $("summary").textContent =
    `${answer.summary.samples} samples, ${answer.summary.method}: ${answer.summary.drift_summary}`;
  drawPlot();
  startAnimation();
}

// ---- the animation: the particles and bodies, or gauges of the coordinates
function startAnimation() {
  cancelAnimationFrame(state.animation);
  state.started = performance.now();
  const step = () => {
    drawFrame();
    state.animation = requestAnimationFrame(step);
  };
  step();
}

function currentIndex() {
  const t = state.run.columns.t;
  const span = t[t.length - 1] - t[0] || 1;
  const elapsed = ((performance.now() - state.started) / 1000) % Math.max(span, 1e-9);
  let low = 0;
  let high = t.length - 1;
  while (low < high) {
    const middle = (low + high) >> 1;
    if (t[middle] - t[0] < elapsed) low = middle + 1;
    else high = middle;
  }
  return low;
}

function project(point, dimension) {
  if (dimension === 3) return [point[0] + 0.35 * point[1], point[2] + 0.35 * point[1]];
  if (dimension === 1) return [point[0], 0];
  return [point[0], point[1]];
}

function drawFrame() {
  const canvas = $("canvas");
  const context = canvas.getContext("2d");
  context.fillStyle = "#fff";
  context.fillRect(0, 0, canvas.width, canvas.height);
  if (!state.run) return;
  const index = currentIndex();
  state.frame = index;
  const scene = state.run.scene;
  if (scene) drawScene(context, canvas, scene, index);
  else drawGauges(context, canvas, index);
  context.fillStyle = "#333";
  context.font = "13px sans-serif";
  context.fillText(`t = ${state.run.columns.t[index].toFixed(2)}`, 8, 16);
  drawPlotCursor(index);
}

function sceneScale(scene, canvas) {
  let extent = 1e-9;
  for (const path of Object.values(scene.points)) {
    for (const p of path) {
      for (const value of project(p, scene.dimension)) {
        if (value !== null && isFinite(value)) extent = Math.max(extent, Math.abs(value));
      }
    }
  }
  return (0.45 * Math.min(canvas.width, canvas.height)) / extent;
}

function drawScene(context, canvas, scene, index) {
  const scale = sceneScale(scene, canvas);
  const toCanvas = (p) => {
    const [x, y] = project(p, scene.dimension);
    return [canvas.width / 2 + scale * x, canvas.height / 2 - scale * y];
  };
  const origin = scene.dimension === 3 ? [0, 0, 0] : [0, 0];
  const where = (end) => {
    if (typeof end === "string") return end === "origin" ? origin : scene.points[end][index];
    return end.map((v) => v ?? 0);
  };
  context.strokeStyle = "#555";
  context.lineWidth = 2;
  for (const [a, b] of scene.links) {
    const [x1, y1] = toCanvas(where(a));
    const [x2, y2] = toCanvas(where(b));
    context.beginPath();
    context.moveTo(x1, y1);
    context.lineTo(x2, y2);
    context.stroke();
  }
  const colors = ["#1e88e5", "#e53935", "#43a047", "#fb8c00", "#8e24aa", "#00897b"];
  Object.entries(scene.points).forEach(([name, path], i) => {
    const color = colors[i % colors.length];
    context.strokeStyle = color;
    context.globalAlpha = 0.4;
    context.lineWidth = 1;
    context.beginPath();
    for (let k = Math.max(0, index - 60); k <= index; k++) {
      const [x, y] = toCanvas(path[k]);
      if (k === Math.max(0, index - 60)) context.moveTo(x, y);
      else context.lineTo(x, y);
    }
    context.stroke();
    context.globalAlpha = 1;
    const [x, y] = toCanvas(path[index]);
    context.fillStyle = color;
    context.beginPath();
    context.arc(x, y, 8, 0, 2 * Math.PI);
    context.fill();
    context.fillStyle = "#333";
    context.fillText(name, x + 10, y - 10);
  });
  context.fillStyle = "#333";
  const [ox, oy] = toCanvas(origin);
  context.fillRect(ox - 3, oy - 3, 6, 6);
}

function gaugeNames() {
  const coordinates = (state.derived && state.derived.coordinates) || [];
  const names = [];
  for (const q of coordinates) names.push(q, q + "_dot");
  return names.filter((n) => state.run.columns[n]);
}

function drawGauges(context, canvas, index) {
  const names = gaugeNames();
  const height = Math.min(40, (canvas.height - 40) / Math.max(1, names.length));
  names.forEach((name, i) => {
    const column = state.run.columns[name];
    const largest = Math.max(...column.map((v) => Math.abs(v ?? 0))) || 1;
    const value = (column[index] ?? 0) / largest;
    const y = 30 + i * height;
    const middle = canvas.width / 2 + 40;
    context.fillStyle = "#eceff1";
    context.fillRect(90, y, canvas.width - 110, height * 0.7);
    context.fillStyle = "#1e88e5";
    const width = value * (canvas.width - 110) / 2;
    context.fillRect(Math.min(middle, middle + width), y, Math.abs(width), height * 0.7);
    context.fillStyle = "#333";
    context.fillText(name, 8, y + height * 0.5);
  });
}

// ---- the plot of the coordinates against time
// ---- the plot: the coordinates against t, a phase portrait, or the energy's change
function plotChoices() {
  const columns = state.run ? state.run.columns : {};
  const names = ((state.derived && state.derived.coordinates) || []).filter((n) => columns[n]);
  const choices = [["coordinates", "coordinates against t"]];
  for (const n of names) if (columns[`${n}_dot`]) choices.push([`phase:${n}`, `phase portrait of ${n}`]);
  if (columns.energy) choices.push(["energy", "energy − E(0) against t"]);
  return choices;
}

function buildPlotMenu() {
  const menu = $("plot-kind");
  const chosen = menu.value;
  menu.innerHTML = "";
  for (const [value, text] of plotChoices()) {
    const option = document.createElement("option");
    option.value = value;
    option.textContent = text;
    menu.appendChild(option);
  }
  if ([...menu.options].some((o) => o.value === chosen)) menu.value = chosen;
}

// The curves of the chosen plot: [{name, xs, ys}], with the axis names.
function plotCurves() {
  const columns = state.run.columns;
  const kind = $("plot-kind").value || "coordinates";
  if (kind.startsWith("phase:")) {
    const name = kind.slice(6);
    return { x: name, y: `${name}_dot`, curves: [{ name, xs: columns[name], ys: columns[`${name}_dot`] }] };
  }
  if (kind === "energy") {
    const e0 = columns.energy[0] ?? 0;
    const ys = columns.energy.map((v) => (v === null ? null : v - e0));
    const label = state.run.summary.drift_summary;
    return { x: "t", y: "E − E(0)", curves: [{ name: label, xs: columns.t, ys }] };
  }
  const names = ((state.derived && state.derived.coordinates) || []).filter((n) => columns[n]);
  return { x: "t", y: "", curves: names.map((name) => ({ name, xs: columns.t, ys: columns[name] })) };
}

function range(arrays) {
  let low = Infinity;
  let high = -Infinity;
  for (const values of arrays) {
    for (const v of values) {
      if (v !== null && isFinite(v)) {
        low = Math.min(low, v);
        high = Math.max(high, v);
      }
    }
  }
  if (!isFinite(low)) [low, high] = [0, 1];
  if (!(high > low)) [low, high] = [low - 1, low + 1];
  return [low, high];
}

function drawPlot() {
  const canvas = $("plot");
  const context = canvas.getContext("2d");
  context.fillStyle = "#fff";
  context.fillRect(0, 0, canvas.width, canvas.height);
  if (!state.run) return;
  const plot = plotCurves();
  const [xLow, xHigh] = range(plot.curves.map((c) => c.xs));
  const [yLow, yHigh] = range(plot.curves.map((c) => c.ys));
  const left = 48;
  const box = { left, top: 10, width: canvas.width - left - 10, height: canvas.height - 40 };
  const x = (v) => box.left + (box.width * (v - xLow)) / (xHigh - xLow);
  const y = (v) => box.top + box.height * (1 - (v - yLow) / (yHigh - yLow));
  state.plotBox = { ...box, plot, x, y };
  context.strokeStyle = "#999";
  context.strokeRect(box.left, box.top, box.width, box.height);
  context.fillStyle = "#333";
  context.font = "11px sans-serif";
  context.fillText(yHigh.toPrecision(3), 2, box.top + 10);
  context.fillText(yLow.toPrecision(3), 2, box.top + box.height);
  context.fillText(plot.y, 2, box.top + box.height / 2);
  context.fillText(`${plot.x}: ${xLow.toPrecision(3)} … ${xHigh.toPrecision(3)}`, box.left + box.width - 150, canvas.height - 12);
  const colors = ["#1e88e5", "#e53935", "#43a047", "#fb8c00", "#8e24aa", "#00897b"];
  plot.curves.forEach((curve, i) => {
    context.strokeStyle = colors[i % colors.length];
    context.lineWidth = 1.5;
    context.beginPath();
    curve.ys.forEach((v, k) => {
      const at = [x(curve.xs[k] ?? 0), y(v ?? 0)];
      if (k === 0) context.moveTo(...at);
      else context.lineTo(...at);
    });
    context.stroke();
    context.fillStyle = colors[i % colors.length];
    const label = plot.curves.length > 1 ? curve.name : curve.name.slice(0, 40);
    context.fillText(label, box.left + 8 + 70 * i, canvas.height - 12);
  });
  state.plotImage = context.getImageData(0, 0, canvas.width, canvas.height);
}

// The current sample on the plot: a line at its time, or a dot on the phase curve.
function drawPlotCursor(index) {
  if (!state.plotImage || !state.plotBox) return;
  const canvas = $("plot");
  const context = canvas.getContext("2d");
  context.putImageData(state.plotImage, 0, 0);
  const { plot, x, y, top, height } = state.plotBox;
  context.strokeStyle = "rgba(0,0,0,0.35)";
  context.fillStyle = "rgba(0,0,0,0.6)";
  if (plot.x === "t") {
    const at = x(state.run.columns.t[index]);
    context.beginPath();
    context.moveTo(at, top);
    context.lineTo(at, top + height);
    context.stroke();
  } else {
    const curve = plot.curves[0];
    context.beginPath();
    context.arc(x(curve.xs[index] ?? 0), y(curve.ys[index] ?? 0), 4, 0, 2 * Math.PI);
    context.fill();
  }
}

// ---- downloads
function download(name, text, type) {
  const link = document.createElement("a");
  link.href = URL.createObjectURL(new Blob([text], { type }));
  link.download = name;
  link.click();
  setTimeout(() => URL.revokeObjectURL(link.href), 1000);
}

function csvText() {
  if (!state.run) return "";
  const names = Object.keys(state.run.columns);
  const rows = [names.join(",")];
  const count = state.run.columns.t.length;
  for (let k = 0; k < count; k++) rows.push(names.map((n) => state.run.columns[n][k]).join(","));
  return rows.join("\n") + "\n";
}

// ---- examples and wiring
async function loadExamples() {
  const response = await fetch("/api/examples");
  const { examples } = await response.json();
  const menu = $("examples");
  for (const { name, description } of examples) {
    const option = document.createElement("option");
    option.value = name;
    option.textContent = name.replace(/_/g, " ");
    option.title = description;
    menu.appendChild(option);
  }
}

async function loadExample(name) {
  if (!name) return;
  const response = await fetch(`/api/examples/${encodeURIComponent(name)}`);
  if (!response.ok) return;
  const example = await response.json();
  editor.value = example.model;
  $("format").value = example.format;
  modelChanged();
  await derive();
  await simulate();
}

function modelChanged() {
  state.settings = {};
  state.run = null;
  $("sliders").innerHTML = "";
  drawGutter();
  saveToUrl();
}

let typingTimer = null;
editor.addEventListener("input", () => {
  modelChanged();
  clearTimeout(typingTimer);
  typingTimer = setTimeout(derive, 700); // errors at their line as the user types
});
editor.addEventListener("scroll", () => {
  gutter.scrollTop = editor.scrollTop;
});
editor.addEventListener("keydown", (event) => {
  if (event.key === "Tab") {
    event.preventDefault();
    editor.setRangeText("  ", editor.selectionStart, editor.selectionEnd, "end");
    modelChanged();
  }
});
$("format").addEventListener("change", saveToUrl);
$("plot-kind").addEventListener("change", () => {
  drawPlot();
  if (state.run) drawPlotCursor(currentIndex());
});
$("examples").addEventListener("change", (event) => loadExample(event.target.value));
$("derive").addEventListener("click", derive);
$("analyze").addEventListener("click", analyze);
$("simulate").addEventListener("click", async () => {
  if (await derive()) await simulate();
});
$("download-model").addEventListener("click", (event) => {
  event.preventDefault();
  download(`model.${$("format").value}`, editor.value, "text/plain");
});
$("download-latex").addEventListener("click", (event) => {
  event.preventDefault();
  const parts = [state.derived && state.derived.latex, state.analysis && state.analysis.latex];
  download("equations.tex", parts.filter(Boolean).join("\n\n"), "text/x-tex");
});
$("download-csv").addEventListener("click", (event) => {
  event.preventDefault();
  download("trajectory.csv", csvText(), "text/csv");
});
$("download-code").addEventListener("click", async (event) => {
  event.preventDefault();
  const language = $("export-language").value;
  const answer = await call("export", { language, set: settingsList() });
  if (!answer) return;
  for (const [name, text] of Object.entries(answer.files)) download(name, text, "text/plain");
});

async function start() {
  await loadExamples();
  if (readUrl()) {
    drawGutter();
    if (await derive()) await simulate();
  } else {
    $("examples").value = "double_pendulum";
    await loadExample("double_pendulum");
  }
  document.body.dataset.ready = "true";
}

start();
