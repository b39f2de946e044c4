// Arms from hands alone (issue 48): how far the wrists handrig places from the hands' image
// position and size (no pose: `handsOnly`) are from the wrists it places from the pose, on the
// shared sign-language clips that have both. Prints a markdown table.
//
//   make pkg                      # or any built package: --pkg DIR
//   node eval/hand-wrists.mjs [--pkg DIR] [--avatar FILE.vrm]
//
// Per clip, two rigs on the same avatar (default the generated woman, 1.0 VRM) with every
// default option: one solves the frames as recorded (pose and hands), the other the same hands
// without the pose (`{ timeMs, hands, imageAspect }`, the HandLandmarker quick start). Per
// side-frame where both place the arm (an IK target on that side in both): the distance between
// the avatar's hand bones (cm, in the avatar's scale), and the angle between the two
// shoulder-to-hand directions (upper-arm joint to hand bone, degrees), and the distance per
// axis (across, up, forward: depth is where the two disagree most). Two framings:
//   * assumed: the options' defaults (a webcam's 60° field of view, the shoulders 0.7 m away at
//     0.8 of the image height, body scale avatar arm / 0.52 m);
//   * from the clip: `handsOnly.distance` and `handsOnly.shoulderY` as the clip's pose shows the
//     shoulders (median over its frames: the shoulder line's image height, and the distance at
//     which the pose's shoulder width spans its image width with the 60° field of view), and
//     the body scale the pose rig calibrated: what an app that saw the user once can set.

import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, "..");
const shared = resolve(root, "../shared");
const require = createRequire(import.meta.url);

const args = process.argv.slice(2);
const arg = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const { HandRig } = require(resolve(arg("--pkg", join(root, "pkg"))));
const avatar = readFileSync(arg("--avatar", join(root, "tests", "fixtures", "avatars", "woman-vrm1.vrm")));

const CLIPS = ["again", "brother", "eat", "hungry", "please", "sister", "thanks"];
const FOV = 1.05;

const median = (xs) => quantile(xs, 0.5);
function quantile(xs, q) {
  if (xs.length === 0) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  const at = (s.length - 1) * q;
  const lo = Math.floor(at);
  return s[lo] + (s[Math.min(lo + 1, s.length - 1)] - s[lo]) * (at - lo);
}
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len = (a) => Math.hypot(a[0], a[1], a[2]);
const angle = (a, b) => (Math.acos(Math.max(-1, Math.min(1, (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (len(a) * len(b))))) * 180) / Math.PI;
const xy = (p) => (Array.isArray(p) ? p : [p.x, p.y, p.z]);

/** The clip's shoulders as its pose shows them (see the header). */
function framing(clip) {
  const aspect = clip.width / clip.height;
  const f = 0.5 / Math.tan(FOV / 2);
  const ys = [];
  const ds = [];
  for (const fr of clip.frames) {
    if (!fr.pose?.landmarks || !fr.pose?.worldLandmarks) continue;
    const [l, r] = [xy(fr.pose.landmarks[11]), xy(fr.pose.landmarks[12])];
    const [wl, wr] = [xy(fr.pose.worldLandmarks[11]), xy(fr.pose.worldLandmarks[12])];
    ys.push((l[1] + r[1]) / 2);
    ds.push((f * len(sub(wl, wr))) / Math.hypot((l[0] - r[0]) * aspect, l[1] - r[1]));
  }
  return { shoulderY: median(ys), distance: median(ds) };
}

function run(clip, handsOnly) {
  const withPose = HandRig.fromVrm(avatar);
  const handsRig = HandRig.fromVrm(avatar, handsOnly ? { handsOnly: handsOnly.options, calibration: handsOnly.calibration } : {});
  const imageAspect = clip.width / clip.height;
  const dist = [];
  const dir = [];
  const axes = [[], [], []];
  for (const fr of clip.frames) {
    const a = structuredClone(withPose.solve(fr));
    const b = handsRig.solve({ timeMs: fr.timeMs, hands: fr.hands, imageAspect });
    for (const side of ["left", "right"]) {
      if (!a.ikTargets[side] || !b.ikTargets[side]) continue;
      const ha = a.worldPositions[`${side}Hand`];
      const hb = b.worldPositions[`${side}Hand`];
      const sa = a.worldPositions[`${side}UpperArm`];
      const sb = b.worldPositions[`${side}UpperArm`];
      dist.push(len(sub(ha, hb)) * 100);
      sub(ha, hb).forEach((d, k) => axes[k].push(Math.abs(d) * 100));
      dir.push(angle(sub(ha, sa), sub(hb, sb)));
    }
  }
  const scale = withPose.bodyScale;
  withPose.free();
  handsRig.free();
  return { dist, dir, axes, scale };
}

const rows = [];
const all = { assumed: { dist: [], dir: [], axes: [[], [], []] }, clip: { dist: [], dir: [], axes: [[], [], []] } };
for (const name of CLIPS) {
  const clip = JSON.parse(readFileSync(join(shared, "data", "asl", `${name}.json`), "utf8"));
  const assumed = run(clip, null);
  const fr = framing(clip);
  const fitted = run(clip, { options: { distance: fr.distance, shoulderY: fr.shoulderY }, calibration: { bodyScale: assumed.scale } });
  for (const [k, r] of [["assumed", assumed], ["clip", fitted]]) {
    all[k].dist.push(...r.dist);
    all[k].dir.push(...r.dir);
    r.axes.forEach((v, i) => all[k].axes[i].push(...v));
  }
  rows.push([name, assumed.dist.length, assumed, fitted, fr]);
}

const f1 = (x) => (Number.isFinite(x) ? x.toFixed(1) : "-");
console.log(`handrig wrists from hands alone vs from the pose (avatar ${arg("--avatar", "woman-vrm1.vrm").split("/").pop()}):\n`);
console.log("| clip | side-frames | assumed framing: distance median / p90 (cm) | direction median / p90 (°) | framing from the clip: distance median / p90 (cm) | direction median / p90 (°) | clip's shoulders: distance (m), image height |");
console.log("| --- | --- | --- | --- | --- | --- | --- |");
for (const [name, n, a, c, fr] of rows) {
  console.log(
    `| ${name} | ${n} | ${f1(median(a.dist))} / ${f1(quantile(a.dist, 0.9))} | ${f1(median(a.dir))} / ${f1(quantile(a.dir, 0.9))} | ${f1(median(c.dist))} / ${f1(quantile(c.dist, 0.9))} | ${f1(median(c.dir))} / ${f1(quantile(c.dir, 0.9))} | ${fr.distance.toFixed(2)}, ${fr.shoulderY.toFixed(2)} |`,
  );
}
const a = all.assumed;
const c = all.clip;
console.log(
  `| all | ${a.dist.length} | ${f1(median(a.dist))} / ${f1(quantile(a.dist, 0.9))} | ${f1(median(a.dir))} / ${f1(quantile(a.dir, 0.9))} | ${f1(median(c.dist))} / ${f1(quantile(c.dist, 0.9))} | ${f1(median(c.dir))} / ${f1(quantile(c.dir, 0.9))} | |`,
);
console.log(
  `\nPer axis, median |difference| (cm, the avatar's x across, y up, z forward): assumed framing ${a.axes.map((v) => f1(median(v))).join(" / ")}; ` +
    `framing from the clip ${c.axes.map((v) => f1(median(v))).join(" / ")}.`,
);
