#!/usr/bin/env node
// The mouth's filter speed (issue 50, src/face MOUTH_D_CUTOFF and MOUTH_BETA) by a replica of
// src/face's `aa` arithmetic (the neutral face over the first 2 s, One Euro on jawOpen and
// mouthClose, aa = 1.6 x (calibrated jawOpen - calibrated mouthClose); the mouth shapes' sum
// to 1 left out), no package, over the FaceLandmarker recordings: for each variant, the bench's
// talking clip (face-talk: aa >= 0.3 on the truth's open frames, <= 0.1 on its closed ones;
// the woman is the tuning half, the man and the child the report half), aa's move a frame on
// the ASL clips (tune and test halves: the price in jitter), and the talking-face clip's
// labelled frames (eval/labels/face.json, nothing tuned on it). A variant: {mc, beta, dc} (the
// mouth's min cutoff Hz, speed coefficient, speed-estimate cutoff Hz) or {off: true}.
//
//   node eval/face-mouth-tune.mjs ['[{}, {"dc":10,"beta":5}, {"off":true}]']
//   (after make eval-face and make eval-face-bench have recorded)

import { readFileSync } from "node:fs";
import { join } from "node:path";
import { REPO } from "./bench/common.mjs";
import { FACE_CLIPS, faceFrame } from "./bench/face-motions.mjs";

// The ASL halves of eval/face.mjs (not imported: that file runs its eval when loaded).
const TUNE = ["again", "eat", "please", "thanks"];
const TEST = ["brother", "hungry", "sister"];
const JAW = 24 + 1; // the recordings keep MediaPipe's `_neutral` first
const CLOSE = 26 + 1;
const alpha = (dt, fc) => 1 / (1 + 1 / (2 * Math.PI * fc) / dt);
function euro(mc, beta, dc) {
  let x = null;
  let dx = 0;
  return (v, dt) => {
    if (x === null || !dt) {
      x = v;
      dx = 0;
      return x;
    }
    dx += alpha(dt, dc) * ((v - x) / dt - dx);
    x += alpha(dt, mc + beta * Math.abs(dx)) * (v - x);
    return x;
  };
}
/** aa per frame (null without a face) for one variant. */
function aaSeries(frames, { mc = 2, beta = 1, dc = 1, off = false }) {
  const filters = [euro(mc, beta, dc), euro(mc, beta, dc)];
  const sum = [0, 0];
  const count = [0, 0];
  let t0 = null;
  let prev = null;
  return frames.map((f) => {
    if (!f.blendshapes) return null;
    const raw = [f.blendshapes[JAW][1], f.blendshapes[CLOSE][1]];
    t0 ??= f.timeMs;
    if (f.timeMs - t0 <= 2000 || count[0] === 0) {
      for (let k = 0; k < 2; k++) if (count[k] === 0 || raw[k] <= sum[k] / count[k] + 0.35) (sum[k] += raw[k]), count[k]++;
    }
    const neutral = [0, 1].map((k) => Math.min(sum[k] / count[k], 0.5));
    const dt = prev === null ? 0 : (f.timeMs - prev) / 1000;
    prev = f.timeMs;
    const v = off ? raw : raw.map((r, k) => filters[k](r, dt));
    const cal = (k) => Math.min(1, Math.max(0, (v[k] - neutral[k]) / (1 - neutral[k])));
    return Math.min(1, Math.max(0, 1.6 * (cal(0) - cal(1))));
  });
}

const variants = JSON.parse(process.argv[2] ?? '[{}, {"dc":10,"beta":5}, {"off":true}]');
const talk = FACE_CLIPS.find((c) => c.id === "face-talk");
const labels = JSON.parse(readFileSync(join(REPO, "eval", "labels", "face.json"), "utf8"));
const share = (xs, p) => (xs.filter(p).length / xs.length).toFixed(2);
const rec = (...p) => JSON.parse(readFileSync(join(REPO, "eval", ...p), "utf8"));
console.log("| variant | bench talk, woman (tune): open / closed | man + child (report) | ASL tune: aa move p95 / max | ASL test | talking face: open / closed |");
console.log("| --- | --- | --- | --- | --- | --- |");
for (const v of variants) {
  const row = [JSON.stringify(v)];
  for (const avatars of [["woman"], ["man", "child"]]) {
    const open = [];
    const shut = [];
    for (const a of avatars) {
      aaSeries(rec("face-bench", `${a}-face-talk.json`).frames, v).forEach((x, i) => {
        const t = faceFrame(talk, i).expressions.aa ?? 0;
        if (t >= 0.8) open.push(x);
        else if (t === 0) shut.push(x);
      });
    }
    row.push(`${share(open, (x) => x >= 0.3)} / ${share(shut, (x) => x <= 0.1)}`);
  }
  for (const clips of [TUNE, TEST]) {
    const moves = [];
    for (const c of clips) {
      const aa = aaSeries(rec("face", `${c}.json`).frames, v);
      for (let i = 1; i < aa.length; i++) if (aa[i] !== null && aa[i - 1] !== null) moves.push(Math.abs(aa[i] - aa[i - 1]));
    }
    moves.sort((a, b) => a - b);
    row.push(`${moves[Math.floor(0.95 * moves.length)].toFixed(3)} / ${moves[moves.length - 1].toFixed(3)}`);
  }
  const aa = aaSeries(rec("face", "carphone.json").frames, v);
  const l = labels.carphone;
  row.push(`${share(l.mouthOpen.map((k) => aa[k]), (x) => x >= 0.3)} / ${share(l.mouthClosed.map((k) => aa[k]), (x) => x <= 0.1)}`);
  console.log(`| ${row.join(" | ")} |`);
}
