// The studio's reproducible build: `npm ci && npm run build` bundles src/main.js and
// src/style.css (with CodeMirror and uPlot from node_modules, pinned by package-lock.json)
// into ../src/motionvm/studio/static, the files the Python package ships; the output is
// committed, so a user needs no npm.
import { build } from "esbuild";
import { copyFileSync, mkdirSync } from "node:fs";

const out = new URL("../src/motionvm/studio/static/", import.meta.url).pathname;
mkdirSync(out, { recursive: true });
const common = { bundle: true, minify: true, legalComments: "eof", logLevel: "warning", target: "es2020" };
await build({ ...common, entryPoints: ["src/main.js"], outfile: `${out}app.js`, format: "esm" });
await build({ ...common, entryPoints: ["src/style.css"], outfile: `${out}app.css` });
copyFileSync("index.html", `${out}index.html`);
