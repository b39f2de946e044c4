// What the leg scorers share (issue 51): eval/bench/score-legs.mjs (the bench's rendered leg
// clips, against their truth) and eval/walk-video.mjs (real video, no truth): forward kinematics
// of a VRM's legs with sole points, Kalidokit's legs on MediaPipe landmarks, and the statistics.

import { add, angle, cap, dot, fromVrm0, len, norm, percentile, PosedHumanoid, qrot, quatFromEulerXYZ, scale, sub } from "./scoring.mjs";
import { LEG_REST_BONES } from "./motions.mjs";

export const SIDES = ["left", "right"];

/** FK over a loaded VRM's normalized humanoid (rotations and the hips' position). */
export class Body extends PosedHumanoid {
  constructor(vrm) {
    super(vrm);
    this.hips = this.h.getNormalizedBoneNode("hips");
    this.hipsRest = this.hips.position.toArray();
    this.reset();
    const s = this.positions();
    this.rest = Object.fromEntries(LEG_REST_BONES.filter((b) => s[b]).map((b) => [b, s[b].p]));
    this.restFull = s;
    // Sole points at rest: the heel under the foot joint, the ball under the toes joint (or a
    // fifth of the leg ahead of the heel without toes), in each bone's frame.
    this.sole = {};
    for (const side of SIDES) {
      const foot = s[`${side}Foot`].p;
      const toes = s[`${side}Toes`]?.p;
      const legLen = len(sub(s[`${side}UpperLeg`].p, s[`${side}LowerLeg`].p)) + len(sub(s[`${side}LowerLeg`].p, foot));
      this.sole[side] = toes
        ? { heel: [0, -foot[1], 0], ball: { bone: `${side}Toes`, off: [0, -toes[1], 0] } }
        : { heel: [0, -foot[1], 0], ball: { bone: `${side}Foot`, off: [0, -foot[1], 0.2 * legLen] } };
    }
  }
  reset() {
    super.reset();
    this.hips.position.fromArray(this.hipsRest);
  }
  set(bones, hipsOffset) {
    super.set(bones);
    if (hipsOffset) this.hips.position.fromArray(add(this.hipsRest, hipsOffset));
  }
  save() {
    return { q: Object.fromEntries(this.names.map((n) => [n, this.h.getNormalizedBoneNode(n).quaternion.toArray()])), hips: this.hips.position.toArray() };
  }
  restore(s) {
    for (const [n, q] of Object.entries(s.q)) this.h.getNormalizedBoneNode(n).quaternion.fromArray(q);
    this.hips.position.fromArray(s.hips);
  }
  /** The legs of the current pose: per side hip joint, knee, ankle, sole points (room, meters); the hips' forward. */
  sample() {
    const s = this.positions();
    const out = { forward: qrot(s.hips.q, [0, 0, 1]) };
    for (const side of SIDES) {
      const foot = s[`${side}Foot`];
      const b = this.sole[side].ball;
      const heel = add(foot.p, qrot(foot.q, this.sole[side].heel));
      const ball = add(s[b.bone].p, qrot(s[b.bone].q, b.off));
      out[side] = { hip: s[`${side}UpperLeg`].p, knee: s[`${side}LowerLeg`].p, ankle: foot.p, soles: [heel, ball] };
    }
    return out;
  }
}

// ---- Kalidokit -------------------------------------------------------------------------------------
export const POSE_SWAP = [0, 4, 5, 6, 1, 2, 3, 8, 7, 10, 9, 12, 11, 14, 13, 16, 15, 18, 17, 20, 19, 22, 21, 24, 23, 26, 25, 28, 27, 30, 29, 32, 31];
export const mirrorPose = (lms, image) =>
  POSE_SWAP.map((j) => {
    const [x, y, z, v] = lms[j];
    return { x: image ? 1 - x : -x, y, z, visibility: v };
  });
export function kalidokitLegs(Kalidokit, p, rec) {
  const solved = Kalidokit.Pose.solve(mirrorPose(p.worldLandmarks, false), mirrorPose(p.landmarks, true), {
    runtime: "mediapipe", imageSize: { width: rec.width, height: rec.height }, enableLegs: true,
  });
  const bones = { hips: fromVrm0(quatFromEulerXYZ(solved.Hips.rotation)) };
  for (const side of SIDES) {
    for (const b of ["UpperArm", "LowerArm", "UpperLeg", "LowerLeg"]) bones[`${side}${b}`] = fromVrm0(quatFromEulerXYZ(solved[`${cap(side)}${b}`]));
  }
  return bones;
}

// ---- statistics ----------------------------------------------------------------------------------
export { percentile };
export const mean = (v) => (v.length ? v.reduce((a, b) => a + b, 0) / v.length : NaN);
export const kneeAngleOf = (l) => angle(sub(l.knee, l.hip), sub(l.ankle, l.knee));
/** A knee bent more than 10 degrees whose knee lies behind the hip-ankle line (against the hips' forward). */
export function bentBackwards(l, forward) {
  if (kneeAngleOf(l) < 10) return false;
  const u = norm(sub(l.ankle, l.hip));
  const k = sub(l.knee, l.hip);
  const off = sub(k, scale(u, dot(k, u)));
  return dot(off, forward) < 0;
}

