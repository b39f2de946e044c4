// Per-frame cost in Node of the built package against Kalidokit, in the same run, on the same
// real frames: the object API (`rig.solve(frame)`: MediaPipe shapes packed in JS, result object
// built from the output view), the flat path (`rig.input.set(...)`, `rig.solveFlat(t)`: the
// wasm solve alone), and Kalidokit 1.1.5 (UMD build) doing the same frame: `Pose.solve` plus
// `Hand.solve` for every tracked hand.
//
//   make pkg && npm ci --prefix eval     # once
//   node eval/speed.mjs [--passes N] [--warmup W] [--json] [--pkg DIR] [--avatar FILE] [--frames FILE]
//   (DIR: a built package, default pkg/; FILE: a .vrm, default the robot. A generated avatar
//   with its skin, e.g. tests/fixtures/avatars/woman-vrm1.vrm, times self-contact on the skin.
//   --frames: the full frames from a JSON file ({ frames: [...] } of rig.solve inputs with pose
//   and hands) instead of the four ASL clips, e.g. eval/frames/hands-near-face.json: both hands
//   near each other and near the face, where self-contact engages; eval/near-face-frames.mjs)
//
// Frames:
// - full frame: the four sign-language clips ../shared/data/asl/*.json (250 frames, pose and
//   0-2 hands of the same person; 95 frames with two hands): handrig solves both hands, the
//   body mapping, fingertip alignment and both arms (two-bone IK); Kalidokit solves the pose
//   and each hand. Also the object API and the flat path with what Kalidokit does not do
//   turned off ("Kalidokit's scope": no filter, alignment, self-contact, wrist limits, dropout
//   easing or torso), in the same interleaved passes.
// - hands only: ../shared/data/hands/right-hand-video-mediapipe.json (621 frames, one hand),
//   against one Kalidokit Hand.solve.
// Avatar: ../shared/avatars/debug-robot.vrm. Each call timed with process.hrtime over N passes
// (default 5; at least 10 for the rows compared with Kalidokit, whose passes alternate so a
// busy machine slows them alike) after W warm-up passes (default 20: the steady state an app reaches within its
// first second or two, once V8 has optimized both the WebAssembly and Kalidokit's JavaScript;
// with one warm-up pass part of the wasm still runs in V8's baseline compiler); median and p95 microseconds, and the ratio of Kalidokit's
// median to handrig's (> 1: handrig is faster). Also: rigs solved per millisecond with 100 rigs
// (one avatar each) solving the same full frames, as a page driving 100 avatars would.

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { aslFrames as readAslFrames, KALIDOKIT_SCOPE, kalidokitFrame, kalidokitSolve, xyz } from "./full-frame.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const shared = process.env.HANDRIG_SHARED ?? resolve(root, "../shared");
const require = createRequire(import.meta.url);

const pkgArg = process.argv.indexOf("--pkg");
const pkgDir = pkgArg > 0 ? resolve(process.argv[pkgArg + 1]) : resolve(root, "pkg");
let HandRig, ChainSolver, Kalidokit;
try {
  ({ HandRig, ChainSolver } = require(pkgDir));
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

const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};
const passes = Number(arg("--passes", 5));
const warmup = Number(arg("--warmup", 20));
const json = process.argv.includes("--json");

// The avatar (named `robot` below: the default).
const robot = readFileSync(arg("--avatar", `${shared}/avatars/debug-robot.vrm`));
const handFrames = JSON.parse(readFileSync(`${shared}/data/hands/right-hand-video-mediapipe.json`, "utf8"));
const framesFile = arg("--frames", null);
const aslFrames = framesFile ? JSON.parse(readFileSync(framesFile, "utf8")).frames : readAslFrames(shared);
const framesName = framesFile ? framesFile.replace(/^.*\//, "") : "ASL";
// Kalidokit's inputs: {x, y, z(, visibility)} objects, converted once (not timed).
const kalidokitFull = aslFrames.map(kalidokitFrame);
const kalidokitHands = handFrames.map((f) => f.hands[0].landmarks.map(xyz));

function time(label, n, fn) {
  for (let w = 0; w < warmup; w++) for (let i = 0; i < n; i++) fn(i); // warm-up
  const samples = [];
  for (let p = 0; p < passes; p++) {
    for (let i = 0; i < n; i++) {
      const t0 = process.hrtime.bigint();
      fn(i);
      samples.push(Number(process.hrtime.bigint() - t0) / 1000);
    }
  }
  return summary(label, samples);
}

/** Median and p95 of per-call microseconds. */
function summary(label, samples) {
  samples.sort((a, b) => a - b);
  const q = (p) => samples[Math.min(samples.length - 1, Math.floor(p * samples.length))];
  return { label, median: q(0.5), p95: q(0.95), count: samples.length };
}

/**
 * Times several methods on the same frames, pass by pass in turn: a pass of each method over
 * all frames, then the next round of passes, so that all of them see the machine in the same
 * states (their ratios hold when it is busy) while each pass runs with its own code and data
 * warm, as a tight loop of one method would. Rows as `time` gives them.
 */
function timeTogether(n, methods) {
  for (let w = 0; w < warmup; w++) for (const [, fn] of methods) for (let i = 0; i < n; i++) fn(i);
  const samples = methods.map(() => []);
  const rounds = Math.max(passes, 10);
  for (let p = 0; p < rounds; p++) {
    for (let m = 0; m < methods.length; m++) {
      const fn = methods[m][1];
      for (let i = 0; i < n; i++) {
        const t0 = process.hrtime.bigint();
        fn(i);
        samples[m].push(Number(process.hrtime.bigint() - t0) / 1000);
      }
    }
  }
  return methods.map(([label], m) => summary(label, samples[m]));
}

let sink = 0;

// Full frames: the object API, the flat path and Kalidokit, interleaved. The flat path gets
// each frame packed once beforehand (by the object API) and copies it into the input view:
// what a caller that fills the Float32Array itself pays.
const rig = HandRig.fromVrm(robot);
const packer = HandRig.fromVrm(robot);
const packed = aslFrames.map((f) => {
  packer.solve(f);
  return Float32Array.from(packer.input);
});
const flatRig = HandRig.fromVrm(robot);
// Self-contact off, all else default: what contact costs on these frames.
const noContactRig = HandRig.fromVrm(robot, { contact: { enabled: false } });
// Kalidokit's scope (eval/full-frame.mjs): what the JS boundary and the core solvers cost
// for equal work.
const scopeRig = HandRig.fromVrm(robot, KALIDOKIT_SCOPE);
// The flat path in Kalidokit's scope: the wasm's share of the equal-work row (the same packed
// frames: packing does not depend on the options).
const scopeFlatRig = HandRig.fromVrm(robot, KALIDOKIT_SCOPE);
// One flat-path call: the packed frame copied into the rig's input view, solved, read. The views
// are taken once every rig exists (a new rig may grow the wasm memory and detach older views).
const flatCall = (r, frames = aslFrames, framesPacked = packed) => {
  const { input, output } = r;
  return (i) => {
    input.set(framesPacked[i]);
    r.solveFlat(frames[i].timeMs);
    sink += output[0];
  };
};
// Legs off (issue 51): what the legs stage costs on these frames (on the ASL clips, where no leg
// is seen, its check of the landmarks; on eval/frames/legs-synthetic.json, the legs solved).
const noLegsRig = HandRig.fromVrm(robot, { legs: { enabled: false } });
const noLegsFlatRig = HandRig.fromVrm(robot, { legs: { enabled: false } });
const [full, noContact, flat, noLegs, noLegsFlat, scoped, scopedFlat, kdFull] = timeTogether(aslFrames.length, [
  ["handrig object API: full frame", (i) => (sink += rig.solve(aslFrames[i]).timeMs)],
  ["handrig object API: full frame, contact off", (i) => (sink += noContactRig.solve(aslFrames[i]).timeMs)],
  ["handrig flat path: full frame", flatCall(flatRig)],
  ["handrig object API: full frame, legs off", (i) => (sink += noLegsRig.solve(aslFrames[i]).timeMs)],
  ["handrig flat path: full frame, legs off", flatCall(noLegsFlatRig)],
  ["handrig object API: full frame, Kalidokit's scope", (i) => (sink += scopeRig.solve(aslFrames[i]).timeMs)],
  ["handrig flat path: full frame, Kalidokit's scope", flatCall(scopeFlatRig)],
  ["Kalidokit Pose.solve + Hand.solve per hand", (i) => (sink += kalidokitSolve(Kalidokit, kalidokitFull[i]))],
]);

// Hands only, interleaved likewise: the object API, the flat path (frames packed once, as
// above), and both in Kalidokit's scope.
const handRig = HandRig.fromVrm(robot);
const handPacked = handFrames.map((f) => {
  packer.solve(f);
  return Float32Array.from(packer.input);
});
const handFlatRig = HandRig.fromVrm(robot);
const handScopeRig = HandRig.fromVrm(robot, KALIDOKIT_SCOPE);
const handScopeFlatRig = HandRig.fromVrm(robot, KALIDOKIT_SCOPE);
const handFlatCall = (r) => flatCall(r, handFrames, handPacked);
const [hands, handsFlat, handsScoped, handsScopedFlat, kdHand] = timeTogether(handFrames.length, [
  ["handrig object API: one hand", (i) => (sink += handRig.solve(handFrames[i]).timeMs)],
  ["handrig flat path: one hand", handFlatCall(handFlatRig)],
  ["handrig object API: one hand, Kalidokit's scope", (i) => (sink += handScopeRig.solve(handFrames[i]).timeMs)],
  ["handrig flat path: one hand, Kalidokit's scope", handFlatCall(handScopeFlatRig)],
  ["Kalidokit Hand.solve", (i) => (sink += Kalidokit.Hand.solve(kalidokitHands[i], "Right") ? 1 : 0)],
]);

// Arm solvers and the handStrategy, through the object API on the full frames, and the
// standalone ChainSolver (a 6-bone chain chasing a moving target).
const variants = [
  ["armSolver fabrik", { armSolver: "fabrik" }],
  ["armSolver ccd", { armSolver: "ccd" }],
  ["handStrategy retarget", { handStrategy: "retarget" }],
].map(([label, options]) => {
  const r = HandRig.fromVrm(robot, options);
  const row = time(`handrig object API: full frame, ${label}`, aslFrames.length, (i) => {
    sink += r.solve(aslFrames[i]).timeMs;
  });
  r.free();
  return row;
});
const chainJoints = Array.from({ length: 7 }, (_, k) => [0, 0.1 * k, 0.02 * (k % 2)]);
const chainRows = ["fabrik", "ccd"].map((method) => {
  const c = new ChainSolver({ method, joints: chainJoints });
  const out = { joints: new Float32Array(21), rotations: new Float32Array(24) };
  const target = new Float32Array(3);
  const iterations = [];
  const row = time(`ChainSolver ${method}, 6 bones (solveInto)`, 600, (i) => {
    const a = i * 0.05;
    target[0] = 0.3 * Math.cos(a);
    target[1] = 0.4 + 0.2 * Math.sin(a);
    target[2] = 0.3 * Math.sin(a);
    c.solveInto(target, out);
    iterations.push(out.iterations);
  });
  iterations.sort((x, y) => x - y);
  row.iterationsMean = iterations.reduce((x, y) => x + y, 0) / iterations.length;
  row.iterationsP95 = iterations[Math.floor(0.95 * iterations.length)];
  c.free();
  return row;
});

// Many avatars: 100 rigs, each solving every full frame once per pass.
const many = HandRig.fromVrm(robot);
const rigs = Array.from({ length: 100 }, () => HandRig.fromVrm(robot));
for (let w = 0; w < Math.min(warmup, 3); w++) for (const r of rigs) for (const f of aslFrames) r.solve(f); // warm-up
let manyBest = Infinity;
for (let p = 0; p < passes; p++) {
  const t0 = process.hrtime.bigint();
  for (const f of aslFrames) for (const r of rigs) sink += r.solve(f).timeMs;
  manyBest = Math.min(manyBest, Number(process.hrtime.bigint() - t0) / 1e6);
}
const rigsPerMs = (rigs.length * aslFrames.length) / manyBest;
for (const r of [rig, noContactRig, noLegsRig, noLegsFlatRig, packer, flatRig, scopeRig, scopeFlatRig, handRig, handFlatRig, handScopeRig, handScopeFlatRig, many, ...rigs]) r.free();

const rows = [
  { ...full, vs: kdFull },
  { ...noContact, vs: kdFull },
  { ...flat, vs: kdFull },
  { ...noLegs, vs: kdFull },
  { ...noLegsFlat, vs: kdFull },
  { ...scoped, vs: kdFull },
  { ...scopedFlat, vs: kdFull },
  ...variants.map((v) => ({ ...v, vs: kdFull })),
  { ...kdFull, vs: kdFull },
  { ...hands, vs: kdHand },
  { ...handsFlat, vs: kdHand },
  { ...handsScoped, vs: kdHand },
  { ...handsScopedFlat, vs: kdHand },
  { ...kdHand, vs: kdHand },
];
if (json) {
  console.log(JSON.stringify({ node: process.version, passes, warmup, avatar: arg("--avatar", "debug-robot.vrm"), frames: framesName, rows, rigsPerMs, chainRows }, null, 2));
} else {
  console.log(
    `Per-frame cost, Node ${process.version}, ${passes} passes after ${warmup} warm-up passes; avatar ${arg("--avatar", "debug-robot.vrm").replace(/^.*\//, "")}; ` +
      `full frame: ${aslFrames.length} ${framesName} frames ` +
      `(pose + 0-2 hands), one hand: ${handFrames.length} frames (sink ${sink > 0})`,
  );
  console.log("method                                                        median us    p95 us   Kalidokit / this (median)");
  for (const r of rows) {
    console.log(
      `${r.label.padEnd(61)} ${r.median.toFixed(1).padStart(9)} ${r.p95.toFixed(1).padStart(9)} ${(r.vs.median / r.median).toFixed(2).padStart(12)}`,
    );
  }
  console.log(`100 rigs, full frames: ${rigsPerMs.toFixed(1)} rigs solved per millisecond (object API)`);
  for (const r of chainRows) {
    console.log(`${r.label}: median ${r.median.toFixed(1)} µs, p95 ${r.p95.toFixed(1)} µs, iterations mean ${r.iterationsMean.toFixed(1)} / p95 ${r.iterationsP95}`);
  }
}
