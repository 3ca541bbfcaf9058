// The editor: one CodeMirror state per file (tabs), highlighting, the language's
// diagnostics, breakpoints in the gutter (click, or F9 on the cursor's line) and the line
// where the run stopped.
import { EditorState, StateEffect, StateField, RangeSet } from "@codemirror/state";
import {
  EditorView, Decoration, GutterMarker, gutter, keymap, lineNumbers,
  highlightActiveLine, highlightActiveLineGutter, drawSelection,
} from "@codemirror/view";
import { defaultKeymap, history, historyKeymap, indentWithTab } from "@codemirror/commands";
import { HighlightStyle, syntaxHighlighting, bracketMatching, indentOnInput } from "@codemirror/language";
import { setDiagnostics, lintGutter } from "@codemirror/lint";
import { tags as t } from "@lezer/highlight";
import { modes } from "./modes.js";

const highlight = HighlightStyle.define([
  { tag: t.keyword, color: "var(--code-keyword)", fontWeight: "600" },
  { tag: t.typeName, color: "var(--code-type)" },
  { tag: t.comment, color: "var(--code-comment)", fontStyle: "italic" },
  { tag: t.string, color: "var(--code-string)" },
  { tag: t.number, color: "var(--code-number)" },
  { tag: [t.meta, t.atom, t.standard(t.name)], color: "var(--code-meta)" },
]);

const toggleBreakpoint = StateEffect.define({ map: (v, m) => ({ pos: m.mapPos(v.pos), on: v.on }) });
const marker = new (class extends GutterMarker {
  toDOM() {
    const el = document.createElement("span");
    el.className = "cm-bp";
    el.textContent = "●";
    el.setAttribute("aria-label", "breakpoint");
    return el;
  }
})();
const spacer = new (class extends GutterMarker {
  toDOM() { return Object.assign(document.createElement("span"), { textContent: "●" }); }
})();
const breakpoints = StateField.define({
  create: () => RangeSet.empty,
  update(set, tr) {
    set = set.map(tr.changes);
    for (const e of tr.effects) {
      if (!e.is(toggleBreakpoint)) continue;
      set = e.value.on
        ? set.update({ add: [marker.range(e.value.pos)] })
        : set.update({ filter: (from) => from !== e.value.pos });
    }
    return set;
  },
});

const setStopped = StateEffect.define();
const stoppedLine = StateField.define({
  create: () => Decoration.none,
  update(deco, tr) {
    deco = deco.map(tr.changes);
    for (const e of tr.effects) {
      if (!e.is(setStopped)) continue;
      deco = e.value == null ? Decoration.none
        : Decoration.set([Decoration.line({ class: "cm-stopped" }).range(e.value)]);
    }
    return deco;
  },
  provide: (f) => EditorView.decorations.from(f),
});

export class Editor {
  constructor(parent, tabs, rpc) {
    this.rpc = rpc;
    this.tabs = tabs;
    this.states = new Map();
    this.diagnostics = new Map();
    this.current = null;
    this.timer = null;
    this.onBreakpoints = () => {};
    this.view = new EditorView({ parent });
    this.view.dom.setAttribute("aria-label", "Program editor");
  }

  extensions(language) {
    const self = this;
    return [
      lineNumbers(),
      gutter({
        class: "cm-bp-gutter",
        markers: (v) => v.state.field(breakpoints),
        initialSpacer: () => spacer,
        domEventHandlers: {
          mousedown(view, line) { self.toggle(line.from); return true; },
        },
      }),
      breakpoints,
      stoppedLine,
      lintGutter(),
      highlightActiveLine(),
      highlightActiveLineGutter(),
      drawSelection(),
      history(),
      indentOnInput(),
      bracketMatching(),
      modes[language] || [],
      syntaxHighlighting(highlight),
      keymap.of([
        { key: "F9", run: (v) => { self.toggle(v.state.doc.lineAt(v.state.selection.main.head).from); return true; } },
        indentWithTab, ...defaultKeymap, ...historyKeymap,
      ]),
      EditorView.updateListener.of((u) => { if (u.docChanged) self.changed(); }),
      EditorView.contentAttributes.of({ "aria-label": "Program text" }),
    ];
  }

  add(file) {
    const state = EditorState.create({ doc: file.text, extensions: this.extensions(file.language) });
    this.states.set(file.path, state);
    const tab = document.createElement("button");
    tab.type = "button";
    tab.role = "tab";
    tab.textContent = file.name || file.path.split("/").pop();
    tab.dataset.path = file.path;
    tab.addEventListener("click", () => this.show(file.path));
    this.tabs.append(tab);
    if (file.diagnostics) this.diagnostics.set(file.path, file.diagnostics);
    if (!this.current) this.show(file.path);
  }

  show(path) {
    if (this.current) this.states.set(this.current, this.view.state);
    this.current = path;
    this.view.setState(this.states.get(path));
    this.applyDiagnostics(path);
    for (const tab of this.tabs.children) tab.setAttribute("aria-selected", String(tab.dataset.path === path));
  }

  toggle(pos) {
    const on = !this.lines().includes(this.view.state.doc.lineAt(pos).number);
    this.view.dispatch({ effects: toggleBreakpoint.of({ pos, on }) });
    this.onBreakpoints(this.current, this.lines());
  }

  lines(state = this.view.state) {
    const out = [];
    state.field(breakpoints).between(0, state.doc.length, (from) => { out.push(state.doc.lineAt(from).number); });
    return out;
  }

  setBreakpoint(line) {
    const pos = this.view.state.doc.line(line).from;
    if (!this.lines().includes(line)) this.toggle(pos);
  }

  changed() {
    clearTimeout(this.timer);
    const path = this.current;
    this.timer = setTimeout(async () => {
      const text = this.view.state.doc.toString();
      const answer = await this.rpc.call("file.edit", { path, text });
      this.diagnostics.set(path, answer.diagnostics);
      if (this.current === path) this.applyDiagnostics(path);
    }, 300);
  }

  applyDiagnostics(path) {
    const doc = this.view.state.doc;
    const items = (this.diagnostics.get(path) || []).filter((d) => d.file === path && d.line <= doc.lines);
    const out = items.map((d) => {
      const line = doc.line(d.line);
      const from = Math.min(line.from + Math.max(0, d.col - 1), line.to);
      return { from, to: Math.max(from, line.to), severity: d.severity === "note" ? "info" : d.severity, message: d.message };
    });
    this.view.dispatch(setDiagnostics(this.view.state, out));
  }

  stoppedAt(path, line) {
    for (const [p, state] of this.states) {
      if (p !== this.current && state.field(stoppedLine).size) {
        this.states.set(p, state.update({ effects: setStopped.of(null) }).state);
      }
    }
    if (path == null) { this.view.dispatch({ effects: setStopped.of(null) }); return; }
    if (path !== this.current && this.states.has(path)) this.show(path);
    if (path !== this.current) return;
    const pos = this.view.state.doc.line(Math.min(line, this.view.state.doc.lines)).from;
    this.view.dispatch({ effects: [setStopped.of(pos), EditorView.scrollIntoView(pos, { y: "center" })] });
  }
}
