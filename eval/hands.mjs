// Hand solver comparison: handrig's analytic solver vs Kalidokit, same avatar, same frames,
// same metric (issue 3).
//
//   npm ci --prefix eval        # once: installs kalidokit (pinned in eval/package.json)
//   node eval/hands.mjs [--json] [--avatar FILE.vrm | --rest REST.json [--rest-key NAME]] [--data DIR]
//
// Default avatar ../shared/avatars/debug-robot.vrm, data ../shared/data/hands (from the repo
// root, wherever the script is started from).
//
// 1. Runs `cargo run --release --example eval_hands -- --json` (handrig's numbers, its
//    per-frame finger rotations and the avatar's rest positions).
// 2. Recomputes handrig's metric here from those rotations (a cross-check of this script's
//    forward kinematics and metric against the Rust ones).
// 3. Runs Kalidokit.Hand.solve on the same landmarks and applies its rotations to the same
//    avatar rest the way Kalidokit's own VRM example does (Euler "XYZ" rotations set on the
//    VRM 0.x normalized finger bones, no smoothing), converted to the VRM 1.0 frame of
//    handrig's avatar (a VRM 0.x model faces -Z: negate quaternion x and z).
// 4. Prints one table per recording: per finger, median and p95 of the angle between avatar
//    bone and MediaPipe segment in the palm frame, for both methods, with their ratio;
//    frames where a handrig joint limit of that finger is active are reported separately.

import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { percentile } from "./bench/scoring.mjs";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const require = createRequire(import.meta.url);
// The ESM build of Kalidokit does not load in Node; its UMD build does.
let Kalidokit;
try {
  Kalidokit = require("kalidokit/dist/kalidokit.umd.js");
} catch (e) {
  console.error(`kalidokit not installed (${e.code ?? e.message}): run \`npm ci --prefix eval\` first`);
  process.exit(1);
}

const args = process.argv.slice(2);
const jsonOut = args.includes("--json");
const passThrough = args.filter((a) => a !== "--json");

// ---- handrig (Rust) ------------------------------------------------------------------------
const rust = JSON.parse(
  execFileSync("cargo", ["run", "--quiet", "--release", "--example", "eval_hands", "--", "--json", ...passThrough], {
    cwd: root,
    maxBuffer: 1 << 30,
    encoding: "utf8",
    stdio: ["ignore", "pipe", "inherit"],
  }),
);
const rest = rust.restInternal;

// ---- small vector math -------------------------------------------------------------------
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const norm = (a) => {
  const l = Math.hypot(a[0], a[1], a[2]);
  return l > 0 ? scale(a, 1 / l) : null;
};
const qmul = (a, b) => [
  a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
  a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
  a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
  a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
];
const qrot = (q, v) => {
  const u = [q[0], q[1], q[2]];
  const t = scale(cross(u, v), 2);
  return add(add(v, scale(t, q[3])), cross(u, t));
};
// three.js Quaternion.setFromEuler, order "XYZ".
const quatFromEulerXYZ = (x, y, z) => {
  const [c1, c2, c3] = [Math.cos(x / 2), Math.cos(y / 2), Math.cos(z / 2)];
  const [s1, s2, s3] = [Math.sin(x / 2), Math.sin(y / 2), Math.sin(z / 2)];
  return [
    s1 * c2 * c3 + c1 * s2 * s3,
    c1 * s2 * c3 - s1 * c2 * s3,
    c1 * c2 * s3 + s1 * s2 * c3,
    c1 * c2 * c3 - s1 * s2 * s3,
  ];
};
const angleDeg = (a, b) => (Math.acos(Math.min(1, Math.max(-1, dot(a, b)))) * 180) / Math.PI;

// Palm frame exactly as handrig::hand::palm_frame: rows (forward, radial, palmar).
function palmFrame(side, wrist, index, little, middle) {
  const f = norm(sub(middle, wrist));
  const across = sub(index, little);
  if (!f) return null;
  const r = norm(sub(across, scale(f, dot(across, f))));
  if (!r) return null;
  const n = side === "right" ? cross(r, f) : cross(f, r);
  return [f, r, n];
}
const inPalm = (frame, v) => [dot(frame[0], v), dot(frame[1], v), dot(frame[2], v)];

// ---- the avatar: finger chains below the hand ----------------------------------------------
const FINGERS = ["thumb", "index", "middle", "ring", "little"];
const SLOTS = { thumb: ["Metacarpal", "Proximal", "Distal"], other: ["Proximal", "Intermediate", "Distal"] };
const cap = (s) => s[0].toUpperCase() + s.slice(1);
const boneName = (side, finger, slot) => `${side}${cap(finger)}${(finger === "thumb" ? SLOTS.thumb : SLOTS.other)[slot]}`;
const LANDMARKS = (finger) => {
  const b = 1 + 4 * FINGERS.indexOf(finger);
  return [b, b + 1, b + 2, b + 3];
};

// Forward kinematics of one hand with the hand at rest orientation: world position and
// rotation of every finger bone from local rotations (bone name -> [x, y, z, w]).
function handFk(side, local) {
  const hand = rest[`${side}Hand`];
  const out = {};
  for (const finger of FINGERS) {
    let parentPos = hand;
    let parentRest = hand;
    let parentRot = [0, 0, 0, 1];
    for (let slot = 0; slot < 3; slot++) {
      const name = boneName(side, finger, slot);
      if (!rest[name]) continue;
      const pos = add(parentPos, qrot(parentRot, sub(rest[name], parentRest)));
      const rot = qmul(parentRot, local[name] ?? [0, 0, 0, 1]);
      out[name] = { pos, rot };
      parentPos = pos;
      parentRest = rest[name];
      parentRot = rot;
    }
  }
  return out;
}

// Per-finger errors (degrees) of one frame: avatar bone vs MediaPipe segment, palm frame.
function frameErrors(side, lm, local) {
  const fk = handFk(side, local);
  const p = (f) => fk[boneName(side, f, 0)].pos;
  const avatarPalm = palmFrame(side, rest[`${side}Hand`], p("index"), p("little"), p("middle"));
  const mpPalm = palmFrame(side, lm[0], lm[5], lm[17], lm[9]);
  const errors = {};
  for (const finger of FINGERS) {
    const ids = LANDMARKS(finger);
    errors[finger] = [];
    const present = [0, 1, 2].filter((s) => rest[boneName(side, finger, s)]);
    for (const slot of present) {
      const name = boneName(side, finger, slot);
      const next = present.find((s) => s > slot);
      let a;
      if (next !== undefined) {
        a = sub(fk[boneName(side, finger, next)].pos, fk[name].pos);
      } else {
        const prev = [...present].reverse().find((s) => s < slot);
        const parentRest = prev !== undefined ? rest[boneName(side, finger, prev)] : rest[`${side}Hand`];
        a = qrot(fk[name].rot, sub(rest[name], parentRest));
      }
      const m = sub(lm[ids[next ?? 3]], lm[ids[slot]]);
      errors[finger].push(angleDeg(inPalm(avatarPalm, norm(a)), inPalm(mpPalm, norm(m))));
    }
  }
  return errors;
}

// ---- the recordings, mapped as in the Rust eval ------------------------------------------
const dataDir = (() => {
  const i = passThrough.indexOf("--data");
  return i >= 0 ? resolve(passThrough[i + 1]) : join(root, "../shared/data/hands");
})();
const video = JSON.parse(readFileSync(join(dataDir, "right-hand-video-mediapipe.json"), "utf8"));
const canonical = JSON.parse(readFileSync(join(dataDir, "right-hand-canonical.json"), "utf8"));
// Highest score; on a tie the later hand, like the Rust side (Iterator::max_by).
const best = (hands) => hands.reduce((a, b) => ((b.score ?? 0) >= (a.score ?? 0) ? b : a));
const recordings = {
  "right-hand-video-mediapipe": video.map((f) => {
    const h = best(f.hands);
    // Default options: (x, -y, -z); the "Left" label on un-mirrored input is the right hand.
    return {
      world: h.worldLandmarks,
      image: h.landmarks,
      avatar: h.worldLandmarks.map(([x, y, z]) => [x, -y, -z]),
    };
  }),
  "right-hand-canonical": canonical.frames.map((f) => (f ? { world: f, image: null, avatar: f } : null)),
};

// ---- Kalidokit -----------------------------------------------------------------------------
function kalidokitLocal(landmarks, side) {
  const solved = Kalidokit.Hand.solve(
    landmarks.map(([x, y, z]) => ({ x, y, z })),
    cap(side),
  );
  const local = {};
  for (const finger of FINGERS) {
    // Kalidokit names VRM 0.x bones: thumbProximal/Intermediate/Distal are VRM 1.0's
    // thumbMetacarpal/Proximal/Distal (three-vrm's remap).
    const names0 = ["Proximal", "Intermediate", "Distal"];
    for (let slot = 0; slot < 3; slot++) {
      const r = solved[`${cap(side)}${cap(finger)}${names0[slot]}`];
      const q = quatFromEulerXYZ(r.x, r.y, r.z);
      local[boneName(side, finger, slot)] = [-q[0], q[1], -q[2], q[3]];
    }
  }
  return local;
}

// ---- statistics ----------------------------------------------------------------------------
const stats = (v) => ({ samples: v.length, median: percentile(v, 50), p95: percentile(v, 95) });

const results = {};
let crossCheck = 0;
for (const rec of rust.recordings) {
  const frames = recordings[rec.recording];
  const buckets = {};
  for (const f of FINGERS) {
    buckets[f] = { hr: [], kd: [], kdImage: [], hrLim: [], kdLim: [], framesFree: 0, framesLim: 0, kdAll: [] };
  }
  rec.perFrame.forEach((out, i) => {
    const input = frames[i];
    if (!out || !input) return;
    const side = out.side;
    const hr = frameErrors(side, input.avatar, out.local);
    const kd = frameErrors(side, input.avatar, kalidokitLocal(input.world, side));
    const kdImage = input.image ? frameErrors(side, input.avatar, kalidokitLocal(input.image, side)) : null;
    FINGERS.forEach((f, k) => {
      const b = buckets[f];
      const limited = out.limited[k];
      b.kdAll.push(...kd[f]);
      if (limited) {
        b.framesLim++;
        b.hrLim.push(...hr[f]);
        b.kdLim.push(...kd[f]);
      } else {
        b.framesFree++;
        b.hr.push(...hr[f]);
        b.kd.push(...kd[f]);
        if (kdImage) b.kdImage.push(...kdImage[f]);
      }
    });
  });
  results[rec.recording] = {};
  for (const f of FINGERS) {
    const b = buckets[f];
    const r = {
      framesFree: b.framesFree,
      framesLimited: b.framesLim,
      handrig: stats(b.hr),
      kalidokit: stats(b.kd),
      kalidokitImageLandmarks: b.kdImage.length ? stats(b.kdImage) : null,
      handrigLimited: stats(b.hrLim),
      kalidokitLimited: stats(b.kdLim),
    };
    // The JS metric on handrig's rotations must equal the Rust metric.
    const rs = rec.fingers.find((x) => x.finger === f).limitFree;
    crossCheck = Math.max(crossCheck, Math.abs(rs.median - r.handrig.median), Math.abs(rs.p95 - r.handrig.p95));
    results[rec.recording][f] = r;
  }
}
if (!(crossCheck < 0.01)) {
  console.error(`metric cross-check failed: Rust and JS differ by ${crossCheck} deg`);
  process.exit(1);
}

if (jsonOut) {
  console.log(JSON.stringify({ avatar: rust.avatar, results }, null, 1));
  process.exit(0);
}

const fmt = (x, w = 6) => (Number.isFinite(x) ? x.toFixed(2) : "-").padStart(w);
// A ratio to a figure below 0.05 degrees (handrig's limit-free medians, which copy the tracked
// directions) would only show float noise: printed as ">100".
const ratio = (a, b, w) => (b < 0.05 && a / b > 100 ? ">100".padStart(w) : fmt(a / b, w));
console.log(`Hand solvers on the same avatar (${rust.avatar}) and frames.`);
console.log("Angle (deg) between avatar bone and MediaPipe segment, both in their palm frame;");
console.log("per finger all bones pooled. 'free' = frames where no handrig limit of that finger is active;");
console.log("'limited' = the others. ratio = Kalidokit / handrig. Kalidokit fed world landmarks;");
console.log("'kd img' = Kalidokit fed normalized image landmarks, as its demo does (video only).");
for (const [name, fingers] of Object.entries(results)) {
  console.log(`\n${name}`);
  console.log(
    `${"finger".padEnd(7)} ${"free".padStart(5)} | ${"handrig".padStart(13)} | ${"Kalidokit".padStart(13)} | ${"ratio".padStart(11)} | ${"kd img".padStart(13)} | ${"lim".padStart(4)} ${"handrig lim".padStart(13)} ${"Kalidokit lim".padStart(13)}`,
  );
  console.log(
    `${"".padEnd(7)} ${"".padStart(5)} | ${"median   p95".padStart(13)} | ${"median   p95".padStart(13)} | ${"med   p95".padStart(11)} | ${"median   p95".padStart(13)} | ${"".padStart(4)} ${"median   p95".padStart(13)} ${"median   p95".padStart(13)}`,
  );
  for (const [f, r] of Object.entries(fingers)) {
    const img = r.kalidokitImageLandmarks;
    console.log(
      `${f.padEnd(7)} ${String(r.framesFree).padStart(5)} | ${fmt(r.handrig.median)} ${fmt(r.handrig.p95)} | ${fmt(r.kalidokit.median)} ${fmt(r.kalidokit.p95)} | ${ratio(r.kalidokit.median, r.handrig.median, 5)} ${ratio(r.kalidokit.p95, r.handrig.p95, 5)} | ${fmt(img?.median)} ${fmt(img?.p95)} | ${String(r.framesLimited).padStart(4)} ${fmt(r.handrigLimited.median)} ${fmt(r.handrigLimited.p95)} ${fmt(r.kalidokitLimited.median)} ${fmt(r.kalidokitLimited.p95)}`,
    );
  }
}
console.log(`\nmetric cross-check (Rust vs this script on handrig's rotations): max difference ${crossCheck.toExponential(1)} deg`);
console.log(`handrig output quaternions not unit or not finite: ${rust.badQuaternions}`);
