// Generated from the layout declaration (src/flat/layout.rs) by `HANDRIG_GENERATE=write cargo
// test --lib flat`; a test fails when this file is stale. Do not edit.

/** The layout version these types describe (`LAYOUT.version`). */
export const LAYOUT_VERSION = 10;

/** Offsets of the input `Float32Array` (`LAYOUT.input`). See docs/reference/flat-layout.md. */
export interface InputLayout {
  /** Hand slots used, 0 to 4 (MediaPipe's order; duplicates allowed). */
  readonly handCount: number;
  /** Image width / height for hands given by image landmarks alone (legacy Holistic); 0.01 to 100, or 0 for the default 16/9. */
  readonly imageAspect: number;
  /** 1 when the pose section holds this frame's pose. */
  readonly posePresent: number;
  /** 1 when `poseImage` holds the pose's image landmarks (read only with the pose). */
  readonly poseHasImage: number;
  /** Hand slots. */
  readonly hands: number;
  /** Floats from one slot to the next of the field above. */
  readonly handStride: number;
  /** Offsets inside one slot of `hand`. */
  readonly hand: {
    /** MediaPipe's label: 0 "Left", 1 "Right" (as given; see `inputMirrored`). */
    readonly handedness: number;
    /** Handedness score, 0 to 1. */
    readonly score: number;
    /** 1 when `world` holds world landmarks. */
    readonly hasWorld: number;
    /** 1 when `image` holds image landmarks. */
    readonly hasImage: number;
    /** 21 world landmarks `x y z` (meters, MediaPipe's camera axes). */
    readonly world: number;
    /** 21 normalized image landmarks `x y z`. */
    readonly image: number;
  };
  /** Pose world landmarks `x y z visibility` (meters, MediaPipe's axes; visibility 0 to 1). */
  readonly pose: number;
  /** Floats from one slot to the next of the field above. */
  readonly poseStride: number;
  /** Wrists from another body tracker, left then right (the avatar's sides). */
  readonly wrists: number;
  /** Floats from one slot to the next of the field above. */
  readonly wristStride: number;
  /** Offsets inside one slot of `wrist`. */
  readonly wrist: {
    /** 1 when this wrist is given. */
    readonly present: number;
    /** 1 when `rotation` is given. */
    readonly hasRotation: number;
    /** Position `x y z`, meters, the model's own frame. */
    readonly position: number;
    /** World rotation of the normalized hand bone `x y z w`, the model's own frame. */
    readonly rotation: number;
  };
  /** The pose's normalized image landmarks `x y z` (MediaPipe's `landmarks`; the same image as the hands': the handedness check). */
  readonly poseImage: number;
  /** The app's torso (`frame.torso`): one slot per bone in `LAYOUT.torsoBones` order. */
  readonly torso: number;
  /** Floats from one slot to the next of the field above. */
  readonly torsoStride: number;
  /** Offsets inside one slot of `torsoBone`. */
  readonly torsoBone: {
    /** 1 when this bone's rotation is given. */
    readonly present: number;
    /** Local rotation of the normalized bone `x y z w`, the model's own frame. */
    readonly rotation: number;
  };
  /** 1 when the body section holds this frame's body-tracker joints. */
  readonly bodyPresent: number;
  /** Body-tracker joints (`frame.body`) in `LAYOUT.bodyJoints` order, `x y z confidence` each: meters, the model's own frame; confidence 0 to 1, 0 for a joint not given. */
  readonly body: number;
  /** Floats from one slot to the next of the field above. */
  readonly bodyStride: number;
  /** Face points from the body tracker that gives `wrists` (`frame.face`, meters, the model's own frame) in `LAYOUT.facePoints` order: nose, left eye, right eye, left ear, right ear, mouth (the avatar's sides). For self-contact with tracker wrists. */
  readonly face: number;
  /** Floats from one slot to the next of the field above. */
  readonly faceStride: number;
  /** Offsets inside one slot of `facePoint`. */
  readonly facePoint: {
    /** 1 when this point is given. */
    readonly present: number;
    /** Position `x y z`. */
    readonly position: number;
  };
  /** 1 when this frame carries a face tracker's face (FaceLandmarker, Holistic). */
  readonly faceTracked: number;
  /** 1 when `faceShapes` holds its blendshapes. */
  readonly faceHasShapes: number;
  /** 1 when `faceMatrix` holds its facial transformation matrix. */
  readonly faceHasMatrix: number;
  /** 1 when `faceMesh` holds its landmarks. */
  readonly faceHasMesh: number;
  /** Blendshape scores 0 to 1 in `LAYOUT.arkit` order (MediaPipe's names and sides; `tongueOut` 0). */
  readonly faceShapes: number;
  /** The facial transformation matrix, 16 numbers column-major (MediaPipe's `data`). */
  readonly faceMatrix: number;
  /** The face-mesh landmarks `LAYOUT.faceMesh` lists (indices into MediaPipe's 468 or 478), normalized image `x y z`. */
  readonly faceMesh: number;
  /** Length of the array. */
  readonly length: number;
}

/** Offsets of the output `Float32Array` (`LAYOUT.output`). See docs/reference/flat-layout.md. */
export interface OutputLayout {
  /** Local rotation of every humanoid bone `x y z w` in `LAYOUT.bones` order, the model's own frame; identity for bones not driven. */
  readonly boneRotations: number;
  /** Per bone: 0 not driven by handrig (or absent from the avatar), 1 driven and solved from this frame, 2 driven but not solved this frame (at rest, or held). */
  readonly boneFlags: number;
  /** World position of every bone's joint after solving `x y z`, meters, the model's own frame (unspecified for absent bones). */
  readonly bonePositions: number;
  /** Per-side reports, left then right. */
  readonly sides: number;
  /** Floats from one slot to the next of the field above. */
  readonly sideStride: number;
  /** Offsets inside one slot of `side`. */
  readonly side: {
    /** The tracked hand driving this side: 0 none, 1 solved, 2 held (degenerate this frame, previous rotations kept), 3 skipped (degenerate, nothing to hold); names by code: `LAYOUT.handStatus`. */
    readonly handStatus: number;
    /** Its handedness score (0 without a hand). */
    readonly handScore: number;
    /** 1 when the wrist IK target is valid. */
    readonly targetPresent: number;
    /** Wrist IK target position `x y z`. */
    readonly targetPosition: number;
    /** Wrist IK target rotation (world rotation of the hand bone) `x y z w`. */
    readonly targetRotation: number;
    /** 1 when the alignment report is valid. */
    readonly alignmentPresent: number;
    /** Where the user's aligned finger point lands on the avatar, `x y z`. */
    readonly targetDip: number;
    /** The aligned wrist IK target, `x y z`. */
    readonly ikWrist: number;
    /** The pose wrist the target was built from, `x y z`. */
    readonly poseWrist: number;
    /** Distance (m) from the avatar's aligned point after IK to `targetDip`; NaN when unknown. */
    readonly alignmentError: number;
    /** 1 when the arm reached the IK wrist. */
    readonly reachable: number;
    /** 1 when the avatar has a point to align (the aligned finger, or what stands in for it: `alignedBone`). */
    readonly aligned: number;
    /** Which input hand slot drove this side (-1 none). */
    readonly handIndex: number;
    /** 1 when that hand drives the side its label does not give (contradicted by the pose, a label that jumped, a duplicate moved here; see `handResolved`). */
    readonly handReassigned: number;
    /** The avatar's fingertips, thumb to little, `x y z` each (the distal bone extended by the anatomical ratio, as `alignment.point: "tip"`); NaN for a finger the avatar lacks. Every frame, every strategy. */
    readonly fingertips: number;
    /** 1 when the retargeting report is valid (`handStrategy: "retarget"`, a hand freshly solved this frame). */
    readonly retargetPresent: number;
    /** The scaled user fingertips placed on the avatar, thumb to little, `x y z` each (NaN where the avatar lacks the finger). */
    readonly retargetTargets: number;
    /** Avatar hand size over user hand size. */
    readonly retargetScale: number;
    /** Gauss-Newton iterations (the most any finger needed). */
    readonly retargetIterations: number;
    /** Weighted RMS fingertip-to-target distance (m). */
    readonly retargetResidual: number;
    /** 1 when the contact report is valid (`contact.enabled`, an IK target). */
    readonly contactPresent: number;
    /** The face anchor nearest the user's fingertip: 0 nose, 1 chin, 2 mouth, 3 left cheek, 4 right cheek, 5 left ear, 6 right ear, 7 forehead; -1 none (no face for this side's wrist source, or no hand). */
    readonly contactAnchor: number;
    /** The face contact blend applied, 0 to 1. */
    readonly contactWeight: number;
    /** Distance (m) from the avatar's fingertip after IK to that avatar anchor; NaN when unknown. */
    readonly contactDistance: number;
    /** The hand-to-hand contact blend applied, 0 to 1. */
    readonly contactHandWeight: number;
    /** How far the body colliders pushed the hand (m). */
    readonly contactPush: number;
    /** What carries the aligned point (with the alignment report): 0 the distal bone of `alignment.finger`, as configured; otherwise 1 + the index (`LAYOUT.bones`) of the bone standing in on an avatar without it: a shallower bone of the same finger (its tip extrapolated), another finger's bone, or the hand bone (the palm). */
    readonly alignedBone: number;
    /** The tracked hand's confidence, 0 to 1 (the handedness score times 1 when it passed the checks, 0.6 solved from the image landmarks, 0.3 held, 0 skipped); 0 without a hand. */
    readonly handConfidence: number;
    /** What the hand checks made of it: 0 good, 1 mirrored and held (0 without a hand; names by code: `LAYOUT.handCheck`). */
    readonly handCheck: number;
    /** What the hand selection resolved on this side: 0 nothing (or no hand), 1 swapped (the label contradicted the pose wrists), 2 jumped (the label flipped between frames, no pose), 3 duplicate (two hands claimed the side); names by code: `LAYOUT.handResolved`. */
    readonly handResolved: number;
  };
  /** What became of each input hand slot: 0 unused, 1 drove the left side, 2 the right side (see `side.handReassigned`), 3 ignored: score below `minHandScore`, 4 ignored: another hand drove its side, 5 ignored: its label contradicts the pose (`handedness: "drop"`); names by code: `LAYOUT.handUse`. */
  readonly handUse: number;
  /** The face: 0 none, 1 tracked this frame, 2 lost and easing out. */
  readonly faceState: number;
  /** The VRM 1.0 presets, 0 to 1, in `LAYOUT.expressions` order (the avatar's sides). */
  readonly expressions: number;
  /** The 52 ARKit weights, 0 to 1, in `LAYOUT.arkit` order (the avatar's sides). */
  readonly arkit: number;
  /** Look-at yaw and pitch, degrees (three-vrm's `VRMLookAt`: yaw > 0 toward the avatar's left, pitch > 0 down). */
  readonly lookAt: number;
  /** The hips' translation from their rest position `x y z` (m, the model's own frame; `legs.moveHips`): add it to the normalized hips' rest position. `bonePositions` are those of the hips at rest. */
  readonly hipsOffset: number;
  /** Per foot (left, right): 1 planted (on the floor, bearing weight, locked where it was put down; `legs.plant`), else 0. */
  readonly feetPlanted: number;
  /** Length of the array. */
  readonly length: number;
}
