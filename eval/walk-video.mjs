#!/usr/bin/env node
// Real video of people walking (issue 51): OpenCV's sample clip vtest.avi (768x576, 10 fps, 795
// frames; a fixed camera looking down on a campus path, people 60-120 px tall walking across
// it; the PETS 2009 sequence as OpenCV's samples distribute it), from Debian's opencv-doc
// package (fetched with `apt-get download opencv-doc` into /tmp when missing; never committed).
//
// 1. Tracking (cached in eval/walk-video/vtest-poses.json, not committed; --track redoes it):
//    the Tasks API PoseLandmarker (pose_landmarker_full.task, CPU, VIDEO mode, numPoses 6) in
//    headless Chromium (eval/bench/walk-video-page.js) on every frame decoded by ffmpeg, as
//    overlapping tiles (`--layout tiles`, the default: 2 x 2 tiles of 448 x 448, each its own
//    landmarker) or the whole frame (`--layout full`: no pose found at 2x, the people too small
//    for the detector's 224 x 224 input), each scaled by `--scale` (default 1) first.
// 2. People: the poses of a frame (tiles overlap: one person found twice is kept once, the
//    pose with the higher visibility) are followed from frame to frame by the nearest hips
//    (image landmarks 23/24, within 0.8 torso lengths of where the track's hips were, greedy
//    by distance); a track ends after 3 frames unmatched. Tracks with at least 30 frames with
//    both legs seen (hip, knee and ankle visibility >= 0.5, inside the image) are kept.
// 3. Each track fed to handrig (pkg/, default options, the pose alone: image and world
//    landmarks, imageAspect 4:3, timeMs at 10 fps; frames of a gap without a pose) and to
//    Kalidokit 1.1.5's Pose.solve with legs (as eval/bench/score-legs.mjs: mirrored landmarks,
//    rotations as given, the hips at rest, no foot; on a frame without a pose it keeps its
//    last), each put on an avatar (three-vrm in Node, applyToVRM), and scored without truth:
//    * turn between frames: each leg bone's (upper leg, lower leg, foot) local rotation change
//      between consecutive frames of the track, degrees: the largest and how many over 90;
//    * knee backwards: frames with a knee bent more than 10 degrees behind its hip-ankle line;
//    * under the floor: frames with a sole point more than 2 cm under y = 0;
//    * sliding: the avatar's ankle (in the room: world position plus the hips' offset)
//      between consecutive stance frames, mm per stance frame. Stance from the video: the
//      camera is fixed, so a foot on the ground stands still in the image; a leg is in stance
//      on a frame when its ankle (image landmark) moved less than 0.15 torso lengths (image,
//      shoulders' to hips' midpoint; about 7 cm, 0.7 m/s at 10 fps) since the last frame and on
//      the next, the leg seen on the three frames. Also handrig's own planted frames
//      (`feetPlanted` on both frames): the lock's own motion;
//    * floating: frames on which a stance foot's lowest sole point is more than 2 cm above
//      the floor; the same on the frames labelled by eye as a person standing still
//      (eval/walk-video/labels.json).
//
//   node eval/walk-video.mjs [--track] [--layout tiles|full] [--scale 2] [--avatars woman,man]
//        [--pkg DIR] [--options JSON] [--tracks] [--shots TRACK:FRAME,...] [--json FILE]
//        [--cache FILE] [--max-frames N] [--min-frames 30]
//
// --tracks lists the tracks (frames, where in the image, legs seen, stance frames) for
// labelling by eye; --shots writes artifacts/screenshots/walk-video-TRACK-FRAME.png: the video
// frame cropped around the person (scaled 4x) beside the avatar as handrig solves that frame
// (the first avatar; front view, the hips' travel across taken out so that it stays in view).

import { execFileSync, spawn } from "node:child_process";
import { existsSync, mkdirSync, readFileSync, readdirSync, writeFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";
import { len, loadSolvers, sub } from "./bench/scoring.mjs";
import { Body, SIDES, bentBackwards, kalidokitLegs, kneeAngleOf, mean, percentile } from "./bench/legs-scoring.mjs";
import { avatarFile } from "./bench/common.mjs";

const REPO = join(dirname(fileURLToPath(import.meta.url)), "..");
const { values: o } = parseArgs({
  options: {
    track: { type: "boolean" }, layout: { type: "string", default: "tiles" }, scale: { type: "string", default: "1" },
    avatars: { type: "string", default: "woman,man,child" }, pkg: { type: "string" }, options: { type: "string", default: "{}" },
    tracks: { type: "boolean" }, shots: { type: "string" }, json: { type: "string" }, "max-frames": { type: "string" },
    cache: { type: "string" }, "min-frames": { type: "string", default: "30" },
  },
});

// ---- the clip ------------------------------------------------------------------------------------
const DEB_ROOT = process.env.WALK_VIDEO_ROOT ?? "/tmp/ocv";
const VIDEO = join(DEB_ROOT, "usr", "share", "doc", "opencv-doc", "examples", "data", "vtest.avi");
const W = 768;
const H = 576;
const FPS = 10;
function getVideo() {
  if (existsSync(VIDEO)) return;
  console.log(`${VIDEO} missing: apt-get download opencv-doc (into /tmp), dpkg -x into ${DEB_ROOT}`);
  execFileSync("apt-get", ["download", "opencv-doc"], { cwd: "/tmp", stdio: "inherit" });
  const deb = readdirSync("/tmp").filter((f) => /^opencv-doc_.*\.deb$/.test(f)).sort().pop();
  execFileSync("dpkg", ["-x", join("/tmp", deb), DEB_ROOT], { stdio: "inherit" });
  if (!existsSync(VIDEO)) throw new Error(`${VIDEO} not in ${deb}`);
}
/** The Debian package's version, from its changelog. */
const packageVersion = () => {
  const f = join(DEB_ROOT, "usr", "share", "doc", "opencv-doc", "changelog.Debian.gz");
  return existsSync(f) ? /\(([^)]+)\)/.exec(execFileSync("zcat", [f]).toString().split("\n")[0])?.[1] : "?";
};

// ---- 1. tracking ---------------------------------------------------------------------------------
const CACHE = o.cache ?? join(REPO, "eval", "walk-video", "vtest-poses.json");
const NUM_POSES = 6;
function tilesOf(layout) {
  if (layout === "full") return [{ x: 0, y: 0, w: W, h: H }];
  // 2 x 2 tiles of 448 x 448, overlapping by 128 px across and 320 px down (a person, at most
  // about 50 x 130 px, lies whole in one of them).
  const out = [];
  for (const y of [0, H - 448]) for (const x of [0, W - 448]) out.push({ x, y, w: 448, h: 448 });
  return out;
}
/** The clip's first `n` frames as RGBA, decoded by ffmpeg: [index, Buffer of `size` bytes]. */
async function* decode(size, n) {
  const p = spawn("ffmpeg", ["-v", "error", "-i", VIDEO, "-frames:v", String(n), "-f", "rawvideo", "-pix_fmt", "rgba", "-"], { stdio: ["ignore", "pipe", "inherit"] });
  let pending = Buffer.alloc(0);
  let i = 0;
  for await (const chunk of p.stdout) {
    pending = Buffer.concat([pending, chunk]);
    while (pending.length >= size) {
      yield [i++, pending.subarray(0, size)];
      pending = pending.subarray(size);
    }
  }
  if (i !== n) throw new Error(`${VIDEO}: ${i} frames decoded, ${n} expected`);
}
async function track() {
  getVideo();
  const { openBenchPage } = await import("./bench/render.mjs");
  const scale = Number(o.scale);
  const tiles = tilesOf(o.layout);
  const size = W * H * 4;
  const n = Math.min(795, Number(o["max-frames"] ?? Infinity));
  const version = JSON.parse(readFileSync(join(REPO, "www", "node_modules", "@mediapipe", "tasks-vision", "package.json"), "utf8")).version;
  const t0 = Date.now();
  const { page, errors, close } = await openBenchPage("walk-video-page.html");
  const frames = [];
  const ms = [];
  try {
    await page.evaluate((a) => window.__walk.start(a), { w: W, h: H, scale, numPoses: NUM_POSES, tiles });
    for await (const [i, raw] of decode(size, n)) {
      const r = await page.evaluate(([t, b]) => window.__walk.frame(t, b), [(i * 1000) / FPS, raw.toString("base64")]);
      frames.push({ frame: i, timeMs: (i * 1000) / FPS, poses: r.poses });
      ms.push(r.ms);
      if (i % 100 === 99) console.log(`frame ${i + 1} of ${n}: ${r.poses.length} poses, ${((Date.now() - t0) / 1000).toFixed(0)} s`);
    }
  } finally {
    await close();
  }
  if (errors.length) throw new Error(`page errors: ${errors.join("; ")}`);
  mkdirSync(dirname(CACHE), { recursive: true });
  const meta = {
    source: `vtest.avi (Debian opencv-doc ${packageVersion()}, ${VIDEO})`, width: W, height: H, fps: FPS,
    mediapipe: `@mediapipe/tasks-vision ${version} (pose_landmarker_full.task, CPU, VIDEO, numPoses ${NUM_POSES})`,
    layout: o.layout, scale, tiles, msMedian: percentile(ms, 50),
  };
  writeFileSync(CACHE, JSON.stringify({ meta, frames }));
  console.log(`tracked ${n} frames in ${((Date.now() - t0) / 1000).toFixed(0)} s (${meta.msMedian.toFixed(0)} ms a frame, median): ${CACHE}`);
}

// ---- 2. people -----------------------------------------------------------------------------------
const LEG = { left: [23, 25, 27], right: [24, 26, 28] };
const px = (p) => [p[0] * W, p[1] * H];
const dist2 = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
const hipsOf = (lm) => [((lm[23][0] + lm[24][0]) / 2) * W, ((lm[23][1] + lm[24][1]) / 2) * H];
const torsoOf = (lm) => dist2(hipsOf(lm), [((lm[11][0] + lm[12][0]) / 2) * W, ((lm[11][1] + lm[12][1]) / 2) * H]);
const inImage = (p) => p[0] >= 0 && p[0] <= 1 && p[1] >= 0 && p[1] <= 1;
const legSeen = (lm, side) => LEG[side].every((j) => lm[j][3] >= 0.5 && inImage(lm[j]));
const legsSeen = (lm) => SIDES.every((s) => legSeen(lm, s));
const quality = (lm) => mean(lm.slice(11).map((p) => p[3]));

function people(rec) {
  const MIN_LEG_FRAMES = Number(o["min-frames"]);
  const GATE = 0.8;
  const MAX_GAP = 3;
  const open = [];
  const done = [];
  for (const f of rec.frames) {
    // One pose per person: the tiles overlap.
    const kept = [];
    for (const p of [...f.poses].sort((a, b) => quality(b.landmarks) - quality(a.landmarks))) {
      const h = hipsOf(p.landmarks);
      const t = torsoOf(p.landmarks);
      if (!(t > 1)) continue;
      if (kept.some((k) => dist2(k.hips, h) < 0.5 * Math.max(t, k.torso))) continue;
      kept.push({ pose: p, hips: h, torso: t });
    }
    // Nearest hips, greedy.
    const pairs = [];
    open.forEach((tr, ti) => kept.forEach((d, di) => {
      const c = dist2(tr.hips, d.hips) / Math.max(tr.torso, d.torso);
      if (c < GATE) pairs.push([c, ti, di]);
    }));
    pairs.sort((a, b) => a[0] - b[0]);
    const usedT = new Set();
    const usedD = new Set();
    for (const [, ti, di] of pairs) {
      if (usedT.has(ti) || usedD.has(di)) continue;
      usedT.add(ti);
      usedD.add(di);
      const tr = open[ti];
      const d = kept[di];
      for (let g = tr.last + 1; g < f.frame; g++) tr.frames.push({ frame: g, timeMs: (g * 1000) / FPS });
      tr.frames.push({ frame: f.frame, timeMs: f.timeMs, pose: { landmarks: d.pose.landmarks, worldLandmarks: d.pose.worldLandmarks } });
      Object.assign(tr, { hips: d.hips, torso: d.torso, last: f.frame });
    }
    kept.forEach((d, di) => {
      if (!usedD.has(di)) open.push({ hips: d.hips, torso: d.torso, last: f.frame, frames: [{ frame: f.frame, timeMs: f.timeMs, pose: { landmarks: d.pose.landmarks, worldLandmarks: d.pose.worldLandmarks } }] });
    });
    for (let i = open.length - 1; i >= 0; i--) if (f.frame - open[i].last >= MAX_GAP) done.push(...open.splice(i, 1));
  }
  done.push(...open);
  const tracks = done
    .map((t) => ({ frames: t.frames, legFrames: t.frames.filter((f) => f.pose && legsSeen(f.pose.landmarks)).length }))
    .filter((t) => t.legFrames >= MIN_LEG_FRAMES)
    .sort((a, b) => a.frames[0].frame - b.frames[0].frame || hipsOf(a.frames[0].pose.landmarks)[0] - hipsOf(b.frames[0].pose.landmarks)[0]);
  tracks.forEach((t, i) => (t.id = `T${i + 1}`));
  return { tracks, poses: rec.frames.reduce((s, f) => s + f.poses.length, 0), all: done.length };
}

/** Stance per frame and side, from the video: the ankle still in the image on this frame and the next. */
function stanceOf(tr) {
  const STILL = 0.15;
  const fr = tr.frames;
  const moved = (i, side) => {
    const a = fr[i - 1]?.pose?.landmarks;
    const b = fr[i]?.pose?.landmarks;
    if (!a || !b || !legSeen(a, side) || !legSeen(b, side)) return Infinity;
    const j = LEG[side][2];
    return dist2(px(a[j]), px(b[j])) / ((torsoOf(a) + torsoOf(b)) / 2);
  };
  return fr.map((_, i) => Object.fromEntries(SIDES.map((s) => [s, moved(i, s) < STILL && moved(i + 1, s) < STILL])));
}

// ---- 3. solving and scoring ----------------------------------------------------------------------
// The MediaPipe segment each bone follows (world landmarks): thigh, shin, heel to foot index.
const SEGMENT = { UpperLeg: { left: [23, 25], right: [24, 26] }, LowerLeg: { left: [25, 27], right: [26, 28] }, Foot: { left: [29, 31], right: [30, 32] } };
/** The turn of the bone's MediaPipe segment between two frames' world landmarks (degrees; NaN without both). */
/** MediaPipe's knee angle (deg) from the world landmarks. */
function mpKnee(w, side) {
  const [h, k, a] = LEG[side].map((j) => w[j]);
  const u = [k[0] - h[0], k[1] - h[1], k[2] - h[2]];
  const v = [a[0] - k[0], a[1] - k[1], a[2] - k[2]];
  return (Math.acos(Math.max(-1, Math.min(1, (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (Math.hypot(...u) * Math.hypot(...v))))) * 180) / Math.PI;
}
function inputTurn(a, b, bone) {
  if (!a || !b) return NaN;
  const side = bone.startsWith("left") ? "left" : "right";
  const [i, j] = SEGMENT[bone.slice(side.length)][side];
  const d = (w) => [w[j][0] - w[i][0], w[j][1] - w[i][1], w[j][2] - w[i][2]];
  const u = d(a.worldLandmarks);
  const v = d(b.worldLandmarks);
  return (Math.acos(Math.max(-1, Math.min(1, (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (Math.hypot(...u) * Math.hypot(...v))))) * 180) / Math.PI;
}
const LEG_BONES = SIDES.flatMap((s) => ["UpperLeg", "LowerLeg", "Foot"].map((b) => `${s}${b}`));
const turnDeg = (a, b) => (2 * Math.acos(Math.min(1, Math.abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]))) * 180) / Math.PI;
const METHODS = ["handrig", "tracked", "kalidokit"];
const LABEL = { handrig: "handrig (defaults)", tracked: "handrig, as tracked", kalidokit: "Kalidokit 1.1.5" };
const newAcc = () => Object.fromEntries(METHODS.map((m) => [m, { turns: [], over90: 0, frames: 0, backwards: 0, under: 0, slide: [], plantedSlide: [], float: 0, stanceFrames: 0, labelFloat: 0, labelFrames: 0, half: { tune: [0, 0, 0, 0], report: [0, 0, 0, 0] }, worst: null, hipsStep: [], events: [] }]));
function merge(into, acc) {
  for (const m of METHODS) {
    for (const k of ["turns", "slide", "plantedSlide", "hipsStep", "events"]) into[m][k].push(...acc[m][k]);
    for (const k of ["over90", "frames", "backwards", "under", "float", "stanceFrames", "labelFloat", "labelFrames"]) into[m][k] += acc[m][k];
    for (const h of ["tune", "report"]) for (let k = 0; k < 4; k++) into[m].half[h][k] += acc[m].half[h][k];
    if (acc[m].worst && (!into[m].worst || acc[m].worst.deg > into[m].worst.deg)) into[m].worst = acc[m].worst;
  }
}

function scoreTrack(S, body, restPose, tr, labels, EXTRA) {
  const rigs = { handrig: new S.HandRig(restPose, EXTRA), tracked: new S.HandRig(restPose, { ...EXTRA, legs: { ...(EXTRA.legs ?? {}), moveHips: false, plant: false } }) };
  const acc = newAcc();
  const stance = stanceOf(tr);
  const mine = (l) => tr.frames.some((f) => f.frame === l.frames[0] && f.pose && dist2(hipsOf(f.pose.landmarks), l.at) < torsoOf(f.pose.landmarks));
  const standing = new Set(labels.filter(mine).flatMap((l) => Array.from({ length: l.frames[1] - l.frames[0] + 1 }, (_, k) => l.frames[0] + k)));
  const prev = {};
  let kaliBones = null;
  const kept = {};
  const solved = [];
  let lastRot = null;
  tr.frames.forEach((frame, i) => {
    const samples = {};
    const rot = {};
    let planted = null;
    let res = null;
    for (const m of ["handrig", "tracked"]) {
      body.reset();
      if (kept[m]) body.restore(kept[m]);
      const r = rigs[m].solve({ frame: frame.frame, timeMs: frame.timeMs, ...(frame.pose ? { pose: frame.pose } : {}), imageAspect: W / H });
      S.applyToVRM(body.vrm, r);
      kept[m] = body.save();
      samples[m] = body.sample();
      rot[m] = Object.fromEntries(LEG_BONES.map((b) => [b, body.h.getNormalizedBoneNode(b).quaternion.toArray()]));
      if (m === "handrig") {
        res = r;
        planted = r.feetPlanted ? { left: !!r.feetPlanted.left, right: !!r.feetPlanted.right } : { left: false, right: false };
        solved.push({ frame: frame.frame, save: kept[m], planted });
      }
    }
    if (process.env.WALK_TRACE && (process.env.WALK_TRACE === "1" || process.env.WALK_TRACE === tr.id)) {
      const mm = (v) => v.map((x) => (1000 * x).toFixed(0)).join(",");
      const sm = samples.handrig;
      const lm = frame.pose?.landmarks;
      console.error(`${tr.id} ${frame.frame} ${lm ? `hips px ${hipsOf(lm).map(Math.round)} torso ${torsoOf(lm).toFixed(0)}` : "no pose"} off ${res.hipsOffset ? mm([...res.hipsOffset]) : "-"} `
        + SIDES.map((sd) => `${sd[0]}: stance ${+stance[i][sd]} planted ${+planted[sd]} ankle ${mm(sm[sd].ankle)} sole ${(1000 * Math.min(...sm[sd].soles.map((p) => p[1]))).toFixed(0)}${lm ? ` px ${px(lm[LEG[sd][2]]).map(Math.round)} v ${[...LEG[sd], LEG[sd][0] + 6, LEG[sd][0] + 8].map((j) => lm[j][3].toFixed(2)).join("/")}` : ""}`
          // The knee angle (deg) as solved and MediaPipe's (world), and each leg bone's turn since the last frame.
          + ` knee ${kneeAngleOf(sm[sd]).toFixed(1)}${frame.pose ? ` mp ${mpKnee(frame.pose.worldLandmarks, sd).toFixed(1)}` : ""}`
          + (lastRot ? ` turn ${["UpperLeg", "LowerLeg", "Foot"].map((b) => turnDeg(lastRot[`${sd}${b}`], rot.handrig[`${sd}${b}`]).toFixed(1)).join("/")}` : "")).join(" "));
    }
    lastRot = rot.handrig;
    if (false) {
    }
    if (S.Kalidokit) {
      body.reset();
      if (frame.pose) kaliBones = kalidokitLegs(S.Kalidokit, frame.pose, { width: W, height: H });
      if (kaliBones) body.set(kaliBones);
      samples.kalidokit = body.sample();
      rot.kalidokit = Object.fromEntries(LEG_BONES.map((b) => [b, body.h.getNormalizedBoneNode(b).quaternion.toArray()]));
    }
    for (const m of METHODS) {
      if (!samples[m]) continue;
      const a = acc[m];
      a.frames++;
      if (prev[m]) {
        const hip = (x) => [(x.left.hip[0] + x.right.hip[0]) / 2, (x.left.hip[1] + x.right.hip[1]) / 2, (x.left.hip[2] + x.right.hip[2]) / 2];
        a.hipsStep.push(1000 * len(sub(hip(samples[m]), hip(prev[m].s))));
        for (const b of LEG_BONES) {
          const d = turnDeg(prev[m].rot[b], rot[m][b]);
          a.turns.push(d);
          if (d > 90) {
            a.over90++;
            // The avatar's own segment (hip to knee, knee to ankle): a turn of the bone that does
            // not move its segment is a twist about it.
            const side = b.startsWith("left") ? "left" : "right";
            const seg = (x) => (b.endsWith("UpperLeg") ? sub(x[side].knee, x[side].hip) : b.endsWith("LowerLeg") ? sub(x[side].ankle, x[side].knee) : null);
            const u = seg(prev[m].s);
            const v = seg(samples[m]);
            const own = u ? (Math.acos(Math.max(-1, Math.min(1, (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (len(u) * len(v))))) * 180) / Math.PI : NaN;
            a.events.push({ track: tr.id, frame: frame.frame, bone: b, deg: d, input: inputTurn(tr.frames[i - 1]?.pose, frame.pose, b), own, knee: [kneeAngleOf(prev[m].s[side]), kneeAngleOf(samples[m][side])] });
          }
          if (!a.worst || d > a.worst.deg) a.worst = { deg: d, track: tr.id, frame: frame.frame, bone: b };
        }
      }
      let under = false;
      let backwards = false;
      let float = false;
      let labelFloat = false;
      for (const side of SIDES) {
        const l = samples[m][side];
        if (l.soles.some((p) => p[1] < -0.02)) under = true;
        if (bentBackwards(l, samples[m].forward)) backwards = true;
        const low = Math.min(...l.soles.map((p) => p[1]));
        if (stance[i][side]) {
          if (low > 0.02) float = true;
          if (prev[m] && stance[i - 1]?.[side]) a.slide.push(1000 * len(sub(l.ankle, prev[m].s[side].ankle)));
        }
        if (standing.has(frame.frame) && low > 0.02) labelFloat = true;
        if (m === "handrig" && planted[side] && prev[m]?.planted?.[side]) a.plantedSlide.push(1000 * len(sub(l.ankle, prev[m].s[side].ankle)));
      }
      if (stance[i].left || stance[i].right) a.stanceFrames++;
      if (standing.has(frame.frame)) a.labelFrames++;
      if (under) a.under++;
      if (backwards) a.backwards++;
      if (float) a.float++;
      if (labelFloat) a.labelFloat++;
      // The tracks' halves: odd tracks tune, even ones report ([stance frames with a foot up, stance
      // frames, standing frames with a foot up, standing frames]).
      const h = a.half[Number(tr.id.slice(1)) % 2 ? "tune" : "report"];
      h[0] += +float;
      h[1] += +(stance[i].left || stance[i].right);
      h[2] += +labelFloat;
      h[3] += +standing.has(frame.frame);
      prev[m] = { rot: rot[m], s: samples[m], planted: m === "handrig" ? planted : null };
    }
  });
  for (const r of Object.values(rigs)) r.free();
  return { acc, solved };
}

// ---- 4. screenshots ------------------------------------------------------------------------------
async function shots(S, avatar, tracksById, solvedBy) {
  const { openRenderer, WIDTH, HEIGHT } = await import("./bench/render.mjs");
  const out = join(REPO, "artifacts", "screenshots");
  mkdirSync(out, { recursive: true });
  const r = await openRenderer();
  try {
    await r.load(avatar);
    await r.clip("walk");
    for (const s of o.shots.split(",")) {
      const [id, fs] = s.split(":");
      const n = Number(fs);
      const tr = tracksById[id];
      const k = tr?.frames.findIndex((f) => f.frame === n);
      if (!tr || k < 0 || !tr.frames[k].pose) throw new Error(`no pose of track ${id} on frame ${n}`);
      const st = solvedBy[id][k].save;
      const hips = [...st.hips];
      const rest = solvedBy[id].hipsRest;
      hips[0] = rest[0];
      hips[2] = rest[2];
      const rgba = Buffer.from(await r.page.evaluate(([b, p]) => window.__bench.show(b, p, "front"), [st.q, hips]), "base64");
      // The person: a square crop around the hips, 5 torso lengths high, scaled to the render's height.
      const lm = tr.frames[k].pose.landmarks;
      const side = Math.round(Math.min(H, Math.max(48, 5 * torsoOf(lm))));
      const [hx, hy] = hipsOf(lm);
      const x0 = Math.round(Math.min(W - side, Math.max(0, hx - side / 2)));
      const y0 = Math.round(Math.min(H - side, Math.max(0, hy - side / 2)));
      const file = join(out, `walk-video-${id}-${n}.png`);
      await new Promise((res, rej) => {
        const p = spawn("ffmpeg", ["-v", "error", "-y", "-i", VIDEO, "-f", "rawvideo", "-pix_fmt", "rgba", "-s", `${WIDTH}x${HEIGHT}`, "-i", "-",
          "-filter_complex", `[0:v]select=eq(n\\,${n}),crop=${side}:${side}:${x0}:${y0},scale=${HEIGHT}:${HEIGHT}:flags=neighbor,format=rgba[a];[a][1:v]hstack=inputs=2`,
          "-frames:v", "1", file], { stdio: ["pipe", "inherit", "inherit"] });
        p.on("close", (c) => (c === 0 ? res() : rej(new Error(`ffmpeg exited with ${c}`))));
        p.stdin.end(rgba);
      });
      console.log(`${file}: track ${id}, frame ${n} (${(n / FPS).toFixed(1)} s), crop ${side} px at (${x0}, ${y0}); planted ${JSON.stringify(solvedBy[id][k].planted)}`);
    }
  } finally {
    await r.close();
  }
}

// ---- run -----------------------------------------------------------------------------------------
if (o.track || !existsSync(CACHE)) await track();
const rec = JSON.parse(readFileSync(CACHE, "utf8"));
const { tracks, poses, all } = people(rec);
const LABELS = join(REPO, "eval", "walk-video", "labels.json");
const labels = existsSync(LABELS) ? JSON.parse(readFileSync(LABELS, "utf8")).standing ?? [] : [];
const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
const f2 = (x) => (Number.isFinite(x) ? x.toFixed(2) : "-");
console.log(`${rec.meta.source}; ${rec.meta.mediapipe}; layout ${rec.meta.layout} (${rec.meta.tiles.length} tiles), scale ${rec.meta.scale}`);
console.log(`${rec.frames.length} frames, ${poses} poses found (tiles counted apart), ${all} tracks, ${tracks.length} with ${o["min-frames"]}+ frames with both legs seen`);
if (o.tracks) {
  console.log("| track | frames | seen | legs seen | hips from -> to (px) | torso px (median) | stance frames left / right | hips still (frames) |");
  console.log("| --- | --- | ---: | ---: | --- | ---: | --- | --- |");
  for (const t of tracks) {
    const withPose = t.frames.filter((f) => f.pose);
    const st = stanceOf(t);
    const a = hipsOf(withPose[0].pose.landmarks).map(Math.round);
    const b = hipsOf(withPose[withPose.length - 1].pose.landmarks).map(Math.round);
    // Candidates for standing still: the hips within 0.5 torso lengths over 10 frames (1 s).
    const still = withPose.filter((f, k) => k + 9 < withPose.length && withPose[k + 9].frame - f.frame === 9
      && dist2(hipsOf(f.pose.landmarks), hipsOf(withPose[k + 9].pose.landmarks)) < 0.5 * torsoOf(f.pose.landmarks)).map((f) => f.frame);
    console.log(`| ${t.id} | ${t.frames[0].frame}-${t.frames[t.frames.length - 1].frame} | ${withPose.length} | ${t.legFrames} | (${a}) -> (${b}) | ${f1(percentile(withPose.map((f) => torsoOf(f.pose.landmarks)), 50))} | ${st.filter((s) => s.left).length} / ${st.filter((s) => s.right).length} | ${still.length ? `${still.length} from ${still[0]}` : "-"} |`);
  }
}
const S = await loadSolvers({ pkg: o.pkg });
const EXTRA = JSON.parse(o.options);
const avatars = o.avatars.split(",");
const perTrack = [];
const total = newAcc();
const byAvatar = {};
let shotData = null;
for (const avatar of avatars) {
  const vrm = await S.loadVrm(avatarFile(avatar));
  const restPose = S.restPoseFromVRM(vrm);
  const body = new Body(vrm);
  byAvatar[avatar] = newAcc();
  const solvedBy = { };
  for (const tr of tracks) {
    const { acc, solved } = scoreTrack(S, body, restPose, tr, labels, EXTRA);
    solvedBy[tr.id] = solved;
    solved.hipsRest = body.hipsRest;
    perTrack.push({ avatar, id: tr.id, acc });
    merge(byAvatar[avatar], acc);
    merge(total, acc);
  }
  if (!shotData) shotData = { avatar, solvedBy };
}

const cell = (a, m) => {
  if (!a.frames) return "-";
  return `${f1(Math.max(...a.turns))}; ${a.over90}; ${a.backwards}; ${a.under}; ${f2(mean(a.slide))}`;
};
console.log();
console.log(`#### Per track (${avatars[0]}): largest leg-bone turn between frames (deg); turns over 90; frames with a knee backwards; frames with a sole > 2 cm under the floor; sliding (mm per stance frame, mean)`);
console.log();
console.log(`| track | frames | stance leg-frames | ${METHODS.map((m) => LABEL[m]).join(" | ")} |`);
console.log(`| --- | ---: | ---: | ${METHODS.map(() => "---").join(" | ")} |`);
for (const p of perTrack.filter((q) => q.avatar === avatars[0])) {
  const tr = tracks.find((t) => t.id === p.id);
  console.log(`| ${p.id} | ${tr.frames.length} | ${p.acc.handrig.slide.length} | ${METHODS.map((m) => cell(p.acc[m], m)).join(" | ")} |`);
}
const FIG = [
  ["leg-bone turns between frames (deg, median / p99 / max)", (a) => `${f1(percentile(a.turns, 50))} / ${f1(percentile(a.turns, 99))} / ${f1(Math.max(...a.turns))}`],
  ["turns over 90 degrees", (a) => `${a.over90} of ${a.turns.length}`],
  ["the largest turn (track, frame, bone)", (a) => (a.worst ? `${f1(a.worst.deg)} (${a.worst.track}, ${a.worst.frame}, ${a.worst.bone})` : "-")],
  ["the hips' move between frames (mm, median / p95)", (a) => `${f1(percentile(a.hipsStep, 50))} / ${f1(percentile(a.hipsStep, 95))}`],
  ["frames with a knee bent backwards", (a) => `${a.backwards} of ${a.frames}`],
  ["frames with a sole > 2 cm under the floor", (a) => `${a.under} of ${a.frames}`],
  ["sliding, mm per stance frame (mean / p95 / max; leg-frames)", (a) => `${f2(mean(a.slide))} / ${f1(percentile(a.slide, 95))} / ${f1(Math.max(...a.slide))} (${a.slide.length})`],
  ["sliding while handrig's foot is planted (mm per frame, mean / p95 / max; leg-frames)", (a, m) => (m === "handrig" ? `${f2(mean(a.plantedSlide))} / ${f1(percentile(a.plantedSlide, 95))} / ${f1(Math.max(...a.plantedSlide))} (${a.plantedSlide.length})` : "-")],
  ["frames with a stance foot > 2 cm above the floor", (a) => `${a.float} of ${a.stanceFrames}`],
  ["frames standing still (by eye) with a foot > 2 cm above the floor", (a) => `${a.labelFloat} of ${a.labelFrames}`],
  ["the same two, tune tracks (odd) / report tracks (even)", (a) => `${a.half.tune[0]} of ${a.half.tune[1]}, ${a.half.tune[2]} of ${a.half.tune[3]} / ${a.half.report[0]} of ${a.half.report[1]}, ${a.half.report[2]} of ${a.half.report[3]}`],
];
for (const [name, acc] of [...avatars.map((a) => [a, byAvatar[a]]), ...(avatars.length > 1 ? [["all avatars", total]] : [])]) {
  console.log();
  console.log(`#### ${name}: ${tracks.length} tracks`);
  console.log();
  console.log(`| figure | ${METHODS.map((m) => LABEL[m]).join(" | ")} |`);
  console.log(`| --- | ${METHODS.map(() => "---:").join(" | ")} |`);
  for (const [n, f] of FIG) console.log(`| ${n} | ${METHODS.map((m) => f(acc[m], m)).join(" | ")} |`);
}
for (const m of METHODS) {
  if (!byAvatar[avatars[0]][m].events.length) continue;
  console.log();
  console.log(`${LABEL[m]} (${avatars[0]}), turns over 90 degrees: ${byAvatar[avatars[0]][m].events.map((e) => `${e.track} ${e.frame} ${e.bone} ${f1(e.deg)} (its segment ${f1(e.own)}, MediaPipe's ${f1(e.input)}; the knee ${f1(e.knee[0])} -> ${f1(e.knee[1])})`).join("; ")}`);
}
if (o.json) writeFileSync(o.json, JSON.stringify({ meta: rec.meta, tracks: tracks.map((t) => ({ id: t.id, first: t.frames[0].frame, last: t.frames[t.frames.length - 1].frame })), perTrack }, null, 1));
if (o.shots) await shots(S, shotData.avatar, Object.fromEntries(tracks.map((t) => [t.id, t])), shotData.solvedBy);
