// The flat frame layout (src/flat/layout.rs): offsets of the input and output Float32Arrays in
// wasm memory, the name lists of the bones, torso bones, body joints and face points, and the
// names of the output's codes. Its values (layout.json) and types (layout-types.ts) are generated
// from the Rust declaration; build.mjs inlines the values as `__HANDRIG_LAYOUT__`, so they are
// there before `init()` (and in the three-vrm adapter) and cannot drift from Rust. The
// finger and face-anchor names come from the option descriptions (options.json, generated from
// the same Rust: their option rows list them in Rust's order). No name list is retyped here.

import { LAYOUT_VERSION, type InputLayout, type OutputLayout } from "./layout-types.js";
import { cleanDescriptions } from "./options.js";

/** The 55 VRM 1.0 humanoid bone names, parent-first (three-vrm's order). */
export type HumanBoneName =
  | "hips" | "spine" | "chest" | "upperChest" | "neck" | "head" | "leftEye" | "rightEye" | "jaw"
  | "leftUpperLeg" | "leftLowerLeg" | "leftFoot" | "leftToes"
  | "rightUpperLeg" | "rightLowerLeg" | "rightFoot" | "rightToes"
  | "leftShoulder" | "leftUpperArm" | "leftLowerArm" | "leftHand"
  | "rightShoulder" | "rightUpperArm" | "rightLowerArm" | "rightHand"
  | "leftThumbMetacarpal" | "leftThumbProximal" | "leftThumbDistal"
  | "leftIndexProximal" | "leftIndexIntermediate" | "leftIndexDistal"
  | "leftMiddleProximal" | "leftMiddleIntermediate" | "leftMiddleDistal"
  | "leftRingProximal" | "leftRingIntermediate" | "leftRingDistal"
  | "leftLittleProximal" | "leftLittleIntermediate" | "leftLittleDistal"
  | "rightThumbMetacarpal" | "rightThumbProximal" | "rightThumbDistal"
  | "rightIndexProximal" | "rightIndexIntermediate" | "rightIndexDistal"
  | "rightMiddleProximal" | "rightMiddleIntermediate" | "rightMiddleDistal"
  | "rightRingProximal" | "rightRingIntermediate" | "rightRingDistal"
  | "rightLittleProximal" | "rightLittleIntermediate" | "rightLittleDistal";

/** The torso bones `frame.torso` may give, parent-first (`LAYOUT.torsoBones`). */
export type TorsoBoneName =
  | "hips" | "spine" | "chest" | "upperChest" | "neck" | "head" | "leftShoulder" | "rightShoulder";

/** Body-tracker joints (`LAYOUT.bodyJoints`), named by the avatar bone whose joint they are, plus the face. */
export type BodyJointName =
  | "hips" | "leftUpperLeg" | "rightUpperLeg" | "leftUpperArm" | "rightUpperArm"
  | "nose" | "leftEye" | "rightEye" | "leftEar" | "rightEar";

/** Face points a body tracker may give (`frame.face`, `LAYOUT.facePoints`). */
export type FacePointName = "nose" | "leftEye" | "rightEye" | "leftEar" | "rightEar" | "mouth";

/** Offsets of the flat frame layout (`LAYOUT`): indices into the input and output Float32Arrays. See docs/reference/flat-layout.md. */
export interface FlatLayout {
  /** Bumped whenever an offset or meaning changes. */
  readonly version: number;
  /** Input offsets (generated from src/flat/layout.rs). */
  readonly input: InputLayout;
  /** Output offsets (generated from src/flat/layout.rs). */
  readonly output: OutputLayout;
  /** The 55 bone names in output order. */
  readonly bones: readonly HumanBoneName[];
  /** The bones VRM requires. */
  readonly requiredBones: readonly HumanBoneName[];
  /** The torso section's bones, in order. */
  readonly torsoBones: readonly TorsoBoneName[];
  /** The body section's joints, in order. */
  readonly bodyJoints: readonly BodyJointName[];
  /** The face section's points (`frame.face`), in order. */
  readonly facePoints: readonly FacePointName[];
  /** The names of `output.side.handStatus`'s codes, by code (0: `"none"`, no hand this frame). */
  readonly handStatus: readonly string[];
  /** The names of `output.side.handCheck`'s codes, by code (0: `"good"`). */
  readonly handCheck: readonly string[];
  /** The names of `output.side.handResolved`'s codes, by code (0: `"none"`). */
  readonly handResolved: readonly string[];
  /** The names of `output.handUse`'s codes, by code (0: `"none"`, no such hand). */
  readonly handUse: readonly string[];
  /** The 52 ARKit blendshape names, in `input.faceShapes` and `output.arkit` order (issue 50). */
  readonly arkit: readonly string[];
  /** The VRM 1.0 presets of `output.expressions`, in order. */
  readonly expressions: readonly string[];
  /** The face-mesh landmark indices `input.faceMesh` holds, in order. */
  readonly faceMesh: readonly number[];
}

// Defined by build.mjs (esbuild `define`): layout.json, generated from the Rust declaration.
declare const __HANDRIG_LAYOUT__: FlatLayout;

function deepFreeze<T extends object>(o: T): T {
  for (const v of Object.values(o)) if (v !== null && typeof v === "object") deepFreeze(v as object);
  return Object.freeze(o);
}

/** The flat frame layout of this build. */
export const LAYOUT: FlatLayout = deepFreeze(__HANDRIG_LAYOUT__);
if (LAYOUT.version !== LAYOUT_VERSION) {
  // The generated types and the wasm come from one build; a mismatch is a broken build.
  throw new Error(`handrig: the wasm's layout version ${LAYOUT.version} is not the TypeScript layer's ${LAYOUT_VERSION}`);
}

export const LI = LAYOUT.input;
export const LO = LAYOUT.output;
export const BONES = LAYOUT.bones;
export const BONE_COUNT = BONES.length;
export const BONE_INDEX = new Map<string, number>(BONES.map((name, i) => [name, i]));
export const HAND_POINTS = 21;
export const POSE_POINTS = 33;
export const MAX_HANDS = (LI.pose - LI.hands) / LI.handStride;
/** The avatar's sides, in the order of the layout's per-side sections. */
export const SIDES = ["left", "right"] as const;

/** Names Rust lists in its option table: the fingers (`alignment.finger`) and face anchors. */
export interface OptionNames {
  /** Thumb first (Rust's `Finger` order: the output's per-finger sections). */
  readonly fingers: readonly string[];
  /** Rust's `FaceAnchor` order (the output's `contactAnchor` index). */
  readonly faceAnchors: readonly string[];
}

let optionNamesCache: OptionNames | undefined;

/** The finger and face-anchor names, from the option descriptions (their rows list them in Rust's order). */
export function optionNames(): OptionNames {
  if (optionNamesCache === undefined) {
    const rows = cleanDescriptions() as { path: string; values?: string[]; names?: string[] }[];
    const row = (path: string) => {
      const d = rows.find((r) => r.path === path);
      if (d === undefined) throw new Error(`handrig: optionDescriptions() has no ${path}`);
      return d;
    };
    optionNamesCache = Object.freeze({
      fingers: Object.freeze([...(row("alignment.finger").values ?? [])]),
      faceAnchors: Object.freeze([...(row("contact.faceAnchors").names ?? [])]),
    });
  }
  return optionNamesCache;
}
