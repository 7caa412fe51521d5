// guardsim viewer: the layers of a patrol or sneak page (guardsim/viewer/layers.py ships their data).
// Inlined before viewer.js, which calls GuardsimLayers.make(env) once its canvas is laid out:
// - laps: the trace is one lap; page tick t shows lap tick t mod period, for several laps;
// - idleness: a number per cell (worst gap, longest unseen window) as a heat map with a colour bar;
// - idle-now: each cell's idleness at the current tick (ticks since a guard last saw it), in steady state;
// - route: each guard's loop, a closed dashed polyline under the animation;
// - intruder: a player who is not a guard: its path from its start tick, no cone, marked when in view.
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
    const heat = data.idleness
      ? { values: decode(data.idleness.values, Float32Array), never: decode(data.idleness.never, Uint8Array) }
      : null;
    const intruder = data.intruder
      ? { path: decode(data.intruder.path, Int32Array), inView: decode(data.intruder.in_view, Uint8Array), start: data.intruder.start }
      : null;
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

    const staticImage = heat
      ? cellImage((pixels) => {
          for (let i = 0; i < cells; i++) {
            let rgb = null;
            if (heat.never[i]) rgb = NEVER;
            else if (heat.values[i] >= 0) rgb = colour(heat.values[i], data.idleness.max);
            if (rgb) pixels.set([rgb[0], rgb[1], rgb[2], 255], 4 * i);
          }
        })
      : null;
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
      if (layers.idleness && staticImage) context.drawImage(staticImage, 0, 0, canvas.width, canvas.height);
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

    function drawOver(tick, layers, radius) {
      if (!intruder || !layers.intruder) return;
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

    function intruderText(tick) {
      if (!intruder) return "";
      const step = intruderStep(tick);
      const name = data.intruder.label;
      if (step < 0) return name + " enters at tick " + intruder.start;
      const ticks = intruder.path.length - 1;
      if (tick - intruder.start >= ticks) {
        return name + " arrived after " + ticks + " ticks, " + data.intruder.ticks_in_view + " in view";
      }
      return name + " tick " + step + " / " + ticks + ": " + (intruder.inView[step] === 1 ? "IN VIEW" : "unseen");
    }

    // The colour bar describes the upper idleness layer shown.
    function colourBar(layers, parts) {
      const now = layers["idle-now"] && runs;
      const shown = now || (layers.idleness && heat);
      parts.box.style.visibility = shown ? "visible" : "hidden";
      if (!shown) return;
      const top = now ? laps.max : data.idleness.max;
      parts.label.textContent = now ? "idleness now" : data.idleness.label;
      parts.max.textContent = String(Math.round(top * 10) / 10);
      parts.unit.textContent = now ? "ticks since last seen" : data.idleness.unit;
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
      if (heat) {
        const value = heat.values[cell];
        const text = heat.never[cell] ? "never seen" : value >= 0 ? Math.round(value * 1000) / 1000 + " " + data.idleness.unit : "-";
        parts.push(data.idleness.label + " " + text);
      }
      if (runs && kinds[cell] === 1) {
        const value = idleAt(cell, tick % period);
        parts.push("idle now " + (value < 0 ? "never seen" : value + " ticks"));
      }
      return parts.join(" \u00b7 ");
    }

    // Ticks marked on the timeline: where each lap begins, where the intruder enters, each stretch in
    // view begins, and where it arrives.
    function marks(total) {
      const found = new Set();
      if (laps && total / period <= 50) for (let t = period; t < total; t += period) found.add(t);
      if (intruder) {
        found.add(intruder.start);
        for (let step = 0; step < intruder.path.length; step++) {
          if (intruder.inView[step] === 1 && (step === 0 || intruder.inView[step - 1] !== 1)) found.add(intruder.start + step);
        }
        found.add(intruder.start + intruder.path.length - 1);
      }
      return [...found].filter((t) => t >= 0 && t <= total).sort((a, b) => a - b);
    }

    // Whether a viridis layer lies under the cones (viridis ends in the cone's yellow; viewer.js then
    // draws the cones as a white wash with a cased edge).
    const heatShown = (layers) => Boolean((layers.idleness && heat) || (layers["idle-now"] && runs));

    const present = [];
    if (heat) present.push("idleness");
    if (runs) present.push("idle-now");
    if (data.routes) present.push("route");
    if (intruder) present.push("intruder");

    function legend() {
      const items = [];
      if (heat || runs) items.push(["#000000", "never seen"]);
      if (data.routes) {
        const dark = data.route_colours[0];
        items.push(["repeating-linear-gradient(90deg," + dark + " 0 4px," + ROUTE_GAP + " 4px 7px)", "route (dashed: each guard's loop)"]);
      }
      if (heat || runs) items.push([CONE_OVER_HEAT, "sees now, over a heat map (white wash, dark edge)"]);
      if (intruder) {
        items.push([data.colours.intruder, data.intruder.label + " (no cone; \u25cb from, \u25a1 to)"]);
        items.push(["#000000", "intruder in view (ringed red)"]);
      }
      return items;
    }

    return { total, local, drawUnder, drawOver, describe, intruderText, colourBar, paintBar, present, legend, marks, cellText, heatShown };
  }

  return { make: make };
})();
