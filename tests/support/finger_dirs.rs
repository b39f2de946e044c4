//! Finger bone directions for the finger evals (`eval/rust/eval_hands.rs`,
//! `eval/rust/eval_fingers.rs`): the avatar's bone by forward kinematics and the MediaPipe
//! segment it is compared with.

use glam::Vec3;
use handrig::mediapipe::HAND_LANDMARKS;
use handrig::{Finger, Side, Skeleton, WorldPose};

/// Avatar bone direction by forward kinematics: joint to child joint; bones without a child
/// continue their parent's rest direction, rotated by their own world rotation.
pub fn avatar_bone_dir(
    skel: &Skeleton,
    world: &WorldPose,
    side: Side,
    finger: Finger,
    slot: usize,
) -> Option<Vec3> {
    let bones = side.finger(finger);
    let bone = bones[slot];
    let p = skel.rest_world(bone)?;
    if let Some(child) = bones[slot + 1..].iter().find(|b| skel.has(**b)) {
        return (world.position[child.index()] - world.position[bone.index()]).try_normalize();
    }
    let parent = skel.parent(bone)?;
    let rest_dir = (p - skel.rest_world(parent)?).try_normalize()?;
    (world.rotation[bone.index()] * rest_dir).try_normalize()
}

/// MediaPipe segment matching an avatar bone: from its landmark to the next present bone's
/// landmark (the tip after the last).
pub fn mp_segment(
    skel: &Skeleton,
    lm: &[Vec3; HAND_LANDMARKS],
    side: Side,
    finger: Finger,
    slot: usize,
) -> Option<Vec3> {
    let bones = side.finger(finger);
    let ids = finger.landmarks();
    let end = (slot + 1..3).find(|s| skel.has(bones[*s])).unwrap_or(3);
    (lm[ids[end]] - lm[ids[slot]]).try_normalize()
}
