#!/usr/bin/env node
// Frames where both hands are near each other and near the face (issue 52's speed figure):
// writes eval/frames/hands-near-face.json, read by eval/speed.mjs and eval/instructions.mjs
// (`--frames eval/frames/hands-near-face.json`).
//
//   node eval/near-face-frames.mjs [--check]
//
// None of the shared clips has such a frame (over the seven clips, every frame with two hands
// has them at least 1.05 head breadths, ear to ear in the image, from the pose's face points),
// so they are constructed from real ones: each frame of the four face clips (eat, thanks,
// brother, sister) whose signer's right hand is within one head breadth of the face is kept
// with its right arm and hand as recorded, and its left arm and hand replaced by the right
// ones mirrored about the body's midline (the shoulders' midpoint; image and pose world x
// mirrored, the pose's left/right landmarks swapped, the hand's world landmarks' x negated,
// its handedness swapped): both hands then meet at the mouth, chin or forehead as two hands
// would. Kept: the frames where the two hands' nearest image landmarks are within half a head
// breadth of each other and each hand within half a head breadth of a face point. Numbers
// rounded to 5 decimals; `timeMs` renumbered at 30 fps so that the set plays as one clip.
// --check: exit 1 when the committed file differs from a fresh build.

import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, "..");
const shared = path.resolve(process.env.HANDRIG_SHARED || path.join(repo, "..", "shared"));
export const NEAR_FACE_FILE = path.join(here, "frames", "hands-near-face.json");

const CLIPS = ["eat", "thanks", "brother", "sister"];
const PAIRS = [[11, 12], [13, 14], [15, 16], [17, 18], [19, 20], [21, 22], [23, 24], [25, 26], [27, 28], [29, 30], [31, 32], [1, 4], [2, 5], [3, 6], [7, 8], [9, 10]];
const ARM = new Set([13, 15, 17, 19, 21]); // the signer's left elbow, wrist, pinky, index, thumb (image right)
const round = (x) => Math.round(x * 1e5) / 1e5;

function dist(a, b) {
  return Math.hypot(a[0] - b[0], a[1] - b[1]);
}

/** Image-space nearness of the frame's hands, in head breadths (ear to ear). */
export function nearness(f, width, height) {
  const px = ([x, y]) => [x * width, y * height];
  const P = f.pose.landmarks.map(px);
  const breadth = dist(P[7], P[8]);
  const hands = f.hands.map((h) => h.landmarks.map(px));
  let between = Infinity;
  for (const a of hands[0] ?? []) for (const b of hands[1] ?? []) between = Math.min(between, dist(a, b));
  const face = hands.map((h) => Math.min(...h.flatMap((a) => P.slice(0, 11).map((q) => dist(a, q)))));
  return { between: between / breadth, face: face.map((d) => d / breadth) };
}

/** The frame with its left arm and hand replaced by the mirrored right ones. */
function mirrored(f) {
  const right = f.hands.find((h) => h.handedness === "Left"); // the signer's right hand
  const img = f.pose.landmarks;
  const world = f.pose.worldLandmarks;
  const cx = (img[11][0] + img[12][0]) / 2;
  const cw = (world[11][0] + world[12][0]) / 2;
  const swap = new Map();
  for (const [a, b] of PAIRS) swap.set(a, b), swap.set(b, a);
  // Landmark i of the signer's left arm takes the mirror of its right-side partner.
  const pose = (list, c) =>
    list.map((p, i) => (ARM.has(i) ? [2 * c - list[swap.get(i)][0], ...list[swap.get(i)].slice(1)] : p.slice()));
  const left = {
    handedness: "Right",
    score: right.score,
    landmarks: right.landmarks.map(([x, ...rest]) => [2 * cx - x, ...rest]),
    worldLandmarks: right.worldLandmarks.map(([x, ...rest]) => [-x, ...rest]),
  };
  return { hands: [right, left], pose: { landmarks: pose(img, cx), worldLandmarks: pose(world, cw) } };
}

export function build() {
  const frames = [];
  const sources = [];
  for (const clip of CLIPS) {
    const rec = JSON.parse(fs.readFileSync(path.join(shared, "data", "asl", `${clip}.json`), "utf8"));
    rec.frames.forEach((f, i) => {
      if (!f.pose || !f.hands.some((h) => h.handedness === "Left")) return;
      const one = nearness({ ...f, hands: f.hands.filter((h) => h.handedness === "Left") }, rec.width, rec.height);
      if (one.face[0] > 1) return;
      const m = mirrored(f);
      const n = nearness(m, rec.width, rec.height);
      if (!(n.between <= 0.5 && Math.max(...n.face) <= 0.5)) return;
      const r = (list) => list.map((p) => p.map(round));
      frames.push({
        timeMs: round((1000 * frames.length) / 30),
        hands: m.hands.map((h) => ({ handedness: h.handedness, score: round(h.score), landmarks: r(h.landmarks), worldLandmarks: r(h.worldLandmarks) })),
        pose: { landmarks: r(m.pose.landmarks), worldLandmarks: r(m.pose.worldLandmarks) },
      });
      sources.push({ clip, frame: i, between: round(n.between), face: n.face.map(round) });
    });
  }
  return {
    about:
      "Both hands near each other and near the face (issue 52): frames of the shared ASL clips eat, thanks, brother, sister whose signer's right hand is within one head breadth of the face, the left arm and hand replaced by the right ones mirrored about the shoulders' midpoint; kept where the hands are within half a head breadth (ear to ear, image) of each other and of the face. Built by eval/near-face-frames.mjs.",
    width: 640,
    height: 480,
    sources,
    frames,
  };
}

/** The committed frame set as rig.solve inputs ({ timeMs, hands, pose }). */
export function nearFaceFrames(file = NEAR_FACE_FILE) {
  return JSON.parse(fs.readFileSync(file, "utf8")).frames;
}

if (process.argv[1] && path.resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const text = `${JSON.stringify(build())}\n`;
  if (process.argv.includes("--check")) {
    const same = fs.existsSync(NEAR_FACE_FILE) && fs.readFileSync(NEAR_FACE_FILE, "utf8") === text;
    console.log(same ? "same" : "DIFFERS: run node eval/near-face-frames.mjs");
    process.exit(same ? 0 : 1);
  }
  fs.mkdirSync(path.dirname(NEAR_FACE_FILE), { recursive: true });
  fs.writeFileSync(NEAR_FACE_FILE, text);
  const d = JSON.parse(text);
  const by = {};
  for (const s of d.sources) by[s.clip] = (by[s.clip] ?? 0) + 1;
  console.log(`${path.relative(repo, NEAR_FACE_FILE)}: ${d.frames.length} frames (${Object.entries(by).map(([c, n]) => `${c} ${n}`).join(", ")}), ${(text.length / 1e3).toFixed(0)} KB`);
}
