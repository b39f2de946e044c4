//! Arm test bodies shared by the arm solver tests: a humanoid with given left-arm rest offsets
//! (the right arm mirrors it) and the rest layouts the property tests run on.
//!
//! Uses its siblings `recordings` and `rigs` (re-exported).

pub use super::{recordings, rigs};

use std::sync::OnceLock;

use glam::{Quat, Vec3};
use handrig::humanoid::bones::HumanBone as B;
use handrig::humanoid::skeleton::{Skeleton, VrmVersion};

/// A humanoid with the left arm's rest offsets `upper` (shoulder joint to elbow) and `lower`
/// (elbow to wrist), internal frame; the right arm mirrors it. Given in the model's own frame
/// for `version` (VRM 0.x: turned to face -Z), so internally every version is the same.
pub fn skeleton(upper: Vec3, lower: Vec3, version: VrmVersion) -> Skeleton {
    let torso = [
        (B::Hips, 1.0),
        (B::Spine, 1.1),
        (B::Chest, 1.25),
        (B::UpperChest, 1.35),
        (B::Neck, 1.45),
        (B::Head, 1.55),
    ];
    let legs = rigs::Legs {
        x: 0.1,
        heights: [0.95, 0.5, 0.08],
    };
    let sh = Vec3::new(0.15, 1.42, 0.0);
    let left = [
        (B::LeftShoulder, Vec3::new(0.03, 1.42, 0.0)),
        (B::LeftUpperArm, sh),
        (B::LeftLowerArm, sh + upper),
        (B::LeftHand, sh + (upper + lower)),
    ];
    rigs::skeleton(&rigs::t_pose(&torso, legs, &left), version)
}

/// Rest layouts the property tests run on: robot-like T-pose (arms along ±X, equal bones),
/// an A-pose with a slightly bent rest elbow and unequal bones, unequal bones with a kinked
/// rest forearm, the A-pose as VRM 0.x, and the real files: the shared robot, the
/// human-proportioned VRM 1.0 fixture and the VRM 0.x fixture (Blender-style rolls, -Z facing).
pub fn layouts() -> &'static [Skeleton] {
    static LAYOUTS: OnceLock<Vec<Skeleton>> = OnceLock::new();
    LAYOUTS.get_or_init(|| {
        let a_upper = 0.28 * Vec3::new(40f32.to_radians().cos(), -40f32.to_radians().sin(), 0.0);
        let a_lower = Quat::from_rotation_y(-0.15) * (a_upper.normalize() * 0.24);
        let mut all = vec![
            skeleton(Vec3::X * 0.25, Vec3::X * 0.25, VrmVersion::V1),
            skeleton(a_upper, a_lower, VrmVersion::V1),
            skeleton(Vec3::X * 0.30, Vec3::new(0.22, 0.0, 0.02), VrmVersion::V1),
            skeleton(a_upper, a_lower, VrmVersion::V0),
        ];
        all.extend(recordings::real_avatars());
        all
    })
}

/// Upper and lower arm lengths (m) of `side`.
pub fn arm_lengths(skel: &Skeleton, side: handrig::humanoid::bones::Side) -> (f32, f32) {
    let [_, _, low, h] = side.arm();
    (skel.rest_local(low).length(), skel.rest_local(h).length())
}
