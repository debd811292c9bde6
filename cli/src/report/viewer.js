// satflock report: the swarm in Hill LVLH (x radial outward, y along-track, z orbit normal), drawn on a
// 2-D canvas with an orthographic projection. No library, nothing loaded: the data is the JSON element
// `satflock-data` of this page (positions as little-endian float32 in base64, NaN where a satellite has
// no row at that time).
(() => {
  "use strict";
  const page = JSON.parse(document.getElementById("satflock-data").textContent);
  const tr = page.trajectory;
  const canvas = document.getElementById("view");
  if (!tr || !canvas || tr.times_s.length === 0) {
    return;
  }
  const scene = page.scene;
  const ctx = canvas.getContext("2d");

  function decodeF32(b64) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) {
      bytes[i] = bin.charCodeAt(i);
    }
    const view = new DataView(bytes.buffer);
    const out = new Float32Array(bytes.length / 4);
    for (let k = 0; k < out.length; k++) {
      out[k] = view.getFloat32(4 * k, true);
    }
    return out;
  }

  const S = tr.satellite_ids.length;
  const T = tr.times_s.length;
  const pos = decodeF32(tr.positions_lvlh_m_f32le);
  const formation = scene.target_formation_lvlh_m || [];

  // ---- colours
  const SINGLE = "#2f6db3";
  const MISSING = "#9aa3ad";
  const THREAT = "#c81e1e";
  const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f", "#aec7e8"];
  const RAMP = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];

  function describeColumn(name, values) {
    const distinct = new Set();
    let min = Infinity;
    let max = -Infinity;
    let integers = true;
    for (const v of values) {
      if (!Number.isFinite(v)) {
        continue;
      }
      min = Math.min(min, v);
      max = Math.max(max, v);
      if (!Number.isInteger(v)) {
        integers = false;
      }
      if (distinct.size <= PALETTE.length) {
        distinct.add(v);
      }
    }
    // A value missing where the satellite has a position (a law without that column at that time).
    let missing = false;
    for (let i = 0; i < values.length && !missing; i++) {
      missing = !Number.isFinite(values[i]) && Number.isFinite(pos[3 * i]);
    }
    const categorical = integers && distinct.size <= PALETTE.length;
    const categories = Array.from(distinct).sort((a, b) => a - b);
    return { name, values, categorical, categories, min, max, missing };
  }

  function rampColour(u) {
    const x = Math.min(1, Math.max(0, u)) * (RAMP.length - 1);
    const k = Math.min(RAMP.length - 2, Math.floor(x));
    const f = x - k;
    const c = RAMP[k].map((a, i) => Math.round(a + f * (RAMP[k + 1][i] - a)));
    return `rgb(${c[0]},${c[1]},${c[2]})`;
  }

  const columns = tr.colour_columns.map((c) => describeColumn(c.name, decodeF32(c.values_f32le)));
  let colourColumn = null;
  function colourOf(sample) {
    if (!colourColumn) {
      return SINGLE;
    }
    const v = colourColumn.values[sample];
    if (!Number.isFinite(v)) {
      return MISSING;
    }
    if (colourColumn.categorical) {
      return PALETTE[colourColumn.categories.indexOf(v)];
    }
    const span = colourColumn.max - colourColumn.min;
    return rampColour(span > 0 ? (v - colourColumn.min) / span : 0.5);
  }

  // ---- extent: every kept satellite position, the obstacles and the target formation
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  function include(p, r) {
    for (let a = 0; a < 3; a++) {
      lo[a] = Math.min(lo[a], p[a] - r);
      hi[a] = Math.max(hi[a], p[a] + r);
    }
  }
  for (let i = 0; i < pos.length; i += 3) {
    if (Number.isFinite(pos[i]) && Number.isFinite(pos[i + 1]) && Number.isFinite(pos[i + 2])) {
      include([pos[i], pos[i + 1], pos[i + 2]], 0);
    }
  }
  for (const o of scene.obstacles) {
    include(o.center_lvlh_m, o.radius_m);
  }
  for (const p of formation) {
    include(p, 0);
  }
  // A threat joins the extent while it is within four times the extent so far (one from far away would
  // shrink the swarm to a dot); the wheel zooms out to it.
  if (Number.isFinite(lo[0]) && scene.threats.length > 0) {
    const mid = [0, 1, 2].map((a) => 0.5 * (lo[a] + hi[a]));
    const reach = 4 * Math.max(1, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
    for (const th of scene.threats) {
      for (const t of tr.times_s) {
        const q = [0, 1, 2].map((a) => th.position_at_t0_lvlh_m[a] + th.velocity_lvlh_mps[a] * t);
        if (Math.hypot(q[0] - mid[0], q[1] - mid[1], q[2] - mid[2]) <= reach) {
          include(q, 0);
        }
      }
    }
  }
  const centre = [0, 1, 2].map((a) => (Number.isFinite(lo[a]) ? 0.5 * (lo[a] + hi[a]) : 0));
  let radius = Number.isFinite(lo[0]) ? 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) : 1;
  if (!(radius > 0)) {
    radius = 1;
  }

  // ---- view: the rows of R are the screen's right, up and toward-the-viewer axes in Hill coordinates
  let R;
  let zoom;
  function rotate(axis, angle) {
    const c = Math.cos(angle);
    const s = Math.sin(angle);
    const i = axis === "up" ? 0 : 1; // turning about "up" mixes right and toward; about "right", up and toward
    const a = R[i];
    const b = R[2];
    R[i] = [0, 1, 2].map((k) => c * a[k] + s * b[k]);
    R[2] = [0, 1, 2].map((k) => -s * a[k] + c * b[k]);
  }
  function resetView() {
    R = [[0, 1, 0], [1, 0, 0], [0, 0, -1]]; // y to the right, x up, z into the screen
    rotate("up", 0.55);
    rotate("right", 0.35);
    zoom = 1;
  }
  resetView();

  let W = 0;
  let H = 0;
  function resize() {
    const dpr = window.devicePixelRatio || 1;
    W = canvas.clientWidth;
    H = canvas.clientHeight;
    canvas.width = Math.max(1, Math.round(W * dpr));
    canvas.height = Math.max(1, Math.round(H * dpr));
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  }
  function scale() {
    return (zoom * 0.45 * Math.min(W, H)) / radius;
  }
  function project(p, k) {
    const d = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
    const dot = (r) => r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
    return [W / 2 + k * dot(R[0]), H / 2 - k * dot(R[1]), dot(R[2])];
  }

  function circle(x, y, r) {
    ctx.beginPath();
    ctx.arc(x, y, Math.max(r, 0.5), 0, 2 * Math.PI);
  }

  function niceLength(target) {
    const p = Math.pow(10, Math.floor(Math.log10(target)));
    for (const m of [5, 2, 1]) {
      if (m * p <= target) {
        return m * p;
      }
    }
    return p;
  }

  function formatNumber(x) {
    if (Number.isInteger(x)) {
      return String(x);
    }
    return String(Number(x.toPrecision(6)));
  }

  // ---- drawing
  let frame = 0;
  function draw() {
    const k = scale();
    ctx.clearRect(0, 0, W, H);
    ctx.lineWidth = 1;
    ctx.font = "12px system-ui, sans-serif";

    for (const o of scene.obstacles) {
      const p = project(o.center_lvlh_m, k);
      circle(p[0], p[1], o.radius_m * k);
      ctx.fillStyle = "rgba(110, 120, 135, 0.18)";
      ctx.fill();
      ctx.strokeStyle = "#6b7785";
      ctx.stroke();
      ctx.fillStyle = "#4a535e";
      ctx.fillText(o.name, p[0] + 4, p[1] - 4);
    }

    ctx.strokeStyle = "#555";
    for (const f of formation) {
      const p = project(f, k);
      ctx.beginPath();
      ctx.moveTo(p[0] - 4, p[1] - 4);
      ctx.lineTo(p[0] + 4, p[1] + 4);
      ctx.moveTo(p[0] - 4, p[1] + 4);
      ctx.lineTo(p[0] + 4, p[1] - 4);
      ctx.stroke();
    }

    // Satellites, far ones first.
    const base = frame * S;
    const order = [];
    const screen = new Float64Array(3 * S);
    for (let s = 0; s < S; s++) {
      const i = 3 * (base + s);
      if (!(Number.isFinite(pos[i]) && Number.isFinite(pos[i + 1]) && Number.isFinite(pos[i + 2]))) {
        continue;
      }
      const p = project([pos[i], pos[i + 1], pos[i + 2]], k);
      screen[3 * s] = p[0];
      screen[3 * s + 1] = p[1];
      screen[3 * s + 2] = p[2];
      order.push(s);
    }
    order.sort((a, b) => screen[3 * a + 2] - screen[3 * b + 2]);
    const dot = S > 200 ? 2.5 : 4;
    ctx.strokeStyle = "rgba(0, 0, 0, 0.45)";
    for (const s of order) {
      circle(screen[3 * s], screen[3 * s + 1], dot);
      ctx.fillStyle = colourOf(base + s);
      ctx.fill();
      if (S <= 200) {
        ctx.stroke();
      }
    }

    const t = tr.times_s[frame];
    for (const th of scene.threats) {
      const q = [0, 1, 2].map((a) => th.position_at_t0_lvlh_m[a] + th.velocity_lvlh_mps[a] * t);
      const p = project(q, k);
      ctx.setLineDash([5, 4]);
      ctx.strokeStyle = THREAT;
      circle(p[0], p[1], th.danger_radius_m * k);
      ctx.stroke();
      ctx.setLineDash([]);
      circle(p[0], p[1], 4);
      ctx.fillStyle = THREAT;
      ctx.fill();
      ctx.fillText(th.name, p[0] + 6, p[1] - 6);
    }

    drawAxes();
    drawScaleBar(k);
  }

  function drawAxes() {
    const ox = 80;
    const oy = H - 60;
    const names = ["x radial", "y along-track", "z normal"];
    const colours = ["#b03a2e", "#1e8449", "#2e5fa8"];
    for (let a = 0; a < 3; a++) {
      const ex = 40 * R[0][a];
      const ey = -40 * R[1][a];
      ctx.strokeStyle = colours[a];
      ctx.fillStyle = colours[a];
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.moveTo(ox, oy);
      ctx.lineTo(ox + ex, oy + ey);
      ctx.stroke();
      // The label beyond the tip, centred on the arrow's line.
      const w = ctx.measureText(names[a]).width;
      const len = Math.max(1e-9, Math.hypot(ex, ey));
      const lx = ox + ex + (ex / len) * (0.5 * w + 4) - 0.5 * w;
      ctx.fillText(names[a], Math.min(W - w - 4, Math.max(4, lx)), oy + ey + (ey / len) * 10 + 4);
    }
    ctx.lineWidth = 1;
  }

  function drawScaleBar(k) {
    const metres = niceLength(120 / k);
    const px = metres * k;
    const x1 = W - 20;
    const y = H - 20;
    ctx.strokeStyle = "#333";
    ctx.fillStyle = "#333";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(x1 - px, y);
    ctx.lineTo(x1, y);
    ctx.moveTo(x1 - px, y - 4);
    ctx.lineTo(x1 - px, y + 4);
    ctx.moveTo(x1, y - 4);
    ctx.lineTo(x1, y + 4);
    ctx.stroke();
    ctx.lineWidth = 1;
    const label = `${formatNumber(metres)} m`;
    ctx.fillText(label, x1 - px / 2 - ctx.measureText(label).width / 2, y - 8);
  }

  // ---- legend (DOM nodes; text set as text, never parsed as HTML)
  const legend = document.getElementById("legend");
  function legendItem(colour, text, ring) {
    const item = document.createElement("div");
    item.className = "item";
    const swatch = document.createElement("span");
    swatch.className = "swatch";
    if (ring) {
      swatch.style.border = `2px dashed ${colour}`;
    } else {
      swatch.style.background = colour;
    }
    item.appendChild(swatch);
    item.appendChild(document.createTextNode(text));
    legend.appendChild(item);
  }
  function buildLegend() {
    legend.textContent = "";
    if (!colourColumn) {
      legendItem(SINGLE, "satellite");
    } else if (colourColumn.categorical) {
      colourColumn.categories.forEach((v, i) => legendItem(PALETTE[i], `${colourColumn.name} = ${v}`));
    } else {
      const item = document.createElement("div");
      item.className = "item";
      const ramp = document.createElement("span");
      ramp.className = "ramp";
      ramp.style.background = `linear-gradient(to right, ${RAMP.map((c) => `rgb(${c.join(",")})`).join(", ")})`;
      item.appendChild(document.createTextNode(formatNumber(colourColumn.min)));
      item.appendChild(ramp);
      item.appendChild(document.createTextNode(`${formatNumber(colourColumn.max)} (${colourColumn.name})`));
      legend.appendChild(item);
    }
    if (colourColumn && colourColumn.missing) {
      legendItem(MISSING, `${colourColumn.name}: no value`);
    }
    if (scene.threats.length > 0) {
      legendItem(THREAT, "threat and its danger sphere", true);
    }
    if (scene.obstacles.length > 0) {
      legendItem("rgba(110, 120, 135, 0.45)", "obstacle");
    }
    if (formation.length > 0) {
      legendItem("#555", "× target formation slot");
    }
  }

  // ---- controls
  const slider = document.getElementById("time-slider");
  const display = document.getElementById("time-display");
  const playButton = document.getElementById("play");
  const speed = document.getElementById("speed");
  const colourBy = document.getElementById("colour-by");
  slider.max = String(T - 1);

  function setFrame(f) {
    frame = Math.min(T - 1, Math.max(0, f));
    slider.value = String(frame);
    display.textContent =
      `t = ${formatNumber(tr.times_s[frame])} s · ${tr.times_utc[frame]} UTC · time ${frame + 1} of ${T}`;
    draw();
  }

  // A whole run plays in at most 20 s at 1×, and never faster than 10 kept times a second.
  const framesPerSecond = Math.max(10, (T - 1) / 20);
  let timer = null;
  let last = 0;
  let pending = 0;
  function pause() {
    clearInterval(timer);
    timer = null;
    playButton.textContent = "Play";
  }
  function play() {
    if (frame >= T - 1) {
      setFrame(0);
    }
    last = performance.now();
    pending = 0;
    timer = setInterval(() => {
      const now = performance.now();
      pending += ((now - last) / 1000) * framesPerSecond * Number(speed.value);
      last = now;
      const step = Math.floor(pending);
      if (step > 0) {
        pending -= step;
        setFrame(frame + step);
        if (frame >= T - 1) {
          pause();
        }
      }
    }, 33);
    playButton.textContent = "Pause";
  }
  playButton.addEventListener("click", () => (timer === null ? play() : pause()));
  slider.addEventListener("input", () => setFrame(Number(slider.value)));

  for (const c of columns) {
    const option = document.createElement("option");
    option.value = c.name;
    option.textContent = c.name;
    colourBy.appendChild(option);
  }
  if (columns.length > 0) {
    colourBy.value = columns[0].name;
    colourColumn = columns[0];
  }
  colourBy.addEventListener("change", () => {
    colourColumn = columns.find((c) => c.name === colourBy.value) || null;
    buildLegend();
    draw();
  });

  document.getElementById("reset-view").addEventListener("click", () => {
    resetView();
    draw();
  });

  let drag = null;
  canvas.addEventListener("pointerdown", (e) => {
    drag = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
    canvas.classList.add("dragging");
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!drag) {
      return;
    }
    rotate("up", (e.clientX - drag[0]) * 0.01);
    rotate("right", (e.clientY - drag[1]) * 0.01);
    drag = [e.clientX, e.clientY];
    draw();
  });
  const endDrag = () => {
    drag = null;
    canvas.classList.remove("dragging");
  };
  canvas.addEventListener("pointerup", endDrag);
  canvas.addEventListener("pointercancel", endDrag);
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    zoom = Math.min(1000, Math.max(0.01, zoom * Math.exp(-0.0015 * e.deltaY)));
    draw();
  }, { passive: false });
  window.addEventListener("resize", () => {
    resize();
    draw();
  });

  resize();
  buildLegend();
  setFrame(0);
})();
