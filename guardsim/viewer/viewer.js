// guardsim episode viewer: draws any tick of a trace on a canvas. Inlined into the page by
// guardsim/viewer/page.py; reads its data from the JSON block #trace-data. No network access.
"use strict";
(function () {
  const errors = document.getElementById("errors");
  function report(message) {
    errors.textContent += message + "\n";
  }
  window.addEventListener("error", (event) => report("error: " + event.message + " (line " + event.lineno + ")"));
  window.addEventListener("unhandledrejection", (event) => report("error: " + event.reason));

  // The trail fades like the GIF's: in blocks of ticks, newest strong, oldest faint.
  const TRAIL_BLOCKS = 24;
  const TRAIL_AGES = [1, 2, 4, 8];
  const TRAIL_ALPHAS = [1.0, 0.72, 0.5, 0.34, 0.22];
  const CONE_ALPHA = 0.42;
  // Over a viridis heat map the GIF's yellow tint vanishes on its yellow end and browns its purple: the
  // cones become a white wash (no viridis colour is near white) with an edge cased in the outline colour.
  const CONE_WASH = "#ffffff";
  const CONE_WASH_ALPHA = 0.5;
  const ARC_STEP_DEGREES = 2.0;
  const VERTEX_NUDGE = 1e-4;
  const MIN_GUARD_RADIUS = 7;

  function decode(text, Type) {
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function rgb(hex) {
    return [parseInt(hex.slice(1, 3), 16), parseInt(hex.slice(3, 5), 16), parseInt(hex.slice(5, 7), 16)];
  }

  function ramp(stops, f) {
    f = Math.min(1, Math.max(0, f));
    for (let i = 1; i < stops.length; i++) {
      if (f <= stops[i][0]) {
        const [f0, c0] = stops[i - 1];
        const [f1, c1] = stops[i];
        const t = f1 > f0 ? (f - f0) / (f1 - f0) : 0;
        return [0, 1, 2].map((k) => Math.round(c0[k] + t * (c1[k] - c0[k])));
      }
    }
    return stops[stops.length - 1][1];
  }
  const FIELD = [[0, [225, 238, 255]], [1, [16, 52, 150]]];

  function parseHash() {
    const result = {};
    for (const part of location.hash.replace(/^#/, "").split("&")) {
      const [key, value] = part.split("=");
      if (key) result[decodeURIComponent(key)] = decodeURIComponent(value || "");
    }
    return result;
  }

  // Segments of the wall rings, bucketed on a coarse grid so a cone only tests the walls near it.
  function WallIndex(rings, bucket) {
    this.bucket = bucket;
    this.segments = [];
    this.buckets = new Map();
    for (const ring of rings) {
      for (let i = 0; i < ring.length; i++) {
        const a = ring[i];
        const b = ring[(i + 1) % ring.length];
        const index = this.segments.length;
        this.segments.push([a[0], a[1], b[0], b[1]]);
        const i0 = Math.floor(Math.min(a[0], b[0]) / bucket), i1 = Math.floor(Math.max(a[0], b[0]) / bucket);
        const j0 = Math.floor(Math.min(a[1], b[1]) / bucket), j1 = Math.floor(Math.max(a[1], b[1]) / bucket);
        for (let i2 = i0; i2 <= i1; i2++) {
          for (let j2 = j0; j2 <= j1; j2++) {
            const key = i2 + "," + j2;
            if (!this.buckets.has(key)) this.buckets.set(key, []);
            this.buckets.get(key).push(index);
          }
        }
      }
    }
    this.stamp = new Int32Array(this.segments.length);
    this.query = 0;
  }
  WallIndex.prototype.near = function (x0, y0, x1, y1) {
    this.query += 1;
    const found = [];
    const b = this.bucket;
    for (let i = Math.floor(x0 / b); i <= Math.floor(x1 / b); i++) {
      for (let j = Math.floor(y0 / b); j <= Math.floor(y1 / b); j++) {
        const list = this.buckets.get(i + "," + j);
        if (!list) continue;
        for (const index of list) {
          if (this.stamp[index] !== this.query) {
            this.stamp[index] = this.query;
            found.push(this.segments[index]);
          }
        }
      }
    }
    return found;
  };

  // The visibility polygon of guardsim/render/sight.py: even rays over the wedge plus a pair of rays
  // either side of every wall vertex in range, each stopped by the first wall it meets.
  function visibility(walls, eye, headingDegrees, fov, range) {
    const full = fov >= 360;
    const half = full ? Math.PI : (fov * Math.PI) / 360;
    const centre = (headingDegrees * Math.PI) / 180;
    const steps = Math.max(2, Math.ceil((2 * half * 180) / Math.PI / ARC_STEP_DEGREES));
    const offsets = [];
    for (let k = 0; k < steps + (full ? 0 : 1); k++) offsets.push(-half + (2 * half * k) / steps);
    const near = walls.near(eye[0] - range, eye[1] - range, eye[0] + range, eye[1] + range);
    for (const s of near) {
      for (const [vx, vy] of [[s[0], s[1]], [s[2], s[3]]]) {
        const dx = vx - eye[0], dy = vy - eye[1];
        const distance = Math.hypot(dx, dy);
        if (distance <= 0 || distance > range) continue;
        let angle = Math.atan2(dy, dx) - centre;
        angle = ((((angle + Math.PI) % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI)) - Math.PI;
        for (const a of [angle - VERTEX_NUDGE, angle + VERTEX_NUDGE]) {
          if (full || Math.abs(a) < half) offsets.push(a);
        }
      }
    }
    offsets.sort((a, b) => a - b);
    const ring = full ? [] : [eye];
    for (const offset of offsets) {
      const angle = centre + offset;
      const rx = range * Math.cos(angle), ry = range * Math.sin(angle);
      let best = 1;
      for (const s of near) {
        const sx = s[2] - s[0], sy = s[3] - s[1];
        const denominator = rx * sy - ry * sx;
        if (Math.abs(denominator) < 1e-12) continue;
        const qx = s[0] - eye[0], qy = s[1] - eye[1];
        const t = (qx * sy - qy * sx) / denominator;
        const u = (qx * ry - qy * rx) / denominator;
        if (t >= 0 && t < best && u >= 0 && u <= 1) best = t;
      }
      ring.push([eye[0] + best * rx, eye[1] + best * ry]);
    }
    return ring;
  }

  function main() {
    const data = JSON.parse(document.getElementById("trace-data").textContent);
    const rows = data.rows, cols = data.cols, steps = data.steps;
    const firstSeen = decode(data.first_seen, Int32Array);
    const kinds = decode(data.kinds, Uint8Array);
    const paths = data.paths.map((text) => decode(text, Int32Array));
    const headings = data.headings.map((text) => decode(text, Uint8Array));
    const guards = paths.length;
    const poses = data.poses ? decode(data.poses, Float32Array) : null;
    // A team in continuous motion: every guard's [x, y, heading_degrees] per tick.
    const guardPoses = data.guard_poses ? data.guard_poses.map((text) => decode(text, Float32Array)) : null;
    const colours = data.colours;
    const field = data.field
      ? { ticks: data.field.ticks, max: data.field.max, values: decode(data.field.data, Float32Array) }
      : null;

    document.getElementById("title").textContent =
      data.level + " \u2014 " + data.planner + ", " + guards + (guards > 1 ? " guards" : " guard");
    const readout = document.getElementById("tick-readout");
    const status = document.getElementById("status");
    const timeline = document.getElementById("timeline");
    const playButton = document.getElementById("play");
    const speed = document.getElementById("speed");
    const canvas = document.getElementById("map");
    const context = canvas.getContext("2d");
    timeline.max = String(steps);
    if (field) document.getElementById("field-toggle").hidden = false;
    // Continuous motion: say which speed is game time (a physics tick is 1 / tick_hz s).
    if (data.tick_hz) {
      for (const option of speed.options) {
        const times = Number(option.value) / data.tick_hz;
        option.textContent += times === 1 ? " (real time)" : " (\u00d7" + (Math.round(times * 100) / 100) + ")";
      }
    }

    const hash = parseHash();
    const layers = {};
    for (const box of document.querySelectorAll("#layers input[data-layer]")) {
      layers[box.dataset.layer] = box.checked;
    }
    const chosen = hash.layers !== undefined ? hash.layers : data.default_layers ? data.default_layers.join(",") : undefined;
    if (chosen !== undefined) {
      const wanted = new Set(chosen.split(",").filter(Boolean));
      for (const name of Object.keys(layers)) layers[name] = wanted.has(name);
      for (const box of document.querySelectorAll("#layers input[data-layer]")) box.checked = layers[box.dataset.layer];
    }

    const bar = {
      box: document.getElementById("colour-bar"),
      label: document.getElementById("bar-label"),
      max: document.getElementById("bar-max"),
      unit: document.getElementById("bar-unit"),
      canvas: document.getElementById("bar"),
    };
    if (data.idleness || data.laps || data.exposure || data.detection_time) bar.box.hidden = false;

    // Whole pixels per cell, so every cell is a solid block of one colour.
    const stage = document.getElementById("stage");
    const roomX = Math.max(200, window.innerWidth - 20);
    const roomY = Math.max(200, window.innerHeight - stage.getBoundingClientRect().top - 14);
    const scale = hash.scale ? Math.max(1, parseInt(hash.scale, 10)) : Math.max(1, Math.floor(Math.min(roomX / cols, roomY / rows)));
    canvas.width = cols * scale;
    canvas.height = rows * scale;
    const perUnit = scale / data.cell_size;
    const ox = data.origin[0], oy = data.origin[1];
    const px = (x) => (x - ox) * perUnit;
    const py = (y) => (y - oy) * perUnit;

    const floor = new Path2D();
    for (const ring of data.rings) {
      ring.forEach((p, i) => (i === 0 ? floor.moveTo(px(p[0]), py(p[1])) : floor.lineTo(px(p[0]), py(p[1]))));
      floor.closePath();
    }
    const walls = new WallIndex(data.rings, Math.max(data.cell_size * 8, data.view_range / 2));
    // The floor's edges, without the cuts that open enclosing walls (holes touching along a line).
    const outline = new Path2D();
    for (const ring of data.outline || data.rings) {
      ring.forEach((p, i) => (i === 0 ? outline.moveTo(px(p[0]), py(p[1])) : outline.lineTo(px(p[0]), py(p[1]))));
      outline.closePath();
    }

    const cellImage = (fill) => {
      const off = document.createElement("canvas");
      off.width = cols;
      off.height = rows;
      const offContext = off.getContext("2d");
      const image = offContext.createImageData(cols, rows);
      fill(image.data);
      offContext.putImageData(image, 0, 0);
      return off;
    };
    const unseen = rgb(colours.unseen), unreachable = rgb(colours.unreachable), tight = rgb(colours.tight);
    // The palette's heat ramp, as the GIF and the PNG draw it (guardsim.render.palette.HEAT_RAMP).
    const HEAT = data.heat_ramp;
    const coverageAt = (tick) =>
      cellImage((pixels) => {
        for (let i = 0; i < kinds.length; i++) {
          let colour = null;
          if (kinds[i] === 1 && (firstSeen[i] < 0 || firstSeen[i] > tick)) colour = unseen;
          else if (kinds[i] === 2) colour = unreachable;
          else if (kinds[i] === 3) colour = tight;
          if (colour) {
            pixels[4 * i] = colour[0];
            pixels[4 * i + 1] = colour[1];
            pixels[4 * i + 2] = colour[2];
            pixels[4 * i + 3] = 255;
          }
        }
      });
    const heatAt = (tick) =>
      cellImage((pixels) => {
        for (let i = 0; i < kinds.length; i++) {
          const seen = firstSeen[i];
          if (kinds[i] !== 1 || seen < 0 || seen > tick) continue;
          const colour = ramp(HEAT, steps ? seen / steps : 0);
          pixels.set([colour[0], colour[1], colour[2], 255], 4 * i);
        }
      });
    const fieldAt = (tick) => {
      let k = 0;
      while (k + 1 < field.ticks.length && field.ticks[k + 1] <= tick) k++;
      const base = k * rows * cols;
      return cellImage((pixels) => {
        for (let i = 0; i < rows * cols; i++) {
          const value = field.values[base + i];
          if (!(value >= 0)) continue;
          const colour = ramp(FIELD, field.max ? value / field.max : 0);
          pixels.set([colour[0], colour[1], colour[2], 255], 4 * i);
        }
      });
    };

    const centre = (cell) => [((cell % cols) + 0.5) * scale, (Math.floor(cell / cols) + 0.5) * scale];
    // A guard's world position and facing (degrees): the recorded pose under continuous motion, else
    // its cell's centre and heading.
    const pose = (guard, tick) => {
      if (guardPoses) {
        const own = guardPoses[guard];
        return [[own[3 * tick], own[3 * tick + 1]], own[3 * tick + 2]];
      }
      if (poses && guard === 0) return [[poses[3 * tick], poses[3 * tick + 1]], poses[3 * tick + 2]];
      const cell = paths[guard][tick];
      return [[ox + ((cell % cols) + 0.5) * data.cell_size, oy + (Math.floor(cell / cols) + 0.5) * data.cell_size], 90 * headings[guard][tick]];
    };
    // Where a guard's trail passes at a tick, in canvas pixels: through its poses when it has them.
    const trailPoint = (guard, tick) => {
      if (guardPoses) return [px(guardPoses[guard][3 * tick]), py(guardPoses[guard][3 * tick + 1])];
      return poses && guard === 0 ? [px(poses[3 * tick]), py(poses[3 * tick + 1])] : centre(paths[guard][tick]);
    };
    const block = Math.max(1, Math.ceil(steps / TRAIL_BLOCKS));
    const trailLevel = (walked, tick) => {
      const age = Math.floor(tick / block) - Math.floor(walked / block);
      let level = 0;
      while (level < TRAIL_AGES.length && age >= TRAIL_AGES[level]) level++;
      return level;
    };

    function drawTrail(guard, tick) {
      context.strokeStyle = data.guard_colours[guard];
      context.lineWidth = Math.max(1.5, scale / 3);
      context.lineJoin = "round";
      context.lineCap = "round";
      let step = 1;
      while (step <= tick) {
        const level = trailLevel(step, tick);
        context.globalAlpha = TRAIL_ALPHAS[level];
        context.beginPath();
        const [x0, y0] = trailPoint(guard, step - 1);
        context.moveTo(x0, y0);
        while (step <= tick && trailLevel(step, tick) === level) {
          const [x, y] = trailPoint(guard, step);
          context.lineTo(x, y);
          step++;
        }
        context.stroke();
      }
      context.globalAlpha = 1;
    }

    function drawGuard(x, y, facing, radius, colour) {
      const angle = (Math.PI / 180) * facing;
      const dx = Math.cos(angle), dy = Math.sin(angle);
      context.fillStyle = colour;
      context.strokeStyle = colours.outline;
      context.lineWidth = 1;
      context.beginPath();
      context.moveTo(x + dx * radius * 1.9, y + dy * radius * 1.9);
      context.lineTo(x - dy * radius * 0.85, y + dx * radius * 0.85);
      context.lineTo(x + dy * radius * 0.85, y - dx * radius * 0.85);
      context.closePath();
      context.fill();
      context.stroke();
      context.beginPath();
      context.arc(x, y, radius, 0, 2 * Math.PI);
      context.fill();
      context.stroke();
      context.fillStyle = "#ffffff";
      context.beginPath();
      context.arc(x + dx * radius * 0.35, y + dy * radius * 0.35, 1.5, 0, 2 * Math.PI);
      context.fill();
    }

    const extra =
      typeof GuardsimLayers !== "undefined" &&
      (data.laps || data.idleness || data.routes || data.intruder || data.exposure || data.detection_time || data.safe || data.alert || data.watch)
        ? GuardsimLayers.make({ data, context, scale, px, py, decode, ramp, cellImage, centre, kinds })
        : null;
    const total = extra ? extra.total(steps, hash.laps) : steps;
    const local = (value) => (extra ? extra.local(value, steps) : value);
    timeline.max = String(total);
    if (extra) {
      for (const name of extra.present) document.querySelector('[data-layer="' + name + '"]').parentElement.hidden = false;
      for (const heat of extra.heats) document.getElementById(heat.name + "-name").textContent = heat.info.label;
      extra.paintBar(bar.canvas);
      const list = document.getElementById("timeline-marks");
      for (const mark of extra.marks(total)) {
        const option = document.createElement("option");
        option.value = String(mark);
        // The peak awareness and the detection are named (option text, which the slider does not show).
        const label = extra.markLabel(mark);
        if (label) option.textContent = label;
        list.append(option);
      }
    }
    const intruderReadout = document.getElementById("intruder-readout");
    const intruderState = document.getElementById("intruder-state");
    const cellReadout = document.getElementById("cell-readout");
    const alertReadout = document.getElementById("alert-readout");
    // The cell whose idleness is read out: under the pointer, or from the address (#cell=COL,ROW).
    let inspected = null;
    if (extra && hash.cell) {
      const [col, row] = hash.cell.split(",").map((v) => parseInt(v, 10));
      if (col >= 0 && col < cols && row >= 0 && row < rows) inspected = [col, row];
    }

    let tick = 0;
    function draw() {
      const now = local(tick);
      context.imageSmoothingEnabled = false;
      context.fillStyle = colours.wall;
      context.fillRect(0, 0, canvas.width, canvas.height);
      context.fillStyle = colours.free;
      context.fill(floor, "evenodd");
      context.save();
      context.clip(floor, "evenodd");
      if (layers.coverage) context.drawImage(coverageAt(now), 0, 0, canvas.width, canvas.height);
      if (layers.heat) context.drawImage(heatAt(now), 0, 0, canvas.width, canvas.height);
      if (layers.field && field) context.drawImage(fieldAt(now), 0, 0, canvas.width, canvas.height);
      if (extra) extra.drawUnder(tick, layers, canvas);
      const cones = [];
      const overHeat = extra ? extra.heatShown(layers) : false;
      if (layers.cone) {
        for (let guard = 0; guard < guards; guard++) {
          const [eye, facing] = pose(guard, now);
          const ring = visibility(walls, eye, facing, data.fov_degrees, data.view_range);
          const shape = new Path2D();
          ring.forEach((p, i) => (i === 0 ? shape.moveTo(px(p[0]), py(p[1])) : shape.lineTo(px(p[0]), py(p[1]))));
          shape.closePath();
          context.globalAlpha = overHeat ? CONE_WASH_ALPHA : CONE_ALPHA;
          context.fillStyle = overHeat ? CONE_WASH : colours.cone;
          context.fill(shape);
          context.globalAlpha = 1;
          cones.push(shape);
        }
      }
      context.restore();
      context.strokeStyle = colours.outline;
      context.lineWidth = 2;
      context.stroke(outline);
      cones.forEach((shape, guard) => {
        if (overHeat) {
          context.strokeStyle = colours.outline;
          context.lineWidth = 4;
          context.stroke(shape);
        }
        context.strokeStyle = data.guard_colours[guard];
        context.lineWidth = overHeat ? 2 : 1;
        context.stroke(shape);
      });
      if (layers.trail) for (let guard = 0; guard < guards; guard++) drawTrail(guard, now);
      const radius = Math.max(MIN_GUARD_RADIUS, 0.45 * scale);
      for (let guard = 0; guard < guards; guard++) {
        const [x, y] = trailPoint(guard, 0);
        const half = Math.max(radius + 2, 0.5 * scale);
        context.strokeStyle = data.guard_colours[guard];
        context.lineWidth = 2;
        context.strokeRect(x - half, y - half, 2 * half, 2 * half);
      }
      // Guards in one place are spread round it so that each stays visible.
      const sharing = new Map();
      const spots = [];
      for (let guard = 0; guard < guards; guard++) {
        const [point, facing] = pose(guard, now);
        const key = point[0] + "," + point[1];
        if (!sharing.has(key)) sharing.set(key, { point: point, team: [] });
        sharing.get(key).team.push([guard, facing]);
      }
      for (const { point, team } of sharing.values()) {
        const cx = px(point[0]), cy = py(point[1]);
        team.forEach(([guard, facing], place) => {
          const angle = (2 * Math.PI * place) / team.length - Math.PI / 2;
          const spread = team.length > 1 ? 0.9 * radius : 0;
          spots[guard] = [cx + spread * Math.cos(angle), cy + spread * Math.sin(angle)];
          drawGuard(spots[guard][0], spots[guard][1], facing, radius, data.guard_colours[guard]);
        });
      }
      if (extra) extra.drawOver(tick, layers, radius, spots);
      const clock = data.tick_hz ? " (" + (tick / data.tick_hz).toFixed(1) + " s)" : "";
      const lap = extra ? extra.describe(tick, total) : null;
      readout.textContent =
        "tick " + tick + " / " + total + clock + (lap ? " \u00b7 " + lap : "") + " \u00b7 " +
        data.unseen_text[now] + (lap ? "% unseen this lap" : "% unseen");
      if (extra) {
        intruderReadout.textContent = extra.intruderText(tick);
        const state = extra.intruderState(tick);
        intruderState.hidden = !state;
        if (state) {
          const [r, g, b] = state.colour;
          intruderState.textContent = state.text;
          intruderState.dataset.state = state.name;
          intruderState.style.background = "rgb(" + r + "," + g + "," + b + ")";
          intruderState.style.color = 0.299 * r + 0.587 * g + 0.114 * b > 150 ? "#000000" : "#ffffff";
        }
        const alert = extra.alertState(tick);
        if (alert) {
          // What the alert layers draw at this tick, also as attributes (a test reads them back).
          alertReadout.hidden = false;
          alertReadout.textContent = alert.text;
          alertReadout.dataset.states = alert.states;
          alertReadout.dataset.intruder = alert.intruder;
          alertReadout.dataset.lastKnown = alert.lastKnown;
          alertReadout.dataset.contaminated = alert.contaminated;
          alertReadout.dataset.heard = alert.heard;
          alertReadout.dataset.noises = alert.noises;
        }
        cellReadout.textContent = inspected
          ? GuardsimLayers.worldPoint(data, inspected[0], inspected[1]) + " (cell [" + inspected[0] + ", " + inspected[1] + "]): " +
            extra.cellText(inspected[1] * cols + inspected[0], tick)
          : "";
        extra.colourBar(layers, bar);
      }
    }

    function setTick(value, updateHash) {
      const next = Math.max(0, Math.min(total, Math.round(Number(value)) || 0));
      tick = next;
      timeline.value = String(next);
      draw();
      if (updateHash) {
        const params = parseHash();
        params.tick = String(next);
        const text = Object.entries(params).map(([k, v]) => k + "=" + v).join("&");
        try {
          history.replaceState(null, "", "#" + text);
        } catch (error) {
          // Some browsers refuse history changes on file:// pages; the tick still changes.
        }
      }
    }

    // Playback runs on timers, not animation frames, so it also advances in a headless browser.
    let playing = false, last = 0, carry = 0;
    function frame() {
      if (!playing) return;
      const now = performance.now();
      carry += ((now - last) / 1000) * Number(speed.value);
      last = now;
      const advance = Math.floor(carry);
      if (advance > 0) {
        carry -= advance;
        setTick(Math.min(total, tick + advance), false);
      }
      if (tick >= total) {
        setPlaying(false);
        setTick(total, true);
        return;
      }
      setTimeout(frame, 16);
    }
    function setPlaying(on) {
      playing = on;
      playButton.textContent = on ? "Pause" : "Play";
      if (on) {
        if (tick >= total) setTick(0, false);
        last = performance.now();
        carry = 0;
        setTimeout(frame, 16);
      }
    }

    playButton.addEventListener("click", () => setPlaying(!playing));
    if (extra) {
      canvas.addEventListener("mousemove", (event) => {
        const box = canvas.getBoundingClientRect();
        const col = Math.floor((event.clientX - box.left) / scale), row = Math.floor((event.clientY - box.top) / scale);
        inspected = col >= 0 && col < cols && row >= 0 && row < rows ? [col, row] : null;
        if (!playing) draw();
      });
    }
    timeline.addEventListener("input", () => setTick(timeline.value, true));
    for (const box of document.querySelectorAll("#layers input[data-layer]")) {
      box.addEventListener("change", () => {
        layers[box.dataset.layer] = box.checked;
        draw();
      });
    }
    document.addEventListener("keydown", (event) => {
      if (event.target instanceof HTMLSelectElement) return;
      const jump = event.shiftKey ? 10 : 1;
      if (event.key === "ArrowRight") setTick(tick + jump, true);
      else if (event.key === "ArrowLeft") setTick(tick - jump, true);
      else if (event.key === "Home") setTick(0, true);
      else if (event.key === "End") setTick(total, true);
      else if (event.key === " ") setPlaying(!playing);
      else return;
      event.preventDefault();
    });
    window.addEventListener("hashchange", () => {
      const wanted = parseHash().tick;
      if (wanted !== undefined && Number(wanted) !== tick) setTick(wanted, false);
    });

    const legend = document.getElementById("legend");
    const items = [
      [colours.wall, "wall"], [colours.unseen, "unseen"], [colours.free, "seen"],
      ...(data.unreachable ? [[colours.unreachable, data.unreachable + " unreachable cells (not counted)"]] : []),
      [colours.cone, "sees now"],
      ...(data.tight ? [[colours.tight, data.tight + " cells too tight to stand in"]] : []),
      [
        "linear-gradient(90deg," + data.heat_ramp.map(([f, c]) => "rgb(" + c.join(",") + ") " + Math.round(100 * f) + "%").join(",") + ")",
        "first seen: early \u2192 late",
      ],
      ...data.guard_colours.map((colour, guard) => [
        colour,
        (guards > 1 ? "guard " + (guard + 1) : "guard (square: start)") + (data.routes ? ", solid: its trail" : ""),
      ]),
      ...(extra ? extra.legend() : []),
    ];
    for (const [colour, label] of items) {
      const item = document.createElement("span");
      const swatch = document.createElement("span");
      swatch.className = "swatch";
      swatch.style.background = colour;
      item.append(swatch, label);
      legend.append(item);
    }

    setTick(hash.tick !== undefined ? hash.tick : 0, false);
    if (hash.speed !== undefined) {
      const wanted = [...speed.options].find((option) => option.value === hash.speed);
      if (wanted) speed.value = wanted.value;
    }
    const box = canvas.getBoundingClientRect();
    const geometry = document.getElementById("canvas-geometry");
    geometry.dataset.left = String(Math.round(box.left + window.scrollX));
    geometry.dataset.top = String(Math.round(box.top + window.scrollY));
    geometry.dataset.scale = String(scale);
    if (extra) {
      const barBox = bar.canvas.getBoundingClientRect();
      geometry.dataset.barLeft = String(Math.round(barBox.left + window.scrollX));
      geometry.dataset.barTop = String(Math.round(barBox.top + window.scrollY));
    }
    status.textContent = "ready";
    if (hash.play === "1") setPlaying(true);
  }

  try {
    main();
  } catch (error) {
    report("error: " + ((error && error.stack) || error));
  }
})();
