#!/usr/bin/env node
// Chest contact on the bench (issue 52): the contact clips (motions.mjs CONTACT_CLIPS: the right
// hand held on the chest and 18 cm before it, as a flat palm, a curved hand, a fist and a curved
// hand at the collar; one clip per avatar, posed for its body) rendered, tracked by the Tasks API
// (render.mjs --contact, tasks.mjs --contact), solved by handrig on the rendered avatar (three-vrm,
// CPU skinning, as eval/skin-contact.mjs measures the real clips), contact on and off. Per hold:
// the truth's own gap (the rendered pose's hand skin to its chest skin), the solved hand's gap, and
// the share of the hold's frames that land (solved hand within 2 cm of the chest and no more than
// 1 cm inside: "on" holds) or touch falsely (within 2 cm: "off" holds). Beside them the chest
// cue's readings (src/contact/chest.rs, replicated here from the recording): the hand's image
// scale over the body's (the size cue; its ramp is 1.1..1.3), the fingertips' extension (the
// flat-palm cue wants 1.35..1.55), and where the palm is over the torso (u, v).
//
//   node eval/bench/render.mjs --contact && node eval/bench/tasks.mjs --contact   # once (about 5 min)
//   node eval/bench/chest-cue.mjs [--pkg DIR] [--avatars woman,man,child] [--options JSON]
//
// The woman is the tuning avatar, the man and the child report (the angles of every clip were
// found for each body; no cue constant was chosen on them).

import fs from "node:fs";
import path from "node:path";
import { parseArgs } from "node:util";
import { pathToFileURL } from "node:url";
import { CONTACT_AVATARS, REPO, avatarFile, recordingFile } from "./common.mjs";
import { CONTACT_CLIPS, clipPose, setNormalizedPose } from "./motions.mjs";

const { values: o } = parseArgs({ options: { pkg: { type: "string" }, avatars: { type: "string" }, options: { type: "string" } } });
const pkg = path.resolve(o.pkg ?? path.join(REPO, "pkg"));
const extra = JSON.parse(o.options ?? "{}");
const measure = await import(pathToFileURL(path.join(REPO, "tests", "node", "consumer", "skin-measure.mjs")).href);
const { HandRig } = await import(pathToFileURL(path.join(pkg, "index.mjs")).href);
const { restPoseFromVRM, applyToVRM } = await import(pathToFileURL(path.join(pkg, "three-vrm.js")).href);

const SEG = [[0, 5], [0, 9], [0, 17], [5, 17]];
const dist = (a, b, n = 3) => Math.hypot(...Array.from({ length: n }, (_, k) => b[k] - a[k]));
/**
 * The chest cue's readings of the right hand, as src/contact/chest.rs reads them. The hand is the
 * one whose wrist is nearest the pose's right wrist: MediaPipe's handedness label reads the hand's
 * look, and a right hand showing its back reads as a left one.
 */
function cue(frame, aspect) {
  const L = frame.pose?.landmarks;
  const W = frame.pose?.worldLandmarks;
  const near = (x) => dist(x.landmarks[0], L[16], 2);
  const h = L && [...(frame.hands ?? [])].sort((a, b) => near(a) - near(b))[0];
  if (!L || !W || !h?.worldLandmarks) return null;
  const torso = Math.hypot((L[11][0] - L[12][0]) * aspect, L[11][1] - L[12][1]) / Math.hypot(W[11][0] - W[12][0], W[11][1] - W[12][1]);
  let seen = 0;
  let size = 0;
  for (const [a, b] of SEG) {
    seen += Math.hypot((h.landmarks[b][0] - h.landmarks[a][0]) * aspect, h.landmarks[b][1] - h.landmarks[a][1]);
    size += dist(h.worldLandmarks[a], h.worldLandmarks[b]);
  }
  const w = h.worldLandmarks;
  const extension = [8, 12, 16, 20].reduce((s, t) => s + dist(w[0], w[t]), 0) / 4 / dist(w[0], w[9]);
  const mid = [0, 1].map((k) => (L[11][k] + L[12][k]) / 2);
  const hips = [0, 1].map((k) => (L[23][k] + L[24][k]) / 2);
  const across = [L[11][0] - L[12][0], L[11][1] - L[12][1]];
  const down = [hips[0] - mid[0], hips[1] - mid[1]];
  const palm = [0, 1].map((k) => [0, 5, 9, 13, 17].reduce((s, i) => s + h.landmarks[i][k], 0) / 5);
  const q = [palm[0] - mid[0], palm[1] - mid[1]];
  const u = (q[0] * across[0] + q[1] * across[1]) / (across[0] ** 2 + across[1] ** 2);
  const v = (q[0] * down[0] + q[1] * down[1]) / (down[0] ** 2 + down[1] ** 2);
  // The palm turned from the camera, as the solver reads it: the image-plane sine between
  // wrist-to-index and wrist-to-little knuckle, signed by the hand's label ("Left": +1).
  const [a, b, c] = [h.landmarks[0], h.landmarks[5], h.landmarks[17]];
  const e1 = [b[0] - a[0], b[1] - a[1]];
  const e2 = [c[0] - a[0], c[1] - a[1]];
  const facing = ((h.handedness === "Left" ? 1 : -1) * (e1[0] * e2[1] - e1[1] * e2[0])) / (Math.hypot(...e1) * Math.hypot(...e2));
  return { size: seen / size / torso, extension, u, v, facing, label: h.handedness };
}

const mean = (xs) => (xs.length ? xs.reduce((a, b) => a + b, 0) / xs.length : NaN);
const f2 = (x) => (Number.isFinite(x) ? x.toFixed(2) : "-");
const f0 = (x) => (Number.isFinite(x) ? x.toFixed(0) : "-");
const avatars = (o.avatars ?? CONTACT_AVATARS.join(",")).split(",");
const totals = { tune: { on: [0, 0], off: [0, 0], onOff: [0, 0], offOff: [0, 0] }, report: { on: [0, 0], off: [0, 0], onOff: [0, 0], offOff: [0, 0] } };
console.log("| avatar | hold | truth gap mm | contact on: lands / false (frames) | solved gap mm | contact off: lands / false | size cue | extension | facing | u, v | labelled |");
console.log("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | --- |");
for (const avatar of avatars) {
  const clip = CONTACT_CLIPS.find((c) => c.avatar === avatar);
  if (!clip) throw new Error(`--avatars: no contact clip for ${avatar} (have ${CONTACT_CLIPS.map((c) => c.avatar).join(", ")})`);
  const file = recordingFile(avatar, clip, "tasks");
  if (!fs.existsSync(file)) throw new Error(`${file}: missing; run node eval/bench/render.mjs --contact && node eval/bench/tasks.mjs --contact`);
  const rec = JSON.parse(fs.readFileSync(file, "utf8"));
  const vrm = await measure.loadVrm(avatarFile(avatar));
  const body = new measure.SkinBody(vrm);
  // The truth's gap per frame: the clip's own pose on this avatar.
  const truth = [];
  for (let i = 0; i < clip.frames; i++) {
    const q = clipPose(clip, i);
    setNormalizedPose(vrm, q);
    vrm.update(0);
    vrm.scene.updateMatrixWorld(true);
    body.update();
    truth.push(body.measure().right);
  }
  const solved = {};
  for (const on of [true, false]) {
    const rig = new HandRig(restPoseFromVRM(vrm), { ...extra, contact: { ...extra.contact, enabled: on } });
    solved[on] = measure.runClip({ vrm, body, rig, applyToVRM, frames: rec.frames });
    rig.free();
  }
  const half = avatar === "woman" ? "tune" : "report";
  for (const [first, last, kind, shape] of clip.holds) {
    const idx = Array.from({ length: last - first + 1 }, (_, k) => first + k);
    const within = (m) => m.right.chest <= 0.02;
    const lands = (m) => within(m) && !(m.right.depth > 0.01);
    const count = (on) => idx.filter((i) => (kind === "on" ? lands : within)(solved[on][i])).length;
    const cues = idx.map((i) => cue(rec.frames[i], rec.width / rec.height)).filter(Boolean);
    const t = totals[half];
    t[kind][0] += count(true);
    t[kind][1] += idx.length;
    t[kind === "on" ? "onOff" : "offOff"][0] += count(false);
    t[kind === "on" ? "onOff" : "offOff"][1] += idx.length;
    console.log(
      `| ${avatar} (${half}) | ${shape} ${kind} | ${f0(1000 * mean(idx.map((i) => truth[i].chest)))} | ${count(true)} / ${idx.length} | ` +
        `${f0(1000 * mean(idx.map((i) => solved[true][i].right.chest)))} | ${count(false)} / ${idx.length} | ` +
        `${f2(mean(cues.map((c) => c.size)))} | ${f2(mean(cues.map((c) => c.extension)))} | ${f2(mean(cues.map((c) => c.facing)))} | ${f2(mean(cues.map((c) => c.u)))}, ${f2(mean(cues.map((c) => c.v)))} | ${[...new Set(cues.map((c) => c.label))].join(", ")} |`,
    );
  }
}
const pct = ([a, n]) => (n ? `${((100 * a) / n).toFixed(0)}% (${a} / ${n})` : "-");
console.log("\n| half | contact on: chest lands | false touches before the chest | contact off: lands | false |");
console.log("| --- | ---: | ---: | ---: | ---: |");
for (const [h, t] of Object.entries(totals)) if (t.on[1] + t.off[1]) console.log(`| ${h} | ${pct(t.on)} | ${pct(t.off)} | ${pct(t.onOff)} | ${pct(t.offOff)} |`);
