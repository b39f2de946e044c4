#!/usr/bin/env node
// Scores the bench (issue 47): the MediaPipe recordings of the rendered clips
// (eval/bench/clips/*-hands.json, *-holistic.json, made by track.mjs) solved by handrig (the
// built package in pkg/, default options and handStrategy "retarget") and by Kalidokit 1.1.5,
// and MediaPipe's own landmarks taken as they are ("MediaPipe raw"), each compared with the
// truth: the rotations motions.mjs gave the rendered avatar.
//
//   make pkg && npm ci --prefix eval && npm ci --prefix tests/node     # once
//   node eval/bench/score.mjs [--avatars woman,child] [--clips reach,fist,...] [--tracker legacy|tasks]
//        [--options JSON] [--json FILE] [--frames] [--no-kalidokit]
//
// --tracker tasks scores the Tasks API recordings (tasks.mjs, *-tasks.json) instead of the
// legacy Hands/Holistic ones; --options adds handrig options to every handrig rig.
//
// Every method is put on the same avatar the clip was rendered with (three-vrm, Node) and
// measured by forward kinematics of its normalized humanoid, so all figures are in that
// avatar's meters and degrees. Metrics (right hand; arms of both sides):
//
// * finger joint angle: per joint the angle between the two segments that meet there (wrist ->
//   MCP / MCP -> PIP for the MCP joint, ...; thumb CMC, MCP, IP), 15 joints; error = |method -
//   truth| in degrees. MediaPipe raw: the same angle between its landmark segments (world
//   landmarks for hand clips; image landmarks, x and z scaled by the width and y by the
//   height, for holistic's hands in body clips).
// * fingertip position in the palm frame (wrist origin; axes from wrist, index and little
//   MCP, as handrig::hand::palm_frame), mm; MediaPipe raw scaled by the ratio of the avatar's
//   wrist -> middle MCP length to MediaPipe's.
// * palm facing: angle between palm normals ((index MCP - wrist) x (little MCP - wrist)) in
//   the world, degrees; MediaPipe raw from its world landmarks mapped to the avatar's frame
//   (x, -y, -z: the camera looks along -Z at the avatar).
// * bone direction: upper arm, forearm and hand (wrist -> middle MCP) in the world, degrees;
//   MediaPipe raw from pose world landmarks (shoulder, elbow, wrist, mid index/pinky).
// * elbow and wrist positions relative to the shoulder joint, mm; MediaPipe raw scaled by the
//   ratio of the avatar's shoulder width (upper-arm joints) to MediaPipe's (landmarks 11-12).
//
// A fingertip is the distal joint plus 0.8 x the rest length of the segment before it, turned
// with the distal bone (the same rule for truth and solved poses).
// Frames scored: hand figures on frames where MediaPipe found the right hand (labelled "Left"
// on the un-mirrored render); arm figures where it found the pose. The same frames for every
// method. handrig is fed every frame in order (a rig keeps state between frames).

import { existsSync, readFileSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { PosedHumanoid, add, angle, cap, cross, dot, fromVrm0, len, loadSolvers, mid, norm, percentile, qrot, quatFromEulerXYZ, scale, sub, toAvatar } from "./scoring.mjs";
import { AVATARS, CLIP_DIR, REPO, avatarFile, recordingFile } from "./common.mjs";
import { CLIPS, clipPose } from "./motions.mjs";

const { values: o } = parseArgs({
  options: {
    avatars: { type: "string" }, clips: { type: "string" }, json: { type: "string" }, frames: { type: "boolean" }, pkg: { type: "string" },
    tracker: { type: "string", default: "legacy" },
    options: { type: "string", default: "{}" },
    "no-kalidokit": { type: "boolean" },
  },
});
if (!["legacy", "tasks"].includes(o.tracker)) throw new Error(`--tracker must be legacy or tasks, got ${o.tracker}`);
const started = performance.now();
// --options JSON: handrig options on top of the defaults for all its rigs (diagnostics; the
// published table uses the defaults).
const EXTRA = JSON.parse(o.options);
const { pkgDir, HandRig, restPoseFromVRM, applyToVRM, loadVrm, Kalidokit } = await loadSolvers({ pkg: o.pkg, noKalidokit: o["no-kalidokit"] });


// ---- the hand and arm model ----------------------------------------------------------------------
const FINGERS = ["thumb", "index", "middle", "ring", "little"];
const chainOf = (side, f) =>
  f === "thumb" ? ["Metacarpal", "Proximal", "Distal"].map((p) => `${side}Thumb${p}`) : ["Proximal", "Intermediate", "Distal"].map((p) => `${side}${cap(f)}${p}`);
const JOINT_NAMES = { thumb: ["CMC", "MCP", "IP"], other: ["MCP", "PIP", "DIP"] };
const jointName = (f, k) => `${f} ${(f === "thumb" ? JOINT_NAMES.thumb : JOINT_NAMES.other)[k]}`;
const LM = (f) => {
  const b = 1 + 4 * FINGERS.indexOf(f);
  return [b, b + 1, b + 2, b + 3];
};
const BONES = ["UpperArm", "LowerArm", "Hand"];

/** FK sampler over a loaded VRM's normalized humanoid. */
class Body extends PosedHumanoid {
  constructor(vrm) {
    super(vrm);
    this.reset();
    this.rest = this.positions();
  }
  /** The measured skeleton of the current pose (see the header). */
  sample() {
    const s = this.positions();
    const P = (n) => s[n].p;
    const out = { P, hand: {} };
    for (const side of ["right", "left"]) {
      const pts = { wrist: P(`${side}Hand`) };
      for (const f of FINGERS) {
        const c = chainOf(side, f);
        const restSeg = sub(this.rest[c[2]].p, this.rest[c[1]].p);
        const tip = add(P(c[2]), qrot(s[c[2]].q, scale(restSeg, 0.8)));
        pts[f] = [P(c[0]), P(c[1]), P(c[2]), tip];
      }
      out.hand[side] = pts;
    }
    return out;
  }
}

// Hand points from MediaPipe landmarks (any 21-point array of [x, y, z]).
function mpHand(lm) {
  const pts = { wrist: lm[0] };
  for (const f of FINGERS) pts[f] = LM(f).map((i) => lm[i]);
  return pts;
}
// The 15 joint angles of a hand, degrees.
function jointAngles(h) {
  const out = [];
  for (const f of FINGERS) {
    const pts = [h.wrist, ...h[f]];
    for (let k = 0; k < 3; k++) out.push(angle(sub(pts[k + 1], pts[k]), sub(pts[k + 2], pts[k + 1])));
  }
  return out;
}
// Palm frame (forward, radial, palmar) of handrig::hand::palm_frame, rows.
function palmFrame(h, side = "right") {
  const f = norm(sub(h.middle[0], h.wrist));
  const across = sub(h.index[0], h.little[0]);
  const r = norm(sub(across, scale(f, dot(across, f))));
  const n = side === "right" ? cross(r, f) : cross(f, r);
  return [f, r, n];
}
const palmNormal = (h) => norm(cross(sub(h.index[0], h.wrist), sub(h.little[0], h.wrist)));
const palmLength = (h) => len(sub(h.middle[0], h.wrist));
/** Fingertips (mm) in the palm frame, scaled by `k`. */
function tipsInPalm(h, k = 1) {
  const F = palmFrame(h);
  return FINGERS.map((f) => {
    const d = sub(h[f][3], h.wrist);
    return [dot(F[0], d), dot(F[1], d), dot(F[2], d)].map((x) => x * k * 1000);
  });
}
// Arm figures of one side from shoulder, elbow, wrist and hand-tip (middle MCP) points.
const armOf = (sh, el, wr, ht) => ({ sh, el, wr, ht });

// MediaPipe pose index of each side's shoulder, elbow, wrist, index, pinky (the subject's side).
const POSE = { right: [12, 14, 16, 20, 18], left: [11, 13, 15, 19, 17] };

/**
 * Ideal MediaPipe hand landmarks of the truth's right hand (hand clips): its joints and
 * fingertips as world landmarks (MediaPipe's axes: x, -y, -z of the avatar's; origin the
 * middle MCP) and image landmarks projected with the clip's camera (z: depth relative to the
 * wrist, in image widths), labelled "Left" as MediaPipe labels a right hand on an un-mirrored image.
 * handrig fed these checks the pipeline: what is left is the solver's own model error.
 */
function idealHand(h, cam, aspect) {
  const pts = [h.wrist];
  for (const f of FINGERS) pts.push(...h[f]);
  const origin = h.middle[0];
  const t = Math.tan((cam.fov * Math.PI) / 360);
  const [cx, cy, cz] = cam.position;
  const zw = h.wrist[2];
  const r6 = (v) => Math.round(v * 1e6) / 1e6;
  const landmarks = pts.map(([x, y, z]) => {
    const d = cz - z;
    return [0.5 + (x - cx) / (2 * d * t * aspect), 0.5 - (y - cy) / (2 * d * t), -(z - zw) / (2 * (cz - zw) * t * aspect)].map(r6);
  });
  return { handedness: "Left", score: 1, landmarks, worldLandmarks: pts.map((p) => toAvatar(sub(p, origin)).map(r6)) };
}

// ---- statistics --------------------------------------------------------------------------------
const METHODS = ["handrig", "retarget", "kalidokit", "mediapipe", "oracle"].filter((m) => m !== "kalidokit" || Kalidokit);
const METHOD_LABEL = {
  handrig: "handrig (defaults)", retarget: "handrig retarget", kalidokit: "Kalidokit 1.1.5", mediapipe: "MediaPipe raw",
  oracle: "handrig on ideal landmarks",
};

// ---- Kalidokit -------------------------------------------------------------------------------------
// Kalidokit mirrors (its RightUpperArm comes from MediaPipe's LEFT shoulder, as its demo shows a
// mirror image): it is fed the landmarks of the mirrored image (x flipped, left and right
// landmarks swapped), which is what MediaPipe gives on a mirrored frame, so that its "Right"
// bones are the avatar's right bones.
const POSE_SWAP = [0, 4, 5, 6, 1, 2, 3, 8, 7, 10, 9, 12, 11, 14, 13, 16, 15, 18, 17, 20, 19, 22, 21, 24, 23, 26, 25, 28, 27, 30, 29, 32, 31];
const mirrorPose = (lms, image) =>
  POSE_SWAP.map((j) => {
    const [x, y, z, v] = lms[j];
    return { x: image ? 1 - x : -x, y, z, visibility: v };
  });
const mirrorHand = (lms, image) => lms.map(([x, y, z]) => ({ x: image ? 1 - x : -x, y, z }));

function kalidokitFingers(handLms, image) {
  const solved = Kalidokit.Hand.solve(mirrorHand(handLms, image), "Right");
  const bones = {};
  for (const f of FINGERS) {
    const names0 = ["Proximal", "Intermediate", "Distal"]; // VRM 0.x thumb names = VRM 1.0's Metacarpal, Proximal, Distal
    const c = chainOf("right", f);
    for (let k = 0; k < 3; k++) bones[c[k]] = fromVrm0(quatFromEulerXYZ(solved[`Right${cap(f)}${names0[k]}`]));
  }
  return { bones, wrist: solved.RightWrist };
}
function kalidokitBody(frame, rec) {
  const p = frame.pose;
  const solved = Kalidokit.Pose.solve(mirrorPose(p.worldLandmarks, false), mirrorPose(p.landmarks, true), {
    runtime: "mediapipe",
    imageSize: { width: rec.width, height: rec.height },
    enableLegs: false,
  });
  const bones = {};
  for (const side of ["right", "left"]) {
    bones[`${side}UpperArm`] = fromVrm0(quatFromEulerXYZ(solved[`${cap(side)}UpperArm`]));
    bones[`${side}LowerArm`] = fromVrm0(quatFromEulerXYZ(solved[`${cap(side)}LowerArm`]));
  }
  // The example's hand: z from the pose, x and y from the hand solver's wrist; fingers from the hand solver.
  const label = { right: "Left", left: "Right" };
  for (const side of ["right", "left"]) {
    const hand = frame.hands?.find((h) => h.handedness === label[side]);
    const pose = solved[`${cap(side)}Hand`];
    if (side === "right" && hand) {
      const k = hand.worldLandmarks ? kalidokitFingers(hand.worldLandmarks, false) : kalidokitFingers(hand.landmarks, true);
      Object.assign(bones, k.bones);
      bones.rightHand = fromVrm0(quatFromEulerXYZ({ x: k.wrist.x, y: k.wrist.y, z: pose.z }));
    } else {
      bones[`${side}Hand`] = fromVrm0(quatFromEulerXYZ({ x: 0, y: 0, z: pose.z }));
    }
  }
  return bones;
}

// ---- one clip ------------------------------------------------------------------------------------
function newAcc() {
  const acc = {};
  for (const m of METHODS) {
    acc[m] = { joint: {}, jointAll: [], signed: [], bins: [[], [], [], []], tip: [], palm: [], dir: { UpperArm: [], LowerArm: [], Hand: [] }, pos: { elbow: [], wrist: [] } };
  }
  return acc;
}
const rightHandOf = (frame) => frame.hands?.find((h) => h.handedness === "Left");
/** The frame with its best-scoring hand labelled "Left" and no pose (see handsOnly). */
function relabelled(frame) {
  if (!frame.hands?.length) return { frame: frame.frame, timeMs: frame.timeMs, hands: [] };
  const best = frame.hands.reduce((a, b) => ((b.score ?? 0) > (a.score ?? 0) ? b : a));
  return { frame: frame.frame, timeMs: frame.timeMs, hands: [{ ...best, handedness: "Left" }] };
}

function scoreClip(body, restPose, clip, rec, acc, perFrame, cam) {
  // "hands" (hands only, world landmarks), "holistic" (pose; hands with image landmarks only) or
  // "tasks" (pose; hands with world landmarks).
  const mode = rec.mode;
  const aspect = rec.width / rec.height;
  const rigs = {
    handrig: new HandRig(restPose, EXTRA),
    retarget: new HandRig(restPose, { ...EXTRA, handStrategy: "retarget" }),
    oracle: clip.kind === "hand" ? new HandRig(restPose, EXTRA) : null,
  };
  const avatarShoulderWidth = len(sub(body.rest.leftUpperArm.p, body.rest.rightUpperArm.p));
  const det = { frames: rec.frames.length, hand: 0, handAny: 0, handMislabelled: 0, pose: 0 };
  const kept = { handrig: null, retarget: null, oracle: null };
  // Tasks API on the hand close-ups: the HandLandmarker labels the one (right) hand in view
  // "Right" in nearly every frame (the legacy Hands model "Left", correctly, in 85-100%), and the
  // PoseLandmarker reports a pose from the face and shoulder in view. To score the fingers, those
  // frames keep only the best-scoring hand, relabelled "Left", and no pose (as in hands mode);
  // the detection table counts the labels as MediaPipe gave them.
  const handsOnly = mode === "tasks" && clip.kind === "hand";
  rec.frames.forEach((original, i) => {
    const frame = handsOnly ? relabelled(original) : original;
    // Truth.
    body.reset();
    body.set(clipPose(clip, i));
    const truth = body.sample();
    // Self-check of the metric: MediaPipe-style landmarks made from the truth measure as the truth.
    {
      const ideal = idealHand(truth.hand.right, cam, aspect);
      const a = jointAngles(mpHand(ideal.worldLandmarks));
      const t = jointAngles(truth.hand.right);
      const palm = angle(palmNormal(mpHand(ideal.worldLandmarks.map(toAvatar))), palmNormal(truth.hand.right));
      const worst = Math.max(palm, ...a.map((x, k) => Math.abs(x - t[k])));
      selfCheck = Math.max(selfCheck, worst);
    }
    const mpRight = rightHandOf(frame);
    if (original.hands?.length) det.handAny++;
    if (rightHandOf(original)) det.hand++;
    else if (original.hands?.length) det.handMislabelled++;
    if (original.pose) det.pose++;
    const samples = {};
    // handrig: the user's loop (rig.solve -> applyToVRM on a persistent avatar pose).
    for (const m of ["handrig", "retarget", "oracle"]) {
      if (!rigs[m]) continue;
      body.reset();
      if (kept[m]) body.set(kept[m]);
      const input =
        m === "oracle"
          ? { timeMs: frame.timeMs, hands: [idealHand(truth.hand.right, cam, aspect)] }
          : mode === "hands" || handsOnly ? frame : { ...frame, imageAspect: aspect };
      const result = rigs[m].solve(input);
      applyToVRM(body.vrm, result);
      kept[m] = Object.fromEntries(body.names.map((n) => [n, body.h.getNormalizedBoneNode(n).quaternion.toArray()]));
      samples[m] = body.sample();
    }
    // Kalidokit.
    if (Kalidokit) {
      body.reset();
      if (frame.pose) {
        body.set(kalidokitBody(frame, rec));
      } else if ((mode === "hands" || handsOnly) && mpRight) {
        body.set(kalidokitFingers(mpRight.worldLandmarks, false).bones);
      }
      samples.kalidokit = body.sample();
    }

    const row = { frame: i, hand: !!mpRight, pose: !!frame.pose, err: {} };
    // Hand figures.
    if (mpRight) {
      const lms = mpRight.worldLandmarks ?? mpRight.landmarks.map(([x, y, z]) => [x * rec.width, y * rec.height, z * rec.width]);
      const mp = mpHand(lms);
      const tAngles = jointAngles(truth.hand.right);
      const tTips = tipsInPalm(truth.hand.right);
      const tNormal = palmNormal(truth.hand.right);
      for (const m of METHODS) {
        if (!samples[m] && m !== "mediapipe") continue;
        const h = m === "mediapipe" ? mp : samples[m].hand.right;
        const a = jointAngles(h);
        const errs = a.map((x, k) => Math.abs(x - tAngles[k]));
        errs.forEach((e, k) => {
          const name = jointName(FINGERS[Math.floor(k / 3)], k % 3);
          (acc[m].joint[name] ??= []).push(e);
        });
        acc[m].jointAll.push(...errs);
        a.forEach((x, k) => {
          acc[m].signed.push(x - tAngles[k]);
          acc[m].bins[Math.min(3, Math.floor(tAngles[k] / 30))].push(errs[k]);
        });
        const k = m === "mediapipe" ? palmLength(truth.hand.right) / palmLength(mp) : 1;
        const tips = tipsInPalm(h, k);
        acc[m].tip.push(...tips.map((t, j) => len(sub(t, tTips[j]))));
        // Palm facing needs the hand's world orientation: MediaPipe's world landmarks (hand
        // clips), the solvers' arm chains; not from holistic's image-only hand landmarks.
        let palmErr = null;
        if (m === "mediapipe") {
          if (mpRight.worldLandmarks) palmErr = angle(palmNormal(mpHand(mpRight.worldLandmarks.map(toAvatar))), tNormal);
        } else if (!(m === "kalidokit" && !frame.pose)) {
          palmErr = angle(palmNormal(h), tNormal);
        }
        if (palmErr !== null) acc[m].palm.push(palmErr);
        row.err[m] = { jointMedian: percentile(errs, 50), jointMax: Math.max(...errs), palm: palmErr };
      }
    }
    // Arm figures.
    if (frame.pose?.worldLandmarks) {
      const W = frame.pose.worldLandmarks.map(toAvatar);
      const mpShoulderWidth = len(sub(W[11], W[12]));
      for (const side of ["right", "left"]) {
        const tArm = armOf(...[`${side}UpperArm`, `${side}LowerArm`, `${side}Hand`, `${side}MiddleProximal`].map(truth.P));
        const [s, e, w, ix, px] = POSE[side];
        for (const m of METHODS) {
          if (!samples[m] && m !== "mediapipe") continue;
          let arm;
          let k = 1;
          if (m === "mediapipe") {
            arm = armOf(W[s], W[e], W[w], mid(W[ix], W[px]));
            k = avatarShoulderWidth / mpShoulderWidth;
          } else {
            arm = armOf(...[`${side}UpperArm`, `${side}LowerArm`, `${side}Hand`, `${side}MiddleProximal`].map(samples[m].P));
          }
          const upperErr = angle(sub(arm.el, arm.sh), sub(tArm.el, tArm.sh));
          acc[m].dir.UpperArm.push(upperErr);
          if (side === "right") (row.arm ??= {})[m] = { upper: upperErr, fore: angle(sub(arm.wr, arm.el), sub(tArm.wr, tArm.el)) };
          acc[m].dir.LowerArm.push(angle(sub(arm.wr, arm.el), sub(tArm.wr, tArm.el)));
          acc[m].dir.Hand.push(angle(sub(arm.ht, arm.wr), sub(tArm.ht, tArm.wr)));
          acc[m].pos.elbow.push(1000 * len(sub(scale(sub(arm.el, arm.sh), k), sub(tArm.el, tArm.sh))));
          acc[m].pos.wrist.push(1000 * len(sub(scale(sub(arm.wr, arm.sh), k), sub(tArm.wr, tArm.sh))));
        }
      }
    }
    perFrame?.push(row);
  });
  for (const r of Object.values(rigs)) r?.free();
  return det;
}

// ---- run -----------------------------------------------------------------------------------------
let selfCheck = 0;
const avatars = (o.avatars ?? AVATARS.join(",")).split(",");
const clips = o.clips ? CLIPS.filter((c) => o.clips.split(",").includes(c.id)) : CLIPS;
const groups = { hand: newAcc(), body: newAcc() };
const byClip = [];
const perFrame = {};
const cameras = JSON.parse(readFileSync(join(CLIP_DIR, "frames.json"), "utf8")).clips;
for (const avatar of avatars) {
  const vrm = await loadVrm(avatarFile(avatar));
  const restPose = restPoseFromVRM(vrm);
  const body = new Body(vrm);
  for (const clip of clips) {
    const file = recordingFile(avatar, clip, o.tracker);
    if (!existsSync(file)) {
      console.error(`${file} missing: run ${o.tracker === "tasks" ? "make bench-tasks (node eval/bench/tasks.mjs)" : "make bench-track (node eval/bench/track.mjs)"} first`);
      process.exit(1);
    }
    const rec = JSON.parse(readFileSync(file, "utf8"));
    if (rec.frames.length !== clip.frames) throw new Error(`${file}: ${rec.frames.length} frames, the clip has ${clip.frames}`);
    const acc = newAcc();
    const rows = [];
    const det = scoreClip(body, restPose, clip, rec, acc, rows, cameras[`${avatar}-${clip.id}`].camera);
    perFrame[`${avatar}-${clip.id}`] = rows;
    for (const m of METHODS) {
      const g = groups[clip.kind][m];
      for (const [j, v] of Object.entries(acc[m].joint)) (g.joint[j] ??= []).push(...v);
      g.jointAll.push(...acc[m].jointAll);
      g.signed.push(...acc[m].signed);
      acc[m].bins.forEach((b, k) => g.bins[k].push(...b));
      g.tip.push(...acc[m].tip);
      g.palm.push(...acc[m].palm);
      for (const b of BONES) g.dir[b].push(...acc[m].dir[b]);
      for (const p of ["elbow", "wrist"]) g.pos[p].push(...acc[m].pos[p]);
    }
    byClip.push({ avatar, clip: clip.id, kind: clip.kind, mode: rec.mode, det, acc });
  }
}

// ---- tables --------------------------------------------------------------------------------------
const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
const mp = (v) => (v.length ? `${f1(percentile(v, 50))} / ${f1(percentile(v, 95))}` : "-");
const pct = (a, b) => (b ? `${((100 * a) / b).toFixed(0)}%` : "-");
const out = [];
const line = (s = "") => out.push(s);

line("### Detection (MediaPipe on the renders)");
line();
line("| avatar | clip | kind | MediaPipe | frames | right hand (label Left) | a hand, other label only | pose |");
line("| --- | --- | --- | --- | ---: | ---: | ---: | ---: |");
for (const c of byClip) {
  line(`| ${c.avatar} | ${c.clip} | ${c.kind} | ${c.mode} | ${c.det.frames} | ${pct(c.det.hand, c.det.frames)} | ${c.det.handMislabelled} | ${c.mode === "hands" ? "-" : pct(c.det.pose, c.det.frames)} |`);
}
line();
// "handrig on ideal landmarks" exists for hand clips only.
const methodsOf = (kind) => (kind === "hand" ? METHODS : METHODS.filter((m) => m !== "oracle"));
for (const kind of ["hand", "body"]) {
  const METHODS = methodsOf(kind);
  const header = `| figure | ${METHODS.map((m) => METHOD_LABEL[m]).join(" | ")} |`;
  const sep = `| --- | ${METHODS.map(() => "---:").join(" | ")} |`;
  const g = groups[kind];
  const n = byClip.filter((c) => c.kind === kind);
  if (!n.length) continue;
  line(`### ${kind === "hand" ? "Hand clips" : "Body clips"} (${[...new Set(n.map((c) => c.clip))].join(", ")}; ${[...new Set(n.map((c) => c.avatar))].join(", ")}), median / p95`);
  line();
  line(header);
  line(sep);
  line(`| finger joint angle error, all 15 joints (deg) | ${METHODS.map((m) => mp(g[m].jointAll)).join(" | ")} |`);
  for (const f of FINGERS) {
    const v = (m) => FINGERS.includes(f) ? [0, 1, 2].flatMap((k) => g[m].joint[jointName(f, k)] ?? []) : [];
    line(`| &nbsp; ${f} (3 joints) | ${METHODS.map((m) => mp(v(m))).join(" | ")} |`);
  }
  for (const j of ["MCP", "PIP", "DIP"]) {
    const v = (m) => ["index", "middle", "ring", "little"].flatMap((f) => g[m].joint[`${f} ${j}`] ?? []);
    line(`| &nbsp; ${j}, four fingers | ${METHODS.map((m) => mp(v(m))).join(" | ")} |`);
  }
  line(`| joint angle, method - truth (deg): median [p5, p95] | ${METHODS.map((m) => (g[m].signed.length ? `${f1(percentile(g[m].signed, 50))} [${f1(percentile(g[m].signed, 5))}, ${f1(percentile(g[m].signed, 95))}]` : "-")).join(" | ")} |`);
  ["0-30", "30-60", "60-90", "90+"].forEach((b, k) => {
    line(`| &nbsp; error where the true angle is ${b} deg (${g.mediapipe.bins[k].length} joint-frames) | ${METHODS.map((m) => mp(g[m].bins[k])).join(" | ")} |`);
  });
  line(`| fingertip position in the palm frame (mm) | ${METHODS.map((m) => mp(g[m].tip)).join(" | ")} |`);
  line(`| palm facing (deg) | ${METHODS.map((m) => mp(g[m].palm)).join(" | ")} |`);
  if (kind === "body") {
    for (const b of BONES) line(`| ${{ UpperArm: "upper arm", LowerArm: "forearm", Hand: "hand" }[b]} direction (deg) | ${METHODS.map((m) => mp(g[m].dir[b])).join(" | ")} |`);
    line(`| elbow position from the shoulder (mm) | ${METHODS.map((m) => mp(g[m].pos.elbow)).join(" | ")} |`);
    line(`| wrist position from the shoulder (mm) | ${METHODS.map((m) => mp(g[m].pos.wrist)).join(" | ")} |`);
  }
  line();
}
line("### Finger joint angle error per clip (deg, median / p95)");
line();
line(`| avatar | clip | frames | ${METHODS.map((m) => METHOD_LABEL[m]).join(" | ")} |`);
line(`| --- | --- | ---: | ${METHODS.map(() => "---:").join(" | ")} |`);
for (const c of byClip) line(`| ${c.avatar} | ${c.clip} | ${c.det.hand} | ${METHODS.map((m) => mp(c.acc[m].jointAll)).join(" | ")} |`);
line();
line("### Arm figures per body clip (median / p95): forearm direction (deg), wrist position (mm)");
line();
line(`| avatar | clip | frames | ${methodsOf("body").map((m) => METHOD_LABEL[m]).join(" | ")} |`);
line(`| --- | --- | ---: | ${methodsOf("body").map(() => "---:").join(" | ")} |`);
for (const c of byClip.filter((x) => x.kind === "body")) {
  line(`| ${c.avatar} | ${c.clip} | ${c.det.pose} | ${methodsOf("body").map((m) => `${mp(c.acc[m].dir.LowerArm)}; ${mp(c.acc[m].pos.wrist)}`).join(" | ")} |`);
}
line();
if (!(selfCheck < 0.05)) {
  console.error(`metric self-check failed: landmarks made from the truth measure ${selfCheck} deg from it`);
  process.exit(1);
}
line(`metric self-check (truth-made landmarks vs truth, joint angles and palm normal): max ${selfCheck.toExponential(1)} deg`);
const seconds = (performance.now() - started) / 1000;
line(`(score.mjs: ${byClip.length} recordings, ${seconds.toFixed(1)} s)`);
console.log(out.join("\n"));
if (o.json) {
  const strip = (acc) => Object.fromEntries(METHODS.map((m) => [m, { jointAll: acc[m].jointAll.length, palm: acc[m].palm.length }]));
  const st = (v) => ({ n: v.length, median: percentile(v, 50), p95: percentile(v, 95) });
  const summary = {};
  for (const [kind, g] of Object.entries(groups)) {
    summary[kind] = Object.fromEntries(
      METHODS.map((m) => [m, { joint: st(g[m].jointAll), tip: st(g[m].tip), palm: st(g[m].palm), forearm: st(g[m].dir.LowerArm), wrist: st(g[m].pos.wrist) }]),
    );
  }
  writeFileSync(o.json, JSON.stringify({ tracker: o.tracker, selfCheck, summary, byClip: byClip.map((c) => ({ ...c, acc: strip(c.acc) })), perFrame }, null, 1));
}
if (o.frames) {
  for (const [name, rows] of Object.entries(perFrame)) {
    for (const r of rows) {
      if (!r.hand) continue;
      console.log(`${name} ${r.frame} ${METHODS.map((m) => `${m} ${f1(r.err[m]?.jointMedian)}/${f1(r.err[m]?.jointMax)} palm ${f1(r.err[m]?.palm)}`).join("  ")}`);
    }
  }
}
