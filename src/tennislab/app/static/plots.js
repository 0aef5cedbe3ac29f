/* tennislab plots: court top and side views (SVG), a 3-D view (canvas, drag to rotate) and a heat map.
   Vanilla JS, no dependencies. Court frame: origin at the net centre on the ground, x toward the far
   baseline, y across (left when facing +x), z up; all lengths in metres. */
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
const COLORS = ["#f3722c", "#ffd400", "#4cc9f0", "#f72585", "#b5e48c", "#ffffff", "#c77dff", "#90be6d"];

/* The width [CSS px] a plot is drawn at: its container's, so that it fills the column and one unit of the
   drawing is one pixel on screen (labels keep their size at 390 px as at 1400 px); 760 while hidden. */
function fitWidth(el, fallback = 760) {
  const box = el && el.parentElement, w = box ? box.clientWidth : 0;
  return Math.max(260, Math.round(w || fallback));
}
/* The colours of a court surface (the figures' colours, from the server); hard when unknown. */
function surfaceColors(court, surface) {
  const all = court.surfaces || {};
  return all[surface] || all.hard || {court: "#3d6fa3", surround: "#4f7f4a"};
}

function svgEl(tag, attrs, parent) {
  const e = document.createElementNS(SVGNS, tag);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (parent) parent.appendChild(e);
  return e;
}

/* Axes: a linear map from data (u, v) to pixels inside an SVG, with optional equal aspect. */
class Axes {
  constructor(svg, width, height, urange, vrange, opts = {}) {
    this.svg = svg;
    this.W = width; this.H = height;
    this.pad = opts.pad || [34, 10, 10, 30]; // left, top, right, bottom
    svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
    svg.setAttribute("width", "100%");
    svg.style.maxWidth = width + "px";
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    const [l, t, r, b] = this.pad;
    const pw = width - l - r, ph = height - t - b;
    let [u0, u1] = urange, [v0, v1] = vrange;
    let su = pw / (u1 - u0), sv = ph / (v1 - v0);
    if (opts.equal) {
      const s = Math.min(su, sv);
      const cu = (u0 + u1) / 2, cv = (v0 + v1) / 2;
      u0 = cu - pw / s / 2; u1 = cu + pw / s / 2; v0 = cv - ph / s / 2; v1 = cv + ph / s / 2;
      su = sv = s;
    }
    Object.assign(this, {u0, u1, v0, v1, su, sv, l, t});
    svg.tlAxes = this;  // read by the export and by the tests (is everything drawn inside?)
    // the court and the data are clipped to the plotting area (a court far larger than a zoom's window
    // stays out of the margins where the ticks are)
    const clipId = `clip-${svg.id || "plot"}`;
    const defs = svgEl("defs", {}, svg), clip = svgEl("clipPath", {id: clipId}, defs);
    svgEl("rect", {x: l, y: t, width: pw, height: ph}, clip);
    this.layers = {
      back: svgEl("g", {class: "back", "clip-path": `url(#${clipId})`}, svg),
      data: svgEl("g", {class: "data", "clip-path": `url(#${clipId})`}, svg),
      front: svgEl("g", {class: "front"}, svg),
    };
  }
  px(u) { return this.l + (u - this.u0) * this.su; }
  py(v) { return this.t + (this.v1 - v) * this.sv; }
  /* pixel (client) -> data */
  fromClient(evt) {
    const pt = this.svg.createSVGPoint();
    pt.x = evt.clientX; pt.y = evt.clientY;
    const p = pt.matrixTransform(this.svg.getScreenCTM().inverse());
    return [this.u0 + (p.x - this.l) / this.su, this.v1 - (p.y - this.t) / this.sv];
  }
  rect(u0, u1, v0, v1, attrs, layer = "back") {
    return svgEl("rect", Object.assign({x: this.px(u0), y: this.py(v1), width: Math.max(0.5, (u1 - u0) * this.su),
      height: Math.max(0.5, (v1 - v0) * this.sv)}, attrs), this.layers[layer]);
  }
  line(u0, v0, u1, v1, attrs, layer = "back") {
    return svgEl("line", Object.assign({x1: this.px(u0), y1: this.py(v0), x2: this.px(u1), y2: this.py(v1)}, attrs),
      this.layers[layer]);
  }
  path(pts, attrs, layer = "data") {
    const d = pts.map((p, i) => (i ? "L" : "M") + this.px(p[0]).toFixed(1) + "," + this.py(p[1]).toFixed(1)).join("");
    return svgEl("path", Object.assign({d, fill: "none"}, attrs), this.layers[layer]);
  }
  dot(u, v, r, attrs, layer = "data") {
    return svgEl("circle", Object.assign({cx: this.px(u), cy: this.py(v), r}, attrs), this.layers[layer]);
  }
  text(u, v, s, attrs, layer = "front") {
    const e = svgEl("text", Object.assign({x: this.px(u), y: this.py(v)}, attrs), this.layers[layer]);
    e.textContent = s;
    return e;
  }
  /* about one tick per 60 px of the axis */
  nTicks(px) { return Math.max(3, Math.round(px / 60)); }
  ticks(ustep, vstep, ulabel, vlabel) {
    const g = this.layers.front;
    const b = this.py(this.v0), lft = this.px(this.u0);
    for (let u = Math.ceil(this.u0 / ustep) * ustep; u <= this.u1; u += ustep) {
      svgEl("line", {x1: this.px(u), x2: this.px(u), y1: b, y2: b + 4, class: "tick"}, g);
      const t = svgEl("text", {x: this.px(u), y: b + 14, class: "ticklabel", "text-anchor": "middle"}, g);
      t.textContent = +u.toFixed(2);
    }
    for (let v = Math.ceil(this.v0 / vstep) * vstep; v <= this.v1; v += vstep) {
      if (vlabel && this.py(v) < this.t + 16) continue;  // the axis label's place
      svgEl("line", {x1: lft - 4, x2: lft, y1: this.py(v), y2: this.py(v), class: "tick"}, g);
      const t = svgEl("text", {x: lft - 6, y: this.py(v) + 3, class: "ticklabel", "text-anchor": "end"}, g);
      t.textContent = +v.toFixed(2);
    }
    if (ulabel) { const t = svgEl("text", {x: this.W - 8, y: b + 27, class: "axislabel", "text-anchor": "end"}, g); t.textContent = ulabel; }
    if (vlabel) { const t = svgEl("text", {x: 2, y: this.t + 10, class: "axislabel"}, g); t.textContent = vlabel; }
  }
}

/* Range [lo, hi] of values vs, widened to contain [a, b] and padded by pad (for framing). */
function span(vs, a, b, pad) {
  let lo = a, hi = b;
  for (const v of vs) if (Number.isFinite(v)) { lo = Math.min(lo, v - pad); hi = Math.max(hi, v + pad); }
  return [lo, hi];
}
function niceStep(range, n) {
  const raw = range / n, p = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}

/* Court top view (x right, y up) in the colours of opts.surface, as wide as its container (opts.width
   to fix it; opts.aspect = height / width). opts.window = [x0, x1, y0, y1] to zoom; otherwise the court
   and every point of opts.points ([[x, y], ...]) are framed. */
function courtTop(svg, court, opts = {}) {
  const L = court.half_length, d = court.doubles_width / 2, m = opts.margin ?? 3;
  const pts = opts.points || [];
  const [x0, x1] = span(pts.map(p => p[0]), -L - m, L + m, 1);
  const [y0, y1] = span(pts.map(p => p[1]), -d - m, d + m, 1);
  const win = opts.window || [x0, x1, y0, y1];
  const W = opts.width || fitWidth(svg), H = opts.height || Math.round(W * (opts.aspect || 0.56));
  const ax = new Axes(svg, W, H, [win[0], win[1]], [win[2], win[3]], {equal: true, pad: opts.pad || [38, 8, 8, 32]});
  const col = surfaceColors(court, opts.surface);
  ax.rect(ax.u0, ax.u1, ax.v0, ax.v1, {class: "surround", fill: col.surround});  // attributes: the CSP allows no inline style
  ax.rect(-L, L, -d, d, {class: "court", fill: col.court});
  for (const [name, r] of Object.entries(court.lines)) ax.rect(r[0], r[1], r[2], r[3], {class: "cline", "data-line": name});
  ax.line(0, -court.y_post, 0, court.y_post, {class: "net"});
  const t = opts.tick || niceStep(ax.u1 - ax.u0, ax.nTicks(W - 50));
  ax.ticks(t, t, "x [m]", "y [m]");
  return ax;
}

/* Court side view (x right, z up), as wide as its container: frames the court and every point of
   opts.points ([[x, z], ...]); the ground in the colour of opts.surface. */
function courtSide(svg, court, opts = {}) {
  const L = court.half_length, m = opts.margin ?? 3;
  const pts = opts.points || [];
  const urange = opts.urange || span(pts.map(p => p[0]), -L - m, L + m, 1);
  const zmax = Math.max(opts.zmax || 3, ...pts.map(p => p[1] * 1.08 + 0.3).filter(Number.isFinite));
  const W = opts.width || fitWidth(svg), H = opts.height || Math.max(170, Math.round(W * 0.3));
  const ax = new Axes(svg, W, H, urange, [0, zmax], {pad: [38, 8, 8, 32]});
  ax.rect(ax.u0, ax.u1, 0, ax.v1, {class: "sky"});
  for (const x of [-L, L, -court.service_line, court.service_line]) ax.line(x, 0, x, ax.v1, {class: "guide"});
  ax.line(ax.u0, 0, ax.u1, 0, {class: "ground", stroke: surfaceColors(court, opts.surface).court});
  ax.line(0, 0, 0, court.net_center_height, {class: "net"});
  ax.ticks(niceStep(ax.u1 - ax.u0, ax.nTicks(W - 50)), niceStep(zmax, ax.nTicks(H - 40) > 5 ? 5 : 3), "x [m]", "z [m]");
  return ax;
}

/* A simple orthographic 3-D view of the court with trajectories; drag to rotate. */
class View3D {
  constructor(canvas, court) {
    this.c = canvas; this.court = court; this.yaw = -0.55; this.pitch = 0.42; this.tracks = [];
    this.marks = [];
    let drag = null;
    canvas.addEventListener("pointerdown", e => { drag = [e.clientX, e.clientY, this.yaw, this.pitch]; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener("pointermove", e => {
      if (!drag) return;
      this.yaw = drag[2] + (e.clientX - drag[0]) * 0.01;
      this.pitch = Math.max(0.02, Math.min(1.5, drag[3] + (e.clientY - drag[1]) * 0.01));
      this.draw();
    });
    canvas.addEventListener("pointerup", () => { drag = null; });
    canvas.tlView = this;  // read by the tests (is everything drawn inside?)
    this.draw();
  }
  /* view coordinates [m] of a court point: turned about z by yaw, tilted toward the viewer by pitch */
  view(p) {
    const cy = Math.cos(this.yaw), sy = Math.sin(this.yaw), cp = Math.cos(this.pitch), sp = Math.sin(this.pitch);
    const xr = p[0] * cy - p[1] * sy, yr = p[0] * sy + p[1] * cy;
    return [xr, p[2] * cp + yr * sp];
  }
  /* Scale and centre so that the court, the net and every point of every track (and its shadow) fit. */
  frame() {
    const ct = this.court, L = ct.half_length + 1, d = ct.doubles_width / 2 + 1;
    const pts = [[-L, -d, 0], [L, -d, 0], [L, d, 0], [-L, d, 0], [0, -ct.y_post, ct.net_post_height], [0, ct.y_post, ct.net_post_height]];
    for (const t of this.tracks) for (const p of (t.points || [])) { pts.push(p); pts.push([p[0], p[1], 0]); }
    let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    for (const p of pts) { const [u, v] = this.view(p); u0 = Math.min(u0, u); u1 = Math.max(u1, u); v0 = Math.min(v0, v); v1 = Math.max(v1, v); }
    const W = this.c.width, H = this.c.height, pad = 12, bottom = 22;   // room for the hint text
    const s = Math.min((W - 2 * pad) / Math.max(u1 - u0, 1e-6), (H - pad - bottom) / Math.max(v1 - v0, 1e-6));
    this.fit = {s, uc: (u0 + u1) / 2, vc: (v0 + v1) / 2, xc: W / 2, yc: pad + (H - pad - bottom) / 2};
  }
  project(p) {
    const [u, v] = this.view(p), f = this.fit;
    return [f.xc + (u - f.uc) * f.s, f.yc - (v - f.vc) * f.s];
  }
  poly(pts, stroke, width = 1, fill = null) {
    const g = this.g; g.beginPath();
    pts.forEach((p, i) => { const q = this.project(p); i ? g.lineTo(q[0], q[1]) : g.moveTo(q[0], q[1]); });
    if (fill) { g.closePath(); g.fillStyle = fill; g.fill(); }
    if (stroke) { g.strokeStyle = stroke; g.lineWidth = width; g.stroke(); }
  }
  setTracks(tracks, surface) { this.tracks = tracks || []; if (surface !== undefined) this.surface = surface; this.draw(); }
  /* the drawing buffer as large as the canvas is shown (one unit one pixel: sharp, labels their size) */
  fitSize() {
    const w = Math.round(this.c.clientWidth);
    if (w > 0 && Math.abs(w - this.c.width) > 1) { this.c.width = w; this.c.height = Math.round(Math.min(w * 0.55, 460)); }
  }
  draw() {
    this.fitSize();
    const g = this.g = this.c.getContext("2d"), ct = this.court, col = surfaceColors(ct, this.surface);
    this.frame();
    g.fillStyle = col.surround; g.fillRect(0, 0, this.c.width, this.c.height);
    const L = ct.half_length, d = ct.doubles_width / 2;
    this.poly([[-L, -d, 0], [L, -d, 0], [L, d, 0], [-L, d, 0]], null, 1, col.court);
    for (const r of Object.values(ct.lines)) {
      const x0 = r[0], x1 = r[1], y0 = r[2], y1 = r[3];
      this.poly([[x0, y0, 0], [x1, y0, 0], [x1, y1, 0], [x0, y1, 0]], "#ffffff", 1, "#ffffff");
    }
    const yp = ct.y_post, hc = ct.net_center_height, hp = ct.net_post_height;
    this.poly([[0, -yp, 0], [0, -yp, hp], [0, 0, hc], [0, yp, hp], [0, yp, 0]], "#eeeeee", 1.5, "rgba(30,30,30,0.55)");
    this.tracks.forEach((t, i) => {
      const col = t.color || COLORS[i % COLORS.length];
      if (!t.points || !t.points.length) return;
      this.poly(t.points.map(p => [p[0], p[1], 0]), "rgba(0,0,0,0.35)", 1.5);   // shadow
      this.poly(t.points, col, 2.5);
      const last = this.project(t.points[t.points.length - 1]);
      this.g.fillStyle = col; this.g.beginPath(); this.g.arc(last[0], last[1], 4, 0, 7); this.g.fill();
    });
    g.fillStyle = "#ffffff"; g.font = "13px sans-serif";
    g.fillText("drag to rotate", 8, this.c.height - 8);
  }
}

/* Heat map of a serve window: code[i_beta][i_alpha] category codes, click picks a cell.  Drawn where the
   window is (data.span: the successes and a few degrees around them, from the server), as wide as the
   canvas is shown, with ticks at round angles. */
class HeatMap {
  constructor(canvas, onPick) {
    this.c = canvas; this.onPick = onPick; this.data = null; this.sel = null;
    canvas.tlHeat = this;  // read by the tests (where is a cell drawn?)
    const cellOf = e => {  // client -> canvas pixels, inside the border
      const r = canvas.getBoundingClientRect(), x = e.clientX - r.left - canvas.clientLeft, y = e.clientY - r.top - canvas.clientTop;
      return this.cellAt(x * canvas.width / canvas.clientWidth, y * canvas.height / canvas.clientHeight);
    };
    canvas.addEventListener("click", e => {
      if (!this.data) return;
      const cell = cellOf(e);
      if (cell) { this.sel = cell; this.draw(); this.onPick(this.data.alpha[cell[0]], this.data.beta[cell[1]]); }
    });
    canvas.addEventListener("mousemove", e => {
      if (!this.data) return;
      const cell = cellOf(e);
      if (!cell) { canvas.title = ""; return; }
      const d = this.data, code = d.code[cell[1]][cell[0]];
      const lab = (d.legend.find(l => l.code === code) || {}).label || "";
      canvas.title = `α ${d.alpha[cell[0]]} deg, β ${d.beta[cell[1]]} deg: ${lab}`;
    });
  }
  fitSize() {
    const w = Math.round(this.c.clientWidth);
    if (w > 0 && Math.abs(w - this.c.width) > 1) { this.c.width = w; this.c.height = Math.round(Math.min(Math.max(w * 0.7, 260), 480)); }
  }
  /* index ranges [i0, i1] of the alpha and beta cells shown */
  shown() {
    const d = this.data, sp = d.span || {};
    const lo = (arr, v) => { const k = arr.findIndex(x => x >= v - 1e-9); return k < 0 ? 0 : k; };
    const hi = (arr, v) => { let k = arr.length - 1; while (k > 0 && arr[k] > v + 1e-9) k--; return k; };
    return {
      a0: sp.alpha_lo === undefined ? 0 : lo(d.alpha, sp.alpha_lo), a1: sp.alpha_hi === undefined ? d.alpha.length - 1 : hi(d.alpha, sp.alpha_hi),
      b0: sp.beta_lo === undefined ? 0 : lo(d.beta, sp.beta_lo), b1: sp.beta_hi === undefined ? d.beta.length - 1 : hi(d.beta, sp.beta_hi),
    };
  }
  geom() { const pad = [50, 10, 12, 42]; return {l: pad[0], t: pad[1], w: this.c.width - pad[0] - pad[2], h: this.c.height - pad[1] - pad[3]}; }
  cellAt(px, py) {
    const gm = this.geom(), v = this.shown(), na = v.a1 - v.a0 + 1, nb = v.b1 - v.b0 + 1;
    const i = Math.floor((px - gm.l) / gm.w * na), j = Math.floor((gm.t + gm.h - py) / gm.h * nb);
    return (i >= 0 && i < na && j >= 0 && j < nb) ? [i + v.a0, j + v.b0] : null;
  }
  /* canvas pixel of the centre of cell (i_alpha, i_beta) */
  cellCenter(i, j) {
    const gm = this.geom(), v = this.shown(), na = v.a1 - v.a0 + 1, nb = v.b1 - v.b0 + 1;
    return [gm.l + (i - v.a0 + 0.5) * gm.w / na, gm.t + gm.h - (j - v.b0 + 0.5) * gm.h / nb];
  }
  set(data) { this.data = data; this.sel = null; this.draw(); }
  select(alpha, beta) {
    if (!this.data) return;
    const near = (arr, v) => arr.reduce((b, x, k) => Math.abs(x - v) < Math.abs(arr[b] - v) ? k : b, 0);
    this.sel = [near(this.data.alpha, alpha), near(this.data.beta, beta)]; this.draw();
  }
  draw() {
    this.fitSize();
    const g = this.c.getContext("2d"), gm = this.geom();
    g.fillStyle = "#fff"; g.fillRect(0, 0, this.c.width, this.c.height);
    if (!this.data) return;
    const d = this.data, v = this.shown(), na = v.a1 - v.a0 + 1, nb = v.b1 - v.b0 + 1, cw = gm.w / na, ch = gm.h / nb;
    const pal = d.palette;
    for (let j = v.b0; j <= v.b1; j++) for (let i = v.a0; i <= v.a1; i++) {
      g.fillStyle = pal[d.code[j][i]] || "#eee";
      g.fillRect(gm.l + (i - v.a0) * cw, gm.t + gm.h - (j - v.b0 + 1) * ch, Math.ceil(cw), Math.ceil(ch));
    }
    g.strokeStyle = "#333"; g.strokeRect(gm.l, gm.t, gm.w, gm.h);
    g.fillStyle = "#222"; g.font = "12px sans-serif"; g.textAlign = "center";
    const a0 = d.alpha[v.a0] - d.step / 2, a1 = d.alpha[v.a1] + d.step / 2, b0 = d.beta[v.b0] - d.step / 2, b1 = d.beta[v.b1] + d.step / 2;
    const as = niceStep(a1 - a0, Math.max(3, Math.round(gm.w / 60))), bs = niceStep(b1 - b0, Math.max(3, Math.round(gm.h / 40)));
    for (let a = Math.ceil(a0 / as) * as; a <= a1; a += as) {
      const x = gm.l + (a - a0) / (a1 - a0) * gm.w;
      g.fillRect(x, gm.t + gm.h, 1, 4); g.fillText(+a.toFixed(1), x, gm.t + gm.h + 16);
    }
    g.fillText("impact angle α [deg]", gm.l + gm.w / 2, gm.t + gm.h + 34);
    g.textAlign = "right";
    for (let b = Math.ceil(b0 / bs) * bs; b <= b1; b += bs) {
      const y = gm.t + gm.h - (b - b0) / (b1 - b0) * gm.h;
      g.fillRect(gm.l - 4, y, 4, 1); g.fillText(+b.toFixed(1), gm.l - 6, y + 4);
    }
    g.save(); g.translate(13, gm.t + gm.h / 2); g.rotate(-Math.PI / 2); g.textAlign = "center"; g.fillText("face angle β [deg]", 0, 0); g.restore();
    if (this.sel && this.sel[0] >= v.a0 && this.sel[0] <= v.a1 && this.sel[1] >= v.b0 && this.sel[1] <= v.b1) {
      const [x, y] = this.cellCenter(this.sel[0], this.sel[1]);
      g.strokeStyle = "#000"; g.lineWidth = 2; g.strokeRect(x - Math.max(cw, 6) / 2 - 1, y - Math.max(ch, 6) / 2 - 1, Math.max(cw, 6) + 2, Math.max(ch, 6) + 2);
      g.lineWidth = 1;
    }
  }
}

/* A legend under a plot: items [{kind: "line" | "dash" | "dot" | "ring" | "square" | "patch" | "cross", color, label}]. */
function legend(el, items) {
  el.replaceChildren();
  for (const it of items) {
    const span = document.createElement("span"); span.className = "legend-entry";
    const sw = svgEl("svg", {width: 18, height: 12, viewBox: "0 0 18 12", class: "legend-swatch"});
    const c = it.color || "#333";
    if (it.kind === "line" || it.kind === "dash") svgEl("line", {x1: 1, y1: 6, x2: 17, y2: 6, stroke: c, "stroke-width": 3, "stroke-dasharray": it.kind === "dash" ? "4 2" : "none"}, sw);
    else if (it.kind === "dot") svgEl("circle", {cx: 9, cy: 6, r: 4, fill: c, stroke: "#000"}, sw);
    else if (it.kind === "ring") svgEl("circle", {cx: 9, cy: 6, r: 4, fill: "none", stroke: c, "stroke-width": 2}, sw);
    else if (it.kind === "square") svgEl("rect", {x: 4, y: 1, width: 10, height: 10, fill: c, stroke: "#fff"}, sw);
    else if (it.kind === "cross") { svgEl("line", {x1: 4, y1: 2, x2: 14, y2: 10, stroke: c, "stroke-width": 2}, sw); svgEl("line", {x1: 14, y1: 2, x2: 4, y2: 10, stroke: c, "stroke-width": 2}, sw); }
    else svgEl("rect", {x: 1, y: 1, width: 16, height: 10, fill: c, stroke: "#555"}, sw);
    const t = document.createElement("span"); t.textContent = it.label;
    span.append(sw, t); el.appendChild(span);
  }
}

/* PNG of a plot: a canvas as it is; an SVG drawn on a canvas at twice its size, with the page's CSS
   copied into presentation attributes (the image is rendered without the page's style sheet). */
const STYLE_PROPS = ["fill", "stroke", "stroke-width", "stroke-dasharray", "opacity", "font-size", "font-family", "font-weight"];
function canvasBlob(canvas) { return new Promise(res => canvas.toBlob(res, "image/png")); }
async function plotPNG(el) {
  if (el instanceof HTMLCanvasElement) return canvasBlob(el);
  const clone = el.cloneNode(true), src = el.querySelectorAll("*"), dst = clone.querySelectorAll("*");
  src.forEach((e, i) => { const cs = getComputedStyle(e); for (const p of STYLE_PROPS) { const v = cs.getPropertyValue(p); if (v) dst[i].setAttribute(p, v); } });
  const vb = el.viewBox.baseVal, k = 2;
  clone.setAttribute("xmlns", SVGNS); clone.setAttribute("width", vb.width); clone.setAttribute("height", vb.height);
  clone.removeAttribute("style");
  const url = URL.createObjectURL(new Blob([new XMLSerializer().serializeToString(clone)], {type: "image/svg+xml"}));
  try {
    const img = new Image();
    await new Promise((res, rej) => { img.onload = res; img.onerror = () => rej(new Error("cannot draw the plot")); img.src = url; });
    const c = document.createElement("canvas"); c.width = vb.width * k; c.height = vb.height * k;
    const g = c.getContext("2d"); g.fillStyle = "#fff"; g.fillRect(0, 0, c.width, c.height);
    g.drawImage(img, 0, 0, c.width, c.height);
    return canvasBlob(c);
  } finally { URL.revokeObjectURL(url); }
}

window.TLPlots = {Axes, courtTop, courtSide, View3D, HeatMap, COLORS, svgEl, plotPNG, legend, surfaceColors};
