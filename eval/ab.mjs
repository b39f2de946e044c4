// Two builds of the package side by side in one process, on the same real frames: what a
// change did to the per-frame cost, measured so that the machine's load (this one is shared)
// slows both alike. Each round times one pass of every case over all frames with A, then with
// B; the figure is the median over rounds of a pass's mean time per frame.
//
//   node eval/ab.mjs --a DIR --b DIR [--rounds N]   (DIR: a built package, e.g. pkg/ or the
//                                                     output of `node pkg-config/build.mjs --out-dir DIR`)
//
// Cases: the ASL clips (../shared/data/asl, 250 full frames: pose and 0-2 hands) through the
// flat path (frames packed once beforehand), and through the object API with MediaPipe's
// landmarks as arrays (as recorded) and as {x, y, z, visibility} objects (as tasks-vision
// returns them). Robot avatar, default options, the build each package loads by default
// (HANDRIG_WASM=baseline or simd128 forces one for both).

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { aslFrames } from "./full-frame.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const shared = process.env.HANDRIG_SHARED ?? resolve(here, "../../shared");
const require = createRequire(import.meta.url);

const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};
const dirs = [arg("--a"), arg("--b")];
if (dirs.some((d) => d === undefined)) {
  console.error("usage: node eval/ab.mjs --a DIR --b DIR [--rounds N]");
  process.exit(1);
}
const rounds = Number(arg("--rounds", 40));
const warm = Math.min(10, Math.floor(rounds / 4));
const [A, B] = dirs.map((d) => require(resolve(d)).HandRig);

const robot = readFileSync(`${shared}/avatars/debug-robot.vrm`);
const frames = aslFrames(shared);
const asObject = ([x, y, z, visibility]) => (visibility === undefined ? { x, y, z } : { x, y, z, visibility });
const objectFrames = frames.map((f) => ({
  ...f,
  pose: { worldLandmarks: f.pose.worldLandmarks.map(asObject), landmarks: f.pose.landmarks.map(asObject) },
  hands: f.hands.map((h) => ({
    ...h,
    landmarks: h.landmarks.map(asObject),
    worldLandmarks: h.worldLandmarks?.map(asObject),
  })),
}));
const packer = A.fromVrm(robot);
const packed = frames.map((f) => {
  packer.solve(f);
  return Float32Array.from(packer.input);
});
packer.free();

let sink = 0;
const cases = {
  "flat path": (rig, round) => {
    const input = rig.input;
    // Each pass is its own session (a gap of 100 s), as every pass starts from frame 0.
    for (let i = 0; i < frames.length; i++) {
      input.set(packed[i]);
      rig.solveFlat(frames[i].timeMs + round * 1e5);
    }
    sink += rig.output[0];
  },
  "object API, arrays": (rig) => {
    for (const f of frames) sink += rig.solve(f).timeMs;
  },
  "object API, objects": (rig) => {
    for (const f of objectFrames) sink += rig.solve(f).timeMs;
  },
};

const median = (v) => [...v].sort((x, y) => x - y)[v.length >> 1];
console.log(`A = ${dirs[0]}, B = ${dirs[1]}; ${rounds - warm} rounds after ${warm}; µs per full frame (median of pass means)`);
for (const [label, run] of Object.entries(cases)) {
  const rigs = [A.fromVrm(robot), B.fromVrm(robot)];
  const times = [[], []];
  for (let round = 0; round < rounds; round++) {
    for (let j = 0; j < 2; j++) {
      const t0 = process.hrtime.bigint();
      run(rigs[j], round);
      if (round >= warm) times[j].push(Number(process.hrtime.bigint() - t0) / 1e3 / frames.length);
    }
  }
  const [a, b] = times.map(median);
  console.log(`${label.padEnd(22)} A ${a.toFixed(2).padStart(6)}   B ${b.toFixed(2).padStart(6)}   B / A ${(b / a).toFixed(3)}`);
  for (const r of rigs) r.free();
}
if (!(sink > 0)) console.log("(sink)");
