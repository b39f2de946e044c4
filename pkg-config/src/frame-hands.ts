// Packing a frame's hands into the rig's flat input (LAYOUT.input.hands): handrig's own list
// `[{ handedness, score?, worldLandmarks, landmarks? }]`, tasks-vision's HandLandmarkerResult,
// legacy Hands results, and the hands of legacy and tasks-vision Holistic results.

import { at, describe, fail, isFiniteNumber, isObject, isView, notFinite, path, type Bag } from "./errors.js";
import { HAND_POINTS, LI, MAX_HANDS } from "./layout.js";
import { packPoints } from "./points.js";

/**
 * "Left" / "Right" (either case), a category { categoryName | label, score }, or tasks-vision's
 * [category] (the first, best one). Returns 0 for "Left", 1 for "Right", plus 2 when the
 * category carried a score, which is then written to `input[scoreAt]` (scores go straight into
 * the Float32Array: a double kept in a JS array or returned would be boxed, a per-frame
 * allocation).
 */
function readHandedness(v: unknown, fa: string, fi: number, fb: string, input: Float32Array, scoreAt: number): number {
  let item = v;
  if (Array.isArray(v)) {
    if (v.length === 0) fail(path(fa, fi, fb), "is an empty array (expected [{ categoryName, score }])");
    item = v[0];
  }
  let label = item;
  let scored = 0;
  if (isObject(item)) {
    const name = item.categoryName;
    label = name !== undefined && name !== null ? name : item.label;
    const score = item.score;
    if (score !== undefined && score !== null) {
      if (!isFiniteNumber(score)) notFinite(score, `${path(fa, fi, fb)}.score`);
      input[scoreAt] = score;
      scored = 2;
    }
  }
  if (label === "Left" || label === "left") return scored;
  if (label === "Right" || label === "right") return scored + 1;
  if (typeof label !== "string") {
    fail(path(fa, fi, fb), `must be "Left" or "Right" (or a category { categoryName, score }), got ${describe(label)}`);
  }
  return fail(path(fa, fi, fb), `must be "Left" or "Right", got ${JSON.stringify(label)}`);
}

function checkScore(score: unknown, fa: string, fi: number, fb: string): void {
  if (!isFiniteNumber(score)) notFinite(score, path(fa, fi, fb));
  if (score < 0 || score > 1) fail(path(fa, fi, fb), `must be in 0..1, got ${score}`);
}

/**
 * One hand into slot `slot`: world and/or image landmarks (either may be absent, not both).
 * Field paths: `path(wa, fi, wb)` and `path(ia, fi, ib)`.
 */
function packHand(
  input: Float32Array,
  slot: number,
  label: number,
  world: unknown,
  image: unknown,
  fi: number,
  wa: string,
  wb: string,
  ia: string,
  ib: string,
): void {
  const o = LI.hands + slot * LI.handStride;
  const H = LI.hand;
  input[o + H.handedness] = label;
  const hasImage = image !== undefined && image !== null;
  const hasWorld = world !== undefined && world !== null;
  if (!hasWorld && !hasImage) {
    fail(path(wa, fi, wb), "is missing (21 points [x, y, z] in meters, or image landmarks)");
  }
  if (hasImage) {
    at(ia, fi, ib);
    packPoints(image, input, o + H.image, HAND_POINTS, 3, ia, fi, ib);
  }
  if (hasWorld) {
    at(wa, fi, wb);
    packPoints(world, input, o + H.world, HAND_POINTS, 3, wa, fi, wb);
  }
  input[o + H.hasWorld] = hasWorld ? 1 : 0;
  input[o + H.hasImage] = hasImage ? 1 : 0;
}

/** handrig's own shape: [{ handedness, score?, worldLandmarks, landmarks? }]. */
export function packHandList(hands: readonly unknown[], input: Float32Array): number {
  at("frame.hands", -1, "");
  const n = hands.length;
  if (!(n <= MAX_HANDS)) {
    if (isOneHandsPoints(hands)) {
      fail("frame.hands", `is one hand's ${HAND_POINTS} landmarks, not a list of hands: give [{ handedness, worldLandmarks, landmarks? }] or a HandLandmarker result`);
    }
    fail("frame.hands", `at most ${MAX_HANDS} hands per frame, got ${n}`);
  }
  for (let i = 0; i < n; i++) {
    at("frame.hands", i, "");
    const h: unknown = hands[i];
    if (!isObject(h) || Array.isArray(h)) {
      fail(path("frame.hands", i, ""), `must be a hand object { handedness, worldLandmarks }, got ${describe(h)}`);
    }
    const hv = h.handedness;
    if (hv === undefined || hv === null) fail(path("frame.hands", i, ".handedness"), 'is missing ("Left" or "Right")');
    const scoreAt = LI.hands + i * LI.handStride + LI.hand.score;
    const label = readHandedness(hv, "frame.hands", i, ".handedness", input, scoreAt);
    const s = h.score;
    if (s !== undefined && s !== null) {
      checkScore(s, "frame.hands", i, ".score");
      input[scoreAt] = s as number;
    } else if (label & 2) checkScore(input[scoreAt], "frame.hands", i, ".handedness.score");
    else input[scoreAt] = 1;
    packHand(input, i, label & 1, h.worldLandmarks, h.landmarks, i, "frame.hands", ".worldLandmarks", "frame.hands", ".landmarks");
  }
  return n;
}

/**
 * Whether `v` is a list of landmark lists ([[...points], ...]) rather than one list of points:
 * its first element is itself a list.
 */
export function isListOfLists(v: unknown): boolean {
  if (!Array.isArray(v) || v.length === 0) return false;
  const first: unknown = v[0];
  return ArrayBuffer.isView(first) || (Array.isArray(first) && first.length > 0 && typeof first[0] !== "number");
}

/**
 * Whether `v` is one hand's 21 points ({x, y, z} or [x, y, z] each, or a typed array of 63)
 * rather than a list of hands.
 */
export function isOneHandsPoints(v: unknown): boolean {
  if (isView(v)) return v.length === HAND_POINTS * 3;
  if (!Array.isArray(v) || v.length !== HAND_POINTS || isListOfLists(v)) return false;
  const p: unknown = v[0];
  return (isObject(p) && !Array.isArray(p) && typeof p.x === "number") || (Array.isArray(p) && typeof p[0] === "number");
}

/** One hand's points where a list of hands belongs: say so, and how to wrap it. */
export function unwrappedHand(field: string): never {
  return fail(field, `is one hand's ${HAND_POINTS} points, not a list of hands: wrap it in [ ] (one list of points per hand)`);
}

/** A per-hand list of a result shape (one landmark list per hand): as many as labels. */
function checkPerHandList(list: unknown, listPath: string, n: number, labelPath: string): void {
  if (list === undefined || list === null) return;
  if (!Array.isArray(list)) {
    if (isOneHandsPoints(list)) unwrappedHand(listPath);
    fail(listPath, `must be an array (one list per hand), got ${describe(list)}`);
  }
  if (list.length !== n) {
    if (isOneHandsPoints(list)) unwrappedHand(listPath);
    fail(listPath, `has ${list.length} hand(s) but ${labelPath} has ${n}: one entry per hand`);
  }
}

// Field paths of MediaPipe result shapes, made once (a good frame builds no strings).
const RESULT_FIELDS = [
  "multiHandedness", "multiHandWorldLandmarks", "multiHandLandmarks", "handedness", "handednesses",
  "worldLandmarks", "landmarks", "leftHandLandmarks", "rightHandLandmarks", "leftHandWorldLandmarks",
  "rightHandWorldLandmarks",
] as const;
type ResultPaths = { readonly [field in (typeof RESULT_FIELDS)[number]]: string };
/** Where a result shape is read: the frame itself, or `frame.hands`. */
export type ResultShapeName = "frame" | "frame.hands";
const RESULT_PATHS = {} as Record<ResultShapeName, ResultPaths>;
for (const name of ["frame", "frame.hands"] as const) {
  const p = {} as Record<(typeof RESULT_FIELDS)[number], string>;
  for (const f of RESULT_FIELDS) p[f] = `${name}.${f}`;
  RESULT_PATHS[name] = p;
}

/**
 * tasks-vision HandLandmarkerResult, legacy Hands or legacy Holistic results (`name`:
 * "frame.hands" or "frame"). Returns the number of hands packed, or -1 when `r` has none of
 * their fields.
 */
export function packResultShape(r: Bag, input: Float32Array, name: ResultShapeName): number {
  const P = RESULT_PATHS[name];
  at(name, -1, "");
  let labels: unknown;
  let labelPath = "";
  let world: unknown;
  let worldPath: string;
  let image: unknown;
  let imagePath: string;
  const multi = r.multiHandedness;
  if (multi !== undefined && multi !== null) {
    labels = multi;
    labelPath = P.multiHandedness;
    world = r.multiHandWorldLandmarks;
    worldPath = P.multiHandWorldLandmarks;
    image = r.multiHandLandmarks;
    imagePath = P.multiHandLandmarks;
  } else {
    world = r.worldLandmarks;
    worldPath = P.worldLandmarks;
    image = r.landmarks;
    imagePath = P.landmarks;
    const h = r.handedness;
    if (h !== undefined && h !== null) {
      labels = h;
      labelPath = P.handedness;
    } else {
      const hs = r.handednesses;
      if (hs !== undefined && hs !== null) {
        labels = hs;
        labelPath = P.handednesses;
      }
    }
  }
  const hasWorld = world !== undefined && world !== null;
  const hasImage = image !== undefined && image !== null;
  if (labels === undefined) {
    if (hasWorld || hasImage) {
      fail(
        P.handedness,
        "is missing: a HandLandmarker result needs `handedness` to tell the hands apart" +
          (name === "frame" ? " (a PoseLandmarker result goes in frame.pose)" : ""),
      );
    }
    // Holistic legacy: image landmarks per side. Holistic names the hands by the subject's side,
    // like its pose (`leftHandLandmarks` is the hand at the pose's left wrist); the Hands
    // solutions label them as if the image were mirrored. So `leftHandLandmarks` is the hand
    // Hands would label "Right", and the other way round. tasks-vision's HolisticLandmarker
    // gives the same sides as lists of hands (none or one: `[]` when the hand is not seen), with
    // world landmarks beside them.
    const left = r.leftHandLandmarks;
    const right = r.rightHandLandmarks;
    let n = 0;
    n = packHolisticHand(input, n, 1, left, r.leftHandWorldLandmarks, P.leftHandLandmarks, P.leftHandWorldLandmarks);
    n = packHolisticHand(input, n, 0, right, r.rightHandWorldLandmarks, P.rightHandLandmarks, P.rightHandWorldLandmarks);
    if (n === 0 && left === undefined && right === undefined) return -1;
    return n;
  }
  if (!Array.isArray(labels)) fail(labelPath, `must be an array, got ${describe(labels)}`);
  const n = labels.length;
  if (!(n <= MAX_HANDS)) fail(labelPath, `at most ${MAX_HANDS} hands per frame, got ${n}`);
  checkPerHandList(world, worldPath, n, labelPath);
  checkPerHandList(image, imagePath, n, labelPath);
  for (let i = 0; i < n; i++) {
    at(labelPath, i, "");
    const scoreAt = LI.hands + i * LI.handStride + LI.hand.score;
    const label = readHandedness(labels[i], labelPath, i, "", input, scoreAt);
    if (label & 2) checkScore(input[scoreAt], labelPath, i, ".score");
    else input[scoreAt] = 1;
    const w: unknown = hasWorld ? (world as unknown[])[i] : null;
    const im: unknown = hasImage ? (image as unknown[])[i] : null;
    packHand(input, i, label & 1, w, im, i, worldPath, "", imagePath, "");
  }
  return n;
}

/**
 * One side of a Holistic result into hand slot `n` (as the label `label` of MediaPipe Hands
 * would give it): legacy Holistic's image landmarks (21 points), or tasks-vision's lists of hands
 * (`[]` or one list) with world landmarks. Returns the next free slot.
 */
function packHolisticHand(
  input: Float32Array,
  n: number,
  label: number,
  image: unknown,
  world: unknown,
  imagePath: string,
  worldPath: string,
): number {
  if (image === undefined || image === null) return n;
  let fi = -1;
  if (Array.isArray(image) && (image.length === 0 || isListOfLists(image))) {
    if (image.length === 0) return n;
    if (image.length > 1) fail(imagePath, `has ${image.length} hands: a Holistic result has one hand per side`);
    image = image[0];
    fi = 0;
    if (world !== undefined && world !== null) {
      if (!Array.isArray(world) || world.length !== 1) {
        fail(worldPath, `must be a list of one hand like ${imagePath}, got ${describe(world)}`);
      }
      world = world[0];
    }
  } else {
    // Legacy Holistic: one hand's image landmarks per side, and no world landmarks. World
    // landmarks beside them are tasks-vision's lists of hands, unwrapped.
    if (world !== undefined && world !== null) {
      if (isOneHandsPoints(world)) unwrappedHand(worldPath);
      if (isListOfLists(world) && isOneHandsPoints(image)) unwrappedHand(imagePath);
      fail(worldPath, `must be a list of hands like tasks-vision's ([[...${HAND_POINTS} points]] or []), got ${describe(world)}`);
    }
    world = null;
  }
  input[LI.hands + n * LI.handStride + LI.hand.score] = 1;
  packHand(input, n, label, world, image, fi, worldPath, "", imagePath, "");
  return n + 1;
}

/**
 * Whether `h` (given as frame.hands) is one hand rather than a list or a result: a single
 * handedness and one list of points.
 */
export function looksLikeOneHand(h: Bag): boolean {
  const hd = h.handedness;
  const w = h.worldLandmarks;
  const pts = w !== undefined ? w : h.landmarks;
  const oneLabel =
    typeof hd === "string" ||
    (isObject(hd) && !Array.isArray(hd)) ||
    (Array.isArray(hd) && hd.length > 0 && isObject(hd[0]) && !Array.isArray(hd[0]));
  return oneLabel && (isView(pts) || (Array.isArray(pts) && pts.length > 0 && !isListOfLists(pts)));
}
