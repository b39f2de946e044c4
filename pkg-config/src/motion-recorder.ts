// `MotionRecorder`: collects solved frames (copies of their rotations, not references to the
// reused result object) and writes them as a VRM Animation (`.vrma`: glTF binary with
// `VRMC_vrm_animation` 1.0) or as BVH text. Both use VRM 1.0's convention (the avatar faces +Z)
// whatever the avatar's version: a VRM 0.x rig's rotations (the model's own frame, facing -Z)
// are turned 180 degrees about Y when they are recorded, as the VRMA format asks (three-vrm-
// animation turns them back for a 0.x avatar). The writers are in motion-writers.ts.

import { describe, isObject } from "./errors.js";
import type { BoneMap, Vec3 } from "./frame-types.js";
import type { HumanBoneName } from "./layout.js";
import { writeBVH, writeVRMA, type BVHOptions, type MotionData, type VRMAOptions } from "./motion-writers.js";

export type { BVHOptions, VRMAOptions } from "./motion-writers.js";

/** What `MotionRecorder` reads from a rig at construction (a `HandRig` fits). */
export interface RecordableRig {
  boneNames(): HumanBoneName[];
  drivenBones(): HumanBoneName[];
  restWorldPositions(): BoneMap<Vec3>;
  readonly vrmVersion: "0" | "1";
}

/** What `add` reads from a result (a `HandRig.solve` result fits): `bones` and `worldPositions.hips`. */
export interface RecordableResult {
  bones: { [boneName: string]: ArrayLike<number> | undefined };
  worldPositions?: { [boneName: string]: ArrayLike<number> | undefined };
  /** The face (issue 50): recorded when a frame had one. */
  face?: string | null;
  expressions?: { [name: string]: number };
  lookAt?: { yaw: number; pitch: number };
  /** The hips' translation from rest (root motion, `legs.moveHips`), added to the hips position. */
  hipsOffset?: ArrayLike<number> | null;
}

/** The presets a recording carries (`FACE_PRESETS` then yaw and pitch per frame): the look* presets are the look-at's. */
export const FACE_PRESETS = ["happy", "angry", "sad", "relaxed", "surprised", "aa", "ih", "ou", "ee", "oh", "blink", "blinkLeft", "blinkRight"] as const;
const FACE_STRIDE = FACE_PRESETS.length + 2;

/** `add`'s bound on times (ms): a JavaScript Date's range. */
const TIME_LIMIT = 8.64e15;
/** `add`'s bound on the hips position (m): float32 and BVH's fixed-point numbers hold it. */
const POSITION_LIMIT = 1e9;

/**
 * Records solved frames and exports them: `const rec = new MotionRecorder(rig)`, then
 * `rec.add(timeMs, rig.solve(frame))` every frame, then `rec.toVRMA()` (the bytes of a `.vrma`)
 * or `rec.toBVH()` (BVH text). See docs/guide/export.md.
 */
export class MotionRecorder {
  readonly #bones: HumanBoneName[];
  readonly #driven: HumanBoneName[];
  readonly #rest: Float64Array; // per present bone, VRM 1.0 frame
  readonly #flip: boolean;
  readonly #restHips: Float64Array;
  #times = new Float64Array(64);
  #rotations: Float32Array;
  #hips = new Float32Array(64 * 3);
  #face = new Float32Array(64 * FACE_STRIDE);
  #hasFace = false;
  #count = 0;

  /**
   * A recorder for `rig`'s avatar: it keeps the rig's bones, driven bones, rest positions and VRM
   * version (the rig may be freed afterwards).
   * @throws TypeError when `rig` is not a HandRig (or has no bones).
   */
  constructor(rig: RecordableRig) {
    const r = rig as Partial<RecordableRig> | null;
    if (
      !isObject(r) ||
      typeof r.boneNames !== "function" ||
      typeof r.drivenBones !== "function" ||
      typeof r.restWorldPositions !== "function"
    ) {
      throw new TypeError(`rig: must be a HandRig, got ${describe(rig)}`);
    }
    const bones = r.boneNames();
    const rest = r.restWorldPositions();
    if (!bones.includes("hips")) throw new TypeError("rig: has no hips bone");
    this.#bones = bones;
    this.#driven = r.drivenBones();
    this.#flip = r.vrmVersion === "0";
    this.#rest = new Float64Array(3 * bones.length);
    bones.forEach((name, k) => {
      const p = rest[name]!;
      const s = this.#flip ? -1 : 1;
      this.#rest[3 * k] = s * p[0];
      this.#rest[3 * k + 1] = p[1];
      this.#rest[3 * k + 2] = s * p[2];
    });
    const h = bones.indexOf("hips");
    this.#restHips = this.#rest.slice(3 * h, 3 * h + 3);
    this.#rotations = new Float32Array(64 * 4 * this.#driven.length);
  }

  /** Frames recorded. */
  get frameCount(): number {
    return this.#count;
  }

  /** Milliseconds from the first recorded frame to the last (0 with fewer than two frames). */
  get duration(): number {
    return this.#count < 2 ? 0 : this.#times[this.#count - 1]! - this.#times[0]!;
  }

  /** The bones with a rotation track: the rig's driven bones, parent-first. */
  get bones(): HumanBoneName[] {
    return this.#driven.slice();
  }

  /**
   * Records one frame: copies the rotation of every driven bone from `result.bones` (and the hips
   * position from `result.worldPositions` plus `result.hipsOffset`, the root motion), so the result object may be reused by the next
   * `solve`. Times must not go back; a frame at the same time as the last one replaces it.
   * Allocates nothing except when its storage doubles.
   * @param timeMs the frame's time, milliseconds (e.g. `result.timeMs`).
   * @param result a `HandRig.solve` result of this recorder's rig.
   * @throws Error naming the field (a missing or non-finite rotation, a time going back); nothing is recorded then.
   */
  add(timeMs: number, result: RecordableResult): void {
    if (typeof timeMs !== "number" || !Number.isFinite(timeMs)) {
      throw new TypeError(`timeMs: must be a finite number, got ${describe(timeMs)}`);
    }
    // Beyond a JavaScript Date's range, differences of times lose their milliseconds and a
    // file's seconds overflow (issue 49's fuzzing: a span of 1e308 ms made infinite key times).
    if (Math.abs(timeMs) > TIME_LIMIT) throw new RangeError(`timeMs: must be within -${TIME_LIMIT}..${TIME_LIMIT} (a Date's range), got ${timeMs}`);
    const n = this.#count;
    const last = n > 0 ? this.#times[n - 1]! : -Infinity;
    if (timeMs < last) throw new RangeError(`timeMs: ${timeMs} goes back in time (the last frame recorded is at ${last} ms)`);
    if (!isObject(result) || !isObject((result as RecordableResult).bones)) {
      throw new TypeError(`result: must be a HandRig.solve() result with bones, got ${describe(result)}`);
    }
    const bones = result.bones;
    const driven = this.#driven;
    // Checked before anything is written: a rejected frame leaves the recording as it was.
    for (let b = 0; b < driven.length; b++) {
      const q = bones[driven[b]!];
      if (q === undefined || q === null || typeof q !== "object" || q.length !== 4) {
        throw new TypeError(`result.bones.${driven[b]}: must be a quaternion [x, y, z, w], got ${describe(q)}`);
      }
      for (let c = 0; c < 4; c++) {
        if (!Number.isFinite(q[c])) throw new TypeError(`result.bones.${driven[b]}[${c}]: must be a finite number, got ${describe(q[c])}`);
      }
    }
    let hipsIn: ArrayLike<number> | undefined;
    const world = result.worldPositions;
    if (isObject(world)) {
      // null, like undefined: no hips position (the rest one is recorded). Issue 49's fuzzing:
      // null threw "Cannot read properties of null".
      hipsIn = world.hips ?? undefined;
      if (hipsIn !== undefined) {
        for (let c = 0; c < 3; c++) {
          const v = hipsIn[c];
          if (!Number.isFinite(v)) throw new TypeError(`result.worldPositions.hips[${c}]: must be a finite number, got ${describe(v)}`);
          // Written as float32 (.vrma) and fixed-point text (BVH): 1e39 became Infinity in the file.
          if (Math.abs(v!) > POSITION_LIMIT) throw new RangeError(`result.worldPositions.hips[${c}]: must be within -${POSITION_LIMIT}..${POSITION_LIMIT} (meters), got ${v}`);
        }
      }
    }
    // Legs (issue 51): the hips' root motion, added to the hips position recorded.
    let offset: ArrayLike<number> | undefined = result.hipsOffset ?? undefined;
    if (offset !== undefined) {
      for (let c = 0; c < 3; c++) {
        const v = offset[c];
        if (!Number.isFinite(v) || Math.abs(v!) > POSITION_LIMIT) throw new TypeError(`result.hipsOffset[${c}]: must be a finite number within -${POSITION_LIMIT}..${POSITION_LIMIT} (meters), got ${describe(v)}`);
      }
      if (offset[0] === 0 && offset[1] === 0 && offset[2] === 0) offset = undefined;
    }
    const k = timeMs === last ? n - 1 : n;
    if (k === n) this.#grow(n + 1);
    this.#times[k] = timeMs;
    const rot = this.#rotations;
    const stride = 4 * driven.length;
    const s = this.#flip ? -1 : 1;
    for (let b = 0; b < driven.length; b++) {
      const q = bones[driven[b]!]!;
      let x = s * q[0]!;
      let y = q[1]!;
      let z = s * q[2]!;
      let w = q[3]!;
      const len = Math.hypot(x, y, z, w);
      if (len > 0) (x /= len), (y /= len), (z /= len), (w /= len);
      else (x = 0), (y = 0), (z = 0), (w = 1);
      const at = k * stride + 4 * b;
      // Same hemisphere as the frame before, so that interpolation between keys is the short way.
      if (k > 0) {
        const p = at - stride;
        if (x * rot[p]! + y * rot[p + 1]! + z * rot[p + 2]! + w * rot[p + 3]! < 0) (x = -x), (y = -y), (z = -z), (w = -w);
      }
      rot[at] = x;
      rot[at + 1] = y;
      rot[at + 2] = z;
      rot[at + 3] = w;
    }
    const h = this.#hips;
    if (hipsIn !== undefined) {
      h[3 * k] = s * hipsIn[0]!;
      h[3 * k + 1] = hipsIn[1]!;
      h[3 * k + 2] = s * hipsIn[2]!;
    } else {
      h[3 * k] = this.#restHips[0]!;
      h[3 * k + 1] = this.#restHips[1]!;
      h[3 * k + 2] = this.#restHips[2]!;
    }
    // The face: its presets and look-at (0 in frames without one), kept when any frame had it.
    const fo = k * FACE_STRIDE;
    const ex = result.expressions;
    const look = result.lookAt;
    const live = result.face !== undefined && result.face !== null && isObject(ex) && isObject(look);
    for (let e = 0; e < FACE_PRESETS.length; e++) {
      const w = live ? ex![FACE_PRESETS[e]!] : 0;
      if (typeof w !== "number" || !(w >= 0 && w <= 1)) throw new TypeError(`result.expressions.${FACE_PRESETS[e]}: must be a weight in 0..1, got ${describe(w)}`);
      this.#face[fo + e] = w;
    }
    const yaw = live ? look!.yaw : 0;
    const pitch = live ? look!.pitch : 0;
    if (!Number.isFinite(yaw) || !Number.isFinite(pitch)) throw new TypeError(`result.lookAt: yaw and pitch must be finite numbers (degrees)`);
    this.#face[fo + FACE_PRESETS.length] = yaw;
    this.#face[fo + FACE_PRESETS.length + 1] = pitch;
    if (live) this.#hasFace = true;
    if (offset !== undefined) {
      h[3 * k] = h[3 * k]! + s * offset[0]!;
      h[3 * k + 1] = h[3 * k + 1]! + offset[1]!;
      h[3 * k + 2] = h[3 * k + 2]! + s * offset[2]!;
    }
    this.#count = k + 1;
  }

  #grow(frames: number): void {
    if (frames <= this.#times.length) return;
    const cap = Math.max(2 * this.#times.length, frames);
    const times = new Float64Array(cap);
    times.set(this.#times);
    this.#times = times;
    const rot = new Float32Array(cap * 4 * this.#driven.length);
    rot.set(this.#rotations);
    this.#rotations = rot;
    const hips = new Float32Array(cap * 3);
    hips.set(this.#hips);
    this.#hips = hips;
    const face = new Float32Array(cap * FACE_STRIDE);
    face.set(this.#face);
    this.#face = face;
  }

  /** Forgets every frame (keeps the avatar). */
  clear(): void {
    this.#count = 0;
    this.#hasFace = false;
  }

  #data(method: string): MotionData {
    if (this.#count === 0) throw new Error(`MotionRecorder.${method}: no frames recorded (call add(timeMs, result) first)`);
    return {
      bones: this.#bones,
      rest: this.#rest,
      driven: this.#driven,
      count: this.#count,
      times: this.#times,
      rotations: this.#rotations,
      hips: this.#hips,
      restHips: this.#restHips,
      face: this.#hasFace ? { presets: FACE_PRESETS, values: this.#face } : undefined,
    };
  }

  /**
   * The recording as a VRM Animation file (`.vrma`, glTF binary with `VRMC_vrm_animation` 1.0):
   * one node per bone of the avatar at its rest (T-)pose, a LINEAR rotation track per driven
   * bone (and a hips translation track when the hips moved), times in seconds from the first
   * frame; VRM 1.0's convention. `options.tolerance` (radians, default 0: every frame a key)
   * drops keys that interpolation between the kept ones reproduces within that angle. A
   * recording with a face (issue 50) also carries the VRM presets (`expressions.preset`, one
   * node each, its translation's x the weight) and the look-at (`lookAt`, a node whose rotation
   * is three-vrm's yaw and pitch, Euler YXZ), every frame a key.
   * @throws Error with no frames recorded, or for a bad option.
   */
  toVRMA(options?: VRMAOptions): Uint8Array {
    return writeVRMA(this.#data("toVRMA"), options, version());
  }

  /**
   * The recording as BVH text: the avatar's bones as the hierarchy (offsets from the rest pose,
   * centimeters by default), the hips with `Xposition Yposition Zposition Zrotation Xrotation
   * Yrotation`, every other joint `Zrotation Xrotation Yrotation` (degrees; the joint's local
   * rotation is Rz * Rx * Ry), at a constant frame time (`options.fps`, default the recording's
   * median frame interval; frames resampled by interpolation); VRM 1.0's convention. BVH is a
   * skeleton format: a face's expressions and look-at are left out (`toVRMA` keeps them).
   * @throws Error with no frames recorded, or for a bad option.
   */
  toBVH(options?: BVHOptions): string {
    return writeBVH(this.#data("toBVH"), options);
  }
}

// Defined by build.mjs (esbuild `define`): the crate's version, from Cargo.toml.
declare const __HANDRIG_VERSION__: string;
function version(): string {
  return __HANDRIG_VERSION__;
}

