// The result of `HandRig.solve()`, built from the output view (LAYOUT.output) into a reused
// object: the rig's own (or the caller's), whose parts are created on first use and updated in
// place after, so that a warmed-up frame allocates nothing.

import { isObject, type Bag } from "./errors.js";
import { TIME } from "./frame.js";
import { BONES, LAYOUT, LI, LO, optionNames } from "./layout.js";

type Mutable = { [key: string | symbol]: unknown };
type Vec = [number, number, number];
type Q = [number, number, number, number];

export function vec(out: Float32Array, at: number, dst: number[]): number[] {
  dst[0] = out[at]!;
  dst[1] = out[at + 1]!;
  dst[2] = out[at + 2]!;
  return dst;
}

export function quat(out: Float32Array, at: number, dst: number[]): number[] {
  dst[0] = out[at]!;
  dst[1] = out[at + 1]!;
  dst[2] = out[at + 2]!;
  dst[3] = out[at + 3]!;
  return dst;
}

// The output's enumerations, named by Rust (src/flat/mod.rs, `LAYOUT.handStatus` / `LAYOUT.handUse`):
// hand status per side, and what became of each hand. Code 0 ("none") reads as undefined / null.
const STATUS: readonly (string | undefined)[] = [undefined, ...LAYOUT.handStatus.slice(1)];
const HAND_USE: readonly (string | null)[] = [null, ...LAYOUT.handUse.slice(1)];

/** Per bone (LAYOUT.bones order): the finger it belongs to, "palm" for the hands, "" otherwise. */
export const BONE_FINGER: readonly string[] = BONES.map((name) => {
  const m = /(Thumb|Index|Middle|Ring|Little)/.exec(name);
  if (m) return m[1]!.toLowerCase();
  return /Hand$/.test(name) ? "palm" : "";
});

/** Per-finger points: `thumb` ... `little` (names from `optionNames()`), the reused arrays hidden. */
type FingerSet = Mutable & {
  points: Vec[];
  thumb: Vec | undefined;
  index: Vec | undefined;
  middle: Vec | undefined;
  ring: Vec | undefined;
  little: Vec | undefined;
};

interface SideParts {
  target: { position: Vec; rotation: Q };
  alignment: {
    targetDip: Vec;
    ikWrist: Vec;
    poseWrist: Vec;
    error: number | null;
    reachable: boolean;
    aligned: boolean;
    finger: string;
    bone: string;
    contact: SideParts["contact"] | null;
  };
  contact: { anchor: string | null; weight: number; distance: number | null; handWeight: number; push: number };
  hand: { status: string; score: number; index: number; reassigned: boolean; confidence: number; check: string; resolved: string | null };
  tips: FingerSet;
  retarget: { targets: FingerSet; scale: number; iterations: number; residual: number };
}

/**
 * Fills `result` (any object; its parts are created on first use and reused after) from the
 * output view. `driven`/`present` are the rig's bone indices, `aligned` per side the bone
 * carrying the aligned point (`alignedBones()`: what `output.side.alignedBone` 0 stands for).
 */
export function fillResult(
  result: object,
  out: Float32Array,
  input: Float32Array,
  driven: number[],
  present: number[],
  aligned: ArrayLike<number>,
): object {
  const r = result as Mutable;
  r.timeMs = TIME[0];
  // The per-bone arrays, found by name once per result object and then updated by index: a
  // property store by a varying key is a slow (megamorphic) lookup every time.
  const arrays = boneArrays(r, driven, present);
  const rotations = arrays.rotations;
  for (let k = 0; k < driven.length; k++) quat(out, LO.boneRotations + 4 * driven[k]!, rotations[k]!);
  const positions = arrays.positions;
  for (let k = 0; k < present.length; k++) vec(out, LO.bonePositions + 3 * present[k]!, positions[k]!);
  let targets = r.ikTargets as Mutable;
  if (!isObject(targets)) targets = r.ikTargets = {};
  let alignment = r.alignment as Mutable;
  if (!isObject(alignment)) alignment = r.alignment = {};
  let hands = r.hands as Mutable;
  if (!isObject(hands)) hands = r.hands = {};
  const names = optionNames();
  const S = LO.side;
  const sides = sideCaches(r);
  // Each side's part stored and deleted by a fixed name (`.left` / `.right`): a store, `in` or
  // delete by a varying key is a slow (megamorphic) lookup every time.
  for (let s = 0; s < 2; s++) {
    const at = LO.sides + s * LO.sideStride;
    const cache = sides[s]!;
    if (out[at + S.targetPresent] === 1) {
      const t = cache.target;
      vec(out, at + S.targetPosition, t.position);
      quat(out, at + S.targetRotation, t.rotation);
      if (s === 0) targets.left = t;
      else targets.right = t;
    } else if (s === 0) {
      if ("left" in targets) delete targets.left;
    } else if ("right" in targets) delete targets.right;
    if (out[at + S.alignmentPresent] === 1) {
      const a = cache.alignment;
      vec(out, at + S.targetDip, a.targetDip);
      vec(out, at + S.ikWrist, a.ikWrist);
      vec(out, at + S.poseWrist, a.poseWrist);
      const err = out[at + S.alignmentError]!;
      a.error = Number.isNaN(err) ? null : err;
      a.reachable = out[at + S.reachable] === 1;
      a.aligned = out[at + S.aligned] === 1;
      const code = out[at + S.alignedBone]!;
      const bone = code === 0 ? aligned[s]! : code - 1;
      a.bone = BONES[bone]!;
      a.finger = BONE_FINGER[bone]!;
      if (out[at + S.contactPresent] === 1) {
        const c = cache.contact;
        c.anchor = names.faceAnchors[out[at + S.contactAnchor]!] ?? null;
        c.weight = out[at + S.contactWeight]!;
        const d = out[at + S.contactDistance]!;
        c.distance = Number.isNaN(d) ? null : d;
        c.handWeight = out[at + S.contactHandWeight]!;
        c.push = out[at + S.contactPush]!;
        a.contact = c;
      } else a.contact = null;
      if (s === 0) alignment.left = a;
      else alignment.right = a;
    } else if (s === 0) {
      if ("left" in alignment) delete alignment.left;
    } else if ("right" in alignment) delete alignment.right;
    const status = STATUS[out[at + S.handStatus]!];
    if (status !== undefined) {
      const h = cache.hand;
      h.status = status;
      h.score = out[at + S.handScore]!;
      h.index = out[at + S.handIndex]!;
      h.reassigned = out[at + S.handReassigned] === 1;
      h.confidence = out[at + S.handConfidence]!;
      h.check = LAYOUT.handCheck[out[at + S.handCheck]!] ?? "good";
      const resolved = out[at + S.handResolved]!;
      h.resolved = resolved > 0 ? (LAYOUT.handResolved[resolved] ?? null) : null;
      if (s === 0) hands.left = h;
      else hands.right = h;
    } else if (s === 0) {
      if ("left" in hands) delete hands.left;
    } else if ("right" in hands) delete hands.right;
  }
  let tips = r.fingertips as Mutable;
  if (!isObject(tips)) tips = r.fingertips = {};
  let retarget = r.retarget as Mutable;
  if (!isObject(retarget)) retarget = r.retarget = {};
  for (let s = 0; s < 2; s++) {
    const at = LO.sides + s * LO.sideStride;
    const cache = sides[s]!;
    if (fingers(out, at + S.fingertips, cache.tips)) {
      if (s === 0) tips.left = cache.tips;
      else tips.right = cache.tips;
    } else if (s === 0) {
      if ("left" in tips) delete tips.left;
    } else if ("right" in tips) delete tips.right;
    if (out[at + S.retargetPresent] === 1) {
      const rt = cache.retarget;
      fingers(out, at + S.retargetTargets, rt.targets);
      rt.scale = out[at + S.retargetScale]!;
      rt.iterations = out[at + S.retargetIterations]!;
      rt.residual = out[at + S.retargetResidual]!;
      if (s === 0) retarget.left = rt;
      else retarget.right = rt;
    } else if (s === 0) {
      if ("left" in retarget) delete retarget.left;
    } else if ("right" in retarget) delete retarget.right;
  }
  let use = r.handUse as (string | null | undefined)[];
  if (!Array.isArray(use)) use = r.handUse = [];
  const count = input[LI.handCount]!;
  // Setting an array's length calls into the runtime even when it is unchanged.
  if (use.length !== count) use.length = count;
  for (let k = 0; k < count; k++) use[k] = HAND_USE[out[LO.handUse + k]!];
  fillFace(r, out, arrays.bones, arrays.faceDriven);
  // Legs (issue 51).
  let hips = r.hipsOffset as Vec | undefined;
  if (!Array.isArray(hips)) r.hipsOffset = hips = [0, 0, 0] as Vec;
  vec(out, LO.hipsOffset, hips as Vec);
  let planted = r.feetPlanted as { left: boolean; right: boolean } | undefined;
  if (!isObject(planted)) planted = r.feetPlanted = { left: false, right: false };
  planted.left = out[LO.feetPlanted] === 1;
  planted.right = out[LO.feetPlanted + 1] === 1;
  return result;
}

// The face (issue 50): the neck and head it turns, the presets, the ARKit weights, the look-at.
const FACE_BONES = [BONES.indexOf("neck"), BONES.indexOf("head")];
// The presets by name, each store a fixed property (a keyed store by a varying name is a slow
// lookup): the order is LAYOUT.expressions', checked once below.
type Expressions = { [name: string]: number };
const PRESET_ORDER = "happy angry sad relaxed surprised aa ih ou ee oh blink blinkLeft blinkRight lookUp lookDown lookLeft lookRight";
if (LAYOUT.expressions.join(" ") !== PRESET_ORDER) throw new Error("handrig: LAYOUT.expressions changed: update results.ts");
function newExpressions(): Expressions {
  return { happy: 0, angry: 0, sad: 0, relaxed: 0, surprised: 0, aa: 0, ih: 0, ou: 0, ee: 0, oh: 0, blink: 0, blinkLeft: 0, blinkRight: 0, lookUp: 0, lookDown: 0, lookLeft: 0, lookRight: 0 };
}
function writeExpressions(e: Expressions, out: Float32Array, o: number): void {
  e.happy = out[o]!;
  e.angry = out[o + 1]!;
  e.sad = out[o + 2]!;
  e.relaxed = out[o + 3]!;
  e.surprised = out[o + 4]!;
  e.aa = out[o + 5]!;
  e.ih = out[o + 6]!;
  e.ou = out[o + 7]!;
  e.ee = out[o + 8]!;
  e.oh = out[o + 9]!;
  e.blink = out[o + 10]!;
  e.blinkLeft = out[o + 11]!;
  e.blinkRight = out[o + 12]!;
  e.lookUp = out[o + 13]!;
  e.lookDown = out[o + 14]!;
  e.lookLeft = out[o + 15]!;
  e.lookRight = out[o + 16]!;
}
const ARKIT_COUNT = LAYOUT.arkit.length;
const FACE_STATE: readonly (string | null)[] = [null, "tracked", "lost"];

function fillFace(r: Mutable, out: Float32Array, bones: Mutable, faceDriven: readonly boolean[]): void {
  // The neck and the head where the face turns them and the body does not drive them, each by
  // its fixed name (a lookup by a varying name is a slow, megamorphic one).
  if (!faceDriven[0]) {
    const b = FACE_BONES[0]!;
    if (out[LO.boneFlags + b] !== 0) {
      let q = bones.neck as number[] | undefined;
      if (!Array.isArray(q) || q.length !== 4) q = bones.neck = [0, 0, 0, 1];
      quat(out, LO.boneRotations + 4 * b, q);
    } else if ("neck" in bones) delete bones.neck;
  }
  if (!faceDriven[1]) {
    const b = FACE_BONES[1]!;
    if (out[LO.boneFlags + b] !== 0) {
      let q = bones.head as number[] | undefined;
      if (!Array.isArray(q) || q.length !== 4) q = bones.head = [0, 0, 0, 1];
      quat(out, LO.boneRotations + 4 * b, q);
    } else if ("head" in bones) delete bones.head;
  }
  const state = FACE_STATE[out[LO.faceState]!] ?? null;
  let ex = r.expressions as Mutable;
  let arkit = r.arkit as Float32Array;
  let look = r.lookAt as { yaw: number; pitch: number };
  const fresh = !isObject(ex) || !(arkit instanceof Float32Array) || arkit.length !== ARKIT_COUNT || !isObject(look);
  if (fresh) {
    ex = r.expressions = newExpressions();
    arkit = r.arkit = new Float32Array(ARKIT_COUNT);
    look = r.lookAt = { yaw: 0, pitch: 0 };
  } else if (state === null && r.face === null) return; // no face, and all zero already
  r.face = state;
  writeExpressions(ex as Expressions, out, LO.expressions);
  for (let k = 0; k < ARKIT_COUNT; k++) arkit[k] = out[LO.arkit + k]!;
  look.yaw = out[LO.lookAt]!;
  look.pitch = out[LO.lookAt + 1]!;
}

/** Finger `f`'s point at `out[o..]` into its reused array, or undefined (NaN: the avatar lacks it). */
function finger(out: Float32Array, o: number, points: Vec[], f: number): Vec | undefined {
  if (Number.isNaN(out[o])) return undefined;
  const p = points[f]!;
  vec(out, o, p);
  return p;
}

/**
 * Five points (NaN for a finger the avatar lacks) into `dst.thumb` ... `dst.little` (undefined
 * where missing), each stored by its fixed name (FINGER_ORDER). Returns whether any finger is
 * there.
 */
function fingers(out: Float32Array, at: number, dst: FingerSet): boolean {
  const points = dst.points;
  const thumb = (dst.thumb = finger(out, at, points, 0));
  const index = (dst.index = finger(out, at + 3, points, 1));
  const middle = (dst.middle = finger(out, at + 6, points, 2));
  const ring = (dst.ring = finger(out, at + 9, points, 3));
  const little = (dst.little = finger(out, at + 12, points, 4));
  return thumb !== undefined || index !== undefined || middle !== undefined || ring !== undefined || little !== undefined;
}

// The fingers by name, in Rust's order (`optionNames().fingers`, checked when a result's parts
// are made): `fingers` stores each by its fixed name.
const FINGER_ORDER = "thumb index middle ring little";

/** { thumb, index, middle, ring, little } with the five reused arrays kept non-enumerable. */
function fingerSet(names: readonly string[]): FingerSet {
  const o: Mutable = {};
  for (const name of names) o[name] = undefined;
  Object.defineProperty(o, "points", { value: names.map((): Vec => [0, 0, 0]), enumerable: false });
  return o as FingerSet;
}

interface BoneArrays {
  bones: Bag;
  world: Bag;
  driven: number[];
  rotations: number[][];
  positions: number[][];
  /** Whether the neck and the head (FACE_BONES) are driven: then in `rotations`. */
  faceDriven: boolean[];
}

/**
 * The arrays of `result.bones` and `result.worldPositions`, in the rig's driven / present order,
 * kept on a hidden property of the result (re-found if the caller swapped an object).
 */
const BONE_ARRAYS: symbol | string = typeof Symbol === "function" ? Symbol("handrig.bones") : "__handrigBones";
function boneArrays(result: Mutable, driven: number[], present: number[]): BoneArrays {
  let c = result[BONE_ARRAYS] as BoneArrays | undefined;
  if (c !== undefined && c.bones === result.bones && c.world === result.worldPositions && c.driven === driven) return c;
  let bones = result.bones as Mutable;
  if (!isObject(bones)) bones = result.bones = {};
  let world = result.worldPositions as Mutable;
  if (!isObject(world)) world = result.worldPositions = {};
  const take = (o: Mutable, name: string, n: number): number[] => {
    const a = o[name];
    if (Array.isArray(a) && a.length === n) return a as number[];
    return (o[name] = n === 4 ? [0, 0, 0, 1] : [0, 0, 0]);
  };
  c = {
    bones,
    world,
    driven,
    rotations: driven.map((i) => take(bones, BONES[i]!, 4)),
    positions: present.map((i) => take(world, BONES[i]!, 3)),
    faceDriven: FACE_BONES.map((b) => driven.includes(b)),
  };
  Object.defineProperty(result, BONE_ARRAYS, { value: c, enumerable: false, configurable: true, writable: true });
  return c;
}

/**
 * Per-side sub-objects, kept on a hidden property of the result so a reused result reuses them
 * (and a fresh `{}` gets its own).
 */
const SIDE_CACHE: symbol | string = typeof Symbol === "function" ? Symbol("handrig.sides") : "__handrigSides";
function sideCaches(result: Mutable): SideParts[] {
  let c = result[SIDE_CACHE] as SideParts[] | undefined;
  if (c === undefined) {
    const fingerNames = optionNames().fingers;
    if (fingerNames.join(" ") !== FINGER_ORDER) throw new Error("handrig: the finger names changed: update results.ts");
    const make = (): SideParts => ({
      target: { position: [0, 0, 0], rotation: [0, 0, 0, 1] },
      alignment: {
        targetDip: [0, 0, 0],
        ikWrist: [0, 0, 0],
        poseWrist: [0, 0, 0],
        error: null,
        reachable: false,
        aligned: false,
        finger: "",
        bone: "",
        contact: null,
      },
      contact: { anchor: null, weight: 0, distance: null, handWeight: 0, push: 0 },
      hand: { status: "solved", score: 0, index: 0, reassigned: false, confidence: 0, check: "good", resolved: null },
      tips: fingerSet(fingerNames),
      retarget: { targets: fingerSet(fingerNames), scale: 0, iterations: 0, residual: 0 },
    });
    c = [make(), make()];
    Object.defineProperty(result, SIDE_CACHE, { value: c, enumerable: false });
  }
  return c;
}
