// Per-frame cost in Node of the built package (wasm, JS object API) against Kalidokit's
// Hand.solve, in the same run, on the same recorded frames.
//
//   make pkg && npm ci --prefix eval     # once
//   node eval/speed.mjs [--passes N]
//
// Frames: ../shared/data/hands/right-hand-video-mediapipe.json (621 frames), passed as the
// recording stores them (handrig) and as arrays of {x, y, z} (Kalidokit, its input shape).
// Avatar: ../shared/avatars/debug-robot.vrm. Timed per call with process.hrtime over N passes
// (default 5) after one warm-up pass; prints median and p95 microseconds per frame and the
// ratio to Kalidokit. handrig does more per call than Kalidokit (all 15 finger bones with joint
// limits, hand rotation, and with `wrists` also fingertip alignment and arm IK), and it pays
// for building the JS result object; Kalidokit returns Euler angles for one hand only.

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const shared = process.env.HANDRIG_SHARED ?? resolve(root, "../shared");
const require = createRequire(import.meta.url);

let HandRig, Kalidokit;
try {
  ({ HandRig } = require(resolve(root, "pkg")));
} catch (e) {
  console.error(`handrig package not built (${e.code ?? e.message}): run \`make pkg\` first`);
  process.exit(1);
}
try {
  Kalidokit = require("kalidokit/dist/kalidokit.umd.js");
} catch (e) {
  console.error(`kalidokit not installed (${e.code ?? e.message}): run \`npm ci --prefix eval\` first`);
  process.exit(1);
}

const passesArg = process.argv.indexOf("--passes");
const passes = passesArg > 0 ? Number(process.argv[passesArg + 1]) : 5;

const frames = JSON.parse(readFileSync(`${shared}/data/hands/right-hand-video-mediapipe.json`, "utf8"));
const robot = readFileSync(`${shared}/avatars/debug-robot.vrm`);
const kalidokitInput = frames.map((f) => f.hands[0].worldLandmarks.map(([x, y, z]) => ({ x, y, z })));
// A reachable wrist in front of the robot's right shoulder (model frame, meters).
const wrists = { right: { position: [-0.45, 1.3, 0.2] } };
const withWrists = frames.map((f) => ({ ...f, wrists }));

function time(label, fn) {
  const n = frames.length;
  for (let i = 0; i < n; i++) fn(i); // warm-up
  const samples = [];
  for (let p = 0; p < passes; p++) {
    for (let i = 0; i < n; i++) {
      const t0 = process.hrtime.bigint();
      fn(i);
      samples.push(Number(process.hrtime.bigint() - t0) / 1000);
    }
  }
  samples.sort((a, b) => a - b);
  const q = (p) => samples[Math.min(samples.length - 1, Math.floor(p * samples.length))];
  return { label, median: q(0.5), p95: q(0.95), count: samples.length };
}

const rig = HandRig.fromVrm(robot);
const rigWrists = HandRig.fromVrm(robot);
let sink = 0;
const rows = [
  time("handrig solve: hands", (i) => {
    sink += rig.solve(frames[i]).timeMs;
  }),
  time("handrig solve: hands + wrists", (i) => {
    sink += rigWrists.solve(withWrists[i]).timeMs;
  }),
  time("Kalidokit Hand.solve", (i) => {
    const r = Kalidokit.Hand.solve(kalidokitInput[i], "Right");
    sink += r ? 1 : 0;
  }),
];
rig.free();
rigWrists.free();

const kd = rows[2];
console.log(`solve time per frame, Node ${process.version}, ${frames.length} frames x ${passes} passes (sink ${sink > 0})`);
console.log("method                           median us    p95 us   median / Kalidokit");
for (const r of rows) {
  console.log(
    `${r.label.padEnd(32)} ${r.median.toFixed(1).padStart(9)} ${r.p95.toFixed(1).padStart(9)} ${(r.median / kd.median).toFixed(2).padStart(20)}`,
  );
}
