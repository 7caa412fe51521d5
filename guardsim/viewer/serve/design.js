// Draws design analyses (guardsim.viewer.serve.payload) on canvases: one for report and watch, two and
// their difference for diff. The live page takes each new analysis from server-sent events.
const PALETTE = JSON.parse(document.getElementById("palette").textContent);
const C = PALETTE.colours;

function bytes(text) {
  const binary = atob(text);
  const out = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) out[i] = binary.charCodeAt(i);
  return out;
}
function rgb(c) { return `rgb(${c[0]},${c[1]},${c[2]})`; }
function mix(a, b, t) { return [0, 1, 2].map((k) => Math.round(a[k] + t * (b[k] - a[k]))); }
function scaleOf(p) { return Math.max(2, Math.floor(Math.min(560 / p.shape[1], 560 / p.shape[0]))); }
function esc(text) { return String(text).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]); }
function world(p, point) { return `${point[0]},${point[1]}`; }

function drawCells(ctx, p, s, colour) {
  const [rows, cols] = p.shape;
  const image = ctx.createImageData(cols * s, rows * s);
  for (let r = 0; r < rows; r++) for (let c = 0; c < cols; c++) {
    const v = colour(r * cols + c);
    for (let y = 0; y < s; y++) {
      let o = ((r * s + y) * cols * s + c * s) * 4;
      for (let x = 0; x < s; x++, o += 4) { image.data[o] = v[0]; image.data[o + 1] = v[1]; image.data[o + 2] = v[2]; image.data[o + 3] = 255; }
    }
  }
  ctx.putImageData(image, 0, 0);
}

function layer() {
  const choice = document.getElementById("layer");
  return choice ? choice.value : "exposure";
}

function drawAnalysis(canvas, p) {
  const s = scaleOf(p), [rows, cols] = p.shape;
  canvas.width = cols * s; canvas.height = rows * s;
  canvas.dataset.scale = s;
  const ctx = canvas.getContext("2d");
  const kinds = bytes(p.kinds), exposure = bytes(p.exposure);
  const hot = [214, 40, 40], safe = [150, 214, 160];
  if (layer() === "idleness") {
    // Each cell's worst gap (ticks unwatched in a row) over the lap: dark blue the longest; never watched, safe green.
    const gap = new Int32Array(bytes(p.worst_gap).buffer);
    drawCells(ctx, p, s, (i) => kinds[i] === 0 ? C.wall : kinds[i] === 2 ? C.unreachable
      : gap[i] < 0 ? safe : mix(C.free, C.unseen, gap[i] / p.period));
  } else {
    drawCells(ctx, p, s, (i) => kinds[i] === 0 ? C.wall : kinds[i] === 2 ? C.unreachable
      : exposure[i] === 0 ? safe : mix(C.free, hot, exposure[i] / 100));
  }
  const centre = (cell) => [(cell[0] + 0.5) * s, (cell[1] + 0.5) * s];
  const line = (cells, colour, width) => {
    if (cells.length < 2) return;
    ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.beginPath();
    cells.forEach((cell, k) => { const [x, y] = centre(cell); if (k) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke();
  };
  p.routes.forEach((route, g) => {
    const colour = g === 0 ? C.guard : PALETTE.guards[(g - 1) % PALETTE.guards.length];
    line(route, rgb(colour), Math.max(1, s / 3));
    if (route.length) {
      // The start of the lap: the guard's colour, outlined so that it shows on watched (red) floor.
      const [x, y] = centre(route[0]);
      ctx.fillStyle = rgb(colour); ctx.fillRect(x - s / 2, y - s / 2, s, s);
      ctx.strokeStyle = rgb(C.outline); ctx.lineWidth = Math.max(1, s / 6); ctx.strokeRect(x - s / 2, y - s / 2, s, s);
    }
  });
  const toCell = (point) => [Math.floor((point[0] - p.origin[0]) / p.cell_size), Math.floor((point[1] - p.origin[1]) / p.cell_size)];
  for (const pair of p.pairs) {
    const found = pair.outcome === "unseen" || pair.outcome === "undetected";
    if (pair.path) line(pair.path, found ? "rgb(40,90,220)" : "rgb(240,140,20)", Math.max(1, s / 2));
    ctx.fillStyle = "rgb(24,26,32)";
    for (const spot of pair.hiding || []) { const [x, y] = centre(spot); ctx.fillRect(x - s / 3, y - s / 3, (2 * s) / 3, (2 * s) / 3); }
    for (const [point, round] of [[pair.from, true], [pair.to, false]]) {
      const [x, y] = centre(toCell(point));
      ctx.fillStyle = "rgb(40,90,220)"; ctx.beginPath();
      if (round) ctx.arc(x, y, 1.5 * s, 0, 2 * Math.PI); else ctx.rect(x - 1.5 * s, y - 1.5 * s, 3 * s, 3 * s);
      ctx.fill();
    }
  }
}

function drawDifference(canvas, a, b) {
  // Exposure after minus before: red where the edit watches more, blue where less; cells added green,
  // removed purple; safe spots lost yellow, gained teal (the grids must match in shape).
  const s = scaleOf(b), [rows, cols] = b.shape;
  canvas.width = cols * s; canvas.height = rows * s;
  const ctx = canvas.getContext("2d");
  const ka = bytes(a.kinds), kb = bytes(b.kinds), ea = bytes(a.exposure), eb = bytes(b.exposure);
  // The same colours, in the same order, as the diff picture (guardsim.render.diff).
  const safeA = (i) => ka[i] === 1 && ea[i] === 0, safeB = (i) => kb[i] === 1 && eb[i] === 0;
  drawCells(ctx, b, s, (i) => {
    if (safeB(i) && !safeA(i)) return [0, 150, 150];
    if (safeA(i) && !safeB(i)) return [255, 196, 40];
    if (ka[i] === 0 && kb[i] === 0) return C.wall;
    if (ka[i] === 0) return [60, 170, 80];
    if (kb[i] === 0) return [140, 84, 162];
    const d = (eb[i] - ea[i]) / 100;
    return d >= 0 ? mix(C.free, [214, 40, 40], Math.min(1, 3 * d)) : mix(C.free, [40, 90, 220], Math.min(1, -3 * d));
  });
}

function reportHtml(p) {
  const r = p.report;
  if (!r) return "";
  const pending = r.provisional ? " (counting the ways through)" : "";
  let h = `<h2>Difficulty <span id="score">${r.score}</span>/100${pending}</h2><p id="formula"><code>${esc(r.formula)}</code></p>`;
  h += "<table><tr><th>part</th><th>weight</th><th>value (0 easy, 1 hard)</th><th>source</th></tr>";
  for (const [name, value] of Object.entries(r.parts)) h += `<tr><td>${name}</td><td>${r.weights[name]}</td><td>${value.toFixed(3)}</td><td>${esc((r.sources || {})[name] || "")}</td></tr>`;
  h += "</table><table><tr><th>from</th><th>to</th><th>outcome</th><th>ticks</th><th>slack</th><th>straight walk</th><th>peak awareness</th><th>path-distance risk</th><th>ways</th></tr>";
  for (const q of r.pairs) {
    const f = (v) => (v === null || v === undefined ? "-" : typeof v === "number" && !Number.isInteger(v) ? v.toFixed(2) : v);
    h += `<tr><td>${world(p, q.from)}</td><td>${world(p, q.to)}</td><td class="outcome">${q.outcome}</td><td>${f(q.ticks)}</td><td>${q.slack}/${q.period}</td><td>${q.direct}/${q.period}</td><td>${f(q.peak_awareness)}</td><td>${f(q.path_distance_risk)}</td><td>${q.ways === null ? "counting" : q.ways}</td></tr>`;
  }
  h += "</table><table><tr><th>guard</th><th>loop (moves)</th><th>cells</th><th>turns</th><th>backtracks</th></tr>";
  r.guards.forEach((g, k) => { h += `<tr><td>${k}</td><td>${g.loop_length}</td><td>${g.cells}</td><td>${g.turns}</td><td>${g.backtracks}</td></tr>`; });
  h += `</table><p>floor never watched: ${(100 * r.never_watched).toFixed(1)}%; worst idleness ${r.worst_idleness ?? "never watched"} ticks, mean ${r.mean_idleness ?? "-"}`;
  if (r.capture_rate !== null) h += `; capture rate ${r.capture_rate.toFixed(2)} of ${r.alert_episodes} alert episodes`;
  return h + "</p>";
}

function figure(caption, id) {
  const fig = document.createElement("figure");
  fig.innerHTML = `<figcaption>${esc(caption)}</figcaption><canvas id="${id}"></canvas>`;
  document.getElementById("views").appendChild(fig);
  return fig.querySelector("canvas");
}

function show(payloads, diff) {
  shown = [payloads, diff];
  document.getElementById("views").innerHTML = "";
  if (payloads.length === 2) {
    drawAnalysis(figure("before: " + payloads[0].level, "before"), payloads[0]);
    drawAnalysis(figure("after: " + payloads[1].level, "after"), payloads[1]);
    if (payloads[0].shape.join() === payloads[1].shape.join()) drawDifference(figure("difference", "difference"), payloads[0], payloads[1]);
    document.getElementById("report").innerHTML = diff ? diff : "";
    return;
  }
  const p = payloads[0];
  drawAnalysis(figure(`${p.level} (patrol: ${p.patrol})`, "level"), p);
  document.getElementById("report").innerHTML = reportHtml(p);
}

let shown = null;
document.getElementById("layer").addEventListener("change", () => { if (shown) show(...shown); });
function showLive(p) {
  show([p], null);
  const reused = p.reused.length ? `, reused ${p.reused.join(" and ")}` : "";
  const status = document.getElementById("status");
  status.textContent = `analysis ${p.number} of ${p.file}: took ${p.seconds.toFixed(2)} s${reused}`;
  status.dataset.number = p.number;
  status.dataset.phase = p.phase;
  document.getElementById("warnings").textContent = p.warnings.map((w) => `warning: ${w}`).join("\n");
  // When this analysis was drawn (ms since the epoch): the latency benchmark reads it.
  status.dataset.shownAt = Date.now();
}

if (LIVE) {
  const events = new EventSource("events");
  events.addEventListener("analysis", (e) => { showLive(JSON.parse(e.data)); document.getElementById("error").textContent = ""; });
  events.addEventListener("failure", (e) => {
    const f = JSON.parse(e.data);
    const error = document.getElementById("error");
    error.textContent = f.message;
    error.dataset.number = f.number;
  });
} else {
  const diffData = JSON.parse(document.getElementById("diff-data").textContent);
  show(JSON.parse(document.getElementById("payloads").textContent), diffData);
}
