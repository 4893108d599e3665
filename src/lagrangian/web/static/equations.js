// The playground's equations: each row of LaTeX typeset with KaTeX as it scrolls into view and
// set to fit its box (loaded before app.js, which calls typeset(); LARGE_ROW is app.js's).
"use strict";

// ---- LaTeX with KaTeX: one row at a time, typeset as it scrolls into view, each set to fit its
// box as a textbook sets a long formula: broken before a top-level +, − or = (continued lines
// indented), then inside its parentheses, then with its fractions opened (A/B as 1/B (A)), then
// between factors; a matrix equation A x = b too wide for its box names its long entries
// (M_{12}) and lists them beneath, or, when even that is too wide, is written row by row. The
// type shrinks only down to the size of the page's text; a row that still does not fit scrolls
// on its own (the last resort).

// KaTeX sets its type at 1.21em: this scale keeps an equation at the size of the text around it.
const SMALLEST_TYPE = 1 / 1.21;
// Parentheses around more LaTeX than this may break inside (a sum of three or more terms).
const LONG_PARENTHESES = 40;
// A matrix equation with more LaTeX than this is not tried whole (typesetting it takes seconds).
const WHOLE_MATRIX = 4000;
// What KaTeX draws past the formula's own box (a 2 px strut beside each stack of lines), in px.
const OVERHANG = 3;

function splitTopLevel(latex, separator) {
  // Pieces of ``latex`` between occurrences of ``separator`` outside braces and environments.
  const pieces = [];
  let depth = 0;
  let start = 0;
  for (let i = 0; i < latex.length; i++) {
    const c = latex[i];
    if (c === "\\") {
      if (latex.startsWith("\\begin{", i)) depth += 1;
      else if (latex.startsWith("\\end{", i)) depth -= 1;
      else if (depth === 0 && latex.startsWith(separator, i)) {
        pieces.push(latex.slice(start, i));
        start = i + separator.length;
        i = start - 1;
        continue;
      }
      i += 1; // an escaped character is never a separator
      continue;
    }
    if (c === "{") depth += 1;
    else if (c === "}") depth -= 1;
    else if (depth === 0 && latex.startsWith(separator, i)) {
      pieces.push(latex.slice(start, i));
      start = i + separator.length;
      i = start - 1;
    }
  }
  pieces.push(latex.slice(start));
  return pieces;
}

function latexRows(latex) {
  const rows = [];
  for (const block of latex.split(/\\end\{align\*\}/)) {
    const body = block.replace(/\\begin\{align\*\}/, "").trim();
    if (!body) continue;
    for (const row of splitTopLevel(body, "\\\\")) if (row.trim()) rows.push(row.trim());
  }
  return rows;
}

// Places where a row may break: before a top-level "+", "-" or "=" (outside \left( \right) too),
// after the comma of a list, between the words of a text, and, when ``betweenFactors``,
// between any two factors.
function breakPoints(row, betweenFactors) {
  const points = [];
  let depth = 0;
  for (let i = 0; i < row.length; i++) {
    const c = row[i];
    if (c === "\\") {
      if (row.startsWith("\\left", i) || row.startsWith("\\begin{", i)) depth += 1;
      else if (row.startsWith("\\right", i) || row.startsWith("\\end{", i)) depth -= 1;
      i += 1;
      continue;
    }
    if (c === "{") depth += 1;
    else if (c === "}") depth -= 1;
    else if (depth === 0 && i > 0 && /[+\-=]/.test(c) && row[i - 1] === " ") {
      const sign = c !== "=" && /= *$/.test(row.slice(Math.max(0, i - 3), i)); // "= -x"
      if (!sign) points.push(i);
    }
    if (depth === 0 && c === ",") {
      // after a comma of a list (values, frequencies), before the next item
      const gap = /^,(\\ |\\quad |\\qquad )/.exec(row.slice(i, i + 9));
      if (gap) points.push(i + gap[0].length);
    }
    if (depth === 0 && row.startsWith(" \\text{", i)) points.push(i + 1); // between words
    else if (betweenFactors && depth === 0 && c === " " && /[\\\w]/.test(row[i + 1] || "")) {
      if (i > 0 && !/[+\-=(]/.test(row[i - 1])) points.push(i + 1); // not right after an operator
    }
  }
  return points;
}

// The pieces of ``latex`` between its break points.
function piecesOf(latex, betweenFactors) {
  const pieces = [];
  let start = 0;
  for (const point of breakPoints(latex, betweenFactors)) {
    pieces.push(latex.slice(start, point));
    start = point;
  }
  pieces.push(latex.slice(start));
  return pieces.filter((piece) => piece.trim());
}

// The group in braces that starts at ``at`` (a "{"): [its inside, the index after it].
function braceGroup(latex, at) {
  let depth = 0;
  for (let i = at; i < latex.length; i++) {
    if (latex[i] === "\\") i += 1;
    else if (latex[i] === "{") depth += 1;
    else if (latex[i] === "}" && --depth === 0) return [latex.slice(at + 1, i), i + 1];
  }
  return [latex.slice(at + 1), latex.length];
}

// ``latex`` with its long \left( … \right) pairs outside braces written \bigl( … \bigr) (\Bigl
// around a fraction): a pair split over lines cannot size itself, and a sum inside may then
// break (a short one, such as (m_1 + m_2), stays whole: the line breaks around it).
function openParentheses(latex) {
  let out = "";
  let depth = 0;
  const opened = []; // where in ``out`` each pair still open starts
  for (let i = 0; i < latex.length; i++) {
    const c = latex[i];
    if (c === "\\" && depth === 0 && latex.startsWith("\\left(", i)) {
      opened.push(out.length);
      out += "\\left(";
      i += 5;
    } else if (c === "\\" && depth === 0 && latex.startsWith("\\right)", i) && opened.length) {
      const at = opened.pop();
      const size = out.includes("\\frac", at) ? "Big" : "big";
      if (out.length - at > LONG_PARENTHESES) {
        out = `${out.slice(0, at)}\\${size}l(${out.slice(at + 6)}\\${size}r)`;
      } else out += "\\right)";
      i += 6;
    } else if (c === "\\") {
      out += latex.slice(i, i + 2);
      i += 1;
    } else {
      if (c === "{") depth += 1;
      else if (c === "}") depth -= 1;
      out += c;
    }
  }
  return out;
}

// Whether ``latex`` is a sum (it may break at a top-level + or −, its parentheses opened).
function isSum(latex) {
  return piecesOf(openParentheses(latex), false).length > 1;
}

// ``latex`` in parentheses if it is a sum.
function grouped(latex) {
  return isSum(latex) ? `\\bigl(${latex}\\bigr)` : latex;
}

// Each fraction outside braces, A/B, written 1/B (A), or (A) (B)^{-1} when B is long, each
// root √X written (X)^{1/2}, and each text word by word: a long numerator, denominator,
// radicand or sentence may then break.
function openFractions(latex) {
  let out = "";
  let depth = 0;
  for (let i = 0; i < latex.length; i++) {
    if (depth === 0 && latex.startsWith("\\frac{", i)) {
      const [top, afterTop] = braceGroup(latex, i + 5);
      const [bottom, after] = braceGroup(latex, afterTop);
      const root = /^\\sqrt\{/.test(bottom) && braceGroup(bottom, 5)[1] === bottom.length;
      const factor = top === "1" ? "" : `${grouped(top)} `;
      if (root) out += `${factor}\\bigl(${braceGroup(bottom, 5)[0]}\\bigr)^{-1/2}`;
      else if (isSum(bottom)) out += `${factor}\\bigl(${bottom}\\bigr)^{-1}`;
      else if (top === "1") out += latex.slice(i, after); // already open
      else out += `\\frac{1}{${bottom}} ${grouped(top)}`;
      i = after - 1;
      continue;
    }
    if (depth === 0 && latex.startsWith("\\sqrt{", i)) {
      const [radicand, after] = braceGroup(latex, i + 5);
      out += `\\bigl(${radicand}\\bigr)^{1/2}`;
      i = after - 1;
      continue;
    }
    if (depth === 0 && latex.startsWith("\\text{", i)) {
      const [words, after] = braceGroup(latex, i + 5);
      out += words.split(" ").map((word) => `\\text{${word} }`).join(" ");
      i = after - 1;
      continue;
    }
    const c = latex[i];
    if (c === "\\") {
      out += c + (latex[i + 1] || "");
      i += 1;
      continue;
    }
    if (c === "{") depth += 1;
    else if (c === "}") depth -= 1;
    out += c;
  }
  return out;
}

// A piece too wide for a line, loosened one step further: its parentheses opened, then its
// fractions and roots, then broken between its factors (the fractions and roots that this
// brings to the top opened too).
const LOOSER = [
  (piece) => piecesOf(openParentheses(piece), false),
  (piece) => piecesOf(openParentheses(openFractions(piece)), false),
  (piece) => piecesOf(openParentheses(openFractions(piece)), true),
];

function katexHtml(latex) {
  return window.katex.renderToString(latex, { displayMode: true, throwOnError: false });
}

// The width in px of what ``node`` has typeset (the formula itself, not the display around it).
function typesetWidth(node) {
  const range = document.createRange();
  range.selectNodeContents(node.querySelector(".katex-html") || node);
  return range.getBoundingClientRect().width;
}

// The widths of ``pieces`` typeset in the type of ``box``, in one layout out of sight;
// ``known`` keeps each piece's width once measured.
function widthsOf(pieces, box, known) {
  const fresh = [...new Set(pieces.filter((piece) => !known.has(piece)))];
  if (fresh.length) {
    const probe = document.createElement("div");
    probe.className = "probe";
    probe.innerHTML = fresh.map((piece) => `<div>${katexHtml(piece)}</div>`).join("");
    box.appendChild(probe);
    [...probe.children].forEach((node, k) => known.set(fresh[k], typesetWidth(node)));
    probe.remove();
  }
  return pieces.map((piece) => known.get(piece));
}

// The pieces of ``flat`` between its break points, each loosened until it fits ``budget``
// (or cannot be loosened further), with their widths.
function fittedPieces(flat, budget, box, known) {
  let pieces = piecesOf(flat, false).map((text) => ({ text, looser: 0 }));
  for (;;) {
    const widths = widthsOf(
      pieces.map((piece) => piece.text),
      box,
      known,
    );
    const next = [];
    pieces.forEach((piece, k) => {
      piece.width = widths[k];
      if (piece.width <= budget || piece.looser >= LOOSER.length) next.push(piece);
      else {
        LOOSER[piece.looser](piece.text).forEach((text, j) => {
          // a piece that starts with no operator continues a product broken between factors
          const factor = (j > 0 || piece.factor) && !/^\s*([+\-=]|\\text)/.test(text);
          next.push({ text, looser: piece.looser + 1, factor });
        });
      }
    });
    if (next.every((piece, k) => piece === pieces[k]) && next.length === pieces.length) {
      return pieces;
    }
    pieces = next;
  }
}

// ``pieces`` filled into lines, the first at most ``first`` wide, the others ``rest``, in a
// type of ``em`` px: a product broken between its factors goes on with a × and keeps its lines
// to itself; an operator between two pieces takes space that it does not take alone.
function filledLines(pieces, first, rest, em) {
  const lines = [];
  let line = "";
  let used = 0;
  let product = false; // whether this line goes on with a product
  for (const piece of pieces) {
    const budget = lines.length ? rest : first;
    if (line && (used + 0.56 * em + piece.width > budget || (product && !piece.factor))) {
      lines.push(line.trim());
      line = "";
      used = 0;
      product = false;
    }
    if (!line && piece.factor) {
      line = "\\quad\\times "; // indented past the terms of the sum
      used = 2 * em;
      product = true;
    }
    used += (line ? 0.56 * em : 0) + piece.width;
    line += piece.text;
  }
  lines.push(line.trim());
  const indent = lines[0].startsWith("\\text{") ? "" : "\\qquad "; // a sentence is not indented
  return lines.length === 1
    ? lines[0]
    : `\\begin{aligned}&${lines.join(`\\\\&${indent}`)}\\end{aligned}`;
}

// ``flat`` (LaTeX without alignment marks) typeset in ``part``, broken over lines to fit its
// width, then in a smaller type down to the page's text size; whether it fits.
function setInLines(part, flat, known) {
  part.style.fontSize = "";
  part.innerHTML = katexHtml(flat);
  const box = part.clientWidth - OVERHANG;
  let width = typesetWidth(part);
  const em = 1.21 * parseFloat(getComputedStyle(part).fontSize); // KaTeX's em, in px
  for (let budget = box, tries = 0; width > box + 0.5 && tries < 4; tries++) {
    // a measured line may come out wider than its pieces (the spacing around an operator)
    const pieces = fittedPieces(flat, budget - 2 * em, part, known);
    part.innerHTML = katexHtml(filledLines(pieces, budget, budget - 2 * em, em));
    const over = typesetWidth(part) - box;
    width = over + box;
    budget -= Math.max(over, 0.2 * em);
  }
  if (width > box + 0.5) part.style.fontSize = `${Math.max(SMALLEST_TYPE, box / width)}em`;
  return typesetWidth(part) <= box + 0.5;
}

// ---- a matrix equation A x = b too wide for its box
// ``flat`` as a matrix equation A x = b (A square, x a column of unknowns, b a column), or
// null: {A: rows of entries, x: entries, b: entries}.
function matrixSystem(flat) {
  const matrices = [];
  const glue = [];
  let from = 0;
  for (let start; (start = flat.indexOf("\\left[\\begin{", from)) >= 0; ) {
    const [, body, end] = environmentAt(flat, start + "\\left[".length);
    if (!flat.startsWith("\\right]", end)) return null;
    glue.push(flat.slice(from, start).trim());
    const rows = splitTopLevel(body, "\\\\");
    matrices.push(rows.map((row) => splitTopLevel(row, "&").map((entry) => entry.trim())));
    from = end + "\\right]".length;
  }
  glue.push(flat.slice(from).trim());
  if (matrices.length !== 3 || glue.join("|") !== "||=|") return null;
  const [A, x, b] = matrices;
  const n = A.length;
  const column = (m) => m.length === n && m.every((row) => row.length === 1);
  if (!A.every((row) => row.length === n) || !column(x) || !column(b)) return null;
  return { A, x: x.map(([e]) => e), b: b.map(([e]) => e) };
}

// The environment that opens at ``at`` ("\begin{matrix}" or "\begin{array}{…}"):
// [its name, its body, the index after its \end{…}].
function environmentAt(latex, at) {
  const [name, afterName] = braceGroup(latex, at + "\\begin".length);
  const bodyStart = latex[afterName] === "{" ? braceGroup(latex, afterName)[1] : afterName;
  let depth = 1;
  for (let i = bodyStart; i < latex.length; i++) {
    if (latex.startsWith("\\begin{", i)) depth += 1;
    else if (latex.startsWith("\\end{", i) && --depth === 0) {
      return [name, latex.slice(bodyStart, i), braceGroup(latex, i + "\\end".length)[1]];
    } else if (latex[i] === "\\") i += 1;
  }
  return [name, latex.slice(bodyStart), latex.length];
}

// The names of A and b: M q̈ = f when the unknowns are accelerations (the mass matrix and the
// forcing), A x = b otherwise (the system augmented with the constraints' multipliers).
function systemNames(system) {
  return system.x.every((e) => e.startsWith("\\ddot{")) ? ["M", "f", "\\ddot{q}"] : ["A", "b", "x"];
}

function columnLatex(rows) {
  const body = rows.map((row) => row.join(" & ")).join("\\\\");
  return `\\left[\\begin{matrix}${body}\\end{matrix}\\right]`;
}

// The system with the entries in ``named`` shown by name (an entry met twice, as in a symmetric
// matrix, keeps one name), then each name with its entry: [the equation, ...the entries].
function namedSystem(system, named) {
  const [A, b] = systemNames(system);
  const wide = system.A.length > 9; // M_{1,12}, not M_{112}
  const listed = new Map(); // an entry's letter and text -> its names
  const nameOf = (letter, entry, ...index) => {
    const key = `${letter} ${entry}`;
    const name = `${letter}_{${index.map((k) => k + 1).join(wide ? "," : "")}}`;
    if (!listed.has(key)) listed.set(key, { entry, names: [] });
    listed.get(key).names.push(name);
    return listed.get(key).names[0];
  };
  const matrix = system.A.map((row, i) =>
    row.map((entry, j) => (named.has(entry) ? nameOf(A, entry, i, j) : entry)),
  );
  const right = system.b.map((e, i) => [named.has(e) ? nameOf(b, e, i) : e]);
  const unknowns = columnLatex(system.x.map((entry) => [entry]));
  const equation = `${columnLatex(matrix)} ${unknowns} = ${columnLatex(right)}`;
  const entries = [...listed.values()].map(({ entry, names }) => `${names.join(" = ")} = ${entry}`);
  return [equation, ...entries];
}

// Each equation of the system, row by row: Σ_j A_ij x_j = b_i, its zero entries left out.
function systemRows(system) {
  const [A, b, x] = systemNames(system);
  const rows = system.A.map((row, i) => {
    const terms = [];
    row.forEach((entry, j) => {
      const unknown = system.x[j];
      if (entry === "0") return;
      if (entry === "1" || entry === "-1") terms.push(`${entry[0] === "-" ? "-" : "+"} ${unknown}`);
      else if (isSum(entry)) terms.push(`+ \\left(${entry}\\right) ${unknown}`);
      else if (entry.startsWith("- ")) terms.push(`${entry} ${unknown}`);
      else terms.push(`+ ${entry} ${unknown}`);
    });
    return `${terms.join(" ").replace(/^\+ /, "") || "0"} = ${system.b[i]}`;
  });
  return [`${A}\\,${x} = ${b}\\text{, row by row:}`, ...rows];
}

// The layout of a system too wide for ``item``: its long entries named, the fewest that let it
// fit (in the smallest type if it must), or null when even every one named does not fit.
function namedLayout(item, system, known) {
  const box = item.clientWidth - OVERHANG;
  const entries = [...new Set([...system.A.flat(), ...system.b])];
  const measured = widthsOf(entries, item, known);
  const widths = new Map(entries.map((e, k) => [e, measured[k]]));
  const longest = `${systemNames(system)[0]}_{${system.A.length > 9 ? "10,10" : "11"}}`;
  const [nameWidth] = widthsOf([longest], item, known);
  const shown = (named, e) => (named.has(e) ? nameWidth : widths.get(e));
  const worthNaming = entries.map((entry) => widths.get(entry)).filter((w) => w > nameWidth);
  const thresholds = [...new Set(worthNaming)].sort((u, v) => v - u);
  let last = null;
  for (const threshold of thresholds) {
    const named = new Set(entries.filter((e) => widths.get(e) >= threshold));
    // no narrower than its widest entry of each column: skip a layout that cannot fit
    const column = (j) => Math.max(...system.A.map((row) => shown(named, row[j])));
    const least = system.A[0].reduce((sum, _, j) => sum + column(j), 0);
    if (least + Math.max(...system.b.map((e) => shown(named, e))) > box / SMALLEST_TYPE) continue;
    const lines = namedSystem(system, named);
    const [width] = widthsOf([lines[0]], item, known);
    if (width <= box) return lines;
    if (width <= box / SMALLEST_TYPE) last = lines;
  }
  return last;
}

// ``lines`` set one under the other in ``item``, each fitted to its width; whether all fit.
function setParts(item, lines, known) {
  item.innerHTML = "";
  let fits = true;
  for (const line of lines) {
    const part = document.createElement("div");
    part.className = "part";
    item.appendChild(part);
    fits = setInLines(part, line, known) && fits;
  }
  return fits;
}

// A matrix equation: whole (broken at its = or in a smaller type if need be), else with its
// long entries named and listed beneath, else row by row.
function setSystem(item, flat, system, known) {
  if (flat.length < WHOLE_MATRIX && setInLines(item, flat, known)) return true;
  item.style.fontSize = "";
  return setParts(item, namedLayout(item, system, known) || systemRows(system), known);
}

function renderRow(item) {
  const row = item.dataset.latex;
  if (!window.katex) {
    item.textContent = row;
  } else {
    const flat = splitTopLevel(row, "&").join("");
    const known = new Map(); // the width of each piece once measured
    const system = matrixSystem(flat);
    const set = system ? setSystem(item, flat, system, known) : setInLines(item, flat, known);
    const fits = set && item.scrollWidth <= item.clientWidth;
    // the last resort: this row scrolls on its own, by keyboard too
    item.classList.toggle("wide", !fits);
    if (!fits) {
      item.tabIndex = 0;
      item.setAttribute("role", "group");
      item.setAttribute("aria-label", "a wide equation: scroll it sideways");
    } else {
      for (const name of ["tabindex", "role", "aria-label"]) item.removeAttribute(name);
    }
  }
  item.dataset.typeset = "true";
}

const observer =
  "IntersectionObserver" in window
    ? new IntersectionObserver(
        (entries) => {
          for (const entry of entries) {
            if (entry.isIntersecting) {
              observer.unobserve(entry.target);
              renderRow(entry.target);
            }
          }
        },
        { rootMargin: "400px" },
      )
    : null;

// A panel whose width changes (a phone turned, a window resized) sets its rows again, each
// as it comes into view.
const refit =
  "ResizeObserver" in window && observer
    ? new ResizeObserver((entries) => {
        for (const { target, contentRect } of entries) {
          const width = String(Math.round(contentRect.width));
          if (target.dataset.width && target.dataset.width !== width) {
            for (const item of target.querySelectorAll(".item[data-typeset]")) {
              delete item.dataset.typeset;
              observer.observe(item);
            }
          }
          target.dataset.width = width;
        }
      })
    : null;

function typeset(target, latex, version) {
  if (refit) refit.observe(target);
  target.innerHTML = "";
  target.dataset.version = version;
  target.classList.remove("stale");
  for (const row of latexRows(latex)) {
    const item = document.createElement("div");
    item.className = "item";
    item.dataset.latex = row;
    if (row.length > LARGE_ROW) {
      const show = document.createElement("button");
      show.type = "button";
      show.className = "show-large";
      show.textContent = `Show this equation (${Math.round(row.length / 1000)} kB of LaTeX)`;
      show.addEventListener("click", () => renderRow(item));
      item.appendChild(show);
    } else if (observer) {
      item.textContent = "…";
      observer.observe(item);
    } else {
      renderRow(item);
    }
    target.appendChild(item);
  }
}
