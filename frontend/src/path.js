// The path view: a path drawn on a canvas with a grid, the travel so far and a dot where
// the machine is. What it draws is chosen in the "View" list: the feedback positions of
// the first axes, or an axis group's Cartesian feedback pose (group N: X, Y and, for a
// group of three axes or more, Z) in the group's own coordinates; the "Plane" list picks
// XY, XZ or YZ, or XYZ (an isometric projection) for a 3-D group. The columns come from
// the recording, so the time slider scrubs every view.
import { atMostEvery } from "./pace.js";

const css = (name) => getComputedStyle(document.documentElement).getPropertyValue(name).trim() || "#888";
const MAX_POINTS = 20000;
const PLANES = { XY: [0, 1], XZ: [0, 2], YZ: [1, 2] };
const COS30 = Math.cos(Math.PI / 6), SIN30 = 0.5;

export class PathView {
  constructor(canvas, plane, view) {
    this.canvas = canvas;
    this.plane = plane;
    this.view = view;
    this.axes = [];      // the first axes' columns
    this.groups = [];    // [{name, dims, channels}]
    this.cols = {};      // column name -> values, one per recorded time
    this.n = 0;          // recorded times held
    this.chosen = false; // the user picked a view: new groups do not take over
    this.dirty = false;
    plane.addEventListener("change", () => this.redraw());
    view.addEventListener("change", () => { this.chosen = true; this.fillPlanes(false); this.redraw(); });
    new ResizeObserver(() => this.redraw()).observe(canvas);
  }

  setChannels(axes, groups = []) {
    this.axes = axes;
    this.groups = [];
    this.cols = {};
    this.n = 0;
    this.chosen = false;
    this.setGroups(groups, true);
  }

  // the groups known so far (the server adds one when the program enables it)
  setGroups(groups, force = false) {
    if (!groups) return;
    const key = (gs) => JSON.stringify(gs.map((g) => [g.name, g.dims]));
    if (!force && key(groups) === key(this.groups)) return;
    const before = this.view.value;
    this.groups = groups;
    const options = [];
    if (this.axes.length) options.push(["axes", `axes ${this.axes.map((c) => c.split(".")[0]).join(", ")}`]);
    for (const g of groups) options.push([g.name, `${g.name} (${g.dims === 3 ? "XYZ" : "XY"})`]);
    this.view.replaceChildren(...options.map(([value, text]) => Object.assign(document.createElement("option"), { value, textContent: text })));
    // a group is what the program moves: it is shown once it appears, unless chosen
    const keep = options.some(([v]) => v === before) && (this.chosen || before !== "axes");
    this.view.value = keep ? before : (groups.length ? groups[0].name : "axes");
    this.view.disabled = options.length < 2;
    this.fillPlanes();
    this.redraw();
  }

  current() {
    const g = this.groups.find((x) => x.name === this.view.value);
    if (g) return { name: g.name, channels: g.channels, labels: ["X", "Y", "Z"], group: true };
    return { name: "axes", channels: this.axes, labels: this.axes.map((c) => c.split(".")[0]), group: false };
  }

  // the planes of the current view (`keep`: the one chosen stays, if the view has it)
  fillPlanes(keep = true) {
    const { channels, group } = this.current();
    const before = keep ? this.plane.value : null;
    const planes = channels.length >= 3 ? (group ? ["XYZ", "XY", "XZ", "YZ"] : ["XY", "XZ", "YZ"]) : ["XY"];
    this.plane.replaceChildren(...planes.map((p) => Object.assign(document.createElement("option"), { value: p, textContent: p })));
    this.plane.value = planes.includes(before) ? before : planes[0];
  }

  append(t, values, groups) {
    this.setGroups(groups);
    for (const name of Object.keys(values)) {
      if (!this.cols[name]) this.cols[name] = new Array(this.n).fill(null);
    }
    for (const [name, col] of Object.entries(this.cols)) {
      const v = values[name] || [];
      for (let i = 0; i < t.length; i++) col.push(v[i] ?? null);
    }
    this.n += t.length;
    if (this.n > MAX_POINTS) {
      for (const name of Object.keys(this.cols)) this.cols[name] = this.cols[name].filter((_, i) => i % 2 === 0);
      this.n = Math.ceil(this.n / 2);
    }
    this.redraw();
  }

  replace(t, values, groups) {
    this.cols = {};
    this.n = 0;
    this.append(t, values, groups);
  }

  // at most 10 times a second: the path is redrawn whole (every recorded point)
  redraw() {
    if (this.dirty) return;
    this.dirty = true;
    this.paced ??= atMostEvery(100, () => requestAnimationFrame(() => { this.dirty = false; this.draw(); }));
    this.paced();
  }

  // the points of the current view: [x, y(, z)] per recorded time that has them
  points() {
    const { channels } = this.current();
    const cols = channels.map((c) => this.cols[c] || []);
    const out = [];
    for (let i = 0; i < this.n; i++) {
      const p = cols.map((col) => col[i] ?? null);
      if (p[0] != null && (p.length < 2 || p[1] != null)) out.push(p);
    }
    return out;
  }

  draw() {
    const c = this.canvas;
    const ratio = window.devicePixelRatio || 1;
    const w = c.clientWidth, h = c.clientHeight;
    if (!w || !h) return;
    c.width = w * ratio; c.height = h * ratio;
    const g = c.getContext("2d");
    g.scale(ratio, ratio);
    g.clearRect(0, 0, w, h);
    const view = this.current();
    const dims = view.channels.length;
    const plane = this.plane.value || "XY";
    const iso = plane === "XYZ" && dims >= 3;
    const [ia, ib] = PLANES[plane] || PLANES.XY;
    const raw = this.points();
    // project: the plane's two coordinates, or the isometric view of X, Y, Z
    const project = iso
      ? (p) => [(p[0] - p[1]) * COS30, (p[2] ?? 0) + (p[0] + p[1]) * SIN30]
      : (p) => [p[ia], dims < 2 ? 0 : (p[ib] ?? 0)];
    const pts = raw.map(project);
    let box = iso ? isoBox(raw) : [[0, 0], [1, 1]];
    const xs = pts.map((p) => p[0]).concat(box.map((p) => (iso ? project(p)[0] : p[0])));
    const ys = pts.map((p) => p[1]).concat(box.map((p) => (iso ? project(p)[1] : p[1])));
    const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
    const pad = 24;
    const scale = Math.min((w - 2 * pad) / (x1 - x0 || 1), (h - 2 * pad) / (y1 - y0 || 1));
    const X = (x) => pad + (x - x0) * scale, Y = (y) => h - pad - (y - y0) * scale;
    g.strokeStyle = css("--grid"); g.lineWidth = 1;
    g.fillStyle = css("--fg"); g.font = "11px sans-serif";
    const names = view.labels;
    const where = `${view.group ? view.name + " " : ""}`;
    if (iso) {
      this.drawIsoFrame(g, raw, project, X, Y);
    } else {
      const step = niceStep((x1 - x0) / 5);
      for (let v = Math.ceil(x0 / step) * step; v <= x1; v += step) { g.beginPath(); g.moveTo(X(v), pad / 2); g.lineTo(X(v), h - pad); g.stroke(); }
      for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) { g.beginPath(); g.moveTo(pad, Y(v)); g.lineTo(w - pad / 2, Y(v)); g.stroke(); }
      g.fillText(`${where}${names[ia] || "x"} [mm] →`, Math.max(4, w - 150), h - 6);
      if (dims >= 2) g.fillText(`↑ ${names[ib]} [mm]`, 4, 12);
    }
    if (!pts.length) {
      this.canvas.setAttribute("aria-label", `Path (${where || "axes "}${plane}): nothing recorded yet`);
      return;
    }
    g.strokeStyle = css("--accent"); g.lineWidth = 1.5; g.beginPath();
    pts.forEach((p, i) => (i ? g.lineTo(X(p[0]), Y(p[1])) : g.moveTo(X(p[0]), Y(p[1]))));
    g.stroke();
    const last = pts[pts.length - 1];
    g.fillStyle = css("--danger"); g.beginPath(); g.arc(X(last[0]), Y(last[1]), 4, 0, 2 * Math.PI); g.fill();
    const at = raw[raw.length - 1];
    const shown = iso ? [0, 1, 2] : dims >= 2 ? [ia, ib] : [ia];
    this.canvas.setAttribute("aria-label", `Path (${where || "axes "}${plane}): ` + shown.map((i) => `${names[i]} ${at[i].toFixed(2)} mm`).join(", "));
  }

  // the isometric view's frame: the bounding box's three edges from its low corner,
  // labelled X, Y, Z with their ranges
  drawIsoFrame(g, raw, project, X, Y) {
    const [lo, hi] = isoBox(raw);
    const edges = [[hi[0], lo[1], lo[2]], [lo[0], hi[1], lo[2]], [lo[0], lo[1], hi[2]]];
    const o = project(lo);
    g.strokeStyle = css("--grid");
    // the bounding box's twelve edges, light: where in the box the path runs
    const corner = (m) => [0, 1, 2].map((i) => (m >> i & 1 ? hi[i] : lo[i]));
    for (let m = 0; m < 8; m++) {
      for (let i = 0; i < 3; i++) {
        if (m >> i & 1) continue;
        const a = project(corner(m)), b = project(corner(m | 1 << i));
        g.beginPath(); g.moveTo(X(a[0]), Y(a[1])); g.lineTo(X(b[0]), Y(b[1])); g.stroke();
      }
    }
    g.strokeStyle = css("--fg");
    ["X", "Y", "Z"].forEach((name, i) => {
      const e = project(edges[i]);
      g.beginPath(); g.moveTo(X(o[0]), Y(o[1])); g.lineTo(X(e[0]), Y(e[1])); g.stroke();
      g.fillText(`${name} ${fmt(lo[i])}…${fmt(hi[i])} mm`, X(e[0]) + (i === 1 ? 0 : 4), Y(e[1]) + [12, 14, -4][i]);
    });
  }
}

function isoBox(raw) {
  const lo = [0, 0, 0], hi = [1, 1, 1];
  for (const p of raw) for (let i = 0; i < 3; i++) { lo[i] = Math.min(lo[i], p[i] ?? 0); hi[i] = Math.max(hi[i], p[i] ?? 0); }
  return [lo, hi];
}

function fmt(v) {
  return Math.abs(v) >= 100 ? v.toFixed(0) : v.toFixed(1);
}

function niceStep(raw) {
  const p = 10 ** Math.floor(Math.log10(raw || 1));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}
