// The public types of what handrig returns: `HandRig.solve()` results (results.ts builds them)
// and the contact model. The finger and face-anchor names are the option table's
// (options-types.ts, generated from Rust), not retyped here.

import type { BoneMap, Quat, Vec3 } from "./frame-types.js";
import type { HandRigOptions } from "./options-types.js";
import type { HumanBoneName } from "./layout.js";

type Group<T> = Exclude<T, boolean | undefined>;

/** A finger: `alignment.finger`'s values (thumb, index, middle, ring, little). */
export type FingerName = NonNullable<Group<HandRigOptions["alignment"]>["finger"]>;

/** A face anchor: a named place of the face contact maps between user and avatar (`contact.faceAnchors`' names). */
export type FaceAnchorName = keyof NonNullable<Group<HandRigOptions["contact"]>["faceAnchors"]>;

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
  /** Whether the avatar has a point to align: its aligned finger or what stands in for it (`finger`, `bone`), so always true in a report. */
  aligned: boolean;
  /**
   * What carries the aligned point: `alignment.finger`, or on an avatar without its distal bone
   * the finger standing in, or `"palm"` (no finger bones). See docs/how-it-works/alignment-ik.md.
   */
  finger: FingerName | "palm";
  /** The bone carrying it (`"rightIndexDistal"` as configured; e.g. `"rightIndexIntermediate"`, `"rightMiddleDistal"`, or `"rightHand"` for the palm). */
  bone: HumanBoneName;
  /** What self-contact did for this hand (null with `contact.enabled: false`); `targetDip` and `ikWrist` include it. */
  contact: ContactReport | null;
}

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

/** What carries one side's aligned point on this avatar (`rig.alignedBones()`). */
export interface AlignedBone {
  /** `alignment.finger`, another finger standing in for it, or `"palm"`. */
  finger: FingerName | "palm";
  /** The bone carrying the point (the hand bone for the palm). */
  bone: HumanBoneName;
  /** False when this is `alignment.finger`'s distal bone (nothing missing); true for a stand-in. */
  standIn: boolean;
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
  /**
   * What self-contact learned from the avatar's skin (`restPose.skin`, or the file's skinned
   * meshes), or `null` when the rig models the body from its bones (docs/how-it-works/contact.md).
   */
  skin: {
    /** Triangle samples and vertices of the head and torso used for the body's surface. */
    samples: number;
    /** Finger radius per side `[left, right]`, meters (the margin of finger joints and tips). */
    fingerRadius: [number, number];
    /** Palm half-thickness per side `[left, right]`, meters. */
    palmHalfThickness: [number, number];
  } | null;
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
  /** It drives the side its label does not give: contradicted by the pose wrists (`handedness: "reassign"`), a label that jumped, or a duplicate moved to a free side (see `resolved`). */
  reassigned: boolean;
  /** How far to trust this hand this frame, 0..1 (for fading it): the handedness score times
   * 1 for a hand that passed the checks, 0.3 for a held hand, 0 when skipped. */
  confidence: number;
  /** What the mirrored-hand checks made of it: "good"; "mirrored": its world landmarks were
   * mirrored (palm depth flipped) or crossed the image's knuckle line, and the side's last
   * solved hand was held. See docs/how-it-works/hands-on-video.md. */
  check: "good" | "mirrored";
  /** What the hand selection resolved on this side this frame (docs/reference/results.md): null,
   * nothing; "swapped": its label contradicted the pose wrists and it was reassigned here;
   * "jumped": no pose, its label flipped between frames and it was kept on the side it was on;
   * "duplicate": two hands claimed the side and this one kept it (with `reassigned`: the
   * second, distinct hand, moved to this free side). */
  resolved: "swapped" | "jumped" | "duplicate" | null;
}

/** What became of one hand of the frame. */
export type HandUse = "left" | "right" | "lowScore" | "duplicate" | "contradicted";

/** The result of one `solve`, in the model's own frame. */
export interface SolveResult {
  /** The frame's timestamp, milliseconds. */
  timeMs: number;
  /** Local rotations of every bone the rig drives (`rig.drivenBones()`: arms, hands, fingers the avatar has; with `legs.enabled` the legs, feet and toes; with `torso: "pose"` the torso bones), every frame: solved, held, or back at rest (identity) when tracking is lost. Write them all to `getNormalizedBoneNode(name).quaternion` (`applyToVRM` does). */
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
  /**
   * The face (issue 50): "tracked" this frame, "lost" (holding, then easing out), null without
   * one. While it is not null the face turns `bones.neck` and `bones.head` (they are in `bones`
   * then, even when `drivenBones()` leaves them out).
   */
  face: "tracked" | "lost" | null;
  /** The VRM 1.0 preset expressions, weights 0..1 (the avatar's sides: `blinkLeft` is its left eye). */
  expressions: { [name in ExpressionPresetName]: number };
  /** The 52 ARKit weights 0..1 in `LAYOUT.arkit` order, the avatar's sides (perfect sync). */
  arkit: Float32Array;
  /** Where the eyes look relative to the head, degrees, as three-vrm's `vrm.lookAt.yaw` / `.pitch` (yaw > 0 toward the avatar's left, pitch > 0 down). */
  lookAt: { yaw: number; pitch: number };
  /** The hips' translation from their rest position (meters, the model's own frame; `legs.moveHips`): add it to the normalized hips' rest position (`applyToVRM` does while the rig drives the legs). `worldPositions` are those of the hips at rest. `[0, 0, 0]` while no leg is tracked. */
  hipsOffset: Vec3;
  /** Per foot: planted (on the floor, bearing weight, locked where it was put down; `legs.plant`). */
  feetPlanted: { left: boolean; right: boolean };
}

/** The VRM 1.0 preset expressions the face gives (`LAYOUT.expressions`). */
export type ExpressionPresetName =
  | "happy" | "angry" | "sad" | "relaxed" | "surprised" | "aa" | "ih" | "ou" | "ee" | "oh"
  | "blink" | "blinkLeft" | "blinkRight" | "lookUp" | "lookDown" | "lookLeft" | "lookRight";

/** One value per finger (undefined where the avatar lacks the finger). */
export type Fingers<T> = { [finger in FingerName]?: T };

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

