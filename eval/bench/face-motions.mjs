// The face clips of the bench (issue 50): known expressions, gaze and head motion on the
// generated avatars' faces (tools/avatars/face.mjs), keyframed as VRM 1.0 expression weights,
// look-at yaw and pitch (degrees, VRM's convention: yaw > 0 toward the avatar's left, pitch > 0
// up) and the head's turn (degrees: yaw > 0 toward the avatar's left, pitch > 0 a nod down;
// 40% on the neck, 60% on the head). Plain JavaScript: the renderer (render-page.js) and the
// scorer (eval/face-bench.mjs) import this one file, so the truth is this code.
//
//   import { FACE_CLIPS, faceFrame } from "./face-motions.mjs";
//   faceFrame(FACE_CLIPS[0], 12) // -> { expressions: { blink: 1, ... }, lookAt: [yaw, pitch], head: [yaw, pitch], bones: {...} }

import { qAxis, qMul } from "./motions.mjs";

// Keys: [frame, value]; linear between keys, held before the first and after the last.
function track(keys, i) {
  if (i <= keys[0][0]) return keys[0][1];
  for (let k = 1; k < keys.length; k++) {
    const [f1, v1] = keys[k];
    if (i <= f1) {
      const [f0, v0] = keys[k - 1];
      return v0 + ((v1 - v0) * (i - f0)) / (f1 - f0);
    }
  }
  return keys[keys.length - 1][1];
}
/** A pulse: 0, ramping to `peak` over `up` frames from `at`, held `hold` frames, back over `down`. */
const pulse = (at, up, hold, down, peak = 1) => [[at, 0], [at + up, peak], [at + up + hold, peak], [at + up + hold + down, 0]];
const pulses = (list) => list.flatMap((p) => pulse(...p));

/**
 * Each clip: `tracks` of expression weights (`expr.NAME`), look-at (`lookYaw`, `lookPitch`) and
 * head (`headYaw`, `headPitch`). A blink closes in 2 frames, stays closed 3, opens in 4 (a real
 * blink lasts 100-300 ms).
 */
export const FACE_CLIPS = [
  { id: "face-still", frames: 60, tracks: {} },
  { id: "face-blink", frames: 100, tracks: { "expr.blink": pulses([[15, 2, 3, 4], [45, 2, 3, 4], [75, 2, 6, 4]]) } },
  { id: "face-wink", frames: 90, tracks: { "expr.blinkLeft": pulse(15, 3, 10, 4), "expr.blinkRight": pulse(55, 3, 10, 4) } },
  { id: "face-aa", frames: 100, tracks: { "expr.aa": pulses([[10, 4, 20, 4], [55, 4, 20, 4]]) } },
  { id: "face-ou", frames: 80, tracks: { "expr.ou": pulses([[10, 4, 20, 4], [45, 4, 20, 4]]) } },
  // Talking: the jaw opening and closing at a syllable rate (4-5 a second: open in 1-2 frames,
  // held 1-4, shut in 2-3, closed 2-5 frames between; a pause of 9), scored on its own
  // (`talk`: every frame counts, a closed one right after an open one too).
  {
    id: "face-talk",
    frames: 120,
    talk: true,
    tracks: { "expr.aa": pulses([[8, 2, 2, 2], [17, 2, 1, 2], [25, 2, 3, 2], [35, 1, 2, 2], [43, 2, 2, 3], [61, 2, 4, 2], [72, 2, 1, 2], [80, 2, 2, 2], [89, 1, 2, 2], [97, 2, 3, 2], [107, 2, 2, 2]]) },
  },
  { id: "face-smile", frames: 80, tracks: { "expr.happy": pulses([[10, 6, 25, 6]]) } },
  { id: "face-look", frames: 100, tracks: { lookYaw: [[10, 0], [16, 20], [40, 20], [50, -20], [74, -20], [80, 0]] } },
  {
    id: "face-turn",
    frames: 140,
    tracks: {
      headYaw: [[10, 0], [25, 25], [40, 25], [60, -25], [75, -25], [90, 0]],
      headPitch: [[90, 0], [100, 15], [112, 15], [124, -12], [134, -12], [140, 0]],
    },
  },
];

export const faceClipById = (id) => FACE_CLIPS.find((c) => c.id === id);

/** The truth of frame i: expression weights, look-at and head angles, and the bones to pose. */
export function faceFrame(clip, i) {
  const expressions = {};
  let lookAt = [0, 0];
  let head = [0, 0];
  for (const [key, keys] of Object.entries(clip.tracks)) {
    const v = track(keys, i);
    if (key.startsWith("expr.")) expressions[key.slice(5)] = v;
    else if (key === "lookYaw") lookAt = [v, lookAt[1]];
    else if (key === "lookPitch") lookAt = [lookAt[0], v];
    else if (key === "headYaw") head = [v, head[1]];
    else if (key === "headPitch") head = [head[0], v];
  }
  // The head's turn: yaw about +Y, then the nod about +X (a nod down turns +Z toward -Y).
  const turn = (share) => qMul(qAxis("y", share * head[0]), qAxis("x", share * head[1]));
  return { expressions, lookAt, head, bones: { neck: turn(0.4), head: turn(0.6) } };
}

/** The arms of the face clips: hanging at the sides (the T-pose's arms would frame the face). */
export const FACE_ARMS = {
  rightUpperArm: qAxis("z", 75),
  leftUpperArm: qAxis("z", -75),
};
