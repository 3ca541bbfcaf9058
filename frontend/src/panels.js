// The panels beside the scope: the console, the axes table, the I/O points (outputs as
// lamps, inputs as buttons that force them), the call stack and variables when paused.
const fmt = (v, digits = 3) => (v == null ? "–" : Number(v).toFixed(digits));

export class Console {
  constructor(el) { this.el = el; this.time = Infinity; }
  clear() { this.el.replaceChildren(); }
  // Lines printed after `time` (the debugger went back, or the slider is scrubbing
  // there) are hidden, until the run passes them again: the run prints each line once.
  // The rows are in time order, so the hidden ones are always the last.
  showUntil(time) {
    if (time === this.time) return;
    this.time = time;
    for (let row = this.el.lastElementChild; row; row = row.previousElementSibling) {
      const later = Number(row.dataset.time) > time + 1e-9;
      if (!later && !row.hidden) break;
      row.hidden = later;
    }
  }
  add(lines) {
    const atEnd = this.el.scrollTop + this.el.clientHeight >= this.el.scrollHeight - 4;
    for (const { time, text, kind } of lines) {
      const row = document.createElement("div");
      row.className = `line ${kind}`;
      row.dataset.time = String(time);
      row.hidden = Number(time) > this.time + 1e-9;
      const stamp = document.createElement("span");
      stamp.className = "stamp";
      stamp.textContent = `${Number(time).toFixed(3)} s `;
      row.append(stamp, document.createTextNode(text));
      this.el.append(row);
    }
    while (this.el.childElementCount > 5000) this.el.firstElementChild.remove();
    if (atEnd) this.el.scrollTop = this.el.scrollHeight;
  }
}

export class AxesTable {
  constructor(tbody) { this.tbody = tbody; }
  show(rows) {
    if (this.tbody.childElementCount !== rows.length) {
      this.tbody.replaceChildren(...rows.map(() => {
        const tr = document.createElement("tr");
        tr.innerHTML = "<th scope=row></th><td class=state></td><td></td><td></td><td></td><td></td><td></td>";
        return tr;
      }));
    }
    rows.forEach((r, i) => {
      const cells = this.tbody.children[i].children;
      const values = [r.name, r.state, fmt(r.ref_pos), fmt(r.pos_fb), fmt(r.vel_fb, 2), fmt(r.pos_err, 4),
        r.fault_status ? `0x${(r.fault_status >>> 0).toString(16)}` : "0"];
      values.forEach((v, j) => { if (cells[j].textContent !== v) cells[j].textContent = v; });
      cells[1].dataset.state = r.state;
    });
  }
}

export class IoPanel {
  constructor(inputs, outputs, onForce) {
    this.inputs = inputs;
    this.outputs = outputs;
    this.onForce = onForce;
    this.buttons = new Map();
    this.lamps = new Map();
  }

  build(machine) {
    this.inputs.replaceChildren();
    this.outputs.replaceChildren();
    this.buttons.clear();
    this.lamps.clear();
    for (const name of machine.inputs) {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "io-in";
      b.textContent = name;
      b.setAttribute("aria-pressed", "false");
      b.title = `force ${name} on or off`;
      b.addEventListener("click", () => this.onForce(name, b.getAttribute("aria-pressed") !== "true"));
      this.inputs.append(b);
      this.buttons.set(name, b);
    }
    for (const name of machine.outputs) {
      const lamp = document.createElement("span");
      lamp.className = "lamp";
      lamp.setAttribute("role", "img");
      lamp.dataset.name = name;
      lamp.textContent = name;
      this.outputs.append(lamp);
      this.lamps.set(name, lamp);
    }
  }

  show(io) {
    for (const [name, v] of Object.entries(io.inputs || {})) {
      const b = this.buttons.get(name);
      if (b) b.setAttribute("aria-pressed", String(v === 1));
    }
    for (const [name, v] of Object.entries(io.outputs || {})) {
      const lamp = this.lamps.get(name);
      if (!lamp) continue;
      lamp.classList.toggle("on", v === 1);
      lamp.setAttribute("aria-label", `${name} ${v === 1 ? "on" : "off"}`);
    }
  }
}

export class DebugPanel {
  constructor(stackEl, varsEl, rpc, onFrame) {
    this.stackEl = stackEl;
    this.varsEl = varsEl;
    this.rpc = rpc;
    this.onFrame = onFrame;
  }

  running() {
    this.stackEl.replaceChildren(Object.assign(document.createElement("li"), { textContent: "running…", className: "muted" }));
    this.varsEl.replaceChildren();
  }

  async paused(stop) {
    let threads = [];
    try { threads = await this.rpc.call("debug.threads"); } catch { return; }
    const items = [];
    let first = null;
    const ordered = stop && stop.thread ? [...threads].sort((a, b) => (b.id === stop.thread) - (a.id === stop.thread)) : threads;
    for (const th of ordered) {
      const frames = await this.rpc.call("debug.stack", { thread: th.id }).catch(() => []);
      for (const f of frames) {
        const li = document.createElement("li");
        const b = document.createElement("button");
        b.type = "button";
        b.textContent = `${th.name}: ${f.name} — ${f.file.split("/").pop()}:${f.line}`;
        b.addEventListener("click", () => this.select(f, b));
        li.append(b);
        items.push(li);
        if (!first) first = [f, b];
      }
    }
    this.stackEl.replaceChildren(...items);
    if (!items.length) this.stackEl.append(Object.assign(document.createElement("li"), { textContent: "no task is inside a function", className: "muted" }));
    if (first) await this.select(...first);
    else await this.variables(null);
  }

  async select(frame, button) {
    for (const b of this.stackEl.querySelectorAll("button")) b.setAttribute("aria-current", String(b === button));
    this.onFrame(frame);
    await this.variables(frame.id);
  }

  async variables(frameId) {
    const vars = await this.rpc.call("debug.variables", { frame: frameId }).catch(() => null);
    if (!vars) return;
    const groups = [];
    for (const [title, items] of Object.entries(vars)) {
      if (!items.length) continue;
      const h = document.createElement("h4");
      h.textContent = title;
      const dl = document.createElement("dl");
      for (const { name, value } of items) {
        dl.append(Object.assign(document.createElement("dt"), { textContent: name }),
          Object.assign(document.createElement("dd"), { textContent: value }));
      }
      groups.push(h, dl);
    }
    this.varsEl.replaceChildren(...groups);
  }
}
