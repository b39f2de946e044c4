#!/usr/bin/env node
// The lean in depth MediaPipe's world landmarks give a body (issue 51, the camera's pitch): per
// leg recording (eval/bench/clips/AVATAR-CLIP-tasks.json, level and pitched), the median over
// its frames of the lean toward the camera of the hips-to-shoulders line and of the hips'
// midpoint to the ankles' midpoint (degrees, camera axes: atan2 of depth over height), and the
// range and last value of the pitch handrig estimates from it (src/pipeline/legs.rs,
// `Legs::estimate_tilt`, replayed here: both legs spanning 0.95 of thigh plus shin, a running
// mean over the first 2 s then an exponential average with a 2 s time constant, less the 8.5
// degrees of LEVEL_LEAN; before the dead zone).
//
//   node eval/bench/legs-lean.mjs [--avatars woman,man,child,primitive] [--pitched]

import { existsSync, readFileSync } from "node:fs";
import { parseArgs } from "node:util";
import { LEG_AVATARS, recordingFile } from "./common.mjs";
import { FPS, LEG_CLIPS, PITCHED_LEG_CLIPS } from "./motions.mjs";

const { values: o } = parseArgs({ options: { avatars: { type: "string" }, pitched: { type: "boolean" } } });
const avatars = (o.avatars ?? LEG_AVATARS.join(",")).split(",");
const clips = o.pitched ? PITCHED_LEG_CLIPS : LEG_CLIPS;
const DEG = 180 / Math.PI;
const LEVEL_LEAN = 8.5;
const TILT_SECONDS = 2;
const STRAIGHT = 0.95;

const mid = (a, b) => [0, 1, 2].map((i) => (a[i] + b[i]) / 2);
const sub = (a, b) => [0, 1, 2].map((i) => a[i] - b[i]);
const dist = (a, b) => Math.hypot(...sub(a, b));
const median = (v) => {
  const s = [...v].sort((a, b) => a - b);
  return s.length ? s[Math.floor(s.length / 2)] : NaN;
};
const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");

console.log("| recording | frames with a pose | torso lean (median) | legs' lean (median) | estimate, min / max / last (deg) |");
console.log("| --- | ---: | ---: | ---: | --- |");
for (const avatar of avatars) {
  for (const clip of clips) {
    const file = recordingFile(avatar, clip, "tasks");
    if (!existsSync(file)) continue;
    const rec = JSON.parse(readFileSync(file, "utf8"));
    const torso = [];
    const legs = [];
    let tilt = LEVEL_LEAN / DEG;
    let seen = 0;
    const est = [];
    const dt = 1 / FPS;
    for (const f of rec.frames) {
      const w = f.pose?.worldLandmarks;
      if (!w) continue;
      const t = sub(mid(w[11], w[12]), mid(w[23], w[24]));
      const l = sub(mid(w[27], w[28]), mid(w[23], w[24]));
      torso.push(Math.atan2(-t[2], -t[1]) * DEG);
      legs.push(Math.atan2(l[2], l[1]) * DEG);
      const straight = (h, k, a) => dist(w[h], w[a]) >= STRAIGHT * (dist(w[h], w[k]) + dist(w[k], w[a]));
      if (straight(23, 25, 27) && straight(24, 26, 28) && l[1] > 0) {
        seen = Math.min(seen + dt, TILT_SECONDS);
        tilt += Math.min(1, dt / Math.max(seen, dt)) * (Math.atan2(l[2], l[1]) - tilt);
      }
      est.push(tilt * DEG - LEVEL_LEAN);
    }
    const range = est.length ? `${f1(Math.min(...est))} / ${f1(Math.max(...est))} / ${f1(est.at(-1))}` : "-";
    console.log(`| ${avatar}-${clip.id} | ${legs.length} | ${f1(median(torso))} | ${f1(median(legs))} | ${range} |`);
  }
}
