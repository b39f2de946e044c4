// The public types of what handrig reads: rest poses and frames (handrig's own shapes and
// MediaPipe's results). Conventions: meters, radians, milliseconds; right-handed, +Y up; the
// avatar faces +Z (VRM 1.0; VRM 0.x models face -Z and everything is in the model's own frame);
// quaternions [x, y, z, w]. Types only: frame.ts and frame-*.ts read these shapes.

import type { BodyJointName, HumanBoneName, TorsoBoneName } from "./layout.js";

/** [x, y, z], meters. */
export type Vec3 = [number, number, number];
/** Unit quaternion [x, y, z, w]. */
export type Quat = [number, number, number, number];

/** Per-bone values; only the bones the avatar has (or that were solved) are present. */
export type BoneMap<T> = { [bone in HumanBoneName]?: T };

/** Rest pose of an avatar: world positions of three-vrm's normalized bones at rest. */
export interface RestPose {
  /** Rest world position of each bone, meters, the model's own frame. Required VRM bones must be present. */
  bones: BoneMap<Vec3> | Record<string, Vec3>;
  /** VRM version of the model: "0" models face -Z. Default "1". */
  vrmVersion?: "0" | "1" | 0 | 1;
  /**
   * The avatar's skin at rest, from which self-contact learns the body's surface (face, chest,
   * hands: docs/how-it-works/contact.md); `restPoseFromVRM` fills it from three-vrm's meshes. Without it the
   * rig models the body from its bones.
   */
  skin?: SkinRest;
  /**
   * The point between the avatar's eyes relative to its head bone's rest position (meters, the
   * model's own frame: three-vrm's `vrm.lookAt.offsetFromHeadBone`, what `HandRig.fromVrm` reads
   * from the file's look-at). Self-contact places the face with it when the avatar has no eye
   * bones; `restPoseFromVRM` fills it. Optional.
   */
  lookAtOffset?: Vec3;
}

/** An avatar's skin at rest (`RestPose.skin`). */
export interface SkinRest {
  /** Rest positions, 3 numbers per vertex (meters, the model's own frame, as `bones`). */
  positions: Float32Array | ArrayLike<number>;
  /**
   * Each vertex's dominant humanoid bone, as its index in `LAYOUT.bones` (a non-humanoid bone
   * counts as its nearest humanoid ancestor, and then adds 128: hair, cloth and accessories on
   * bones of their own; the head's such vertices below the neck are not taken as the head).
   */
  bones: Uint8Array | ArrayLike<number>;
  /** Triangles, 3 vertex indices each (optional: without them only the vertices are used). */
  triangles?: Uint32Array | ArrayLike<number>;
}

/** A point as MediaPipe gives it; pose landmarks carry `visibility`. */
export interface Landmark {
  x: number;
  y: number;
  z: number;
  visibility?: number;
}

/** 21 (hand) or 33 (pose) points: `{x, y, z}` objects, `[x, y, z]` arrays, or a flat list of 63 / 99 numbers. */
export type LandmarkList =
  | ReadonlyArray<Landmark | Vec3 | readonly [number, number, number]>
  | ReadonlyArray<number>
  | Float32Array
  | Float64Array;

/** A MediaPipe handedness category (tasks-vision `Category`, legacy `Handedness`). */
export interface HandednessCategory {
  categoryName?: string;
  label?: string;
  score?: number;
  index?: number;
  displayName?: string;
}

/** MediaPipe's label: it assumes a mirrored (selfie) image; see the README's mirror table. */
export type HandednessLabel = "Left" | "Right";

/** One hand in handrig's own shape. */
export interface HandInput {
  /** MediaPipe's label as given, a category, or tasks-vision's `[category]`. */
  handedness: HandednessLabel | HandednessCategory | ReadonlyArray<HandednessCategory>;
  /** Handedness score 0..1 (default: the category's score, else 1). */
  score?: number;
  /** 21 world landmarks, meters, MediaPipe camera axes (x image-right, y down, z away from the camera). */
  worldLandmarks?: LandmarkList;
  /** 21 normalized image landmarks (used when worldLandmarks is absent). */
  landmarks?: LandmarkList;
}

/** tasks-vision `HandLandmarkerResult`. */
export interface HandLandmarkerResultLike {
  landmarks?: ReadonlyArray<LandmarkList>;
  worldLandmarks?: ReadonlyArray<LandmarkList>;
  handedness?: ReadonlyArray<ReadonlyArray<HandednessCategory>>;
  handednesses?: ReadonlyArray<ReadonlyArray<HandednessCategory>>;
}

/** Legacy `@mediapipe/hands` results. */
export interface LegacyHandsResultLike {
  multiHandLandmarks?: ReadonlyArray<LandmarkList>;
  multiHandWorldLandmarks?: ReadonlyArray<LandmarkList>;
  multiHandedness: ReadonlyArray<HandednessCategory>;
}

/** Legacy `@mediapipe/holistic` results (image landmarks only for hands). */
export interface LegacyHolisticResultLike {
  leftHandLandmarks?: LandmarkList;
  rightHandLandmarks?: LandmarkList;
  poseWorldLandmarks?: LandmarkList;
  /** The 0.5 build's minified name for `poseWorldLandmarks` (read beside `poseLandmarks`). */
  za?: LandmarkList;
  /** Earlier builds' minified name for `poseWorldLandmarks`. */
  ea?: LandmarkList;
}

/** tasks-vision `HolisticLandmarkerResult`: per side a list of none or one hand (the subject's side, as its pose). */
export interface HolisticLandmarkerResultLike {
  leftHandLandmarks?: ReadonlyArray<LandmarkList>;
  leftHandWorldLandmarks?: ReadonlyArray<LandmarkList>;
  rightHandLandmarks?: ReadonlyArray<LandmarkList>;
  rightHandWorldLandmarks?: ReadonlyArray<LandmarkList>;
  poseLandmarks?: ReadonlyArray<LandmarkList>;
  poseWorldLandmarks?: ReadonlyArray<LandmarkList>;
  faceLandmarks?: unknown;
  faceBlendshapes?: unknown;
  poseSegmentationMasks?: unknown;
}

/** Pose: 33 world landmarks (meters, camera axes), handrig's shape or a PoseLandmarker result. */
export type PoseInput =
  | { worldLandmarks: LandmarkList | ReadonlyArray<LandmarkList>; landmarks?: LandmarkList | ReadonlyArray<LandmarkList> }
  | { poseWorldLandmarks: LandmarkList }
  | LandmarkList;

/** A wrist from another body tracker, in the avatar's frame. */
export interface WristInput {
  /** Meters, the model's own frame. */
  position: Vec3 | Landmark;
  /** World rotation of the avatar's normalized hand bone [x, y, z, w]. */
  rotation?: Quat;
}

/** A quaternion as an object (three.js `Quaternion`-like). */
export interface QuatLike {
  x: number;
  y: number;
  z: number;
  w: number;
}

/** The app's torso: normalized-bone local rotations [x, y, z, w] (the model's own frame, like handrig's output); a bone left out is at rest. */
export type TorsoInput = { [bone in TorsoBoneName]?: Quat | QuatLike | null };

/** A body-tracker joint, meters, the model's own frame: [x, y, z], [x, y, z, confidence] or { x, y, z, confidence? } (confidence 0..1, default 1). */
export type BodyJointInput =
  | Vec3
  | readonly [number, number, number, number]
  | { x: number; y: number; z: number; confidence?: number };

/** Joints from a body tracker with spine joints (used by `torso: "pose"`); left and right are the avatar's sides. */
export type BodyInput = { [joint in BodyJointName]?: BodyJointInput | null };

/** Face points from the body tracker that gives `wrists` (Azure Kinect: NOSE, EYE_*, EAR_*), meters, the model's own frame, sides by the avatar's sides. The face frame needs both eyes or both ears and a third point. */
export interface FaceInput {
  nose?: Vec3 | Landmark;
  leftEye?: Vec3 | Landmark;
  rightEye?: Vec3 | Landmark;
  leftEar?: Vec3 | Landmark;
  rightEar?: Vec3 | Landmark;
  /** The middle of the mouth. */
  mouth?: Vec3 | Landmark;
}

/**
 * One frame of tracking. A MediaPipe result object may also be passed as the frame itself. A
 * field given as `undefined` is not given (also under `exactOptionalPropertyTypes`).
 */
export interface Frame {
  /**
   * Timestamp, milliseconds (`performance.now()`, or a video frame's time * 1000). A frame
   * without it is taken as 33.3 ms (one frame at 30 fps) after the rig's last frame (0 for the
   * first), and the rig warns once.
   */
  timeMs?: number | undefined;
  /** Hands: handrig's own list, or a HandLandmarker / legacy Hands result. */
  hands?: ReadonlyArray<HandInput> | HandLandmarkerResultLike | LegacyHandsResultLike | undefined;
  /** Pose landmarks. */
  pose?: PoseInput | undefined;
  /** Legacy Pose / Holistic: world landmarks at the top level of the frame. */
  poseWorldLandmarks?: LandmarkList | undefined;
  /** Legacy Pose / Holistic: the pose's image landmarks (with the hands' image landmarks they check handedness). */
  poseLandmarks?: LandmarkList | undefined;
  /** Wrists from another body tracker (used instead of pose wrists). */
  wrists?: { left?: WristInput; right?: WristInput } | undefined;
  /** The app's torso (local rotations, model frame): forward kinematics, alignment and arm IK work from it. */
  torso?: TorsoInput | undefined;
  /** Body-tracker joints: the torso for `torso: "pose"` (preferred over the pose's). */
  body?: BodyInput | undefined;
  /** Face points from the same tracker, for self-contact with tracker wrists (pose wrists use the pose's face landmarks). */
  face?: FaceInput | undefined;
  /**
   * Image width / height, used to scale image-only hand landmarks (legacy Holistic and Hands
   * results, which carry no world landmarks for the hands). Default 16/9: give it for a 4:3 or
   * portrait camera.
   */
  imageAspect?: number | undefined;
}

/** What `solve` accepts. */
export type FrameInput =
  | Frame
  | (Frame & HandLandmarkerResultLike)
  | (Frame & LegacyHandsResultLike)
  | (Frame & LegacyHolisticResultLike)
  | (Omit<Frame, "poseWorldLandmarks" | "poseLandmarks"> & HolisticLandmarkerResultLike);

