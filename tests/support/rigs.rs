//! Synthetic T-pose test bodies: one builder for the symmetric humanoids the native tests
//! rig, each test giving its own proportions (they differ on purpose: arm lengths, hand
//! shapes, shoulder heights), and the VRM 0.x variant of any of them.

use glam::Vec3;
use handrig::{HumanBone, Skeleton, VrmVersion};

/// The legs of a T-pose body: the left hip joint's x offset (m; the right leg mirrors it) and
/// the heights (m) of upperLeg, lowerLeg and foot, all at z = 0.
#[derive(Clone, Copy, Debug)]
pub struct Legs {
    pub x: f32,
    pub heights: [f32; 3],
}

/// Rest positions (VRM 1.0 frame: facing +Z, the avatar's left at +X) of a symmetric T-pose
/// humanoid: `torso` bones straight above the origin at the given heights (m), `legs`, and
/// the `left` arm and hand bones at the given positions; the right side mirrors `left`
/// (x negated, exactly, so the body is symmetric to the last bit).
pub fn t_pose(
    torso: &[(HumanBone, f32)],
    legs: Legs,
    left: &[(HumanBone, Vec3)],
) -> Vec<(HumanBone, Vec3)> {
    let mut bones: Vec<(HumanBone, Vec3)> = torso
        .iter()
        .map(|&(b, y)| (b, Vec3::new(0.0, y, 0.0)))
        .collect();
    let leg = [
        HumanBone::LeftUpperLeg,
        HumanBone::LeftLowerLeg,
        HumanBone::LeftFoot,
    ];
    for (b, y) in leg.into_iter().zip(legs.heights) {
        bones.push((b, Vec3::new(legs.x, y, 0.0)));
        bones.push((b.mirrored(), Vec3::new(-legs.x, y, 0.0)));
    }
    for &(b, p) in left {
        bones.push((b, p));
        bones.push((b.mirrored(), Vec3::new(-p.x, p.y, p.z)));
    }
    bones
}

/// The skeleton of `bones` (VRM 1.0 frame) as a model of `version` stores it: for VRM 0.x the
/// positions are turned 180 degrees about +Y (the file faces -Z), so that internally every
/// version is the same body.
pub fn skeleton(bones: &[(HumanBone, Vec3)], version: VrmVersion) -> Skeleton {
    let model: Vec<(HumanBone, Vec3)> = bones
        .iter()
        .map(|&(b, p)| (b, version.position_to_internal(p)))
        .collect();
    Skeleton::new(&model, version).expect("test skeleton")
}
