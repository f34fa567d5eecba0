// sphd's dashboard: the jobs, a live plot of a job's diagnostics, its particles and its controls.
// Everything goes through sphd's own requests (POST /api/request: the wire protocol's ops, the
// same command table as sphctl's) and its event stream (GET /api/events: Server-Sent Events).
"use strict";

const $ = (id) => document.getElementById(id);
const state = {
  token: sessionStorage.getItem("sphd-token") || "",
  jobs: [],
  job: null,        // the selected job's id
  status: null,     // its latest status
  series: {},       // name -> [values], with "t"
  plot: null,
  plotted: "",
  points: 0,        // points in the plot (the browser test reads it)
  view: { yaw: 0.6, pitch: 0.35, particles: null },
};

function headers(json) {
  const h = {};
  if (json) h["Content-Type"] = "application/json";
  if (state.token) h["X-Sphd-Token"] = state.token;
  return h;
}

function askToken() {
  $("token-box").hidden = false;
}

// One request of the wire protocol; resolves to its result, rejects with its error.
async function api(op, args) {
  const r = await fetch("/api/request", {
    method: "POST",
    headers: headers(true),
    body: JSON.stringify({ v: 1, id: "web", op: op, args: args || {} }),
  });
  if (r.status === 401) {
    askToken();
    throw new Error("this dashboard needs its token");
  }
  const rep = await r.json();
  if (!rep.ok) {
    const e = rep.error || {};
    throw new Error(`${e.code || "error"}${e.path ? " at " + e.path : ""}: ${e.message || ""}`);
  }
  return rep.result;
}

function say(text, ok) {
  const m = $("message");
  m.textContent = text;
  m.className = ok ? "ok" : "";
}

function fmtTime(p) {
  if (!p || p.t == null || p.t_end == null) return "-";
  return `${(+p.t).toPrecision(4)} / ${(+p.t_end).toPrecision(4)} s`;
}

function fmtEta(p) {
  if (!p || p.eta == null) return "-";
  const s = +p.eta;
  return s < 90 ? `${s.toFixed(0)} s` : `${(s / 60).toFixed(1)} min`;
}

// ---- the jobs ----------------------------------------------------------------------------

async function refreshJobs() {
  let list;
  try {
    list = await api("list", {});
  } catch (e) {
    $("conn").textContent = e.message;
    return;
  }
  state.jobs = list.jobs || [];
  const tb = $("jobs").querySelector("tbody");
  tb.textContent = "";
  for (const j of state.jobs) {
    const tr = document.createElement("tr");
    tr.dataset.job = j.job;
    if (j.job === state.job) tr.className = "selected";
    const cells = [j.job, j.state, j.method, fmtTime(j.progress),
                   j.progress ? j.progress.steps : "-", fmtEta(j.progress), j.sweep || ""];
    cells.forEach((c, k) => {
      const td = document.createElement("td");
      td.textContent = c;
      if (k === 1) td.className = `state s-${c}`;
      tr.appendChild(td);
    });
    tr.addEventListener("click", () => select(j.job));
    tb.appendChild(tr);
  }
  $("no-jobs").hidden = state.jobs.length > 0;
  if (state.job) {
    const s = state.jobs.find((j) => j.job === state.job);
    if (s) showStatus(s);
  }
}

function showStatus(s) {
  state.status = s;
  $("job-id").textContent = s.job;
  const st = $("job-state");
  st.textContent = s.state;
  st.className = `state s-${s.state}`;
  $("job-reason").textContent = s.reason || "";
  const steer = s.steering ? JSON.stringify(s.steering, null, 1) : "no changes";
  $("steering").textContent = steer;
}

// ---- the plot ----------------------------------------------------------------------------

const SKIP = new Set(["step", "t", "seq", "job", "type"]);

// The numbers of a diag event, flattened: gauges and pressure probes by name, bodies as
// BODY.member (BODY.x.1 for a vector's component): the names the triggers use.
function flatten(ev) {
  const out = {};
  for (const [k, v] of Object.entries(ev)) {
    if (SKIP.has(k)) continue;
    if (typeof v === "number") out[k] = v;
    else if (v && typeof v === "object" && (k === "gauges" || k === "pressure")) {
      for (const [n, x] of Object.entries(v)) if (typeof x === "number") out[n] = x;
    } else if (v && typeof v === "object" && k === "bodies") {
      for (const [b, m] of Object.entries(v))
        for (const [n, x] of Object.entries(m)) {
          if (typeof x === "number") out[`${b}.${n}`] = x;
          else if (Array.isArray(x)) x.forEach((c, i) => (out[`${b}.${n}.${i}`] = c));
        }
    }
  }
  return out;
}

function addPoint(ev) {
  const f = flatten(ev);
  const n = state.series.t ? state.series.t.length : 0;
  if (n && ev.t <= state.series.t[n - 1]) return; // a replay of what export gave
  (state.series.t = state.series.t || []).push(ev.t);
  for (const [k, v] of Object.entries(f)) {
    if (!state.series[k]) state.series[k] = new Array(n).fill(null);
    state.series[k].push(v);
  }
  for (const k of Object.keys(state.series))
    if (state.series[k].length < n + 1) state.series[k].push(null);
  updateSeriesList();
  drawPlot();
}

// The history so far, from the job's diag.h5 (the export op's CSV).
async function loadHistory(job) {
  state.series = {};
  try {
    const r = await api("export", { job: job });
    const lines = r.csv.trim().split("\n");
    const cols = lines[0].split(",");
    for (const c of cols) state.series[c] = [];
    for (const line of lines.slice(1)) {
      line.split(",").forEach((v, i) => state.series[cols[i]].push(v === "" ? null : +v));
    }
    for (const c of cols) if (SKIP.has(c) && c !== "t") delete state.series[c];
  } catch (e) {
    // not run yet: the stream fills it
  }
  updateSeriesList();
  drawPlot();
}

function updateSeriesList() {
  const sel = $("series");
  const names = Object.keys(state.series).filter((k) => k !== "t").sort();
  if (names.join() === sel.dataset.names) return;
  sel.dataset.names = names.join();
  const keep = sel.value;
  sel.textContent = "";
  for (const n of names) {
    const o = document.createElement("option");
    o.textContent = n;
    sel.appendChild(o);
  }
  const pick = ["front_x", "ekin", "vmax"].find((n) => names.includes(n));
  sel.value = names.includes(keep) ? keep : pick || names[0] || "";
}

function drawPlot() {
  const name = $("series").value;
  const t = state.series.t || [];
  const y = state.series[name] || [];
  state.points = t.length;
  $("points").textContent = `${t.length} points`;
  $("plot").dataset.points = String(t.length);
  if (!name) return;
  const data = [t.slice(), y.slice()];
  if (!state.plot || state.plotted !== name) {
    if (state.plot) state.plot.destroy();
    state.plot = new uPlot({
      width: 560, height: 320,
      scales: { x: { time: false } },
      axes: [{ label: "t [s]" }, { label: name }],
      series: [{ label: "t" }, { label: name, stroke: "#2364aa", width: 1.5 }],
    }, data, $("plot"));
    state.plotted = name;
  } else {
    state.plot.setData(data);
  }
}

// ---- the event stream --------------------------------------------------------------------

async function stream() {
  for (;;) {
    try {
      const r = await fetch("/api/events", { headers: headers(false) });
      if (r.status === 401) {
        askToken();
        await new Promise((ok) => setTimeout(ok, 2000));
        continue;
      }
      $("conn").textContent = "live";
      $("conn").className = "conn live";
      const reader = r.body.getReader();
      const dec = new TextDecoder();
      let buf = "";
      for (;;) {
        const { value, done } = await reader.read();
        if (done) break;
        buf += dec.decode(value, { stream: true });
        let cut;
        while ((cut = buf.indexOf("\n\n")) >= 0) {
          const block = buf.slice(0, cut);
          buf = buf.slice(cut + 2);
          const data = block.split("\n").filter((l) => l.startsWith("data: "))
            .map((l) => l.slice(6)).join("\n");
          if (data) onEvent(JSON.parse(data));
        }
      }
    } catch (e) {
      // reconnect below
    }
    $("conn").textContent = "reconnecting";
    $("conn").className = "conn";
    await new Promise((ok) => setTimeout(ok, 1000));
  }
}

function onEvent(ev) {
  if (ev.job !== state.job) {
    if (ev.type === "state") refreshJobs();
    return;
  }
  if (ev.type === "diag") addPoint(ev);
  else if (ev.type === "state" || ev.type === "steer" || ev.type === "trigger") refreshJobs();
  if (ev.type === "trigger") say(`trigger '${ev.when}' fired at t = ${ev.t}: ${ev.do}`, true);
}

// ---- the particles -----------------------------------------------------------------------

function colourOf(x) { // a blue-green-yellow ramp, x in [0, 1]
  const c = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  const s = Math.min(Math.max(x, 0), 1) * (c.length - 1), i = Math.min(Math.floor(s), c.length - 2);
  const f = s - i;
  return `rgb(${c[i].map((v, k) => Math.round(v + f * (c[i + 1][k] - v))).join(",")})`;
}

async function loadParticles() {
  if (!state.job) return;
  const field = $("colour").value;
  const fields = ["pos", "type"];
  if (field !== "type") fields.push(field);
  try {
    const r = await api("query", { job: state.job, fields: fields, max: 20000 });
    state.view.particles = r.particles;
    state.view.field = field;
    drawParticles();
  } catch (e) {
    $("pcount").textContent = e.message;
  }
}

function drawParticles() {
  const P = state.view.particles, cv = $("particles"), g = cv.getContext("2d");
  g.clearRect(0, 0, cv.width, cv.height);
  if (!P) return;
  const pos = P.fields.pos, type = P.fields.type, f = state.view.field;
  let val = f === "type" ? type : P.fields[f];
  if (f === "vel") val = val.map((v) => Math.hypot(...v));
  const isFluid = (i) => type[i] === 0 || type[i] === "fluid";
  if (f === "type") val = type.map((v) => ({ fluid: 0, boundary: 1, lost: 2, body: 4 }[v] ?? v));
  const fluid = val.filter((v, i) => isFluid(i));
  const lo = Math.min(...fluid), hi = Math.max(...fluid);
  const dim = pos.length ? pos[0].length : 2;
  // the points in the view: 2D as they are; 3D turned by yaw and pitch (drag to turn)
  const cy = Math.cos(state.view.yaw), sy = Math.sin(state.view.yaw);
  const cp = Math.cos(state.view.pitch), sp = Math.sin(state.view.pitch);
  const pts = pos.map((p) => {
    if (dim === 2) return [p[0], p[1], 0];
    const x = cy * p[0] - sy * p[1], y = sy * p[0] + cy * p[1];
    return [x, cp * p[2] - sp * y, sp * p[2] + cp * y];
  });
  const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
  const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
  const k = 0.92 * Math.min(cv.width / (x1 - x0 || 1), cv.height / (y1 - y0 || 1));
  const order = pts.map((p, i) => i).sort((a, b) => pts[b][2] - pts[a][2]);
  const r = dim === 2 ? 1.6 : 1.3;
  for (const i of order) {
    g.fillStyle = !isFluid(i) ? "rgba(120,120,120,0.45)"
      : colourOf(hi > lo ? (val[i] - lo) / (hi - lo) : 0.5);
    const X = (cv.width - k * (x1 - x0)) / 2 + k * (pts[i][0] - x0);
    const Y = cv.height - ((cv.height - k * (y1 - y0)) / 2 + k * (pts[i][1] - y0));
    g.fillRect(X - r, Y - r, 2 * r, 2 * r);
  }
  $("pcount").textContent = `${P.count} of ${P.total} particles, ${dim}D` +
    (f !== "type" && fluid.length ? `; ${f} ${lo.toPrecision(4)} to ${hi.toPrecision(4)}` : "");
  cv.dataset.drawn = String(P.count);
}

function dragToTurn() {
  const cv = $("particles");
  let at = null;
  cv.addEventListener("mousedown", (e) => (at = [e.clientX, e.clientY]));
  window.addEventListener("mouseup", () => (at = null));
  window.addEventListener("mousemove", (e) => {
    if (!at) return;
    state.view.yaw += (e.clientX - at[0]) * 0.01;
    state.view.pitch += (e.clientY - at[1]) * 0.01;
    at = [e.clientX, e.clientY];
    drawParticles();
  });
}

// ---- the controls ------------------------------------------------------------------------

async function control(op) {
  const args = { job: state.job };
  if (op === "step") args.n = Math.max(1, +$("step-n").value || 1);
  try {
    const s = await api(op, args);
    say(`${op}: ${s.state}`, true);
  } catch (e) {
    say(e.message);
  }
  refreshJobs();
}

async function setValue() {
  const text = $("set-text").value.trim();
  if (!text) return;
  try {
    const s = await api("set", { job: state.job, set: text.split(/\s+/) });
    if (s.steering && s.steering.error) say(`not changed: ${s.steering.error}`);
    else say(`changed: ${text}`, true);
    showStatus(s);
  } catch (e) {
    say(e.message);
  }
  refreshJobs();
}

// The triggers in effect: the steered list, else the case's (its case.json).
async function currentTriggers() {
  const s = state.status || {};
  if (s.steering && s.steering.values && s.steering.values.triggers)
    return s.steering.values.triggers;
  const r = await api("fetch", { job: state.job, file: "case.json" });
  return JSON.parse(atob(r.data)).triggers || [];
}

async function addTrigger() {
  const when = $("trig-text").value.trim();
  if (!when) return;
  try {
    const list = await currentTriggers();
    list.push({ when: when, do: $("trig-do").value });
    const s = await api("set", { job: state.job, set: ["triggers=" + JSON.stringify(list)] });
    if (s.steering && s.steering.error) say(`not added: ${s.steering.error}`);
    else say(`trigger added: ${when} -> ${$("trig-do").value}`, true);
  } catch (e) {
    say(e.message);
  }
}

async function select(job) {
  state.job = job;
  $("job").hidden = false;
  if (state.plot) {
    state.plot.destroy();
    state.plot = null;
  }
  say("");
  await refreshJobs();
  await loadHistory(job);
  loadParticles();
}

async function main() {
  $("token-save").addEventListener("click", () => {
    state.token = $("token").value.trim();
    sessionStorage.setItem("sphd-token", state.token);
    $("token-box").hidden = true;
    refreshJobs();
  });
  document.querySelectorAll("button[data-op]").forEach((b) =>
    b.addEventListener("click", () => control(b.dataset.op)));
  $("set-go").addEventListener("click", setValue);
  $("trig-go").addEventListener("click", addTrigger);
  $("series").addEventListener("change", () => { state.plotted = ""; drawPlot(); });
  $("colour").addEventListener("change", loadParticles);
  $("refresh").addEventListener("click", loadParticles);
  dragToTurn();
  try {
    const h = await api("hello", {});
    $("server").textContent = `${h.server} ${h.version}`;
  } catch (e) {
    $("conn").textContent = e.message;
  }
  stream();
  await refreshJobs();
  setInterval(refreshJobs, 1500);
  const first = new URLSearchParams(location.search).get("job");
  if (first) select(first);
}

// for tests and scripts: what the page shows
window.sphdDash = { state: state, select: select, points: () => state.points };
main();
