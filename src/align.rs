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

use crate::humanoid::bones::{Finger, HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::{Skeleton, WorldPose};
use crate::input::mediapipe::{hand_landmark, HAND_LANDMARKS};

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
    /// Whether the avatar has a point to align: the aligned finger or what stands in for it
    /// ([`AlignmentReport::part`]), so always `true` (before stand-ins, `false` on avatars
    /// without the finger's distal bone, whose IK wrist was the pose wrist).
    pub aligned: bool,
    /// The avatar's wrist-to-aligned-point vector (world axes) for this frame's hand and
    /// finger rotations ([`part_offset`]); zero when not aligned. With the wrist on
    /// `ik_wrist` the avatar's point is at `ik_wrist + avatar_offset`.
    pub avatar_offset: Vec3,
    /// What carries the aligned point on this avatar ([`AlignedPart::choose`]).
    pub part: AlignedPart,
}

/// What carries a side's aligned point on the avatar, chosen once at setup
/// ([`AlignedPart::choose`]) from the bones the avatar has.
///
/// Partial finger rigs are common (no distal bones, no fingers at all). Rather than switching
/// alignment and contact off, the rig aligns with what the avatar has: the configured finger's
/// distal bone; else that finger's deepest bone with the missing joints extrapolated
/// ([`extension`]); else another finger; else the palm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlignedPart {
    /// A finger, through its deepest bone the avatar has: `depth` 2 the distal bone (the
    /// aligned point as designed), 1 the intermediate (thumb: proximal), 0 the proximal
    /// (fingers only). Missing joints past it are extrapolated ([`extension`]).
    Finger {
        /// The finger.
        finger: Finger,
        /// Index in the finger's chain ([`Side::finger`]) of its deepest present bone.
        depth: usize,
    },
    /// No usable finger: the palm's front (the middle knuckle, MCP) on the user, on the avatar
    /// the middle proximal joint or, without it, the hand bone extended by the avatar's palm
    /// length ([`palm_front`]).
    Palm,
}

/// The order in which other fingers stand in for the configured one when the avatar lacks it
/// (after depth: a finger with its distal bone first): the index, the usual pointing and
/// touching finger; then the middle, its neighbour and the longest finger (its tip leads the
/// hand); ring, little; the thumb last (it opposes the others, its tip is not where a pointing
/// hand touches).
pub const STAND_IN_ORDER: [Finger; 5] = [
    Finger::Index,
    Finger::Middle,
    Finger::Ring,
    Finger::Little,
    Finger::Thumb,
];

impl AlignedPart {
    /// The deepest usable bone of `finger` on this side: its index in the finger's chain, or
    /// `None` (no bone; the thumb's metacarpal alone is not usable: its rest offset from the
    /// hand points across the palm, not along the thumb).
    #[must_use]
    pub fn depth(skeleton: &Skeleton, side: Side, finger: Finger) -> Option<usize> {
        let bones = side.finger(finger);
        let depth = (0..3).rev().find(|&k| skeleton.has(bones[k]))?;
        (finger != Finger::Thumb || depth > 0).then_some(depth)
    }

    /// The part for `configured` (`alignment.finger`) on this side: that finger's distal
    /// bone; else its deepest usable bone; else the other finger with the deepest usable
    /// bone (ties in [`STAND_IN_ORDER`]); else the palm.
    #[must_use]
    pub fn choose(skeleton: &Skeleton, side: Side, configured: Finger) -> AlignedPart {
        if let Some(depth) = Self::depth(skeleton, side, configured) {
            return AlignedPart::Finger {
                finger: configured,
                depth,
            };
        }
        let mut best: Option<(Finger, usize)> = None;
        for finger in STAND_IN_ORDER {
            if finger == configured {
                continue;
            }
            if let Some(d) = Self::depth(skeleton, side, finger) {
                if best.is_none_or(|(_, b)| d > b) {
                    best = Some((finger, d));
                }
            }
        }
        best.map_or(AlignedPart::Palm, |(finger, depth)| AlignedPart::Finger {
            finger,
            depth,
        })
    }

    /// The bone the aligned point is carried by (the palm: the hand bone).
    #[must_use]
    pub fn bone(self, side: Side) -> HumanBone {
        match self {
            AlignedPart::Finger { finger, depth } => side.finger(finger)[depth],
            AlignedPart::Palm => side.hand(),
        }
    }

    /// The finger, `None` for the palm.
    #[must_use]
    pub fn finger(self) -> Option<Finger> {
        match self {
            AlignedPart::Finger { finger, .. } => Some(finger),
            AlignedPart::Palm => None,
        }
    }

    /// `"thumb"` ... `"little"`, or `"palm"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        self.finger().map_or("palm", Finger::as_str)
    }

    /// Whether this is `configured`'s distal bone: alignment as designed, nothing missing.
    #[must_use]
    pub fn is_configured(self, configured: Finger) -> bool {
        self == AlignedPart::Finger {
            finger: configured,
            depth: 2,
        }
    }

    /// The finger whose contact point ([`crate::contact::HandPoints`] tip slot) makes face
    /// contact: this finger, or for the palm the configured finger (whose slot then holds the
    /// palm's front, the avatar's stand-in for it).
    #[must_use]
    pub fn touch_finger(self, configured: Finger) -> Finger {
        self.finger().unwrap_or(configured)
    }

    /// The user's point matching the avatar's aligned point: the finger's DIP (thumb: IP) or
    /// TIP landmark, or for the palm the middle MCP landmark (the palm's front).
    #[must_use]
    pub fn user_point(self, point: AlignPoint, landmarks: &[Vec3; HAND_LANDMARKS]) -> Vec3 {
        match self {
            AlignedPart::Finger { finger, .. } => {
                let lm = finger.landmarks();
                match point {
                    AlignPoint::Dip => landmarks[lm[2]],
                    AlignPoint::Tip => landmarks[lm[3]],
                }
            }
            AlignedPart::Palm => landmarks[hand_landmark::MIDDLE_MCP],
        }
    }
}

/// Segment lengths of an average adult finger in millimeters, thumb to little, `[L0, L1, L2]`:
/// `Lk` is the segment ending at the chain's joint `k` (fingers: wrist joint to MCP, MCP to
/// PIP, PIP to DIP; thumb: L0 unused, CMC to MCP, MCP to IP). The segment past the DIP is
/// `TIP_RATIO * L2`. Phalanges and the thumb's metacarpal: the mean lengths of Buryanov &
/// Kotiuk 2010 (the source of [`TIP_RATIO`]). Wrist joint to MCP, which anatomy tables do not
/// give (they measure the metacarpal bone; the wrist joint sits inside the carpus): the
/// human-proportioned test fixture's (tests/fixtures/PROVENANCE.md), scaled to these
/// phalanges. Avatars differ from it (the generated MakeHuman hands have proximal phalanges
/// a quarter of the wrist-to-knuckle length, against two fifths here), so a point extrapolated
/// from the proximal bone alone is approximate; docs/how-it-works/alignment-ik.md has the figures.
pub const SEGMENT_MM: [[f32; 3]; 5] = [
    [0.0, 46.2, 30.9],
    [95.6, 39.8, 22.4],
    [96.2, 44.6, 26.3],
    [91.1, 41.4, 25.7],
    [87.3, 32.7, 18.1],
];

/// How far past the joint of the chain's bone `depth` the avatar's point (`Dip`: joint 2,
/// `Tip`: joint 3) lies, in multiples of that bone's rest offset from its parent (the segment
/// ending at its joint): the missing segments summed in [`SEGMENT_MM`] proportions, straight
/// on along the last segment present. `depth` 2 with `Tip` is [`TIP_RATIO`]; `depth` 2 with
/// `Dip` is 0.
#[must_use]
pub fn extension(finger: Finger, depth: usize, point: AlignPoint) -> f32 {
    let f = finger.index();
    let l = SEGMENT_MM[f];
    let lengths = [l[0], l[1], l[2], TIP_RATIO[f] * l[2]];
    let last = match point {
        AlignPoint::Dip => 2,
        AlignPoint::Tip => 3,
    };
    let d = depth.min(2);
    lengths[d + 1..=last].iter().sum::<f32>() / lengths[d]
}

/// The avatar's palm front relative to the hand joint in the hand's rest axes, for an avatar
/// without finger bones ([`AlignedPart::Palm`]): the hand bone's direction (from its parent)
/// times the avatar's palm length ([`crate::humanoid::measure::avatar_palm_length`], from its
/// arm), where the middle knuckle would be.
#[must_use]
pub fn palm_front(skeleton: &Skeleton, side: Side) -> Vec3 {
    let middle = side.finger(Finger::Middle)[0];
    if skeleton.has(middle) {
        return skeleton.rest_local(middle);
    }
    let length = crate::humanoid::measure::avatar_palm_length(skeleton);
    skeleton.rest_local(side.hand()).normalize_or_zero() * length
}

/// The avatar's aligned point of `part` relative to its wrist joint, in world axes, for a
/// hand with world rotation `hand_rotation` and finger rotations `local`. For a finger's
/// distal bone this is [`avatar_offset`]; for a shallower bone forward kinematics down to it,
/// then [`extension`] times its rest offset, turned by its world rotation (the missing joints
/// straight); for the palm [`palm_front`] turned by the hand.
#[must_use]
pub fn part_offset(
    skeleton: &Skeleton,
    side: Side,
    part: AlignedPart,
    point: AlignPoint,
    hand_rotation: Quat,
    local: &[Quat; BONE_COUNT],
) -> Vec3 {
    match part {
        AlignedPart::Finger { finger, depth: 2 } => {
            let options = AlignmentOptions {
                enabled: true,
                finger,
                point,
                weight: 1.0,
            };
            avatar_offset(skeleton, side, &options, hand_rotation, local).unwrap_or(Vec3::ZERO)
        }
        AlignedPart::Finger { finger, depth } => {
            let bones = side.finger(finger);
            let mut position = Vec3::ZERO;
            let mut rotation = hand_rotation;
            for bone in bones[..=depth].iter().filter(|b| skeleton.has(**b)) {
                position += rotation * skeleton.rest_local(*bone);
                rotation *= local[bone.index()];
            }
            let last = skeleton.rest_local(bones[depth]);
            position + rotation * (last * extension(finger, depth, point))
        }
        AlignedPart::Palm => hand_rotation * palm_front(skeleton, side),
    }
}

/// World position of `part`'s point in a posed avatar `world` ([`part_offset`] placed on the
/// hand joint).
#[must_use]
pub fn part_world(
    skeleton: &Skeleton,
    world: &WorldPose,
    local: &[Quat; BONE_COUNT],
    side: Side,
    part: AlignedPart,
    point: AlignPoint,
) -> Vec3 {
    let hand = side.hand().index();
    world.position[hand] + part_offset(skeleton, side, part, point, world.rotation[hand], local)
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

/// The user's hand as alignment places it on the avatar.
#[derive(Clone, Copy, Debug)]
pub struct UserHand<'a> {
    /// Where the user's wrist lands on the avatar (the wrist source: the pose wrist mapped
    /// onto the avatar, or a tracker's wrist).
    pub wrist: Vec3,
    /// The hand's 21 world landmarks, in the avatar frame.
    pub landmarks: &'a [Vec3; HAND_LANDMARKS],
    /// The scale applied to the user's wrist-to-fingertip offset (the body scale; 1 for
    /// `wrists` input).
    pub scale: f32,
}

/// Places the wrist IK target for one hand: the user's hand `user`, the avatar's turned to
/// `hand_rotation` with its fingers as in `local`, the aligned point carried by `part`
/// ([`AlignedPart::choose`]).
#[must_use]
pub fn wrist_target(
    skeleton: &Skeleton,
    side: Side,
    options: &AlignmentOptions,
    part: AlignedPart,
    user: &UserHand,
    hand_rotation: Quat,
    local: &[Quat; BONE_COUNT],
) -> AlignmentReport {
    let (pose_wrist, landmarks, scale) = (user.wrist, user.landmarks, user.scale);
    let user_point = part.user_point(options.point, landmarks);
    let user_offset = scale * (user_point - landmarks[0]);
    let target = pose_wrist + user_offset;
    let avatar = part_offset(skeleton, side, part, options.point, hand_rotation, local);
    let ik_wrist = pose_wrist + options.effective_weight() * (user_offset - avatar);
    AlignmentReport {
        target_dip: target,
        ik_wrist,
        pose_wrist,
        error: f32::NAN,
        reachable: true,
        aligned: true,
        avatar_offset: avatar,
        part,
    }
}

/// Distance between the avatar's aligned point in the posed avatar and the report's target.
/// Updates `world` for the side's arm, hand and fingers from `local` (the rest of `world`, the
/// torso in particular, must be current).
pub fn alignment_error(
    skeleton: &Skeleton,
    side: Side,
    options: &AlignmentOptions,
    report: &AlignmentReport,
    local: &[Quat; BONE_COUNT],
    world: &mut WorldPose,
) -> f32 {
    skeleton.forward_arm(side, local, world);
    let point = part_world(skeleton, world, local, side, report.part, options.point);
    (point - report.target_dip).length()
}
