//! The Azure Kinect session as handrig `wrists` input, paired with the hand video, the way
//! `eval/rust/eval_alignment.rs` pairs them (and the body-tracker recipe of docs/guide/frames.md builds them):
//!
//! * The recording's frame is left-handed: +X right, +Y up, the subject facing +Z (the nose
//!   is at larger z than the head's centre) with the LEFT shoulder at -X. Negating x gives
//!   the avatar's VRM 1.0 frame (facing +Z, its left at +X): the subject's left wrist drives
//!   the avatar's left.
//! * Each wrist is taken relative to the same side's shoulder (Kinect SHOULDER_*, the
//!   glenohumeral joint = VRM upperArm), scaled by avatar arm / subject arm (upper + lower
//!   arm; the subject's a robust mean over the session and both arms) and placed at the
//!   avatar's upperArm rest position; VRM 0.x models get it in their own frame (turned 180
//!   degrees about +Y).

use glam::Vec3;
use handrig::humanoid::bones::Side;
use handrig::math::robust_mean;
use handrig::mediapipe::{FrameInput, WristObservation, MAX_HANDS};
use handrig::Skeleton;

use super::recordings;

/// The Kinect wrists for `skel`, per frame `[left, right]`, in the model's own frame.
pub fn kinect_wrists(skel: &Skeleton) -> Vec<[Vec3; 2]> {
    let kinect = recordings::kinect();
    let idx = |n: &str| kinect.joint(n).unwrap_or_else(|| panic!("joint {n}"));
    let ids = [
        [idx("SHOULDER_LEFT"), idx("ELBOW_LEFT"), idx("WRIST_LEFT")],
        [
            idx("SHOULDER_RIGHT"),
            idx("ELBOW_RIGHT"),
            idx("WRIST_RIGHT"),
        ],
    ];
    let a = |j: [f32; 4]| Vec3::new(-j[0], j[1], j[2]);
    let mut lengths = Vec::new();
    for f in &kinect.frames {
        for [s, e, w] in ids {
            let (s, e, w) = (a(f[s]), a(f[e]), a(f[w]));
            lengths.push((e - s).length() + (w - e).length());
        }
    }
    let mut scratch = vec![0.0; lengths.len()];
    let user_arm = robust_mean(&lengths, &mut scratch).expect("arm samples");
    let avatar_arm = Side::BOTH
        .iter()
        .map(|side| {
            let [_, _, lower, hand] = side.arm();
            skel.rest_local(lower).length() + skel.rest_local(hand).length()
        })
        .sum::<f32>()
        / 2.0;
    let scale = avatar_arm / user_arm;
    let version = skel.version();
    kinect
        .frames
        .iter()
        .map(|f| {
            Side::BOTH.map(|side| {
                let [s, _, w] = ids[side.index()];
                // Skeleton positions are internal (+Z facing); `wrists` are the model's own.
                let shoulder = skel.rest_world(side.arm()[1]).expect("upper arm");
                version.position_to_internal(shoulder + scale * (a(f[w]) - a(f[s])))
            })
        })
        .collect()
}

/// The session's frames for avatar `side`: the hand video's frame i with the Kinect wrist of
/// `side` in frame i (30 fps). The video is the subject's right hand; drive the avatar's left
/// with `mirror: true`.
pub fn paired_frames(skel: &Skeleton, side: Side) -> Vec<FrameInput> {
    let video = recordings::hand_video();
    kinect_wrists(skel)
        .iter()
        .zip(&video)
        .enumerate()
        .map(|(i, (w, hands))| {
            let mut f = recordings::frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f.wrists[side.index()] = Some(WristObservation {
                position: w[side.index()],
                rotation: None,
            });
            f
        })
        .collect()
}
