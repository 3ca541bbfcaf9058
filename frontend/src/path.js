// The path view: the feedback positions of the first axes (a group's X, Y, Z) drawn on a
// canvas, in the plane chosen (XY, XZ or YZ), with a grid, the travel so far and a dot
// where the machine is.
const css = (name) => getComputedStyle(document.documentElement).getPropertyValue(name).trim() || "#888";
const MAX_POINTS = 20000;

export class PathView {
  constructor(canvas, plane) {
    this.canvas = canvas;
    this.plane = plane;
    this.channels = [];
    this.points = [];
    this.dirty = false;
    plane.addEventListener("change", () => this.redraw());
    new ResizeObserver(() => this.redraw()).observe(canvas);
  }

  setChannels(channels) {
    this.channels = channels;
    this.points = [];
    const planes = channels.length >= 3 ? ["XY", "XZ", "YZ"] : ["XY"];
    this.plane.replaceChildren(...planes.map((p) => Object.assign(document.createElement("option"), { value: p, textContent: p })));
    this.redraw();
  }

  append(t, values) {
    const cols = this.channels.map((c) => values[c] || []);
    for (let i = 0; i < t.length; i++) this.points.push(cols.map((col) => col[i] ?? null));
    if (this.points.length > MAX_POINTS) this.points = this.points.filter((_, i) => i % 2 === 0);
    this.redraw();
  }

  replace(t, values) {
    this.points = [];
    this.append(t, values);
  }

  redraw() {
    if (this.dirty) return;
    this.dirty = true;
    requestAnimationFrame(() => { this.dirty = false; this.draw(); });
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
    const [ia, ib] = { XY: [0, 1], XZ: [0, 2], YZ: [1, 2] }[this.plane.value || "XY"];
    const pts = this.points.filter((p) => p[ia] != null && (p[ib] != null || this.channels.length < 2));
    const ys = (p) => (this.channels.length < 2 ? 0 : p[ib]);
    let x0 = Math.min(...pts.map((p) => p[ia]), 0), x1 = Math.max(...pts.map((p) => p[ia]), 1);
    let y0 = Math.min(...pts.map(ys), 0), y1 = Math.max(...pts.map(ys), 1);
    const pad = 24;
    const scale = Math.min((w - 2 * pad) / (x1 - x0 || 1), (h - 2 * pad) / (y1 - y0 || 1));
    const X = (x) => pad + (x - x0) * scale, Y = (y) => h - pad - (y - y0) * scale;
    g.strokeStyle = css("--grid"); g.lineWidth = 1;
    const step = niceStep((x1 - x0) / 5);
    for (let v = Math.ceil(x0 / step) * step; v <= x1; v += step) { g.beginPath(); g.moveTo(X(v), pad / 2); g.lineTo(X(v), h - pad); g.stroke(); }
    for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) { g.beginPath(); g.moveTo(pad, Y(v)); g.lineTo(w - pad / 2, Y(v)); g.stroke(); }
    g.fillStyle = css("--fg"); g.font = "11px sans-serif";
    const names = this.channels.map((n) => n.split(".")[0]);
    g.fillText(`${names[ia] || "x"} [mm] →`, w - 90, h - 6);
    if (this.channels.length >= 2) g.fillText(`↑ ${names[ib]} [mm]`, 4, 12);
    if (!pts.length) return;
    g.strokeStyle = css("--accent"); g.lineWidth = 1.5; g.beginPath();
    pts.forEach((p, i) => (i ? g.lineTo(X(p[ia]), Y(ys(p))) : g.moveTo(X(p[ia]), Y(ys(p)))));
    g.stroke();
    const last = pts[pts.length - 1];
    g.fillStyle = css("--danger"); g.beginPath(); g.arc(X(last[ia]), Y(ys(last)), 4, 0, 2 * Math.PI); g.fill();
    this.canvas.setAttribute("aria-label", `Path: ${names[ia]} ${last[ia].toFixed(2)} mm` + (this.channels.length >= 2 ? `, ${names[ib]} ${ys(last).toFixed(2)} mm` : ""));
  }
}

function niceStep(raw) {
  const p = 10 ** Math.floor(Math.log10(raw || 1));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}
