#!/usr/bin/env node
// Self-contact on the avatar's skin (issues 26 and 52), the way a user sees it: each labeled ASL
// clip (../shared/data/asl, labels in eval/labels/) drives each avatar through three-vrm
// (HandRig(restPoseFromVRM(vrm)) -> rig.solve -> applyToVRM -> humanoid.update), the skin is
// computed on the CPU (three's SkinnedMesh.getVertexPosition) and measured per hand-frame by
// tests/node/consumer/skin-measure.mjs: gap of the hand's surface to the face, chest and other
// hand; hand vertices inside the head/torso (winding number). Contact on (default options) and
// off (`contact.enabled: false`).
//
//   make pkg (or copy a built pkg/) && npm ci --prefix tests/node
//   node eval/skin-contact.mjs [--pkg DIR] [--avatars woman-vrm1,voxel-vrm1,...] [--clips eat,please]
//                              [--per-clip] [--json] [--options JSON] [--fist]
//
// --fist adds `please-fist`: `please` with the chest hand curled into a fist (eval/fist.mjs;
// no clip has a fist on the chest), scored on please's labels, in neither half (a hand shape
// nothing was tuned on); it shows in the per-avatar and per-clip rows.
//
// Avatars (issue 52): the generated human bodies (tests/fixtures/avatars, VRM 1.0 and 0.x), the
// stylized variants (target/avatars, made here by tools/avatars/generate.mjs when missing), the
// figure of primitives and the voxel figure (tests/fixtures/avatars/figures), and the robot
// (../shared/avatars, rigid meshes: not measurable, listed as such).
//
// The split (issue 52), fixed here and nowhere else: the clips and the avatars each in a TUNE
// half (what a contact solver may be tuned on) and a REPORT half (what it is judged on). See
// SPLIT below for the reasons. Printed: per half (tune clips x tune avatars; report clips x
// report avatars; report clips on every avatar; all), per avatar (report clips, all clips),
// and with --per-clip every avatar x clip; contact on vs off.
//
// Columns: face / chest / hands: share of the labeled touch hand-frames whose touching hand is
// within 2 cm of that skin AND no more than 1 cm inside head or torso ("lands"), beside the
// share within 2 cm alone (issue 26's figure, which also counts a hand sunk into the head);
// false touches: "none" hand-frames within 2 cm of face, chest or other hand; frames with a
// hand vertex > 1 cm inside head/torso; the deepest (mm).
//
// --json also writes every row to target/skin-contact.json.
//
// Takes about 5-8 minutes for the 16 measurable avatars and 7 clips on a quiet 2-core machine
// (86 s for 6 avatars x 6 clips at 5d814c0), longer on a busy one; `--avatars woman-vrm1` ~20 s.

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..");
const shared = path.resolve(process.env.HANDRIG_SHARED || path.join(repo, "..", "shared"));
const argv = process.argv.slice(2);
const arg = (name) => {
  const i = argv.indexOf(name);
  return i >= 0 ? argv[i + 1] : undefined;
};

/**
 * The fixed split of issue 52. Each half holds each kind of touch, so that a solver tuned on
 * one half is judged on the same kinds of touch made otherwise:
 * - clips: TUNE again (hands), eat (fingertips to the mouth), please (flat palm circling on the
 *   chest), sister (thumb at the chin, then hands); REPORT brother (a forehead touch, then
 *   hands), hungry (a curved hand on the chest), thanks (flat fingers from the chin). The
 *   report half holds the touches issue 52 found not to carry over (a forehead touch, a chest
 *   touch by a hand that is not a flat palm), so they cannot be tuned on; face hand-frames are
 *   balanced (tune 20, report 19), chest 50 / 32, hands 120 / 34.
 * - avatars: TUNE the woman and the child (VRM 1.0 and 0.x), head 1.5x, the deep chest, the long
 *   arms, the figure of primitives; REPORT the man (1.0 and 0.x), the chibi head 2x (1.0 and
 *   0.x), the wide chest, the short arms, the large hands, the voxel figure. Each kind of
 *   departure has one side in each half or, where there is one variant only (large hands), is
 *   held out: the report half extrapolates (a bigger head than any tuned on, short arms after
 *   long ones, a box head and missing thumbs and distal bones after spheres); both halves hold
 *   VRM 1.0 and 0.x files and one human body the other half lacks.
 */
export const SPLIT = {
  clips: { tune: ["again", "eat", "please", "sister"], report: ["brother", "hungry", "thanks"] },
  avatars: {
    tune: ["woman-vrm1", "woman-vrm0", "child-vrm1", "child-vrm0", "woman-head15-vrm1", "woman-deepchest-vrm1", "woman-longarms-vrm1", "primitive-vrm1"],
    report: ["man-vrm1", "man-vrm0", "woman-head2-vrm1", "woman-head2-vrm0", "woman-widechest-vrm1", "woman-shortarms-vrm1", "woman-largehands-vrm1", "voxel-vrm1"],
  },
};
const ALL = [...SPLIT.avatars.tune, ...SPLIT.avatars.report, "debug-robot"];

const pkg = path.resolve(arg("--pkg") ?? path.join(repo, "pkg"));
const measure = await import(pathToFileURL(path.join(repo, "tests", "node", "consumer", "skin-measure.mjs")).href);
const gen = await import(pathToFileURL(path.join(repo, "tools", "avatars", "generate.mjs")).href);
const { HandRig } = await import(pathToFileURL(path.join(pkg, "index.mjs")).href);
const { restPoseFromVRM, applyToVRM } = await import(pathToFileURL(path.join(pkg, "three-vrm.js")).href);
const avatars = (arg("--avatars") ?? ALL.join(",")).split(",");
const clips = (arg("--clips") ?? measure.labeledClips(repo).join(",")).split(",");
if (argv.includes("--fist")) clips.push("please-fist");
const { fistFrames } = await import("./fist.mjs");
/** A clip's frames (`please-fist`: please with the signer's right hand, MediaPipe's "Left", a fist). */
const clipFrames = (clip) => {
  const rec = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip.replace(/-fist$/, "")}.json`), "utf8"));
  return clip.endsWith("-fist") ? fistFrames(rec, "Left") : rec.frames;
};
const asJson = argv.includes("--json");
const perClip = argv.includes("--per-clip");
// --options JSON: options for both runs (contact.enabled is set per run on top of them).
const extra = JSON.parse(arg("--options") ?? "{}");
for (const c of [...SPLIT.clips.tune, ...SPLIT.clips.report]) if (!measure.labeledClips(repo).includes(c)) throw new Error(`SPLIT: no labels for ${c}`);
if (SPLIT.clips.tune.length + SPLIT.clips.report.length !== measure.labeledClips(repo).length) throw new Error("SPLIT: a labeled clip is in neither half");

const stylized = new Set(gen.stylizedFileNames().map((n) => n.replace(/\.vrm$/, "")));
const figures = new Set(gen.figureFileNames().map((n) => n.replace(/\.vrm$/, "")));
function fileOf(a) {
  if (a === "debug-robot") return path.join(shared, "avatars", "debug-robot.vrm");
  if (figures.has(a)) return path.join(gen.FIGURES_OUT, `${a}.vrm`);
  if (stylized.has(a)) {
    const file = path.join(gen.DEFAULT_STYLIZED_OUT, `${a}.vrm`);
    // Made fresh each run (about 3 s for all): a stale copy from an older generator never counts.
    if (!fileOf.made) {
      fs.mkdirSync(gen.DEFAULT_STYLIZED_OUT, { recursive: true });
      for (const [n, b] of gen.generateStylized()) fs.writeFileSync(path.join(gen.DEFAULT_STYLIZED_OUT, n), b);
      fileOf.made = true;
    }
    return file;
  }
  return path.join(repo, "tests", "fixtures", "avatars", `${a}.vrm`);
}

const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
const f0 = (x) => (Number.isFinite(x) ? x.toFixed(0) : "-");
const cell = (t) => (t.n ? `${f0(t.cleanPct)}% (${f0(t.pct)}%, ${t.n})` : "-");
const HEADER =
  "| contact | face lands (within 2 cm, hand-frames) | chest | hands | false touches | frames > 1 cm inside | deepest mm | touches tracked |";
const SEP = "| --- | --- | --- | --- | --- | ---: | ---: | ---: |";
const line = (label, k, f) =>
  `| ${label}${k} | ${cell(f.face)} | ${cell(f.chest)} | ${cell(f.hand)} | ${f.falseTouch.n ? `${f0(f.falseTouch.pct)}% (${f.falseTouch.n})` : "-"} | ${f1(f.deep.pct)}% | ${f0(f.deep.maxMm)} | ${f0(f.touchTracked)}% |`;

const rows = [];
const started = performance.now();
const half = (list, x) => (list.tune.includes(x) ? "tune" : list.report.includes(x) ? "report" : "-");
// Scores by (avatar, clip, contact), accumulated into the groups below.
const groups = new Map();
const acc = (key, k) => {
  const id = `${key}|${k}`;
  if (!groups.has(id)) groups.set(id, measure.newScore());
  return groups.get(id);
};
const skipped = [];
if (perClip) {
  console.log(`| avatar | clip ${HEADER}`);
  console.log(`| --- | --- ${SEP}`);
}
for (const a of avatars) {
  const t0 = performance.now();
  const vrm = await measure.loadVrm(fileOf(a));
  const body = new measure.SkinBody(vrm);
  if (!body.hasBody || body.vertices.leftHand.length === 0) {
    skipped.push(a);
    continue;
  }
  for (const clip of clips) {
    const frames = clipFrames(clip);
    const labels = measure.readLabels(repo, clip.replace(/-fist$/, ""));
    for (const contact of [true, false]) {
      const k = contact ? "on" : "off";
      const rig = new HandRig(restPoseFromVRM(vrm), { ...extra, contact: { ...extra.contact, enabled: contact } });
      const m = measure.runClip({ vrm, body, rig, applyToVRM, frames });
      rig.free();
      const ah = half(SPLIT.avatars, a);
      const ch = half(SPLIT.clips, clip);
      const keys = [`avatar:${a}:all`, `avatar:${a}:${ch}`, "all", `clips:${ch}`];
      if (ah === ch) keys.push(`half:${ah}`);
      for (const key of keys) measure.score(m, labels, {}, acc(key, k));
      const f = measure.figures(measure.score(m, labels));
      rows.push({ avatar: a, clip, avatarHalf: ah, clipHalf: ch, contact, ...f });
      if (perClip) console.log(`| ${a} | ${clip} ${line("", k, f)}`);
    }
  }
  console.error(`${a}: ${((performance.now() - t0) / 1000).toFixed(0)} s`);
}
const show = (label, key) => {
  for (const k of ["on", "off"]) {
    if (!groups.has(`${key}|${k}`)) continue;
    const f = measure.figures(groups.get(`${key}|${k}`));
    rows.push({ group: key, contact: k === "on", ...f });
    console.log(line(label, k, f));
  }
};
console.log(`\nBy half (face, chest, hands: lands = within 2 cm and the hand no more than 1 cm inside; in brackets within 2 cm alone, and the hand-frames)\n`);
console.log(`| half ${HEADER}`);
console.log(`| --- ${SEP}`);
show("tune (tune clips x tune avatars) | ", "half:tune");
show("report (report clips x report avatars) | ", "half:report");
show("report clips x every avatar | ", "clips:report");
show("tune clips x every avatar | ", "clips:tune");
show("all clips x every avatar | ", "all");
console.log(`\nPer avatar, the report clips (${SPLIT.clips.report.join(", ")})\n`);
console.log(`| avatar (half) ${HEADER}`);
console.log(`| --- ${SEP}`);
for (const a of avatars) if (!skipped.includes(a)) show(`${a} (${half(SPLIT.avatars, a)}) | `, `avatar:${a}:report`);
console.log(`\nPer avatar, all ${clips.length} clips\n`);
console.log(`| avatar (half) ${HEADER}`);
console.log(`| --- ${SEP}`);
for (const a of avatars) if (!skipped.includes(a)) show(`${a} (${half(SPLIT.avatars, a)}) | `, `avatar:${a}:all`);
for (const a of skipped) console.log(`\n${a}: no skinned body or hands (rigid meshes only): not measurable`);
console.log(`\n(${((performance.now() - started) / 1000).toFixed(0)} s)`);
if (asJson) {
  fs.mkdirSync(path.join(repo, "target"), { recursive: true });
  fs.writeFileSync(path.join(repo, "target", "skin-contact.json"), JSON.stringify({ split: SPLIT, rows }, null, 2));
  console.log("rows written to target/skin-contact.json");
}
