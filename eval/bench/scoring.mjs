// What eval/bench/score.mjs (arms and hands) and eval/bench/score-legs.mjs (legs) share: the
// solvers under test, loaded from a built package and eval/'s Kalidokit, and the small vector
// and quaternion math both score with (arrays: [x, y, z], quaternions [x, y, z, w]).
import { createRequire } from "node:module";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { REPO } from "./common.mjs";

/**
 * handrig from `pkg` (default: the repository's pkg/), its three-vrm adapter, the VRM loader
 * of the skin measure, and Kalidokit 1.1.5 (null with `noKalidokit`; exits with a message
 * when it is not installed).
 */
export async function loadSolvers({ pkg, noKalidokit }) {
  const pkgDir = pkg ?? join(REPO, "pkg");
  const { HandRig } = await import(pathToFileURL(join(pkgDir, "index.mjs")).href);
  const { restPoseFromVRM, applyToVRM } = await import(pathToFileURL(join(pkgDir, "three-vrm.js")).href);
  const { loadVrm } = await import(pathToFileURL(join(REPO, "tests", "node", "consumer", "skin-measure.mjs")).href);
  let Kalidokit = null;
  if (!noKalidokit) {
    try {
      Kalidokit = createRequire(join(REPO, "eval", "package.json"))("kalidokit/dist/kalidokit.umd.js");
    } catch (e) {
      console.error(`kalidokit not installed (${e.code ?? e.message}): run \`npm ci --prefix eval\` first (or pass --no-kalidokit)`);
      process.exit(1);
    }
  }
  return { pkgDir, HandRig, restPoseFromVRM, applyToVRM, loadVrm, Kalidokit };
}

export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
export const len = (a) => Math.hypot(a[0], a[1], a[2]);
export const norm = (a) => scale(a, 1 / len(a));
/** The angle between two vectors, degrees. */
export const angle = (a, b) => (Math.acos(Math.min(1, Math.max(-1, dot(norm(a), norm(b))))) * 180) / Math.PI;
export const mid = (a, b) => scale(add(a, b), 0.5);
/** The p-th percentile (0-100) of v, linear between ranks; NaN when empty. */
export const percentile = (v, p) => {
  if (!v.length) return NaN;
  const s = [...v].sort((a, b) => a - b);
  const rank = (p / 100) * (s.length - 1);
  const lo = Math.floor(rank);
  const hi = Math.ceil(rank);
  return s[lo] + (s[hi] - s[lo]) * (rank - lo);
};
/** `v` turned by the unit quaternion `q`. */
export const qrot = (q, v) => {
  const u = [q[0], q[1], q[2]];
  const t = scale(cross(u, v), 2);
  return add(add(v, scale(t, q[3])), cross(u, t));
};
/** three.js Quaternion.setFromEuler, order "XYZ". */
export const quatFromEulerXYZ = ({ x, y, z }) => {
  const [c1, c2, c3] = [Math.cos(x / 2), Math.cos(y / 2), Math.cos(z / 2)];
  const [s1, s2, s3] = [Math.sin(x / 2), Math.sin(y / 2), Math.sin(z / 2)];
  return [s1 * c2 * c3 + c1 * s2 * s3, c1 * s2 * c3 - s1 * c2 * s3, c1 * c2 * s3 + s1 * s2 * c3, c1 * c2 * c3 - s1 * s2 * s3];
};
/**
 * Kalidokit's rotations target VRM 0.x normalized bones (the model faces -Z); in the VRM 1.0
 * frame (faces +Z) that is a half turn about Y: negate x and z.
 */
export const fromVrm0 = (q) => [-q[0], q[1], -q[2], q[3]];
/** MediaPipe's camera axes (y down, z away) to the avatar's (y up, z toward the camera). */
export const toAvatar = ([x, y, z]) => [x, -y, -z];
export const cap = (s) => s[0].toUpperCase() + s.slice(1);

/** Forward kinematics over a loaded VRM's normalized humanoid (three-vrm's bone nodes). */
export class PosedHumanoid {
  constructor(vrm) {
    this.vrm = vrm;
    this.h = vrm.humanoid;
    this.names = Object.keys(this.h.humanBones).filter((n) => this.h.getNormalizedBoneNode(n));
    this.root = this.h.normalizedHumanBonesRoot;
    // three's classes, from the avatar's own nodes (no second copy of three imported).
    this.V = this.h.getNormalizedBoneNode("hips").position.constructor;
    this.Q = this.h.getNormalizedBoneNode("hips").quaternion.constructor;
  }
  /** Every bone's rotation back to the rest pose's. */
  reset() {
    for (const n of this.names) this.h.getNormalizedBoneNode(n).quaternion.identity();
  }
  /** Normalized bone rotations by name, [x, y, z, w]. */
  set(bones) {
    for (const [n, q] of Object.entries(bones)) this.h.getNormalizedBoneNode(n)?.quaternion.set(q[0], q[1], q[2], q[3]);
  }
  /** Every bone's world position and rotation now: { name: { p, q } }. */
  positions() {
    this.root.updateMatrixWorld(true);
    const out = {};
    const v = new this.V();
    const q = new this.Q();
    for (const n of this.names) {
      const node = this.h.getNormalizedBoneNode(n);
      node.getWorldPosition(v);
      node.getWorldQuaternion(q);
      out[n] = { p: [v.x, v.y, v.z], q: [q.x, q.y, q.z, q.w] };
    }
    return out;
  }
}
