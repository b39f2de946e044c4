//! Optimization-based hand retargeting (`HandStrategy::Retarget`, seed 003): known answers on
//! hands built from the avatar's own skeleton, scale, limits on real data, degenerate input,
//! and the rig's fingertip and retarget outputs.

use crate::support::hand_model;
use crate::support::recordings;

use glam::{Quat, Vec3};
use hand_model::{avatar, place, pose, poses, Angles, HandLayout, HandModel};
use handrig::align::{fingertip, TIP_RATIO};
use handrig::hand::retarget::OPEN_EXTENT;
use handrig::hand::{HandSolver, HandStatus, HandStrategy, RetargetOptions, LIMITS};
use handrig::mediapipe::{FrameInput, Handedness, WristObservation};
use handrig::{Finger, Side, Skeleton, WorldPose, BONE_COUNT};
use handrig::{Rig, RigOptions, SolveOutput};

/// Segment stretch that makes the model's tip (0.8 of the previous segment past the DIP) the
/// avatar's fingertip model (`TIP_RATIO`).
fn tip_stretch(k: f32) -> [[f32; 3]; 5] {
    core::array::from_fn(|f| [k, k, k * TIP_RATIO[f] / 0.8])
}

/// Avatar fingertips relative to the hand joint, in the hand's frame, for finger `local`s.
fn avatar_tips(skel: &Skeleton, side: Side, local: &[Quat; BONE_COUNT]) -> [Option<Vec3>; 5] {
    let mut world = WorldPose::default();
    skel.forward(local, &mut world);
    let hand = side.hand().index();
    let (p, r) = (world.position[hand], world.rotation[hand]);
    Finger::ALL.map(|f| fingertip(skel, &world, side, f).map(|t| r.inverse() * (t - p)))
}

/// The model hand posed by `angles`, with `stretch`, placed by `q` at some offset.
fn landmarks(model: &HandModel, angles: &Angles, stretch: &[[f32; 3]; 5], q: Quat) -> [Vec3; 21] {
    place(
        &model.landmarks(angles, stretch),
        q,
        1.0,
        Vec3::new(0.3, -0.2, 0.5),
    )
}

fn turn() -> Quat {
    Quat::from_euler(glam::EulerRot::YXZ, 0.9, -0.4, 2.2)
}

/// The user's fingertips of `lm` relative to the wrist in the solved hand's frame, scaled.
fn user_tips(lm: &[Vec3; 21], hand: Quat, scale: f32) -> [Vec3; 5] {
    Finger::ALL.map(|f| scale * (hand.inverse() * (lm[f.landmarks()[3]] - lm[0])))
}

#[test]
fn a_hand_built_from_the_avatar_is_recovered_to_a_tenth_of_a_millimeter() {
    let avatars = [
        ("standard", avatar(&HandLayout::standard(), &[])),
        (
            "relaxed",
            avatar(
                &HandLayout::standard()
                    .relaxed(0.15, [0.1, 0.0, -0.08, -0.15])
                    .bent_thumb(0.3, 0.4),
                &[],
            ),
        ),
        ("human fixture", recordings::vrm(recordings::FIXTURE_VRM1)),
        ("vrm0 fixture", recordings::vrm(recordings::FIXTURE_VRM0)),
    ];
    for (name, skel) in &avatars {
        for side in Side::BOTH {
            let model = HandModel::from_skeleton(skel, side);
            for (pose, angles) in poses() {
                let lm = landmarks(&model, &angles, &tip_stretch(1.0), turn());
                let mut solver = HandSolver::new(skel, HandStrategy::Retarget).unwrap();
                // The hand is the avatar's own: its scale is 1.
                solver.set_hand_scale(side, Some(1.0));
                let mut local = [Quat::IDENTITY; BONE_COUNT];
                let hand = solver.solve(skel, side, &lm, &mut local).unwrap();
                let report = *solver.retarget_report(side).expect("retargeted");
                assert_eq!(report.scale, 1.0);
                let want = user_tips(&lm, hand, 1.0);
                let got = avatar_tips(skel, side, &local);
                for f in Finger::ALL {
                    let e = (got[f.index()].unwrap() - want[f.index()]).length();
                    assert!(
                        e < 1e-4,
                        "{name} {side:?} {pose} {f:?}: fingertip off by {:.3} mm",
                        e * 1e3
                    );
                }
                assert!(report.residual < 1e-4, "{name} {pose}: {report:?}");
            }
        }
    }
}

/// Finger segment stretch of a user whose proximal phalanges are 15% longer and middle
/// phalanges 25% shorter than the avatar's: about the same finger lengths, other
/// proportions, so copied angles put the fingertips elsewhere.
fn odd_proportions() -> [[f32; 3]; 5] {
    core::array::from_fn(|f| [1.15, 0.75, TIP_RATIO[f] / 0.8])
}

#[test]
fn fingertips_reach_the_targets_where_copied_angles_miss_them() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let side = Side::Right;
    let model = HandModel::from_skeleton(&skel, side);
    let (mut analytic_sum, mut retarget_sum) = (0.0, 0.0);
    for (pose, angles) in poses() {
        let lm = landmarks(&model, &angles, &odd_proportions(), turn());
        let mut worst = [0.0_f32; 2];
        for (k, strategy) in [HandStrategy::Analytic, HandStrategy::Retarget]
            .into_iter()
            .enumerate()
        {
            let mut solver = HandSolver::new(&skel, strategy).unwrap();
            solver.set_hand_scale(side, Some(1.0));
            let mut local = [Quat::IDENTITY; BONE_COUNT];
            let hand = solver.solve(&skel, side, &lm, &mut local).unwrap();
            let want = user_tips(&lm, hand, 1.0);
            let got = avatar_tips(&skel, side, &local);
            for f in Finger::ALL {
                let e = (got[f.index()].unwrap() - want[f.index()]).length();
                worst[k] = worst[k].max(e);
            }
        }
        assert!(
            worst[1] < 1e-3,
            "{pose}: worst fingertip error retarget {:.2} mm (analytic {:.2} mm)",
            worst[1] * 1e3,
            worst[0] * 1e3
        );
        analytic_sum += worst[0];
        retarget_sum += worst[1];
    }
    // The proportions matter: copied angles miss by millimeters.
    assert!(
        analytic_sum > 10.0 * retarget_sum && analytic_sum > 0.02,
        "analytic {analytic_sum} retarget {retarget_sum}"
    );
}

#[test]
fn automatic_and_calibrated_scales_compare_hand_lengths() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let side = Side::Left;
    let model = HandModel::from_skeleton(&skel, side);
    // The user's hand is the avatar's, 1.2 times larger.
    let k = 1.2;
    let flat = place(
        &model.landmarks(&pose("flat"), &tip_stretch(1.0)),
        turn(),
        k,
        Vec3::ZERO,
    );
    let fist = place(
        &model.landmarks(&pose("fist"), &tip_stretch(1.0)),
        turn(),
        k,
        Vec3::ZERO,
    );
    let mut solver = HandSolver::new(&skel, HandStrategy::Retarget).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    assert_eq!(solver.hand_scale(side), None);
    assert_eq!(
        solver.calibrate_hand_scale(side),
        None,
        "nothing solved yet"
    );
    // Automatic: path lengths (pose-independent) times the open-hand extent ratio.
    for lm in [&fist, &flat, &fist] {
        solver.solve(&skel, side, lm, &mut local).unwrap();
        let s = solver.hand_scale(side).unwrap();
        assert!((s - OPEN_EXTENT / k).abs() < 1e-4, "automatic scale {s}");
    }
    // Calibration refuses a fist and keeps the automatic scale.
    assert_eq!(solver.calibrate_hand_scale(side), None);
    assert!((solver.hand_scale(side).unwrap() - OPEN_EXTENT / k).abs() < 1e-4);
    // An open hand: the bounding boxes' lengths, 1 / k here.
    solver.solve(&skel, side, &flat, &mut local).unwrap();
    let s = solver
        .calibrate_hand_scale(side)
        .expect("open hand calibrates");
    assert!((s - 1.0 / k).abs() < 1e-3, "calibrated scale {s}");
    solver.solve(&skel, side, &fist, &mut local).unwrap();
    assert_eq!(solver.hand_scale(side), Some(s), "calibration sticks");
    assert_eq!(solver.retarget_report(side).unwrap().scale, s);
    // A preset overrides, clearing it returns to the automatic scale.
    solver.set_hand_scale(side, Some(0.5));
    assert_eq!(solver.hand_scale(side), Some(0.5));
    solver.set_hand_scale(side, None);
    assert!((solver.hand_scale(side).unwrap() - OPEN_EXTENT / k).abs() < 1e-4);
}

#[test]
fn joint_limits_hold_and_outputs_are_unit_on_the_real_recording() {
    let frames: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| {
            h.world
                .map(|p| handrig::CameraMapping::default().to_avatar(p))
        })
        .collect();
    for skel in recordings::real_avatars() {
        let mut solver = HandSolver::new(&skel, HandStrategy::Retarget).unwrap();
        let mut limited = 0;
        for lm in &frames {
            let mut local = [Quat::IDENTITY; BONE_COUNT];
            let hand = solver.solve(&skel, Side::Right, lm, &mut local);
            assert!(hand.is_some_and(|q| q.is_finite()));
            for q in &local {
                assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-4, "{q}");
            }
            let report = solver.retarget_report(Side::Right).expect("retargeted");
            assert!(report.residual.is_finite() && report.iterations > 0);
            for (f, angles) in Finger::ALL
                .iter()
                .zip(solver.avatar_angles(Side::Right, &local))
            {
                let angles = angles.expect("every finger retargeted");
                for (k, a) in angles.iter().enumerate() {
                    let range = LIMITS[f.index()][k];
                    assert!(
                        range.contains(*a, 1e-3),
                        "{f:?} dof {k}: {} deg",
                        a.to_degrees()
                    );
                    let (lo, hi) = range.radians();
                    if (a - lo).abs() < 1e-3 || (a - hi).abs() < 1e-3 {
                        limited += 1;
                    }
                }
            }
        }
        // The limits are really in play on this recording.
        assert!(limited > 100, "limits active {limited} times");
    }
}

#[test]
fn degenerate_hands_keep_the_previous_solution_and_never_produce_nan() {
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let side = Side::Right;
    let model = HandModel::from_skeleton(&skel, side);
    let good = landmarks(&model, &pose("pinch"), &tip_stretch(0.9), turn());
    let mut solver = HandSolver::new(&skel, HandStrategy::Retarget).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let same = [Vec3::new(0.1, 0.2, 0.3); 21];
    // Nothing to hold yet.
    assert_eq!(solver.solve(&skel, side, &same, &mut local), None);
    assert_eq!(solver.report(side).status, HandStatus::Skipped);
    assert!(solver.retarget_report(side).is_none());

    let hand = solver.solve(&skel, side, &good, &mut local).unwrap();
    let solved = local;
    let mut collinear = good;
    for (i, p) in collinear.iter_mut().enumerate() {
        *p = Vec3::new(0.01 * i as f32, 0.0, 0.0);
    }
    for bad in [same, collinear] {
        let mut held = [Quat::IDENTITY; BONE_COUNT];
        let h = solver.solve(&skel, side, &bad, &mut held).unwrap();
        assert_eq!(solver.report(side).status, HandStatus::Held);
        assert!(solver.retarget_report(side).is_none());
        // The previous output, exactly.
        assert_eq!(h, hand);
        for f in Finger::ALL {
            for b in side.finger(f) {
                assert_eq!(held[b.index()], solved[b.index()], "{b}");
            }
        }
    }
    // Tiny, huge and far-off hands: finite output, limits kept.
    for (s, t) in [
        (1e-4, Vec3::ZERO),
        (100.0, Vec3::ZERO),
        (1.0, Vec3::splat(1e4)),
    ] {
        let lm = place(&good, Quat::IDENTITY, s, t);
        let mut out = [Quat::IDENTITY; BONE_COUNT];
        if let Some(h) = solver.solve(&skel, side, &lm, &mut out) {
            assert!(h.is_finite());
        }
        assert!(out.iter().all(|q| q.is_finite()), "scale {s}");
        if let Some(r) = solver.retarget_report(side) {
            assert!(r.residual.is_finite() && r.scale.is_finite(), "{r:?}");
        }
    }
}

/// The landmarks of `lm` (avatar frame) as MediaPipe reports them (camera axes; the default
/// mapping `(x, -y, -z)` is its own inverse), labelled for the un-mirrored subject's right
/// hand (MediaPipe says "Left").
fn mediapipe_frame(lm: &[Vec3; 21], wrist: Option<Vec3>) -> FrameInput {
    let world = lm.map(|p| Vec3::new(p.x, -p.y, -p.z));
    let mut frame = recordings::frame_of(&[recordings::hand(Handedness::Left, 0.9, world)]);
    frame.wrists[Side::Right.index()] = wrist.map(|position| WristObservation {
        position,
        rotation: None,
    });
    frame
}

fn rig_options(json: &str) -> RigOptions {
    RigOptions::from_json(json).unwrap()
}

#[test]
fn the_rig_reports_fingertips_for_every_strategy_and_retarget_targets_in_world() {
    for skel in [
        recordings::vrm(recordings::FIXTURE_VRM1),
        recordings::vrm(recordings::FIXTURE_VRM0),
    ] {
        let side = Side::Right;
        let model = HandModel::from_skeleton(&skel, side);
        let lm = landmarks(&model, &pose("pinch"), &tip_stretch(1.0), turn());
        // A reachable wrist in front of the right shoulder (model frame).
        let shoulder = skel.rest_world(side.arm()[1]).unwrap();
        let wrist = shoulder + Vec3::new(-0.05, -0.2, 0.28);
        let frame = mediapipe_frame(&lm, Some(skel.version().position_to_internal(wrist)));
        for strategy in ["analytic", "retarget"] {
            // Wrist limits off: the targets are checked against the tracked hand's world
            // offsets, which a limited hand rotation turns.
            let options = rig_options(&format!(
                r#"{{ "handStrategy": "{strategy}", "alignment": {{ "point": "tip" }}, "arm": {{ "wristLimits": false }} }}"#
            ));
            let mut rig = Rig::new(skel.clone(), options).unwrap();
            let mut out = SolveOutput::default();
            rig.solve(&frame, &mut out).unwrap();
            out.turn_to_internal_frame(rig.skeleton().version());
            // Fingertips: the distal bone extended by the anatomical ratio, both sides.
            for s in Side::BOTH {
                for f in Finger::ALL {
                    let distal = s.finger(f)[2].index();
                    let want = out.world.position[distal]
                        + out.world.rotation[distal]
                            * (skel.rest_local(s.finger(f)[2]) * TIP_RATIO[f.index()]);
                    let got = out.fingertips[s.index()][f.index()].expect("fingertip");
                    assert!((got - want).length() < 1e-6, "{strategy} {s:?} {f:?}");
                }
            }
            // Fingertip alignment works with either strategy's rotations.
            let a = out.alignment[side.index()].expect("aligned");
            assert!(a.reachable && a.error < 1e-3, "{strategy}: {a:?}");
            match strategy {
                "analytic" => assert!(out.retarget.iter().all(Option::is_none)),
                _ => {
                    assert!(out.retarget[Side::Left.index()].is_none());
                    let r = out.retarget[side.index()].expect("retarget report");
                    // Targets: the user's wrist-to-tip offsets, scaled, from the avatar's
                    // hand joint in the world; the avatar's fingertips on them, the residual
                    // their weighted RMS distance.
                    let hand = out.world.position[side.hand().index()];
                    let (mut err, mut weight) = (0.0, 0.0);
                    for f in Finger::ALL {
                        let target = r.targets[f.index()].unwrap();
                        let user = r.scale * (lm[f.landmarks()[3]] - lm[0]);
                        assert!((target - hand - user).length() < 1e-5, "{f:?}");
                        let tip = out.fingertips[side.index()][f.index()].unwrap();
                        let w = RetargetOptions::default().tip_weights[f.index()];
                        err += w * (tip - target).length_squared();
                        weight += w;
                        assert!((tip - target).length() < 1e-3, "{f:?}");
                    }
                    assert!(((err / weight).sqrt() - r.residual).abs() < 1e-5, "{r:?}");
                }
            }
        }
    }
}

#[test]
fn the_rig_calibrates_the_hand_scale_from_an_open_hand() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let side = Side::Right;
    let model = HandModel::from_skeleton(&skel, side);
    let options = rig_options(r#"{ "handStrategy": "retarget", "filter": { "enabled": false } }"#);
    let mut rig = Rig::new(skel.clone(), options).unwrap();
    let mut out = SolveOutput::default();
    assert_eq!(rig.calibrate_hand_scale(), [None, None]);
    let open = place(
        &model.landmarks(&pose("flat"), &tip_stretch(1.0)),
        Quat::IDENTITY,
        0.8,
        Vec3::ZERO,
    );
    rig.solve(&mediapipe_frame(&open, None), &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    let auto = out.retarget[side.index()].unwrap().scale;
    assert!((auto - OPEN_EXTENT / 0.8).abs() < 1e-4, "{auto}");
    let [left, right] = rig.calibrate_hand_scale();
    assert_eq!(left, None, "no left hand was seen");
    let s = right.expect("open hand calibrates");
    assert!((s - 1.0 / 0.8).abs() < 1e-3, "{s}");
    let fist = place(
        &model.landmarks(&pose("fist"), &tip_stretch(1.0)),
        Quat::IDENTITY,
        0.8,
        Vec3::ZERO,
    );
    rig.solve(&mediapipe_frame(&fist, None), &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    assert_eq!(out.retarget[side.index()].unwrap().scale, s);
    // A fist does not calibrate; the calibrated scale stays.
    assert_eq!(rig.calibrate_hand_scale(), [None, None]);
    rig.solve(&mediapipe_frame(&fist, None), &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    assert_eq!(out.retarget[side.index()].unwrap().scale, s);
}

/// Pinches close through the whole rig (every default, `handStrategy: "retarget"`): on the
/// hand video's pinch frames (the user's thumb and index tips within 2 cm in the world
/// landmarks; three frames, each a pinch that closes for one to three frames) the avatar's
/// thumb-index tip distance is the user's times the hand scale within 2 mm, on the robot and
/// the generated adult. The One Euro filter alone leaves them 8-28 mm open (the filtered tips
/// lag a fast pinch); without the raw-gap restoration this fails.
#[test]
fn pinches_close_through_the_filtered_rig_on_the_hand_video() {
    let raw = recordings::hand_video();
    let frames = recordings::hand_video_frames();
    for path in [recordings::ROBOT, "tests/fixtures/avatars/woman-vrm1.vrm"] {
        let mut rig = Rig::new(
            recordings::vrm(path),
            rig_options(r#"{ "handStrategy": "retarget" }"#),
        )
        .unwrap();
        let mut out = SolveOutput::default();
        let mut checked = 0;
        for (i, frame) in frames.iter().enumerate() {
            rig.solve(frame, &mut out).unwrap();
            let Some(h) = recordings::best_hand(&raw[i]) else {
                continue;
            };
            let user = (h.world[4] - h.world[8]).length();
            if user >= 0.02 {
                continue;
            }
            let s = Side::Right.index();
            let rep = out.retarget[s].expect("retarget report on a pinch frame");
            let (a, b) = (out.fingertips[s][0].unwrap(), out.fingertips[s][1].unwrap());
            let err = ((a - b).length() - rep.scale * user).abs();
            assert!(
                err < 0.002,
                "{path} frame {i}: pinch {:.2} mm off (user {:.1} mm)",
                err * 1e3,
                user * 1e3
            );
            checked += 1;
        }
        assert_eq!(checked, 3, "{path}: the hand video's pinch frames");
    }
}
