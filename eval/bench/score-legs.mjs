#!/usr/bin/env node
// Scores the bench's leg clips (issue 51): the Tasks API PoseLandmarker's tracking of the
// rendered whole-body clips (eval/bench/clips/AVATAR-CLIP-tasks.json, made by
// `node eval/bench/tasks.mjs --legs`) solved by handrig (the built package in pkg/) and by
// Kalidokit 1.1.5's Pose.solve with its legs, each put on the avatar the clip was rendered
// with and compared with the truth (motions.mjs legClipPose: the rotations and hips offset the
// rendered avatar had).
//
//   make pkg && npm ci --prefix eval        # once
//   node eval/bench/score-legs.mjs [--avatars woman,man,child,primitive] [--clips walk,...]
//        [--options JSON] [--json FILE] [--frames] [--no-kalidokit]
//
// Methods:
// * handrig (defaults): rig.solve on every frame in order, applyToVRM (bones and the hips'
//   position, root motion).
// * handrig, as tracked: `legs: { moveHips: false, plant: false }` (the hips fixed, no
//   planted feet): the legs as the landmarks give them.
// * Kalidokit 1.1.5: Pose.solve(world, image, { enableLegs: true }) on the mirrored landmarks
//   (as score.mjs does for the arms, so that its Right* bones are the avatar's right), its
//   Hips.rotation, UpperLeg and LowerLeg rotations (VRM 0.x frame turned to VRM 1.0) applied
//   as given, no smoothing; it has no foot, so the feet follow the shins; its Hips.position is
//   not in meters (an image-space cue; its demo adds 1 to y), so the hips stay at rest.
// * MediaPipe raw (knee and ankle from the hip and the knee angle only): the pose world
//   landmarks (x, -y, -z), each leg scaled to the avatar's leg length.
//
// Figures, per avatar and clip, over the frames where MediaPipe found a pose (both legs):
// * knee / ankle position (mm): the joint from the same side's hip joint, in world axes,
//   against the truth's;
// * knee / ankle in the room (mm): absolute positions (root motion included), handrig only
//   moves the hips;
// * knee angle (deg): |method - truth| of the angle between thigh and shin;
// * sliding (mm per stance frame): the method's ankle displacement (3D, in the room) between
//   consecutive frames on which the truth's foot stands (its ankle still within 0.5 mm and its
//   sole on the floor);
// * under the floor: frames with a sole point (heel under the foot joint, ball under the toes
//   joint, carried by the bones) more than 2 cm under y = 0;
// * floating: frames on which a standing foot of the truth has its lowest sole point more than
//   2 cm above the floor;
// * knee backwards: frames with a knee bent more than 10 degrees whose knee lies behind its
//   hip-ankle line (against the hips' forward).
//
// LEGS_DEBUG=FRAME prints each method's hip joints, knees and ankles (from the hip, mm) on that
// frame of every clip to stderr (diagnostics).

import { existsSync, readFileSync, writeFileSync } from "node:fs";
import { join } from "node:path";
import { parseArgs } from "node:util";
import { add, len, loadSolvers, mid, scale, sub, toAvatar } from "./scoring.mjs";
import { Body, SIDES, bentBackwards, kalidokitLegs, kneeAngleOf, mean, percentile } from "./legs-scoring.mjs";
import { LEG_AVATARS, avatarFile, recordingFile } from "./common.mjs";
import { LEG_CLIPS, PITCHED_LEG_CLIPS, legClipPose } from "./motions.mjs";

const { values: o } = parseArgs({
  options: {
    avatars: { type: "string" }, clips: { type: "string" }, json: { type: "string" }, frames: { type: "boolean" }, pkg: { type: "string" },
    options: { type: "string", default: "{}" }, pitched: { type: "boolean" },
    "no-kalidokit": { type: "boolean" },
  },
});
const started = performance.now();
const EXTRA = JSON.parse(o.options);
const { pkgDir, HandRig, restPoseFromVRM, applyToVRM, loadVrm, Kalidokit } = await loadSolvers({ pkg: o.pkg, noKalidokit: o["no-kalidokit"] });

// MediaPipe pose indices of each side's hip, knee, ankle (the subject's side).
const MP_LEG = { left: [23, 25, 27], right: [24, 26, 28] };

// ---- statistics --------------------------------------------------------------------------------
const METHODS = ["handrig", "tracked", "kalidokit", "mediapipe"].filter((m) => m !== "kalidokit" || Kalidokit);
const LABEL = { handrig: "handrig (defaults)", tracked: "handrig, as tracked", kalidokit: "Kalidokit 1.1.5", mediapipe: "MediaPipe raw" };
const SOLVERS = METHODS.filter((m) => m !== "mediapipe");
const newAcc = () => Object.fromEntries(METHODS.map((m) => [m, { knee: [], ankle: [], kneeRoom: [], ankleRoom: [], kneeAngle: [], slide: [], hipsRoom: [], travel: 0, truthTravel: 0, under: 0, float: 0, backwards: 0, frames: 0 }]));
function merge(into, acc) {
  for (const m of METHODS) {
    for (const k of ["knee", "ankle", "kneeRoom", "ankleRoom", "kneeAngle", "slide", "hipsRoom"]) into[m][k].push(...acc[m][k]);
    for (const k of ["under", "float", "backwards", "frames", "travel", "truthTravel"]) into[m][k] += acc[m][k];
  }
}

// ---- one clip ------------------------------------------------------------------------------------
const TRACE = {};
function scoreClip(body, restPose, clip, rec, acc, rows) {
  const aspect = rec.width / rec.height;
  const rigs = { handrig: new HandRig(restPose, EXTRA), tracked: new HandRig(restPose, { ...EXTRA, legs: { ...(EXTRA.legs ?? {}), moveHips: false, plant: false } }) };
  const kept = {};
  const prev = {};
  const det = { frames: rec.frames.length, pose: 0 };
  let selfCheck = 0;
  rec.frames.forEach((frame, i) => {
    // The truth.
    const t = legClipPose(clip, i, body.rest);
    body.reset();
    body.set(t.bones, t.hipsOffset);
    const truth = body.sample();
    for (const side of SIDES) {
      selfCheck = Math.max(selfCheck, len(sub(truth[side].knee, t.points[`${side}Knee`])), len(sub(truth[side].ankle, t.points[`${side}Ankle`])));
    }
    const samples = {};
    for (const m of ["handrig", "tracked"]) {
      body.reset();
      if (kept[m]) body.restore(kept[m]);
      const res = rigs[m].solve({ ...frame, imageAspect: aspect });
      if (m === "handrig") TRACE.res = { off: res.hipsOffset && [...res.hipsOffset], planted: res.feetPlanted && `${+res.feetPlanted.left}${+res.feetPlanted.right}` };
      applyToVRM(body.vrm, res);
      kept[m] = body.save();
      samples[m] = body.sample();
    }
    if (Kalidokit) {
      body.reset();
      if (frame.pose) body.set(kalidokitLegs(Kalidokit, frame.pose, rec));
      samples.kalidokit = body.sample();
    }
    if (!frame.pose?.worldLandmarks) {
      for (const m of SOLVERS) prev[m] = null;
      rows.push({ frame: i, pose: false });
      return;
    }
    det.pose++;
    // MediaPipe raw: each leg from its hip joint, scaled to the avatar's leg length.
    const W = frame.pose.worldLandmarks.map(toAvatar);
    const mp = {};
    for (const side of SIDES) {
      const [h, k, a] = MP_LEG[side];
      const tl = truth[side];
      const avatarLeg = len(sub(body.restFull[`${side}LowerLeg`].p, body.restFull[`${side}UpperLeg`].p)) + len(sub(body.restFull[`${side}Foot`].p, body.restFull[`${side}LowerLeg`].p));
      const s = avatarLeg / (len(sub(W[k], W[h])) + len(sub(W[a], W[k])));
      mp[side] = { hip: tl.hip, knee: add(tl.hip, scale(sub(W[k], W[h]), s)), ankle: add(tl.hip, scale(sub(W[a], W[h]), s)) };
    }
    samples.mediapipe = mp;
    if (process.env.LEGS_DEBUG && Number(process.env.LEGS_DEBUG) === i) {
      const r3 = (v) => v.map((x) => (1000 * x).toFixed(0)).join(",");
      for (const m of ["truth", ...METHODS]) {
        const x = m === "truth" ? truth : samples[m];
        console.error(m, SIDES.map((sd) => `${sd} hip ${r3(x[sd].hip)} knee-hip ${r3(sub(x[sd].knee, x[sd].hip))} ankle-hip ${r3(sub(x[sd].ankle, x[sd].hip))}`).join(" | "), x.forward ? `fwd ${x.forward.map((v) => v.toFixed(2))}` : "");
      }
    }
    const row = { frame: i, pose: true, err: {} };
    for (const m of METHODS) {
      const a = acc[m];
      const r = (row.err[m] = {});
      a.frames++;
      let under = false;
      let float = false;
      let backwards = false;
      if (m !== "mediapipe") {
        // The hips (the hip joints' midpoint) in the room, and their travel across (x and z)
        // since the last frame, the method's and the truth's.
        const hips = (x) => mid(x.left.hip, x.right.hip);
        a.hipsRoom.push(1000 * len(sub(hips(samples[m]), hips(truth))));
        if (prev[m] && prev.truth) {
          const across = (v) => 1000 * Math.hypot(v[0], v[2]);
          a.travel += across(sub(hips(samples[m]), hips(prev[m])));
          a.truthTravel += across(sub(hips(truth), hips(prev.truth)));
        }
      }
      for (const side of SIDES) {
        const l = samples[m][side];
        const tl = truth[side];
        const ek = 1000 * len(sub(sub(l.knee, l.hip), sub(tl.knee, tl.hip)));
        const ea = 1000 * len(sub(sub(l.ankle, l.hip), sub(tl.ankle, tl.hip)));
        const eAngle = Math.abs(kneeAngleOf(l) - kneeAngleOf(tl));
        a.knee.push(ek);
        a.ankle.push(ea);
        a.kneeAngle.push(eAngle);
        r[side] = { knee: ek, ankle: ea, kneeAngle: eAngle };
        if (o.json) {
          // Per frame, for the diagnostics: the knee's and ankle's error vectors (mm, from the hip,
          // world axes) and the truth's ankle height (mm) and knee angle (deg).
          const v = (x) => x.map((c) => Math.round(1000 * c));
          Object.assign(r[side], { kv: v(sub(sub(l.knee, l.hip), sub(tl.knee, tl.hip))), av: v(sub(sub(l.ankle, l.hip), sub(tl.ankle, tl.hip))), tAnkleY: Math.round(1000 * tl.ankle[1]), tAngle: Math.round(kneeAngleOf(tl)) });
        }
        if (m === "mediapipe") continue;
        a.kneeRoom.push(1000 * len(sub(l.knee, tl.knee)));
        a.ankleRoom.push(1000 * len(sub(l.ankle, tl.ankle)));
        if (l.soles.some((p) => p[1] < -0.02)) under = true;
        if (bentBackwards(l, samples[m].forward)) backwards = true;
        // Standing: the truth's ankle still since the last frame and its sole on the floor.
        const tPrev = prev.truth?.[side];
        const standing = tPrev && len(sub(tl.ankle, tPrev.ankle)) < 5e-4 && Math.min(...tl.soles.map((p) => p[1])) < 0.01;
        if (standing) {
          const lPrev = prev[m]?.[side];
          if (lPrev) {
            const sl = 1000 * len(sub(l.ankle, lPrev.ankle));
            a.slide.push(sl);
            r[side].slide = sl;
          }
          if (Math.min(...l.soles.map((p) => p[1])) > 0.02) float = true;
        }
      }
      if (under) a.under++;
      if (float) a.float++;
      if (backwards) a.backwards++;
      Object.assign(r, { under, float, backwards });
    }
    if (process.env.LEGS_TRACE) {
      const r3 = (v) => v.map((x) => (1000 * x).toFixed(0)).join(",");
      const dist = (x, sd) => (1000 * len(sub(x[sd].ankle, x[sd].hip))).toFixed(0);
      console.error(`${clip.id} ${i} toff ${r3(t.hipsOffset)} off ${TRACE.res.off ? r3(TRACE.res.off) : "-"} planted ${TRACE.res.planted} ` + SIDES.map((sd) => `${sd[0]}: d ${dist(truth, sd)}/${dist(samples.handrig, sd)}/${dist(samples.tracked, sd)} k ${row.err.handrig[sd].knee.toFixed(0)}/${row.err.tracked[sd].knee.toFixed(0)} ankleY ${(1000 * truth[sd].ankle[1]).toFixed(0)}/${(1000 * samples.handrig[sd].ankle[1]).toFixed(0)} sole ${(1000 * Math.min(...samples.handrig[sd].soles.map((p) => p[1]))).toFixed(0)} dA ${r3(sub(sub(samples.handrig[sd].ankle, samples.handrig[sd].hip), sub(samples.tracked[sd].ankle, samples.tracked[sd].hip)))} dK ${r3(sub(sub(samples.handrig[sd].knee, samples.handrig[sd].hip), sub(samples.tracked[sd].knee, samples.tracked[sd].hip)))} tK ${r3(sub(sub(samples.tracked[sd].knee, samples.tracked[sd].hip), sub(truth[sd].knee, truth[sd].hip)))}`).join(" "));
    }
    for (const m of SOLVERS) prev[m] = samples[m];
    prev.truth = truth;
    rows.push(row);
  });
  for (const r of Object.values(rigs)) r.free();
  return { det, selfCheck };
}

// ---- run -----------------------------------------------------------------------------------------
const avatars = (o.avatars ?? LEG_AVATARS.join(",")).split(",");
const ALL_LEG = o.pitched ? PITCHED_LEG_CLIPS : LEG_CLIPS;
const clips = o.clips ? ALL_LEG.filter((c) => o.clips.split(",").includes(c.id)) : ALL_LEG;
const byClip = [];
const perFrame = {};
let selfCheck = 0;
for (const avatar of avatars) {
  const vrm = await loadVrm(avatarFile(avatar));
  const restPose = restPoseFromVRM(vrm);
  const body = new Body(vrm);
  for (const clip of clips) {
    const file = recordingFile(avatar, clip, "tasks");
    if (!existsSync(file)) {
      console.error(`${file} missing: run node eval/bench/render.mjs --legs and node eval/bench/tasks.mjs --legs (make eval-bench-legs)`);
      process.exit(1);
    }
    const rec = JSON.parse(readFileSync(file, "utf8"));
    if (rec.frames.length !== clip.frames) throw new Error(`${file}: ${rec.frames.length} frames, the clip has ${clip.frames}`);
    const acc = newAcc();
    const rows = [];
    const r = scoreClip(body, restPose, clip, rec, acc, rows);
    selfCheck = Math.max(selfCheck, r.selfCheck);
    perFrame[`${avatar}-${clip.id}`] = rows;
    byClip.push({ avatar, clip: clip.id, det: r.det, acc });
  }
}
if (!(selfCheck < 1e-4)) {
  console.error(`truth self-check failed: the avatar's FK is ${selfCheck} m from legClipPose's knees and ankles`);
  process.exit(1);
}

// ---- tables --------------------------------------------------------------------------------------
const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
const f2 = (x) => (Number.isFinite(x) ? x.toFixed(2) : "-");
const mp = (v) => (v.length ? `${f1(percentile(v, 50))} / ${f1(percentile(v, 95))}` : "-");
const out = [];
const line = (s = "") => out.push(s);
const FIGURES = [
  ["knee from the hip (mm)", (a) => mp(a.knee)],
  ["ankle from the hip (mm)", (a) => mp(a.ankle)],
  ["knee angle (deg)", (a) => mp(a.kneeAngle)],
  ["knee in the room (mm)", (a, m) => (m === "mediapipe" ? "-" : mp(a.kneeRoom))],
  ["ankle in the room (mm)", (a, m) => (m === "mediapipe" ? "-" : mp(a.ankleRoom))],
  ["hips in the room (mm)", (a, m) => (m === "mediapipe" ? "-" : mp(a.hipsRoom))],
  ["hips' travel across, mm (the truth's)", (a, m) => (m === "mediapipe" ? "-" : `${a.travel.toFixed(0)} (${a.truthTravel.toFixed(0)})`)],
  ["sliding, mm per stance frame (mean / p95 / max)", (a, m) => (m === "mediapipe" ? "-" : `${f2(mean(a.slide))} / ${f1(percentile(a.slide, 95))} / ${f1(Math.max(...a.slide))}`)],
  ["frames with a sole > 2 cm under the floor", (a, m) => (m === "mediapipe" ? "-" : `${a.under} of ${a.frames}`)],
  ["frames with a standing foot > 2 cm above the floor", (a, m) => (m === "mediapipe" ? "-" : `${a.float} of ${a.frames}`)],
  ["frames with a knee bent backwards", (a, m) => (m === "mediapipe" ? "-" : `${a.backwards} of ${a.frames}`)],
];
function table(title, acc) {
  line(`#### ${title}`);
  line();
  line(`| figure (median / p95 unless said) | ${METHODS.map((m) => LABEL[m]).join(" | ")} |`);
  line(`| --- | ${METHODS.map(() => "---:").join(" | ")} |`);
  for (const [name, f] of FIGURES) line(`| ${name} | ${METHODS.map((m) => f(acc[m], m)).join(" | ")} |`);
  line();
}
line("### Detection (the PoseLandmarker on the renders)");
line();
line("| avatar | clip | frames | pose |");
line("| --- | --- | ---: | ---: |");
for (const c of byClip) line(`| ${c.avatar} | ${c.clip} | ${c.det.frames} | ${c.det.pose} |`);
line();
const groupAcc = (pred) => {
  const a = newAcc();
  for (const c of byClip.filter(pred)) merge(a, c.acc);
  return a;
};
const tune = avatars.includes("woman") ? ["woman"] : [];
const report = avatars.filter((a) => !tune.includes(a));
if (tune.length) table(`Tune avatar (${tune.join(", ")}), all clips (${clips.map((c) => c.id).join(", ")})`, groupAcc((c) => tune.includes(c.avatar)));
if (report.length) table(`Report avatars (${report.join(", ")}), all clips`, groupAcc((c) => report.includes(c.avatar)));
const groups = {};
for (const clip of clips) {
  groups[clip.id] = groupAcc((c) => c.clip === clip.id && report.includes(c.avatar));
  if (report.length) table(`${clip.id}, report avatars (${report.join(", ")})`, groups[clip.id]);
}
line("#### Per avatar and clip: knee / ankle from the hip (mm, median), knee angle (deg, median), sliding (mm per stance frame, mean), frames under the floor, knee backwards");
line();
line(`| avatar | clip | ${SOLVERS.map((m) => LABEL[m]).join(" | ")} |`);
line(`| --- | --- | ${SOLVERS.map(() => "---").join(" | ")} |`);
for (const c of byClip) {
  line(`| ${c.avatar} | ${c.clip} | ${SOLVERS.map((m) => {
    const a = c.acc[m];
    return `${f1(percentile(a.knee, 50))} / ${f1(percentile(a.ankle, 50))}; ${f1(percentile(a.kneeAngle, 50))}; ${f2(mean(a.slide))}; ${a.under}; ${a.backwards}`;
  }).join(" | ")} |`);
}
line();
// The issue's goals on the report avatars.
const rep = groupAcc((c) => report.includes(c.avatar));
if (report.length && Kalidokit) {
  const ratio = (k) => percentile(rep.handrig[k], 50) / percentile(rep.kalidokit[k], 50);
  line(`goals (report avatars): knee error ${f2(ratio("knee"))} x Kalidokit's median, ankle ${f2(ratio("ankle"))} x (goal <= 0.70); `
    + `sliding ${f2(mean(rep.handrig.slide))} mm per stance frame (goal <= 2); ${rep.handrig.under} frames under the floor (goal 0); `
    + `${rep.handrig.backwards} with a knee backwards (goal 0)`);
}
line(`truth self-check (the avatar's FK against legClipPose's knees and ankles): max ${selfCheck.toExponential(1)} m`);
line(`(score-legs.mjs: ${byClip.length} recordings, ${((performance.now() - started) / 1000).toFixed(1)} s)`);
console.log(out.join("\n"));
if (o.json) {
  const st = (v) => ({ n: v.length, median: percentile(v, 50), p95: percentile(v, 95), mean: mean(v) });
  const sum = (a) => Object.fromEntries(METHODS.map((m) => [m, {
    knee: st(a[m].knee), ankle: st(a[m].ankle), kneeAngle: st(a[m].kneeAngle), kneeRoom: st(a[m].kneeRoom), ankleRoom: st(a[m].ankleRoom),
    slide: st(a[m].slide), under: a[m].under, float: a[m].float, backwards: a[m].backwards, frames: a[m].frames,
  }]));
  writeFileSync(o.json, JSON.stringify({
    selfCheck,
    tune: tune.length ? sum(groupAcc((c) => tune.includes(c.avatar))) : null,
    report: report.length ? sum(rep) : null,
    byClip: byClip.map((c) => ({ avatar: c.avatar, clip: c.clip, det: c.det, summary: sum(c.acc) })),
    perFrame,
  }, null, 1));
}
if (o.frames) {
  for (const [name, rows] of Object.entries(perFrame)) {
    for (const r of rows) {
      if (!r.pose) continue;
      console.log(`${name} ${r.frame} ${SOLVERS.map((m) => `${m} ${SIDES.map((s) => `${s[0]} k${f1(r.err[m][s].knee)} a${f1(r.err[m][s].ankle)} ang${f1(r.err[m][s].kneeAngle)}${r.err[m][s].slide !== undefined ? ` sl${f1(r.err[m][s].slide)}` : ""}`).join(" ")}${r.err[m].under ? " UNDER" : ""}${r.err[m].backwards ? " BACK" : ""}`).join("  ")}`);
    }
  }
}
