//! The torso's and body tracker's parts of a frame: the app's torso rotations
//! (`frame.torso`, [`TorsoRotations`]) and body-tracker joints (`frame.body`,
//! [`BodyObservation`]). Read by [`crate::torso`], which re-exports them.

use glam::{Quat, Vec3};

use crate::humanoid::bones::HumanBone;

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
pub const BODY_JOINT_COUNT: usize = 10;

/// The joints of `frame.body`: named by the avatar bone whose joint they are (plus the face
/// points), so one table maps any body tracker onto them (docs/torso.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyJoint {
    /// `hips`: the hip center (pelvis).
    Hips,
    /// `leftUpperLeg`: the left hip joint.
    LeftUpperLeg,
    /// `rightUpperLeg`: the right hip joint.
    RightUpperLeg,
    /// `leftUpperArm`: the left shoulder joint.
    LeftUpperArm,
    /// `rightUpperArm`: the right shoulder joint.
    RightUpperArm,
    /// `nose`: the tip of the nose.
    Nose,
    /// `leftEye`: the center of the left eye.
    LeftEye,
    /// `rightEye`: the center of the right eye.
    RightEye,
    /// `leftEar`: the left ear (tragus).
    LeftEar,
    /// `rightEar`: the right ear.
    RightEar,
}

impl BodyJoint {
    /// Every joint, in the order of the flat section (`LAYOUT.bodyJoints`).
    pub const ALL: [BodyJoint; BODY_JOINT_COUNT] = [
        BodyJoint::Hips,
        BodyJoint::LeftUpperLeg,
        BodyJoint::RightUpperLeg,
        BodyJoint::LeftUpperArm,
        BodyJoint::RightUpperArm,
        BodyJoint::Nose,
        BodyJoint::LeftEye,
        BodyJoint::RightEye,
        BodyJoint::LeftEar,
        BodyJoint::RightEar,
    ];

    /// Position in [`BodyJoint::ALL`].
    #[inline]
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The JS name, e.g. `"leftUpperArm"`.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            BodyJoint::Hips => "hips",
            BodyJoint::LeftUpperLeg => "leftUpperLeg",
            BodyJoint::RightUpperLeg => "rightUpperLeg",
            BodyJoint::LeftUpperArm => "leftUpperArm",
            BodyJoint::RightUpperArm => "rightUpperArm",
            BodyJoint::Nose => "nose",
            BodyJoint::LeftEye => "leftEye",
            BodyJoint::RightEye => "rightEye",
            BodyJoint::LeftEar => "leftEar",
            BodyJoint::RightEar => "rightEar",
        }
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
