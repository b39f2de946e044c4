#!/usr/bin/env node
// The face on the ground-truth bench (issue 50): known expressions, gaze and head motion
// (eval/bench/face-motions.mjs) rendered on the generated avatars' faces (render-page.js,
// three-vrm in headless Chromium), tracked by MediaPipe's FaceLandmarker (face-page.js, the
// shared face_landmarker.task, blendshapes and matrices), then solved by handrig (pkg/, default
// options, the rendered avatar as the rig) and Kalidokit 1.1.5's Face.solve on the same frames,
// and scored against the truth:
//   - blink recall: frames where the truth closes an eye (weight >= 0.8) and the solver's blink
//     for that eye is at least 0.5; false blinks: frames with both eyes open in the truth (2
//     frames or more from any closing) where either eye's blink is at least 0.5;
//     the same split into frames with both eyes closed (a blink) and one (a wink);
//   - the wink's side: on one-eye closed frames, the other eye stays under 0.5;
//   - closing and opening: from each frame the truth closes an eye (>= 0.8), how many frames
//     to its blink at least 0.5 (within the closure, else not read); from each frame it opens
//     again (an eye shown closed), how many to its blink under 0.5;
//   - aa on open-mouth frames (truth aa >= 0.8: mean, share >= 0.3) and on closed-mouth ones
//     (no mouth expression within 2 frames: share <= 0.1);
//   - head yaw and pitch against the transformation matrix's (issue 50's criterion, as
//     eval/face.mjs measures it on the ASL clips: what the solver makes of MediaPipe's head);
//   - head yaw and pitch against the rendered truth (neck x head, degrees: mean, 95th percentile,
//     largest), every frame; raw, and from the solver's reading of the avatar's still face (the
//     rendered face at rest is not MediaPipe's canonical face at rest: a constant offset);
//   - look-at: on frames looking 20 degrees aside, the share with the yaw's sign right;
// Kalidokit's signs (head angles, eye sides, pupil) are each taken as the one that agrees with
// the truth over the clip; handrig's are used as they come (the avatar's own: un-mirrored input).
//   - still stretches: frames whose truth has not changed for 6 frames (a face held still: the
//     whole face-still clip and the holds), how far the expression weights move per frame.
// Tuning half: the woman; report half: the man and the child (nothing was chosen on them).
//
//   node eval/face-bench.mjs [--record] [--avatars woman,man,child] [--json FILE]
//   node eval/face-bench.mjs --avatars woman --write-shots   # tests/fixtures/face/bench-shots.json
//   FACE_STILL_TRACE=0.02 node eval/face-bench.mjs            # each still-stretch move over 0.02: where, which weight
//
// --record renders and tracks the clips again (about 4 s a frame-second here); the recordings
// go to eval/face-bench/AVATAR-CLIP.json (not committed, ~0.8 MB a clip), made when missing.

import { existsSync, mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { parseArgs } from "node:util";
import { REPO } from "./bench/common.mjs";
import { FACE_CLIPS, faceFrame } from "./bench/face-motions.mjs";

const { values: o } = parseArgs({
  options: { "write-shots": { type: "boolean" }, record: { type: "boolean" }, avatars: { type: "string" }, json: { type: "string" }, pkg: { type: "string" }, options: { type: "string" } },
});
export const TUNE = ["woman"];
export const REPORT = ["man", "child"];
const avatars = o.avatars ? o.avatars.split(",") : [...TUNE, ...REPORT];
const DIR = join(REPO, "eval", "face-bench");
const recFile = (a, c) => join(DIR, `${a}-${c.id}.json`);
const WIDTH = 640;
const HEIGHT = 480;
const FPS = 30;

async function record(list) {
  const { openRenderer, openBenchPage } = await import("./bench/render.mjs");
  const version = JSON.parse(readFileSync(join(REPO, "www", "node_modules", "@mediapipe", "tasks-vision", "package.json"), "utf8")).version;
  const r = await openRenderer();
  const t = await openBenchPage("face-page.html");
  mkdirSync(DIR, { recursive: true });
  try {
    for (const avatar of avatars) {
      await r.load(avatar);
      for (const clip of list) {
        if (!o.record && existsSync(recFile(avatar, clip))) continue;
        const t0 = Date.now();
        await r.clip(clip.id);
        // A new tracker per clip (VIDEO mode: timestamps from 0).
        await t.page.evaluate((a) => window.__face.start(a), { w: WIDTH, h: HEIGHT });
        const frames = [];
        for (let i = 0; i < clip.frames; i++) {
          const px = await r.frame(i);
          const timeMs = (i * 1000) / FPS;
          const f = await t.page.evaluate(([tm, b]) => window.__face.frame(tm, b), [timeMs, px.toString("base64")]);
          frames.push({ frame: i, timeMs, ...(f ?? {}) });
        }
        const out = { source: `${avatar}-vrm1.vrm ${clip.id} (eval/bench/face-motions.mjs)`, width: WIDTH, height: HEIGHT, fps: FPS, mediapipe: `@mediapipe/tasks-vision ${version} (face_landmarker.task)`, frames };
        writeFileSync(recFile(avatar, clip), JSON.stringify(out));
        console.error(`${avatar}-${clip.id}: ${frames.filter((f) => f.landmarks).length}/${clip.frames} frames with a face, ${((Date.now() - t0) / 1000).toFixed(0)} s`);
      }
    }
  } finally {
    await r.close();
    await t.close();
  }
  if (r.errors.length || t.errors.length) throw new Error(`page errors: ${[...r.errors, ...t.errors].join("; ")}`);
}

/**
 * The screenshot test's input (www/tests/face-shots.test.mjs): the woman's FaceLandmarker
 * blendshapes, matrices and the 20 landmarks the package reads (`MESH`) of face-still
 * (2 s: the neutral face the rig calibrates on) and of each shot's clip up to its frame.
 */
export const SHOTS = [
  { name: "blink", clip: "face-blink", frame: 19, expression: "blink" },
  { name: "aa", clip: "face-aa", frame: 24, expression: "aa" },
  { name: "ou", clip: "face-ou", frame: 24, expression: "ou" },
  { name: "smile", clip: "face-smile", frame: 30, expression: "happy" },
  { name: "look-left", clip: "face-look", frame: 30, lookYaw: 20 },
];
// The face-mesh landmarks the package reads beside the blendshapes (LAYOUT.faceMesh: the eyes'
// corners and lids, the inner lips, the mouth's corners, forehead, chin, cheeks).
const MESH = [33, 160, 158, 133, 153, 144, 263, 387, 385, 362, 380, 373, 13, 14, 61, 291, 10, 152, 234, 454];
function writeShots(file) {
  const frames = (clip, to) =>
    JSON.parse(readFileSync(recFile("woman", { id: clip }), "utf8")).frames.slice(0, to + 1).map((f) => ({
      timeMs: f.timeMs,
      blendshapes: f.blendshapes.map(([, v]) => v),
      matrix: f.matrix,
      mesh: MESH.map((k) => f.landmarks[k]),
    }));
  const names = JSON.parse(readFileSync(recFile("woman", { id: "face-still" }), "utf8")).frames[0].blendshapes.map(([n]) => n);
  const out = {
    note: "eval/face-bench.mjs --write-shots: FaceLandmarker on the bench's renders of woman-vrm1 (eval/bench/face-motions.mjs); blendshape scores in `names` order, matrices column-major, of the 478 landmarks only the 20 the package reads (`meshIndices`)",
    names,
    meshIndices: MESH,
    still: frames("face-still", 59),
    shots: SHOTS.map((s) => ({ ...s, frames: frames(s.clip, s.frame) })),
  };
  mkdirSync(join(file, ".."), { recursive: true });
  writeFileSync(file, JSON.stringify(out));
  console.error(`${file}: ${(JSON.stringify(out).length / 1e3).toFixed(0)} kB`);
}

const missing = avatars.flatMap((a) => FACE_CLIPS.filter((c) => !existsSync(recFile(a, c))));
if (o.record || missing.length) await record(FACE_CLIPS);
if (o["write-shots"]) {
  writeShots(join(REPO, "tests", "fixtures", "face", "bench-shots.json"));
  process.exit(0);
}

const pkgDir = o.pkg ?? join(REPO, "pkg");
const { HandRig } = await import(pathToFileURL(join(pkgDir, "index.mjs")).href);
const { Face } = createRequire(join(REPO, "eval", "package.json"))("kalidokit/dist/kalidokit.umd.js");

const DEG = 180 / Math.PI;
const qmul = (a, b) => [
  a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
  a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
  a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
  a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
];
/** Yaw (toward the avatar's left, +) and pitch (nod down, +) of a rotation: the turn of +Z. */
function yawPitch([x, y, z, w]) {
  const fx = 2 * (x * z + w * y);
  const fy = 2 * (y * z - w * x);
  const fz = 1 - 2 * (x * x + y * y);
  return [Math.atan2(fx, fz) * DEG, Math.atan2(-fy, Math.hypot(fx, fz)) * DEG];
}
/** The matrix's head direction as yaw, pitch (the avatar frame, un-mirrored), as eval/face.mjs. */
function matrixYawPitch(m) {
  const n = Math.hypot(m[8], m[9], m[10]);
  const fx = m[8] / n, fy = m[9] / n, fz = m[10] / n;
  return [Math.atan2(fx, fz) * DEG, Math.atan2(-fy, Math.hypot(fx, fz)) * DEG];
}
const PRESETS = ["happy", "angry", "sad", "relaxed", "surprised", "aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight"];

const runs = new Map();
/** Each frame of one avatar's clip: the truth, handrig's and Kalidokit's readings (cached). */
function run(avatar, clip) {
  const key = `${avatar}/${clip.id}`;
  if (!runs.has(key)) runs.set(key, runOnce(avatar, clip));
  return runs.get(key);
}
function runOnce(avatar, clip) {
  const rec = JSON.parse(readFileSync(recFile(avatar, clip), "utf8"));
  const rig = HandRig.fromVrm(readFileSync(join(REPO, "tests", "fixtures", "avatars", `${avatar}-vrm1.vrm`)), JSON.parse(o.options ?? "{}"));
  return rec.frames.map((f, i) => {
    const truth = faceFrame(clip, i);
    const t = truth.expressions;
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
    const hk = f.landmarks ? Face.solve(frame.faceLandmarks[0], { runtime: "mediapipe", imageSize: { width: rec.width, height: rec.height }, smoothBlink: false }) : null;
    return {
      tracked: !!f.landmarks,
      matrix: f.matrix ? matrixYawPitch(f.matrix) : null,
      truth: {
        left: Math.max(t.blink ?? 0, t.blinkLeft ?? 0),
        right: Math.max(t.blink ?? 0, t.blinkRight ?? 0),
        aa: t.aa ?? 0,
        mouth: (t.aa ?? 0) + (t.ou ?? 0) + (t.happy ?? 0),
        head: yawPitch(qmul(truth.bones.neck, truth.bones.head)),
        look: truth.lookAt[0],
        key: JSON.stringify([t, truth.lookAt, truth.head]),
      },
      handrig: {
        left: e.blink + e.blinkLeft,
        right: e.blink + e.blinkRight,
        aa: e.aa,
        head: yawPitch(qmul(r.bones.neck ?? [0, 0, 0, 1], r.bones.head ?? [0, 0, 0, 1])),
        look: r.lookAt?.yaw ?? 0,
        weights: PRESETS.map((n) => e[n]),
      },
      // Kalidokit: eye openness per side (its l and r are the image's sides seen un-mirrored:
      // taken as the avatar's left and right after the check below), mouth shapes, head degrees.
      kalidokit: hk && {
        left: 1 - hk.eye.l,
        right: 1 - hk.eye.r,
        aa: hk.mouth.shape.A,
        head: [hk.head.degrees.y, hk.head.degrees.x],
        look: hk.pupil.x,
        weights: [hk.mouth.shape.A, hk.mouth.shape.I, hk.mouth.shape.U, hk.mouth.shape.E, hk.mouth.shape.O, 1 - hk.eye.l, 1 - hk.eye.r],
      },
    };
  });
}

const pct = (xs, p) => {
  if (!xs.length) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(p * s.length))];
};
const mean = (xs) => (xs.length ? xs.reduce((a, b) => a + b, 0) / xs.length : NaN);
const share = (xs, pred) => (xs.length ? xs.filter(pred).length / xs.length : NaN);

function score(list, who) {
  const acc = { talkOpen: [], talkShut: [], frames: 0, tracked: 0, closed: [], closedBoth: [], closedWink: [], otherEye: [], open: [], shut: [], yaw: [], pitch: [], yawM: [], pitchM: [], yawRest: [], pitchRest: [], look: [], still: [], falseBlink: [], toClose: [], toOpen: [] };
  for (const avatar of list) {
    // The avatar's rest face as the solver reads it (mean head angles over face-still after its
    // first 10 frames): the rendered face at rest is not MediaPipe's canonical face at rest.
    const still = run(avatar, FACE_CLIPS.find((c) => c.id === "face-still")).slice(10).filter((r) => r[who]);
    const rest = [0, 1].map((c) => still.reduce((a, r) => a + r[who].head[c], 0) / still.length);
    for (const clip of FACE_CLIPS) {
      const res = run(avatar, clip);
      // Signs that are the solver's own convention (Kalidokit's sides and angles): each taken as
      // the one that agrees with the truth over the clip; handrig's are used as they come.
      const flip = (get) => {
        if (who === "handrig") return 1;
        let agree = 0;
        for (const r of res) if (r[who]) agree += Math.abs(get(r[who]) - get(r.truth)) - Math.abs(-get(r[who]) - get(r.truth));
        return agree <= 0 ? 1 : -1;
      };
      const sy = flip((s) => s.head[0]);
      // Against the matrix: each sign as the one that agrees with it (handrig's as they come).
      const flipM = (c) => {
        if (who === "handrig") return 1;
        let agree = 0;
        for (const r of res) if (r[who] && r.matrix) agree += Math.abs(r[who].head[c] - r.matrix[c]) - Math.abs(-r[who].head[c] - r.matrix[c]);
        return agree <= 0 ? 1 : -1;
      };
      const smy = flipM(0);
      const smp = flipM(1);
      const sp = flip((s) => s.head[1]);
      const sl = flip((s) => s.look);
      // Kalidokit's eye sides: swapped if that matches the truth better.
      let swap = false;
      if (who === "kalidokit") {
        let d = 0;
        for (const r of res) if (r[who]) d += Math.abs(r[who].left - r.truth.left) + Math.abs(r[who].right - r.truth.right) - Math.abs(r[who].right - r.truth.left) - Math.abs(r[who].left - r.truth.right);
        swap = d > 0;
      }
      const near = (k, d, pred) => {
        for (let j = Math.max(0, k - d); j <= Math.min(res.length - 1, k + d); j++) if (pred(res[j].truth)) return true;
        return false;
      };
      // Each closure of an eye in the truth (>= 0.8 from frame k): frames from k to the eye shown
      // closed (>= 0.5) within it; and from its opening (under 0.8) to the eye shown open (< 0.5).
      if (!clip.talk) {
        for (const side of ["left", "right"]) {
          const eye = (j) => res[j][who]?.[swap ? (side === "left" ? "right" : "left") : side];
          for (let k = 1; k < res.length; k++) {
            const was = res[k - 1].truth[side] >= 0.8;
            if (was === res[k].truth[side] >= 0.8) continue;
            let j = k;
            if (!was) {
              while (j < res.length && res[j].truth[side] >= 0.8 && !(eye(j) >= 0.5)) j++;
              acc.toClose.push(j < res.length && res[j].truth[side] >= 0.8 ? j - k : null);
            } else if (eye(k - 1) >= 0.5) {
              while (j < res.length && !(eye(j) < 0.5)) j++;
              acc.toOpen.push(j - k);
            }
          }
        }
      }
      for (let k = 0; k < res.length; k++) {
        const r = res[k];
        acc.frames++;
        const s = r[who];
        if (!s || !r.tracked) continue;
        acc.tracked++;
        // The talking clip: only its own rows (every frame: the truth's aa at least 0.8, or 0).
        if (clip.talk) {
          if (r.truth.aa >= 0.8) acc.talkOpen.push(s.aa);
          else if (r.truth.aa === 0) acc.talkShut.push(s.aa);
          continue;
        }
        const [L, R] = swap ? [s.right, s.left] : [s.left, s.right];
        for (const [eye, other, te, to] of [[L, R, r.truth.left, r.truth.right], [R, L, r.truth.right, r.truth.left]]) {
          if (te >= 0.8) {
            acc.closed.push(eye);
            if (to >= 0.8) acc.closedBoth.push(eye);
            if (to === 0) {
              acc.otherEye.push(other);
              acc.closedWink.push(eye);
            }
          }
        }
        if (!near(k, 2, (t) => t.left > 0 || t.right > 0)) acc.falseBlink.push(Math.max(L, R));
        if (r.truth.aa >= 0.8) acc.open.push(s.aa);
        else if (!near(k, 2, (t) => t.mouth > 0)) acc.shut.push(s.aa);
        acc.yaw.push(Math.abs(sy * s.head[0] - r.truth.head[0]));
        acc.pitch.push(Math.abs(sp * s.head[1] - r.truth.head[1]));
        if (r.matrix) {
          acc.yawM.push(Math.abs(smy * s.head[0] - r.matrix[0]));
          acc.pitchM.push(Math.abs(smp * s.head[1] - r.matrix[1]));
        }
        acc.yawRest.push(Math.abs(sy * (s.head[0] - rest[0]) - r.truth.head[0]));
        acc.pitchRest.push(Math.abs(sp * (s.head[1] - rest[1]) - r.truth.head[1]));
        if (Math.abs(r.truth.look) >= 20) acc.look.push(Math.sign(sl * s.look) === Math.sign(r.truth.look) ? 1 : 0);
        const prev = res[k - 1];
        let still = k >= 6;
        for (let j = k - 6; still && j < k; j++) if (res[j].truth.key !== r.truth.key) still = false;
        if (still && prev[who]) {
          const moves = s.weights.map((w, i) => Math.abs(w - prev[who].weights[i]));
          const m = Math.max(...moves);
          acc.still.push(m);
          if (process.env.FACE_STILL_TRACE && m > Number(process.env.FACE_STILL_TRACE)) {
            const i = moves.indexOf(m);
            const around = res.slice(Math.max(0, k - 8), k + 3).map((x) => x[who]?.weights[i].toFixed(3)).join(" ");
            console.error(`still move ${m.toFixed(3)}: ${who} ${avatar} ${clip.id} frame ${k} ${(who === "handrig" ? PRESETS : ["A", "I", "U", "E", "O", "eye.l", "eye.r"])[i]} (frames ${Math.max(0, k - 8)}..${k + 2}: ${around})`);
          }
        }
      }
    }
  }
  return {
    frames: acc.frames,
    tracked: acc.tracked,
    blinkRecall: share(acc.closed, (b) => b >= 0.5),
    closedFrames: acc.closed.length,
    blinkBothRecall: share(acc.closedBoth, (b) => b >= 0.5),
    closedBothFrames: acc.closedBoth.length,
    winkRecall: share(acc.closedWink, (b) => b >= 0.5),
    winkClosedFrames: acc.closedWink.length,
    winkOtherOpen: share(acc.otherEye, (b) => b < 0.5),
    winkFrames: acc.otherEye.length,
    falseBlinks: share(acc.falseBlink, (b) => b >= 0.5),
    openEyeFrames: acc.falseBlink.length,
    aaOpenMean: mean(acc.open),
    aaOpenAtLeast03: share(acc.open, (a) => a >= 0.3),
    openFrames: acc.open.length,
    aaShutAtMost01: share(acc.shut, (a) => a <= 0.1),
    talkOpenAtLeast03: share(acc.talkOpen, (a) => a >= 0.3),
    talkOpenFrames: acc.talkOpen.length,
    talkShutAtMost01: share(acc.talkShut, (a) => a <= 0.1),
    talkShutFrames: acc.talkShut.length,
    shutFrames: acc.shut.length,
    yawErrMean: mean(acc.yaw),
    yawErrP95: pct(acc.yaw, 0.95),
    yawErrMax: Math.max(...acc.yaw),
    pitchErrMean: mean(acc.pitch),
    pitchErrP95: pct(acc.pitch, 0.95),
    pitchErrMax: Math.max(...acc.pitch),
    yawMatrixMean: mean(acc.yawM),
    yawMatrixMax: Math.max(...acc.yawM),
    pitchMatrixMean: mean(acc.pitchM),
    pitchMatrixMax: Math.max(...acc.pitchM),
    yawRestMean: mean(acc.yawRest),
    yawRestP95: pct(acc.yawRest, 0.95),
    yawRestMax: Math.max(...acc.yawRest),
    pitchRestMean: mean(acc.pitchRest),
    pitchRestP95: pct(acc.pitchRest, 0.95),
    pitchRestMax: Math.max(...acc.pitchRest),
    lookSign: mean(acc.look),
    lookFrames: acc.look.length,
    stillFrames: acc.still.length,
    stillMoveP95: pct(acc.still, 0.95),
    stillMoveMax: Math.max(...acc.still),
    closures: acc.toClose.length,
    closuresRead: acc.toClose.filter((x) => x !== null).length,
    toCloseMean: mean(acc.toClose.filter((x) => x !== null)),
    toCloseMax: Math.max(...acc.toClose.filter((x) => x !== null)),
    openings: acc.toOpen.length,
    toOpenMean: mean(acc.toOpen),
    toOpenMax: Math.max(...acc.toOpen),
  };
}

const table = {};
for (const [half, list] of [["tune", TUNE], ["report", REPORT]]) {
  const l = list.filter((a) => avatars.includes(a));
  if (!l.length) continue;
  for (const who of ["handrig", "kalidokit"]) table[`${half} (${l.join(", ")})/${who}`] = score(l, who);
}
const f = (v, d = 2) => (Number.isNaN(v) ? "n/a" : v.toFixed(d));
const rows = [
  ["frames / with a face", (s) => `${s.frames} / ${s.tracked}`],
  ["blink recall (closed-eye frames, per eye)", (s) => `${f(s.blinkRecall)} (${s.closedFrames})`],
  ["of which both eyes closed (a blink)", (s) => `${f(s.blinkBothRecall)} (${s.closedBothFrames})`],
  ["of which one eye closed (a wink)", (s) => `${f(s.winkRecall)} (${s.winkClosedFrames})`],
  ["wink: the other eye stays open", (s) => `${f(s.winkOtherOpen)} (${s.winkFrames})`],
  ["closing: frames from the truth's (>= 0.8) to shown closed (>= 0.5): mean / max (closures read)", (s) => `${f(s.toCloseMean)} / ${s.toCloseMax} (${s.closuresRead} of ${s.closures})`],
  ["opening: frames from the truth's (< 0.8) to shown open (< 0.5): mean / max (openings)", (s) => `${f(s.toOpenMean)} / ${s.toOpenMax} (${s.openings})`],
  ["false blinks (share of open-eye frames)", (s) => `${f(s.falseBlinks, 3)} (${s.openEyeFrames})`],
  ["aa on open-mouth frames: mean / share >= 0.3", (s) => `${f(s.aaOpenMean)} / ${f(s.aaOpenAtLeast03)} (${s.openFrames})`],
  ["aa on closed-mouth frames: share <= 0.1", (s) => `${f(s.aaShutAtMost01)} (${s.shutFrames})`],
  ["talking (face-talk): aa >= 0.3 on open frames / <= 0.1 on closed ones", (s) => `${f(s.talkOpenAtLeast03)} (${s.talkOpenFrames}) / ${f(s.talkShutAtMost01)} (${s.talkShutFrames})`],
  ["head yaw vs matrix (deg): mean / max", (s) => `${f(s.yawMatrixMean, 1)} / ${f(s.yawMatrixMax, 1)}`],
  ["head pitch vs matrix (deg): mean / max", (s) => `${f(s.pitchMatrixMean, 1)} / ${f(s.pitchMatrixMax, 1)}`],
  ["head yaw vs truth (deg): mean / p95 / max", (s) => `${f(s.yawErrMean, 1)} / ${f(s.yawErrP95, 1)} / ${f(s.yawErrMax, 1)}`],
  ["head pitch vs truth (deg): mean / p95 / max", (s) => `${f(s.pitchErrMean, 1)} / ${f(s.pitchErrP95, 1)} / ${f(s.pitchErrMax, 1)}`],
  ["head yaw vs truth, from the rest reading (deg): mean / p95 / max", (s) => `${f(s.yawRestMean, 1)} / ${f(s.yawRestP95, 1)} / ${f(s.yawRestMax, 1)}`],
  ["head pitch vs truth, from the rest reading (deg): mean / p95 / max", (s) => `${f(s.pitchRestMean, 1)} / ${f(s.pitchRestP95, 1)} / ${f(s.pitchRestMax, 1)}`],
  ["look-at 20 deg aside: yaw's sign right", (s) => `${f(s.lookSign)} (${s.lookFrames})`],
  ["still stretches: weight move per frame p95 / max", (s) => `${f(s.stillMoveP95, 3)} / ${f(s.stillMoveMax, 3)} (${s.stillFrames})`],
];
const cols = Object.keys(table);
console.log(`| | ${cols.join(" | ")} |`);
console.log(`| --- | ${cols.map(() => "---").join(" | ")} |`);
for (const [name, fmt] of rows) console.log(`| ${name} | ${cols.map((c) => fmt(table[c])).join(" | ")} |`);
if (o.json) writeFileSync(o.json, JSON.stringify(table, null, 2));
