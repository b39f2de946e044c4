#!/usr/bin/env node
// The face on real faces (issue 50): handrig (the built package in pkg/, default options) and
// Kalidokit 1.1.5's Face.solve on the same FaceLandmarker recordings of the shared ASL clips
// (eval/face/CLIP.json, made by eval/face-record.mjs), scored against the frames labelled by eye
// in eval/labels/face.json (eyes closed, mouth open, head turned):
//   - blink recall: labelled closed-eye frames where the blink (either eye) is at least 0.5;
//   - false blinks: other frames (not next to a closed one) where it is at least 0.5;
//   - closing: from each labelled closure's first frame, the frames to the blink at least 0.5;
//   - aa on open-mouth frames (mean, and the share at least 0.3) and on the others (share at most 0.1);
//   - head yaw and pitch against the transformation matrix's (degrees, mean and largest);
//   - on still stretches (the matrix turning under 1 degree a frame, no blendshape moving 0.1 or
//     more, no labelled event within 3 frames), how far the expression weights move per frame
//     (95th percentile and largest), beside how far MediaPipe's blendshapes moved.
// The clips are split in two halves: the constants of src/face were looked at on the tuning
// half, the figures that count are the test half's. A third group, `talking`, is a talking face
// (eval/talking-clip.mjs: a man talking, a wide-open mouth, blinks, the head turned), added after
// every constant was set: nothing was tuned on it. Its mouth is labelled both ways (mouthOpen,
// mouthClosed: talking mouths between the two are left out); the ASL clips' mouths are closed
// throughout, so there every frame not labelled open counts as closed.
//
//   make eval-face                       # records (once) and scores
//   node eval/face.mjs [--pkg DIR] [--json FILE] [--options JSON]

import { existsSync, readFileSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";

const { values: o } = parseArgs({ options: { pkg: { type: "string" }, json: { type: "string" }, options: { type: "string" } } });
const pkgDir = o.pkg ?? join(REPO, "pkg");
const { HandRig } = await import(pathToFileURL(join(pkgDir, "index.mjs")).href);
const { Face } = createRequire(join(REPO, "eval", "package.json"))("kalidokit/dist/kalidokit.umd.js");

export const TUNE = ["again", "eat", "please", "thanks"];
export const TEST = ["brother", "hungry", "sister"];
export const TALK = ["carphone"];
const labels = JSON.parse(readFileSync(join(REPO, "eval", "labels", "face.json"), "utf8"));
const robot = readFileSync(join(REPO, "..", "shared", "avatars", "debug-robot.vrm"));

const DEG = 180 / Math.PI;
/** Yaw and pitch (degrees) of a rotation given as a quaternion [x, y, z, w]: the turn of +Z. */
function yawPitch([x, y, z, w]) {
  // +Z turned: the third column of the rotation matrix.
  const fx = 2 * (x * z + w * y);
  const fy = 2 * (y * z - w * x);
  const fz = 1 - 2 * (x * x + y * y);
  return [Math.atan2(fx, fz) * DEG, Math.atan2(-fy, Math.hypot(fx, fz)) * DEG];
}
const qmul = (a, b) => [
  a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
  a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
  a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
  a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
];
/** The matrix's head direction as yaw, pitch (the avatar frame, un-mirrored: x as in the image). */
function matrixYawPitch(m) {
  const n = Math.hypot(m[8], m[9], m[10]);
  const fx = m[8] / n, fy = m[9] / n, fz = m[10] / n;
  return [Math.atan2(fx, fz) * DEG, Math.atan2(-fy, Math.hypot(fx, fz)) * DEG];
}

function run(clip) {
  const rec = JSON.parse(readFileSync(join(REPO, "eval", "face", `${clip}.json`), "utf8"));
  const rig = HandRig.fromVrm(robot, JSON.parse(o.options ?? "{}"));
  const out = [];
  for (const f of rec.frames) {
    const frame = { timeMs: f.timeMs };
    if (f.landmarks) {
      frame.faceLandmarks = [f.landmarks.map(([x, y, z]) => ({ x, y, z }))];
      frame.faceBlendshapes = [{ categories: f.blendshapes.map(([categoryName, score], index) => ({ index, score, categoryName, displayName: "" })) }];
      frame.facialTransformationMatrixes = [{ rows: 4, columns: 4, data: f.matrix }];
    } else {
      // No face found: a FaceLandmarkerResult's empty lists, as an app passes them (a frame
      // without the fields would be a frame of an app with no face tracker: the rig looks for
      // face fields only every 30th frame until it has seen them).
      frame.faceLandmarks = [];
      frame.faceBlendshapes = [];
      frame.facialTransformationMatrixes = [];
    }
    const r = rig.solve(frame);
    const e = r.expressions;
    const neck = r.bones.neck ?? [0, 0, 0, 1];
    const head = r.bones.head ?? [0, 0, 0, 1];
    const hk = f.landmarks ? Face.solve(frame.faceLandmarks[0], { runtime: "mediapipe", imageSize: { width: rec.width, height: rec.height }, smoothBlink: false }) : null;
    out.push({
      frame: f.frame,
      tracked: !!f.landmarks,
      handrig: {
        blink: Math.max(e.blink + e.blinkLeft, e.blink + e.blinkRight),
        aa: e.aa,
        head: yawPitch(qmul(neck, head)),
        weights: LAYOUT_PRESETS.map((n) => e[n]),
      },
      kalidokit: hk && {
        blink: 1 - Math.min(hk.eye.l, hk.eye.r),
        aa: hk.mouth.shape.A,
        head: [hk.head.degrees.y, hk.head.degrees.x],
        weights: [hk.mouth.shape.A, hk.mouth.shape.I, hk.mouth.shape.U, hk.mouth.shape.E, hk.mouth.shape.O, 1 - hk.eye.l, 1 - hk.eye.r],
      },
      matrix: f.matrix ? matrixYawPitch(f.matrix) : null,
      shapes: f.blendshapes ? f.blendshapes.map(([, v]) => v) : null,
    });
  }
  return out;
}
const LAYOUT_PRESETS = ["happy", "angry", "sad", "relaxed", "surprised", "aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight"];

const pct = (xs, p) => {
  if (!xs.length) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(p * s.length))];
};
const mean = (xs) => (xs.length ? xs.reduce((a, b) => a + b, 0) / xs.length : NaN);

function score(clips, who) {
  const acc = { closed: 0, closedHit: 0, other: 0, falseBlink: 0, down: 0, downBlink: 0, open: [], shut: [], yaw: [], pitch: [], still: [], stillRaw: [], frames: 0, turned: 0, turnedRight: 0, toClose: [] };
  for (const clip of clips) {
    const res = run(clip);
    const l = labels[clip];
    const closed = new Set(l.eyesClosed);
    const down = new Set(l.eyesDown);
    const unsure = new Set(l.eyesUnsure ?? []);
    const open = new Set(l.mouthOpen);
    const shut = l.mouthClosed ? new Set(l.mouthClosed) : null;
    const turnedLeft = new Set(l.headTurned.imageLeft ?? []);
    const turnedRight = new Set(l.headTurned.imageRight ?? []);
    // Kalidokit's head angles have their own signs: each is taken with the sign that agrees with
    // the matrix over the clip (handrig's are the avatar's, checked against the turned frames).
    const sign = [0, 1].map((c) => {
      let agree = 0;
      for (const r of res) if (r[who] && r.matrix) agree += Math.abs(r[who].head[c] - r.matrix[c]) - Math.abs(-r[who].head[c] - r.matrix[c]);
      return who === "handrig" || agree <= 0 ? 1 : -1;
    });
    const near = (set, k, d) => { for (let j = k - d; j <= k + d; j++) if (set.has(j)) return true; return false; };
    // Each labelled closure's first frame: how many frames to the blink shown at least 0.5
    // (within the closure, else not read).
    for (const k of closed) {
      if (closed.has(k - 1)) continue;
      let j = k;
      while (closed.has(j) && !(res[j]?.[who]?.blink >= 0.5)) j++;
      acc.toClose.push(closed.has(j) ? j - k : null);
    }
    for (let k = 0; k < res.length; k++) {
      const r = res[k];
      const s = r[who];
      if (!s || !r.tracked) continue;
      acc.frames++;
      if (closed.has(k)) {
        acc.closed++;
        if (s.blink >= 0.5) acc.closedHit++;
      } else if (!near(closed, k, 1) && !unsure.has(k)) {
        acc.other++;
        if (s.blink >= 0.5) acc.falseBlink++;
        if (down.has(k)) {
          acc.down++;
          if (s.blink >= 0.5) acc.downBlink++;
        }
      }
      // A face turned toward the image's left is the user turning to their right: the avatar
      // (un-mirrored input, no mirror) turns to its right, yaw < 0.
      if (turnedLeft.has(k) || turnedRight.has(k)) {
        acc.turned++;
        if (Math.sign(sign[0] * s.head[0]) === (turnedLeft.has(k) ? -1 : 1)) acc.turnedRight++;
      }
      if (open.has(k)) acc.open.push(s.aa);
      else if (shut ? shut.has(k) : !near(open, k, 1)) acc.shut.push(s.aa);
      if (r.matrix) {
        // The matrix's yaw in the avatar's frame: un-mirrored input, no mirror (x as in the image).
        acc.yaw.push(Math.abs(sign[0] * s.head[0] - r.matrix[0]));
        acc.pitch.push(Math.abs(sign[1] * s.head[1] - r.matrix[1]));
      }
      const prev = res[k - 1];
      if (prev && prev[who] && r.matrix && prev.matrix) {
        const turn = Math.hypot(r.matrix[0] - prev.matrix[0], r.matrix[1] - prev.matrix[1]);
        // Still: the head turns under 1 degree and no blendshape moves 0.1 or more (jitter, not
        // an expression changing), away from labelled events.
        const rawMove = Math.max(...r.shapes.map((v, i) => Math.abs(v - prev.shapes[i])));
        if (turn < 1 && rawMove < 0.1 && !near(closed, k, 3) && !near(open, k, 3)) {
          acc.stillRaw.push(rawMove);
          acc.still.push(Math.max(...s.weights.map((w, i) => Math.abs(w - prev[who].weights[i]))));
        }
      }
    }
  }
  return {
    frames: acc.frames,
    blinkRecall: acc.closed ? acc.closedHit / acc.closed : NaN,
    closures: acc.toClose.length,
    toClose: acc.toClose.map((x) => (x === null ? "not read" : x)).join(", "),
    closedFrames: acc.closed,
    falseBlinks: acc.other ? acc.falseBlink / acc.other : NaN,
    falseBlinksDown: acc.down ? acc.downBlink / acc.down : NaN,
    downFrames: acc.down,
    turnedRight: acc.turned ? acc.turnedRight / acc.turned : NaN,
    turnedFrames: acc.turned,
    aaOpenMean: mean(acc.open),
    aaOpenAtLeast03: acc.open.length ? acc.open.filter((a) => a >= 0.3).length / acc.open.length : NaN,
    openFrames: acc.open.length,
    aaShutAtMost01: acc.shut.length ? acc.shut.filter((a) => a <= 0.1).length / acc.shut.length : NaN,
    yawErrMean: mean(acc.yaw),
    yawErrMax: Math.max(...acc.yaw),
    pitchErrMean: mean(acc.pitch),
    pitchErrMax: Math.max(...acc.pitch),
    stillFrames: acc.still.length,
    stillMoveP95: pct(acc.still, 0.95),
    stillMoveMax: Math.max(...acc.still),
    stillRawP95: pct(acc.stillRaw, 0.95),
  };
}

const missing = [...TUNE, ...TEST, ...TALK].filter((c) => !existsSync(join(REPO, "eval", "face", `${c}.json`)));
if (missing.length) throw new Error(`no recording for ${missing.join(", ")}: run node eval/face-record.mjs (make eval-face)`);
const table = {};
for (const [half, clips] of [["tune", TUNE], ["test", TEST], ["talking", TALK]]) {
  for (const who of ["handrig", "kalidokit"]) table[`${half}/${who}`] = score(clips, who);
}
const f = (v, d = 2) => (Number.isNaN(v) ? "n/a" : v.toFixed(d));
const rows = [
  ["frames with a face", (s) => String(s.frames)],
  ["blink recall (closed frames)", (s) => `${f(s.blinkRecall)} (${s.closedFrames})`],
  ["closing: frames from a labelled closure's first frame to the blink >= 0.5, each closure", (s) => (s.closures ? s.toClose : "n/a")],
  ["false blinks (share of other frames)", (s) => f(s.falseBlinks, 3)],
  ["false blinks on eyes-down frames", (s) => `${f(s.falseBlinksDown, 3)} (${s.downFrames})`],
  ["head turn to the labelled side", (s) => `${f(s.turnedRight)} (${s.turnedFrames})`],
  ["aa on open-mouth frames: mean / share >= 0.3", (s) => `${f(s.aaOpenMean)} / ${f(s.aaOpenAtLeast03)} (${s.openFrames})`],
  ["aa on closed-mouth frames: share <= 0.1", (s) => f(s.aaShutAtMost01)],
  ["head yaw vs matrix (deg): mean / max", (s) => `${f(s.yawErrMean, 1)} / ${f(s.yawErrMax, 1)}`],
  ["head pitch vs matrix (deg): mean / max", (s) => `${f(s.pitchErrMean, 1)} / ${f(s.pitchErrMax, 1)}`],
  ["still stretches: weight move per frame p95 / max", (s) => `${f(s.stillMoveP95, 3)} / ${f(s.stillMoveMax, 3)} (${s.stillFrames})`],
  ["(there, MediaPipe's largest blendshape move p95)", (s) => f(s.stillRawP95, 3)],
];
const cols = Object.keys(table);
console.log(`| | ${cols.join(" | ")} |`);
console.log(`| --- | ${cols.map(() => "---").join(" | ")} |`);
for (const [name, fmt] of rows) console.log(`| ${name} | ${cols.map((c) => fmt(table[c])).join(" | ")} |`);
if (o.json) writeFileSync(o.json, JSON.stringify(table, null, 2));
