/* tennislab plots: court top and side views (SVG), a 3-D view (canvas, drag to rotate) and a heat map.
   Vanilla JS, no dependencies. Court frame: origin at the net centre on the ground, x toward the far
   baseline, y across (left when facing +x), z up; all lengths in metres. */
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
const COLORS = ["#f3722c", "#ffd400", "#4cc9f0", "#f72585", "#b5e48c", "#ffffff", "#c77dff", "#90be6d"];

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
    this.layers = {
      back: svgEl("g", {class: "back"}, svg), data: svgEl("g", {class: "data"}, svg),
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
  ticks(ustep, vstep, ulabel, vlabel) {
    const g = this.layers.front;
    const b = this.py(this.v0), lft = this.px(this.u0);
    for (let u = Math.ceil(this.u0 / ustep) * ustep; u <= this.u1; u += ustep) {
      svgEl("line", {x1: this.px(u), x2: this.px(u), y1: b, y2: b + 4, class: "tick"}, g);
      const t = svgEl("text", {x: this.px(u), y: b + 14, class: "ticklabel", "text-anchor": "middle"}, g);
      t.textContent = +u.toFixed(2);
    }
    for (let v = Math.ceil(this.v0 / vstep) * vstep; v <= this.v1; v += vstep) {
      svgEl("line", {x1: lft - 4, x2: lft, y1: this.py(v), y2: this.py(v), class: "tick"}, g);
      const t = svgEl("text", {x: lft - 6, y: this.py(v) + 3, class: "ticklabel", "text-anchor": "end"}, g);
      t.textContent = +v.toFixed(2);
    }
    if (ulabel) { const t = svgEl("text", {x: this.W - 12, y: b + 26, class: "axislabel", "text-anchor": "end"}, g); t.textContent = ulabel; }
    if (vlabel) { const t = svgEl("text", {x: 4, y: this.t + 8, class: "axislabel"}, g); t.textContent = vlabel; }
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

/* Court top view (x right, y up). opts.window = [x0, x1, y0, y1] to zoom; otherwise the court and
   every point of opts.points ([[x, y], ...]) are framed. */
function courtTop(svg, court, opts = {}) {
  const L = court.half_length, d = court.doubles_width / 2, m = opts.margin ?? 3;
  const pts = opts.points || [];
  const [x0, x1] = span(pts.map(p => p[0]), -L - m, L + m, 1);
  const [y0, y1] = span(pts.map(p => p[1]), -d - m, d + m, 1);
  const win = opts.window || [x0, x1, y0, y1];
  const ax = new Axes(svg, opts.width || 760, opts.height || 400, [win[0], win[1]], [win[2], win[3]],
    {equal: true, pad: opts.pad || [34, 8, 8, 28]});
  ax.rect(ax.u0, ax.u1, ax.v0, ax.v1, {class: "surround"});
  ax.rect(-L, L, -d, d, {class: "court"});
  for (const [name, r] of Object.entries(court.lines)) ax.rect(r[0], r[1], r[2], r[3], {class: "cline", "data-line": name});
  ax.line(0, -court.y_post, 0, court.y_post, {class: "net"});
  const t = opts.tick || niceStep(Math.max(ax.u1 - ax.u0, ax.v1 - ax.v0), 14);
  ax.ticks(t, t, "x [m]", "y [m]");
  return ax;
}

/* Court side view (x right, z up): frames the court and every point of opts.points ([[x, z], ...]). */
function courtSide(svg, court, opts = {}) {
  const L = court.half_length, m = opts.margin ?? 3;
  const pts = opts.points || [];
  const urange = opts.urange || span(pts.map(p => p[0]), -L - m, L + m, 1);
  const zmax = Math.max(opts.zmax || 3, ...pts.map(p => p[1] * 1.08 + 0.3).filter(Number.isFinite));
  const ax = new Axes(svg, opts.width || 760, opts.height || 200, urange, [0, zmax], {pad: [34, 8, 8, 28]});
  ax.rect(ax.u0, ax.u1, 0, ax.v1, {class: "sky"});
  for (const x of [-L, L, -court.service_line, court.service_line]) ax.line(x, 0, x, ax.v1, {class: "guide"});
  ax.line(ax.u0, 0, ax.u1, 0, {class: "ground"});
  ax.line(0, 0, 0, court.net_center_height, {class: "net"});
  ax.ticks(niceStep(ax.u1 - ax.u0, 14), niceStep(zmax, 5), "x [m]", "z [m]");
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
  setTracks(tracks) { this.tracks = tracks || []; this.draw(); }
  draw() {
    const g = this.g = this.c.getContext("2d"), ct = this.court;
    this.frame();
    g.fillStyle = "#1d3b24"; g.fillRect(0, 0, this.c.width, this.c.height);
    const L = ct.half_length, d = ct.doubles_width / 2;
    this.poly([[-L, -d, 0], [L, -d, 0], [L, d, 0], [-L, d, 0]], null, 1, "#3a7d44");
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
    g.fillStyle = "#cccccc"; g.font = "12px sans-serif";
    g.fillText("drag to rotate", 8, this.c.height - 8);
  }
}

/* Heat map of a serve window: values[i_beta][i_alpha] category codes, click picks a cell. */
class HeatMap {
  constructor(canvas, onPick) {
    this.c = canvas; this.onPick = onPick; this.data = null; this.sel = null;
    const cellOf = e => {
      const r = canvas.getBoundingClientRect();
      return this.cellAt((e.clientX - r.left) * canvas.width / r.width, (e.clientY - r.top) * canvas.height / r.height);
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
  geom() { const pad = [40, 10, 10, 34]; return {l: pad[0], t: pad[1], w: this.c.width - pad[0] - pad[2], h: this.c.height - pad[1] - pad[3]}; }
  cellAt(px, py) {
    const gm = this.geom(), na = this.data.alpha.length, nb = this.data.beta.length;
    const i = Math.floor((px - gm.l) / gm.w * na), j = Math.floor((gm.t + gm.h - py) / gm.h * nb);
    return (i >= 0 && i < na && j >= 0 && j < nb) ? [i, j] : null;
  }
  cellCenter(i, j) {
    const gm = this.geom(), na = this.data.alpha.length, nb = this.data.beta.length;
    return [gm.l + (i + 0.5) * gm.w / na, gm.t + gm.h - (j + 0.5) * gm.h / nb];
  }
  set(data) { this.data = data; this.sel = null; this.draw(); }
  select(alpha, beta) {
    if (!this.data) return;
    const near = (arr, v) => arr.reduce((b, x, k) => Math.abs(x - v) < Math.abs(arr[b] - v) ? k : b, 0);
    this.sel = [near(this.data.alpha, alpha), near(this.data.beta, beta)]; this.draw();
  }
  draw() {
    const g = this.c.getContext("2d"), gm = this.geom();
    g.fillStyle = "#fff"; g.fillRect(0, 0, this.c.width, this.c.height);
    if (!this.data) return;
    const d = this.data, na = d.alpha.length, nb = d.beta.length, cw = gm.w / na, ch = gm.h / nb;
    const pal = d.palette;
    for (let j = 0; j < nb; j++) for (let i = 0; i < na; i++) {
      g.fillStyle = pal[d.code[j][i]] || "#eee";
      g.fillRect(gm.l + i * cw, gm.t + gm.h - (j + 1) * ch, Math.ceil(cw), Math.ceil(ch));
    }
    g.strokeStyle = "#333"; g.strokeRect(gm.l, gm.t, gm.w, gm.h);
    g.fillStyle = "#222"; g.font = "11px sans-serif"; g.textAlign = "center";
    for (let a = 0; a <= 90; a += 15) { const x = gm.l + (a - d.alpha[0] + d.step / 2) / (d.step * na) * gm.w; g.fillText(a, x, gm.t + gm.h + 13); }
    g.fillText("impact angle α [deg]", gm.l + gm.w / 2, gm.t + gm.h + 28);
    g.textAlign = "right";
    for (let b = 0; b <= 90; b += 15) { const y = gm.t + gm.h - (b - d.beta[0] + d.step / 2) / (d.step * nb) * gm.h; g.fillText(b, gm.l - 4, y + 4); }
    g.save(); g.translate(11, gm.t + gm.h / 2); g.rotate(-Math.PI / 2); g.textAlign = "center"; g.fillText("face angle β [deg]", 0, 0); g.restore();
    if (this.sel) {
      const [x, y] = this.cellCenter(this.sel[0], this.sel[1]);
      g.strokeStyle = "#000"; g.lineWidth = 2; g.strokeRect(x - Math.max(cw, 6) / 2 - 1, y - Math.max(ch, 6) / 2 - 1, Math.max(cw, 6) + 2, Math.max(ch, 6) + 2);
      g.lineWidth = 1;
    }
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

window.TLPlots = {Axes, courtTop, courtSide, View3D, HeatMap, COLORS, svgEl, plotPNG};
