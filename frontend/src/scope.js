// The scope: uPlot over the streamed samples. Channels with their units (one y scale per
// unit, the first two drawn as axes), a grid and the default channels from the start,
// the hover cursor's values in the legend, drag to zoom (double-click: back to following
// the run), a channel picker fed by the run's channel list. Two fixed cursors, A and B:
// click sets A, shift-click B (or type their times in the labelled fields, arrow keys
// step them); each is drawn as a line, and a table gives each cursor's time and the
// channels' values there (the recorded sample at or before it) and B − A, Δt included.
import uPlot from "uplot";

const PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
const MAX_POINTS = 20000;
const css = (name) => getComputedStyle(document.documentElement).getPropertyValue(name).trim() || "#888";

export class Scope {
  constructor(box, picker, rpc, cursors = null) {
    this.box = box;
    this.cursors = cursors; // {a, b, dt, clear, table}: the cursors' fields and table
    this.marks = { a: null, b: null }; // the fixed cursors' times [s]
    this.picker = picker;
    this.rpc = rpc;
    this.channels = [];
    this.units = {};
    this.t = [];
    this.values = {};
    this.span = 5;
    this.follow = true;
    this.dirty = false;
    this.frames = 0;
    this.plot = null;
    new ResizeObserver(() => this.resize()).observe(box);
    if (cursors) {
      for (const k of ["a", "b"]) {
        cursors[k].addEventListener("input", () => {
          const v = cursors[k].value === "" ? null : Number(cursors[k].value);
          this.setMark(k, v != null && Number.isFinite(v) ? v : null, false);
        });
      }
      cursors.clear.addEventListener("click", () => { this.setMark("a", null); this.setMark("b", null); });
    }
  }

  // cursor `k` ("a" or "b") at `t` seconds (null: none)
  setMark(k, t, field = true) {
    this.marks[k] = t;
    if (field && this.cursors) this.cursors[k].value = t == null ? "" : t.toFixed(3);
    this.showMarks();
    if (this.plot) this.plot.redraw(false);
  }

  // the recorded sample at or before `t` (the first one before all): its index
  sampleAt(t) {
    const ts = this.t;
    let lo = 0, hi = ts.length - 1;
    if (hi < 0) return -1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (ts[mid] <= t + 1e-9) lo = mid; else hi = mid - 1; }
    return lo;
  }

  valueAt(name, t) {
    const i = this.sampleAt(t);
    return i < 0 ? null : (this.values[name] || [])[i] ?? null;
  }

  showMarks() {
    const c = this.cursors;
    if (!c) return;
    const { a, b } = this.marks;
    c.dt.textContent = a != null && b != null ? `Δt ${(b - a).toFixed(3)} s` : "Δt –";
    const hidden = a == null && b == null;
    const legend = this.plot ? this.plot.root.querySelector(".u-legend") : null;
    if (legend) legend.hidden = !hidden;
    if (c.table.hidden !== hidden) { c.table.hidden = hidden; requestAnimationFrame(() => this.resize()); }
    if (hidden) return;
    const num = (v) => (v == null ? "–" : Math.abs(v) >= 1000 ? v.toFixed(1) : Number(v.toPrecision(6)).toString());
    const head = document.createElement("tr");
    head.append(Object.assign(document.createElement("th"), { scope: "col", textContent: "cursor" }),
      Object.assign(document.createElement("th"), { scope: "col", textContent: "t [s]" }));
    this.channels.forEach((name, i) => {
      const th = Object.assign(document.createElement("th"), { scope: "col" });
      th.append(Object.assign(document.createElement("span"), { className: "swatch", style: `background:${PALETTE[i % PALETTE.length]}` }), this.label(name));
      head.append(th);
    });
    const row = (label, t, values) => {
      const tr = document.createElement("tr");
      tr.append(Object.assign(document.createElement("th"), { scope: "row", textContent: label }),
        Object.assign(document.createElement("td"), { textContent: t == null ? "–" : t.toFixed(3) }));
      for (const v of values) tr.append(Object.assign(document.createElement("td"), { textContent: num(v) }));
      return tr;
    };
    const at = (t) => this.channels.map((n) => (t == null ? null : this.valueAt(n, t)));
    const va = at(a), vb = at(b);
    // the hover cursor's row too: the table stands in for the legend while it shows
    const idx = this.plot ? this.plot.cursor.idx : null;
    const th = idx != null ? this.t[idx] ?? null : null;
    const rows = [head, row("hover", th, this.channels.map((n) => (idx != null ? (this.values[n] || [])[idx] ?? null : null))),
      row("A", a, va), row("B", b, vb)];
    if (a != null && b != null) rows.push(row("B − A", b - a, vb.map((v, i) => (v == null || va[i] == null ? null : v - va[i]))));
    c.table.replaceChildren(...rows);
  }

  drawMarks(u) {
    const g = u.ctx;
    const { top, height, left, width } = u.bbox;
    g.save();
    g.font = `${Math.round(11 * devicePixelRatio)}px sans-serif`;
    for (const [k, color] of [["a", css("--accent")], ["b", css("--danger")]]) {
      const t = this.marks[k];
      if (t == null) continue;
      const x = Math.round(u.valToPos(t, "x", true));
      if (x < left || x > left + width) continue;
      g.strokeStyle = color; g.fillStyle = color; g.lineWidth = 1.5 * devicePixelRatio;
      g.setLineDash([6 * devicePixelRatio, 3 * devicePixelRatio]);
      g.beginPath(); g.moveTo(x, top); g.lineTo(x, top + height); g.stroke();
      g.fillText(k.toUpperCase(), x + 3 * devicePixelRatio, top + 12 * devicePixelRatio);
    }
    g.restore();
  }

  setChannels(channels, units) {
    this.channels = channels;
    this.units = { ...this.units, ...units };
    this.t = [];
    this.values = Object.fromEntries(channels.map((c) => [c, []]));
    this.build();
  }

  label(name) {
    const unit = this.units[name];
    return unit && unit !== "raw" ? `${name} [${unit}]` : name;
  }

  build() {
    if (this.plot) this.plot.destroy();
    const unitsSeen = [];
    const series = [{ label: "t [s]", value: (u, v) => (v == null ? "–" : v.toFixed(3)) }];
    const scales = { x: { time: false, range: (u, lo, hi) => this.xRange(lo, hi) } };
    for (const [i, name] of this.channels.entries()) {
      const unit = this.units[name] || "";
      if (!unitsSeen.includes(unit)) unitsSeen.push(unit);
      const scale = `u${unitsSeen.indexOf(unit)}`;
      scales[scale] = { range: (u, lo, hi) => (lo == null || lo === hi ? [(lo ?? 0) - 1, (hi ?? 0) + 1] : uPlot.rangeNum(lo, hi, 0.1, true)) };
      series.push({ label: this.label(name), scale, stroke: PALETTE[i % PALETTE.length], width: 1.5, points: { show: false },
        value: (u, v) => (v == null ? "–" : Math.abs(v) >= 1000 ? v.toFixed(1) : v.toPrecision(5)) });
    }
    const fg = css("--fg"), grid = css("--grid");
    const axes = [{ label: "simulated time [s]", stroke: fg, grid: { stroke: grid, width: 1 }, ticks: { stroke: grid } }];
    unitsSeen.slice(0, 2).forEach((unit, i) => axes.push({
      scale: `u${i}`, side: i === 0 ? 3 : 1, label: unit || "value", stroke: fg,
      grid: { show: i === 0, stroke: grid, width: 1 }, ticks: { stroke: grid },
    }));
    const { width, height } = this.size();
    this.plot = new uPlot({
      width, height, series, scales, axes,
      cursor: { drag: { x: true, y: false, setScale: true } },
      legend: { live: true },
      hooks: {
        setSelect: [() => { this.follow = false; }],
        draw: [(u) => this.drawMarks(u)],
        setCursor: [() => { if (this.marks.a != null || this.marks.b != null) this.showMarks(); }],
      },
    }, this.data(), this.box);
    // the plot's height follows the legend's (its rows depend on the plot's width)
    this.legendWatch?.disconnect();
    this.legendWatch = new ResizeObserver(() => this.resize());
    this.legendWatch.observe(this.plot.root.querySelector(".u-legend"));
    const over = this.plot.over;
    over.addEventListener("dblclick", () => { this.follow = true; this.redraw(); });
    // a click (not a drag) sets cursor A, a shift-click cursor B
    let down = null;
    over.addEventListener("mousedown", (e) => { down = e.clientX; });
    over.addEventListener("click", (e) => {
      if (down == null || Math.abs(e.clientX - down) > 3) return;
      const t = this.plot.posToVal(e.offsetX, "x");
      if (Number.isFinite(t)) this.setMark(e.shiftKey ? "b" : "a", Math.max(0, t));
    });
    this.showMarks();
  }

  xRange(lo, hi) {
    if (!this.follow && lo != null && hi != null && hi > lo) return [lo, hi];
    const last = this.t.length ? this.t[this.t.length - 1] : 0;
    const end = Math.max(last, this.span);
    return [Math.max(0, end - this.span), end];
  }

  size() {
    const r = this.box.getBoundingClientRect();
    // the legend (one or more rows of channels) goes below the plot, inside the box
    const legend = this.plot ? this.plot.root.querySelector(".u-legend") : null;
    const below = (legend && !legend.hidden ? legend.offsetHeight : 0) + 6 + (legend ? 0 : 54);
    return { width: Math.max(200, Math.floor(r.width)), height: Math.max(120, Math.floor(r.height) - below) };
  }

  resize() {
    if (this.plot) this.plot.setSize(this.size());
  }

  data() {
    return [this.t, ...this.channels.map((c) => this.values[c] || [])];
  }

  append(t, values) {
    if (!t.length) return;
    const last = this.t.length ? this.t[this.t.length - 1] : -1;
    const from = t.findIndex((x) => x > last);
    if (from < 0) return;
    this.t.push(...t.slice(from));
    for (const c of this.channels) {
      const col = this.values[c];
      const v = values[c] || [];
      for (let i = from; i < t.length; i++) col.push(v[i] ?? null);
    }
    if (this.t.length > MAX_POINTS) this.thin();
    this.redraw();
  }

  replace(t, values) {
    this.t = [...t];
    for (const c of this.channels) this.values[c] = (values[c] || []).slice();
    this.redraw();
  }

  thin() {
    const keep = (a) => a.filter((_, i) => i % 2 === 0);
    this.t = keep(this.t);
    for (const c of this.channels) this.values[c] = keep(this.values[c]);
  }

  redraw() {
    if (this.dirty) return;
    this.dirty = true;
    requestAnimationFrame(() => {
      this.dirty = false;
      if (!this.plot) return;
      this.plot.setData(this.data(), true);
      this.frames += 1;
      if (this.marks.a != null || this.marks.b != null) this.showMarks();
    });
  }

  async fillPicker() {
    const all = await this.rpc.call("scope.channels");
    const list = this.picker.querySelector("ul");
    const filter = this.picker.querySelector("input[type=search]");
    list.replaceChildren();
    for (const { name, unit } of all) {
      this.units[name] = unit;
      const li = document.createElement("li");
      const label = document.createElement("label");
      const box = document.createElement("input");
      box.type = "checkbox";
      box.value = name;
      box.checked = this.channels.includes(name);
      box.addEventListener("change", () => this.choose());
      label.append(box, ` ${name}`, Object.assign(document.createElement("span"), { className: "unit", textContent: unit ? ` ${unit}` : "" }));
      li.append(label);
      list.append(li);
    }
    filter.oninput = () => {
      const q = filter.value.toLowerCase();
      for (const li of list.children) li.hidden = !li.textContent.toLowerCase().includes(q);
    };
  }

  async choose() {
    const names = [...this.picker.querySelectorAll("input[type=checkbox]:checked")].map((b) => b.value);
    const chosen = await this.rpc.call("scope.select", { channels: names.length ? names : null });
    this.setChannels(chosen.scope, chosen.units);
    this.onChosen?.();
  }
}
