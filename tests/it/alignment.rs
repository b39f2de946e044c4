//! Fingertip alignment through the whole pipeline on synthetic data with known answers: after
//! solving, the avatar's index distal (forward kinematics of the returned rotations) is on
//! the target DIP with every arm solver; weight 0 and disabled alignment put the wrist on the pose wrist; tip mode
//! puts the extended distal bone on the target tip; no one-frame lag.
// Native only: reads ../shared from disk and uses proptest (not built for wasm32).

use crate::support::recordings;
use crate::support::rigs;

use glam::{EulerRot, Quat, Vec3};
use handrig::align::{AlignPoint, TIP_RATIO};
use handrig::humanoid::bones::{Finger, HumanBone as B, Side};
use handrig::ik::ArmSolver;
use handrig::mediapipe::{FrameInput, Handedness, WristObservation, HAND_LANDMARKS};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput, VrmVersion};
use recordings::{frame_of, hand};

/// Left-side rest positions (VRM 1.0 frame) of a human-proportioned T-pose avatar: upper arm
/// 0.28 m, forearm 0.25 m, wrist to index DIP about 0.165 m. The right side mirrors it.
const LEFT: [(B, [f32; 3]); 19] = [
    (B::LeftShoulder, [0.03, 1.42, 0.0]),
    (B::LeftUpperArm, [0.17, 1.42, 0.0]),
    (B::LeftLowerArm, [0.45, 1.42, 0.0]),
    (B::LeftHand, [0.70, 1.42, 0.0]),
    (B::LeftThumbMetacarpal, [0.72, 1.41, 0.025]),
    (B::LeftThumbProximal, [0.755, 1.40, 0.05]),
    (B::LeftThumbDistal, [0.785, 1.395, 0.065]),
    (B::LeftIndexProximal, [0.795, 1.42, 0.03]),
    (B::LeftIndexIntermediate, [0.84, 1.42, 0.03]),
    (B::LeftIndexDistal, [0.865, 1.42, 0.03]),
    (B::LeftMiddleProximal, [0.80, 1.42, 0.008]),
    (B::LeftMiddleIntermediate, [0.85, 1.42, 0.008]),
    (B::LeftMiddleDistal, [0.878, 1.42, 0.008]),
    (B::LeftRingProximal, [0.795, 1.42, -0.012]),
    (B::LeftRingIntermediate, [0.84, 1.42, -0.012]),
    (B::LeftRingDistal, [0.866, 1.42, -0.012]),
    (B::LeftLittleProximal, [0.785, 1.42, -0.03]),
    (B::LeftLittleIntermediate, [0.82, 1.42, -0.03]),
    (B::LeftLittleDistal, [0.84, 1.42, -0.03]),
];

/// The avatar, given in the model's own frame of `version`.
fn avatar(version: VrmVersion) -> Skeleton {
    let torso = [
        (B::Hips, 0.95),
        (B::Spine, 1.05),
        (B::Chest, 1.2),
        (B::UpperChest, 1.32),
        (B::Neck, 1.45),
        (B::Head, 1.55),
    ];
    let legs = rigs::Legs {
        x: 0.09,
        heights: [0.9, 0.5, 0.08],
    };
    let left = LEFT.map(|(b, p)| (b, Vec3::from(p)));
    rigs::skeleton(&rigs::t_pose(&torso, legs, &left), version)
}

/// 21 MediaPipe world landmarks (camera axes, un-mirrored image) of a user hand shaped like
/// the avatar's `side` hand at rest, `size` times larger, turned by `rotation` (avatar frame).
fn user_hand(skel: &Skeleton, side: Side, size: f32, rotation: Quat) -> [Vec3; HAND_LANDMARKS] {
    let wrist = skel.rest_world(side.hand()).unwrap();
    let mut lm = [Vec3::ZERO; HAND_LANDMARKS];
    for f in Finger::ALL {
        let [b0, b1, b2] = side.finger(f);
        let p = |b: B| skel.rest_world(b).unwrap();
        let tip = p(b2) + (p(b2) - p(b1)) * TIP_RATIO[f.index()];
        for (k, q) in [p(b0), p(b1), p(b2), tip].into_iter().enumerate() {
            lm[f.landmarks()[k]] = q;
        }
    }
    lm[0] = wrist;
    // MediaPipe's origin is near the hand's center, not the wrist.
    let origin = Vec3::new(0.01, -0.02, 0.03);
    lm.map(|q| {
        let a = rotation * ((q - wrist) * size) + origin;
        // Avatar frame -> camera axes for an un-mirrored image: (x, -y, -z).
        Vec3::new(a.x, -a.y, -a.z)
    })
}

/// MediaPipe labels an un-mirrored image's hands the opposite way.
fn label_for(side: Side) -> Handedness {
    match side {
        Side::Left => Handedness::Right,
        Side::Right => Handedness::Left,
    }
}

fn frame(skel: &Skeleton, side: Side, rotation: Quat, wrist_model: Vec3) -> FrameInput {
    // Centered on the hand, as MediaPipe's world landmarks are (handrig reads only their
    // offsets; a hand placed where the avatar's is would read as image landmarks given as world
    // ones when its wrist has z = 0).
    let mut points = user_hand(skel, side, 1.25, rotation);
    let center = points.iter().copied().sum::<Vec3>() / points.len() as f32;
    points.iter_mut().for_each(|p| *p -= center);
    let mut f = frame_of(&[hand(label_for(side), 0.95, points)]);
    f.wrists[side.index()] = Some(WristObservation {
        position: wrist_model,
        rotation: None,
    });
    f
}

fn options(json: &str) -> RigOptions {
    RigOptions::from_json(json).unwrap()
}

/// A reachable pose wrist in front of the avatar (model frame), for `side`.
fn reachable_wrist(skel: &Skeleton, side: Side) -> Vec3 {
    let sh = skel.rest_world(side.arm()[1]).unwrap();
    let out = if side == Side::Left { 1.0 } else { -1.0 };
    let internal = sh + Vec3::new(0.05 * out, -0.2, 0.28);
    skel.version().position_to_internal(internal)
}

fn hand_turns() -> [Quat; 4] {
    [
        Quat::IDENTITY,
        Quat::from_euler(EulerRot::YXZ, 0.6, -0.3, 0.9),
        Quat::from_euler(EulerRot::YXZ, -1.2, 0.5, -0.4),
        Quat::from_euler(EulerRot::ZXY, 2.0, 0.2, 0.1),
    ]
}

/// The synthetic avatar in both versions, and the real files: the shared robot, the
/// human-proportioned VRM 1.0 fixture and the VRM 0.x fixture with fingers.
fn avatars() -> Vec<Skeleton> {
    let mut all = vec![avatar(VrmVersion::V1), avatar(VrmVersion::V0)];
    all.extend(recordings::real_avatars());
    all
}

#[test]
fn index_distal_lands_on_the_target_dip() {
    for (skel, solver) in avatars()
        .into_iter()
        .flat_map(|s| ArmSolver::ALL.map(|a| (s.clone(), a)))
    {
        let version = skel.version();
        for side in Side::BOTH {
            let options = RigOptions {
                arm_solver: solver,
                ..RigOptions::per_frame()
            };
            let mut rig = Rig::new(skel.clone(), options).unwrap();
            let mut out = SolveOutput::default();
            for r in hand_turns() {
                let wrist = reachable_wrist(&skel, side);
                let f = frame(&skel, side, r, wrist);
                rig.solve(&f, &mut out).unwrap();
                out.turn_to_internal_frame(rig.skeleton().version());
                let report = out.alignment[side.index()].expect("aligned");
                assert!(report.reachable && report.aligned);
                // The target DIP is the pose wrist plus the user's wrist-to-DIP offset (s = 1).
                let lm = f.hands[0].world;
                let offset = Vec3::new(lm[7].x - lm[0].x, lm[0].y - lm[7].y, lm[0].z - lm[7].z);
                let pose_wrist = version.position_to_internal(wrist);
                assert!((report.target_dip - (pose_wrist + offset)).length() < 1e-5);
                // Forward kinematics of the returned rotations: the distal is on the target.
                let distal = out.world.position[side.finger(Finger::Index)[2].index()];
                let err = (distal - report.target_dip).length();
                assert!(
                    err < 1e-4,
                    "{version:?} {side:?} {solver:?}: distal {err} m from the target"
                );
                assert!(report.error < 1e-4);
                // The hand's world rotation is the IK target rotation.
                let target = out.ik_targets[side.index()].unwrap();
                let hand = out.world.rotation[side.hand().index()];
                assert!(hand.dot(target.rotation).abs() > 1.0 - 1e-6);
                assert!(
                    (out.world.position[side.hand().index()] - target.position).length() < 1e-4
                );
                // The user's hand is 25% larger: without alignment the distal would be off by
                // about a quarter of the avatar's wrist-to-DIP length.
                assert!((pose_wrist - target.position).length() > 0.03);
            }
        }
    }
}

#[test]
fn weight_zero_and_disabled_use_the_pose_wrist() {
    let skel = avatar(VrmVersion::V1);
    let side = Side::Right;
    let wrist = reachable_wrist(&skel, side);
    for json in [
        r#"{"alignment": {"weight": 0}}"#,
        r#"{"alignment": {"enabled": false}}"#,
        r#"{"alignment": {"enabled": false, "weight": 0.7}}"#,
    ] {
        let mut rig = Rig::new(skel.clone(), options(json)).unwrap();
        let mut out = SolveOutput::default();
        let r = hand_turns()[1];
        rig.solve(&frame(&skel, side, r, wrist), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let target = out.ik_targets[side.index()].unwrap();
        assert!((target.position - wrist).length() < 1e-6, "{json}");
        assert!((out.world.position[side.hand().index()] - wrist).length() < 1e-4);
        // The report still says how far off the finger is (the cost of not aligning).
        let report = out.alignment[side.index()].unwrap();
        assert!(report.error > 0.03, "{json}: {}", report.error);
    }
    // Half weight: halfway between the pose wrist and the fully aligned wrist, for the same
    // hand rotation (the wrist limits, which turn the hand about a point that depends on the
    // weight, off).
    let mut full = Rig::new(skel.clone(), options(r#"{"arm": {"wristLimits": false}}"#)).unwrap();
    let mut half = Rig::new(
        skel.clone(),
        options(r#"{"alignment": {"weight": 0.5}, "arm": {"wristLimits": false}}"#),
    )
    .unwrap();
    let (mut a, mut b) = (SolveOutput::default(), SolveOutput::default());
    let f = frame(&skel, side, hand_turns()[2], wrist);
    full.solve(&f, &mut a).unwrap();
    a.turn_to_internal_frame(full.skeleton().version());
    half.solve(&f, &mut b).unwrap();
    b.turn_to_internal_frame(half.skeleton().version());
    let mid = 0.5 * (wrist + a.ik_targets[1].unwrap().position);
    assert!((b.ik_targets[1].unwrap().position - mid).length() < 1e-5);
}

#[test]
fn tip_mode_puts_the_extended_distal_on_the_target_tip() {
    let skel = avatar(VrmVersion::V1);
    let side = Side::Left;
    let mut rig = Rig::new(skel.clone(), options(r#"{"alignment": {"point": "tip"}}"#)).unwrap();
    assert_eq!(rig.options().alignment.point, AlignPoint::Tip);
    let mut out = SolveOutput::default();
    let wrist = reachable_wrist(&skel, side);
    let f = frame(&skel, side, hand_turns()[3], wrist);
    rig.solve(&f, &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    let report = out.alignment[side.index()].unwrap();
    let lm = f.hands[0].world;
    let tip_offset = Vec3::new(lm[8].x - lm[0].x, lm[0].y - lm[8].y, lm[0].z - lm[8].z);
    assert!((report.target_dip - (wrist + tip_offset)).length() < 1e-5);
    // The avatar's tip: the distal bone extended by TIP_RATIO of the intermediate segment.
    let [_, _, distal] = side.finger(Finger::Index);
    let tip = out.world.position[distal.index()]
        + out.world.rotation[distal.index()] * (skel.rest_local(distal) * TIP_RATIO[1]);
    assert!((tip - report.target_dip).length() < 1e-4);
    // ... which is not where the distal joint is.
    assert!((out.world.position[distal.index()] - report.target_dip).length() > 0.01);
}

#[test]
fn other_fingers_and_mirroring() {
    let skel = avatar(VrmVersion::V1);
    // Thumb: its distal (IP joint) on the user's IP.
    let mut rig = Rig::new(
        skel.clone(),
        options(r#"{"alignment": {"finger": "thumb"}}"#),
    )
    .unwrap();
    let mut out = SolveOutput::default();
    let side = Side::Right;
    rig.solve(
        &frame(&skel, side, hand_turns()[1], reachable_wrist(&skel, side)),
        &mut out,
    )
    .unwrap();
    let report = out.alignment[1].unwrap();
    let thumb = out.world.position[B::RightThumbDistal.index()];
    assert!((thumb - report.target_dip).length() < 1e-4);
    // mirror: the user's right hand (labelled "Left" un-mirrored) drives the avatar's left,
    // reflected; the wrist given for the avatar's left.
    let mut rig = Rig::new(skel.clone(), options(r#"{"mirror": true}"#)).unwrap();
    let mut f = frame(&skel, Side::Right, hand_turns()[2], Vec3::ZERO);
    f.wrists = [None, None];
    let wrist = reachable_wrist(&skel, Side::Left);
    f.wrists[Side::Left.index()] = Some(WristObservation {
        position: wrist,
        rotation: None,
    });
    rig.solve(&f, &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    assert!(out.alignment[1].is_none());
    let report = out.alignment[0].expect("left side aligned");
    let distal = out.world.position[B::LeftIndexDistal.index()];
    assert!(report.reachable && (distal - report.target_dip).length() < 1e-4);
}

#[test]
fn no_one_frame_lag() {
    // The hand turns a lot between two frames; the avatar vector comes from this frame's
    // hand rotation (and finger rotations), so the second frame is as exact as the first.
    // (The turns are faster than `arm.maxTurnSpeed`, which would show them over a few frames:
    // this is about the solve, so the limit is off.)
    let skel = avatar(VrmVersion::V1);
    let side = Side::Left;
    let mut options = RigOptions::default();
    options.arm.max_turn_speed = 0.0;
    let mut rig = Rig::new(skel.clone(), options).unwrap();
    let mut out = SolveOutput::default();
    let wrist = reachable_wrist(&skel, side);
    for r in [hand_turns()[1], hand_turns()[2], hand_turns()[3]] {
        rig.solve(&frame(&skel, side, r, wrist), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let report = out.alignment[0].unwrap();
        let distal = out.world.position[B::LeftIndexDistal.index()];
        assert!((distal - report.target_dip).length() < 1e-4);
    }
}

#[test]
fn unreachable_target_reports_and_stays_finite() {
    let skel = avatar(VrmVersion::V1);
    let side = Side::Right;
    let mut rig = Rig::new(skel.clone(), RigOptions::default()).unwrap();
    let mut out = SolveOutput::default();
    let far = skel.rest_world(side.arm()[1]).unwrap() + Vec3::new(-0.2, 0.1, 1.5);
    rig.solve(&frame(&skel, side, hand_turns()[1], far), &mut out)
        .unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    let report = out.alignment[1].unwrap();
    assert!(!report.reachable);
    assert!(report.error.is_finite() && report.error > 0.5);
    assert!(out.local.iter().all(|q| q.is_finite()));
    assert!(out.world.position.iter().all(|p| p.is_finite()));
    // Straight arm: elbow on the shoulder-wrist line.
    let sh = out.world.position[B::RightUpperArm.index()];
    let el = out.world.position[B::RightLowerArm.index()];
    let wr = out.world.position[B::RightHand.index()];
    let d = (wr - sh).normalize();
    assert!(((el - sh) - d * d.dot(el - sh)).length() < 1e-4);
}
