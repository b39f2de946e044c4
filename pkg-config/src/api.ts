// What every entry point exports besides init: the classes, the layout, `wasmBuild()`, and the
// public types (index.ts's declarations are the package's index.d.ts).

import { ensureReady, wasm } from "./wasm.js";

export { ChainSolver } from "./chain-solver.js";
export type { ChainSolution, ChainSolverOptions, JointConstraint } from "./chain-solver.js";
export type {
  BodyInput,
  BodyJointInput,
  BoneMap,
  FaceInput,
  Frame,
  FrameInput,
  HandInput,
  HandLandmarkerResultLike,
  HandednessCategory,
  HandednessLabel,
  HolisticLandmarkerResultLike,
  Landmark,
  LandmarkList,
  LegacyHandsResultLike,
  LegacyHolisticResultLike,
  PoseInput,
  Quat,
  QuatLike,
  RestPose,
  SkinRest,
  TorsoInput,
  Vec3,
  WristInput,
} from "./frame-types.js";
export { HandRig } from "./hand-rig.js";
export type { GltfOptions } from "./hand-rig.js";
export { LAYOUT } from "./layout.js";
export { MotionRecorder } from "./motion-recorder.js";
export type { BVHOptions, RecordableResult, RecordableRig, VRMAOptions } from "./motion-recorder.js";
export type { BodyJointName, FlatLayout, HumanBoneName, TorsoBoneName } from "./layout.js";
export type { InputLayout, OutputLayout } from "./layout-types.js";
export type { HandRigOptions, OptionDescription } from "./options.js";
export type {
  AlignedBone,
  AlignmentReport,
  ContactModel,
  ContactReport,
  FaceAnchorName,
  FingerName,
  Fingers,
  HandUse,
  IkTarget,
  RetargetReport,
  SolveResult,
  TrackedHand,
} from "./result-types.js";

/**
 * What `init` accepts: the .wasm file's URL (string or URL), a fetch `Response` (or a promise of
 * one), its bytes, or a compiled `WebAssembly.Module`. Typed structurally so that no DOM lib is
 * needed to type-check the package's types.
 */
export type InitInput =
  | string
  | { readonly href: string }
  | { arrayBuffer(): Promise<ArrayBuffer> }
  | ArrayBuffer
  | ArrayBufferView
  | object
  | Promise<unknown>;

/**
 * Which of the package's two WebAssembly builds is running: `"simd128"` (WebAssembly SIMD,
 * chosen where the engine supports it) or `"baseline"`. Throws before `init()` in browsers.
 */
export function wasmBuild(): "simd128" | "baseline" {
  ensureReady("wasmBuild()");
  return wasm().wasmBuild() as "simd128" | "baseline";
}

// Defined by build.mjs (esbuild `define`): the crate's version, from Cargo.toml.
declare const __HANDRIG_VERSION__: string;

/** The package version. */
export const version: string = __HANDRIG_VERSION__;
