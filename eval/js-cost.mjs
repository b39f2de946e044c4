// The object API's JavaScript alone: `packFrame` (the frame into the input view) and
// `fillResult` (the result object from the output view), bundled from pkg-config/src with
// esbuild as build.mjs bundles them, timed without the wasm solve in between on the speed
// eval's full frames (the four ASL clips), with the outputs a rig of the built package gave
// for them. With `--against REV`, the same from a git revision's pkg-config/src, in the same
// process, pass by pass in turn (their difference holds on a busy machine), after checking
// that both build the same results (keys in order, values) frame after frame.
//
//   node eval/js-cost.mjs [--against REV] [--rounds N] [--avatar FILE] [--pkg DIR]
//   (make pkg and npm ci --prefix pkg-config first; REV e.g. main)
//
// Medians over N rounds (default 40) of a pass's median frame (microseconds, the timer's own
// cost included: the same for both). In a frame the same code costs more than here: the wasm
// solve in between evicts the caches (see docs/measurements/2026-12-04-speed.md, "The object
// API's JavaScript"). `JS_COST_RAW=1` prints every round.

import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { aslFrames } from "./full-frame.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const shared = process.env.HANDRIG_SHARED ?? resolve(root, "../shared");
const require = createRequire(import.meta.url);
const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};
const against = arg("--against", null);
const rounds = Number(arg("--rounds", 40));
const { HandRig } = require(resolve(arg("--pkg", join(root, "pkg"))));
const { build } = require(join(root, "pkg-config/node_modules/esbuild"));

const work = mkdtempSync(join(tmpdir(), "handrig-js-cost-"));
/** packFrame and fillResult of the sources in `src`, bundled into `work`. */
async function bundle(src, name) {
  const layout = readFileSync(join(src, "layout.json"), "utf8");
  const options = readFileSync(join(src, "options.json"), "utf8");
  const outfile = join(work, `${name}.mjs`);
  await build({
    stdin: {
      contents: 'export { packFrame } from "./frame.js"; export { fillResult } from "./results.js"; export { BONES, LI } from "./layout.js";',
      resolveDir: src,
      loader: "ts",
    },
    outfile,
    bundle: true,
    format: "esm",
    platform: "node",
    target: "es2022",
    define: { __HANDRIG_LAYOUT__: layout, __HANDRIG_OPTIONS__: options, __HANDRIG_VERSION__: '"js-cost"' },
    logLevel: "warning",
  });
  return import(pathToFileURL(outfile).href);
}
const versions = [["this checkout", await bundle(join(root, "pkg-config/src"), "this")]];
if (against !== null) {
  execFileSync("sh", ["-c", `git -C "${root}" archive "${against}" pkg-config/src | tar -x -C "${work}"`]);
  versions.unshift([against, await bundle(join(work, "pkg-config/src"), "against")]);
}

const frames = aslFrames(shared);
const rig = HandRig.fromVrm(readFileSync(arg("--avatar", join(root, "tests/fixtures/avatars/woman-vrm1.vrm"))));
const outs = frames.map((f) => {
  rig.solve(f);
  return Float32Array.from(rig.output);
});
const index = new Map(versions[0][1].BONES.map((n, i) => [n, i]));
const driven = rig.drivenBones().map((n) => index.get(n));
const present = rig.boneNames().map((n) => index.get(n));
const ab = rig.alignedBones();
const aligned = new Uint8Array([index.get(ab.left.bone), index.get(ab.right.bone), ab.left.standIn ? 1 : 0, ab.right.standIn ? 1 : 0]);
const inputs = versions.map(([, J]) => new Float32Array(J.LI.length));

/** The same result: keys in order (undefined values included), equal values (NaN too). */
function same(a, b, path) {
  if (a === b || (Number.isNaN(a) && Number.isNaN(b))) return;
  if (!(a !== null && b !== null && typeof a === "object" && typeof b === "object")) throw new Error(`${path}: ${a} vs ${b}`);
  if (Array.isArray(a) !== Array.isArray(b) || ArrayBuffer.isView(a) !== ArrayBuffer.isView(b)) throw new Error(`${path}: kinds differ`);
  const ka = Object.keys(a);
  if (ka.join() !== Object.keys(b).join()) throw new Error(`${path}: keys ${ka.join()} vs ${Object.keys(b).join()}`);
  for (const k of ka) same(a[k], b[k], `${path}.${k}`);
}
if (versions.length === 2) {
  // Reused result objects (as a rig's own) and fresh ones.
  const reused = versions.map(() => ({}));
  for (let i = 0; i < frames.length; i++) {
    const fill = (target) => versions.map(([, J], v) => (J.packFrame(frames[i], inputs[v], false, true), J.fillResult(target[v], outs[i], inputs[v], driven, present, aligned)));
    const r = fill(reused);
    same(r[0], r[1], `frame ${i}`);
    const f = fill([{}, {}]);
    same(f[0], f[1], `frame ${i} (fresh)`);
  }
}

let sink = 0;
const results = versions.map(() => ({}));
const samples = new Float64Array(frames.length);
/**
 * One pass over the frames: 0 pack, 1 fill, 2 both. The median frame's microseconds (each
 * frame timed: a pass's mean takes in whatever else the machine ran meanwhile).
 */
function pass(v, which) {
  const J = versions[v][1];
  const input = inputs[v];
  const result = results[v];
  for (let i = 0; i < frames.length; i++) {
    const t0 = process.hrtime.bigint();
    // The rig looks for a face's fields in every 30th frame of frames without one.
    if (which !== 1) J.packFrame(frames[i], input, false, i % 30 === 0);
    if (which !== 0) sink += J.fillResult(result, outs[i], input, driven, present, aligned).timeMs;
    samples[i] = Number(process.hrtime.bigint() - t0) / 1000;
  }
  samples.sort();
  return samples[samples.length >> 1];
}
for (let w = 0; w < 40; w++) for (let v = 0; v < versions.length; v++) for (let k = 0; k < 3; k++) pass(v, k);
const t = versions.map(() => [[], [], []]);
// The two versions' order alternates round by round (the first of a pair ran slower).
for (let r = 0; r < rounds; r++) {
  for (let k = 0; k < 3; k++) {
    for (let j = 0; j < versions.length; j++) {
      const v = r % 2 === 0 ? j : versions.length - 1 - j;
      t[v][k].push(pass(v, k));
    }
  }
}
const median = (a) => [...a].sort((x, y) => x - y)[a.length >> 1];
console.log(`JavaScript of the object API alone, us a frame (median of ${rounds} rounds' median frames; ${frames.length} ASL frames${versions.length === 2 ? "; results identical" : ""})`);
["packFrame", "fillResult", "both"].forEach((name, k) => {
  const cells = versions.map(([label], v) => `${label} ${median(t[v][k]).toFixed(2)}`);
  const diff = versions.length === 2 ? `  (paired difference ${median(t[0][k].map((x, r) => x - t[1][k][r])).toFixed(2)})` : "";
  console.log(`${name.padEnd(11)} ${cells.join("  ")}${diff}`);
});
if (process.env.JS_COST_RAW) for (let v = 0; v < versions.length; v++) console.log(versions[v][0], t[v].map((a) => a.map((x) => x.toFixed(1)).join(" ")));
rmSync(work, { recursive: true, force: true });
if (!(sink > 0)) process.exitCode = 1;
