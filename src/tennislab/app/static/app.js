/* tennislab app: forms built from the server's field definitions, validated here and on the server.

   Every page computes as soon as its inputs are valid (and again on each change); an emptied or bad
   field blocks the computation, clears the results shown and says why, with the field's label.  The
   URL keeps the inputs (#page?name=value&...): a link or a reload restores them. */
"use strict";
const P = window.TLPlots;
const state = {
  meta: null, drill: [], lastAim: null, window: null, track: null, heat: null, views: {},
  results: {}, timers: {}, aborts: {}, ran: {}, sampleOverride: null,
};
window.tennislab = state;  // for the curious and for the browser tests
const AUTO_DELAY_MS = 300;

// the page's label of a serve's success criteria (the field's choice labels; the value as a fallback)
function criteriaLabel(value) {
  const f = (specs("serve") || []).find((x) => x.name === "target");
  const i = f ? f.choices.indexOf(value || "seed-2d") : -1;
  return i >= 0 && f.choice_labels ? f.choice_labels[i] : (value || "seed-2d");
}

/* A spin-axis angle [deg] by name (tennislab.plot.text.spin_axis_name: 0 topspin, 180 backspin, +90
   sidespin curving left; within 2.5° of a named axis it is that axis). */
function spinAxisName(deg) {
  if (deg === null || deg === undefined || !Number.isFinite(deg)) return "along the path";
  const wrap = x => { let a = ((x % 360) + 360) % 360; return a > 180 ? a - 360 : a; };
  const a = wrap(deg);
  for (const [ref, word] of [[0, "topspin"], [180, "backspin"], [90, "sidespin (curving left)"], [-90, "sidespin (curving right)"]]) {
    if (Math.abs(wrap(a - ref)) <= 2.5) return word;
  }
  return `${Math.abs(a) < 90 ? "topspin" : "backspin"} and sidespin to the ${a > 0 ? "left" : "right"}`;
}
function $(sel) { return document.querySelector(sel); }
function fmt(x, d = 2) {
  if (x === null || x === undefined || Number.isNaN(x)) return "–";
  const s = Number(x).toFixed(d);
  return /^-0(\.0+)?$/.test(s) ? s.slice(1) : s;   /* -0.00 is said 0.00 (plot.text.num) */
}

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
const NUMBER = /^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*$/;
const NONFINITE = /^\s*[+-]?(inf|infinity|nan)\s*$/i;
function fieldError(f, raw) {
  const lab = f.label, s = raw === null || raw === undefined ? "" : String(raw);
  if (s.length > 60) return `${lab}: expected ${f.kind === "choice" ? "one of " + f.choices.join(", ") : "a number"}, got a text of ${s.length} characters`;
  if (s.trim() === "") return `${lab}: a value is required`;
  if (f.kind === "choice") return f.choices.includes(s) ? "" : `${lab}: '${s}' is not one of ${f.choices.join(", ")}`;
  if (NONFINITE.test(s)) return `${lab}: must be a finite number, got '${s.trim()}'`;
  if (!NUMBER.test(s)) return `${lab}: expected a number, got '${s}'`;
  const v = Number(s);
  if (!Number.isFinite(v)) return `${lab}: must be a finite number, got '${s.trim()}'`;
  const u = f.unit ? " " + f.unit : "";
  const badLo = f.lo !== null && (f.lo_open ? v <= f.lo : v < f.lo), badHi = f.hi !== null && v > f.hi;
  if (badLo || badHi) {
    const lo = f.lo === null ? "-inf" : pyFloat(f.lo), hi = f.hi === null ? "inf" : pyFloat(f.hi);
    return `${lab}: ${fmtG(v)}${u} is outside the allowed range ${f.lo_open ? "(" : "["}${lo}, ${hi}]${u}`;
  }
  if (f.kind === "int" && !Number.isInteger(v)) return `${lab}: expected a whole number, got ${pyFloat(v)}`;
  return "";
}

function specs(formName, only) {
  const all = state.meta.forms[formName];
  return only ? all.filter(f => only.includes(f.name)) : all;
}

/* A form from the field definitions; every edit validates the field and tells the page (onEdit). */
function buildForm(formName, container, opts = {}) {
  const form = document.createElement("form");
  form.id = "form-" + formName; form.noValidate = true; form.className = opts.inline ? "tlform inline" : "tlform";
  for (const f of specs(formName, opts.only)) {
    const row = document.createElement("div"); row.className = "field";
    const lab = document.createElement("label"); lab.htmlFor = `${formName}-${f.name}`;
    lab.textContent = f.label + (f.unit ? ` [${f.unit}]` : "");
    let inp;
    if (f.kind === "choice") {
      inp = document.createElement("select");
      f.choices.forEach((c, i) => {
        const o = document.createElement("option"); o.value = c;
        o.textContent = (f.choice_labels && f.choice_labels[i]) || c; inp.appendChild(o);
      });
      inp.value = f.default;
    } else {
      inp = document.createElement("input"); inp.type = "text"; inp.inputMode = "decimal";
      inp.value = f.default;
    }
    inp.id = `${formName}-${f.name}`; inp.name = f.name;
    if (f.help) inp.title = f.help;
    const err = document.createElement("div"); err.className = "field-error"; err.id = `err-${formName}-${f.name}`;
    const check = () => { err.textContent = fieldError(f, inp.value); inp.classList.toggle("bad", !!err.textContent); };
    inp.addEventListener("input", () => { check(); if (opts.onEdit) opts.onEdit(f.name); });
    inp.addEventListener("change", check);
    row.append(lab, inp, err); form.appendChild(row);
  }
  const btn = document.createElement("button"); btn.type = "submit"; btn.textContent = opts.submit || "compute";
  btn.id = opts.submitId || `submit-${formName}`;
  form.appendChild(btn);
  form.addEventListener("submit", e => { e.preventDefault(); if (opts.onSubmit) opts.onSubmit(); });
  container.appendChild(form);
  return form;
}

/* Read and validate a form: {body, errors}; messages are shown under the fields. */
function readForm(formName, only) {
  const body = {}, errors = [];
  for (const f of specs(formName, only)) {
    const inp = document.getElementById(`${formName}-${f.name}`), err = document.getElementById(`err-${formName}-${f.name}`);
    const msg = fieldError(f, inp.value);
    err.textContent = msg; inp.classList.toggle("bad", !!msg);
    if (msg) { errors.push(msg); continue; }
    body[f.name] = f.kind === "choice" ? inp.value : Number(inp.value);
  }
  return {body: errors.length ? null : body, errors};
}
function setField(formName, name, value) {
  const inp = document.getElementById(`${formName}-${name}`); inp.value = value;
  inp.dispatchEvent(new Event("input"));
}
function rawValues(formName, only) {
  const out = {};
  for (const f of specs(formName, only)) out[f.name] = document.getElementById(`${formName}-${f.name}`).value;
  return out;
}

function setStatus(el, text, kind) { el.textContent = text; el.className = "status " + kind; }

/* POST a body for a page: a newer request of the same page aborts the older one (the server then
   cancels its work); a failure clears the page's results and shows the server's one-line message. */
async function post(page, path, body, statusEl) {
  if (state.aborts[page]) state.aborts[page].abort();
  const ctl = new AbortController(); state.aborts[page] = ctl;
  setStatus(statusEl, "computing…", "busy");
  try {
    const r = await fetch(path, {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(body), signal: ctl.signal});
    const j = await r.json().catch(() => ({error: `HTTP ${r.status}`}));
    if (state.aborts[page] !== ctl) return null;     // superseded while the answer was read
    if (!r.ok) throw new Error(j.error || `HTTP ${r.status}`);
    setStatus(statusEl, "done", "ok");
    return j;
  } catch (e) {
    if (e.name === "AbortError" || state.aborts[page] !== ctl) return null;
    PAGES[page].clear();
    setStatus(statusEl, e.message, "error");
    return null;
  }
}

/* A result table: rows [label, value, key, unit, digits]; each value cell carries data-key and data-value. */
function resultTable(el, rows, inputs) {
  el.innerHTML = "";
  const t = document.createElement("table"); t.className = "results";
  for (const [label, value, key, unit, digits, text] of rows) {
    const tr = t.insertRow(); tr.insertCell().textContent = label;
    const c = tr.insertCell(); c.dataset.key = key;
    c.dataset.value = (value === null || value === undefined) ? "" : String(value);
    c.textContent = text && typeof value === "number" ? text(value)
      : typeof value === "number" ? fmt(value, digits ?? 2) + (unit ? " " + unit : "") : String(value ?? "–");
  }
  el.appendChild(t);
  el.dataset.for = JSON.stringify(inputs || {});
}
function clearBox(el) { el.innerHTML = ""; delete el.dataset.for; }

/* ---------- pages: run (compute from the form), clear (remove every result shown) ---------- */
const PAGES = {};
function page(name, def) { PAGES[name] = def; }

/* Computations scheduled or running, per page: state.idle() is true when nothing is pending. */
const busy = {};
function begin(n) { busy[n] = (busy[n] || 0) + 1; }
function end(n) { busy[n] -= 1; }
state.idle = () => Object.values(busy).every(v => v === 0);
function unschedule(name) {
  if (state.timers[name]) { clearTimeout(state.timers[name]); state.timers[name] = null; end(name); }
}
function schedule(name, fn) {
  unschedule(name);
  begin(name);
  state.timers[name] = setTimeout(async () => { state.timers[name] = null; try { await fn(); } finally { end(name); } }, AUTO_DELAY_MS);
}
async function now(name, fn) {   /* run at once (a click, a submit), dropping a pending run */
  unschedule(name);
  begin(name);
  try { await fn(); } finally { end(name); }
}

function onEdit(name) {
  const pg = PAGES[name];
  unschedule(name);
  const {body, errors} = readForm(pg.form);
  updateURL(name);
  if (!body) {
    if (state.aborts[name]) state.aborts[name].abort();
    pg.clear();
    setStatus($(pg.status), errors[0] + (errors.length > 1 ? ` (and ${errors.length - 1} more)` : ""), "error");
    return;
  }
  if (pg.auto && pg.auto()) {
    setStatus($(pg.status), "inputs changed…", "busy");
    schedule(name, pg.run);
  } else {
    pg.clear();
    setStatus($(pg.status), pg.hint || "", "");
  }
}
async function runPage(name) {
  const pg = PAGES[name];
  const {body, errors} = readForm(pg.form);
  updateURL(name);
  if (!body) {
    pg.clear();
    setStatus($(pg.status), errors[0] + (errors.length > 1 ? ` (and ${errors.length - 1} more)` : ""), "error");
    return null;
  }
  state.ran[name] = true;
  return body;
}

/* ---------- views shared by pages ---------- */
/* Each page's last drawing, redrawn when the window is resized (the plots are as wide as their column). */
const redraws = {};
function drawn(name, fn) { redraws[name] = fn; fn(); }
let resizeTimer = null;
window.addEventListener("resize", () => {
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(() => { const fn = redraws[currentPage()]; if (fn) fn(); if (state.heat) state.heat.draw(); }, 150);
});

/* Flights on the side and top views of a page, in the colours of the court's surface; every marker in
   the legend under them (#prefix-legend): the flight, where it lands (and bounces). */
function drawFlight(prefix, flights, extra = {}) {
  const court = state.meta.court, pts = flights.flatMap(f => f.points), surface = extra.surface;
  const side = P.courtSide($(`#${prefix}-side`), court, {points: pts.map(p => [p[0], p[2]]).concat(extra.side || []), surface});
  const top = P.courtTop($(`#${prefix}-top`), court, {points: pts.map(p => [p[0], p[1]]).concat(extra.top || []), surface});
  flights.forEach((f, i) => {
    const col = f.color || P.COLORS[i % P.COLORS.length];
    side.path(f.points.map(p => [p[0], p[2]]), {stroke: col, "stroke-width": 2, class: "traj"});
    top.path(f.points.map(p => [p[0], p[1]]), {stroke: col, "stroke-width": 2, class: "traj"});
    (f.bounces || []).forEach((b, k) => {
      top.dot(b[0], b[1], 3.5, {fill: col, stroke: "#000", class: "bounce"});
      if ((f.bounces || []).length > 1) top.text(b[0] + 0.4, b[1] + 0.4, String(k + 1), {class: "drilllabel"});
    });
  });
  const el = $(`#${prefix}-legend`);
  if (el) {
    const nb = Math.max(0, ...flights.map(f => (f.bounces || []).length));
    P.legend(el, [{kind: "line", color: P.COLORS[0], label: extra.what || "flight"},
      {kind: "dot", color: P.COLORS[0], label: nb > 1 ? "landing and bounces (numbered, top view)" : "landing"},
      {kind: "line", color: "#222", label: "net"}, {kind: "dash", color: "#999", label: "baselines and service lines (side view)"},
      {kind: "patch", color: P.surfaceColors(court, surface).court, label: `court: ${surface || "hard"}`}]);
  }
  return {side, top};
}
function emptyViews(prefix) {
  const court = state.meta.court;
  P.courtSide($(`#${prefix}-side`), court, {});
  P.courtTop($(`#${prefix}-top`), court, {});
  if (state.views[prefix]) state.views[prefix].setTracks([]);
  const el = $(`#${prefix}-legend`); if (el) el.replaceChildren();
  delete redraws[prefix];
}

/* ---------- flight page ---------- */
page("flight", {
  form: "flight", status: "#flight-status", auto: () => true,
  run: runFlight,
  clear() { clearBox($("#flight-result")); emptyViews("flight"); state.results.flight = null; exportsEnabled(); },
});
async function runFlight() {
  const body = await runPage("flight"); if (!body) return;
  const r = await post("flight", "/api/flight", body, $("#flight-status")); if (!r) return;
  const rows = [
    ["landing x", r.landing.x, "landing_x", "m", 3], ["landing y", r.landing.y, "landing_y", "m", 3],
    ["flight time", r.landing.t, "landing_t", "s", 3], ["landing speed", r.landing.speed_kmh, "landing_speed_kmh", "km/h", 1],
    ["net", r.net.result, "net_result"], ["net clearance", r.net.clearance, "net_clearance", "m", 3],
    ["apex height", r.apex.z, "apex_z", "m", 3], ["apex x", r.apex.x, "apex_x", "m", 2],
    ["lands in", r.landing.areas.join(", ") || "out", "areas"],
  ];
  (r.bounces || []).forEach((b, i) => {
    rows.push([`bounce ${i + 1} x`, b.x, `bounces.${i}.x`, "m", 3], [`bounce ${i + 1} y`, b.y, `bounces.${i}.y`, "m", 3]);
  });
  resultTable($("#flight-result"), rows, body);
  const bounces = [[r.landing.x, r.landing.y]].concat((r.bounces || []).slice(1).map(b => [b.x, b.y]));
  const surface = body.bounces > 0 ? body.surface : "hard";
  drawn("flight", () => drawFlight("flight", [{points: r.points, bounces}], {surface}));
  state.views.flight.setTracks([{points: r.points}], surface);
  state.results.flight = {inputs: body, rows, points: r.points};
  exportsEnabled();
}

/* ---------- serve explorer ---------- */
const REASONS = {net: "into the net", long: "long", wide: "wide", short: "short"};
function renderVerdict(r) {
  const box = $("#serve-verdict"); box.replaceChildren();
  const v = r.verdict || null, ok = v ? !!v.success : !!r.success;
  box.className = "verdict " + (ok ? "in" : "fault");
  box.dataset.success = ok ? "yes" : "no";
  box.dataset.reason = v && v.reason ? v.reason : "";
  const head = document.createElement("strong"); head.id = "serve-verdict-head";
  head.textContent = ok ? "In: a successful serve" : `Fault${v && v.reason ? ": " + (REASONS[v.reason] || v.reason) : ""}`;
  const detail = document.createElement("p"); detail.id = "serve-verdict-detail";
  detail.textContent = v ? (v.detail || "") : (ok
    ? `It succeeds by the criteria “${criteriaLabel(r.criteria)}”.`
    : `It fails the criteria “${criteriaLabel(r.criteria)}”.`);
  box.append(head, detail);
  if (v && v.advice) {
    const adv = document.createElement("p"); adv.id = "serve-verdict-advice";
    adv.textContent = (ok ? "" : "To fix it: ") + v.advice;
    box.append(adv);
  }
  if (r.caveats && r.caveats.length) {
    const ul = document.createElement("ul"); ul.id = "serve-caveats";
    for (const c of r.caveats) { const li = document.createElement("li"); li.textContent = c; ul.append(li); }
    box.append(ul);
  }
}
page("serve", {
  form: "serve", status: "#serve-status", auto: () => true,
  run: runServe,
  clear() {
    clearBox($("#serve-result")); $("#serve-verdict").replaceChildren(); $("#serve-verdict").className = "verdict";
    emptyViews("serve"); state.results.serve = null; exportsEnabled();
  },
});
function applyPlayer() {
  const name = $("#serve-player").value, prof = state.meta.players[name];
  if (prof) {
    $("#serve-height").value = prof.height; $("#serve-racket_speed").value = prof.racket_speed;
  }
}
function clearWindow(msg) {
  state.window = null; state.heat.set(null); $("#window-legend").replaceChildren(); $("#window-note").textContent = "";
  setStatus($("#window-status"), msg || "", msg ? "busy" : ""); exportsEnabled();
}
async function runServe() {
  const body = await runPage("serve"); if (!body) return;
  const r = await post("serve", "/api/serve", body, $("#serve-status")); if (!r) return;
  renderVerdict(r);
  resultTable($("#serve-result"), [
    ["ball speed", r.speed, "speed", "m/s", 2], ["spin", r.spin_rpm, "spin_rpm", "rpm", 0],
    ["launch angle", r.launch_angle, "launch_angle", "deg", 2], ["net clearance", r.net_clearance, "net_clearance", "m", 3],
    ["net height (ball centre)", r.net_height, "net_height", "m", 3],
    ["landing x (from the server)", r.landing_x, "landing_x", "m", 3], ["landing y", r.landing_y, "landing_y", "m", 3],
    ["category", r.category, "category"], ["success", r.success ? "yes" : "no", "success"],
    ["impact regime", r.regime ?? "–", "regime"], ["contact time", r.contact_time_ms, "contact_time_ms", "ms", 2],
  ], body);
  const rows = [...$("#serve-result").querySelectorAll("td[data-key]")].map(c => [c.previousSibling.textContent, c.dataset.value, c.dataset.key]);
  if (r.flight) {
    drawn("serve", () => drawFlight("serve", [{points: r.flight.points, bounces: [[r.landing.x, r.landing.y]]}], {what: "serve"}));
    state.views.serve.setTracks([{points: r.flight.points}]);
  } else {
    emptyViews("serve");
  }
  state.results.serve = {inputs: body, rows, points: r.flight ? r.flight.points : []};
  if (state.window) state.heat.select(body.impact_angle, body.face_angle);
  exportsEnabled();
}
/* The window follows the player, height, racket speed and step (it is quick: at most 181 x 181 serves). */
function scheduleWindow() {
  setStatus($("#window-status"), "inputs changed…", "busy");
  schedule("window", runWindow);
}
async function runWindow() {
  const s = readForm("serve", ["player", "height", "racket_speed"]), w = readForm("window", ["step"]);
  const errors = s.errors.concat(w.errors);
  if (errors.length) { clearWindow(); setStatus($("#window-status"), errors[0], "error"); return; }
  const body = {...s.body, step: w.body.step};
  const r = await post("window", "/api/serve/window", body, $("#window-status"));
  if (!r) return;
  state.window = {inputs: body, data: r}; state.heat.set(r);
  const cur = readForm("serve").body;
  if (cur) state.heat.select(cur.impact_angle, cur.face_angle);
  const legend = $("#window-legend"); legend.innerHTML = "";
  for (const it of r.legend) {
    const entry = document.createElement("span"); entry.className = "legend-entry";  // swatch and label kept together
    const sp = document.createElement("span"); sp.className = "swatch"; sp.style.background = it.color;
    const lab = document.createElement("span"); lab.textContent = `${it.label} (${it.n})`; lab.dataset.code = it.code; lab.dataset.n = it.n;
    lab.className = "legend-item";
    entry.append(sp, lab); legend.append(entry);
  }
  const sp = r.span, a = r.alpha, b = r.beta, note = $("#window-note");
  note.textContent = sp ? `Shown where the window is: α ${sp.alpha_lo}–${sp.alpha_hi}°, β ${sp.beta_lo}–${sp.beta_hi}° `
    + `(computed over α ${a[0]}–${a[a.length - 1]}°, β ${b[0]}–${b[b.length - 1]}° in ${r.step}° steps); the black box is the serve above.` : "";
  exportsEnabled();
}
page("window", {form: "window", status: "#window-status", clear() { clearWindow(); }});

/* ---------- launcher planner ---------- */
page("launcher", {
  form: "aim", status: "#aim-status", auto: () => true,
  run: runAim,
  clear() {
    clearBox($("#aim-result")); state.lastAim = null; $("#add-shot").disabled = true;
    delete redraws.launcher;
    drawLauncherCourt(); P.courtSide($("#launcher-side"), state.meta.court, {}); state.results.aim = null; exportsEnabled();
  },
});
function drawLauncherCourt(extra, pts = []) {
  const mx = Number($("#aim-machine_x").value), my = Number($("#aim-machine_y").value);
  const all = pts.concat(state.drill.flatMap(s => s.result.flight.points.map(p => [p[0], p[1]])));
  if (Number.isFinite(mx) && Number.isFinite(my)) all.push([mx, my]);
  const ax = P.courtTop($("#launcher-court"), state.meta.court, {points: all});
  if (Number.isFinite(mx) && Number.isFinite(my)) ax.rect(mx - 0.25, mx + 0.25, my - 0.25, my + 0.25, {class: "machine"}, "front");
  state.drill.forEach((s, i) => {
    ax.path(s.result.flight.points.map(p => [p[0], p[1]]), {stroke: P.COLORS[(i + 1) % P.COLORS.length], "stroke-width": 1.5, class: "traj drill"});
    ax.dot(s.result.landing.x, s.result.landing.y, 4, {fill: P.COLORS[(i + 1) % P.COLORS.length], stroke: "#000"});
    ax.text(s.result.landing.x + 0.3, s.result.landing.y + 0.3, String(i + 1), {class: "drilllabel"});
  });
  if (extra) extra(ax);
  const items = [{kind: "square", color: "#222", label: "machine"}];
  if (extra) items.push({kind: "line", color: P.COLORS[0], label: "this shot"}, {kind: "ring", color: "#ff0", label: "target (click to move)"},
    {kind: "dot", color: P.COLORS[0], label: "landing"});
  if (state.drill.length) items.push({kind: "dot", color: P.COLORS[1], label: "drill shots (numbered)"});
  P.legend($("#launcher-legend"), items);
  ax.svg.onclick = evt => {
    const [x, y] = ax.fromClient(evt);
    $("#aim-target_x").value = x.toFixed(2); $("#aim-target_y").value = y.toFixed(2);
    now("launcher", runAim);
  };
  return ax;
}
async function runAim() {
  const body = await runPage("launcher"); if (!body) return;
  const r = await post("launcher", "/api/launcher/aim", body, $("#aim-status"));
  if (!r) return;
  state.lastAim = {body, result: r};
  $("#add-shot").disabled = false;
  drawAim(body, r);
}
function drawAim(body, r) {
  const st = r.settings;
  resultTable($("#aim-result"), [
    ["height", st.height_m, "settings.height_m", "m", 1], ["speed", st.speed_kmh, "settings.speed_kmh", "km/h", 0],
    ["elevation", st.elevation_deg, "settings.elevation_deg", "deg", 0], ["heading", st.heading_deg, "settings.heading_deg", "deg", 0],
    ["spin", st.spin_rpm, "settings.spin_rpm", "rpm", 0],
    ["spin axis", st.spin_axis_deg, "settings.spin_axis_deg", "deg", 0, d => `${fmt(d, 0)}° (${spinAxisName(d)})`],
    ["roller 1", r.rollers.rpm1, "rollers.rpm1", "rpm", 0], ["roller 2", r.rollers.rpm2, "rollers.rpm2", "rpm", 0],
    ["landing x", r.landing.x, "landing.x", "m", 3], ["landing y", r.landing.y, "landing.y", "m", 3],
    ["miss", r.miss_mm, "miss_mm", "mm", 0], ["net clearance", r.net_clearance_m, "net_clearance_m", "m", 3],
    ["exact elevation", r.exact ? r.exact.elevation_deg : null, "exact.elevation_deg", "deg", 2],
    ["exact heading", r.exact ? r.exact.heading_deg : null, "exact.heading_deg", "deg", 2],
    ["flight time", r.flight_time_s, "flight_time_s", "s", 2],
  ], body);
  const pts = r.flight.points;
  drawn("launcher", () => {
    drawLauncherCourt(ax => {
      ax.path(pts.map(p => [p[0], p[1]]), {stroke: P.COLORS[0], "stroke-width": 2.5, class: "traj"});
      ax.dot(body.target_x, body.target_y, 5, {fill: "none", stroke: "#ff0", "stroke-width": 2, class: "target"});
      ax.dot(r.landing.x, r.landing.y, 4, {fill: P.COLORS[0], stroke: "#000", class: "landing"});
    }, pts.map(p => [p[0], p[1]]));
    const side = P.courtSide($("#launcher-side"), state.meta.court, {points: pts.map(p => [p[0], p[2]])});
    side.path(pts.map(p => [p[0], p[2]]), {stroke: P.COLORS[0], "stroke-width": 2, class: "traj"});
  });
  const rows = [...$("#aim-result").querySelectorAll("td[data-key]")].map(c => [c.previousSibling.textContent, c.dataset.value, c.dataset.key]);
  state.results.aim = {inputs: body, rows, points: pts};
  exportsEnabled();
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
  if (state.lastAim) drawAim(state.lastAim.body, state.lastAim.result); else drawLauncherCourt();
  exportsEnabled();
}
async function downloadDrill() {
  const shots = state.drill.map(s => s.body);
  const name = $("#drill-name").value || "my drill";
  let r = null;
  await now("drill", async () => { r = await post("drill", "/api/launcher/drill", {name, shots}, $("#drill-status")); });
  if (!r) return;
  download(new Blob([r.text], {type: r.media_type || "text/plain"}), r.filename);
}
page("drill", {form: null, status: "#drill-status", clear() {}});

/* ---------- line-call replay ---------- */
page("linecall", {
  form: "linecall", status: "#call-status", auto: () => state.track !== null,
  hint: "choose a track file, or call the example track",
  run: () => runCall(),
  clear() {
    clearBox($("#call-result"));
    P.courtTop($("#call-zoom"), state.meta.court, {aspect: 0.62});
    P.courtSide($("#call-side"), state.meta.court, {});
    $("#call-legend").replaceChildren(); delete redraws.linecall;
    state.results.call = null; exportsEnabled();
  },
});
async function runCall() {
  const body = await runPage("linecall"); if (!body) return;
  const text = state.track;
  if (text === null) { PAGES.linecall.clear(); setStatus($("#call-status"), "track file: choose a track file first", "error"); return; }
  if (text.length > state.meta.limits.track_bytes) {
    PAGES.linecall.clear(); setStatus($("#call-status"), `track file: the track file is larger than ${state.meta.limits.track_bytes / 1000} kB`, "error"); return;
  }
  const r = await post("linecall", "/api/linecall", {...body, csv: text}, $("#call-status")); if (!r) return;
  const bo = r.bounce || {}, mk = r.mark || {}, fit = r.fit || {};
  const why = r.reason || (r.review_reasons || []).join("; ") || null;
  const mm = v => (typeof v === "number" ? v * 1000 : null), words = r.words || {};
  resultTable($("#call-result"), [
    ["call", r.call, "call"], ["why", why, "reason"], ["against", r.target || r.line || "–", "against"],
    ["line drawn", r.line ?? "–", "line"],
    [body.line !== "auto" ? `mark vs the ${body.line}` : `mark vs ${r.target || "the area"} (lines included)`,
      r.distance_mm, "distance_mm", "mm", 1, () => words.distance],
    ["probability in", r.p_in, "p_in", "", 3], ["bounce x", bo.x, "bounce.x", "m", 4], ["bounce y", bo.y, "bounce.y", "m", 4],
    ["contact uncertainty (1σ)", bo.sigma_mm, "bounce.sigma_mm", "mm", 2], ["mark length", mm(mk.length), "mark.length_mm", "mm", 1],
    ["mark width", mm(mk.width), "mark.width_mm", "mm", 1], ["fit rms", fit.rms_mm, "fit.rms_mm", "mm", 2],
    ["outliers", fit.outliers, "fit.outliers", "", 0],
    ["drag scale (1σ)", fit.drag_scale, "fit.drag_scale", "", 3, () => words.drag_scale],
    ["lift scale (1σ)", fit.lift_scale, "fit.lift_scale", "", 3, () => words.lift_scale],
    ["fitted spin (1σ)", r.spin ? r.spin.rpm : null, "spin.rpm", "rpm", 0, () => words.spin],
  ], body);
  drawn("linecall", () => drawCall(r, body.surface));
  const rows = [...$("#call-result").querySelectorAll("td[data-key]")].map(c => [c.previousSibling.textContent, c.dataset.value, c.dataset.key]);
  state.results.call = {inputs: body, rows, track: r.track, fitted: r.fitted};
  exportsEnabled();
  return r;
}
/* The call's views on the court of its surface: the mark against the lines (zoomed, the line judged
   highlighted) and the track with its fit (side view); every marker in the legend. */
function drawCall(r, surface) {
  const court = state.meta.court, bo = r.bounce || {}, mk = r.mark || {};
  const cx = mk.x ?? bo.x ?? (r.net && r.net.x) ?? 0, cy = mk.y ?? bo.y ?? (r.net && r.net.y) ?? 0, half = 0.3;
  const zoom = P.courtTop($("#call-zoom"), court, {window: [cx - half, cx + half, cy - half * 0.6, cy + half * 0.6],
    aspect: 0.62, tick: 0.1, pad: [44, 8, 8, 32], surface});
  if (r.line_rect) zoom.rect(r.line_rect[0], r.line_rect[1], r.line_rect[2], r.line_rect[3], {class: "cline called"}, "data");
  const kind = r.call === "in" ? "in" : r.call === "out" ? "out" : "review";
  const g = P.svgEl("g", {id: "call-mark", class: "mark " + kind}, zoom.layers.front);
  for (const d of (mk.discs || [])) if (d[2] > 0) P.svgEl("circle", {cx: zoom.px(d[0]), cy: zoom.py(d[1]), r: d[2] * zoom.su}, g);
  if (typeof bo.x === "number") zoom.dot(bo.x, bo.y, 2.5, {fill: "#000", id: "call-contact"}, "front");
  const sidePts = r.track.map(p => [p[1], p[3]]).concat(r.fitted.map(p => [p[0], p[2]]));
  const side = P.courtSide($("#call-side"), court, {points: sidePts, surface});
  side.path(r.fitted.map(p => [p[0], p[2]]), {stroke: "#d62828", "stroke-width": 1.5, class: "traj"});
  for (const p of r.track) side.dot(p[1], p[3], 1.8, {fill: "#444", "fill-opacity": 0.6});
  P.legend($("#call-legend"), [
    {kind: "patch", color: "#ffe066", label: `line drawn${r.line ? ": " + r.line : ""}`},
    {kind: "patch", color: {in: "#8a4b1c", out: "#c81e1e", review: "#e0a020"}[kind], label: `ball mark (call ${r.call})`},
    {kind: "dot", color: "#000", label: "fitted first contact"},
    {kind: "dot", color: "#666", label: "track points (side view)"}, {kind: "line", color: "#d62828", label: "fitted flight"},
  ]);
}
/* The example serve is called against the deuce service box: the page sets the target area for it (and
   says so); a file chosen next is called with the user's own choice again, the one before the example,
   unless the user picked a target or line since. */
function restoreAfterSample() {
  const o = state.sampleOverride;
  if (!o) return;
  state.sampleOverride = null;
  $("#linecall-target").value = o.target; $("#linecall-line").value = o.line;
  readForm("linecall"); updateURL("linecall");
}
function callFromFile() {
  restoreAfterSample();
  const f = $("#track-file").files[0];
  if (!f) { state.track = null; PAGES.linecall.clear(); setStatus($("#call-status"), "track file: choose a track file first", "error"); return; }
  if (f.size > state.meta.limits.track_bytes) {
    state.track = null; PAGES.linecall.clear();
    setStatus($("#call-status"), `track file: the track file is larger than ${state.meta.limits.track_bytes / 1000} kB`, "error"); return;
  }
  begin("linecall");
  const rd = new FileReader();
  rd.onloadend = () => { end("linecall"); if (rd.result !== null) { state.track = String(rd.result); now("linecall", runCall); } };
  rd.readAsText(f);
}
async function callSample() {
  const t = $("#linecall-target"), l = $("#linecall-line");
  if (!state.sampleOverride) state.sampleOverride = {target: t.value, line: l.value};
  t.value = SAMPLE_TARGET; l.value = "auto";
  updateURL("linecall");
  await now("linecall", async () => {
    const r = await fetch("/api/linecall/sample");
    if (!r.ok) { PAGES.linecall.clear(); setStatus($("#call-status"), `example track: HTTP ${r.status}`, "error"); return; }
    state.track = await r.text();
    if (await runCall()) {
      setStatus($("#call-status"), `example serve: called against ${areaLabel(SAMPLE_TARGET)} (target area set for it; a file you choose next is called against ${areaLabel(state.sampleOverride ? state.sampleOverride.target : t.value)})`, "ok");
    }
  });
}
const SAMPLE_TARGET = "deuce-box";
function areaLabel(v) {
  if (v === "auto") return "the singles court of the half it lands in";
  return "the " + ({"deuce-box": "deuce service box", "ad-box": "ad service box"}[v] || v);
}

/* ---------- exports: PNG of each plot, CSV of the numbers ---------- */
function download(blob, name) {
  const a = document.createElement("a"); a.href = URL.createObjectURL(blob); a.download = name;
  document.body.appendChild(a); a.click(); setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}
function csvText(header, rows) {
  const q = v => { const s = v === null || v === undefined ? "" : String(v); return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s; };
  return [header, ...rows].map(r => r.map(q).join(",")).join("\n") + "\n";
}
function numbersCSV(formName, res) {
  const rows = [];
  for (const f of state.meta.forms[formName]) if (f.name in res.inputs) rows.push(["input", f.label, res.inputs[f.name], f.unit]);
  for (const [label, value, key] of res.rows) rows.push(["result", label, value, key]);
  return csvText(["section", "quantity", "value", "unit_or_key"], rows);
}
const pointsCSV = pts => csvText(["x_m", "y_m", "z_m"], pts);
const CSV = {
  "flight-results": () => state.results.flight && numbersCSV("flight", state.results.flight),
  "flight-trajectory": () => state.results.flight && pointsCSV(state.results.flight.points),
  "serve-results": () => state.results.serve && numbersCSV("serve", state.results.serve),
  "serve-trajectory": () => state.results.serve && pointsCSV(state.results.serve.points),
  "serve-window": () => {
    if (!state.window) return null;
    const d = state.window.data, rows = [], lab = Object.fromEntries(d.legend.map(l => [l.code, l.label]));
    d.beta.forEach((b, j) => d.alpha.forEach((a, i) => rows.push([a, b, d.code[j][i], lab[d.code[j][i]], d.speed[j][i], d.spin_rpm[j][i]])));
    return csvText(["alpha_deg", "beta_deg", "code", "outcome", "speed_ms", "spin_rpm"], rows);
  },
  "aim-results": () => state.results.aim && numbersCSV("aim", state.results.aim),
  "aim-trajectory": () => state.results.aim && pointsCSV(state.results.aim.points),
  "drill": () => state.drill.length ? csvText(
    ["shot", "target_x_m", "target_y_m", "speed_kmh", "spin_rpm", "spin_axis_deg", "elevation_deg", "heading_deg", "roller1_rpm", "roller2_rpm", "miss_mm"],
    state.drill.map((s, i) => { const st = s.result.settings; return [i + 1, s.body.target_x, s.body.target_y, st.speed_kmh, st.spin_rpm, st.spin_axis_deg, st.elevation_deg, st.heading_deg, s.result.rollers.rpm1, s.result.rollers.rpm2, s.result.miss_mm]; })) : null,
  "call-results": () => state.results.call && numbersCSV("linecall", state.results.call),
  "call-track": () => state.results.call && csvText(["kind", "t_s", "x_m", "y_m", "z_m"],
    state.results.call.track.map(p => ["track", ...p]).concat(state.results.call.fitted.map(p => ["fit", "", ...p]))),
};
const PNG_READY = {
  "flight-3d": () => !!state.results.flight, "flight-side": () => !!state.results.flight, "flight-top": () => !!state.results.flight,
  "serve-3d": () => !!state.results.serve, "serve-side": () => !!state.results.serve, "serve-top": () => !!state.results.serve,
  "serve-heatmap": () => !!state.window, "launcher-court": () => true, "launcher-side": () => !!state.results.aim,
  "call-zoom": () => !!state.results.call, "call-side": () => !!state.results.call,
};
function exportsEnabled() {
  document.querySelectorAll("button.export").forEach(b => {
    b.disabled = b.dataset.csv ? !CSV[b.dataset.csv]() : !PNG_READY[b.dataset.png]();
  });
}
async function exportClicked(b) {
  if (b.dataset.csv) {
    const text = CSV[b.dataset.csv]();
    if (text) download(new Blob([text], {type: "text/csv"}), `tennislab-${b.dataset.csv}.csv`);
  } else {
    const blob = await P.plotPNG(document.getElementById(b.dataset.png));
    download(blob, `tennislab-${b.dataset.png}.png`);
  }
}

/* ---------- the URL keeps the inputs: #page?name=value&... ---------- */
const URL_FORMS = {flight: [["flight"]], serve: [["serve"], ["window", ["step"]]], launcher: [["aim"]], linecall: [["linecall"]]};
function currentPage() {
  const p = location.hash.slice(1).split("?")[0];
  return p in URL_FORMS ? p : "serve";
}
function updateURL(name) {
  if (!(name in URL_FORMS) || currentPage() !== name) return;
  const q = new URLSearchParams();
  for (const [form, only] of URL_FORMS[name]) {
    for (const [k, v] of Object.entries(rawValues(form, only))) q.set(form === "window" ? "window_" + k : k, v);
  }
  history.replaceState(null, "", `#${name}?${q.toString()}`);
}
/* Put the URL's values in the page's form (unknown names ignored); true if any was given. */
function applyURL() {
  const [name, query] = location.hash.slice(1).split("?");
  if (!(name in URL_FORMS) || !query) return false;
  const q = new URLSearchParams(query);
  let any = false;
  for (const [form, only] of URL_FORMS[name]) {
    for (const f of specs(form, only)) {
      const key = form === "window" ? "window_" + f.name : f.name;
      if (q.has(key)) { document.getElementById(`${form}-${f.name}`).value = q.get(key); any = true; }
    }
  }
  return any;
}

/* ---------- pages ---------- */
function showPage() {
  const name = currentPage();
  document.querySelectorAll(".page").forEach(p => p.hidden = p.id !== `page-${name}`);
  document.querySelectorAll("nav a").forEach(a => a.classList.toggle("active", a.getAttribute("href") === `#${name}`));
  return name;
}
async function openPage(fromURL) {
  const name = showPage();
  if (redraws[name]) redraws[name]();  // drawn while hidden: again at the width it is shown at
  if (state.views[name]) state.views[name].draw();
  if (name === "serve" && state.heat) state.heat.draw();
  const given = fromURL ? applyURL() : false;
  const pg = PAGES[name];
  if (given || !state.ran[name]) {
    if (pg.auto && pg.auto()) await now(name, pg.run); else onEdit(name);
    if (name === "serve") await now("window", runWindow);
  }
  updateURL(name);
}

async function init() {
  let meta = null;
  try { const r = await fetch("/api/meta"); if (r.ok) meta = await r.json(); } catch (e) { meta = null; }
  if (!meta) { document.body.textContent = "cannot reach the tennislab server"; return; }
  state.meta = meta;
  $("#version").textContent = "tennislab " + meta.version;
  const court = meta.court;

  buildForm("flight", $("#flight-form"), {onEdit: () => onEdit("flight"), onSubmit: () => now("flight", runFlight)});
  state.views.flight = new P.View3D($("#flight-3d"), court);

  buildForm("serve", $("#serve-form"), {onEdit: n => {
    if (n === "player") applyPlayer();
    if (n === "height" || n === "racket_speed") $("#serve-player").value = "custom";
    if (["player", "height", "racket_speed"].includes(n)) scheduleWindow();
    onEdit("serve");
  }, onSubmit: () => now("serve", runServe)});
  buildForm("window", $("#window-form"), {only: ["step"], inline: true, submit: "compute window", submitId: "run-window",
    onEdit: () => { updateURL("serve"); scheduleWindow(); }, onSubmit: () => now("window", runWindow)});
  state.views.serve = new P.View3D($("#serve-3d"), court);
  state.heat = new P.HeatMap($("#serve-heatmap"), (a, b) => {
    $("#serve-impact_angle").value = a; $("#serve-face_angle").value = b; now("serve", runServe);
  });

  buildForm("aim", $("#aim-form"), {onEdit: n => {
    if (n === "shot") {
      const axis = {topspin: 0, flat: 0, backspin: 180, "sidespin-left": 90, "sidespin-right": -90}[$("#aim-shot").value];
      if (axis !== undefined) $("#aim-spin_axis_deg").value = axis;
      if ($("#aim-shot").value === "flat") $("#aim-spin_rpm").value = 0;
    }
    onEdit("launcher");
  }, onSubmit: () => now("launcher", runAim), submit: "aim"});
  $("#add-shot").addEventListener("click", () => {
    if (state.lastAim && state.drill.length < meta.limits.drill_shots) { state.drill.push(state.lastAim); renderDrill(); }
  });
  $("#clear-drill").addEventListener("click", () => { state.drill = []; renderDrill(); });
  $("#download-drill").addEventListener("click", downloadDrill);

  buildForm("linecall", $("#linecall-form"), {onEdit: n => {
    if (n === "target" || n === "line") state.sampleOverride = null;  // the user's own choice from now on
    onEdit("linecall");
  }, onSubmit: callFromFile, submit: "call from file"});
  $("#track-file").addEventListener("change", callFromFile);
  $("#call-sample").addEventListener("click", callSample);

  for (const name of ["flight", "serve", "launcher", "linecall"]) PAGES[name].clear();
  clearWindow();
  document.querySelectorAll("button.export").forEach(b => b.addEventListener("click", () => exportClicked(b)));
  exportsEnabled();
  window.addEventListener("hashchange", () => openPage(true));
  await openPage(true);
  document.body.dataset.ready = "1";
}
document.addEventListener("DOMContentLoaded", init);
