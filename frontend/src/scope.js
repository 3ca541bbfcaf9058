// The scope: uPlot over the streamed samples. Channels with their units (one y scale per
// unit, the first two drawn as axes), a grid and the default channels from the start,
// cursor values in the legend, drag to zoom (double-click: back to following the run),
// a channel picker fed by the run's channel list.
import uPlot from "uplot";

const PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
const MAX_POINTS = 20000;
const css = (name) => getComputedStyle(document.documentElement).getPropertyValue(name).trim() || "#888";

export class Scope {
  constructor(box, picker, rpc) {
    this.box = box;
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
      hooks: { setSelect: [() => { this.follow = false; }] },
    }, this.data(), this.box);
    this.plot.over.addEventListener("dblclick", () => { this.follow = true; this.redraw(); });
  }

  xRange(lo, hi) {
    if (!this.follow && lo != null && hi != null && hi > lo) return [lo, hi];
    const last = this.t.length ? this.t[this.t.length - 1] : 0;
    const end = Math.max(last, this.span);
    return [Math.max(0, end - this.span), end];
  }

  size() {
    const r = this.box.getBoundingClientRect();
    return { width: Math.max(200, Math.floor(r.width)), height: Math.max(160, Math.floor(r.height) - 60) };
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
