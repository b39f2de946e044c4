// Types of the handrig package. Conventions: meters, radians, milliseconds; right-handed, +Y up;
// the avatar faces +Z (VRM 1.0; VRM 0.x models face -Z and everything is in the model's own
// frame); quaternions [x, y, z, w]. build.mjs emits this file as index.d.ts (ES module entry
// points) and index.d.cts (CommonJS, without the default export).

/** [x, y, z], meters. */
export type Vec3 = [number, number, number];
/** Unit quaternion [x, y, z, w]. */
export type Quat = [number, number, number, number];

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

/** Per-bone values; only the bones the avatar has (or that were solved) are present. */
export type BoneMap<T> = { [bone in HumanBoneName]?: T };

/** Rest pose of an avatar: world positions of three-vrm's normalized bones at rest. */
export interface RestPose {
  /** Rest world position of each bone, meters, the model's own frame. Required VRM bones must be present. */
  bones: BoneMap<Vec3> | Record<string, Vec3>;
  /** VRM version of the model: "0" models face -Z. Default "1". */
  vrmVersion?: "0" | "1" | 0 | 1;
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

/** The torso bones `frame.torso` may give, parent-first (`LAYOUT.torsoBones`). */
export type TorsoBoneName =
  | "hips" | "spine" | "chest" | "upperChest" | "neck" | "head" | "leftShoulder" | "rightShoulder";

/** The app's torso: normalized-bone local rotations [x, y, z, w] (the model's own frame, like handrig's output); a bone left out is at rest. */
export type TorsoInput = { [bone in TorsoBoneName]?: Quat | QuatLike | null };

/** Body-tracker joints (`LAYOUT.bodyJoints`), named by the avatar bone whose joint they are, plus the face. */
export type BodyJointName =
  | "hips" | "leftUpperLeg" | "rightUpperLeg" | "leftUpperArm" | "rightUpperArm"
  | "nose" | "leftEye" | "rightEye" | "leftEar" | "rightEar";

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

/** One frame of tracking. A MediaPipe result object may also be passed as the frame itself. */
export interface Frame {
  /** Timestamp, milliseconds. Default 0. */
  timeMs?: number;
  /** Hands: handrig's own list, or a HandLandmarker / legacy Hands result. */
  hands?: ReadonlyArray<HandInput> | HandLandmarkerResultLike | LegacyHandsResultLike;
  /** Pose landmarks. */
  pose?: PoseInput;
  /** Legacy Pose / Holistic: world landmarks at the top level of the frame. */
  poseWorldLandmarks?: LandmarkList;
  /** Legacy Pose / Holistic: the pose's image landmarks (with the hands' image landmarks they check handedness). */
  poseLandmarks?: LandmarkList;
  /** Wrists from another body tracker (used instead of pose wrists). */
  wrists?: { left?: WristInput; right?: WristInput };
  /** The app's torso (local rotations, model frame): forward kinematics, alignment and arm IK work from it. */
  torso?: TorsoInput;
  /** Body-tracker joints: the torso for `torso: "pose"` (preferred over the pose's). */
  body?: BodyInput;
  /** Face points from the same tracker, for self-contact with tracker wrists (pose wrists use the pose's face landmarks). */
  face?: FaceInput;
  /** Image width / height, used to scale image-only hand landmarks. Default 16/9. */
  imageAspect?: number;
}

/** What `solve` accepts. */
export type FrameInput =
  | Frame
  | (Frame & HandLandmarkerResultLike)
  | (Frame & LegacyHandsResultLike)
  | (Frame & LegacyHolisticResultLike)
  | (Omit<Frame, "poseWorldLandmarks" | "poseLandmarks"> & HolisticLandmarkerResultLike);

/** A wrist IK target, the model's own frame. */
export interface IkTarget {
  /** Where the avatar's hand bone (wrist joint) should be, meters. */
  position: Vec3;
  /** World rotation the avatar's normalized hand bone should have. */
  rotation: Quat;
}

/** What fingertip alignment did for one hand. */
export interface AlignmentReport {
  /** Where the user's aligned point (DIP or tip) is, mapped onto the avatar, meters. */
  targetDip: Vec3;
  /** The wrist IK target position, meters. */
  ikWrist: Vec3;
  /** The pose wrist the target was built from, meters. */
  poseWrist: Vec3;
  /** Distance (m) between the avatar's aligned point after IK and targetDip; null when unknown. */
  error: number | null;
  /** Whether the arm reached the IK wrist. */
  reachable: boolean;
  /** Whether the avatar has the aligned finger (otherwise the IK wrist is the pose wrist). */
  aligned: boolean;
  /** What self-contact did for this hand (null with `contact.enabled: false`); `targetDip` and `ikWrist` include it. */
  contact: ContactReport | null;
}

/** A face anchor: a named place of the face contact maps between user and avatar. */
export type FaceAnchorName =
  | "nose"
  | "chin"
  | "mouth"
  | "leftCheek"
  | "rightCheek"
  | "leftEar"
  | "rightEar"
  | "forehead";

/** What self-contact retargeting did for one hand. */
export interface ContactReport {
  /** The face anchor nearest the user's fingertip (null: no face for this side's wrist source, or no hand). */
  anchor: FaceAnchorName | null;
  /** The face contact blend applied, 0 (plain alignment) to 1 (the fingertip mapped onto the avatar's face). */
  weight: number;
  /** Distance (m) from the avatar's fingertip (the aligned finger, after IK) to the avatar's anchor; null when unknown. */
  distance: number | null;
  /** The hand-to-hand contact blend applied, 0..1. */
  handWeight: number;
  /** How far the body colliders pushed the hand, meters. */
  push: number;
}

/** The avatar's self-contact model at rest, meters, the model's own frame (`rig.contactModel()`). */
export interface ContactModel {
  /** The face anchors (from `contact.faceAnchors` where given, derived from the rig elsewhere). */
  anchors: { [name in FaceAnchorName]: Vec3 };
  /** Head breadth (ear to ear) the derived anchors assume, meters. */
  headBreadth: number;
  /** The body colliders (absent where dropped). */
  colliders: {
    torso?: { a: Vec3; b: Vec3; radius: number };
    neck?: { a: Vec3; b: Vec3; radius: number };
    head?: { center: Vec3; radius: number };
  };
}

/** The tracked hand that drove one avatar side this frame. */
export interface TrackedHand {
  /** "solved" from this frame; "held": this frame's hand was degenerate and the previous
   * rotations are reported again; "skipped": degenerate with nothing to hold. */
  status: "solved" | "held" | "skipped";
  /** Its handedness score, 0..1. */
  score: number;
  /** Its index among the frame's hands. */
  index: number;
  /** Its label contradicted the pose wrists and it was reassigned to this side (`handedness: "reassign"`). */
  reassigned: boolean;
}

/** What became of one hand of the frame. */
export type HandUse = "left" | "right" | "lowScore" | "duplicate" | "contradicted";

/** The result of one `solve`, in the model's own frame. */
export interface SolveResult {
  /** The frame's timestamp, milliseconds. */
  timeMs: number;
  /** Local rotations of every bone the rig drives (`rig.drivenBones()`: arms, hands, fingers the avatar has; with `torso: "pose"` the torso bones), every frame: solved, held, or back at rest (identity) when tracking is lost. Write them all to `getNormalizedBoneNode(name).quaternion` (`applyToVRM` does). */
  bones: BoneMap<Quat>;
  /** World positions of every bone of the avatar after solving, meters. */
  worldPositions: BoneMap<Vec3>;
  /**
   * Wrist IK targets, per avatar side, when both the wrist and the hand's rotation are known (a
   * solved hand, or a tracker wrist with `rotation`); a wrist position alone moves the arm
   * (see `worldPositions`) without a target here.
   */
  ikTargets: { left?: IkTarget; right?: IkTarget };
  /** Fingertip-alignment reports, per avatar side. */
  alignment: { left?: AlignmentReport; right?: AlignmentReport };
  /** Which tracked hand drove each avatar side, and whether its rotations are fresh. */
  hands: { left?: TrackedHand; right?: TrackedHand };
  /** Per hand of the frame (its order): the avatar side it drove, or why it was ignored. */
  handUse: HandUse[];
  /** The avatar's fingertips per side (the distal bone extended by the anatomical ratio), every frame and strategy; a finger the avatar lacks is undefined. */
  fingertips: { left?: Fingers<Vec3>; right?: Fingers<Vec3> };
  /** What `handStrategy: "retarget"` did per side this frame (sides freshly solved by it). */
  retarget: { left?: RetargetReport; right?: RetargetReport };
}

/** One value per finger (undefined where the avatar lacks the finger). */
export interface Fingers<T> {
  thumb?: T;
  index?: T;
  middle?: T;
  ring?: T;
  little?: T;
}

/** The retargeting of one hand (seed 003). */
export interface RetargetReport {
  /** The user's fingertips, scaled to the avatar's hand and placed on it (same frame as `fingertips`). */
  targets: Fingers<Vec3>;
  /** Avatar hand size / user hand size. */
  scale: number;
  /** Gauss-Newton iterations (the most any finger needed). */
  iterations: number;
  /** Weighted RMS distance (m) between the avatar's fingertips and the targets. */
  residual: number;
}

export type FingerName = "thumb" | "index" | "middle" | "ring" | "little";

/** Options, set at construction. `HandRig.optionDescriptions()` lists them with ranges and defaults. */
export interface HandRigOptions {
  /** The image given to MediaPipe was flipped horizontally (selfie view). Default false. */
  inputMirrored?: boolean;
  /** The avatar mirrors the user: the user's right hand drives the avatar's left. Default false. */
  mirror?: boolean;
  /** How hands are solved: "analytic" (default) or "retarget" (Gauss-Newton fingertip retargeting, seed 003). */
  handStrategy?: "analytic" | "retarget";
  /** Arm IK solver reaching the wrist target: "twoBone" (default), "fabrik" (seed 002) or "ccd" (seed 004). */
  armSolver?: "twoBone" | "fabrik" | "ccd";
  /** Options every arm solver shares. */
  arm?: {
    /** Largest angle (radians, 0..pi/2) the shoulder turns to help a far reach; 0 keeps shoulders at rest. Default 0.26 (about 15 degrees). */
    shoulderAngle?: number;
    /** Fraction of the arm's length (0.5..1) beyond which the shoulder turns toward the target. Default 0.9. */
    shoulderReach?: number;
    /** Share (0..1) of the hand's twist about the forearm that the forearm takes. Default 0.5. */
    forearmTwist?: number;
    /**
     * Clamp the hand's flexion (80°), extension (70°) and radial (20°) / ulnar (40°) deviation
     * against the forearm, turning the hand about the aligned fingertip so alignment stays exact.
     * Default true; false applies the tracked hand rotation as given.
     */
    wristLimits?: boolean;
  };
  /** Fingertip alignment. */
  alignment?: {
    /** Default true. */
    enabled?: boolean;
    /** Default "index". */
    finger?: FingerName;
    /** Default "dip". */
    point?: "dip" | "tip";
    /** 0..1 blend between the pose wrist (0) and the fully aligned wrist (1). Default 1. */
    weight?: number;
  };
  /** Body-scale calibration from pose landmarks. */
  calibration?: {
    /** Preset body scale (avatar arm / user arm); unset = calibrate automatically. */
    bodyScale?: number;
    /** Pose frames with a visible arm that automatic calibration averages (outliers beyond 20% of the median dropped). Default 30, 1..300. */
    frames?: number;
    /** Pose landmarks below this visibility are ignored. Default 0.5. */
    minVisibility?: number;
  };
  /** Hands whose handedness score is below this are ignored. Default 0.5. */
  minHandScore?: number;
  /** A hand whose label contradicts the pose wrists: "reassign" (default) drives the side the pose says, "drop" ignores it, "trust" keeps MediaPipe's label. */
  handedness?: "reassign" | "drop" | "trust";
  /** One Euro filtering of the landmarks before solving; `false` turns it off. */
  filter?:
    | boolean
    | {
        /** Default true. */
        enabled?: boolean;
        /** Cutoff at rest, Hz (0.05..1000). Default 1.5. */
        minCutoff?: number;
        /** Speed coefficient, Hz per m/s (0..10000). Default 2. */
        beta?: number;
        /** Cutoff of the speed estimate, Hz (0.05..1000). Default 1. */
        dCutoff?: number;
      };
  /** Where the torso comes from: "frame" (default: the app's `frame.torso`, rest where not given; not in `result.bones`), "pose" (tracked from `frame.body` joints or the pose; driven), "off" (the rest torso). */
  torso?: "off" | "frame" | "pose";
  /** Holding and easing over tracking loss; `false`: lost hands and arms snap to rest. */
  dropout?:
    | boolean
    | {
        /** Default true. */
        enabled?: boolean;
        /** How long a lost hand or arm keeps its pose, ms. Default 250. */
        holdMs?: number;
        /** How long it then eases to rest, ms. Default 500. */
        fadeOutMs?: number;
        /** How long a returning one blends in, ms. Default 250. */
        fadeInMs?: number;
      };
  /** Self-contact retargeting: a finger on the face lands on the avatar's face, touching hands stay touching, hands stay out of the body. */
  contact?:
    | boolean
    | {
        /** Default true. */
        enabled?: boolean;
        /** Blend radius in head breadths (0.05..3): full contact mapping within half of it, plain alignment beyond it. Default 0.5. */
        radius?: number;
        /** Scale of the contact blend, 0..1. Default 1. */
        weight?: number;
        /** Hand-to-hand contact. Default true. */
        hands?: boolean;
        /** The avatar's face points, [x, y, z] meters from the head bone at rest in the model's axes (e.g. raycast on its mesh); missing ones are derived from the rig. */
        faceAnchors?: { [name in FaceAnchorName]?: Vec3 | Landmark | null };
        /** Body colliders push hand targets out of the avatar's torso, neck and head. Default true. */
        colliders?: boolean;
        /** Torso capsule radius, meters (0..2); unset = 0.6 x the shoulder half-width; 0 = none. */
        torsoRadius?: number | null;
        /** Head sphere radius, meters (0..2); unset = half the head breadth; 0 = none. */
        headRadius?: number | null;
        /** MediaPipe pose input: how much the tracked depth between fingertip and face counts (0..1); where on the face comes from the image. Default 0.1. */
        depthTrust?: number;
      };
  /** The objective of handStrategy "retarget" (seed 003). See docs/options.md. */
  retarget?: {
    tipWeights?: [number, number, number, number, number];
    jointWeight?: number;
    pinchWeight?: number;
    pinchDistance?: number;
    spatialWeight?: number;
    temporalWeight?: number;
    temporalSpeed?: number;
    maxIterations?: number;
    stepTolerance?: number;
  };
  /** Dotted paths as `optionDescriptions()` spells them are accepted too: `{ "alignment.weight": 0.5 }`. */
  [dottedPath: `${string}.${string}`]:
    | boolean
    | number
    | number[]
    | string
    | null
    | undefined
    | { [name in FaceAnchorName]?: Vec3 | Landmark | null };
}

/** Offsets of the flat frame layout (`LAYOUT`): indices into the input and output Float32Arrays. See the README. */
export interface FlatLayout {
  /** Bumped whenever an offset or meaning changes. */
  readonly version: number;
  readonly input: {
    readonly length: number;
    readonly handCount: number;
    readonly imageAspect: number;
    readonly posePresent: number;
    readonly poseHasImage: number;
    readonly poseImage: number;
    readonly hands: number;
    readonly handStride: number;
    readonly hand: {
      readonly handedness: number;
      readonly score: number;
      readonly hasWorld: number;
      readonly hasImage: number;
      readonly world: number;
      readonly image: number;
    };
    readonly pose: number;
    readonly poseStride: number;
    readonly wrists: number;
    readonly wristStride: number;
    readonly wrist: {
      readonly present: number;
      readonly hasRotation: number;
      readonly position: number;
      readonly rotation: number;
    };
    readonly torso: number;
    readonly torsoStride: number;
    readonly torsoBone: {
      readonly present: number;
      readonly rotation: number;
    };
    readonly bodyPresent: number;
    readonly body: number;
    readonly bodyStride: number;
    readonly face: number;
    readonly faceStride: number;
    readonly facePoint: {
      readonly present: number;
      readonly position: number;
    };
  };
  readonly output: {
    readonly length: number;
    readonly boneRotations: number;
    readonly boneFlags: number;
    readonly bonePositions: number;
    readonly sides: number;
    readonly sideStride: number;
    readonly side: {
      readonly handStatus: number;
      readonly handScore: number;
      readonly targetPresent: number;
      readonly targetPosition: number;
      readonly targetRotation: number;
      readonly alignmentPresent: number;
      readonly targetDip: number;
      readonly ikWrist: number;
      readonly poseWrist: number;
      readonly alignmentError: number;
      readonly reachable: number;
      readonly aligned: number;
      readonly handIndex: number;
      readonly handReassigned: number;
      readonly fingertips: number;
      readonly retargetPresent: number;
      readonly retargetTargets: number;
      readonly retargetScale: number;
      readonly retargetIterations: number;
      readonly retargetResidual: number;
      readonly contactPresent: number;
      readonly contactAnchor: number;
      readonly contactWeight: number;
      readonly contactDistance: number;
      readonly contactHandWeight: number;
      readonly contactPush: number;
    };
    readonly handUse: number;
  };
  /** The 55 bone names in output order. */
  readonly bones: readonly HumanBoneName[];
  /** The bones VRM requires. */
  readonly requiredBones: readonly HumanBoneName[];
  /** The torso section's bones, in order. */
  readonly torsoBones: readonly TorsoBoneName[];
  /** The body section's joints, in order. */
  readonly bodyJoints: readonly BodyJointName[];
}

/** The flat frame layout of this build. */
export declare const LAYOUT: FlatLayout;

/** A joint limit of a chain bone, in the parent bone's frame (bone 0: against its rest direction). */
export type JointConstraint =
  | { type: "cone"; maxAngle: number }
  | { type: "hinge"; axis: Vec3 | Landmark; min: number; max: number };

/** Options of a `ChainSolver`. */
export interface ChainSolverOptions {
  /** "fabrik" (default, seed 002) or "ccd" (seed 004). */
  method?: "fabrik" | "ccd";
  /** Rest joint positions, root first, at least 3 (meters). */
  joints: ReadonlyArray<Vec3 | Landmark>;
  /** One entry per bone (joints.length - 1), or null for a free bone; omit for none. */
  constraints?: ReadonlyArray<JointConstraint | null>;
  /** Most iterations per solve (default FABRIK 100, CCD 200). */
  iterations?: number;
  /** End-to-target distance that counts as reached (default 1e-5 of the chain length). */
  tolerance?: number;
  /** CCD's damping: the largest angle (radians) a joint turns per step (default 0.5). */
  maxStepAngle?: number;
}

/** A solved chain. */
export interface ChainSolution {
  /** Joint positions, root first. */
  joints: Vec3[];
  /** Each bone's world rotation from its rest direction. */
  rotations: Quat[];
  /** The end is within the tolerance of the target. */
  reached: boolean;
  /** The target is within the chain's length (limits ignored). */
  reachable: boolean;
  /** End-to-target distance (m). */
  error: number;
  /** Iterations run. */
  iterations: number;
}

/** FABRIK or CCD on any chain (tails, spines, custom rigs). Create once, `solve` per frame, `free()` when done. */
export declare class ChainSolver {
  /** @throws Error naming the field (`options.joints[3]`, `options.constraints[1].maxAngle`). */
  constructor(options: ChainSolverOptions);
  /** Number of joints. */
  readonly jointCount: number;
  /** Solves toward `goal.target` (with the middle joints turned toward `goal.pole`). The result object is reused by the next call; pass `into` for one of your own. */
  solve(goal: { target: Vec3 | Landmark; pole?: Vec3 | Landmark }, into?: object): ChainSolution;
  /** The same into typed arrays (`joints`: 3 N, `rotations`: 4 (N - 1)); sets `reached`, `reachable`, `error`, `iterations` on `out`. Allocates nothing. */
  solveInto<T extends { joints: Float32Array; rotations: Float32Array }>(
    target: Vec3 | Landmark | Float32Array,
    out: T,
    pole?: Vec3 | Landmark | Float32Array,
  ): T & { reached: boolean; reachable: boolean; error: number; iterations: number };
  /** Back to the rest pose. */
  reset(): void;
  /** Releases the wasm memory. Idempotent. */
  free(): void;
  /** True once `free()` was called. */
  readonly freed: boolean;
}

/** One option, for building UIs: its dot-separated path, type, range and default. */
export type OptionDescription =
  | { path: string; type: "boolean"; default: boolean; description: string }
  | { path: string; type: "enum"; values: string[]; default: string; description: string }
  | {
      path: string;
      type: "number";
      min: number;
      max: number;
      /** Absent when the option is unset by default. */
      default?: number | null;
      step: number;
      /** True when only whole numbers are accepted. */
      integer?: boolean;
      description: string;
    }
  | {
      path: string;
      /** An object of named points `{ name: [x, y, z] }`; no default (derived values apply). */
      type: "points";
      names: string[];
      default: null;
      description: string;
    }
  | {
      path: string;
      /** A fixed-length array of numbers, each in min..max. */
      type: "numbers";
      length: number;
      min: number;
      max: number;
      default: number[];
      description: string;
    };

/** The solver for one avatar. Create once, `solve` every frame, `free()` when done. */
export declare class HandRig {
  /**
   * @param restPose rest world positions of the normalized bones (see `restPoseFromVRM` in `handrig/three-vrm`).
   * @throws Error naming the field on bad input (unknown bone, missing required bone, non-finite number, unknown option).
   */
  constructor(restPose: RestPose, options?: HandRigOptions);
  /**
   * A rig for a `.vrm` file (VRM 1.0 or 0.x), parsed in wasm.
   * @throws Error starting with "vrm:" for a truncated or non-VRM file.
   */
  static fromVrm(
    bytes: Uint8Array | ArrayBuffer | ArrayBufferView,
    options?: HandRigOptions,
  ): HandRig;
  /**
   * Every option with its path, type, range, default and description. Numbers are the shortest
   * decimals of the f32 values Rust holds (`0.05`, not `0.05000000074505806`); `min` and `max`
   * are accepted.
   */
  static optionDescriptions(): OptionDescription[];
  /** The flat frame layout (same as the `LAYOUT` export). */
  static readonly layout: FlatLayout;
  /**
   * Solves one frame. Returns the rig's own result object, updated in place by the next call
   * (a warmed-up frame allocates nothing); pass `target` (e.g. `{}`) to fill an object of your
   * own instead, for results you keep.
   * @throws Error naming the field (e.g. "frame.hands[0].worldLandmarks: must have 21 points, got 20"); the rig is unchanged and keeps working.
   */
  solve(frame: FrameInput, target?: object): SolveResult;
  /** The rig's flat input (a Float32Array view into wasm memory, `LAYOUT.input`). Read the getter again after creating other rigs (views go stale when wasm memory grows). */
  readonly input: Float32Array;
  /** The rig's flat output (a Float32Array view into wasm memory, `LAYOUT.output`). */
  readonly output: Float32Array;
  /**
   * Solves the frame in `rig.input` into `rig.output`. Allocates nothing.
   * @param timeMs the frame's timestamp, milliseconds.
   */
  solveFlat(timeMs: number): void;
  /** Copies `input` in, solves, copies the result into `output` (and returns it). Allocates nothing. */
  solveInto(input: Float32Array, output: Float32Array, timeMs: number): Float32Array;
  /** The bones the rig writes every frame (`result.bones`), parent-first. */
  drivenBones(): HumanBoneName[];
  /** Forgets all history: filters, dropout holds and blends, held hands, elbow swivel, body-scale calibration. */
  reset(): void;
  /** Calibrates the retargeting's hand scale from the last hand solved per side (show an open, flat hand); null where nothing changed. */
  calibrateHandScale(): { left: number | null; right: number | null };
  /** Rest world positions of the avatar's bones, meters, the model's own frame. */
  restWorldPositions(): BoneMap<Vec3>;
  /** The avatar's self-contact model at rest: face anchors, head breadth, body colliders. */
  contactModel(): ContactModel;
  /** The bones this avatar has, parent-first. */
  boneNames(): HumanBoneName[];
  /** "0" or "1": the VRM version the rig was built for. */
  readonly vrmVersion: "0" | "1";
  /** Body scale in force for pose input (avatar arm / user arm); before any calibration sample, avatar arm / 0.52 m. */
  readonly bodyScale: number;
  /** Restarts body-scale calibration. */
  resetCalibration(): void;
  /** Releases the wasm memory. Idempotent; the rig throws on use afterwards. */
  free(): void;
  /**
   * True once `free()` was called. (Where `Symbol.dispose` exists the rig also has
   * `[Symbol.dispose]()`, an alias of `free()`; it is left out of these types so that they
   * type-check without the esnext.disposable lib.)
   */
  readonly freed: boolean;
}

/**
 * What `init` accepts: the .wasm file's URL (string or URL), a fetch `Response` (or a promise of
 * one), its bytes, or a compiled `WebAssembly.Module`. Typed structurally so that no DOM lib is
 * needed to type-check this file.
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
 * Instantiates the WebAssembly module. Required once in browsers and bundlers before any other
 * call (`await init()` fetches `handrig_simd_bg.wasm` next to the module where the engine has
 * WebAssembly SIMD, `handrig_bg.wasm` elsewhere; or pass either's URL or bytes); a resolved
 * no-op in Node.
 */
export declare function init(input?: InitInput | { module_or_path: InitInput }): Promise<void>;
/** Synchronous `init` from the .wasm bytes or a compiled module (workers); a no-op in Node. */
export declare function initSync(module?: ArrayBuffer | ArrayBufferView | object): void;
/** The package version. */
export declare const version: string;
/**
 * Which of the package's two WebAssembly builds is running: `"simd128"` (WebAssembly SIMD,
 * chosen where the engine supports it) or `"baseline"`. Throws before `init()` in browsers.
 */
export declare function wasmBuild(): "simd128" | "baseline";
/**
 * The file in the package's `wasm/` folder that `init()` loads in this engine:
 * `"handrig_simd_bg.wasm"` where it has WebAssembly SIMD, else `"handrig_bg.wasm"`. Needs no
 * `init()`: what a page fetches for a worker's `initSync`.
 */
export declare function wasmFile(): "handrig_simd_bg.wasm" | "handrig_bg.wasm";
export default init;
