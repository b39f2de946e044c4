#!/usr/bin/env node
// What the face costs per frame (issue 50), in Node on the built package: the four ASL clips of
// eval/speed.mjs (pose and hands, ../shared/data/asl) solved with and without the face that
// FaceLandmarker found in the same frame (eval/face/CLIP.json, `make eval-face` records them:
// 52 blendshapes, the matrix, 478 landmarks), interleaved pass by pass as eval/speed.mjs does;
// the object API (`rig.solve(frame)`: the face packed in JS, result.expressions / .arkit /
// .lookAt filled) and the flat path (the packed input copied in, `rig.solveFlat(t)`). The object
// API twice with the face: the 250 frames' results made once and cycled (out of cache by the
// time a frame comes round again), and each frame's result made just before its call, untimed
// (in cache, as an app reads the result MediaPipe's glue has just written). Also
// Kalidokit 1.1.5's Face.solve on the same landmarks (which it scales in place: they are reset
// before each call, inside the timing, a copy of 478 points). Median and p95 microseconds.
//
//   node eval/face-speed.mjs [--passes N] [--warmup W] [--pkg DIR] [--one-copy]

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join, resolve, sep } from "node:path";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";

const { values: o } = parseArgs({
  options: { pkg: { type: "string" }, passes: { type: "string" }, warmup: { type: "string" }, "one-copy": { type: "boolean" } },
});
const pkgDir = resolve(o.pkg ?? join(REPO, "pkg"));
const pkgRequire = createRequire(join(pkgDir, "index.cjs"));
/**
 * The package loaded afresh (its JS and its wasm instance): each method's rig runs its own copy
 * of the JS layer, whose JIT sees only that method's frames, as in an app whose frames all have
 * one shape. With --one-copy all rigs share one copy (the frame-reading code then sees frames
 * with and without the face fields, and is slower for both).
 */
function loadHandRig() {
  for (const k of Object.keys(pkgRequire.cache)) if (k.startsWith(pkgDir + sep)) delete pkgRequire.cache[k];
  return pkgRequire(join(pkgDir, "index.cjs")).HandRig;
}
const shared1 = o["one-copy"] ? loadHandRig() : null;
const newRig = (bytes) => (shared1 ?? loadHandRig()).fromVrm(bytes);
const { Face } = createRequire(join(REPO, "eval", "package.json"))("kalidokit/dist/kalidokit.umd.js");
const shared = process.env.HANDRIG_SHARED ?? join(REPO, "..", "shared");
const passes = Number(o.passes ?? 10);
const warmup = Number(o.warmup ?? 20);
const robot = readFileSync(join(shared, "avatars", "debug-robot.vrm"));

const plain = [];
const withFace = [];
const landmarks = [];
const lmIn = [];
const faces = [];
for (const clip of ["eat", "thanks", "brother", "sister"]) {
  const asl = JSON.parse(readFileSync(join(shared, "data", "asl", `${clip}.json`), "utf8")).frames;
  const face = JSON.parse(readFileSync(join(REPO, "eval", "face", `${clip}.json`), "utf8")).frames;
  asl.forEach((f, k) => {
    const g = face[k];
    plain.push(f);
    if (!g?.landmarks) {
      withFace.push(f);
      landmarks.push(null);
      lmIn.push(null);
      return;
    }
    // Kalidokit's Face.solve scales the points it is given in place: its own copy.
    landmarks.push(g.landmarks.map(([x, y, z]) => ({ x, y, z })));
    lmIn.push(g.landmarks);
    // As an app passes it: rig.solve({ timeMs, hands, pose, ...faceLandmarkerResult }). (Built
    // as { ...f, faceLandmarks, ... }, on the recording's parsed frame, V8 reads the fields the
    // frame lacks slowly, leaving ~30 bytes of garbage each: ~4 µs more, face or not.)
    withFace.push(asApp(f, g));
  });
  faces.push(...face);
}
/** The recording's frame `f` with the face `g`, as an app writes it. */
function asApp(f, g) {
  return { timeMs: f.timeMs, hands: f.hands, pose: f.pose, ...faceResult(g) };
}
/** A FaceLandmarkerResult of the recording's frame, its objects new, as MediaPipe's glue makes each frame's. */
function faceResult(g) {
  return {
    faceLandmarks: [g.landmarks.map(([x, y, z]) => ({ x, y, z }))],
    faceBlendshapes: [{ categories: g.blendshapes.map(([categoryName, score], index) => ({ index, score, categoryName, displayName: "" })), headIndex: -1, headName: "" }],
    facialTransformationMatrixes: [{ rows: 4, columns: 4, data: g.matrix.slice() }],
  };
}
const n = plain.length;
let sink = 0;
const pack = (frames) => {
  const r = newRig(robot);
  return frames.map((f) => (r.solve(f), Float32Array.from(r.input)));
};
const packedPlain = pack(plain);
const packedFace = pack(withFace);
let fresh = null;
const rigs = [0, 1, 2, 3, 4].map(() => newRig(robot));
const flat = (r, packed) => {
  const { input, output } = r;
  return (i) => {
    input.set(packed[i]);
    r.solveFlat(plain[i].timeMs);
    sink += output[0];
  };
};
const methods = [
  ["object API, no face", (i) => (sink += rigs[0].solve(plain[i]).timeMs)],
  ["object API, with the face", (i) => (sink += rigs[1].solve(withFace[i]).timeMs)],
  // The frame's result made just before (untimed): read from cache, as an app reads the result
  // MediaPipe has just written; the rows above cycle 250 frames' results, read from memory.
  ["object API, with the face just made", (i) => (sink += rigs[4].solve(fresh).timeMs), (i) => (fresh = withFace[i] === plain[i] ? plain[i] : asApp(plain[i], faces[i]))],
  ["flat path, no face", flat(rigs[2], packedPlain)],
  ["flat path, with the face", flat(rigs[3], packedFace)],
  ["Kalidokit Face.solve", (i) => {
    const lm = landmarks[i];
    if (lm) for (let k = 0; k < lm.length; k++) (lm[k].x = lmIn[i][k][0]), (lm[k].y = lmIn[i][k][1]), (lm[k].z = lmIn[i][k][2]);
    const r = lm && Face.solve(lm, { runtime: "mediapipe", imageSize: { width: 640, height: 480 } });
    sink += r ? r.head.x : 0;
  }],
];
for (let w = 0; w < warmup; w++) for (const [, fn, prep] of methods) for (let i = 0; i < n; i++) (prep?.(i), fn(i));
const samples = methods.map(() => []);
for (let p = 0; p < passes; p++) {
  for (let m = 0; m < methods.length; m++) {
    const prep = methods[m][2];
    for (let i = 0; i < n; i++) {
      prep?.(i);
      const t0 = process.hrtime.bigint();
      methods[m][1](i);
      samples[m].push(Number(process.hrtime.bigint() - t0) / 1000);
    }
  }
}
const q = (s, p) => [...s].sort((a, b) => a - b)[Math.min(s.length - 1, Math.floor(p * s.length))];
console.log(`${n} frames (${withFace.filter((f, i) => f !== plain[i]).length} with a face) x ${passes} passes after ${warmup} warm-up passes`);
console.log("| | median µs | p95 µs |\n| --- | ---: | ---: |");
methods.forEach(([label], m) => console.log(`| ${label} | ${q(samples[m], 0.5).toFixed(1)} | ${q(samples[m], 0.95).toFixed(1)} |`));
const added = (m, base) => (q(samples[m], 0.5) - q(samples[base], 0.5)).toFixed(1);
console.log(`face added, median: object API ${added(1, 0)} µs (its result just made: ${added(2, 0)} µs), flat path ${added(4, 3)} µs`);
if (sink === 42) console.log("");
