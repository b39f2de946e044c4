// Stylized proportions of a MakeHuman body (issue 52): a bigger head, a deeper or wider chest,
// longer or shorter arms, larger hands, made by deforming the rest mesh and its skeleton before
// the T-pose bake, so that the result is skinned like the human bodies.
//
// Each bone b gets an affine map A_b(p) = A_parent(head_b) + S_b (p - head_b): its head follows
// its parent's map (the skeleton stays connected) and S_b is the bone's own linear change
// (identity unless the style sets one), applied about its head joint. Vertices move by the
// blend of their bones' maps with their skin weights (all influences), as linear-blend skinning
// blends poses; bone heads move by A_parent, tails by A_b. Frames: the base mesh's (+Y up, the
// body faces +Z, its left at +X), in the A-pose it is modeled in.

import { add, normalize, scale, sub } from "./math.mjs";

const I = [1, 0, 0, 0, 1, 0, 0, 0, 1];
const diag = (x, y, z) => [x, 0, 0, 0, y, 0, 0, 0, z];
const apply3 = (m, v) => [
  m[0] * v[0] + m[1] * v[1] + m[2] * v[2],
  m[3] * v[0] + m[4] * v[1] + m[5] * v[2],
  m[6] * v[0] + m[7] * v[1] + m[8] * v[2],
];
/** Stretch by k along the unit direction u: I + (k - 1) u u^T. */
const along = (u, k) => I.map((x, i) => x + (k - 1) * u[Math.floor(i / 3)] * u[i % 3]);

/**
 * The styles: one defining proportion each (a factor), nothing else changed.
 *   head: the head (and eyes) scaled about the head joint (top of the neck);
 *   chestDepth / chestWidth: spine_02, spine_03 and the clavicles scaled front-to-back /
 *     sideways about their joints (spine_01 by the square root, a smooth waist), the arms
 *     carried out with the shoulders;
 *   arms: upper arm and forearm stretched along their length (hands unchanged);
 *   hands: hand and fingers scaled about the wrist.
 */
export function linearMaps(skeleton, style) {
  const S = new Map();
  const set = (name, m) => S.set(name, m);
  const bone = (n) => skeleton.find((b) => b.name === n);
  if (style.head) {
    for (const n of ["head", "eye_l", "eye_r"]) set(n, diag(style.head, style.head, style.head));
  }
  for (const [key, axis] of [["chestDepth", 2], ["chestWidth", 0]]) {
    const k = style[key];
    if (!k) continue;
    const f = (x) => diag(...[0, 1, 2].map((a) => (a === axis ? x : 1)));
    set("spine_01", f(Math.sqrt(k)));
    for (const n of ["spine_02", "spine_03", "clavicle_l", "clavicle_r"]) set(n, f(k));
  }
  if (style.arms) {
    for (const s of ["l", "r"]) {
      for (const n of [`upperarm_${s}`, `lowerarm_${s}`]) {
        const b = bone(n);
        set(n, along(normalize(sub(b.tail, b.head)), style.arms));
      }
    }
  }
  if (style.hands) {
    for (const b of skeleton) {
      if (/^(hand|thumb|index|middle|ring|pinky)(_0[123])?_[lr]$/.test(b.name)) set(b.name, diag(style.hands, style.hands, style.hands));
    }
  }
  return S;
}

/**
 * Deforms rest `positions` (Float64Array, every vertex of the base mesh) and the skeleton (parent
 * first) by `style`; `weights[v]` = [[boneIndex, w], ...]. Returns new positions and a new
 * skeleton (same bones, moved heads and tails). Vertices without weights (helper geometry
 * that is not written) stay.
 */
export function stylize(positions, skeleton, weights, style) {
  const S = linearMaps(skeleton, style);
  for (const name of S.keys()) if (!skeleton.some((b) => b.name === name)) throw new Error(`stylize: no bone ${name}`);
  // A_b(p) = origin_b + S_b (p - head_b), origin_b = A_parent(head_b).
  const maps = [];
  for (const b of skeleton) {
    const parent = b.parentIndex >= 0 ? maps[b.parentIndex] : null;
    const origin = parent ? parent.apply(b.head) : b.head;
    const m = S.get(b.name) ?? I;
    maps[b.index] = { apply: (p) => add(origin, apply3(m, sub(p, b.head))) };
  }
  const out = Float64Array.from(positions);
  for (let v = 0; v < weights.length; v++) {
    const list = weights[v];
    if (!list.length) continue;
    const p = [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]];
    let acc = [0, 0, 0];
    let total = 0;
    for (const [bi, w] of list) {
      acc = add(acc, scale(maps[bi].apply(p), w));
      total += w;
    }
    acc = scale(acc, 1 / total);
    out[3 * v] = acc[0];
    out[3 * v + 1] = acc[1];
    out[3 * v + 2] = acc[2];
  }
  const moved = skeleton.map((b) => ({
    ...b,
    head: b.parentIndex >= 0 ? maps[b.parentIndex].apply(b.head) : maps[b.index].apply(b.head),
    tail: maps[b.index].apply(b.tail),
  }));
  return { positions: out, skeleton: moved };
}
