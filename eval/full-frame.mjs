// The full-frame comparison shared by eval/speed.mjs, eval/instructions.mjs and eval/ab.mjs:
// the ASL clips, Kalidokit's inputs and call for a frame, and handrig's options in Kalidokit's
// scope.

import { readFileSync } from "node:fs";

/** The four ASL clips' frames (pose and 0-2 hands of the same person), 250 in all. */
export function aslFrames(shared) {
  return ["eat", "thanks", "brother", "sister"].flatMap(
    (n) => JSON.parse(readFileSync(`${shared}/data/asl/${n}.json`, "utf8")).frames,
  );
}

/** A recorded [x, y, z(, visibility)] point as the {x, y, z, visibility} object Kalidokit takes. */
export const xyz = ([x, y, z, visibility]) => ({ x, y, z, visibility });

/** One ASL frame as Kalidokit's inputs (converted once, not timed). */
export function kalidokitFrame(f) {
  return {
    world: f.pose.worldLandmarks.map(xyz),
    image: f.pose.landmarks.map(xyz),
    // Kalidokit's side argument is the avatar side; MediaPipe's label is the mirrored one.
    hands: f.hands.map((h) => ({ points: h.landmarks.map(xyz), side: h.handedness === "Left" ? "Right" : "Left" })),
  };
}

const IMAGE = { runtime: "mediapipe", imageSize: { width: 640, height: 480 } };

/** Kalidokit's full frame: `Pose.solve` and `Hand.solve` per hand. Returns how many solved. */
export function kalidokitSolve(Kalidokit, k) {
  let solved = Kalidokit.Pose.solve(k.world, k.image, IMAGE) ? 1 : 0;
  for (const h of k.hands) solved += Kalidokit.Hand.solve(h.points, h.side) ? 1 : 0;
  return solved;
}

// "Kalidokit's scope": handrig's options with what Kalidokit does not do turned off (landmark
// filtering, fingertip alignment, self-contact, wrist limits, dropout easing, the torso), so
// that both turn the same frames into finger and arm rotations.
export const KALIDOKIT_SCOPE = Object.freeze({
  filter: { enabled: false },
  alignment: { enabled: false },
  contact: { enabled: false },
  arm: { wristLimits: false },
  dropout: { enabled: false },
  torso: "off",
});
