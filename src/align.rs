//! Fingertip alignment (seeds 000 and 001, without their one-frame lag).
//!
//! The avatar's hand is proportionally smaller than the user's, so putting the avatar's wrist
//! where the user's wrist is leaves the avatar's fingertip short of where the user's finger
//! is (on the face, say). Instead:
//!
//! ```text
//! target DIP = pose wrist + s * (hand DIP - hand wrist)          (user's offset, avatar frame)
//! IK wrist   = target DIP - (avatar wrist -> index distal)        (forward kinematics, this frame)
//! ```
//!
//! `s` is the body scale ([`crate::body`]); with `wrists` input it is 1 and this is exactly
//! the seed formula. The avatar vector comes from forward kinematics of this frame's solved
//! hand rotation and finger rotations, so there is no lag (the seed reads bone transforms one
//! frame late). With `weight` w the IK wrist is `pose wrist + w * (user offset - avatar offset)`.

use glam::{Quat, Vec3};

use crate::bones::{Finger, Side, BONE_COUNT};
use crate::mediapipe::HAND_LANDMARKS;
use crate::skeleton::{Skeleton, WorldPose};

/// Which point of the finger is aligned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlignPoint {
    /// The DIP joint (thumb: IP), i.e. the avatar's distal bone origin. The seed's choice:
    /// avatars have no tip bone, so this is the most distal point known exactly.
    Dip,
    /// The fingertip: MediaPipe's TIP landmark on the user, and on the avatar the distal bone
    /// extended past its joint by `TIP_RATIO[finger]` times the intermediate segment's length
    /// (distal/middle phalanx length ratios of an average adult hand, see [`TIP_RATIO`]).
    Tip,
}

/// Distal phalanx length over the previous phalanx length, thumb to little finger, from the
/// mean phalanx lengths of Buryanov & Kotiuk, "Proportions of Hand Segments", Int. J.
/// Morphol. 28(3), 2010 (thumb: distal / proximal phalanx). Used for [`AlignPoint::Tip`]
/// because avatars have no tip bone.
pub const TIP_RATIO: [f32; 5] = [0.70, 0.71, 0.66, 0.67, 0.88];

/// Fingertip-alignment options (JS: `options.alignment`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlignmentOptions {
    /// Turn alignment on (default) or off (IK wrist = pose wrist).
    pub enabled: bool,
    /// Which finger to align. Default `"index"`.
    pub finger: Finger,
    /// Which point of the finger. Default `"dip"`.
    pub point: AlignPoint,
    /// 0..1 blend between the pose wrist (0) and the fully aligned wrist (1). Default 1.
    pub weight: f32,
}

impl AlignmentOptions {
    /// The effective weight (0 when disabled).
    #[must_use]
    pub fn effective_weight(&self) -> f32 {
        if self.enabled {
            self.weight
        } else {
            0.0
        }
    }
}

/// What alignment did for one hand, in the internal frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlignmentReport {
    /// Where the user's aligned point (DIP or tip) is, mapped onto the avatar.
    pub target_dip: Vec3,
    /// The wrist IK target position.
    pub ik_wrist: Vec3,
    /// The pose wrist the target was built from.
    pub pose_wrist: Vec3,
    /// Distance (m) between the avatar's aligned point after IK and `target_dip`.
    pub error: f32,
    /// Whether the arm reached the IK wrist.
    pub reachable: bool,
    /// Whether the avatar has the aligned finger (otherwise the IK wrist is the pose wrist).
    pub aligned: bool,
    /// The avatar's wrist-to-aligned-point vector (world axes) for this frame's hand and
    /// finger rotations ([`avatar_offset`]); zero when not aligned. With the wrist on
    /// `ik_wrist` the avatar's point is at `ik_wrist + avatar_offset`.
    pub avatar_offset: Vec3,
}

/// The avatar's aligned point relative to its wrist joint, in world axes, for a hand with
/// world rotation `hand_rotation` and finger rotations `local`: the same-frame forward
/// kinematics the seed does a frame late. `None` when the avatar lacks the finger.
#[must_use]
pub fn avatar_offset(
    skeleton: &Skeleton,
    side: Side,
    options: &AlignmentOptions,
    hand_rotation: Quat,
    local: &[Quat; BONE_COUNT],
) -> Option<Vec3> {
    let (dip, rot) = distal_pose(skeleton, side, options.finger, hand_rotation, local)?;
    match options.point {
        AlignPoint::Dip => Some(dip),
        AlignPoint::Tip => Some(dip + rot * tip_offset(skeleton, side, options.finger)?),
    }
}

/// The finger's distal joint relative to the hand joint and the distal bone's world rotation,
/// for a hand with world rotation `hand_rotation` and finger rotations `local`: forward
/// kinematics down the finger's present bones (each one's parent is the one before it, or the
/// hand). `None` when the avatar lacks the distal bone.
fn distal_pose(
    skeleton: &Skeleton,
    side: Side,
    finger: Finger,
    hand_rotation: Quat,
    local: &[Quat; BONE_COUNT],
) -> Option<(Vec3, Quat)> {
    let bones = side.finger(finger);
    let distal = bones[2];
    if !skeleton.has(distal) {
        return None;
    }
    let mut position = Vec3::ZERO;
    let mut rotation = hand_rotation;
    for bone in bones.into_iter().filter(|b| skeleton.has(*b)) {
        position += rotation * skeleton.rest_local(bone);
        rotation *= local[bone.index()];
    }
    Some((position, rotation))
}

/// The avatar's fingertip model ([`AlignPoint::Tip`]): the tip relative to the distal bone's
/// joint, in the distal bone's normalized frame (so a posed tip is `distal position + distal
/// world rotation * offset`): the distal bone's rest offset from its parent (the previous
/// segment) times [`TIP_RATIO`]. VRM has no tip bones. `None` when the avatar lacks the
/// finger's distal bone.
#[must_use]
pub fn tip_offset(skeleton: &Skeleton, side: Side, finger: Finger) -> Option<Vec3> {
    let distal = side.finger(finger)[2];
    skeleton
        .has(distal)
        .then(|| skeleton.rest_local(distal) * TIP_RATIO[finger.index()])
}

/// World position of the avatar's fingertip ([`tip_offset`]) in a posed avatar `world`
/// (forward kinematics of the current rotations). `None` when the avatar lacks the distal bone.
#[must_use]
pub fn fingertip(
    skeleton: &Skeleton,
    world: &WorldPose,
    side: Side,
    finger: Finger,
) -> Option<Vec3> {
    let distal = side.finger(finger)[2].index();
    Some(world.position[distal] + world.rotation[distal] * tip_offset(skeleton, side, finger)?)
}

/// Places the wrist IK target for one hand.
///
/// `landmarks` are the hand's 21 world landmarks already in the avatar frame; `scale` is the
/// body scale applied to the user's wrist-to-DIP offset (1 for `wrists` input).
#[allow(clippy::too_many_arguments)]
#[must_use]
pub fn wrist_target(
    skeleton: &Skeleton,
    side: Side,
    options: &AlignmentOptions,
    pose_wrist: Vec3,
    landmarks: &[Vec3; HAND_LANDMARKS],
    scale: f32,
    hand_rotation: Quat,
    local: &[Quat; BONE_COUNT],
) -> AlignmentReport {
    let lm = options.finger.landmarks();
    let user_point = match options.point {
        AlignPoint::Dip => landmarks[lm[2]],
        AlignPoint::Tip => landmarks[lm[3]],
    };
    let user_offset = scale * (user_point - landmarks[0]);
    let target = pose_wrist + user_offset;
    let avatar = avatar_offset(skeleton, side, options, hand_rotation, local);
    let ik_wrist = match avatar {
        Some(a) => pose_wrist + options.effective_weight() * (user_offset - a),
        None => pose_wrist,
    };
    AlignmentReport {
        target_dip: target,
        ik_wrist,
        pose_wrist,
        error: f32::NAN,
        reachable: true,
        aligned: avatar.is_some(),
        avatar_offset: avatar.unwrap_or(Vec3::ZERO),
    }
}

/// Distance between the avatar's aligned point in the posed avatar and the report's target.
/// Updates `world` for the side's arm, hand and fingers from `local` (the rest of `world`, the
/// torso in particular, must be current). `f32::NAN` if the avatar lacks the finger.
pub fn alignment_error(
    skeleton: &Skeleton,
    side: Side,
    options: &AlignmentOptions,
    report: &AlignmentReport,
    local: &[Quat; BONE_COUNT],
    world: &mut WorldPose,
) -> f32 {
    skeleton.forward_arm(side, local, world);
    let hand = side.hand().index();
    match avatar_offset(skeleton, side, options, world.rotation[hand], local) {
        Some(a) => (world.position[hand] + a - report.target_dip).length(),
        None => f32::NAN,
    }
}
