//! The hand solver inside `Rig::solve`: both sides from MediaPipe input through the camera
//! mapping, and degenerate hands keeping the previous rotations.

use crate::support::hand_model;
use crate::support::recordings;

use glam::{Quat, Vec3};
use hand_model::{avatar, place, pose, HandLayout, HandModel, NO_STRETCH};
use handrig::mediapipe::WristObservation;
use handrig::{Finger, FrameInput, Handedness, Rig, RigOptions, Side, SolveOutput};
use recordings::{frame_of, hand};

/// MediaPipe world landmarks (camera axes) of the model hand of `side`, turned by `q`, a
/// user's hand 1.3 times the avatar's (so that fingertip alignment moves the wrist target).
/// The default mapping is `(x, -y, -z)`, its own inverse.
fn mediapipe_hand(model: &HandModel, q: Quat) -> [Vec3; 21] {
    let lm = place(
        &model.landmarks(&pose("pinch"), &NO_STRETCH),
        q,
        1.3,
        Vec3::ZERO,
    );
    lm.map(|p| Vec3::new(p.x, -p.y, -p.z))
}

fn frame_with(hands: &[(Handedness, [Vec3; 21])]) -> FrameInput {
    let hands: Vec<_> = hands.iter().map(|(h, w)| hand(*h, 0.9, *w)).collect();
    frame_of(&hands)
}

#[test]
fn both_hands_through_the_rig_and_held_on_degenerate_frames() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let q = Quat::from_rotation_x(0.6) * Quat::from_rotation_y(-0.3);
    // Un-mirrored input: MediaPipe labels the subject's right hand "Left".
    let right = mediapipe_hand(&HandModel::from_skeleton(&skel, Side::Right), q);
    let left = mediapipe_hand(&HandModel::from_skeleton(&skel, Side::Left), q);
    let mut rig = Rig::new(skel.clone(), RigOptions::per_frame()).unwrap();
    let mut out = SolveOutput::default();

    let mut frame = frame_with(&[(Handedness::Left, right), (Handedness::Right, left)]);
    frame.wrists[Side::Right.index()] = Some(WristObservation {
        position: Vec3::new(-0.5, 1.3, 0.2),
        rotation: None,
    });
    rig.solve(&frame, &mut out).unwrap();
    for side in Side::BOTH {
        let hand = side.hand();
        assert!(out.solved[hand.index()]);
        // Both hands get the same world rotation (the model placement) through the mapping.
        let w = out.world.rotation[hand.index()];
        assert!(
            (2.0 * w.dot(q).abs().min(1.0).acos()).to_degrees() < 0.5,
            "{side:?}"
        );
        for f in Finger::ALL {
            for b in side.finger(f) {
                assert!(out.solved[b.index()], "{b}");
                assert!(out.local[b.index()].is_finite());
            }
        }
    }
    assert!(out.alignment[Side::Right.index()].is_some());
    let kept = out.local;
    let aligned = out.ik_targets[Side::Right.index()].unwrap().position;
    assert!(
        aligned.distance(Vec3::new(-0.5, 1.3, 0.2)) > 0.01,
        "alignment moved the target: {aligned}"
    );

    // The right hand collapses to a point: the right side keeps its finger rotations and
    // hand rotation, without fingertip alignment from the collapsed landmarks.
    let mut frame = frame_with(&[
        (Handedness::Left, [Vec3::new(0.01, 0.02, 0.03); 21]),
        (Handedness::Right, left),
    ]);
    frame.wrists[Side::Right.index()] = Some(WristObservation {
        position: Vec3::new(-0.5, 1.3, 0.2),
        rotation: None,
    });
    rig.solve(&frame, &mut out).unwrap();
    for f in Finger::ALL {
        for b in Side::Right.finger(f) {
            assert!(out.solved[b.index()]);
            assert_eq!(out.local[b.index()], kept[b.index()], "{b}");
        }
    }
    assert!(out.alignment[Side::Right.index()].is_none());
    // The held hand keeps its last alignment's offset from the wrist (the wrist did not move:
    // the same target), rather than jumping to the bare wrist.
    let target = out.ik_targets[Side::Right.index()].unwrap();
    assert!(
        target.position.distance(aligned) < 1e-6,
        "{target:?} vs {aligned}"
    );
    assert!((2.0 * target.rotation.dot(q).abs().min(1.0).acos()).to_degrees() < 0.5);
    for q in out.local.iter().chain(out.world.rotation.iter()) {
        assert!(q.is_finite());
    }

    // The right hand lost (the wrist still given): with the dropout easing off nothing is
    // carried, and a hand held on its first frame back starts from the bare wrist, not from
    // the offset of before the loss.
    let mut lost = frame_with(&[(Handedness::Right, left)]);
    lost.wrists[Side::Right.index()] = frame.wrists[Side::Right.index()];
    rig.solve(&lost, &mut out).unwrap();
    assert!(out.hands[Side::Right.index()].is_none());
    rig.solve(&frame, &mut out).unwrap();
    assert_eq!(
        out.hands[Side::Right.index()].map(|h| h.status),
        Some(handrig::hand::HandStatus::Held)
    );
    let target = out.ik_targets[Side::Right.index()].unwrap();
    assert!(
        target.position.distance(Vec3::new(-0.5, 1.3, 0.2)) < 1e-4,
        "{target:?}"
    );
}
