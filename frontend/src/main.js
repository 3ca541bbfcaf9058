// The studio page: connects to the server with the page's token and wires the panels
// to the protocol (docs/studio.md). Keyboard: F5 Run, F6 Pause, F10 Step cycle, F9 a
// breakpoint on the cursor's line; every control is a labelled native element.
import { Rpc } from "./rpc.js";
import { Editor } from "./editor.js";
import { Scope } from "./scope.js";
import { atMostEvery } from "./pace.js";
import { PathView } from "./path.js";
import { Console, AxesTable, IoPanel, DebugPanel } from "./panels.js";

const $ = (id) => document.getElementById(id);
const token = new URLSearchParams(location.search).get("token") || "";
const rpc = new Rpc(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws?token=${encodeURIComponent(token)}`);

const ui = {
  run: $("run"), pause: $("pause"), step: $("step"), reset: $("reset"),
  runTo: $("run-to"), runToTime: $("run-to-time"), speed: $("speed"), time: $("time"), status: $("status"),
  slider: $("slider"), sliderTime: $("slider-time"), span: $("scope-span"),
};
const editor = new Editor($("editor"), $("tabs"), rpc);
const scope = new Scope($("scope-plot"), $("scope-picker"), rpc, {
  a: $("cursor-a"), b: $("cursor-b"), dt: $("cursor-dt"), clear: $("cursor-clear"), table: $("cursor-table"),
});
const path = new PathView($("path"), $("plane"), $("path-view"));
const consoleView = new Console($("console"));
const axes = new AxesTable($("axes-body"));
const io = new IoPanel($("inputs"), $("outputs"), (name, on) => act("io.force", { name, value: on ? 1 : 0 }));
const debug = new DebugPanel($("stack"), $("variables"), rpc, (frame) => editor.stoppedAt(frame.file, frame.line));

let state = { running: false, time: 0, cycle: 0, recorded: 0, recorded_cycle: 0, cycle_time: 0.001 };
let scrubbing = false;
let scrubBusy = false;
let scrubNext = null;

window.studio = { scope, path, rpc, editor, get state() { return state; } };

async function act(method, params = {}) {
  try {
    return await rpc.call(method, params);
  } catch (err) {
    ui.status.textContent = err.message;
    return null;
  }
}

let wasRunning = false;
function showState(s) {
  state = { ...state, ...s };
  ui.time.textContent = `t = ${Number(state.time).toFixed(3)} s`;
  ui.run.disabled = state.running || !state.loaded;
  ui.pause.disabled = !state.running;
  ui.step.disabled = state.running || !state.loaded;
  ui.runToTime.disabled = !state.loaded;
  if (!scrubbing) {
    consoleView.showUntil(Number(state.time));
    ui.slider.max = String(Math.max(state.recorded_cycle || 0, state.cycle || 0));
    ui.slider.value = String(state.cycle);
    ui.sliderTime.textContent = `${Number(state.time).toFixed(3)} s of ${Math.max(state.recorded, state.time).toFixed(3)} s`;
  }
  if (state.running) ui.status.textContent = "running";
  else if (!state.loaded) ui.status.textContent = state.error || "no program";
  document.body.dataset.runState = state.running ? "running" : state.waits_forever ? "waits forever" : "paused";
  if (state.running && !wasRunning) { debug.running(); editor.stoppedAt(null); }
  wasRunning = state.running;
}

function describe(hello) {
  if (hello.machine) {
    io.build(hello.machine);
    path.setChannels(hello.machine.path, hello.machine.groups);
  }
  scope.setChannels(hello.scope, hello.units);
  scope.follow = true;
  showState(hello.state);
}

rpc.on("state", showState);
rpc.on("console", (p) => consoleView.add(p.lines));
rpc.on("scope", (p) => { if (!scrubbing) { scope.append(p.t, p.values); path.append(p.t, p.values, p.groups); } });
// the tables and lamps at most 10 times a second while a run goes (the scope at every update)
const showPanels = atMostEvery(100, (p) => { if (!scrubbing) { axes.show(p.axes); io.show(p.io); } });
rpc.on("panels", (p) => showPanels(p));
rpc.on("stopped", (stop) => {
  const where = stop.line ? ` at ${stop.file.split("/").pop()}:${stop.line}` : "";
  const why = { goto: "paused", pause: "paused", step: "paused after a cycle", exited: "the run ended", "waits forever": "waits forever" }[stop.reason] || stop.reason;
  ui.status.textContent = `${why}${where} (t = ${stop.time.toFixed(3)} s)${stop.text ? ": " + stop.text : ""}`;
  editor.stoppedAt(stop.file, stop.line);
  debug.paused(stop);
});
rpc.on("reset", (hello) => { consoleView.clear(); scope.setMark("a", null); scope.setMark("b", null); describe(hello); editor.stoppedAt(null); });
rpc.on("closed", () => { ui.status.textContent = "the studio's server went away"; });

ui.run.addEventListener("click", () => { scope.follow = true; act("run.start"); });
ui.pause.addEventListener("click", () => act("run.pause"));
ui.step.addEventListener("click", () => act("run.step_cycle", { count: 1 }));
ui.reset.addEventListener("click", () => act("run.reset"));
ui.runTo.addEventListener("submit", (e) => {
  e.preventDefault();
  scope.follow = true;
  act("run.to_time", { seconds: Number(ui.runToTime.value) });
});
ui.speed.addEventListener("change", () => act("run.speed", { factor: ui.speed.value === "max" ? null : Number(ui.speed.value) }));
ui.span.addEventListener("change", () => { scope.span = Number(ui.span.value); scope.follow = true; scope.redraw(); });
document.addEventListener("keydown", (e) => {
  const key = { F5: ui.run, F6: ui.pause, F10: ui.step }[e.key];
  if (key) { e.preventDefault(); if (!key.disabled) key.click(); }
});

// the time slider: dragging shows the recording; letting go moves the debugger there
async function scrub(cycle) {
  if (scrubBusy) { scrubNext = cycle; return; }
  scrubBusy = true;
  const at = await act("history.at", { cycle, span: scope.span });
  scrubBusy = false;
  if (at && scrubbing) {
    axes.show(at.axes);
    io.show(at.io);
    scope.follow = true;
    scope.replace(at.scope.t, at.scope.values);
    path.replace(at.path.t, at.path.values, at.path.groups);
    consoleView.showUntil(at.time);
    ui.sliderTime.textContent = `${at.time.toFixed(3)} s (recorded) of ${Number(state.recorded).toFixed(3)} s`;
  }
  if (scrubNext != null) { const next = scrubNext; scrubNext = null; scrub(next); }
}
ui.slider.addEventListener("input", () => {
  if (state.running) act("run.pause");
  scrubbing = true;
  scrub(Number(ui.slider.value));
});
ui.slider.addEventListener("change", async () => {
  const cycle = Number(ui.slider.value);
  const now = await act("run.seek", { cycle });
  scrubbing = false;
  if (now) showState(now);
  const all = await act("history.at", { cycle, span: null });
  if (all) {
    scope.replace(all.scope.t, all.scope.values);
    path.replace(all.path.t, all.path.values, all.path.groups);
  }
});

scope.onChosen = async () => {
  const all = await act("history.at", { cycle: state.recorded_cycle || 0, span: null });
  if (all) scope.replace(all.scope.t, all.scope.values);
};

async function main() {
  try {
    await rpc.open();
  } catch (err) {
    ui.status.textContent = err.message;
    return;
  }
  const hello = await rpc.call("studio.hello");
  for (const f of hello.files) {
    const file = await rpc.call("file.open", { path: f.path });
    editor.add({ ...file, name: f.name });
  }
  editor.onBreakpoints = async (p, lines) => {
    const bps = await act("breakpoints.set", { path: p, lines });
    if (bps) ui.status.textContent = bps.filter((b) => !b.verified).map((b) => `line ${b.line}: ${b.message}`).join("; ") || ui.status.textContent;
  };
  describe(hello);
  ui.status.textContent = hello.state.loaded ? "ready (paused at t = 0)" : hello.state.error;
  $("scope-picker").addEventListener("toggle", (e) => { if (e.target.open) scope.fillPicker(); }, { once: true });
  document.body.dataset.ready = "true";
}

main();
