// `HandRig`, the idiomatic class over the raw wasm-bindgen `HandRig` (rapier.js style: the wasm
// class stays thin, users get this one). Per frame nothing crosses the wasm boundary but
// numbers: the rig owns a flat input and output buffer in wasm memory (LAYOUT, src/flat/layout.rs);
// `solve` packs the frame through a Float32Array view (frame.ts), calls `solveFlat(timeMs)` and
// builds the result object from the output view (results.ts), reusing one object per rig (or
// the caller's), so that a frame allocates nothing once warmed up.

import { asError, describe, fail, givenFields, isObject, readError, readUser, reading } from "./errors.js";
import type { BoneMap, FrameInput, RestPose, Vec3 } from "./frame-types.js";
import { FACE_FIELDS, TIME, packFrame } from "./frame.js";
import { BONES, BONE_COUNT, BONE_INDEX, LAYOUT, LI, LO, optionNames, type FlatLayout, type HumanBoneName } from "./layout.js";
import { cleanDescriptions, optionsValue, type HandRigOptions, type OptionDescription } from "./options.js";
import type { AlignedBone, ContactModel, FingerName, SolveResult } from "./result-types.js";
import { BONE_FINGER, fillResult } from "./results.js";
import { restPoseToFlat, vrmBytes } from "./rest-pose.js";
import { addDispose, ensureReady, wasm, wasmMemory, type RawHandRig } from "./wasm.js";

/** The options only `HandRig.fromGltf` reads. */
export interface GltfOptions {
  skeleton?: {
    /** `{ humanBoneName: nodeName }`: binds the humanoid by node names (the whole binding). */
    boneMap?: BoneMap<string>;
  };
}

/** `options.skeleton.boneMap` as pairs of strings, and the other options. */
function splitSkeletonOptions(options: unknown): { boneMap: string[]; rest: unknown } {
  return readUser("options", () => {
    if (!isObject(options) || !("skeleton" in options)) return { boneMap: [], rest: options };
    // Fields set to undefined are absent (givenFields), here as in the other options.
    const { skeleton, ...rest } = givenFields(options, "options");
    const pairs: string[] = [];
    if (skeleton === undefined) return { boneMap: pairs, rest };
    reading.part = "options.skeleton";
    if (!isObject(skeleton) || Array.isArray(skeleton)) fail("options.skeleton", `must be an object { boneMap }, got ${describe(skeleton)}`);
    const given = givenFields(skeleton, "options.skeleton");
    for (const key of Object.keys(given)) {
      if (key !== "boneMap") fail(`options.skeleton.${key}`, "unknown option (options.skeleton has boneMap only)");
    }
    const boneMap = given.boneMap;
    if (boneMap === undefined) return { boneMap: pairs, rest };
    reading.part = "options.skeleton.boneMap";
    if (!isObject(boneMap) || Array.isArray(boneMap)) {
      fail("options.skeleton.boneMap", `must be an object { [humanBoneName]: nodeName }, got ${describe(boneMap)}`);
    }
    const map = givenFields(boneMap, "options.skeleton.boneMap");
    for (const bone of Object.keys(map)) {
      const field = `options.skeleton.boneMap.${bone}`;
      reading.part = field;
      if (!BONE_INDEX.has(bone)) {
        fail("options.skeleton.boneMap", `unknown bone name ${JSON.stringify(bone)} (expected a VRM 1.0 humanoid bone name such as "leftHand")`);
      }
      const node = map[bone];
      if (typeof node !== "string") fail(field, `must be a node name (a string), got ${describe(node)}`);
      pairs.push(bone, node);
    }
    return { boneMap: pairs, rest };
  });
}

// Constructor token for wrapping a raw rig made by a static factory (fromVrm).
const ADOPT = {};

/**
 * `solve(landmarks, "Right")`: Kalidokit's `Hand.solve(landmarks, side)` call shape. Blame the
 * frame (the string is only a symptom), and say what handrig takes instead.
 */
function kalidokitCall(frame: unknown, side: string): never {
  const plainFrame = isObject(frame) && !Array.isArray(frame) && !ArrayBuffer.isView(frame);
  if (plainFrame) {
    throw new TypeError(
      `target: must be an object to fill with the result, got ${describe(side)}; handrig takes no ` +
        "side argument (Kalidokit's Hand.solve(landmarks, side) call shape): each hand's side is its handedness in the frame",
    );
  }
  throw new TypeError(
    `frame: must be a frame object { timeMs, hands?, pose?, wrists? }, got ${describe(frame)} with ${describe(side)} as ` +
      "a second argument: that is Kalidokit's Hand.solve(landmarks, side) call shape, not handrig's. Pass the " +
      "MediaPipe result in one frame: rig.solve({ timeMs, hands: handLandmarkerResult }) or " +
      "rig.solve({ timeMs, ...holisticLandmarkerResult })",
  );
}

// A timeMs step (ms) this small, this many frames in a row, is seconds given for milliseconds:
// 30 fps is 0.033 s a frame. (Real milliseconds advance by ~10-70 a frame.)
const SECONDS_STEP_MIN = 0.004;
const SECONDS_STEP_MAX = 0.15;
const SECONDS_FRAMES = 5;
// A timeMs step of exactly 1 or 2, this many frames in a row, is frame numbers given for
// milliseconds (a camera's frames come 10-70 ms apart, and performance.now() and video times are
// not whole numbers frame after frame).
const INDEX_STEP_MAX = 2;
const INDEX_FRAMES = 5;
/** The time step (ms) a frame without `timeMs` is taken to come after the last: 30 fps. */
export const MISSING_TIME_STEP_MS = 1000 / 30;

// The rig's clock (a Float64Array: double fields would be boxed per frame): the last frame's
// time (NaN before the first), seconds-like steps in a row, frame-number-like steps in a row, and
// per warning whether it was said.
const LAST = 0;
const SECONDS_RUN = 1;
const INDEX_RUN = 2;
const SAID_SECONDS = 3;
const SAID_INDEX = 4;
const SAID_MISSING = 5;

function warn(message: string): void {
  const log = (globalThis as { console?: { warn?: (message: string) => void } }).console;
  log?.warn?.(message);
}

/**
 * The frame's time in TIME[0], checked against the rig's clock: a frame without `timeMs`
 * (TIME[1]) is put one 30 fps frame after the last (0 for a rig's first frame) and warns once;
 * steps that look like seconds or frame numbers warn once each. Results stay in typed arrays (no
 * boxed doubles).
 */
function clockCheck(clock: Float64Array): void {
  const last = clock[LAST]!;
  if (TIME[1] === 1) {
    TIME[0] = last === last ? last + MISSING_TIME_STEP_MS : 0;
    clock[LAST] = TIME[0]!;
    if (clock[SAID_MISSING] === 0) {
      clock[SAID_MISSING] = 1;
      warn(
        "handrig: frame.timeMs is missing: each frame without it is taken as 33.3 ms (one frame at 30 fps) after the last. " +
          "Give every frame its time in milliseconds (performance.now(), or a video frame's time * 1000): the filters, " +
          "the dropout hold and the turn limits run on it. (Said once per rig.)",
      );
    }
    return;
  }
  const t = TIME[0]!;
  const step = t - last;
  clock[LAST] = t;
  if (step >= SECONDS_STEP_MIN && step <= SECONDS_STEP_MAX) clock[SECONDS_RUN]!++;
  else clock[SECONDS_RUN] = 0;
  if (step >= 1 && step <= INDEX_STEP_MAX && step === Math.floor(step)) clock[INDEX_RUN]!++;
  else clock[INDEX_RUN] = 0;
  if (clock[SECONDS_RUN]! >= SECONDS_FRAMES && clock[SAID_SECONDS] === 0) {
    clock[SAID_SECONDS] = 1;
    warn(
      `handrig: frame.timeMs advanced by ${step.toFixed(3)} a frame for ${SECONDS_FRAMES} frames: it looks like seconds. ` +
        "timeMs is milliseconds (performance.now(), or a video frame's time * 1000); in seconds the filters and the " +
        "dropout hold see frames microseconds apart. (Said once per rig.)",
    );
  }
  if (clock[INDEX_RUN]! >= INDEX_FRAMES && clock[SAID_INDEX] === 0) {
    clock[SAID_INDEX] = 1;
    warn(
      `handrig: frame.timeMs advanced by ${step} a frame for ${INDEX_FRAMES} frames: it looks like frame numbers. ` +
        "timeMs is milliseconds (performance.now(), a video frame's time * 1000, or frame number * 1000 / fps); as frame " +
        "numbers the filters see 1000 frames a second and the dropout hold lasts 30 times too long. (Said once per rig.)",
    );
  }
}

/** The solver for one avatar. Create once, `solve` every frame, `free()` when done. */
export class HandRig {
  #raw: RawHandRig | null = null;
  #input = new Float32Array(0);
  #output = new Float32Array(0);
  #result: object | undefined;
  #driven: number[] = [];
  #present: number[] = [];
  // Per side the bone carrying the aligned point, then per side 1 for a stand-in (alignedBones()).
  #aligned: Uint8Array = new Uint8Array(4);
  #framesRead = 0;
  // The last frame's time, and the time checks' state (clockCheck).
  #clock = new Float64Array([Number.NaN, 0, 0, 0, 0, 0]);
  #faceSeen = false;
  #faceSkip = 0;

  /**
   * `new HandRig(restPose, options?)`: a solver for one avatar. `restPose.bones` maps VRM 1.0
   * humanoid bone names to rest world positions [x, y, z] (meters, the model's own frame,
   * three-vrm's normalized bones); `restPose.vrmVersion` is "0" or "1" (default "1").
   * @param restPose rest world positions of the normalized bones (see `restPoseFromVRM` in `handrig/three-vrm`).
   * @throws Error naming the field on bad input (unknown bone, missing required bone, non-finite number, unknown option).
   */
  constructor(restPose: RestPose, options?: HandRigOptions) {
    if ((restPose as unknown) === ADOPT) {
      this.#adopt(options as unknown as RawHandRig);
      return;
    }
    ensureReady("new HandRig()");
    let r: RawHandRig;
    try {
      const { rest, version, skin, lookAt } = restPoseToFlat(restPose);
      r = new (wasm().HandRig)(rest, version, optionsValue(options), skin?.positions, skin?.bones, skin?.triangles, lookAt);
    } catch (e) {
      throw asError(e);
    }
    this.#adopt(r);
  }

  #adopt(r: RawHandRig): void {
    this.#raw = r;
    const states = r.boneStates();
    const driven: number[] = [];
    const present: number[] = [];
    for (let i = 0; i < BONE_COUNT; i++) {
      if (states[i] !== 0) present.push(i);
      if (states[i] === 2) driven.push(i);
    }
    this.#driven = driven;
    this.#present = present;
    this.#aligned = r.alignedBones();
    // Once per rig: an avatar without `alignment.finger`'s distal bone aligns and touches with
    // what it has (docs/how-it-works/alignment-ik.md), never silently off.
    const warning = r.alignmentWarning;
    if (typeof warning === "string" && warning.length > 0) (globalThis as { console?: { warn(m: string): void } }).console?.warn(warning);
    this.#input = new Float32Array(0);
    this.#output = new Float32Array(0);
  }

  /**
   * A rig for a `.vrm` file (VRM 1.0 or 0.x), read directly from its bytes (parsed in wasm).
   * @throws Error starting with "vrm:" for a truncated or non-VRM file.
   */
  static fromVrm(bytes: Uint8Array | ArrayBuffer | ArrayBufferView, options?: HandRigOptions): HandRig {
    ensureReady("HandRig.fromVrm()");
    let r: RawHandRig;
    try {
      r = wasm().HandRig.fromVrm(vrmBytes(bytes), optionsValue(options));
    } catch (e) {
      throw asError(e);
    }
    return new HandRig(ADOPT as RestPose, r as unknown as HandRigOptions);
  }

  /**
   * A rig for any glTF humanoid (`.glb`, or a `.vrm`), read from the file's bytes (in wasm). The
   * humanoid is `options.skeleton.boneMap` (`{ leftHand: "nodeName", ... }`, the whole binding)
   * when given, else the VRM extension, else Mixamo (`mixamorig:LeftHandIndex1`) or Unreal
   * (`upperarm_l`, `index_01_l`) node names. The model may face +Z or -Z (found from its
   * skeleton); bone rest rotations (rolls) do not matter. `rig.boneMap()` reports the binding.
   * @throws Error starting with "gltf:" naming the bone (missing required bones, duplicate
   * bindings, a chain out of order, no humanoid found) or the part of the file.
   */
  static fromGltf(bytes: Uint8Array | ArrayBuffer | ArrayBufferView, options?: HandRigOptions & GltfOptions): HandRig {
    ensureReady("HandRig.fromGltf()");
    let r: RawHandRig;
    try {
      const { boneMap, rest } = splitSkeletonOptions(options);
      r = wasm().HandRig.fromGltf(vrmBytes(bytes), boneMap, optionsValue(rest));
    } catch (e) {
      throw asError(e);
    }
    return new HandRig(ADOPT as RestPose, r as unknown as HandRigOptions);
  }

  /**
   * Which node each humanoid bone is bound to, `{ hips: "mixamorig:Hips", ... }` (node names as
   * written in the file), for a rig made by `HandRig.fromGltf`; `null` for other rigs.
   */
  boneMap(): BoneMap<string> | null {
    const m = this.#live("boneMap").boneMap();
    return m === undefined ? null : (m as BoneMap<string>);
  }

  /**
   * Every option with its path, type, range, default and description: `{ path, type, default,
   * values?, min?, max?, step?, description }`. Numbers are the shortest decimals of the f32
   * values Rust holds (`0.05`, not `0.05000000074505806`); `min` and `max` are accepted.
   */
  static optionDescriptions(): OptionDescription[] {
    ensureReady("HandRig.optionDescriptions()");
    return cleanDescriptions();
  }

  /** The flat frame layout (same as the `LAYOUT` export): offsets of the input and output arrays; see docs/reference/flat-layout.md. */
  static get layout(): FlatLayout {
    return LAYOUT;
  }

  #live(method: string): RawHandRig {
    const r = this.#raw;
    if (r === null) {
      throw new Error(`HandRig.${method}: this rig was freed (free() was called); create a new HandRig`);
    }
    return r;
  }

  // Views into wasm memory, re-created only when the memory grew (its old buffer is then
  // detached and the old views have length 0).
  #views(method: string): RawHandRig {
    const r = this.#live(method);
    if (this.#input.length === 0) {
      const buffer = wasmMemory().buffer;
      this.#input = new Float32Array(buffer, r.inputPtr(), LI.length);
      this.#output = new Float32Array(buffer, r.outputPtr(), LO.length);
    }
    return r;
  }

  /**
   * The rig's flat input array (a Float32Array view into wasm memory, `LAYOUT.input`): write a
   * frame here, then call `solveFlat(timeMs)`. Read the getter again after creating other rigs
   * (a view goes stale when wasm memory grows); it returns the same view while it is valid.
   */
  get input(): Float32Array {
    this.#views("input");
    return this.#input;
  }

  /** The rig's flat output array (a Float32Array view into wasm memory, `LAYOUT.output`). */
  get output(): Float32Array {
    this.#views("output");
    return this.#output;
  }

  /**
   * Solves the frame in `rig.input` into `rig.output`. Allocates nothing.
   * @param timeMs the frame's timestamp, milliseconds.
   */
  solveFlat(timeMs: number): void {
    const r = this.#views("solveFlat");
    if (typeof timeMs !== "number") throw new TypeError(`timeMs: must be a number, got ${describe(timeMs)}`);
    if (r.solveFlat(timeMs) !== 0) throw new Error(r.takeError());
  }

  /**
   * Copies `input` (a Float32Array of `LAYOUT.input.length`) in, solves, and copies the output
   * into `output` (a Float32Array of `LAYOUT.output.length`), which it returns. Allocates nothing.
   */
  solveInto(input: Float32Array, output: Float32Array, timeMs: number): Float32Array {
    const r = this.#views("solveInto");
    if (!(input instanceof Float32Array) || input.length !== LI.length) {
      throw new TypeError(`input: must be a Float32Array of ${LI.length} (LAYOUT.input.length)`);
    }
    if (!(output instanceof Float32Array) || output.length !== LO.length) {
      throw new TypeError(`output: must be a Float32Array of ${LO.length} (LAYOUT.output.length)`);
    }
    if (typeof timeMs !== "number") throw new TypeError(`timeMs: must be a number, got ${describe(timeMs)}`);
    this.#input.set(input);
    if (r.solveFlat(timeMs) !== 0) throw new Error(r.takeError());
    output.set(this.#output);
    return output;
  }

  /**
   * Solves one frame (see docs/guide/frames.md and docs/reference/results.md for the frame and result shapes). Returns the rig's own
   * result object, updated in place by the next call (a warmed-up frame allocates nothing); pass
   * `target` (e.g. `{}`) to fill an object of your own instead, for results you keep.
   * @throws Error naming the field (e.g. "frame.hands[0].worldLandmarks: must have 21 points, got 20"); the rig is unchanged and keeps working.
   */
  solve(frame: FrameInput, target?: object): SolveResult {
    const r = this.#views("solve");
    if (typeof target === "string") kalidokitCall(frame, target);
    // The target is checked first: a rejected call leaves the rig where it was.
    let result: unknown = target;
    if (result === undefined || result === null) {
      if (this.#result === undefined) this.#result = {};
      result = this.#result;
    } else if (!isObject(result) || !Object.isExtensible(result)) {
      throw new TypeError(
        `target: must be an object to fill with the result${isObject(result) ? " (this one is frozen, sealed or not extensible)" : `, got ${describe(result)}`}`,
      );
    }
    try {
      const first = this.#framesRead < 3;
      // A face's fields are looked for in every frame once a frame had them, else in every
      // 30th (FACE_FIELDS).
      const lookForFace = this.#faceSeen || first || ++this.#faceSkip >= 30;
      if (lookForFace) this.#faceSkip = 0;
      packFrame(frame, this.#input, first, lookForFace);
      if (FACE_FIELDS.given) this.#faceSeen = true;
      if (first) this.#framesRead++;
    } catch (e) {
      throw readError(e);
    }
    // A getter that freed this rig or grew wasm memory (creating rigs) while the frame was read:
    // the input view is gone, and what was packed with it.
    if (this.#input.length === 0) {
      this.#views("solve");
      throw new Error("frame: reading it changed wasm memory (a getter created or freed rigs); the frame was not solved, solve it again");
    }
    const clock = this.#clock;
    const last = clock[LAST]!;
    clockCheck(clock);
    if (r.solveFlat(TIME[0]!) !== 0) {
      clock[LAST] = last;
      throw new Error(r.takeError());
    }
    return fillResult(result as object, this.#output, this.#input, this.#driven, this.#present, this.#aligned) as SolveResult;
  }

  /**
   * The avatar's self-contact model at rest (meters, the model's own frame): `{ anchors: { nose,
   * chin, mouth, leftCheek, rightCheek, leftEar, rightEar, forehead: [x, y, z] }, headBreadth,
   * colliders: { torso?, neck?: { a, b, radius }, head?: { center, radius } } }` (from
   * `contact.faceAnchors` where given, derived from the rig elsewhere: on the skin when the rest
   * pose has one, `skin` then says what was learned from it; with a skin the colliders are not
   * used, the skin is). Anchors relative to the head bone are `anchors[name] - restWorldPositions().head`.
   */
  contactModel(): ContactModel {
    const v = this.#live("contactModel").contactModel();
    const p = (k: number): Vec3 => [v[k]!, v[k + 1]!, v[k + 2]!];
    const faceAnchors = optionNames().faceAnchors;
    const anchors: { [name: string]: Vec3 } = {};
    faceAnchors.forEach((name, i) => (anchors[name] = p(3 * i)));
    const colliders: { [name: string]: object } = {};
    let k = 3 * faceAnchors.length + 1;
    for (const name of ["torso", "neck"]) {
      if (v[k] === 1) colliders[name] = { a: p(k + 1), b: p(k + 4), radius: v[k + 7] };
      k += 8;
    }
    if (v[k] === 1) colliders.head = { center: p(k + 1), radius: v[k + 4] };
    k += 5;
    const skin =
      v[k] === 1
        ? { samples: v[k + 1]!, fingerRadius: [v[k + 2]!, v[k + 3]!] as [number, number], palmHalfThickness: [v[k + 4]!, v[k + 5]!] as [number, number] }
        : null;
    return { anchors, headBreadth: v[3 * faceAnchors.length], colliders, skin } as ContactModel;
  }

  /**
   * What carries each side's aligned point on this avatar, chosen at construction: `{ left,
   * right }`, each `{ finger, bone, standIn }`. `alignment.finger`'s distal bone as configured;
   * on an avatar without it (partial finger rigs), a shallower bone of that finger (its tip
   * extrapolated), another finger, or the palm (`finger: "palm"`, `bone: "<side>Hand"`); the
   * rig then warned once with `console.warn`. Same as `result.alignment.<side>.finger`/`.bone`.
   */
  alignedBones(): { left: AlignedBone; right: AlignedBone } {
    this.#live("alignedBones");
    const side = (s: number): AlignedBone => {
      const i = this.#aligned[s]!;
      return { finger: BONE_FINGER[i] as FingerName | "palm", bone: BONES[i]!, standIn: this.#aligned[2 + s] === 1 };
    };
    return { left: side(0), right: side(1) };
  }

  /** `{ [boneName]: [x, y, z] }`: rest world positions of the avatar's bones, meters, the model's own frame. */
  restWorldPositions(): BoneMap<Vec3> {
    const p = this.#live("restWorldPositions").restPositions();
    const o: { [name: string]: Vec3 } = {};
    for (const i of this.#present) o[BONES[i]!] = [p[3 * i]!, p[3 * i + 1]!, p[3 * i + 2]!];
    return o;
  }

  /** The bones this avatar has, parent-first, VRM 1.0 names. */
  boneNames(): HumanBoneName[] {
    this.#live("boneNames");
    return this.#present.map((i) => BONES[i]!);
  }

  /** The bones the rig writes every frame (in `result.bones`), parent-first. */
  drivenBones(): HumanBoneName[] {
    this.#live("drivenBones");
    return this.#driven.map((i) => BONES[i]!);
  }

  /** "0" or "1": the VRM version the rig was built for. */
  get vrmVersion(): "0" | "1" {
    return this.#live("vrmVersion").vrmVersion as "0" | "1";
  }

  /** Body scale in force for pose input (avatar arm / user arm); before any calibration sample, avatar arm / 0.52 m. */
  get bodyScale(): number {
    return this.#live("bodyScale").bodyScale;
  }

  /** Restarts body-scale calibration. */
  resetCalibration(): void {
    this.#live("resetCalibration").resetCalibration();
  }

  /** Forgets all history: filters, dropout holds and blends, held hands, elbow swivel, body-scale calibration. */
  reset(): void {
    this.#live("reset").reset();
    this.#clock[LAST] = Number.NaN;
    this.#clock[SECONDS_RUN] = 0;
    this.#clock[INDEX_RUN] = 0;
  }

  /**
   * Calibrates the hand scale of `handStrategy: "retarget"` from the last hand solved on each
   * side, which should be an open, flat hand (call it while the user shows one). Returns
   * `{ left, right }`: the new scale (avatar hand / user hand), or null where nothing changed (no
   * hand yet, fingers not straight).
   */
  calibrateHandScale(): { left: number | null; right: number | null } {
    const [left, right] = this.#live("calibrateHandScale").calibrateHandScale() as unknown as [number, number];
    return { left: Number.isNaN(left) ? null : left, right: Number.isNaN(right) ? null : right };
  }

  /**
   * Starts the neutral face's calibration again: the next `face.calibrationTime` seconds of face
   * frames are averaged into the user's neutral face (call it while the user looks at the camera
   * with a relaxed face). A rig calibrates over its first face frames by itself.
   */
  calibrateFace(): void {
    this.#live("calibrateFace").calibrateFace();
  }

  /** Releases the wasm memory. Safe to call twice (idempotent); the rig throws on use afterwards. */
  free(): void {
    const r = this.#raw;
    if (r) {
      this.#raw = null;
      this.#input = new Float32Array(0);
      this.#output = new Float32Array(0);
      r.free();
    }
  }

  /**
   * True once `free()` was called. (Where `Symbol.dispose` exists the rig also has
   * `[Symbol.dispose]()`, an alias of `free()`; it is left out of these types so that they
   * type-check without the esnext.disposable lib.)
   */
  get freed(): boolean {
    return this.#raw === null;
  }
}

addDispose(HandRig);
