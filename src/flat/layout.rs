//! The flat layout, declared once: every field of the input and output arrays, in memory
//! order, with its size and description. Each line makes the Rust offset constant, its entry in
//! JavaScript's `LAYOUT`, its member of the TypeScript `FlatLayout` type and its row of the
//! reference table in `docs/reference/flat-layout.md` ([`super::generated`]; tests fail when a committed
//! file is stale).
//!
//! A new field is one line in its side below (before `LEN` moves, bump [`VERSION`] and say
//! what changed); a per-side output field goes into `side`'s slot, which keeps room to grow
//! within its stride.

use super::declare::{layout_side, Row};
use crate::face::{MESH_POINTS, PRESET_COUNT, SHAPES};
use crate::humanoid::bones::BONE_COUNT;
use crate::input::mediapipe::{TrackerFace, HAND_LANDMARKS, MAX_HANDS, POSE_LANDMARKS};
use crate::input::torso::{BODY_JOINT_COUNT, TORSO_BONE_COUNT};

/// Layout version: bumped whenever an offset or meaning changes, and with it
/// [`LAYOUT_SIGNATURE`] (a test checks that they move together).
pub const VERSION: u32 = 10;

/// A digest of every row's path, offset and size at [`VERSION`]: a test recomputes it, so a
/// layout change without a version bump fails.
pub const LAYOUT_SIGNATURE: u64 = 0x6b5f_4609_bb55_af06;

layout_side! {
    /// Input offsets (indices into the input `f32` array).
    input "input" {
        /// Hand slots used, 0 to 4 (MediaPipe's order; duplicates allowed).
        HAND_COUNT handCount: 1;
        /// Image width / height for hands given by image landmarks alone (legacy Holistic);
        /// 0.01 to 100, or 0 for the default 16/9.
        IMAGE_ASPECT imageAspect: 1;
        /// 1 when the pose section holds this frame's pose.
        POSE_PRESENT posePresent: 1;
        /// 1 when `poseImage` holds the pose's image landmarks (read only with the pose).
        POSE_HAS_IMAGE poseHasImage: 1;
        /// Hand slots.
        HANDS hands: [MAX_HANDS] stride HAND_STRIDE handStride = 132, slot hand "hand" {
            /// MediaPipe's label: 0 "Left", 1 "Right" (as given; see `inputMirrored`).
            HANDEDNESS handedness: 1;
            /// Handedness score, 0 to 1.
            SCORE score: 1;
            /// 1 when `world` holds world landmarks.
            HAS_WORLD hasWorld: 1;
            /// 1 when `image` holds image landmarks.
            HAS_IMAGE hasImage: 1;
            /// 21 world landmarks `x y z` (meters, MediaPipe's camera axes).
            WORLD world: [HAND_LANDMARKS] x 3;
            /// 21 normalized image landmarks `x y z`.
            IMAGE image: [HAND_LANDMARKS] x 3;
        };
        /// Pose world landmarks `x y z visibility` (meters, MediaPipe's axes; visibility 0 to
        /// 1).
        POSE pose: [POSE_LANDMARKS] stride POSE_STRIDE poseStride = 4;
        /// Wrists from another body tracker, left then right (the avatar's sides).
        WRISTS wrists: [2] stride WRIST_STRIDE wristStride = 9, slot wrist "wrist" {
            /// 1 when this wrist is given.
            PRESENT present: 1;
            /// 1 when `rotation` is given.
            HAS_ROTATION hasRotation: 1;
            /// Position `x y z`, meters, the model's own frame.
            POSITION position: 3;
            /// World rotation of the normalized hand bone `x y z w`, the model's own frame.
            ROTATION rotation: 4;
        };
        /// The pose's normalized image landmarks `x y z` (MediaPipe's `landmarks`; the same
        /// image as the hands': the handedness check).
        POSE_IMAGE poseImage: [POSE_LANDMARKS] x 3;
        /// The app's torso (`frame.torso`): one slot per bone in `LAYOUT.torsoBones` order.
        TORSO torso: [TORSO_BONE_COUNT] stride TORSO_STRIDE torsoStride = 5, slot torso_bone "torsoBone" {
            /// 1 when this bone's rotation is given.
            PRESENT present: 1;
            /// Local rotation of the normalized bone `x y z w`, the model's own frame.
            ROTATION rotation: 4;
        };
        /// 1 when the body section holds this frame's body-tracker joints.
        BODY_PRESENT bodyPresent: 1;
        /// Body-tracker joints (`frame.body`) in `LAYOUT.bodyJoints` order, `x y z confidence`
        /// each: meters, the model's own frame; confidence 0 to 1, 0 for a joint not given.
        BODY body: [BODY_JOINT_COUNT] stride BODY_STRIDE bodyStride = 4;
        /// Face points from the body tracker that gives `wrists` (`frame.face`, meters, the
        /// model's own frame) in `LAYOUT.facePoints` order: nose, left eye, right eye, left
        /// ear, right ear, mouth (the avatar's sides). For self-contact with tracker wrists.
        FACE face: [TrackerFace::POINTS] stride FACE_STRIDE faceStride = 4, slot face_point "facePoint" {
            /// 1 when this point is given.
            PRESENT present: 1;
            /// Position `x y z`.
            POSITION position: 3;
        };
        // The face tracker's face (issue 50).
        /// 1 when this frame carries a face tracker's face (FaceLandmarker, Holistic).
        FACE_TRACKED faceTracked: 1;
        /// 1 when `faceShapes` holds its blendshapes.
        FACE_HAS_SHAPES faceHasShapes: 1;
        /// 1 when `faceMatrix` holds its facial transformation matrix.
        FACE_HAS_MATRIX faceHasMatrix: 1;
        /// 1 when `faceMesh` holds its landmarks.
        FACE_HAS_MESH faceHasMesh: 1;
        /// Blendshape scores 0 to 1 in `LAYOUT.arkit` order (MediaPipe's names and sides;
        /// `tongueOut` 0).
        FACE_SHAPES faceShapes: SHAPES;
        /// The facial transformation matrix, 16 numbers column-major (MediaPipe's `data`).
        FACE_MATRIX faceMatrix: 16;
        /// The face-mesh landmarks `LAYOUT.faceMesh` lists (indices into MediaPipe's 468 or
        /// 478), normalized image `x y z`.
        FACE_MESH faceMesh: [MESH_POINTS] x 3;
    }
}

layout_side! {
    /// Output offsets (indices into the output `f32` array).
    output "output" {
        /// Local rotation of every humanoid bone `x y z w` in `LAYOUT.bones` order, the
        /// model's own frame; identity for bones not driven.
        BONE_ROTATIONS boneRotations: [BONE_COUNT] x 4;
        /// Per bone: 0 not driven by handrig (or absent from the avatar), 1 driven and solved
        /// from this frame, 2 driven but not solved this frame (at rest, or held).
        BONE_FLAGS boneFlags: BONE_COUNT;
        /// World position of every bone's joint after solving `x y z`, meters, the model's own
        /// frame (unspecified for absent bones).
        BONE_POSITIONS bonePositions: [BONE_COUNT] x 3;
        /// Per-side reports, left then right.
        SIDES sides: [2] stride SIDE_STRIDE sideStride = 72, slot side "side" {
            /// The tracked hand driving this side: 0 none, 1 solved, 2 held (degenerate this
            /// frame, previous rotations kept), 3 skipped (degenerate, nothing to hold); names
            /// by code: `LAYOUT.handStatus`.
            HAND_STATUS handStatus: 1;
            /// Its handedness score (0 without a hand).
            HAND_SCORE handScore: 1;
            /// 1 when the wrist IK target is valid.
            TARGET_PRESENT targetPresent: 1;
            /// Wrist IK target position `x y z`.
            TARGET_POSITION targetPosition: 3;
            /// Wrist IK target rotation (world rotation of the hand bone) `x y z w`.
            TARGET_ROTATION targetRotation: 4;
            /// 1 when the alignment report is valid.
            ALIGNMENT_PRESENT alignmentPresent: 1;
            /// Where the user's aligned finger point lands on the avatar, `x y z`.
            TARGET_DIP targetDip: 3;
            /// The aligned wrist IK target, `x y z`.
            IK_WRIST ikWrist: 3;
            /// The pose wrist the target was built from, `x y z`.
            POSE_WRIST poseWrist: 3;
            /// Distance (m) from the avatar's aligned point after IK to `targetDip`; NaN when
            /// unknown.
            ALIGNMENT_ERROR alignmentError: 1;
            /// 1 when the arm reached the IK wrist.
            REACHABLE reachable: 1;
            /// 1 when the avatar has a point to align (the aligned finger, or what stands in
            /// for it: `alignedBone`).
            ALIGNED aligned: 1;
            /// Which input hand slot drove this side (-1 none).
            HAND_INDEX handIndex: 1;
            /// 1 when that hand drives the side its label does not give (contradicted by the
            /// pose, a label that jumped, a duplicate moved here; see `handResolved`).
            HAND_REASSIGNED handReassigned: 1;
            /// The avatar's fingertips, thumb to little, `x y z` each (the distal bone extended
            /// by the anatomical ratio, as `alignment.point: "tip"`); NaN for a finger the
            /// avatar lacks. Every frame, every strategy.
            FINGERTIPS fingertips: [5] x 3;
            /// 1 when the retargeting report is valid (`handStrategy: "retarget"`, a hand
            /// freshly solved this frame).
            RETARGET_PRESENT retargetPresent: 1;
            /// The scaled user fingertips placed on the avatar, thumb to little, `x y z` each
            /// (NaN where the avatar lacks the finger).
            RETARGET_TARGETS retargetTargets: [5] x 3;
            /// Avatar hand size over user hand size.
            RETARGET_SCALE retargetScale: 1;
            /// Gauss-Newton iterations (the most any finger needed).
            RETARGET_ITERATIONS retargetIterations: 1;
            /// Weighted RMS fingertip-to-target distance (m).
            RETARGET_RESIDUAL retargetResidual: 1;
            /// 1 when the contact report is valid (`contact.enabled`, an IK target).
            CONTACT_PRESENT contactPresent: 1;
            /// The face anchor nearest the user's fingertip: 0 nose, 1 chin, 2 mouth, 3 left
            /// cheek, 4 right cheek, 5 left ear, 6 right ear, 7 forehead; -1 none (no face for
            /// this side's wrist source, or no hand).
            CONTACT_ANCHOR contactAnchor: 1;
            /// The face contact blend applied, 0 to 1.
            CONTACT_WEIGHT contactWeight: 1;
            /// Distance (m) from the avatar's fingertip after IK to that avatar anchor; NaN
            /// when unknown.
            CONTACT_DISTANCE contactDistance: 1;
            /// The hand-to-hand contact blend applied, 0 to 1.
            CONTACT_HAND_WEIGHT contactHandWeight: 1;
            /// How far the body colliders pushed the hand (m).
            CONTACT_PUSH contactPush: 1;
            /// What carries the aligned point (with the alignment report): 0 the distal bone of
            /// `alignment.finger`, as configured; otherwise 1 + the index (`LAYOUT.bones`) of
            /// the bone standing in on an avatar without it: a shallower bone of the same
            /// finger (its tip extrapolated), another finger's bone, or the hand bone (the
            /// palm).
            ALIGNED_BONE alignedBone: 1;
            /// The tracked hand's confidence, 0 to 1 (the handedness score times 1 when it
            /// passed the checks, 0.6 solved from the image landmarks, 0.3 held, 0 skipped); 0
            /// without a hand.
            HAND_CONFIDENCE handConfidence: 1;
            /// What the hand checks made of it: 0 good, 1 mirrored and held (0 without a hand;
            /// names by code: `LAYOUT.handCheck`).
            HAND_CHECK handCheck: 1;
            /// What the hand selection resolved on this side: 0 nothing (or no hand), 1
            /// swapped (the label contradicted the pose wrists), 2 jumped (the label flipped
            /// between frames, no pose), 3 duplicate (two hands claimed the side); names by
            /// code: `LAYOUT.handResolved`.
            HAND_RESOLVED handResolved: 1;
        };
        /// What became of each input hand slot: 0 unused, 1 drove the left side, 2 the right
        /// side (see `side.handReassigned`), 3 ignored: score below `minHandScore`, 4 ignored:
        /// another hand drove its side, 5 ignored: its label contradicts the pose
        /// (`handedness: "drop"`); names by code: `LAYOUT.handUse`.
        HAND_USE handUse: MAX_HANDS;
        // The face (issue 50).
        /// The face: 0 none, 1 tracked this frame, 2 lost and easing out.
        FACE_STATE faceState: 1;
        /// The VRM 1.0 presets, 0 to 1, in `LAYOUT.expressions` order (the avatar's sides).
        EXPRESSIONS expressions: PRESET_COUNT;
        /// The 52 ARKit weights, 0 to 1, in `LAYOUT.arkit` order (the avatar's sides).
        ARKIT arkit: SHAPES;
        /// Look-at yaw and pitch, degrees (three-vrm's `VRMLookAt`: yaw > 0 toward the avatar's
        /// left, pitch > 0 down).
        LOOK_AT lookAt: 2;
        // Legs (issue 51).
        /// The hips' translation from their rest position `x y z` (m, the model's own frame;
        /// `legs.moveHips`): add it to the normalized hips' rest position. `bonePositions`
        /// are those of the hips at rest.
        HIPS_OFFSET hipsOffset: 3;
        /// Per foot (left, right): 1 planted (on the floor, bearing weight, locked where it
        /// was put down; `legs.plant`), else 0.
        FEET_PLANTED feetPlanted: 2;
    }
}

/// Every row of the layout, input then output.
pub fn rows() -> impl Iterator<Item = &'static Row> {
    input::ROWS.iter().chain(output::ROWS)
}
