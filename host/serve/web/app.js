// mahost serve's page: the state of the printer and its job, live, and its controls.
// Talks to the same API as the slicers (OctoPrint's) plus /api/mahost/*; the API key is kept
// in this browser's localStorage and sent as X-Api-Key, never as a cookie.
"use strict";

const KEY_STORE = "mahost-api-key";
const CHART_SECONDS = 600;
const $ = (id) => document.getElementById(id);

const state = {
  key: localStorage.getItem(KEY_STORE) || "",
  status: null,
  lastEvent: 0,
  temps: [],            // {t, hotend, hotendTarget, bed, bedTarget}
  layerShown: null,     // "layer:commandsDone" last drawn
  layerFetchedAt: 0,
  profiles: null,
  filesVersion: "",
  streaming: false,
  instance: null,       // the server process the page last heard from
  lost: false,          // the server stopped answering
  lostSince: 0,
  heard: 0,             // when the live stream last brought anything
  uploading: false,
};

// ---- the API ---------------------------------------------------------------------------

class KeyRefused extends Error {}
class ServerLost extends Error {}

async function api(method, path, body) {
  const options = { method, headers: { "X-Api-Key": state.key } };
  if (body !== undefined) {
    options.headers["Content-Type"] = "application/json";
    options.body = JSON.stringify(body);
  }
  let response;
  try {
    response = await fetch(path, options);
  } catch (e) {
    serverLost();
    throw new ServerLost("the server does not answer");
  }
  serverFound();
  if (response.status === 401 || response.status === 403) {
    askForKey(response.status === 401 ? "The printer needs its API key." : "The printer refused this key.");
    throw new KeyRefused();
  }
  const text = await response.text();
  let data = null;
  try { data = text ? JSON.parse(text) : null; } catch (e) { data = null; }
  if (!response.ok) {
    const message = data && data.error ? data.error : `${response.status} ${response.statusText}`;
    throw new Error(message);
  }
  return data;
}

function report(error) {
  if (error instanceof KeyRefused || error instanceof ServerLost) return;
  addLocalEvent(`error: ${error.message}`);
}

// Whether the server took it; a refusal is reported in the event list.
async function act(method, path, body) {
  try {
    await api(method, path, body);
    return true;
  } catch (e) {
    report(e);
    return false;
  }
}

// ---- a lost server ---------------------------------------------------------------------

// The page keeps what it last knew, says since when it has not heard, and takes no clicks
// until the server answers again.
function serverLost() {
  if (!state.lost) {
    state.lost = true;
    state.lostSince = Date.now() / 1000;
    addLocalEvent("the server does not answer");
  }
  const pill = $("state-pill");
  pill.textContent = "Server lost";
  pill.dataset.state = "lost";
  $("lost-card").hidden = false;
  $("lost-text").textContent = `mahost serve has not answered since ${timeOfDay(state.lostSince)}. ` +
    "What this page shows is what it knew then; it tries again every 2 s.";
  updateControls();
}

function serverFound() {
  if (!state.lost) return;
  state.lost = false;
  $("lost-card").hidden = true;
  addLocalEvent("the server answers again");
  updateControls();
}

// ---- the key ---------------------------------------------------------------------------

function askForKey(message) {
  $("key-card").hidden = false;
  $("key-error").textContent = message || "";
  $("key-input").focus();
}

$("key-form").addEventListener("submit", async (event) => {
  event.preventDefault();
  state.key = $("key-input").value.trim();
  try {
    await api("GET", "/api/version");
    localStorage.setItem(KEY_STORE, state.key);
    $("key-card").hidden = true;
    $("key-input").value = "";
    start();
  } catch (e) {
    report(e);
  }
});

// ---- formatting ------------------------------------------------------------------------

function clock(seconds) {
  if (seconds === null || seconds === undefined || !isFinite(seconds)) return "—";
  const s = Math.max(0, Math.round(seconds));
  const h = Math.floor(s / 3600), m = Math.floor((s % 3600) / 60), r = s % 60;
  return h > 0 ? `${h}:${String(m).padStart(2, "0")}:${String(r).padStart(2, "0")}` : `${m}:${String(r).padStart(2, "0")}`;
}

function duration(seconds) {
  if (!seconds && seconds !== 0) return "";
  const s = Math.round(seconds);
  const h = Math.floor(s / 3600), m = Math.round((s % 3600) / 60);
  return h > 0 ? `${h} h ${m} min` : `${Math.max(1, m)} min`;
}

function bytes(n) {
  if (n >= 1 << 30) return `${(n / (1 << 30)).toFixed(1)} GiB`;
  if (n >= 1 << 20) return `${(n / (1 << 20)).toFixed(1)} MiB`;
  if (n >= 1 << 10) return `${(n / (1 << 10)).toFixed(0)} KiB`;
  return `${n} B`;
}

function degrees(v) { return v === null || v === undefined ? "—" : `${v.toFixed(1)} °C`; }

function timeOfDay(unix) {
  return new Date(unix * 1000).toLocaleTimeString([], { hour: "2-digit", minute: "2-digit", second: "2-digit" });
}

function element(tag, className, text) {
  const e = document.createElement(tag);
  if (className) e.className = className;
  if (text !== undefined) e.textContent = text;
  return e;
}

// ---- rendering the status -------------------------------------------------------------

function render(s) {
  // Another server process than before (restarted): its events count from 1 again.
  const restarted = state.instance !== null && s.instance !== state.instance;
  state.instance = s.instance;
  if (restarted) {
    state.lastEvent = 0;
    $("events").replaceChildren();
    addLocalEvent("the server restarted");
    state.layerShown = null;
    api("GET", "/api/mahost/status?events_after=0").then((fresh) => {
      loadHistory(fresh.history);
      render(fresh);
    }, report);
  }
  state.status = s;
  const job = s.job || {};
  const file = job.file || {};
  const m = s.mahost || {};
  const p = s.progress || {};
  const text = s.state;
  // Heating before the first layer (a pause asked meanwhile waits for it: "Pausing").
  const heating = !!m.heating && (text === "Printing" || text === "Pausing");
  const pill = $("state-pill");
  pill.textContent = heating && text === "Printing" ? "Heating" : text;
  const key = text.startsWith("Offline") || text === "Error" ? "error"
    : text === "Opening serial connection" ? "offline" : heating && text === "Printing" ? "heating" : text.toLowerCase();
  pill.dataset.state = key;
  $("printer-name").textContent = s.connection ? `${s.connection.link}${s.connection.firmware ? " · " + s.connection.firmware : ""}` : "";

  $("job-file").textContent = file.name ? file.name : "no file selected";
  const active = ["Printing", "Pausing", "Paused", "Cancelling"].includes(text) || m.jobState === "starting";
  const completion = p.completion === null || p.completion === undefined ? 0 : p.completion;
  $("progress-fill").style.width = `${Math.min(100, Math.max(0, completion)).toFixed(1)}%`;
  $("progress").setAttribute("aria-valuenow", completion.toFixed(0));
  const t = s.temperature || {};
  const tool = t.tool0 || {}, bed = t.bed || {};
  const heater = (name, h) => h.target ? `${name} ${h.actual === null ? "—" : h.actual.toFixed(0)}/${h.target.toFixed(0)} °C` : "";
  let label = "idle";
  if (heating) {
    label = ["heating", heater("hotend", tool), heater("bed", bed)].filter(Boolean).join(" · ");
  } else if (m.layers) {
    const layer = m.layer > 0 ? `layer ${m.layer}/${m.layers}` : `start of ${m.layers} layers`;
    label = `${layer} · ${completion.toFixed(1)}%`;
    if (!active && m.jobState !== "none") label = `${m.jobState} · ${label}`;
  } else if (m.jobState === "starting") {
    label = "starting";
  } else if (file.name) {
    label = "ready";
  }
  $("progress-label").textContent = label;
  $("fact-layer").textContent = m.layers ? `${Math.max(m.layer, 0)}/${m.layers}` : "—";
  $("fact-elapsed").textContent = clock(p.printTime);
  // While heating at a pace not known yet, the time left cannot be told.
  $("fact-left").textContent = heating && m.heating.secondsLeft === null ? "heating…"
    : active && m.estimating ? "estimating…"
    : active ? clock(p.printTimeLeft) : (m.jobState === "completed" ? "done" : "—");
  $("fact-z").textContent = m.z !== null && m.z !== undefined ? `${m.z.toFixed(2)} mm` : "—";

  const notes = [];
  if (m.pauseBeforeLayer > 0 && text !== "Paused") {
    notes.push(`pausing before layer ${m.pauseBeforeLayer}` + (heating ? ", once the heat-up has ended" : ""));
  }
  if (m.contour) notes.push(`${m.contour} contour`);
  if (job.estimatedPrintTime) notes.push(`estimated ${duration(job.estimatedPrintTime)}`);
  if (!active && m.endedReason) notes.push(m.endedReason);
  if (s.error) notes.push(s.error);
  $("job-note").textContent = notes.join(" · ");

  updateControls();

  const planned = s.pauseAt || [];
  $("pause-at-now").textContent = planned.length ? `pausing before ${planned.join(", ")}` : "";

  $("t-hotend").textContent = degrees(tool.actual);
  $("t-hotend-target").textContent = tool.target ? `/ ${tool.target.toFixed(0)} °C` : "";
  $("t-bed").textContent = degrees(bed.actual);
  $("t-bed-target").textContent = bed.target ? `/ ${bed.target.toFixed(0)} °C` : "";
  addTemperature(Date.now() / 1000, tool, bed);

  const interrupted = s.interrupted;
  $("interrupted-card").hidden = !interrupted;
  if (interrupted) {
    const name = interrupted.file.split("/").pop();
    $("interrupted-text").textContent =
      `${name} stopped at layer ${interrupted.layer}/${interrupted.layers} (${interrupted.state}` +
      `${interrupted.reason ? ": " + interrupted.reason : ""}, ${interrupted.updated}). ` +
      "Finishing it re-heats, homes X and Y, and reprints that layer from its start.";
  }
  const broken = s.connection && s.connection.error && !operational && text !== "Opening serial connection";
  $("error-card").hidden = !broken;
  if (broken) {
    const retries = s.connection.retries;
    $("error-text").textContent = s.connection.error +
      (retries ? ` — tried again ${retries} time${retries === 1 ? "" : "s"} so far` : "");
  }

  const slicing = s.slicing;
  $("slicing").hidden = !slicing;
  if (slicing) {
    $("slicing").textContent = slicing.stage === "done"
      ? `Sliced ${slicing.gcode}: ${slicing.summary}${slicing.plan ? "; " + slicing.plan : ""}`
      : slicing.stage === "failed" ? `Slicing ${slicing.model} failed: ${slicing.error}`
      : `Slicing ${slicing.model} → ${slicing.gcode}: ${slicing.stage} ${slicing.total ? `${slicing.done}/${slicing.total}` : ""}`;
  }

  if (!restarted) for (const e of s.events || []) addEvent(e);
  drawLayerSoon();
  const filesVersion = `${file.name}|${slicing ? slicing.stage + slicing.gcode : ""}|${m.jobState}|` +
    `${JSON.stringify(s.fileLocks || {})}|${s.startRefusal || ""}`;
  if (filesVersion !== state.filesVersion) {
    state.filesVersion = filesVersion;
    loadFiles();
  }
}

// Every control enabled only when it can act: with the key, the server answering, and the
// printer and its job in a state the control applies to.
function updateControls() {
  const s = state.status;
  const live = !!state.key && !state.lost && !!s;
  const text = s ? s.state : "";
  const m = (s && s.mahost) || {};
  const file = (s && s.job && s.job.file) || {};
  const operational = live && s.printer && s.printer.flags && s.printer.flags.operational;
  const active = live && (["Printing", "Pausing", "Paused", "Cancelling"].includes(text) || m.jobState === "starting");
  const paused = text === "Paused" || text === "Pausing";
  $("start").disabled = !operational || active || !file.name || !!s.startRefusal;
  $("start").title = live && s.startRefusal ? s.startRefusal : "";
  $("pause").hidden = live && paused;
  $("resume").hidden = !(live && paused);
  $("pause").disabled = !live || text !== "Printing";
  $("resume").disabled = !live || !paused;
  $("cancel").disabled = !active || text === "Cancelling";
  $("stop").disabled = !operational;
  for (const id of ["tune-hotend", "tune-bed", "tune-fan", "tune-speed", "tune-flow", "tune-set", "tune-down",
                    "tune-up", "gcode-line", "gcode-send"]) $(id).disabled = !operational;
  $("gcode-note").textContent = operational && active
    ? "while printing: temperatures, fan, M220, M221, M290, M117, M105, M114" : "";
  for (const id of ["pause-at-input", "pause-at-set"]) $(id).disabled = !live;
  for (const id of ["reconnect", "resume-interrupted", "discard-interrupted"]) $(id).disabled = !live;
  $("resume-interrupted").disabled = !operational || active;
  $("upload-button").disabled = !live || state.uploading;
  for (const b of document.querySelectorAll("#file-list button")) {
    b.disabled = !live || (b.dataset.refusal || "") !== "";
    b.title = live ? b.dataset.refusal || "" : "";
  }
}

// ---- events ----------------------------------------------------------------------------

function addEvent(e) {
  if (e.id <= state.lastEvent) return;
  state.lastEvent = e.id;
  prependEvent(e.time, e.text);
}

function addLocalEvent(text) { prependEvent(Date.now() / 1000, text); }

function prependEvent(time, text) {
  const list = $("events");
  const item = element("li");
  item.append(element("time", "", timeOfDay(time)), element("span", "", text));
  list.prepend(item);
  while (list.children.length > 100) list.lastChild.remove();
}

// ---- temperatures ----------------------------------------------------------------------

function addTemperature(t, tool, bed) {
  const last = state.temps[state.temps.length - 1];
  if (last && t - last.t < 1) return;
  state.temps.push({ t, hotend: tool.actual, hotendTarget: tool.target, bed: bed.actual, bedTarget: bed.target });
  while (state.temps.length && state.temps[0].t < t - CHART_SECONDS) state.temps.shift();
  drawChart();
}

function drawChart() {
  const points = state.temps;
  const chart = $("chart");
  // Drawn in the chart's own pixels, so its lines and labels keep their shape at any width.
  const width = Math.max(200, Math.round(chart.clientWidth || 600)), height = 170, top = 16, bottom = 6;
  chart.setAttribute("viewBox", `0 0 ${width} ${height}`);
  let max = 60;
  for (const p of points) max = Math.max(max, p.hotend || 0, p.hotendTarget || 0, p.bed || 0, p.bedTarget || 0);
  max = Math.ceil((max + 10) / 50) * 50;
  const now = Date.now() / 1000;
  const x = (t) => width * (1 - (now - t) / CHART_SECONDS);
  const y = (v) => top + (height - top - bottom) * (1 - v / max);
  const line = (field) => points.filter((p) => p[field] !== null && p[field] !== undefined)
    .map((p) => `${x(p.t).toFixed(1)},${y(p[field]).toFixed(1)}`).join(" ");
  $("line-hotend").setAttribute("points", line("hotend"));
  $("line-bed").setAttribute("points", line("bed"));
  $("line-hotend-target").setAttribute("points", line("hotendTarget"));
  $("line-bed-target").setAttribute("points", line("bedTarget"));
  const grid = $("chart-grid");
  grid.replaceChildren();
  const ns = "http://www.w3.org/2000/svg";
  for (let v = 0; v <= max; v += max > 150 ? 50 : 25) {
    const l = document.createElementNS(ns, "line");
    l.setAttribute("class", "gridline");
    l.setAttribute("x1", 0); l.setAttribute("x2", width);
    l.setAttribute("y1", y(v)); l.setAttribute("y2", y(v));
    const label = document.createElementNS(ns, "text");
    label.setAttribute("class", "gridlabel");
    label.setAttribute("x", 4); label.setAttribute("y", y(v) - 4);
    label.textContent = `${v}°`;
    grid.append(l, label);
  }
}

function loadHistory(history) {
  state.temps = [];
  for (const p of history || []) {
    state.temps.push({ t: p.time, hotend: p.tool0.actual, hotendTarget: p.tool0.target, bed: p.bed.actual, bedTarget: p.bed.target });
  }
  drawChart();
}

// ---- the layer drawing -----------------------------------------------------------------

let layerTimer = null;
function drawLayerSoon() {
  if (layerTimer) return;
  layerTimer = setTimeout(() => { layerTimer = null; drawLayer(); }, 150);
}

async function drawLayer() {
  const s = state.status;
  const m = (s && s.mahost) || {};
  if (!m.layers) return;
  const shown = `${m.layer}:${m.commandsDone}`;
  const printing = s.state === "Printing" || s.state === "Pausing";
  // The current layer's done part grows as it prints: redrawn at most every 1.5 s.
  if (shown === state.layerShown || (printing && Date.now() - state.layerFetchedAt < 1500 &&
      state.layerShown && state.layerShown.split(":")[0] === String(m.layer))) return;
  state.layerShown = shown;
  state.layerFetchedAt = Date.now();
  try {
    const layer = await api("GET", `/api/mahost/layer?layer=${Math.max(1, m.layer)}`);
    const [minX, minY, maxX, maxY] = layer.bounds;
    const margin = Math.max(2, 0.06 * Math.max(maxX - minX, maxY - minY));
    const w = Math.max(maxX - minX, 1) + 2 * margin, h = Math.max(maxY - minY, 1) + 2 * margin;
    const size = Math.max(w, h);
    const cx = (minX + maxX) / 2, cy = (minY + maxY) / 2;
    $("drawing").setAttribute("viewBox", `${cx - size / 2} ${-cy - size / 2} ${size} ${size}`);
    $("drawing-flip").setAttribute("transform", "scale(1,-1)");
    const bed = $("bed");
    bed.setAttribute("x", 0); bed.setAttribute("y", 0);
    bed.setAttribute("width", layer.bed[0]); bed.setAttribute("height", layer.bed[1]);
    $("path-done").setAttribute("d", layer.done);
    $("path-todo").setAttribute("d", layer.todo);
    $("path-travel").setAttribute("d", layer.travel);
    $("layer-caption").textContent = `layer ${layer.layer}/${layer.layers}` +
      (layer.z !== null ? ` at ${layer.z.toFixed(2)} mm` : "") + ` · ${layer.moves} move${layer.moves === 1 ? "" : "s"}`;
  } catch (e) {
    report(e);
  }
}

// ---- files and uploads -----------------------------------------------------------------

async function loadFiles() {
  let data;
  try { data = await api("GET", "/api/files"); } catch (e) { report(e); return; }
  $("free-space").textContent = `${bytes(data.free)} free`;
  const list = $("file-list");
  list.replaceChildren();
  const selected = state.status && state.status.job && state.status.job.file ? state.status.job.file.name : null;
  if (!data.files.length) list.append(element("li", "empty", "No files yet: upload a G-code or STL file."));
  for (const f of data.files) {
    const item = element("li");
    item.append(element("span", "name" + (f.name === selected ? " selected" : ""), f.name));
    const meta = [bytes(f.size), new Date(f.date * 1000).toLocaleString()];
    if (f.gcodeAnalysis) {
      meta.push(duration(f.gcodeAnalysis.estimatedPrintTime));
      meta.push(`${(f.gcodeAnalysis.filament.length / 1000).toFixed(2)} m`);
    }
    if (f.mahost && f.mahost.layers) meta.push(`${f.mahost.layers} layers`);
    if (f.mahost && f.mahost.contour) meta.push(f.mahost.contour);
    if (f.mahost && f.mahost.error) meta.push(f.mahost.error);
    item.append(element("span", "meta", meta.filter(Boolean).join(" · ")));
    const actions = element("span", "actions");
    // Why a button cannot act on this file now (the server's reasons), kept on the button.
    const locks = (state.status && state.status.fileLocks) || {};
    const startRefusal = (state.status && state.status.startRefusal) || "";
    if (f.type === "machinecode") {
      const print = element("button", "primary", "Print");
      print.dataset.refusal = locks[f.name] || startRefusal;
      print.addEventListener("click", () => act("POST", `/api/files/local/${encodeURIComponent(f.name)}`, { command: "select", print: true }));
      actions.append(print);
    } else {
      const slice = element("button", "", "Slice");
      slice.addEventListener("click", () => sliceStored(f.name));
      actions.append(slice);
    }
    const remove = element("button", "", "Delete");
    remove.dataset.refusal = locks[f.name] || "";
    remove.addEventListener("click", async () => {
      if (!confirm(`Delete ${f.name}?`)) return;
      await act("DELETE", `/api/files/local/${encodeURIComponent(f.name)}`);
      loadFiles();
    });
    actions.append(remove);
    item.append(actions);
    list.append(item);
  }
  updateControls();
}

// The form's settings as the slice command's fields (the upload sends the same as form fields).
// Values are sent as typed: the server checks them and says what is wrong in one line.
function sliceOptions() {
  const options = {
    printer: $("opt-printer").value, material: $("opt-material").value,
    contour: $("opt-contour").value, units: $("opt-units").value, up: $("opt-up").value,
    support: $("opt-support").value, raft: $("opt-raft").checked ? "true" : "false",
  };
  if ($("opt-height").value) options.height = $("opt-height").value;
  if ($("opt-brim").value !== "") options.brim = $("opt-brim").value;
  if ($("opt-orient").checked) options.orient = "auto";
  if ($("opt-adaptive").checked) {
    options.adaptive = "true";
    if ($("opt-tolerance").value !== "") options.tolerance = $("opt-tolerance").value;
    if ($("opt-max-layers").value !== "") options.maxLayers = $("opt-max-layers").value;
    if ($("opt-max-time").value.trim() !== "") options.maxTime = $("opt-max-time").value.trim();
  } else {
    options.layer = $("opt-layer").value;
  }
  return options;
}

async function sliceStored(name) {
  $("slice-options").hidden = false;
  try {
    await api("POST", `/api/files/local/${encodeURIComponent(name)}`,
      Object.assign({ command: "slice", print: $("upload-print").checked }, sliceOptions()));
    $("upload-message").textContent = `Slicing ${name} on the host…`;
  } catch (e) {
    if (!(e instanceof KeyRefused)) $("upload-message").textContent = `Refused: ${e.message}`;
    report(e);
  }
}

// The chosen printer's thicknesses and, for every field the printer profile decides, its value.
function fillDefaults() {
  const printer = (state.profiles.printers || []).find((p) => p.id === $("opt-printer").value);
  const select = $("opt-layer");
  select.replaceChildren();
  if (!printer) return;
  const values = printer.layers.length ? printer.layers : [printer.defaultLayer];
  for (const v of values) {
    const o = element("option", "", `${v} mm`);
    o.value = v;
    if (v === printer.defaultLayer) o.selected = true;
    select.append(o);
  }
  if (printer.material) $("opt-material").value = printer.material;
  const d = printer.defaults || {};
  if (d.support) $("opt-support").value = d.support;
  $("opt-brim").value = d.brim !== undefined ? d.brim : "";
  $("opt-raft").checked = !!d.raft;
  $("opt-orient").checked = d.orient === "auto";
  $("opt-adaptive").checked = !!d.adaptive;
  $("opt-tolerance").value = "";
  $("opt-tolerance").placeholder = d.tolerance !== undefined ? `${d.tolerance}` : "";
  $("opt-max-layers").value = "";
  $("opt-max-time").value = "";
  adaptiveChanged();
  $("opt-defaults").textContent = `${printer.name}'s defaults: support ${d.support}, brim ${d.brim} mm, ` +
    `${d.raft ? "on a raft" : "no raft"}, ${printer.defaultLayer} mm layers` +
    (d.tolerance !== undefined ? ` (adaptive: tolerance ${d.tolerance} mm)` : "");
}

// Adaptive layers choose their own thicknesses: the layer choice gives way to the plan's.
function adaptiveChanged() {
  const adaptive = $("opt-adaptive").checked;
  $("opt-layer").disabled = adaptive;
  $("opt-tolerance").disabled = !adaptive;
  $("opt-max-layers").disabled = !adaptive;
  $("opt-max-time").disabled = !adaptive;
}

async function loadProfiles() {
  try { state.profiles = await api("GET", "/api/mahost/profiles"); } catch (e) { report(e); return; }
  const fill = (id, items, chosen) => {
    const select = $(id);
    select.replaceChildren();
    for (const item of items) {
      const o = element("option", "", item.name || item);
      o.value = item.id || item;
      if ((item.id || item) === chosen) o.selected = true;
      select.append(o);
    }
  };
  fill("opt-printer", state.profiles.printers, state.profiles.serving.printer);
  fill("opt-material", state.profiles.materials, state.profiles.serving.material);
  fill("opt-contour", state.profiles.contours, "best");
  fill("opt-support", state.profiles.supports || [], "");
  fillDefaults();
  $("opt-material").value = state.profiles.serving.material;
}

$("opt-printer").addEventListener("change", fillDefaults);
$("opt-adaptive").addEventListener("change", adaptiveChanged);

// A model the host slices before printing (as file_store.cpp's kind_of).
const isModel = (name) => /\.(stl|3mf|obj)$/i.test(name);

$("upload-file").addEventListener("change", () => {
  const file = $("upload-file").files[0];
  $("upload-name").textContent = file ? `${file.name} (${bytes(file.size)})` : "Choose a G-code file or a model…";
  $("slice-options").hidden = !(file && isModel(file.name));
});

$("upload-form").addEventListener("submit", (event) => {
  event.preventDefault();
  const file = $("upload-file").files[0];
  if (!file) return;
  const form = new FormData();
  form.append("file", file, file.name);
  const print = $("upload-print").checked;
  form.append("print", print ? "true" : "false");
  form.append("select", "true");  // ready for Start (taken only while no job runs)
  if (isModel(file.name)) {
    form.append("slice", "true");
    for (const [k, v] of Object.entries(sliceOptions())) form.append(k, v);
  }
  // XMLHttpRequest for its upload progress; the key in the header, as every call.
  const request = new XMLHttpRequest();
  request.open("POST", "/api/files/local");
  request.setRequestHeader("X-Api-Key", state.key);
  $("upload-progress").hidden = false;
  state.uploading = true;
  $("upload-button").disabled = true;
  $("upload-message").textContent = "";
  request.upload.addEventListener("progress", (e) => {
    if (e.lengthComputable) $("upload-fill").style.width = `${(100 * e.loaded / e.total).toFixed(0)}%`;
  });
  request.addEventListener("loadend", () => {
    state.uploading = false;
    updateControls();
    $("upload-progress").hidden = true;
    $("upload-fill").style.width = "0";
    let data = null;
    try { data = JSON.parse(request.responseText); } catch (e) { data = null; }
    if (request.status === 401 || request.status === 403) {
      askForKey("The printer refused this key.");
    } else if (request.status === 201) {
      const notPrinted = data && data.mahost && data.mahost.notPrinted;
      $("upload-message").textContent = data && data.error ? `Stored, not sliced: ${data.error}`
        : notPrinted ? `Uploaded, not printed: ${notPrinted}`
        : data && !data.done ? "Uploaded: slicing on the host…" : "Uploaded.";
      // The slice settings stay for the next upload; the file and "print" do not.
      $("upload-file").value = "";
      $("upload-print").checked = false;
      $("upload-name").textContent = "Choose a G-code file or a model…";
      $("slice-options").hidden = true;
    } else if (request.status === 0) {
      $("upload-message").textContent = "The upload failed: the server did not answer.";
    } else {
      $("upload-message").textContent = `Refused: ${data && data.error ? data.error : request.status}`;
    }
    loadFiles();
  });
  request.send(form);
});

// ---- controls --------------------------------------------------------------------------

$("pause-at-form").addEventListener("submit", (event) => {
  event.preventDefault();
  const text = $("pause-at-input").value.trim();
  const layers = text ? text.split(/[\s,;]+/).filter(Boolean).map(Number) : [];
  if (layers.some((n) => !Number.isInteger(n) || n < 1)) {
    addLocalEvent("pause before layers: give whole layer numbers from 1, e.g. 20, 45");
    return;
  }
  act("POST", "/api/mahost/pause-at", { layers }).then((taken) => { if (taken) $("pause-at-input").value = ""; });
});

$("start").addEventListener("click", () => act("POST", "/api/job", { command: "start" }));
$("pause").addEventListener("click", () => act("POST", "/api/job", { command: "pause", action: "pause" }));
$("resume").addEventListener("click", () => act("POST", "/api/job", { command: "pause", action: "resume" }));
$("cancel").addEventListener("click", () => {
  if (confirm("Cancel the print? The heaters go off and the nozzle parks.")) act("POST", "/api/job", { command: "cancel" });
});
$("stop").addEventListener("click", () => {
  if (confirm("Emergency stop? The printer halts at once (M112) and needs a reset.")) act("POST", "/api/mahost/stop");
});
// Tuning: what was filled in as G-code lines, taken mid-print (between the job's lines) as
// well as idle; the server refuses anything else mid-print and says why.
$("tune-form").addEventListener("submit", (event) => {
  event.preventDefault();
  const value = (id) => $(id).value.trim() === "" ? null : Number($(id).value);
  const commands = [];
  const hotend = value("tune-hotend"), bed = value("tune-bed"), fan = value("tune-fan");
  const speed = value("tune-speed"), flow = value("tune-flow");
  if (hotend !== null) commands.push(`M104 S${Math.round(hotend)}`);
  if (bed !== null) commands.push(`M140 S${Math.round(bed)}`);
  if (fan !== null) commands.push(fan > 0 ? `M106 S${Math.round(Math.min(fan, 100) * 2.55)}` : "M107");
  if (speed !== null) commands.push(`M220 S${Math.round(speed)}`);
  if (flow !== null) commands.push(`M221 S${Math.round(flow)}`);
  if (!commands.length) return;
  act("POST", "/api/printer/command", { commands }).then((taken) => {
    if (taken) for (const id of ["tune-hotend", "tune-bed", "tune-fan", "tune-speed", "tune-flow"]) $(id).value = "";
  });
});
$("tune-down").addEventListener("click", () => act("POST", "/api/printer/command", { command: "M290 Z-0.05" }));
$("tune-up").addEventListener("click", () => act("POST", "/api/printer/command", { command: "M290 Z0.05" }));
$("gcode-form").addEventListener("submit", (event) => {
  event.preventDefault();
  const command = $("gcode-line").value.trim();
  if (!command) return;
  act("POST", "/api/printer/command", { command }).then((taken) => { if (taken) $("gcode-line").value = ""; });
});
$("reconnect").addEventListener("click", () => act("POST", "/api/connection", { command: "connect" }));
$("resume-interrupted").addEventListener("click", () => act("POST", "/api/mahost/interrupted", { command: "resume" }));
$("discard-interrupted").addEventListener("click", () => {
  if (confirm("Discard the interrupted job? It cannot be resumed afterwards.")) act("POST", "/api/mahost/interrupted", { command: "discard" });
});

// ---- live updates ----------------------------------------------------------------------

// Server-sent events read through fetch, so the key goes in a header (EventSource cannot).
async function stream() {
  state.streaming = true;
  // The server says something every 10 s at least: silence for three times that is a lost
  // server (a machine gone from the network closes nothing).
  const abort = new AbortController();
  state.heard = Date.now();
  const watchdog = setInterval(() => { if (Date.now() - state.heard > 30000) abort.abort(); }, 5000);
  try {
    const response = await fetch("/api/mahost/events", { headers: { "X-Api-Key": state.key }, signal: abort.signal });
    serverFound();
    if (response.status === 401 || response.status === 403) { askForKey("The printer refused this key."); return; }
    if (!response.ok || !response.body) throw new Error(`live updates: ${response.status}`);
    const reader = response.body.getReader();
    const decoder = new TextDecoder();
    let buffer = "";
    for (;;) {
      const { value, done } = await reader.read();
      if (done) break;
      state.heard = Date.now();
      buffer += decoder.decode(value, { stream: true });
      let end;
      while ((end = buffer.indexOf("\n\n")) >= 0) {
        const message = buffer.slice(0, end);
        buffer = buffer.slice(end + 2);
        const data = message.split("\n").filter((l) => l.startsWith("data: ")).map((l) => l.slice(6)).join("\n");
        if (data) render(JSON.parse(data));
      }
    }
  } catch (e) {
    // falls back to polling until the stream comes back
  } finally {
    clearInterval(watchdog);
    state.streaming = false;
  }
}

async function poll() {
  if (!state.key || state.streaming) return;
  try {
    render(await api("GET", `/api/mahost/status?events_after=${state.lastEvent}`));
  } catch (e) {
    report(e);
  }
}

let started = false;
async function start() {
  try {
    const version = await api("GET", "/api/version");
    $("version").textContent = version.mahost;
    const status = await api("GET", `/api/mahost/status?events_after=0`);
    loadHistory(status.history);
    render(status);
  } catch (e) {
    report(e);
    return;
  }
  loadProfiles();
  if (started) return;
  started = true;
  const keepStreaming = async () => {
    await stream();
    setTimeout(keepStreaming, 2000);
  };
  keepStreaming();
  setInterval(poll, 2000);
  setInterval(drawChart, 5000);
}

if (state.key) start(); else askForKey("");
