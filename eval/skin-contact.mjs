#!/usr/bin/env node
// Self-contact on the avatar's skin (issue 26), the way a user sees it: each labeled ASL clip
// (../shared/data/asl, labels in eval/labels/) drives each avatar through three-vrm
// (HandRig(restPoseFromVRM(vrm)) -> rig.solve -> applyToVRM -> humanoid.update), the skin is
// computed on the CPU (three's SkinnedMesh.getVertexPosition) and measured per hand-frame by
// tests/node/consumer/skin-measure.mjs: gap of the hand's surface to the face, chest and other
// hand; hand vertices inside the head/torso (winding number). Contact on (default options) and
// off (`contact.enabled: false`).
//
//   make pkg (or copy a built pkg/) && npm ci --prefix tests/node
//   node eval/skin-contact.mjs [--pkg DIR] [--avatars woman-vrm1,man-vrm0,...] [--clips eat,please] [--json]
//
// --json also writes every row to target/skin-contact.json.
//
// Takes about 1.5-2 minutes for the six generated avatars (86 s measured at 5d814c0; 8-12 minutes
// when first written), longer on a busy machine; `--avatars woman-vrm1` about 15 s.

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
const pkg = path.resolve(arg("--pkg") ?? path.join(repo, "pkg"));
const measure = await import(pathToFileURL(path.join(repo, "tests", "node", "consumer", "skin-measure.mjs")).href);
const { HandRig } = await import(pathToFileURL(path.join(pkg, "index.mjs")).href);
const { restPoseFromVRM, applyToVRM } = await import(pathToFileURL(path.join(pkg, "three-vrm.js")).href);
const ALL = ["woman-vrm1", "woman-vrm0", "man-vrm1", "man-vrm0", "child-vrm1", "child-vrm0", "debug-robot"];
const avatars = (arg("--avatars") ?? ALL.join(",")).split(",");
const clips = (arg("--clips") ?? measure.labeledClips(repo).join(",")).split(",");
const asJson = argv.includes("--json");
// --options JSON: options for both runs (contact.enabled is set per run on top of them).
const extra = JSON.parse(arg("--options") ?? "{}");

const fileOf = (a) =>
  a === "debug-robot" ? path.join(shared, "avatars", "debug-robot.vrm") : path.join(repo, "tests", "fixtures", "avatars", `${a}.vrm`);

const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
const f2 = (x) => (Number.isFinite(x) ? x.toFixed(2) : "-");
const f0 = (x) => (Number.isFinite(x) ? x.toFixed(0) : "-");
const cell = (t) => (t.n ? `${f0(t.pct)}% (${t.n}) ${f0(t.medianMm)}` : "-");

const rows = [];
const totals = { on: measure.newScore(), off: measure.newScore() };
const started = performance.now();
console.log(
  "| avatar | clip | contact | face: within 2 cm (hand-frames) median gap mm | chest | hands | false touches | frames > 1 cm inside | max depth mm | alignment median mm (none) | touches tracked |",
);
console.log("| --- | --- | --- | --- | --- | --- | --- | ---: | ---: | ---: | ---: |");
for (const a of avatars) {
  const vrm = await measure.loadVrm(fileOf(a));
  const body = new measure.SkinBody(vrm);
  if (!body.hasBody || body.vertices.leftHand.length === 0) {
    console.log(`| ${a} | all | - | no skinned body or hands (rigid meshes only): not measurable | | | | | | | |`);
    continue;
  }
  const perAvatar = { on: measure.newScore(), off: measure.newScore() };
  for (const clip of clips) {
    const frames = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip}.json`), "utf8")).frames;
    const labels = measure.readLabels(repo, clip);
    for (const contact of [true, false]) {
      const rig = new HandRig(restPoseFromVRM(vrm), {
        ...extra,
        contact: { ...extra.contact, enabled: contact },
      });
      const m = measure.runClip({ vrm, body, rig, applyToVRM, frames });
      rig.free();
      const s = measure.score(m, labels);
      measure.score(m, labels, {}, totals[contact ? "on" : "off"]);
      measure.score(m, labels, {}, perAvatar[contact ? "on" : "off"]);
      const f = measure.figures(s);
      rows.push({ avatar: a, clip, contact, ...f });
      console.log(
        `| ${a} | ${clip} | ${contact ? "on" : "off"} | ${cell(f.face)} | ${cell(f.chest)} | ${cell(f.hand)} | ${f.falseTouch.n ? `${f0(f.falseTouch.pct)}% (${f.falseTouch.n})` : "-"} | ${f1(f.deep.pct)}% | ${f0(f.deep.maxMm)} | ${f2(f.alignmentMedianMm)} | ${f0(f.touchTracked)}% |`,
      );
    }
  }
  for (const k of ["on", "off"]) {
    const f = measure.figures(perAvatar[k]);
    rows.push({ avatar: a, clip: "all", contact: k === "on", ...f });
    console.log(
      `| **${a}** | all | ${k} | ${cell(f.face)} | ${cell(f.chest)} | ${cell(f.hand)} | ${f0(f.falseTouch.pct)}% (${f.falseTouch.n}) | ${f1(f.deep.pct)}% | ${f0(f.deep.maxMm)} | ${f2(f.alignmentMedianMm)} | ${f0(f.touchTracked)}% |`,
    );
  }
}
for (const k of ["on", "off"]) {
  const f = measure.figures(totals[k]);
  console.log(
    `| **all** | all | ${k} | ${cell(f.face)} | ${cell(f.chest)} | ${cell(f.hand)} | ${f0(f.falseTouch.pct)}% (${f.falseTouch.n}) | ${f1(f.deep.pct)}% | ${f0(f.deep.maxMm)} | ${f2(f.alignmentMedianMm)} | ${f0(f.touchTracked)}% |`,
  );
  rows.push({ avatar: "all", clip: "all", contact: k === "on", ...f });
}
console.log(`(${((performance.now() - started) / 1000).toFixed(0)} s)`);
if (asJson) {
  fs.mkdirSync(path.join(repo, "target"), { recursive: true });
  fs.writeFileSync(path.join(repo, "target", "skin-contact.json"), JSON.stringify(rows, null, 2));
  console.log("rows written to target/skin-contact.json");
}
