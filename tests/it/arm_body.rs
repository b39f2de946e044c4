//! Body mapping and arm-length calibration from pose landmarks: the mapping formula, the
//! calibrated scale with outliers, visibility handling, presets and reset, and the rig's
//! behaviour with missing or poorly visible pose input.
// Native only: reads ../shared from disk and uses proptest (not built for wasm32).

use crate::support::rigs;

use glam::{Quat, Vec3};
use handrig::body::{BodyMapper, CalibrationOptions, REFERENCE_USER_ARM};
use handrig::humanoid::bones::{HumanBone as B, Side, BONE_COUNT};
use handrig::math::{insert_sorted, robust_mean, robust_mean_sorted};
use handrig::mediapipe::{
    pose_landmark as pl, CameraMapping, FrameInput, PoseObservation, POSE_LANDMARKS,
};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput, VrmVersion};

/// A humanoid whose arms are `upper` + `lower` long along ±X from shoulders at ±0.15 m.
fn skeleton(upper: f32, lower: f32) -> Skeleton {
    let torso = [
        (B::Hips, 0.9),
        (B::Spine, 1.0),
        (B::Chest, 1.15),
        (B::Neck, 1.4),
        (B::Head, 1.5),
    ];
    let legs = rigs::Legs {
        x: 0.1,
        heights: [0.85, 0.45, 0.05],
    };
    let [shoulder, up, low, hand] = Side::Left.arm();
    let left = [
        (shoulder, Vec3::new(0.04, 1.35, 0.0)),
        (up, Vec3::new(0.15, 1.35, 0.0)),
        (low, Vec3::new(0.15 + upper, 1.35, 0.0)),
        (hand, Vec3::new(0.15 + upper + lower, 1.35, 0.0)),
    ];
    rigs::skeleton(&rigs::t_pose(&torso, legs, &left), VrmVersion::V1)
}

/// A pose (MediaPipe camera axes: x right in the image, y down, z away) of a user facing the
/// camera with the given arm segment lengths; arms hanging forward-down. The subject's left
/// side is on the image's right (+x) when the image is not mirrored.
fn pose(upper: f32, lower: f32) -> PoseObservation {
    let mut world = [Vec3::ZERO; POSE_LANDMARKS];
    let visibility = [1.0; POSE_LANDMARKS];
    for (s, [sh, el, wr]) in [
        (1.0f32, [pl::LEFT_SHOULDER, pl::LEFT_ELBOW, pl::LEFT_WRIST]),
        (-1.0, [pl::RIGHT_SHOULDER, pl::RIGHT_ELBOW, pl::RIGHT_WRIST]),
    ] {
        world[sh] = Vec3::new(0.18 * s, -0.45, 0.0);
        world[el] = world[sh] + Vec3::new(0.05 * s, 1.0, -0.3).normalize() * upper;
        world[wr] = world[el] + Vec3::new(-0.1 * s, 0.2, -1.0).normalize() * lower;
    }
    PoseObservation { world, visibility }
}

#[test]
fn scale_is_avatar_arm_over_user_arm() {
    let skel = skeleton(0.25, 0.25); // avatar arm 0.5
    let options = CalibrationOptions::default();
    let mut m = BodyMapper::new(&skel, &options);
    assert!((m.avatar_arm() - 0.5).abs() < 1e-6);
    // Before any sample: the reference user arm.
    assert!((m.scale() - 0.5 / REFERENCE_USER_ARM).abs() < 1e-6);
    let p = pose(0.30, 0.26);
    for i in 0..options.frames {
        assert!(!m.is_calibrated(), "calibrated after {i} frames");
        m.observe(&p);
        // Provisional estimates are already right on consistent input.
        assert!((m.scale() - 0.5 / 0.56).abs() < 1e-5, "{}", m.scale());
    }
    assert!(m.is_calibrated());
    assert_eq!(m.frames_observed(), 30);
    // Calibrated: further frames (a different user) change nothing.
    m.observe(&pose(0.2, 0.2));
    assert!((m.scale() - 0.5 / 0.56).abs() < 1e-5);
}

#[test]
fn outliers_beyond_twenty_percent_of_the_median_are_dropped() {
    let skel = skeleton(0.3, 0.24); // avatar arm 0.54
    let options = CalibrationOptions {
        frames: 20,
        ..CalibrationOptions::default()
    };
    let mut m = BodyMapper::new(&skel, &options);
    // 20 frames: 14 good (0.55 m, jittering +-1 cm), 4 with a mis-tracked elbow making the arm
    // 0.95 m, 2 foreshortened to 0.25 m. Both arms visible: two samples per frame.
    let mut lengths = Vec::new();
    for i in 0..20 {
        let total = match i % 10 {
            3 | 7 => 0.95,
            5 => 0.25,
            _ => 0.55 + 0.01 * ((i % 3) as f32 - 1.0),
        };
        let p = pose(total * 0.55, total * 0.45);
        m.observe(&p);
        lengths.push(total);
        lengths.push(total);
    }
    assert!(m.is_calibrated());
    let good: Vec<f32> = lengths
        .iter()
        .copied()
        .filter(|l| (l - 0.55).abs() < 0.05)
        .collect();
    let good_mean = good.iter().sum::<f32>() / good.len() as f32;
    let naive_mean = lengths.iter().sum::<f32>() / lengths.len() as f32;
    assert!(
        (m.scale() - 0.54 / good_mean).abs() < 1e-4,
        "{} vs {}",
        m.scale(),
        0.54 / good_mean
    );
    // The outliers matter: without rejection the scale would be visibly off.
    assert!((0.54 / naive_mean - 0.54 / good_mean).abs() > 0.02);
}

#[test]
fn robust_mean_known_answers() {
    let mut scratch = [0.0; 8];
    assert_eq!(robust_mean(&[], &mut scratch), None);
    assert_eq!(robust_mean(&[2.0], &mut scratch), Some(2.0));
    // Median 1.0; 1.3 and 0.5 are beyond 20%; 1.19 and 0.81 are within.
    let m = robust_mean(&[1.0, 1.3, 0.5, 1.19, 0.81, 1.0], &mut scratch).unwrap();
    assert!((m - 1.0).abs() < 1e-6, "{m}");
}

#[test]
fn samples_inserted_in_order_give_the_robust_mean_of_the_samples() {
    // The calibrations keep their samples sorted as they come instead of sorting each frame.
    let mut buf = [0.0_f32; 64];
    let mut scratch = [0.0_f32; 64];
    let mut seen = Vec::new();
    let mut seed = 12_345_u32;
    for count in 0..64 {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let x = 0.5 + (seed >> 8) as f32 / (1u32 << 24) as f32;
        insert_sorted(&mut buf, count, x);
        seen.push(x);
        assert!(
            buf[..=count].windows(2).all(|w| w[0] <= w[1]),
            "not sorted at {count}"
        );
        assert_eq!(
            robust_mean_sorted(&buf[..=count]),
            robust_mean(&seen, &mut scratch)
        );
    }
    // A full buffer is left as it is.
    let before = buf;
    insert_sorted(&mut buf, 64, 0.0);
    assert_eq!(buf, before);
}

#[test]
fn low_visibility_landmarks_are_ignored() {
    let skel = skeleton(0.25, 0.25);
    let mut m = BodyMapper::new(&skel, &CalibrationOptions::default());
    let before = m.scale();
    let mut p = pose(0.3, 0.25);
    // Both elbows hidden: no calibration sample.
    p.visibility[pl::LEFT_ELBOW] = 0.2;
    p.visibility[pl::RIGHT_ELBOW] = 0.49;
    m.observe(&p);
    assert_eq!(m.frames_observed(), 0);
    assert_eq!(m.scale(), before);
    // NaN visibility counts as not seen.
    let mut q = pose(0.3, 0.25);
    q.visibility[pl::LEFT_WRIST] = f32::NAN;
    q.visibility[pl::RIGHT_WRIST] = 0.0;
    m.observe(&q);
    assert_eq!(m.frames_observed(), 0);
    // Mapping: a hidden elbow gives no pole, a hidden wrist or shoulder no mapping at all.
    let cam = CameraMapping::default();
    let a = m.map_arm(&skel, Side::Left, &p, cam).unwrap();
    assert!(a.elbow.is_none());
    assert!(m.map_arm(&skel, Side::Left, &q, cam).is_none());
    let mut r = pose(0.3, 0.25);
    r.visibility[pl::RIGHT_SHOULDER] = 0.1;
    assert!(m.map_arm(&skel, Side::Right, &r, cam).is_none());
    assert!(m.map_arm(&skel, Side::Left, &r, cam).is_some());
    // A threshold of 0.1 accepts them.
    let lenient = BodyMapper::new(
        &skel,
        &CalibrationOptions {
            min_visibility: 0.1,
            ..CalibrationOptions::default()
        },
    );
    assert!(lenient.map_arm(&skel, Side::Right, &r, cam).is_some());
}

#[test]
fn preset_scale_and_reset() {
    let skel = skeleton(0.25, 0.25);
    let options = CalibrationOptions {
        body_scale: Some(0.8),
        ..CalibrationOptions::default()
    };
    let mut m = BodyMapper::new(&skel, &options);
    assert!(m.is_calibrated());
    for _ in 0..40 {
        m.observe(&pose(0.3, 0.3));
    }
    assert_eq!(m.scale(), 0.8);
    m.reset();
    assert_eq!(m.scale(), 0.8);

    let mut auto = BodyMapper::new(&skel, &CalibrationOptions::default());
    for _ in 0..30 {
        auto.observe(&pose(0.3, 0.3));
    }
    assert!(auto.is_calibrated() && (auto.scale() - 0.5 / 0.6).abs() < 1e-5);
    auto.reset();
    assert!(!auto.is_calibrated());
    assert_eq!(auto.frames_observed(), 0);
    assert!((auto.scale() - 0.5 / REFERENCE_USER_ARM).abs() < 1e-6);
    // A new user after reset.
    auto.observe(&pose(0.2, 0.2));
    assert!((auto.scale() - 0.5 / 0.4).abs() < 1e-5);
}

#[test]
fn mapping_formula_and_sides() {
    let skel = skeleton(0.25, 0.25);
    let options = CalibrationOptions {
        body_scale: Some(0.9),
        ..CalibrationOptions::default()
    };
    let m = BodyMapper::new(&skel, &options);
    let p = pose(0.3, 0.25);
    for (cam, side, user) in [
        // Not mirrored: avatar left <- subject's left.
        (CameraMapping::default(), Side::Left, Side::Left),
        (
            CameraMapping {
                input_mirrored: false,
                mirror: true,
            },
            Side::Left,
            Side::Right,
        ),
    ] {
        let (sh, el, wr) = match user {
            Side::Left => (pl::LEFT_SHOULDER, pl::LEFT_ELBOW, pl::LEFT_WRIST),
            Side::Right => (pl::RIGHT_SHOULDER, pl::RIGHT_ELBOW, pl::RIGHT_WRIST),
        };
        let a = m.map_arm(&skel, side, &p, cam).unwrap();
        let avatar_shoulder = skel.rest_world(side.arm()[1]).unwrap();
        let expect = |i: usize| avatar_shoulder + 0.9 * cam.to_avatar(p.world[i] - p.world[sh]);
        assert!((a.wrist - expect(wr)).length() < 1e-6);
        assert!((a.elbow.unwrap() - expect(el)).length() < 1e-6);
        // The mapped arm hangs forward and down from the avatar's shoulder, and on the
        // avatar's own side (outward = +X for the left arm).
        assert!(a.wrist.z > avatar_shoulder.z && a.wrist.y < avatar_shoulder.y);
        assert!(a.elbow.unwrap().x > avatar_shoulder.x, "{:?}", a.elbow);
    }
}

#[test]
fn options_are_validated_and_named() {
    for (json, field) in [
        (
            r#"{"calibration": {"frames": 0}}"#,
            "options.calibration.frames",
        ),
        (
            r#"{"calibration": {"frames": 301}}"#,
            "options.calibration.frames",
        ),
        (
            r#"{"calibration": {"minVisibility": 1.5}}"#,
            "options.calibration.minVisibility",
        ),
        (
            r#"{"calibration": {"bodyScale": -1}}"#,
            "options.calibration.bodyScale",
        ),
    ] {
        let options = RigOptions::from_json(json).unwrap();
        let err = Rig::new(skeleton(0.25, 0.25), options).unwrap_err();
        assert!(err.to_string().contains(field), "{json}: {err}");
    }
    let ok =
        RigOptions::from_json(r#"{"calibration": {"frames": 10, "minVisibility": 0.7}}"#).unwrap();
    assert_eq!(ok.calibration.frames, 10);
    assert!(Rig::new(skeleton(0.25, 0.25), ok).is_ok());
    let e = RigOptions::from_json(r#"{"calibration": {"frame": 10}}"#).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "options.calibration.frame: unknown option (did you mean calibration.frames?)"
        ),
        "{e}"
    );
}

fn finite(out: &SolveOutput) -> bool {
    out.local.iter().all(|q| q.is_finite()) && out.world.position.iter().all(|p| p.is_finite())
}

#[test]
fn rig_with_pose_only_missing_pose_and_hidden_wrists() {
    let skel = skeleton(0.25, 0.25);
    let mut rig = Rig::new(skel.clone(), RigOptions::per_frame()).unwrap();
    let mut out = SolveOutput::default();
    let mut frame = FrameInput::default();
    // Pose only (no hands): both arms reach their mapped wrists; pole from the elbows.
    let p = pose(0.28, 0.25);
    frame.pose = Some(p);
    rig.solve(&frame, &mut out).unwrap();
    assert!(finite(&out));
    let s = rig.body().scale();
    assert!((s - 0.5 / 0.53).abs() < 1e-5, "{s}");
    for side in Side::BOTH {
        let mapped = rig
            .body()
            .map_arm(&skel, side, &p, CameraMapping::default())
            .unwrap();
        let wrist = out.world.position[side.hand().index()];
        assert!((wrist - mapped.wrist).length() < 1e-4, "{side:?}");
        assert!(out.solved[side.arm()[1].index()] && out.solved[side.arm()[2].index()]);
        // No hand: nothing aligned, no IK target reported.
        assert!(out.alignment[side.index()].is_none());
    }
    // Missing pose: arms at their idle rest (`arm.idle`, down by the sides), every other
    // bone at rest, nothing solved.
    let idle = Side::BOTH.map(|s| {
        handrig::ik::idle_arm(&skel, s, handrig::ik::ArmIdle::Down).map(|q| rig.export_rotation(q))
    });
    let at_idle = |local: &[Quat; BONE_COUNT]| {
        (0..BONE_COUNT).all(|i| {
            let want = Side::BOTH
                .into_iter()
                .find_map(|s| {
                    let [_, upper, lower, _] = s.arm();
                    (i == upper.index())
                        .then_some(idle[s.index()][0])
                        .or((i == lower.index()).then_some(idle[s.index()][1]))
                })
                .unwrap_or(Quat::IDENTITY);
            local[i].dot(want).abs() > 1.0 - 1e-6
        })
    };
    frame.pose = None;
    rig.solve(&frame, &mut out).unwrap();
    assert!(finite(&out));
    assert!(at_idle(&out.local));
    assert!(
        idle[0][0].angle_between(Quat::IDENTITY) > 1.0,
        "down, not the T-pose"
    );
    assert!(!out.solved.iter().any(|s| *s));
    // Hidden left wrist: the left arm rests, the right arm is solved.
    let mut hidden = p;
    hidden.visibility[pl::LEFT_WRIST] = 0.1;
    frame.pose = Some(hidden);
    rig.solve(&frame, &mut out).unwrap();
    assert!(finite(&out));
    assert!(out.local[B::LeftUpperArm.index()].dot(idle[0][0]).abs() > 1.0 - 1e-6);
    assert!(!out.solved[B::LeftUpperArm.index()]);
    assert!(out.solved[B::RightUpperArm.index()]);
    // Everything hidden: no NaN, arms at their idle rest.
    let mut dark = p;
    dark.visibility = [0.0; POSE_LANDMARKS];
    frame.pose = Some(dark);
    rig.solve(&frame, &mut out).unwrap();
    assert!(finite(&out));
    assert!(at_idle(&out.local));
}
