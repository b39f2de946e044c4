#!/usr/bin/env node
// What FaceLandmarker's mesh (not its blendshapes) says where the blendshapes fall short (issue 50):
//   - winks: each eye's opening from the mesh (the six-point eye aspect ratio of the flat layout's
//     faceMesh points: corners 33/133 and 263/362, lids 160 158 / 144 153 and 387 385 / 373 380;
//     x scaled by the image aspect) and the two eyes' ratio (smaller over larger), on the shared
//     ASL clips and the talking face (real faces: no wink) and on the bench's rendered clips (the
//     wink clip closes one eye fully: does the mesh?);
//   - the mouth: the inner lips' gap (13-14) over the mouth's width (61-291) against `jawOpen`, on
//     the talking face's labelled open and closed frames and on the ASL clips (closed mouths).
// Reads the recordings of eval/face-record.mjs (eval/face/CLIP.json) and eval/face-bench.mjs
// (eval/face-bench/AVATAR-CLIP.json); nothing is solved.
//
//   node eval/face-mesh-cues.mjs

import { existsSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO } from "./bench/common.mjs";

const at = (L, i) => (Array.isArray(L[i]) ? L[i] : [L[i].x, L[i].y, L[i].z]);
const EYES = [
  [33, 160, 158, 133, 153, 144],
  [263, 387, 385, 362, 380, 373],
];
function rows(file) {
  const r = JSON.parse(readFileSync(file, "utf8"));
  const aspect = r.width / r.height;
  const d = (L, a, b) => {
    const [A, B] = [at(L, a), at(L, b)];
    return Math.hypot((A[0] - B[0]) * aspect, A[1] - B[1]);
  };
  const ear = (L, [c1, u1, u2, c2, l2, l1]) => (d(L, u1, l1) + d(L, u2, l2)) / (2 * d(L, c1, c2));
  const shape = (f, n) => f.blendshapes.find(([k]) => k === n)?.[1] ?? NaN;
  return r.frames
    .filter((f) => f.landmarks && f.blendshapes)
    .map((f) => {
      const [a, b] = EYES.map((e) => ear(f.landmarks, e));
      return { frame: f.frame, ratio: Math.min(a, b) / Math.max(a, b), gap: d(f.landmarks, 13, 14) / d(f.landmarks, 61, 291), jaw: shape(f, "jawOpen") };
    });
}
const q = (xs, p) => [...xs].sort((a, b) => a - b)[Math.floor(p * (xs.length - 1))];
const f2 = (x) => x.toFixed(2);
const REAL = ["again", "eat", "please", "thanks", "brother", "hungry", "sister", "carphone"];
const real = REAL.map((c) => [c, join(REPO, "eval", "face", `${c}.json`)]).filter(([, p]) => existsSync(p));
if (real.length < REAL.length) console.error(`missing recordings (node eval/face-record.mjs): ${REAL.filter((c) => !real.some(([k]) => k === c)).join(", ")}`);

console.log("## The two eyes' openings from the mesh (smaller over larger)\n");
console.log("| data | frames | min | p5 | median |\n| --- | ---: | ---: | ---: | ---: |");
for (const [c, p] of real) {
  const r = rows(p).map((x) => x.ratio);
  console.log(`| ${c} (real) | ${r.length} | ${f2(q(r, 0))} | ${f2(q(r, 0.05))} | ${f2(q(r, 0.5))} |`);
}
for (const avatar of ["woman", "man", "child"]) {
  for (const clip of ["face-still", "face-blink", "face-wink", "face-turn"]) {
    const p = join(REPO, "eval", "face-bench", `${avatar}-${clip}.json`);
    if (!existsSync(p)) continue;
    const all = rows(p);
    const r = all.map((x) => x.ratio);
    // The wink clip (eval/bench/face-motions.mjs): the left eye held shut on frames 18-27, the right on 58-67.
    const held = clip === "face-wink" ? ` (held shut: ${all.filter((x) => (x.frame >= 18 && x.frame <= 27) || (x.frame >= 58 && x.frame <= 67)).map((x) => f2(x.ratio)).filter((v, i, a) => a.indexOf(v) === i).sort().join(" ")})` : "";
    console.log(`| ${avatar} ${clip} (bench)${held} | ${r.length} | ${f2(q(r, 0))} | ${f2(q(r, 0.05))} | ${f2(q(r, 0.5))} |`);
  }
}

const carphone = real.find(([c]) => c === "carphone");
if (carphone) {
  const lab = JSON.parse(readFileSync(join(REPO, "eval", "labels", "face.json"), "utf8")).carphone;
  const R = rows(carphone[1]);
  const show = (fr) => R.filter((x) => fr.includes(x.frame)).map((x) => `${x.frame}: ${f2(x.gap)} / ${f2(x.jaw)}`).join(", ");
  console.log("\n## The mouth: inner-lip gap over mouth width / jawOpen\n");
  console.log(`- talking face, open (labelled): ${show(lab.mouthOpen)}`);
  console.log(`- talking face, closed (labelled): ${show(lab.mouthClosed)}`);
  for (const [c, p] of real.filter(([c]) => c !== "carphone")) {
    const g = rows(p).map((x) => x.gap);
    console.log(`- ${c} (no open mouth labelled): gap median ${q(g, 0.5).toFixed(3)}, p95 ${q(g, 0.95).toFixed(3)}, max ${q(g, 1).toFixed(3)}`);
  }
}
