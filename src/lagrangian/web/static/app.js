// The playground page: an editor for a model file, the equations and the analysis typeset
// with KaTeX, and the simulation drawn on a canvas. Everything it needs comes from the
// server's JSON API (/api/derive, /api/analyze, /api/simulate, /api/examples).
//
// Every result belongs to one text of the model (state.version, raised at each edit): an
// answer to an older text is dropped, a panel computed from an older text is marked out of
// date, and downloads take only what is current.
"use strict";

const $ = (id) => document.getElementById(id);
const editor = $("editor");
const gutter = $("gutter");
// This page's name for itself: the server queues its requests together, and its newer
// request of a kind replaces the older one there too.
const CLIENT =
  (window.crypto && crypto.randomUUID && crypto.randomUUID()) || String(Math.random()).slice(2);
// Rows of LaTeX longer than this are typeset only when asked (the Whipple bicycle's are MBs).
const LARGE_ROW = 20000;
// Curve colours with at least 4.5:1 contrast on white (WCAG AA for text).
const COLORS = ["#1f5fa8", "#b3261e", "#2e7d32", "#8a4b08", "#6a1b9a", "#00695c"];
const state = {
  version: 0, // raised at each change of the model's text or format
  derived: null, // {version, answer}
  analysis: null, // {version, answer}
  run: null, // {version, settings, answer}
  settings: {}, // slider values: name -> number (options.set)
  defaults: {}, // the model's own values of the sliders' names
  playing: true,
  playhead: 0, // the motion's time shown
  rate: 1, // seconds of motion per second on screen
  frame: 0,
  lastTick: 0,
  animation: null,
};

const current = (result) => result && result.version === state.version;

// ---- the model in the URL: #model=<base64url of the UTF-8 text>&format=yaml&set=k=2;m=1
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
  const settings = settingsList();
  if (settings.length) params.set("set", settings.join(";"));
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
  state.settings = {};
  for (const item of (params.get("set") || "").split(";").filter(Boolean)) {
    const [name, value] = item.split("=");
    if (name && isFinite(Number(value))) state.settings[name] = Number(value);
  }
  return true;
}

// ---- the editor: line numbers, errors, and the keyboard (Tab leaves, Esc then Tab indents)
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
      const go = document.createElement("button");
      go.type = "button";
      go.className = "go";
      go.textContent = `go to line ${p.line}`;
      go.addEventListener("click", () => goToLine(p.line, p.column));
      item.appendChild(go);
      item.dataset.line = p.line;
      badLines.add(p.line);
    }
    list.appendChild(item);
  }
  drawGutter();
}

const INDENT = "  ";
let indentArmed = false; // Escape or Ctrl-] pressed: Tab indents until another key

function indentLines(outdent) {
  const text = editor.value;
  const start = text.lastIndexOf("\n", editor.selectionStart - 1) + 1;
  const end = editor.selectionEnd;
  const block = text.slice(start, end);
  const lines = block.split("\n");
  const changed = lines
    .map((line) => (outdent ? line.replace(/^ {1,2}/, "") : INDENT + line))
    .join("\n");
  editor.setRangeText(changed, start, end, "select");
  if (editor.selectionStart === editor.selectionEnd || lines.length === 1) {
    const caret = outdent ? Math.max(start, end - (block.length - changed.length)) : end + INDENT.length;
    editor.setSelectionRange(caret, caret);
  }
  modelChanged();
}

function setIndentMode(armed) {
  indentArmed = armed;
  $("editor-help").textContent = armed
    ? "Tab indents, Shift+Tab outdents (any other key, and Tab moves on again)."
    : "Tab moves to the next control; Esc or Ctrl+] then Tab indents.";
}

editor.addEventListener("keydown", (event) => {
  if (event.key === "Escape" || (event.ctrlKey && event.key === "]")) {
    event.preventDefault();
    setIndentMode(true);
    return;
  }
  if (event.key === "Tab" && indentArmed) {
    event.preventDefault();
    indentLines(event.shiftKey);
    return;
  }
  if (indentArmed && event.key !== "Shift") setIndentMode(false);
});
editor.addEventListener("blur", () => setIndentMode(false));

// ---- the server: requests tied to the text that made them, and a server that went away
const controllers = {}; // command -> the AbortController of its request in flight
let lost = false;

function setStatus(text) {
  $("status").textContent = text;
}

function serverLost() {
  if (lost) return;
  lost = true;
  const banner = $("connection");
  banner.hidden = false;
  banner.textContent =
    "The server does not answer: is lagrangian serve still running? Results shown may be out " +
    "of date; the page tries again every few seconds.";
  setStatus("no server");
  document.body.dataset.server = "lost";
}

function serverFound() {
  if (!lost) return;
  lost = false;
  $("connection").hidden = true;
  document.body.dataset.server = "up";
  setStatus("the server answers again");
  if (!current(state.derived) || !current(state.run)) refresh();
}

async function checkServer() {
  try {
    const response = await fetch("/api/health", { cache: "no-store" });
    if (response.ok) serverFound();
    else serverLost();
  } catch (error) {
    serverLost();
  }
}

// The answer of ``command`` for the current text, or null (an error shown, a newer request
// made, the text changed meanwhile, or no server).
async function call(command, options) {
  const version = state.version;
  const body = { model: editor.value, format: $("format").value, options: options || {} };
  if (controllers[command]) controllers[command].abort();
  const controller = new AbortController();
  controllers[command] = controller;
  setStatus(`${command}…`);
  let response;
  let answer;
  try {
    response = await fetch(`/api/${command}`, {
      method: "POST",
      headers: { "Content-Type": "application/json", "X-Lagrangian-Client": CLIENT },
      body: JSON.stringify(body),
      signal: controller.signal,
    });
    answer = await response.json();
  } catch (error) {
    if (controller.signal.aborted) return null; // replaced by a newer request
    serverLost();
    return null;
  } finally {
    if (controllers[command] === controller) delete controllers[command];
  }
  serverFound();
  if (version !== state.version || response.status === 409) return null;
  if (!response.ok) {
    showProblems(answer.problems || [{ field: "", message: `HTTP ${response.status}` }]);
    setStatus(`${command}: ${answer.error || "error"}`);
    return null;
  }
  showProblems([]);
  setStatus(`${command}: done`);
  return answer;
}

// ---- the panels and what they show
function markStale() {
  for (const id of ["equations", "analysis", "simulation-panel"]) {
    const panel = $(id);
    panel.classList.toggle("stale", panel.dataset.version !== String(state.version));
  }
  const latexReady = current(state.derived);
  const csvReady = current(state.run);
  $("download-latex").setAttribute("aria-disabled", String(!latexReady));
  $("download-csv").setAttribute("aria-disabled", String(!csvReady));
}

async function derive() {
  const answer = await call("derive", { steps: true });
  if (!answer) {
    markStale();
    return false;
  }
  state.derived = { version: state.version, answer };
  typeset($("equations"), answer.latex, state.version);
  markStale();
  return true;
}

async function analyze() {
  const answer = await call("analyze", { set: settingsList() });
  if (!answer) return;
  state.analysis = { version: state.version, answer };
  const target = $("analysis");
  typeset(target, answer.latex, state.version);
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
  markStale();
}

// ---- sliders: each parameter and initial value, with an exact number beside it
function settingsList() {
  return Object.entries(state.settings).map(([name, value]) => `${name}=${value}`);
}

// The slider's range: from the value's size and sign; coordinates and velocities go both ways.
function sliderRange(value, signed, scale) {
  const size = Math.max(Math.abs(value), scale || 0);
  if (signed) {
    const reach = 2 * size || 1;
    return [-reach, reach];
  }
  if (value > 0) return [0, 3 * value];
  if (value < 0) return [3 * value, 0];
  return [-1, 1];
}

const shortNumber = (v) => Number(Number(v).toPrecision(3));

function addSlider(name, fallback, kind, signed, scale) {
  const model = state.defaults[name] ?? fallback;
  state.defaults[name] = model;
  const value = state.settings[name] ?? model;
  const unit = ((current(state.derived) && state.derived.answer.units) || {})[name];
  const row = document.createElement("div");
  row.className = "slider";
  const id = `set-${name}`;
  const label = document.createElement("label");
  label.htmlFor = id;
  label.textContent = unit ? `${name} (${unit})` : name;
  label.title = kind;
  const [low, high] = sliderRange(model, signed, scale);
  const slider = document.createElement("input");
  Object.assign(slider, { type: "range", min: Math.min(low, value), max: Math.max(high, value) });
  slider.step = "any";
  slider.value = value;
  slider.dataset.name = name;
  slider.setAttribute("aria-label", `${name}, ${kind}, slider`);
  const box = document.createElement("input");
  Object.assign(box, { type: "number", id, step: "any", value: String(value) });
  box.dataset.name = name;
  const reset = document.createElement("button");
  reset.type = "button";
  reset.className = "reset";
  reset.textContent = "↺";
  reset.setAttribute("aria-label", `reset ${name} to ${model}`);
  reset.title = `back to the model's ${model}`;
  row.append(label, slider, box, reset);
  const chosen = (number) => {
    if (number === model) delete state.settings[name];
    else state.settings[name] = number;
    saveToUrl();
    scheduleSimulation();
  };
  slider.addEventListener("input", () => {
    const number = shortNumber(slider.value); // a short value, not the slider's pixel
    box.value = String(number);
    chosen(number);
  });
  box.addEventListener("input", () => {
    if (box.value === "" || !isFinite(Number(box.value))) return;
    const number = Number(box.value); // exactly as typed
    slider.min = Math.min(Number(slider.min), number);
    slider.max = Math.max(Number(slider.max), number);
    slider.value = number;
    chosen(number);
  });
  reset.addEventListener("click", () => {
    box.value = String(model);
    slider.value = model;
    chosen(model);
  });
  $("sliders").appendChild(row);
}

let simulationTimer = null;
function scheduleSimulation() {
  clearTimeout(simulationTimer);
  simulationTimer = setTimeout(() => simulate(false), 250);
}

function columnScale(column) {
  return Math.max(0, ...(column || []).map((v) => Math.abs(v ?? 0)));
}

function buildSliders(run) {
  $("sliders").innerHTML = "";
  const derived = current(state.derived) ? state.derived.answer : {};
  for (const [name, value] of Object.entries(derived.parameters || run.summary.parameters || {})) {
    addSlider(name, value, "parameter", false, 0);
  }
  const initial = derived.initial || {};
  for (const q of derived.coordinates || []) {
    for (const name of [q, q + "_dot"]) {
      const column = run.columns[name];
      if (column) addSlider(name, initial[name] ?? column[0], "initial value", true, columnScale(column));
    }
  }
  $("reset-all").hidden = !$("sliders").children.length;
}

async function simulate(rebuild = true) {
  const settings = settingsList().join(";");
  const answer = await call("simulate", { set: settingsList() });
  if (!answer || !current(state.derived)) {
    markStale();
    return;
  }
  const times = answer.rows.map((row) => answer.columns.t[row]); // the scene's frames' times
  state.run = { version: state.version, settings, answer, times };
  $("simulation-panel").dataset.version = state.version;
  if (rebuild || !$("sliders").children.length) buildSliders(answer);
  buildPlotMenu();
  const s = answer.summary;
  const impacts = s.impacts_summary ? `; ${s.impacts_summary}` : ""; // as the command line says
  $("summary").textContent = `${s.samples} samples, ${s.method}: ${s.drift_summary}${impacts}`;
  drawPlot();
  startAnimation(rebuild);
  markStale();
}

async function refresh() {
  if (await derive()) await simulate();
}

// ---- the animation: the run's scene (Scene.to_dict(), drawn by scene_player.js, the one
// drawing code of the command line's animations too), each of its frames one sample of the
// run (answer.rows); played at the motion's own time scale, with play/pause, step, speed and
// a time slider over the frames.
const PANEL_HEIGHT = 300; // the canvas's height per panel of the scene (panels stack)

function motionPeriod(columns, names) {
  // The shortest period among the coordinates, from how often each crosses its mean.
  const t = columns.t;
  const span = t[t.length - 1] - t[0] || 1;
  let period = span;
  for (const name of names) {
    const values = (columns[name] || []).filter((v) => v !== null);
    if (values.length < 3) continue;
    const mean = values.reduce((a, b) => a + b, 0) / values.length;
    let crossings = 0;
    for (let k = 1; k < values.length; k++) {
      if ((values[k - 1] - mean) * (values[k] - mean) < 0) crossings += 1;
    }
    if (crossings >= 2) period = Math.min(period, (2 * span) / crossings);
  }
  return period;
}

// The coordinates and velocities the run has columns for.
function motionNames() {
  const columns = state.run ? state.run.answer.columns : {};
  const coordinates = (current(state.derived) && state.derived.answer.coordinates) || [];
  const names = [];
  for (const q of coordinates) names.push(q, q + "_dot");
  return names.filter((n) => columns[n]);
}

function chooseSpeeds(columns) {
  // One period of the motion takes 2 s on screen, and the whole run at least 4 s.
  const t = columns.t;
  const span = t[t.length - 1] - t[0] || 1;
  const base = Math.min(motionPeriod(columns, motionNames()) / 2, span / 4);
  const menu = $("speed");
  menu.innerHTML = "";
  for (const factor of [0.25, 0.5, 1, 2, 4]) {
    const option = document.createElement("option");
    option.value = String(base * factor);
    option.textContent = `${shortNumber(base * factor)}× real time`;
    menu.appendChild(option);
  }
  menu.selectedIndex = 2;
  state.rate = base;
}

function startAnimation(fresh) {
  const run = state.run;
  const times = run.times;
  $("time").max = String(times.length - 1);
  const height = PANEL_HEIGHT * Math.max(1, run.answer.scene.panels.length);
  if ($("canvas").height !== height) $("canvas").height = height;
  if (fresh) {
    chooseSpeeds(run.answer.columns);
    state.playhead = times[0];
  }
  cancelAnimationFrame(state.animation);
  state.lastTick = performance.now();
  const tick = (now) => {
    if (state.playing && current(state.run)) {
      const span = times[times.length - 1] - times[0] || 1;
      state.playhead += ((now - state.lastTick) / 1000) * state.rate;
      if (state.playhead > times[times.length - 1]) {
        state.playhead = times[0] + ((state.playhead - times[0]) % span);
      }
    }
    state.lastTick = now;
    drawFrame();
    state.animation = requestAnimationFrame(tick);
  };
  state.animation = requestAnimationFrame(tick);
}

function setPlaying(playing) {
  state.playing = playing;
  const button = $("play");
  button.textContent = playing ? "Pause" : "Play";
  button.setAttribute("aria-pressed", String(!playing));
}

function stepFrame(by) {
  if (!state.run) return;
  setPlaying(false);
  const times = state.run.times;
  state.playhead = times[Math.min(times.length - 1, Math.max(0, state.frame + by))];
}

// The first frame at or after ``time``.
function indexAt(time) {
  const times = state.run.times;
  let low = 0;
  let high = times.length - 1;
  while (low < high) {
    const middle = (low + high) >> 1;
    if (times[middle] < time) low = middle + 1;
    else high = middle;
  }
  return low;
}

// The frame at the playhead: the scene drawn, the time slider, the time and the plot's cursor
// at its sample.  What was drawn is kept in state.drawn (the frame, its sample, the elements).
function drawFrame() {
  const canvas = $("canvas");
  if (!state.run) {
    const context = canvas.getContext("2d");
    context.fillStyle = "#fff";
    context.fillRect(0, 0, canvas.width, canvas.height);
    return;
  }
  const run = state.run.answer;
  const frame = indexAt(state.playhead);
  const sample = run.rows[frame];
  state.frame = frame;
  const drawn = LagrangianScene.drawFrame(canvas, run.scene, frame);
  state.drawn = { version: state.run.version, sample, ...drawn };
  const t = run.columns.t[sample];
  $("time").value = String(frame);
  $("time-shown").textContent = `t = ${t.toPrecision(4)} s`;
  drawPlotCursor(sample);
}

// ---- the plot: the coordinates against t, a phase portrait, or the energy's change
function units() {
  return (current(state.derived) && state.derived.answer.units) || {};
}

function withUnit(name) {
  const unit = units()[name];
  return unit ? `${name} (${unit})` : name;
}

function plotChoices() {
  const columns = state.run ? state.run.answer.columns : {};
  const names = ((current(state.derived) && state.derived.answer.coordinates) || []).filter(
    (n) => columns[n],
  );
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

// The curves of the chosen plot: [{name, xs, ys}], with the axis titles.
function plotCurves() {
  const columns = state.run.answer.columns;
  const kind = $("plot-kind").value || "coordinates";
  const time = units().t ? `t (${units().t})` : "t (s)";
  if (kind.startsWith("phase:")) {
    const name = kind.slice(6);
    const rate = units()[name] ? `${name}_dot (${units()[name]}/s)` : `${name}_dot`;
    return { x: withUnit(name), y: rate, curves: [{ name, xs: columns[name], ys: columns[`${name}_dot`] }] };
  }
  if (kind === "energy") {
    const e0 = columns.energy[0] ?? 0;
    const ys = columns.energy.map((v) => (v === null ? null : v - e0));
    const label = state.run.answer.summary.drift_summary;
    return { x: time, y: "E − E(0)", curves: [{ name: label, xs: columns.t, ys }] };
  }
  const names = ((current(state.derived) && state.derived.answer.coordinates) || []).filter(
    (n) => columns[n],
  );
  const shared = new Set(names.map((n) => units()[n] || ""));
  const y = shared.size === 1 && [...shared][0] ? `(${[...shared][0]})` : "";
  const curves = names.map((name) => ({ name: withUnit(name), xs: columns.t, ys: columns[name] }));
  return { x: time, y, curves };
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

// Ticks at 1, 2 or 5 times a power of ten, about ``count`` of them over [low, high].
function ticks(low, high, count) {
  const raw = (high - low) / count;
  const power = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((f) => f * power).find((s) => s >= raw) || 10 * power;
  const values = [];
  for (let v = Math.ceil(low / step) * step; v <= high + step * 1e-9; v += step) {
    values.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  }
  return values;
}

function tickText(v) {
  const text = Number(v.toPrecision(6));
  return Math.abs(text) >= 1e5 || (Math.abs(text) < 1e-3 && text !== 0)
    ? text.toExponential(1)
    : String(text);
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
  const box = { left: 58, top: 12, width: canvas.width - 70, height: canvas.height - 58 };
  const x = (v) => box.left + (box.width * (v - xLow)) / (xHigh - xLow);
  const y = (v) => box.top + box.height * (1 - (v - yLow) / (yHigh - yLow));
  state.plotBox = { ...box, plot, x, y };
  context.font = "12px sans-serif";
  context.fillStyle = "#263238";
  context.strokeStyle = "#e0e0e0";
  context.lineWidth = 1;
  context.textAlign = "center";
  for (const v of ticks(xLow, xHigh, 5)) {
    context.beginPath();
    context.moveTo(x(v), box.top);
    context.lineTo(x(v), box.top + box.height);
    context.stroke();
    context.fillText(tickText(v), x(v), box.top + box.height + 15);
  }
  context.textAlign = "right";
  for (const v of ticks(yLow, yHigh, 5)) {
    context.beginPath();
    context.moveTo(box.left, y(v));
    context.lineTo(box.left + box.width, y(v));
    context.stroke();
    context.fillText(tickText(v), box.left - 5, y(v) + 4);
  }
  context.strokeStyle = "#546e7a";
  context.strokeRect(box.left, box.top, box.width, box.height);
  context.textAlign = "center";
  context.fillText(plot.x, box.left + box.width / 2, canvas.height - 8);
  context.save();
  context.translate(12, box.top + box.height / 2);
  context.rotate(-Math.PI / 2);
  context.fillText(plot.y, 0, 0);
  context.restore();
  context.textAlign = "left";
  plot.curves.forEach((curve, i) => {
    context.strokeStyle = COLORS[i % COLORS.length];
    context.lineWidth = 1.5;
    context.beginPath();
    curve.ys.forEach((v, k) => {
      const at = [x(curve.xs[k] ?? 0), y(v ?? 0)];
      if (k === 0) context.moveTo(...at);
      else context.lineTo(...at);
    });
    context.stroke();
  });
  drawLegend(plot);
  state.plotImage = context.getImageData(0, 0, canvas.width, canvas.height);
}

// The legend as text beside the plot: it wraps, never overlaps, and screen readers read it.
function drawLegend(plot) {
  const legend = $("legend");
  legend.innerHTML = "";
  plot.curves.forEach((curve, i) => {
    const item = document.createElement("li");
    item.style.color = COLORS[i % COLORS.length];
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = COLORS[i % COLORS.length];
    item.append(swatch, document.createTextNode(curve.name));
    legend.appendChild(item);
  });
}

// The current sample on the plot: a line at its time, or a dot on the phase curve.
function drawPlotCursor(index) {
  if (!state.plotImage || !state.plotBox) return;
  const canvas = $("plot");
  const context = canvas.getContext("2d");
  context.putImageData(state.plotImage, 0, 0);
  const { plot, x, y, top, height } = state.plotBox;
  context.strokeStyle = "rgba(0,0,0,0.45)";
  context.fillStyle = "rgba(0,0,0,0.7)";
  if (!plot.curves.length) return;
  if (plot.x.startsWith("t")) {
    const at = x(state.run.answer.columns.t[index]);
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

// ---- downloads: only what the page shows for the current text
function download(name, text, type) {
  const link = document.createElement("a");
  link.href = URL.createObjectURL(new Blob([text], { type }));
  link.download = name;
  link.click();
  setTimeout(() => URL.revokeObjectURL(link.href), 1000);
}

function csvText() {
  const columns = state.run.answer.columns;
  const names = Object.keys(columns);
  const rows = [names.join(",")];
  for (let k = 0; k < columns.t.length; k++) rows.push(names.map((n) => columns[n][k] ?? "").join(","));
  return rows.join("\n") + "\n";
}

// ---- examples and wiring
async function loadExamples() {
  let examples = [];
  try {
    const response = await fetch("/api/examples");
    ({ examples } = await response.json());
  } catch (error) {
    serverLost();
    return;
  }
  const menu = $("examples");
  for (const entry of examples) exampleEntries[entry.name] = entry;
  for (const { name, description, benchmark } of examples) {
    const option = document.createElement("option");
    option.value = name;
    option.textContent = name.replace(/_/g, " ") + (benchmark ? " (large)" : "");
    option.title = description;
    menu.appendChild(option);
  }
}

// An example built to a size (the gas's disks, the pendulum's links) shows the size field:
// its number of disks is its number of coordinates, which no slider can change, so a new
// size is a new model, written by the server.
const exampleEntries = {};
function showSizeField(name) {
  const bounds = (exampleEntries[name] || {}).size;
  $("size-field").hidden = !bounds;
  if (!bounds) return null;
  const input = $("example-size");
  $("size-counts").textContent = bounds.counts[0].toUpperCase() + bounds.counts.slice(1);
  input.max = bounds.largest;
  if (input.dataset.example !== name) input.value = bounds.default;
  input.dataset.example = name;
  $("size-help").textContent =
    `${bounds.counts} of the example, 1 to ${bounds.largest} here; more with the command line`;
  const asked = Math.round(Number(input.value));
  const size = Math.min(bounds.largest, Math.max(1, isFinite(asked) ? asked : bounds.default));
  input.value = size;
  return size;
}

let examplePicked = 0;
async function loadExample(name) {
  const size = showSizeField(name);
  if (!name) return;
  const picked = ++examplePicked;
  let example;
  try {
    const query = size === null ? "" : `?size=${size}`;
    const response = await fetch(`/api/examples/${encodeURIComponent(name)}${query}`);
    if (!response.ok) return;
    example = await response.json();
  } catch (error) {
    serverLost();
    return;
  }
  serverFound();
  if (picked !== examplePicked) return; // another example was picked meanwhile
  $("example-size").dataset.loaded = size === null ? "" : `${name}:${size}`;
  editor.value = example.model;
  $("format").value = example.format;
  modelChanged();
  await refresh();
}

function modelChanged() {
  state.version += 1;
  document.body.dataset.version = state.version;
  state.settings = {};
  state.defaults = {};
  $("sliders").innerHTML = "";
  $("reset-all").hidden = true;
  $("analysis").innerHTML = '<p class="hint">Press Analyze.</p>';
  $("analysis").dataset.version = state.version;
  for (const command of Object.keys(controllers)) controllers[command].abort();
  drawGutter();
  saveToUrl();
  markStale();
}

let typingTimer = null;
editor.addEventListener("input", () => {
  modelChanged();
  clearTimeout(typingTimer);
  typingTimer = setTimeout(refresh, 700); // errors at their line as the user types
});
editor.addEventListener("scroll", () => {
  gutter.scrollTop = editor.scrollTop;
});
$("format").addEventListener("change", () => {
  modelChanged();
  refresh();
});
$("plot-kind").addEventListener("change", () => {
  drawPlot();
  if (state.run) drawPlotCursor(state.run.answer.rows[state.frame]);
});
$("examples").addEventListener("change", (event) => loadExample(event.target.value));
$("example-size").addEventListener("change", () => {
  const input = $("example-size");
  const asked = `${$("examples").value}:${Math.round(Number(input.value))}`;
  if (asked !== input.dataset.loaded) loadExample($("examples").value); // a new size only
});
$("derive").addEventListener("click", derive);
$("analyze").addEventListener("click", analyze);
$("simulate").addEventListener("click", refresh);
$("play").addEventListener("click", () => setPlaying(!state.playing));
$("step-back").addEventListener("click", () => stepFrame(-1));
$("step-forward").addEventListener("click", () => stepFrame(1));
$("speed").addEventListener("change", () => {
  state.rate = Number($("speed").value);
});
$("time").addEventListener("input", () => {
  if (!state.run) return;
  setPlaying(false);
  state.playhead = state.run.times[Number($("time").value)];
});
$("reset-all").addEventListener("click", () => {
  state.settings = {};
  saveToUrl();
  if (state.run) buildSliders(state.run.answer);
  scheduleSimulation();
});
$("download-model").addEventListener("click", (event) => {
  event.preventDefault();
  download(`model.${$("format").value}`, editor.value, "text/plain");
});
$("download-latex").addEventListener("click", (event) => {
  event.preventDefault();
  if (!current(state.derived)) {
    setStatus("LaTeX: derive the current text first");
    return;
  }
  const parts = [state.derived.answer.latex];
  if (current(state.analysis)) parts.push(state.analysis.answer.latex);
  download("equations.tex", parts.join("\n\n"), "text/x-tex");
});
$("download-csv").addEventListener("click", (event) => {
  event.preventDefault();
  if (!current(state.run)) {
    setStatus("CSV: simulate the current text first");
    return;
  }
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
  setIndentMode(false);
  document.body.dataset.server = "up";
  setInterval(checkServer, 3000); // a lost server is noticed even when nothing is asked
  await loadExamples();
  if (readUrl()) {
    const settings = { ...state.settings };
    modelChanged();
    state.settings = settings;
    saveToUrl();
    await refresh();
  } else {
    $("examples").value = "double_pendulum";
    await loadExample("double_pendulum");
  }
  document.body.dataset.ready = "true";
}

start();
