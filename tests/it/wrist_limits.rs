//! Wrist limits (`arm.wristLimits`, `handrig::ik::wrist`) through the whole pipeline on the
//! real recordings: with the limits every shown hand is within the wrist's anatomical range
//! of its forearm, and fingertip alignment stays exact (the index distal on the target DIP,
//! the reported IK target and rotation the ones reached) with every arm solver; without them
//! the same data bends beyond the range (so the check means something); alignment weights
//! keep their meaning; hands-only input is not limited.
// Native only: reads ../shared from disk.

use crate::support::kinect_wrists;
use crate::support::recordings;

use glam::Quat;
use handrig::hand::HandStatus;
use handrig::humanoid::bones::{Finger, Side};
use handrig::ik::{ArmSolver, WristFrame, WRIST_RANGE};
use handrig::mediapipe::FrameInput;
use handrig::{Rig, RigOptions, Skeleton, SolveOutput};

/// What one pass over a recording found.
#[derive(Default, Debug)]
struct Found {
    hand_frames: usize,
    /// Hand-frames the limits changed (the arm solver reported it).
    limited: usize,
    /// Largest excess (radians) of a shown hand over the range.
    worst_excess: f32,
    /// Largest index distal to target DIP distance (m) on reachable aligned frames.
    worst_error: f32,
    /// Largest mismatch between the reported IK target (position m, rotation radians) and the
    /// hand as shown, on reachable frames.
    worst_report: (f32, f32),
}

/// Angle (radians) between two rotations, accurate near 0 (unlike `acos` of the dot).
fn angle(a: Quat, b: Quat) -> f32 {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    2.0 * (a - b).length().atan2((a + b).length())
}

/// Default options with `solver`, the limits on or off, `mirror`, and no dropout easing (a
/// returning hand blends in over a few frames, so what is shown would differ from the solve
/// the reports describe), no turn limit (for the same reason, on MediaPipe's flips), nor
/// self-contact (it moves targets near the face, body and other
/// hand, and turns a limited hand about the touching point: see `tests/it/contact.rs`).
fn options(solver: ArmSolver, limits: bool, mirror: bool) -> RigOptions {
    let mut o = RigOptions::default();
    o.dropout.enabled = false;
    o.arm.max_turn_speed = 0.0;
    o.contact.enabled = false;
    o.arm_solver = solver;
    o.arm.wrist_limits = limits;
    o.mirror = mirror;
    o
}

/// Solves `frames` on a fresh rig and measures `side`'s hand-frames.
fn pass(skel: &Skeleton, frames: &[FrameInput], options: RigOptions, side: Side) -> Found {
    let frame = WristFrame::new(skel, side).expect("wrist frame");
    let mut rig = Rig::new(skel.clone(), options).unwrap();
    let mut out = SolveOutput::default();
    let mut found = Found::default();
    let [_, upper, lower, hand] = side.arm();
    let distal = side.finger(Finger::Index)[2];
    for f in frames {
        rig.solve(f, &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let s = side.index();
        let fresh = out.hands[s].is_some_and(|h| h.status == HandStatus::Solved);
        if !fresh || !out.solved[upper.index()] {
            continue;
        }
        found.hand_frames += 1;
        found.limited += usize::from(rig.arms().last_wrist(side).is_some());
        let (hw, lw) = (
            out.world.rotation[hand.index()],
            out.world.rotation[lower.index()],
        );
        found.worst_excess = found
            .worst_excess
            .max(frame.excess(lw.inverse() * hw, &WRIST_RANGE));
        let Some(a) = out.alignment[s].filter(|a| a.reachable && a.aligned) else {
            continue;
        };
        found.worst_error = found.worst_error.max(a.error);
        // The error the rig reports is the one forward kinematics gives.
        let measured = (out.world.position[distal.index()] - a.target_dip).length();
        assert!(
            (measured - a.error).abs() < 1e-5,
            "{measured} vs {}",
            a.error
        );
        let target = out.ik_targets[s].expect("IK target");
        let wrist = out.world.position[hand.index()];
        found.worst_report.0 = found.worst_report.0.max(
            (target.position - wrist)
                .length()
                .max((a.ik_wrist - wrist).length()),
        );
        found.worst_report.1 = found.worst_report.1.max(angle(target.rotation, hw));
        // The reported avatar offset is the one shown.
        let offset = out.world.position[distal.index()] - wrist;
        assert!(
            (offset - a.avatar_offset).length() < 1e-4,
            "{offset} vs {a:?}"
        );
    }
    found
}

/// Both data sets for `side`: the ASL clips (pose input, a fresh rig per clip) and the Kinect
/// wrists paired with the hand video.
fn both_recordings(
    skel: &Skeleton,
    clips: &[Vec<FrameInput>],
    solver: ArmSolver,
    limits: bool,
) -> Vec<(String, Found)> {
    let mut all = Vec::new();
    for (c, clip) in clips.iter().enumerate() {
        for side in Side::BOTH {
            let found = pass(skel, clip, options(solver, limits, false), side);
            all.push((format!("asl clip {c} {side:?}"), found));
        }
    }
    for side in Side::BOTH {
        let frames = kinect_wrists::paired_frames(skel, side);
        let found = pass(
            skel,
            &frames,
            options(solver, limits, side == Side::Left),
            side,
        );
        all.push((format!("kinect {side:?}"), found));
    }
    all
}

#[test]
fn limited_hands_are_within_range_and_the_index_distal_stays_on_the_target() {
    let clips: Vec<Vec<FrameInput>> = recordings::ASL.iter().map(|p| recordings::asl(p)).collect();
    for skel in recordings::real_avatars() {
        for solver in ArmSolver::ALL {
            let mut limited = 0;
            for (what, f) in both_recordings(&skel, &clips, solver, true) {
                let tag = format!("{solver:?} {what}: {f:?}");
                assert!(f.worst_excess < 1e-3, "{tag}");
                assert!(f.worst_error < 1e-4, "{tag}");
                assert!(f.worst_report.0 < 1e-4 && f.worst_report.1 < 1e-3, "{tag}");
                limited += f.limited;
            }
            // The limits were at work (the mismatched Kinect pairing bends every frame).
            assert!(limited > 500, "{solver:?}: {limited} limited hand-frames");
        }
    }
}

#[test]
fn without_limits_the_same_recordings_bend_beyond_the_range() {
    let clips: Vec<Vec<FrameInput>> = recordings::ASL.iter().map(|p| recordings::asl(p)).collect();
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let all = both_recordings(&skel, &clips, ArmSolver::TwoBone, false);
    let worst = all.iter().map(|(_, f)| f.worst_excess).fold(0.0, f32::max);
    assert!(worst > 1.0, "largest excess {worst} rad");
    for (what, f) in &all {
        assert_eq!(f.limited, 0, "{what}");
        // The hand rotation is applied as given: the report and the shown hand agree.
        assert!(
            f.worst_report.1 < 1e-3 && f.worst_error < 1e-4,
            "{what}: {f:?}"
        );
    }
}

#[test]
fn alignment_weight_keeps_its_meaning_under_the_limits() {
    // IK wrist = pose wrist + w * (user offset - avatar offset), with the avatar offset of the
    // hand as shown (limited): the point w of the way along the avatar's offset stays put.
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let side = Side::Right;
    let frames = kinect_wrists::paired_frames(&skel, side);
    let mut o = options(ArmSolver::TwoBone, true, false);
    o.alignment.weight = 0.5;
    let mut rig = Rig::new(skel.clone(), o).unwrap();
    let mut out = SolveOutput::default();
    let (hand, distal) = (side.hand(), side.finger(Finger::Index)[2]);
    let mut checked = 0;
    for f in &frames {
        rig.solve(f, &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let (Some(a), Some(_)) = (out.alignment[1], rig.arms().last_wrist(side)) else {
            continue;
        };
        if !a.reachable {
            continue;
        }
        let shown = out.world.position[distal.index()] - out.world.position[hand.index()];
        let user = a.target_dip - a.pose_wrist;
        let want = a.pose_wrist + 0.5 * (user - shown);
        assert!(
            (a.ik_wrist - want).length() < 1e-4,
            "{} vs {want}",
            a.ik_wrist
        );
        assert!((out.world.position[hand.index()] - a.ik_wrist).length() < 1e-4);
        checked += 1;
    }
    assert!(checked > 100, "{checked} limited frames checked");
}

#[test]
fn hands_only_input_is_not_limited() {
    // Without wrists, pose or arms from the hands alone (`handsOnly: false`) the arm stays at
    // rest and the hand takes the tracked rotation: limiting it against a resting forearm would
    // only lose the hand's orientation.
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let frames: Vec<FrameInput> = recordings::hand_video()
        .iter()
        .take(120)
        .enumerate()
        .map(|(i, h)| {
            let mut f = recordings::frame_of(&h[..h.len().min(4)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f
        })
        .collect();
    let hand_only = |mut o: RigOptions| {
        o.hands_only.enabled = false;
        o
    };
    let mut on = Rig::new(
        skel.clone(),
        hand_only(options(ArmSolver::TwoBone, true, false)),
    )
    .unwrap();
    let mut off = Rig::new(
        skel.clone(),
        hand_only(options(ArmSolver::TwoBone, false, false)),
    )
    .unwrap();
    let (mut a, mut b) = (SolveOutput::default(), SolveOutput::default());
    let hand = Side::Right.hand().index();
    for f in &frames {
        on.solve(f, &mut a).unwrap();
        a.turn_to_internal_frame(on.skeleton().version());
        off.solve(f, &mut b).unwrap();
        b.turn_to_internal_frame(off.skeleton().version());
        assert!(angle(a.local[hand], b.local[hand]) < 1e-6);
        assert!(on.arms().last_wrist(Side::Right).is_none());
    }
}
