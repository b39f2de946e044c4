//! The torso's and body tracker's parts of a frame: the app's torso rotations
//! (`frame.torso`, [`TorsoRotations`]) and body-tracker joints (`frame.body`,
//! [`BodyObservation`]). Read by [`crate::torso`], which re-exports them.

use glam::{Quat, Vec3};

use crate::humanoid::bones::HumanBone;
use crate::names::named_enum;

/// Number of torso bones.
pub const TORSO_BONE_COUNT: usize = 8;

/// The torso bones, parent-first: the keys of `frame.torso` and the order of its flat
/// section (`LAYOUT.torsoBones`).
pub const TORSO_BONES: [HumanBone; TORSO_BONE_COUNT] = [
    HumanBone::Hips,
    HumanBone::Spine,
    HumanBone::Chest,
    HumanBone::UpperChest,
    HumanBone::Neck,
    HumanBone::Head,
    HumanBone::LeftShoulder,
    HumanBone::RightShoulder,
];

/// Local rotations given by the app for the torso bones ([`TORSO_BONES`] order), in the
/// model's own frame (`frame.torso`); `None` = at rest.
pub type TorsoRotations = [Option<Quat>; TORSO_BONE_COUNT];

/// Number of body-tracker joints.
pub const BODY_JOINT_COUNT: usize = BodyJoint::COUNT;

named_enum! {
    /// The joints of `frame.body`: named by the avatar bone whose joint they are (plus the face
    /// points), so one table maps any body tracker onto them (docs/how-it-works/torso.md).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum BodyJoint {
        /// `hips`: the hip center (pelvis).
        Hips = "hips",
        /// `leftUpperLeg`: the left hip joint.
        LeftUpperLeg = "leftUpperLeg",
        /// `rightUpperLeg`: the right hip joint.
        RightUpperLeg = "rightUpperLeg",
        /// `leftUpperArm`: the left shoulder joint.
        LeftUpperArm = "leftUpperArm",
        /// `rightUpperArm`: the right shoulder joint.
        RightUpperArm = "rightUpperArm",
        /// `nose`: the tip of the nose.
        Nose = "nose",
        /// `leftEye`: the center of the left eye.
        LeftEye = "leftEye",
        /// `rightEye`: the center of the right eye.
        RightEye = "rightEye",
        /// `leftEar`: the left ear (tragus).
        LeftEar = "leftEar",
        /// `rightEar`: the right ear.
        RightEar = "rightEar",
    }
}

/// Joints from a body tracker (`frame.body`), in the model's own frame (meters, like
/// `wrists`; left and right are the avatar's sides), with a confidence in `0..=1` each: a
/// joint below `calibration.minVisibility` (0 for absent) is not seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyObservation {
    /// Positions, [`BodyJoint::ALL`] order.
    pub position: [Vec3; BODY_JOINT_COUNT],
    /// Confidences, [`BodyJoint::ALL`] order.
    pub confidence: [f32; BODY_JOINT_COUNT],
}

impl Default for BodyObservation {
    fn default() -> Self {
        BodyObservation {
            position: [Vec3::ZERO; BODY_JOINT_COUNT],
            confidence: [0.0; BODY_JOINT_COUNT],
        }
    }
}
