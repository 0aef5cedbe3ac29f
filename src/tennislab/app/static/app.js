/* tennislab app: forms built from the server's field definitions, validated here and on the server. */
"use strict";
const P = window.TLPlots;
const state = {meta: null, drill: [], lastAim: null, serveView: null, flightView: null, window: null};

function $(sel) { return document.querySelector(sel); }
function fmt(x, d = 2) { return (x === null || x === undefined || Number.isNaN(x)) ? "–" : Number(x).toFixed(d); }

/* ---------- field validation (mirrors tennislab.app.fields.Field.parse and errors.check_range) ---------- */
function fmtG(v) {            /* Python's format(v, "g") */
  if (v === 0) return "0";
  const e = Math.floor(Math.log10(Math.abs(v)));
  if (e < -4 || e >= 6) {
    return v.toExponential(5).replace(/\.?0+e/, "e").replace(/e([+-])(\d)$/, "e$10$2");
  }
  let s = v.toPrecision(6);
  if (s.includes(".")) s = s.replace(/\.?0+$/, "");
  return s;
}
function pyFloat(x) { return Number.isInteger(x) ? x.toFixed(1) : String(x); }   /* str(float) */
function fieldError(f, raw) {
  if (f.kind === "choice") return f.choices.includes(raw) ? "" : `${f.name}: '${raw}' is not one of ${f.choices.join(", ")}`;
  if (raw === "" || raw === null || raw === undefined) return f.optional ? "" : `${f.name}: a value is required`;
  const v = Number(raw);
  if (String(raw).trim() === "" || Number.isNaN(v)) return `${f.name}: expected a number, got '${raw}'`;
  if (!Number.isFinite(v)) return `${f.name}: must be a finite number, got '${raw}'`;
  const u = f.unit ? " " + f.unit : "";
  const badLo = f.lo !== null && (f.lo_open ? v <= f.lo : v < f.lo), badHi = f.hi !== null && v > f.hi;
  if (badLo || badHi) {
    const lo = f.lo === null ? "-inf" : pyFloat(f.lo), hi = f.hi === null ? "inf" : pyFloat(f.hi);
    return `${f.name}: ${fmtG(v)}${u} is outside the allowed range ${f.lo_open ? "(" : "["}${lo}, ${hi}]${u}`;
  }
  if (f.kind === "int" && !Number.isInteger(v)) return `${f.name}: expected a whole number, got '${raw}'`;
  return "";
}

function buildForm(formName, container, onSubmit, submitLabel = "compute") {
  const specs = state.meta.forms[formName];
  const form = document.createElement("form");
  form.id = "form-" + formName; form.noValidate = true; form.className = "tlform";
  for (const f of specs) {
    const row = document.createElement("div"); row.className = "field";
    const lab = document.createElement("label"); lab.htmlFor = `${formName}-${f.name}`;
    lab.textContent = f.label + (f.unit ? ` [${f.unit}]` : "");
    let inp;
    if (f.kind === "choice") {
      inp = document.createElement("select");
      for (const c of f.choices) { const o = document.createElement("option"); o.value = o.textContent = c; inp.appendChild(o); }
      inp.value = f.default;
    } else {
      inp = document.createElement("input"); inp.type = "text"; inp.inputMode = "decimal";
      inp.value = f.default; inp.dataset.lo = f.lo; inp.dataset.hi = f.hi;
    }
    inp.id = `${formName}-${f.name}`; inp.name = f.name;
    if (f.help) inp.title = f.help;
    const err = document.createElement("div"); err.className = "field-error"; err.id = `err-${formName}-${f.name}`;
    inp.addEventListener("input", () => { err.textContent = fieldError(f, inp.value); inp.classList.toggle("bad", !!err.textContent); });
    row.append(lab, inp, err); form.appendChild(row);
  }
  const btn = document.createElement("button"); btn.type = "submit"; btn.textContent = submitLabel; btn.id = `submit-${formName}`;
  form.appendChild(btn);
  form.addEventListener("submit", e => { e.preventDefault(); onSubmit(); });
  container.appendChild(form);
  return form;
}

/* Read and validate a form: returns the body or null (messages shown under the fields). */
function readForm(formName) {
  const body = {}; let ok = true;
  for (const f of state.meta.forms[formName]) {
    const inp = document.getElementById(`${formName}-${f.name}`), err = document.getElementById(`err-${formName}-${f.name}`);
    const msg = fieldError(f, inp.value);
    err.textContent = msg; inp.classList.toggle("bad", !!msg);
    if (msg) { ok = false; continue; }
    body[f.name] = f.kind === "choice" ? inp.value : (inp.value === "" ? null : Number(inp.value));
  }
  return ok ? body : null;
}
function setField(formName, name, value) {
  const inp = document.getElementById(`${formName}-${name}`); inp.value = value;
  inp.dispatchEvent(new Event("input"));
}

async function api(path, body, statusEl) {
  if (statusEl) { statusEl.textContent = "computing…"; statusEl.className = "status busy"; }
  try {
    const r = await fetch(path, body === undefined ? {} : {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(body)});
    const j = await r.json().catch(() => ({error: `HTTP ${r.status}`}));
    if (!r.ok) throw new Error(j.error || `HTTP ${r.status}`);
    if (statusEl) { statusEl.textContent = "done"; statusEl.className = "status ok"; }
    return j;
  } catch (e) {
    if (statusEl) { statusEl.textContent = e.message; statusEl.className = "status error"; }
    return null;
  }
}

/* A result table: rows [label, value, key, unit]; each value cell carries data-key and data-value. */
function resultTable(el, rows) {
  el.innerHTML = "";
  const t = document.createElement("table"); t.className = "results";
  for (const [label, value, key, unit, digits] of rows) {
    const tr = t.insertRow(); tr.insertCell().textContent = label;
    const c = tr.insertCell(); c.dataset.key = key;
    c.dataset.value = (value === null || value === undefined) ? "" : String(value);
    c.textContent = typeof value === "number" ? fmt(value, digits ?? 2) + (unit ? " " + unit : "") : String(value ?? "–");
  }
  el.appendChild(t);
}

function unavailable(page, feature) {
  const m = state.meta.modules[feature];
  if (m && m.available) return false;
  const box = document.getElementById(`${page}-body`);
  const p = document.createElement("p"); p.className = "unavailable"; p.id = `${page}-unavailable`;
  p.textContent = `${feature}: not available in this installation${m && m.reason ? " (" + m.reason + ")" : ""}.`;
  box.replaceChildren(p);
  return true;
}

/* ---------- views shared by pages ---------- */
function drawFlight(prefix, flights, opts = {}) {
  const court = state.meta.court;
  let zmax = 3;
  for (const f of flights) for (const p of f.points) zmax = Math.max(zmax, p[2] + 0.5);
  const side = P.courtSide($(`#${prefix}-side`), court, {zmax: Math.ceil(zmax)});
  const top = P.courtTop($(`#${prefix}-top`), court, {});
  flights.forEach((f, i) => {
    const col = f.color || P.COLORS[i % P.COLORS.length];
    side.path(f.points.map(p => [p[0], p[2]]), {stroke: col, "stroke-width": 2, class: "traj"});
    top.path(f.points.map(p => [p[0], p[1]]), {stroke: col, "stroke-width": 2, class: "traj"});
    const e = f.points[f.points.length - 1];
    top.dot(e[0], e[1], 4, {fill: col, stroke: "#000", class: "landing"});
  });
  return {side, top};
}

/* ---------- flight page ---------- */
async function runFlight() {
  const body = readForm("flight"); if (!body) return;
  const r = await api("/api/flight", body, $("#flight-status")); if (!r) return;
  resultTable($("#flight-result"), [
    ["landing x", r.landing.x, "landing_x", "m", 3], ["landing y", r.landing.y, "landing_y", "m", 3],
    ["flight time", r.landing.t, "landing_t", "s", 3], ["net", r.net.result, "net_result"],
    ["net clearance", r.net.clearance, "net_clearance", "m", 3], ["apex height", r.apex.z, "apex_z", "m", 3],
    ["lands in", r.landing.areas.join(", ") || "out", "areas"],
  ]);
  drawFlight("flight", [r]);
  state.flightView.setTracks([{points: r.points}]);
}

/* ---------- serve explorer ---------- */
function applyPlayer() {
  const name = $("#serve-player").value, prof = state.meta.players[name];
  if (prof) { setField("serve", "height", prof.height); setField("serve", "racket_speed", prof.racket_speed); }
}
async function runServe() {
  const body = readForm("serve"); if (!body) return;
  const r = await api("/api/serve", body, $("#serve-status")); if (!r) return;
  resultTable($("#serve-result"), [
    ["ball speed", r.speed, "speed", "m/s", 2], ["spin", r.spin_rpm, "spin_rpm", "rpm", 0],
    ["launch angle", r.launch_angle, "launch_angle", "deg", 2], ["net clearance", r.net_clearance, "net_clearance", "m", 3],
    ["net height (ball centre)", r.net_height, "net_height", "m", 3],
    ["landing x (from the server)", r.landing_x, "landing_x", "m", 3], ["landing y", r.landing_y, "landing_y", "m", 3],
    ["category", r.category, "category"], ["success", r.success ? "yes" : "no", "success"],
    ["impact regime", r.regime ?? "–", "regime"], ["contact time", r.contact_time_ms, "contact_time_ms", "ms", 2],
  ]);
  if (r.flight) { drawFlight("serve", [r.flight]); state.serveView.setTracks([{points: r.flight.points}]); }
  if (state.heat && state.heat.data) state.heat.select(body.impact_angle, body.face_angle);
}
async function runWindow() {
  const s = readForm("serve"); if (!s) return;
  const body = {player: s.player, height: s.height, racket_speed: s.racket_speed, step: Number($("#window-step").value)};
  const msg = fieldError(state.meta.forms.window.find(f => f.name === "step"), $("#window-step").value);
  $("#err-window-step").textContent = msg; if (msg) return;
  const r = await api("/api/serve/window", body, $("#window-status")); if (!r) return;
  state.window = r; state.heat.set(r);
  state.heat.select(s.impact_angle, s.face_angle);
  const legend = $("#window-legend"); legend.innerHTML = "";
  for (const it of r.legend) {
    const sp = document.createElement("span"); sp.className = "swatch"; sp.style.background = it.color;
    const lab = document.createElement("span"); lab.textContent = ` ${it.label} (${it.n}) `; lab.dataset.code = it.code; lab.dataset.n = it.n;
    lab.className = "legend-item";
    legend.append(sp, lab);
  }
}

/* ---------- launcher planner ---------- */
function drawLauncherCourt(extra) {
  const ax = P.courtTop($("#launcher-court"), state.meta.court, {});
  const mx = Number($("#aim-machine_x").value), my = Number($("#aim-machine_y").value);
  if (Number.isFinite(mx) && Number.isFinite(my)) ax.rect(mx - 0.25, mx + 0.25, my - 0.25, my + 0.25, {class: "machine"}, "front");
  state.drill.forEach((s, i) => {
    ax.path(s.result.flight.points.map(p => [p[0], p[1]]), {stroke: P.COLORS[(i + 1) % P.COLORS.length], "stroke-width": 1.5, class: "traj drill"});
    ax.dot(s.result.landing.x, s.result.landing.y, 4, {fill: P.COLORS[(i + 1) % P.COLORS.length], stroke: "#000"});
    ax.text(s.result.landing.x + 0.3, s.result.landing.y + 0.3, String(i + 1), {class: "drilllabel"});
  });
  if (extra) extra(ax);
  ax.svg.onclick = evt => {
    const [x, y] = ax.fromClient(evt);
    setField("aim", "target_x", x.toFixed(2)); setField("aim", "target_y", y.toFixed(2));
    runAim();
  };
  return ax;
}
async function runAim() {
  const body = readForm("aim"); if (!body) return;
  const r = await api("/api/launcher/aim", body, $("#aim-status"));
  if (!r) { state.lastAim = null; $("#add-shot").disabled = true; return; }
  state.lastAim = {body, result: r};
  $("#add-shot").disabled = false;
  const st = r.settings;
  resultTable($("#aim-result"), [
    ["height", st.height_m, "settings.height_m", "m", 1], ["speed", st.speed_kmh, "settings.speed_kmh", "km/h", 0],
    ["elevation", st.elevation_deg, "settings.elevation_deg", "deg", 0], ["heading", st.heading_deg, "settings.heading_deg", "deg", 0],
    ["spin", st.spin_rpm, "settings.spin_rpm", "rpm", 0], ["spin axis", st.spin_axis_deg, "settings.spin_axis_deg", "deg", 0],
    ["roller 1", r.rollers.rpm1, "rollers.rpm1", "rpm", 0], ["roller 2", r.rollers.rpm2, "rollers.rpm2", "rpm", 0],
    ["landing x", r.landing.x, "landing.x", "m", 3], ["landing y", r.landing.y, "landing.y", "m", 3],
    ["miss", r.miss_mm, "miss_mm", "mm", 0], ["net clearance", r.net_clearance_m, "net_clearance_m", "m", 3],
    ["exact elevation", r.exact ? r.exact.elevation_deg : null, "exact.elevation_deg", "deg", 2],
    ["exact heading", r.exact ? r.exact.heading_deg : null, "exact.heading_deg", "deg", 2],
    ["flight time", r.flight_time_s, "flight_time_s", "s", 2],
  ]);
  drawLauncherCourt(ax => {
    ax.path(r.flight.points.map(p => [p[0], p[1]]), {stroke: P.COLORS[0], "stroke-width": 2.5, class: "traj"});
    ax.dot(body.target_x, body.target_y, 5, {fill: "none", stroke: "#ff0", "stroke-width": 2, class: "target"});
    ax.dot(r.landing.x, r.landing.y, 4, {fill: P.COLORS[0], stroke: "#000", class: "landing"});
  });
  const side = P.courtSide($("#launcher-side"), state.meta.court, {zmax: Math.ceil(Math.max(3, ...r.flight.points.map(p => p[2] + 0.5)))});
  side.path(r.flight.points.map(p => [p[0], p[2]]), {stroke: P.COLORS[0], "stroke-width": 2, class: "traj"});
}
function renderDrill() {
  const tb = $("#drill-table tbody"); tb.innerHTML = "";
  state.drill.forEach((s, i) => {
    const st = s.result.settings, tr = tb.insertRow();
    [i + 1, fmt(s.body.target_x), fmt(s.body.target_y), st.speed_kmh, st.spin_rpm, st.spin_axis_deg, st.elevation_deg,
      st.heading_deg, fmt(s.result.rollers.rpm1, 0), fmt(s.result.rollers.rpm2, 0), fmt(s.result.miss_mm, 0)]
      .forEach(v => { tr.insertCell().textContent = v; });
  });
  $("#drill-count").textContent = state.drill.length;
  $("#download-drill").disabled = state.drill.length === 0;
  drawLauncherCourt();
}
async function downloadDrill() {
  const shots = state.drill.map(s => s.body);
  const name = $("#drill-name").value || "my drill";
  const r = await api("/api/launcher/drill", {name, shots}, $("#drill-status")); if (!r) return;
  const blob = new Blob([r.text], {type: r.media_type || "text/plain"});
  const a = document.createElement("a"); a.href = URL.createObjectURL(blob); a.download = r.filename; a.id = "drill-link";
  document.body.appendChild(a); a.click(); setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}

/* ---------- line-call replay ---------- */
async function runCall(text) {
  const body = readForm("linecall"); if (!body) return;
  if (text.length > state.meta.limits.track_bytes) { $("#call-status").textContent = "csv: the track file is larger than 1000 kB"; $("#call-status").className = "status error"; return; }
  body.csv = text;
  const r = await api("/api/linecall", body, $("#call-status")); if (!r) return;
  resultTable($("#call-result"), [
    ["call", r.call, "call"], ["against", r.target || r.line || "–", "against"], ["line drawn", r.line ?? "–", "line"],
    ["distance of the mark to the line", r.distance_mm, "distance_mm", "mm", 1],
    ["probability in", r.p_in, "p_in", "", 3], ["bounce x", r.bounce.x, "bounce.x", "m", 4], ["bounce y", r.bounce.y, "bounce.y", "m", 4],
    ["bounce sigma", r.bounce.sigma_mm, "bounce.sigma_mm", "mm", 2], ["mark length", r.mark.length * 1000, "mark.length_mm", "mm", 1],
    ["mark width", r.mark.width * 1000, "mark.width_mm", "mm", 1], ["fit rms", r.fit.rms_mm, "fit.rms_mm", "mm", 2],
    ["outliers", r.fit.outliers, "fit.outliers", "", 0],
  ]);
  const court = state.meta.court;
  const bx = r.mark.x, by = r.mark.y, half = 0.3;
  const zoom = P.courtTop($("#call-zoom"), court, {window: [bx - half, bx + half, by - half * 0.6, by + half * 0.6], width: 520, height: 340, tick: 0.2, pad: [40, 8, 8, 28]});
  if (r.line_rect) zoom.rect(r.line_rect[0], r.line_rect[1], r.line_rect[2], r.line_rect[3], {class: "cline called"}, "data");
  const g = P.svgEl("g", {id: "call-mark", class: "mark " + (r.call === "in" ? "in" : "out")}, zoom.layers.front);
  for (const d of r.mark.discs) if (d[2] > 0) P.svgEl("circle", {cx: zoom.px(d[0]), cy: zoom.py(d[1]), r: d[2] * zoom.su}, g);
  zoom.dot(r.bounce.x, r.bounce.y, 2.5, {fill: "#000", id: "call-contact"}, "front");
  const side = P.courtSide($("#call-side"), court, {zmax: 4});
  for (const p of r.track) side.dot(p[1], p[3], 1.2, {fill: "#888"});
  side.path(r.fitted.map(p => [p[0], p[2]]), {stroke: "#d62828", "stroke-width": 2, class: "traj"});
}
function callFromFile() {
  const f = $("#track-file").files[0];
  if (!f) { $("#call-status").textContent = "csv: choose a track file first"; $("#call-status").className = "status error"; return; }
  if (f.size > state.meta.limits.track_bytes) { $("#call-status").textContent = "csv: the track file is larger than 1000 kB"; $("#call-status").className = "status error"; return; }
  const rd = new FileReader(); rd.onload = () => runCall(String(rd.result)); rd.readAsText(f);
}
async function callSample() {
  setField("linecall", "target", "deuce-box"); setField("linecall", "line", "auto");
  const r = await fetch("/api/linecall/sample"); runCall(await r.text());
}

/* ---------- pages ---------- */
function showPage() {
  const page = (location.hash || "#serve").slice(1);
  document.querySelectorAll(".page").forEach(p => p.hidden = p.id !== `page-${page}`);
  document.querySelectorAll("nav a").forEach(a => a.classList.toggle("active", a.getAttribute("href") === `#${page}`));
}

async function init() {
  state.meta = await api("/api/meta");
  if (!state.meta) { document.body.textContent = "cannot reach the tennislab server"; return; }
  $("#version").textContent = "tennislab " + state.meta.version;
  const court = state.meta.court;

  // flight page (always available)
  buildForm("flight", $("#flight-form"), runFlight);
  state.flightView = new P.View3D($("#flight-3d"), court);

  // serve explorer
  if (!unavailable("serve", "serve")) {
    buildForm("serve", $("#serve-form"), runServe);
    $("#serve-player").addEventListener("change", applyPlayer);
    for (const n of ["height", "racket_speed"]) $(`#serve-${n}`).addEventListener("change", () => { $("#serve-player").value = "custom"; });
    applyPlayer();
    state.serveView = new P.View3D($("#serve-3d"), court);
    state.heat = new P.HeatMap($("#serve-heatmap"), (a, b) => { setField("serve", "impact_angle", a); setField("serve", "face_angle", b); runServe(); });
    $("#run-window").addEventListener("click", runWindow);
  }
  // launcher planner
  if (!unavailable("launcher", "launcher")) {
    buildForm("aim", $("#aim-form"), runAim, "aim");
    $("#aim-shot").addEventListener("change", () => {
      const axis = {topspin: 0, flat: 0, backspin: 180, "sidespin-left": 90, "sidespin-right": -90}[$("#aim-shot").value];
      if (axis !== undefined) setField("aim", "spin_axis_deg", axis);
      if ($("#aim-shot").value === "flat") setField("aim", "spin_rpm", 0);
    });
    $("#add-shot").addEventListener("click", () => { if (state.lastAim && state.drill.length < state.meta.limits.drill_shots) { state.drill.push(state.lastAim); renderDrill(); } });
    $("#clear-drill").addEventListener("click", () => { state.drill = []; renderDrill(); });
    $("#download-drill").addEventListener("click", downloadDrill);
    drawLauncherCourt();
    P.courtSide($("#launcher-side"), court, {});
  }
  // line-call replay
  if (!unavailable("linecall", "linecall")) {
    buildForm("linecall", $("#linecall-form"), callFromFile, "call from file");
    $("#call-sample").addEventListener("click", callSample);
    P.courtTop($("#call-zoom"), court, {width: 520, height: 340});
    P.courtSide($("#call-side"), court, {});
  }
  window.addEventListener("hashchange", showPage);
  showPage();
  // first paint: the default flight and serve (fast), so the pages open with something to look at
  await runFlight();
  if (state.meta.modules.serve.available) await runServe();
  document.body.dataset.ready = "1";
}
document.addEventListener("DOMContentLoaded", init);
