//! MediaPipe input: hand and pose landmarks, body-tracker wrists and joints, the app's torso,
//! and the conversion from MediaPipe's camera axes to the avatar frame.
//!
//! MediaPipe axes: x to the image right, y down, z away from the camera (right-handed). The
//! user faces the camera; the avatar faces +Z (toward the viewer). Two options decide the
//! mapping (see the README table):
//!
//! * `input_mirrored`: the image given to MediaPipe was flipped horizontally (selfie view).
//!   MediaPipe's handedness labels assume exactly that, so on an un-mirrored image the label
//!   is the opposite of the subject's hand, and on a mirrored image the landmarks are the
//!   mirror image of the real hand.
//! * `mirror`: the avatar mirrors the user (VTuber style): the user's right hand drives the
//!   avatar's left hand, and motion is reflected left-right like a mirror image.
//!
//! With `flip = input_mirrored XOR mirror`, a MediaPipe point `(x, y, z)` maps to
//! `(flip ? -x : x, -y, -z)`; the avatar side is the label's side, swapped when the input is
//! not mirrored and swapped again when `mirror` is on.

use glam::Vec3;

use super::torso::{BodyObservation, TorsoRotations, TORSO_BONE_COUNT};
use crate::humanoid::bones::Side;

/// Number of MediaPipe hand landmarks.
pub const HAND_LANDMARKS: usize = 21;
/// Number of MediaPipe pose landmarks.
pub const POSE_LANDMARKS: usize = 33;
/// Most hands one frame may carry (MediaPipe's `numHands` can exceed 2; duplicates happen).
pub const MAX_HANDS: usize = 4;

/// MediaPipe hand landmark indices.
pub mod hand_landmark {
    /// Wrist.
    pub const WRIST: usize = 0;
    /// Thumb CMC.
    pub const THUMB_CMC: usize = 1;
    /// Thumb tip.
    pub const THUMB_TIP: usize = 4;
    /// Index finger MCP.
    pub const INDEX_MCP: usize = 5;
    /// Index finger DIP.
    pub const INDEX_DIP: usize = 7;
    /// Index finger tip.
    pub const INDEX_TIP: usize = 8;
    /// Middle finger MCP.
    pub const MIDDLE_MCP: usize = 9;
    /// Ring finger MCP.
    pub const RING_MCP: usize = 13;
    /// Little finger (pinky) MCP.
    pub const PINKY_MCP: usize = 17;
}

/// MediaPipe pose landmark indices used by handrig.
pub mod pose_landmark {
    /// Nose.
    pub const NOSE: usize = 0;
    /// Left eye (the subject's left; the eye's center, between its inner and outer corner).
    pub const LEFT_EYE: usize = 2;
    /// Right eye.
    pub const RIGHT_EYE: usize = 5;
    /// Left ear.
    pub const LEFT_EAR: usize = 7;
    /// Right ear.
    pub const RIGHT_EAR: usize = 8;
    /// Left corner of the mouth.
    pub const MOUTH_LEFT: usize = 9;
    /// Right corner of the mouth.
    pub const MOUTH_RIGHT: usize = 10;
    /// Left shoulder (the subject's left).
    pub const LEFT_SHOULDER: usize = 11;
    /// Right shoulder.
    pub const RIGHT_SHOULDER: usize = 12;
    /// Left elbow.
    pub const LEFT_ELBOW: usize = 13;
    /// Right elbow.
    pub const RIGHT_ELBOW: usize = 14;
    /// Left wrist.
    pub const LEFT_WRIST: usize = 15;
    /// Right wrist.
    pub const RIGHT_WRIST: usize = 16;
    /// Left index finger (knuckle).
    pub const LEFT_INDEX: usize = 19;
    /// Right index finger (knuckle).
    pub const RIGHT_INDEX: usize = 20;
    /// Left hip.
    pub const LEFT_HIP: usize = 23;
    /// Right hip.
    pub const RIGHT_HIP: usize = 24;

    /// The pose landmarks a [`crate::Rig`] reads for the arms and torso (face, arms, shoulders
    /// and hips); the others (the pose's hands, and the legs unless `legs.enabled`) change
    /// nothing, and the rig does not filter them.
    pub const READ: [usize; 15] = [
        NOSE,
        LEFT_EYE,
        RIGHT_EYE,
        LEFT_EAR,
        RIGHT_EAR,
        MOUTH_LEFT,
        MOUTH_RIGHT,
        LEFT_SHOULDER,
        RIGHT_SHOULDER,
        LEFT_ELBOW,
        RIGHT_ELBOW,
        LEFT_WRIST,
        RIGHT_WRIST,
        LEFT_HIP,
        RIGHT_HIP,
    ];

    /// [`READ`] and the legs' knees, ankles, heels and toes (25-32): what a rig with
    /// `legs.enabled` reads.
    pub const READ_WITH_LEGS: [usize; 23] = {
        let mut read = [0; 23];
        let mut k = 0;
        while k < 23 {
            read[k] = if k < READ.len() {
                READ[k]
            } else {
                25 + k - READ.len()
            };
            k += 1;
        }
        read
    };
}

/// MediaPipe's handedness label as given (it assumes a mirrored image; see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handedness {
    /// `"Left"`.
    Left,
    /// `"Right"`.
    Right,
}

impl Handedness {
    /// Parses `"Left"` / `"Right"` (also accepts lowercase).
    #[must_use]
    pub fn from_label(label: &str) -> Option<Handedness> {
        match label {
            "Left" | "left" => Some(Handedness::Left),
            "Right" | "right" => Some(Handedness::Right),
            _ => None,
        }
    }
}

/// How MediaPipe input relates to the avatar.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct CameraMapping {
    /// The image given to MediaPipe was flipped horizontally (selfie view).
    pub input_mirrored: bool,
    /// The avatar mirrors the user (user's right hand drives the avatar's left).
    pub mirror: bool,
}

/// The camera's orientation to gravity (JS: `options.camera`): MediaPipe's world landmarks
/// are oriented with the camera, so a camera that looks down leans an upright body's legs in
/// depth by its pitch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraOptions {
    /// How far the camera looks down (radians; negative: up), taken out of the pose's world
    /// landmarks before the legs are solved. `None` (the default): estimated over time from
    /// the user's straight legs ([`crate::legs`]).
    pub pitch: Option<f32>,
}

impl CameraMapping {
    /// Whether the x axis is negated on the way into the avatar frame.
    #[inline]
    #[must_use]
    pub const fn flips_x(self) -> bool {
        self.input_mirrored ^ self.mirror
    }

    /// Converts a MediaPipe world-landmark vector (meters, camera axes) to the avatar frame.
    #[inline]
    #[must_use]
    pub fn to_avatar(self, p: Vec3) -> Vec3 {
        Vec3::new(if self.flips_x() { -p.x } else { p.x }, -p.y, -p.z)
    }

    /// The avatar side a hand with MediaPipe label `label` drives.
    #[must_use]
    pub const fn avatar_side(self, label: Handedness) -> Side {
        let label_side = match label {
            Handedness::Left => Side::Left,
            Handedness::Right => Side::Right,
        };
        // The label is the subject's hand only on mirrored input.
        let subject = if self.input_mirrored {
            label_side
        } else {
            label_side.opposite()
        };
        if self.mirror {
            subject.opposite()
        } else {
            subject
        }
    }

    /// The subject's (user's) side whose pose landmarks drive the avatar side `side`.
    /// MediaPipe Pose labels its landmarks by the subject's body side on un-mirrored input; on
    /// mirrored input they swap like the hand labels do.
    #[must_use]
    pub const fn pose_side_for(self, side: Side) -> Side {
        let subject = if self.mirror { side.opposite() } else { side };
        if self.input_mirrored {
            subject.opposite()
        } else {
            subject
        }
    }
}

/// One hand as MediaPipe reports it. Fixed-size storage: no allocation per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandObservation {
    /// MediaPipe's label.
    pub handedness: Handedness,
    /// Handedness score in 0..1 (1 when not given).
    pub score: f32,
    /// World landmarks, meters, MediaPipe camera axes, origin near the hand's center.
    pub world: [Vec3; HAND_LANDMARKS],
    /// Normalized image landmarks, when given.
    pub image: Option<[Vec3; HAND_LANDMARKS]>,
}

/// MediaPipe pose world landmarks (meters, camera axes, origin between the hips).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseObservation {
    /// The 33 world landmarks.
    pub world: [Vec3; POSE_LANDMARKS],
    /// Visibility 0..1 per landmark (1 when not given).
    pub visibility: [f32; POSE_LANDMARKS],
}

/// A wrist from any body tracker, already in the avatar's frame (the Kinect wrist of seed 000).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristObservation {
    /// Position, meters, avatar frame.
    pub position: Vec3,
    /// Optional world rotation of the avatar's normalized hand bone.
    pub rotation: Option<glam::Quat>,
}

/// Face points from another body tracker (the head joints of Azure Kinect body tracking:
/// `NOSE`, `EYE_*`, `EAR_*`), already in the avatar's frame like [`WristObservation`], sides
/// by the avatar's sides (`eyes[0]` is the avatar's left eye). Each point is optional; the
/// face frame needs both eyes or both ears, and the nose or the mouth (see
/// [`crate::contact`]).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TrackerFace {
    /// Tip of the nose.
    pub nose: Option<Vec3>,
    /// Eye centers, `[left, right]`.
    pub eyes: [Option<Vec3>; 2],
    /// Ears, `[left, right]`.
    pub ears: [Option<Vec3>; 2],
    /// Center of the mouth.
    pub mouth: Option<Vec3>,
}

impl TrackerFace {
    /// Number of points, in the flat layout's order: nose, left eye, right eye, left ear,
    /// right ear, mouth.
    pub const POINTS: usize = 6;
    /// Their names as `frame.face` spells them, in that order.
    pub const NAMES: [&'static str; 6] = [
        "nose", "leftEye", "rightEye", "leftEar", "rightEar", "mouth",
    ];

    /// The point at flat index `k` (see [`TrackerFace::POINTS`]).
    #[must_use]
    pub fn point(&self, k: usize) -> Option<Vec3> {
        match k {
            0 => self.nose,
            1 => self.eyes[0],
            2 => self.eyes[1],
            3 => self.ears[0],
            4 => self.ears[1],
            5 => self.mouth,
            _ => None,
        }
    }

    /// Sets the point at flat index `k` (out-of-range indices are ignored).
    pub fn set_point(&mut self, k: usize, p: Option<Vec3>) {
        match k {
            0 => self.nose = p,
            1 => self.eyes[0] = p,
            2 => self.eyes[1] = p,
            3 => self.ears[0] = p,
            4 => self.ears[1] = p,
            5 => self.mouth = p,
            _ => {}
        }
    }

    /// Whether no point is given.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        (0..Self::POINTS).all(|k| self.point(k).is_none())
    }
}

/// Everything one frame may carry. `Copy`-sized buffers so a caller can keep one and refill it
/// every frame without allocating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameInput {
    /// Timestamp, milliseconds.
    pub time_ms: f64,
    /// Hands in MediaPipe's order; only the first `hand_count` are valid.
    pub hands: [HandObservation; MAX_HANDS],
    /// How many entries of `hands` are valid.
    pub hand_count: usize,
    /// Pose world landmarks, if any.
    pub pose: Option<PoseObservation>,
    /// The pose's normalized image landmarks (`x, y` in 0..1 of the image, MediaPipe's), when
    /// given: with the hands' image landmarks they tell which tracked hand is at which pose
    /// wrist (handedness sanity). Only read when `pose` is present.
    pub pose_image: Option<[Vec3; POSE_LANDMARKS]>,
    /// Wrists from another body tracker in the avatar frame, indexed by [`Side::index`].
    pub wrists: [Option<WristObservation>; 2],
    /// The app's torso: local rotations of the torso bones in the model's own frame
    /// ([`crate::torso::TORSO_BONES`] order; `None` = at rest). See [`crate::torso`].
    pub torso: TorsoRotations,
    /// Joints from a body tracker with spine joints, in the model's own frame (used by
    /// `torso: "pose"`). See [`crate::torso::BodyObservation`].
    pub body: Option<BodyObservation>,
    /// Face points from the same body tracker (the model's own frame), for self-contact
    /// retargeting of tracker wrists ([`crate::contact`]).
    pub face: Option<TrackerFace>,
    /// A face tracker's face (FaceLandmarker or Holistic: blendshapes, transformation matrix,
    /// face-mesh landmarks), for expressions, look-at and the head ([`crate::face`]).
    pub face_tracking: Option<crate::face::FaceObservation>,
    /// The image's width / height (`frame.imageAspect`; 16/9 when not given): how image
    /// landmarks' x and y compare ([`crate::input::hand_wrist`]).
    pub image_aspect: f32,
    /// Per entry of `hands`: its `world` was made from its image landmarks (legacy Holistic
    /// gives no hand world landmarks; [`image_to_pseudo_world`]), so it carries no metric
    /// size of its own (chest contact's size cue skips such a hand).
    pub world_from_image: [bool; MAX_HANDS],
}

impl Default for FrameInput {
    fn default() -> Self {
        let empty_hand = HandObservation {
            handedness: Handedness::Left,
            score: 0.0,
            world: [Vec3::ZERO; HAND_LANDMARKS],
            image: None,
        };
        FrameInput {
            time_ms: 0.0,
            hands: [empty_hand; MAX_HANDS],
            hand_count: 0,
            pose: None,
            pose_image: None,
            wrists: [None, None],
            torso: [None; TORSO_BONE_COUNT],
            body: None,
            face: None,
            face_tracking: None,
            image_aspect: 16.0 / 9.0,
            world_from_image: [false; MAX_HANDS],
        }
    }
}

impl FrameInput {
    /// The valid hands.
    #[must_use]
    pub fn hands(&self) -> &[HandObservation] {
        &self.hands[..self.hand_count.min(MAX_HANDS)]
    }

    /// Clears the frame for reuse.
    pub fn clear(&mut self) {
        self.time_ms = 0.0;
        self.hand_count = 0;
        self.pose = None;
        self.pose_image = None;
        self.wrists = [None, None];
        self.torso = [None; TORSO_BONE_COUNT];
        self.body = None;
        self.face = None;
        self.face_tracking = None;
        self.image_aspect = 16.0 / 9.0;
    }
}

/// Converts normalized image landmarks (Holistic legacy results carry no hand world
/// landmarks) into approximate metric hand-centered points: x is scaled by the image aspect
/// (width / height) so both axes are in the same unit, then everything is scaled so the
/// wrist-to-middle-MCP distance is 9 cm, an average adult's (rotations do not depend on the
/// scale; positions from it are approximate).
pub fn image_to_pseudo_world(points: &mut [Vec3; HAND_LANDMARKS], aspect: f32) {
    for p in points.iter_mut() {
        p.x *= aspect;
        p.z *= aspect;
    }
    let wrist = points[hand_landmark::WRIST];
    let palm = (points[hand_landmark::MIDDLE_MCP] - wrist).length();
    let k = if palm > 1e-6 { 0.09 / palm } else { 1.0 };
    for p in points.iter_mut() {
        *p = (*p - wrist) * k;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_combinations_of_the_mapping() {
        let p = Vec3::new(0.1, 0.2, 0.3);
        let cases = [
            // (input_mirrored, mirror, label Left -> avatar side, x sign)
            (false, false, Side::Right, 1.0),
            (true, false, Side::Left, -1.0),
            (false, true, Side::Left, -1.0),
            (true, true, Side::Right, 1.0),
        ];
        for (input_mirrored, mirror, side, sx) in cases {
            let m = CameraMapping {
                input_mirrored,
                mirror,
            };
            assert_eq!(m.avatar_side(Handedness::Left), side, "{m:?}");
            assert_eq!(m.avatar_side(Handedness::Right), side.opposite(), "{m:?}");
            assert_eq!(m.to_avatar(p), Vec3::new(0.1 * sx, -0.2, -0.3), "{m:?}");
        }
    }
}
