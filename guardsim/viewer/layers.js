// guardsim viewer: the layers of a patrol or sneak page (guardsim/viewer/layers.py ships their data).
// Inlined before viewer.js, which calls GuardsimLayers.make(env) once its canvas is laid out:
// - laps: the trace is one lap; page tick t shows lap tick t mod period, for several laps;
// - idleness: a number per cell (worst gap, longest unseen window) as a heat map with a colour bar;
// - exposure, detection-time: a sneak's other numbers per cell, drawn by the same heat-map code;
// - idle-now: each cell's idleness at the current tick (ticks since a guard last saw it), in steady state;
// - route: each guard's loop, a closed dashed polyline under the animation;
// - intruder: a player who is not a guard: its path from its start tick, no cone, marked when in view;
// - meters: each guard's awareness meter as a bar over it while the intruder is in;
// - safe: the safe spots given, each cell outlined (green: holds, magenta: broken);
// - an alert episode's (data.alert): states, each guard's state as the alert GIF's letter over it;
//   meters at every tick; contaminated, the cells the intruder may be in as dots; last-known, a cross;
//   noises, a ring of its radius where each noise is made at its tick (H over a guard that heard one);
// - light: the level's light, darkness shaded over the floor; cameras: each camera's cone at the lap tick
//   and its meter over it while the intruder is in (data.watch).
"use strict";
const GuardsimLayers = (function () {
  const NEVER = [0, 0, 0];
  const MARK = "#ff2020";
  const BAR_WIDTH = 256;
  const ROUTE_GAP = "#ffffff";
  // The legend's swatch of a cone over the heat map: viridis's ends and middle under viewer.js's white wash.
  const CONE_OVER_HEAT = "linear-gradient(90deg,#a280aa,#90c8c6,#fef392)";
  // Dash and gap in whole canvas pixels.
  const routeDash = (scale) => [Math.max(6, Math.round(scale)), Math.max(4, Math.round(scale * 0.6))];

  function make(env) {
    const { data, context, scale, px, py, decode, ramp, cellImage, centre, kinds } = env;
    const cells = data.rows * data.cols;
    const laps = data.laps || null;
    const period = laps ? laps.period : 0;
    const runs = laps
      ? { offsets: decode(laps.offsets, Int32Array), starts: decode(laps.starts, Int32Array), ends: decode(laps.ends, Int32Array) }
      : null;
    // The heat maps, in drawing order (the colour bar describes the upper one shown): layer name, data.
    const heats = [["idleness", data.idleness], ["exposure", data.exposure], ["detection-time", data.detection_time]]
      .filter(([, info]) => info)
      .map(([name, info]) => ({
        name: name,
        info: info,
        values: decode(info.values, Float32Array),
        never: decode(info.never, Uint8Array),
        image: null,
      }));
    const intruder = data.intruder
      ? {
          path: decode(data.intruder.path, Int32Array),
          inView: decode(data.intruder.in_view, Uint8Array),
          start: data.intruder.start,
          meters: data.intruder.meters ? decode(data.intruder.meters, Float32Array) : null,
          states: data.intruder.states ? decode(data.intruder.states, Uint8Array) : null,
        }
      : null;
    const meters = intruder && intruder.meters ? intruder.meters : null;
    const alert = data.alert
      ? {
          info: data.alert,
          guards: data.alert.guards,
          states: decode(data.alert.states, Uint8Array),
          meters: decode(data.alert.meters, Float32Array),
          contaminated: decode(data.alert.contaminated, Uint8Array),
          lastKnown: decode(data.alert.last_known, Int32Array),
          heard: decode(data.alert.heard, Uint8Array),
        }
      : null;
    const watch = data.watch
      ? {
          light: data.watch.light ? decode(data.watch.light, Float32Array) : null,
          meters: data.watch.meters ? decode(data.watch.meters, Float32Array) : null,
          cameras: data.watch.cameras.map((camera) => ({ ...camera, headings: decode(camera.headings, Float32Array) })),
          image: null,
        }
      : null;
    const alertTicks = alert ? alert.lastKnown.length : 0;
    // The alert row shown at page tick `tick` (the last once the episode is over).
    const alertRow = (tick) => Math.max(0, Math.min(tick, alertTicks - 1));
    // A cell's centre in world units, written as the command line takes a point: "29.5,48.5".
    const worldText = (cell) => GuardsimLayers.worldPoint(data, cell % data.cols, Math.floor(cell / data.cols));
    const colour = (value, top) => ramp(data.ramp, top > 0 ? value / top : 0);

    // The timeline: whole laps (from the address, else the page's default), and the intruder's walk.
    function total(steps, wanted) {
      let end = steps;
      if (laps) {
        const count = Math.max(1, Math.min(1000, parseInt(wanted, 10) || laps.laps));
        end = count * period;
      }
      if (intruder) end = Math.max(end, intruder.start + intruder.path.length - 1);
      return end;
    }
    const local = (tick, steps) => (laps ? tick % period : Math.min(tick, steps));

    // Ticks since a guard last saw the cell at lap tick tau, the lap repeating for ever; -1 if never seen.
    function idleAt(cell, tau) {
      const a = runs.offsets[cell], b = runs.offsets[cell + 1];
      if (a === b) return -1;
      let lo = a, hi = b - 1, found = -1;
      while (lo <= hi) {
        const mid = (lo + hi) >> 1;
        if (runs.starts[mid] <= tau) {
          found = mid;
          lo = mid + 1;
        } else hi = mid - 1;
      }
      if (found < 0) return tau + period - runs.ends[b - 1];
      return tau <= runs.ends[found] ? 0 : tau - runs.ends[found];
    }

    function heatImage(heat) {
      if (!heat.image) {
        heat.image = cellImage((pixels) => {
          for (let i = 0; i < cells; i++) {
            let rgb = null;
            if (heat.never[i]) rgb = NEVER;
            else if (heat.values[i] >= 0) rgb = colour(heat.values[i], heat.info.max);
            if (rgb) pixels.set([rgb[0], rgb[1], rgb[2], 255], 4 * i);
          }
        });
      }
      return heat.image;
    }
    let nowCache = { tau: -1, image: null };
    function nowImage(tau) {
      if (nowCache.tau !== tau) {
        const image = cellImage((pixels) => {
          for (let i = 0; i < cells; i++) {
            if (kinds[i] !== 1) continue;
            const value = idleAt(i, tau);
            const rgb = value < 0 ? NEVER : colour(value, laps.max);
            pixels.set([rgb[0], rgb[1], rgb[2], 255], 4 * i);
          }
        });
        nowCache = { tau: tau, image: image };
      }
      return nowCache.image;
    }

    // Drawn inside the floor's clip, over the trace's own cell layers and under cones and guards.
    function drawUnder(tick, layers, canvas) {
      for (const heat of heats) if (layers[heat.name]) context.drawImage(heatImage(heat), 0, 0, canvas.width, canvas.height);
      if (layers["idle-now"] && runs) context.drawImage(nowImage(tick % period), 0, 0, canvas.width, canvas.height);
      if (layers.route && data.routes) {
        // Dashes of the guard's dark shade over a white line, thinner than the trail: the solid trail in the
        // guard's colour would otherwise pass for its loop. Whole-pixel dashes keep every pixel one colour.
        context.lineWidth = Math.max(2, 2 * Math.round(scale / 10));
        context.lineJoin = "round";
        const dash = routeDash(scale);
        data.routes.forEach((route, guard) => {
          context.beginPath();
          route.forEach((p, i) => (i === 0 ? context.moveTo(px(p[0]), py(p[1])) : context.lineTo(px(p[0]), py(p[1]))));
          context.closePath();
          context.setLineDash([]);
          context.strokeStyle = ROUTE_GAP;
          context.stroke();
          context.setLineDash(dash);
          context.strokeStyle = data.route_colours[guard];
          context.stroke();
          context.setLineDash([]);
        });
      }
      if (alert && layers.contaminated) drawContaminated(alertRow(tick));
      if (watch && watch.light && layers.light) context.drawImage(lightImage(), 0, 0, canvas.width, canvas.height);
    }

    // The dark over each floor cell: the watch colour at (1 - light) * dark_alpha, so the floor still reads.
    function lightImage() {
      if (!watch.image) {
        const dark = data.watch.dark_colour;
        watch.image = cellImage((pixels) => {
          for (let i = 0; i < cells; i++) {
            if (kinds[i] !== 1) continue;
            const alpha = Math.round(255 * (1 - Math.min(1, Math.max(0, watch.light[i]))) * data.watch.dark_alpha);
            pixels.set([dark[0], dark[1], dark[2], alpha], 4 * i);
          }
        });
      }
      return watch.image;
    }

    // Each camera, its cone's outline at page tick `tick` (the swing repeats), and its meter while the
    // intruder walks; returns nothing.
    function drawCameras(tick, radius) {
      const rgb = "rgb(" + data.watch.camera_colour.join(",") + ")";
      const step = walking(tick);
      watch.cameras.forEach((camera, index) => {
        const x = px(camera.position[0]), y = py(camera.position[1]);
        const heading = (camera.headings[tick % camera.ticks] * Math.PI) / 180;
        const half = (camera.fov * Math.PI) / 360;
        const reach = camera.range * scale;
        context.strokeStyle = rgb;
        context.lineWidth = 2;
        context.beginPath();
        if (camera.fov >= 360) context.arc(x, y, reach, 0, 2 * Math.PI);
        else {
          context.moveTo(x, y);
          context.arc(x, y, reach, heading - half, heading + half);
          context.closePath();
        }
        context.stroke();
        context.fillStyle = rgb;
        context.beginPath();
        context.arc(x, y, Math.max(3, radius * 0.8), 0, 2 * Math.PI);
        context.fill();
        if (watch.meters && step >= 0) {
          // Below the camera when there is no room above it (a camera on the top wall).
          const height = Math.max(5, Math.round(0.6 * radius));
          const above = Math.round(y - radius) - 4 - height >= 0;
          const spot = [x, above ? y : y + 3 * radius + 8];
          drawMeters(watch.meters, watch.cameras.length, data.intruder, step, radius, [spot], index);
        }
      });
    }

    // Whether the intruder may be in `cell` at alert row `row` (a bit per cell, rows whole bytes).
    const contaminatedAt = (row, cell) =>
      (alert.contaminated[row * alert.info.contaminated_stride + (cell >> 3)] >> (cell & 7)) & 1;

    // A dot at each contaminated cell's centre, as the alert GIF draws them.
    function drawContaminated(row) {
      const dot = Math.max(1, scale / 5);
      context.fillStyle = "rgb(" + alert.info.contaminated_colour.join(",") + ")";
      for (let cell = 0; cell < cells; cell++) {
        if (!contaminatedAt(row, cell)) continue;
        const [x, y] = centre(cell);
        context.fillRect(x - dot, y - dot, 2 * dot, 2 * dot);
      }
    }

    // The last known cell: a cross in the alert GIF's colour.
    function drawLastKnown(row) {
      const cell = alert.lastKnown[row];
      if (cell < 0) return;
      const [x, y] = centre(cell);
      const arm = Math.max(3, scale * 0.6);
      context.strokeStyle = "rgb(" + alert.info.last_known_colour.join(",") + ")";
      context.lineWidth = 2;
      context.lineCap = "butt";
      context.beginPath();
      context.moveTo(x - arm, y - arm);
      context.lineTo(x + arm, y + arm);
      context.moveTo(x - arm, y + arm);
      context.lineTo(x + arm, y - arm);
      context.stroke();
    }

    // The noises made at page tick `tick` (each lasts its tick): where they are made, a ring of their radius,
    // as the alert GIF draws them.
    const noisesAt = (tick) => alert.info.noises.filter(([at]) => at === tick);
    function drawNoises(tick) {
      context.strokeStyle = data.colours.outline;
      context.lineWidth = 2;
      for (const [, cell, reach] of noisesAt(tick)) {
        const [x, y] = centre(cell);
        context.beginPath();
        context.arc(x, y, (reach / data.cell_size) * scale, 0, 2 * Math.PI);
        context.stroke();
      }
    }
    // Whether `guard` is investigating a noise it heard at alert row `row`.
    const heardAt = (row, guard) => alert.heard[row * alert.guards + guard] === 1;

    // Each guard's state as the alert GIF's letter, up beside it (left of it near the canvas's right edge).
    function drawStates(row, radius, spots) {
      const size = Math.max(11, Math.round(radius * 1.3));
      context.font = "bold " + size + "px sans-serif";
      context.textBaseline = "bottom";
      context.lineJoin = "round";
      spots.forEach(([x, y], guard) => {
        if (guard >= alert.guards) return;
        const letter = heardAt(row, guard) ? alert.info.heard_letter : alert.info.state_letters[alert.states[row * alert.guards + guard]];
        const width = context.measureText(letter).width;
        const left = x + radius + width + 4 > context.canvas.width ? x - radius - width - 2 : x + radius + 2;
        // Below the guard when there is no room above it.
        const base = y - radius + 2 - size < 0 ? y + radius + size : y - radius + 2;
        context.strokeStyle = "#ffffff";
        context.lineWidth = 3;
        context.strokeText(letter, left, base);
        context.fillStyle = data.colours.outline;
        context.fillText(letter, left, base);
      });
    }

    // The guards' states, the intruder's cell, the last known cell and the contaminated count at page
    // tick `tick`, read from the arrays the layers draw (the readout, and what a test reads back).
    function alertState(tick) {
      if (!alert) return null;
      const row = alertRow(tick);
      const names = [];
      for (let guard = 0; guard < alert.guards; guard++) names.push(alert.info.state_names[alert.states[row * alert.guards + guard]]);
      const step = intruder ? intruderStep(tick) : -1;
      const inside = intruder && step >= 0 && tick - intruder.start < intruder.path.length;
      const cellText = (cell) => (cell < 0 ? "" : (cell % data.cols) + "," + Math.floor(cell / data.cols));
      const known = alert.lastKnown[row];
      const count = alert.info.contaminated_counts[row];
      const heard = names.map((name, guard) => heardAt(row, guard));
      const parts = names.map(
        (name, guard) => (alert.guards > 1 ? "guard " + (guard + 1) + " " : "") + name + (heard[guard] ? " (heard a noise)" : "")
      );
      const noises = tick === row ? noisesAt(tick) : [];
      if (noises.length) parts.push(noises.length + (noises.length === 1 ? " noise" : " noises"));
      if (known >= 0) parts.push("last known " + worldText(known));
      parts.push(count + (count === 1 ? " cell" : " cells") + " contaminated");
      return {
        text: parts.join(" \u00b7 "),
        states: names.join(","),
        intruder: inside ? cellText(intruder.path[step]) : "",
        lastKnown: cellText(known),
        contaminated: String(count),
        heard: heard.map((flag) => (flag ? "1" : "0")).join(","),
        noises: noises.map(([, cell, reach]) => cellText(cell) + "," + reach).join(";"),
      };
    }

    // Where the intruder is at page tick `tick`: its path index, or -1 before it enters.
    const intruderStep = (tick) => (tick < intruder.start ? -1 : Math.min(tick - intruder.start, intruder.path.length - 1));

    function drawPoint(point, square, radius) {
      const x = px(point[0]), y = py(point[1]);
      for (const [width, style] of [[4, data.colours.outline], [2, data.colours.intruder]]) {
        context.lineWidth = width;
        context.strokeStyle = style;
        context.beginPath();
        if (square) context.rect(x - radius, y - radius, 2 * radius, 2 * radius);
        else context.arc(x, y, radius, 0, 2 * Math.PI);
        context.stroke();
      }
    }

    // Each safe spot's cell outlined outside its edge (its own colours stay visible), cased in black.
    function drawSafe() {
      const width = Math.max(2, Math.round(scale / 6));
      for (const spot of data.safe) {
        const x = spot.cell[0] * scale, y = spot.cell[1] * scale;
        const rgb = data.safe_colours[spot.holds ? "holds" : "broken"];
        context.strokeStyle = data.colours.outline;
        context.lineWidth = 1;
        context.strokeRect(x - width - 0.5, y - width - 0.5, scale + 2 * width + 1, scale + 2 * width + 1);
        context.fillStyle = "rgb(" + rgb.join(",") + ")";
        context.fillRect(x - width, y - width, scale + 2 * width, width);
        context.fillRect(x - width, y + scale, scale + 2 * width, width);
        context.fillRect(x - width, y, width, scale);
        context.fillRect(x + scale, y, width, scale);
      }
    }

    // The path tick shown at page tick `tick` while the intruder is in (entered, not yet arrived), else -1.
    const walking = (tick) => (intruder && tick >= intruder.start && tick - intruder.start < intruder.path.length ? tick - intruder.start : -1);

    // What one meter's level says by itself (guardsim.detection.meter_state): its bar's fill colour.
    function meterState(level, suspicious) {
      if (level >= 1 - 1e-6) return "detected";
      if (level > 0 && level >= suspicious) return "suspicious";
      return level > 0 ? "in view" : "unseen";
    }

    // A bar over each guard (at `spots`, where viewer.js drew it), framed in the outline colour, white
    // inside, filled from the left by its meter: the box of guardsim.render.sneak.meter_bar_box. `levels`
    // holds `guards` meters per step; `info` the suspicious level and the state colours.
    function drawMeters(levels, guards, info, step, radius, spots, only) {
      spots.forEach(([x, y], spot) => {
        // `only`: the one column (a camera's) drawn at the one spot given.
        const guard = only === undefined ? spot : only;
        if (guard >= guards) return;
        const level = Math.min(1, Math.max(0, levels[step * guards + guard]));
        const half = Math.round(radius) + 1;
        const height = Math.max(5, Math.round(0.6 * radius));
        const left = Math.round(x) - half, top = Math.round(y - radius) - 4 - height;
        context.fillStyle = data.colours.outline;
        context.fillRect(left, top, 2 * half, height);
        context.fillStyle = "#ffffff";
        context.fillRect(left + 1, top + 1, 2 * half - 2, height - 2);
        const filled = Math.round(level * (2 * half - 2));
        if (filled > 0) {
          context.fillStyle = "rgb(" + info.state_colours[meterState(level, info.suspicious)].join(",") + ")";
          context.fillRect(left + 1, top + 1, filled, height - 2);
        }
      });
    }

    function drawOver(tick, layers, radius, spots) {
      if (watch && layers.cameras) drawCameras(tick, radius);
      if (data.safe && layers.safe) drawSafe();
      if (intruder && layers.intruder) drawIntruder(tick, radius);
      const step = walking(tick);
      if (meters && layers.meters && step >= 0) drawMeters(meters, data.intruder.guards, data.intruder, step, radius, spots || []);
      if (alert) {
        const row = alertRow(tick);
        if (layers["last-known"]) drawLastKnown(row);
        if (layers.noises) drawNoises(tick);
        if (layers.meters) drawMeters(alert.meters, alert.guards, alert.info, row, radius, spots || []);
        if (layers.states) drawStates(row, radius, spots || []);
      }
    }

    function drawIntruder(tick, radius) {
      const info = data.intruder;
      if (info.from) drawPoint(info.from, false, radius + 3);
      if (info.to) drawPoint(info.to, true, radius + 3);
      const step = intruderStep(tick);
      if (step < 0) return;
      context.strokeStyle = data.colours.intruder;
      context.lineWidth = Math.max(2, scale / 2);
      context.lineJoin = "round";
      context.lineCap = "round";
      context.beginPath();
      for (let i = 0; i <= step; i++) {
        const [x, y] = centre(intruder.path[i]);
        if (i === 0) context.moveTo(x, y);
        else context.lineTo(x, y);
      }
      context.stroke();
      // An alert's intruder leaves the level at its goal: its walk stays drawn, not the intruder.
      if (alert && tick - intruder.start >= intruder.path.length) return;
      // No cone: the intruder watches nothing. A disc, white while unseen, black and ringed red in view.
      const [x, y] = centre(intruder.path[step]);
      const seen = intruder.inView[step] === 1;
      context.fillStyle = seen ? "#000000" : "#ffffff";
      context.strokeStyle = data.colours.intruder;
      context.lineWidth = 2;
      context.beginPath();
      context.arc(x, y, radius, 0, 2 * Math.PI);
      context.fill();
      context.stroke();
      if (seen) {
        context.strokeStyle = MARK;
        context.lineWidth = 3;
        context.beginPath();
        context.arc(x, y, radius + 4, 0, 2 * Math.PI);
        context.stroke();
      }
    }

    function describe(tick, total) {
      if (!laps) return null;
      const count = Math.ceil(total / period);
      const lap = Math.min(count, Math.floor(tick / period) + 1);
      return "lap " + lap + " / " + count + " \u00b7 lap tick " + (tick % period) + " / " + period;
    }

    // The intruder's state at page tick `tick` (guardsim.detection.intruder_state, worked out in Python)
    // and its colour, while it is in; null otherwise.
    function intruderState(tick) {
      const step = walking(tick);
      if (step < 0 || !intruder.states) return null;
      const name = data.intruder.state_names[intruder.states[step]];
      let text = name;
      if (meters) {
        let top = 0;
        for (let guard = 0; guard < data.intruder.guards; guard++) top = Math.max(top, meters[step * data.intruder.guards + guard]);
        text += " \u00b7 awareness " + top.toFixed(2);
      } else if (alert) {
        let top = 0;
        const row = alertRow(tick);
        for (let guard = 0; guard < alert.guards; guard++) top = Math.max(top, alert.meters[row * alert.guards + guard]);
        // Once detected the guards chase and search: their meters no longer measure the intruder, and
        // "detected · awareness 0.00" read as a contradiction.
        if (name !== "detected") text += " \u00b7 awareness " + top.toFixed(2);
      }
      return { name: name, text: text, colour: data.intruder.state_colours[name] };
    }

    function intruderText(tick) {
      if (!intruder) return "";
      const step = intruderStep(tick);
      const name = data.intruder.label;
      if (step < 0) return name + " enters at tick " + intruder.start;
      if (alert) {
        // An alert's intruder is in from tick 0 until it is captured or leaves at its goal.
        if (tick - intruder.start >= intruder.path.length) return name + " left the level at tick " + (intruder.start + intruder.path.length);
        const cell = intruder.path[step];
        return name + " at " + worldText(cell) + ": " + (intruder.inView[step] === 1 ? "IN VIEW" : "unseen");
      }
      const ticks = intruder.path.length - 1;
      if (tick - intruder.start >= ticks) {
        return name + " arrived after " + ticks + " ticks, " + data.intruder.ticks_in_view + " in view";
      }
      return name + " tick " + step + " / " + ticks + ": " + (intruder.inView[step] === 1 ? "IN VIEW" : "unseen");
    }

    // The upper heat map shown, of those drawn from data (idleness now is drawn over them all).
    const upperHeat = (layers) => heats.filter((heat) => layers[heat.name]).pop() || null;

    // The colour bar describes the upper heat layer shown.
    function colourBar(layers, parts) {
      const now = layers["idle-now"] && runs;
      const heat = upperHeat(layers);
      const shown = now || heat;
      parts.box.style.visibility = shown ? "visible" : "hidden";
      if (!shown) return;
      const top = now ? laps.max : heat.info.max;
      parts.label.textContent = now ? "idleness now" : heat.info.label;
      parts.max.textContent = String(Math.round(top * 10) / 10);
      parts.unit.textContent = now ? "ticks since last seen" : heat.info.unit;
    }

    function paintBar(bar) {
      bar.width = BAR_WIDTH;
      bar.height = 14;
      const barContext = bar.getContext("2d");
      const image = barContext.createImageData(BAR_WIDTH, 14);
      for (let x = 0; x < BAR_WIDTH; x++) {
        const rgb = ramp(data.ramp, x / (BAR_WIDTH - 1));
        for (let y = 0; y < 14; y++) image.data.set([rgb[0], rgb[1], rgb[2], 255], 4 * (y * BAR_WIDTH + x));
      }
      barContext.putImageData(image, 0, 0);
    }

    // What the idleness layers say of one cell at page tick `tick` (the inspected cell's readout).
    function cellText(cell, tick) {
      const parts = [];
      for (const heat of heats) {
        const value = heat.values[cell];
        const text = heat.never[cell] ? heat.info.never_text : value >= 0 ? Math.round(value * 1000) / 1000 + " " + heat.info.unit : "-";
        parts.push(heat.info.label + " " + text);
      }
      if (runs && kinds[cell] === 1) {
        const value = idleAt(cell, tick % period);
        parts.push("idle now " + (value < 0 ? "never seen" : value + " ticks"));
      }
      for (const spot of data.safe || []) {
        if (spot.cell[1] * data.cols + spot.cell[0] === cell) parts.push("safe spot " + (spot.holds ? "holds" : "broken") + ": " + spot.label);
      }
      return parts.join(" \u00b7 ");
    }

    // The peak awareness is marked unless no meter ever rose.
    const peakShown = Boolean(meters && data.intruder.peak && data.intruder.peak.value > 0);

    // What a mark of the timeline is, when it is more than a tick: the peak awareness, the detection.
    function markLabel(tick) {
      const found = [];
      if (alert) {
        for (const [at, guard, event] of alert.info.events) {
          // A camera's alarm is numbered after the guards.
          const who = guard >= alert.guards ? "camera " + (guard - alert.guards + 1) + " " : guard >= 0 && alert.guards > 1 ? "guard " + (guard + 1) + " " : "";
          if (at === tick) found.push(who + event.replace(/_/g, " "));
        }
      }
      if (!intruder) return [...new Set(found)].join(", ");
      if (peakShown && tick === intruder.start + data.intruder.peak.step) {
        found.push("peak awareness " + data.intruder.peak.value.toFixed(2));
      }
      // (An alert names its detections among its events.)
      if (!alert && data.intruder.detected_at !== null && data.intruder.detected_at !== undefined && tick === intruder.start + data.intruder.detected_at) {
        found.push("detected");
      }
      return [...new Set(found)].join(", ");
    }

    // Ticks marked on the timeline: where each lap begins, where the intruder enters, each stretch in
    // view begins, where the guards' awareness peaks, where it is detected, and where it arrives.
    function marks(total) {
      const found = new Set();
      if (laps && total / period <= 50) for (let t = period; t < total; t += period) found.add(t);
      if (intruder) {
        found.add(intruder.start);
        for (let step = 0; step < intruder.path.length; step++) {
          if (intruder.inView[step] === 1 && (step === 0 || intruder.inView[step - 1] !== 1)) found.add(intruder.start + step);
        }
        found.add(intruder.start + intruder.path.length - 1);
        if (peakShown) found.add(intruder.start + data.intruder.peak.step);
        if (data.intruder.detected_at !== null && data.intruder.detected_at !== undefined) found.add(intruder.start + data.intruder.detected_at);
      }
      // An alert's events: detections, losses of sight, give-ups, returns to the route, the capture.
      if (alert) for (const [at, , event] of alert.info.events) if (event !== "noticed" && event !== "joined") found.add(at);
      return [...found].filter((t) => t >= 0 && t <= total).sort((a, b) => a - b);
    }

    // Whether a viridis layer lies under the cones (viridis ends in the cone's yellow; viewer.js then
    // draws the cones as a white wash with a cased edge).
    const heatShown = (layers) => Boolean(upperHeat(layers) || (layers["idle-now"] && runs));

    const present = heats.map((heat) => heat.name);
    if (runs) present.push("idle-now");
    if (data.routes) present.push("route");
    if (intruder) present.push("intruder");
    if (meters || alert) present.push("meters");
    if (alert) present.push("contaminated", "last-known", "states");
    if (alert && alert.info.noises.length) present.push("noises");
    if (data.safe) present.push("safe");
    if (watch && watch.light) present.push("light");
    if (watch && watch.cameras.length) present.push("cameras");

    const hex = (rgb) => "#" + rgb.map((v) => v.toString(16).padStart(2, "0")).join("");

    function legend() {
      const items = [];
      const blacks = new Set(heats.map((heat) => heat.info.never_text));
      if (runs) blacks.add("never seen");
      for (const text of blacks) items.push(["#000000", text]);
      const heat = heats.length > 0 || runs;
      if (data.routes) {
        const dark = data.route_colours[0];
        items.push(["repeating-linear-gradient(90deg," + dark + " 0 4px," + ROUTE_GAP + " 4px 7px)", "route (dashed: each guard's loop)"]);
      }
      if (heat) items.push([CONE_OVER_HEAT, "sees now, over a heat map (white wash, dark edge)"]);
      if (intruder) {
        items.push([data.colours.intruder, data.intruder.label + " (no cone; \u25cb from, \u25a1 to)"]);
        items.push(["#000000", "intruder in view (ringed red)"]);
      }
      if (meters || alert) {
        const colours = (alert ? alert.info : data.intruder).state_colours;
        const bar = ["in view", "suspicious", "detected"].map((name) => hex(colours[name]));
        items.push(["linear-gradient(90deg," + bar.join(",") + ")", "awareness meter over each guard: rising, suspicious, full"]);
      }
      if (alert) {
        const letters = alert.info.state_names.map((name, k) => alert.info.state_letters[k] + " " + name).join(", ");
        items.push([data.colours.outline, "guard state: " + letters]);
        items.push([hex(alert.info.contaminated_colour), "contaminated: where the intruder may be (dots)"]);
        items.push([hex(alert.info.last_known_colour), "last known position (cross)"]);
        if (alert.info.noises.length) {
          items.push([data.colours.outline, "noise: a ring of its radius where and when it is made; " + alert.info.heard_letter + " over a guard that heard one"]);
        }
      }
      if (data.safe) {
        items.push([hex(data.safe_colours.holds), "safe spot (holds)"]);
        items.push([hex(data.safe_colours.broken), "safe spot (broken)"]);
      }
      if (watch && watch.cameras.length) items.push([hex(data.watch.camera_colour), "camera, its cone and meter"]);
      if (watch && watch.light) items.push(["linear-gradient(90deg," + hex(data.watch.dark_colour) + ",#ffffff)", "light: dark to full"]);
      return items;
    }

    return {
      total, local, drawUnder, drawOver, describe, intruderText, intruderState, colourBar, paintBar, present, legend,
      marks, markLabel, cellText, heatShown, heats, alertState,
    };
  }


  // A cell's centre in world units as the command line takes a point, "29.5,48.5" (at most three decimals).
  function worldPoint(data, col, row) {
    const at = (origin, index) => String(Math.round((origin + (index + 0.5) * data.cell_size) * 1000) / 1000);
    return at(data.origin[0], col) + "," + at(data.origin[1], row);
  }

  return { make: make, worldPoint: worldPoint };
})();
