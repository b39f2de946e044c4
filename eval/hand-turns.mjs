// Hand turns on real video (issue 27): handrig (every default option on, the generated avatars
// and the robot, from `cargo run --release --example eval_turns -- --json`) against the
// MediaPipe input and Kalidokit 1.1.5 on the same frames. Prints a markdown table.
//
//   npm ci --prefix eval        # once: kalidokit 1.1.5
//   node eval/hand-turns.mjs    # about 1 minute with a warm release build
//
// Per side-frame (a side whose hand is tracked in this frame and the one before): the largest
// angle between consecutive frames of the world rotations of upper arm, forearm and hand.
// Kalidokit as its VRM example drives an avatar: `Pose.solve(world, image)` for the arms and
// `Hand.solve(image landmarks, side)` for the wrist, the hand's rotation {x, y: Hand.solve's
// wrist, z: Pose.solve's hand} as Euler XYZ, world rotations composed upper arm * forearm *
// hand (its arms are relative to the chest; the torso is left out), no smoothing.

import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

import { kalidokitFrame } from "./full-frame.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const shared = resolve(root, "../shared");
const require = createRequire(import.meta.url);
const Kalidokit = require("kalidokit/dist/kalidokit.umd.js");

const CLIPS = ["again", "brother", "eat", "please", "sister", "thanks"];

// three.js Quaternion.setFromEuler, order "XYZ".
const quatFromEulerXYZ = ({ x, y, z }) => {
  const [c1, c2, c3] = [Math.cos(x / 2), Math.cos(y / 2), Math.cos(z / 2)];
  const [s1, s2, s3] = [Math.sin(x / 2), Math.sin(y / 2), Math.sin(z / 2)];
  return [
    s1 * c2 * c3 + c1 * s2 * s3,
    c1 * s2 * c3 - s1 * c2 * s3,
    c1 * c2 * s3 + s1 * s2 * c3,
    c1 * c2 * c3 - s1 * s2 * s3,
  ];
};
const qmul = (a, b) => [
  a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
  a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
  a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
  a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
];
const angle = (a, b) => {
  const d = Math.min(1, Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]));
  return (2 * Math.acos(d) * 180) / Math.PI;
};

const IMAGE = { runtime: "mediapipe", imageSize: { width: 640, height: 480 } };

/** Kalidokit's per side-frame turns over one clip's frames. */
function kalidokitTurns(frames) {
  const turns = [];
  const last = { Left: null, Right: null };
  for (const f of frames) {
    const k = kalidokitFrame(f);
    const pose = Kalidokit.Pose.solve(k.world, k.image, IMAGE);
    for (const side of ["Left", "Right"]) {
      const h = k.hands.find((x) => x.side === side);
      const hand = h && pose ? Kalidokit.Hand.solve(h.points, side) : null;
      let now = null;
      if (hand) {
        const upper = quatFromEulerXYZ(pose[`${side}UpperArm`]);
        const lower = qmul(upper, quatFromEulerXYZ(pose[`${side}LowerArm`]));
        const wrist = hand[`${side}Wrist`];
        const handQ = qmul(lower, quatFromEulerXYZ({ x: wrist.x, y: wrist.y, z: pose[`${side}Hand`].z }));
        now = [upper, lower, handQ];
      }
      if (now && last[side]) turns.push(Math.max(...now.map((q, i) => angle(q, last[side][i]))));
      last[side] = now;
    }
  }
  return turns;
}

function figures(v) {
  const s = [...v].sort((a, b) => a - b);
  return {
    sideFrames: v.length,
    over90: v.filter((a) => a > 90).length,
    pctOver45: (100 * v.filter((a) => a > 45).length) / Math.max(1, v.length),
    median: s.length ? s[Math.floor(s.length / 2)] : NaN,
    max: s.length ? s[s.length - 1] : 0,
  };
}

const rust = JSON.parse(
  execFileSync("cargo", ["run", "--quiet", "--release", "--example", "eval_turns", "--", "--json"], {
    cwd: root,
    encoding: "utf8",
    maxBuffer: 64 << 20,
  }),
);
const kd = figures(
  CLIPS.flatMap((c) => kalidokitTurns(JSON.parse(readFileSync(join(shared, "data/asl", `${c}.json`), "utf8")).frames)),
);

const cell = (f) =>
  `${f.sideFrames} | ${f.over90} | ${f.pctOver45.toFixed(1)} | ${f.median.toFixed(1)} | ${f.max.toFixed(1)}`;
console.log("| ASL clips (6), turn between frames (deg) | side-frames | > 90 | % > 45 | median | max | palm labels agree |");
console.log("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
console.log(`| input: MediaPipe palm (world landmarks) | ${cell(rust.input.asl)} | ${rust.input.palm.agree}/${rust.input.palm.labelled} |`);
for (const a of rust.avatars) {
  console.log(`| handrig, ${a.avatar} | ${cell(a.asl)} | ${a.palm.agree}/${a.palm.labelled} |`);
}
console.log(`| Kalidokit 1.1.5 (image landmarks) | ${cell(kd)} | |`);
console.log("\n| hand video (621 frames), turn between frames (deg) | side-frames | > 90 | % > 45 | median | max |");
console.log("| --- | ---: | ---: | ---: | ---: | ---: |");
console.log(`| input: MediaPipe palm | ${cell(rust.input.video)} |`);
for (const a of rust.avatars) console.log(`| handrig, ${a.avatar} | ${cell(a.video)} |`);
console.log("\nLargest handrig turns (robot):");
for (const w of rust.worst) {
  console.log(
    `  ${w.clip}:${w.frame} ${w.side} ${w.bone}: avatar ${w.avatar_turn.toFixed(1)}, input palm ${w.input_turn.toFixed(1)}`,
  );
}
