//! The three arm solvers side by side (`armSolver`: twoBone, fabrik, ccd): FABRIK and CCD
//! agree with the analytic solver given the same pole; no elbow flip on a path of the hand
//! across the chest to the opposite shoulder and back; the shoulder option raises the
//! shoulder on far reaches only; the forearm takes its share of the hand's twist without
//! flipping.

// Native only: proptest and the shared files are not available on wasm32.

use crate::support::arms;
use crate::support::geometry;

use core::f32::consts::PI;

use arms::{arm_lengths, layouts, skeleton};
use geometry::{across, angle, dir};
use glam::{EulerRot, Quat, Vec3};
use handrig::humanoid::bones::{Side, BONE_COUNT};
use handrig::humanoid::skeleton::{Skeleton, VrmVersion, WorldPose};
use handrig::ik::{ArmOptions, ArmSolver, ArmSolverState, CcdOptions, FabrikOptions};
use proptest::prelude::*;

/// Arm options with the shoulder option off (the plain two-bone arm) or at its default; the
/// wrist limits off (these tests give hand rotations the solvers must reach as given; the
/// limits are tested in `tests/it/wrist_limits.rs`).
fn arm_options(shoulder: bool) -> ArmOptions {
    ArmOptions {
        shoulder_angle: if shoulder {
            ArmOptions::default().shoulder_angle
        } else {
            0.0
        },
        wrist_limits: false,
        ..ArmOptions::default()
    }
}

/// `solver` with `arm` options and an iteration budget large enough for FABRIK and CCD to
/// converge from rest in one solve (their defaults rely on the previous frame's warm start;
/// their convergence on the recordings is measured by `eval/rust/eval_alignment.rs`).
fn converged(skel: &Skeleton, solver: ArmSolver, arm: &ArmOptions) -> ArmSolverState {
    match solver {
        ArmSolver::Fabrik => ArmSolverState::with_fabrik(
            skel,
            FabrikOptions {
                iterations: 2000,
                ..FabrikOptions::default()
            },
            arm,
        ),
        ArmSolver::Ccd => ArmSolverState::with_ccd(
            skel,
            CcdOptions {
                iterations: 2000,
                ..CcdOptions::default()
            },
            arm,
        ),
        _ => ArmSolverState::with_options(skel, solver, arm),
    }
    .unwrap()
}

/// One solved arm measured by forward kinematics of the written rotations.
#[derive(Clone, Copy, Debug)]
struct Arm {
    shoulder_turn: Quat,
    upper_joint: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    hand_world: Quat,
    upper: Quat,
    lower: Quat,
    hand: Quat,
    reachable: bool,
}

/// Solves `side` toward `target` through [`ArmSolverState::solve`] (the rig's entry) with the
/// shoulder's local rotation `shoulder_rot` before the solve.
fn solve(
    state: &mut ArmSolverState,
    skel: &Skeleton,
    side: Side,
    shoulder_rot: Quat,
    target: Vec3,
    hand: Option<Quat>,
    pole: Option<Vec3>,
) -> Arm {
    let [sh, up, low, h] = side.arm();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    local[sh.index()] = shoulder_rot;
    let mut world = WorldPose::default();
    skel.forward(&local, &mut world);
    let to = handrig::ik::ArmTarget {
        target,
        hand_rotation: hand,
        pole,
        finger: None,
    };
    let reach = state.solve(side, &to, &mut local, &world);
    skel.forward(&local, &mut world);
    assert!(local.iter().all(|q| q.is_finite()), "non-finite rotation");
    Arm {
        shoulder_turn: shoulder_rot.inverse() * local[sh.index()],
        upper_joint: world.position[up.index()],
        elbow: world.position[low.index()],
        wrist: world.position[h.index()],
        hand_world: world.rotation[h.index()],
        upper: local[up.index()],
        lower: local[low.index()],
        hand: local[h.index()],
        reachable: reach.reachable,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Random reachable targets, poles off the target line, hand and shoulder rotations, on
    /// every layout and side, each solver fresh (from rest, with the budget to converge):
    /// FABRIK and CCD put the elbow and the wrist within 1 mm of the analytic solver's and
    /// every local rotation within 2 degrees.
    #[test]
    fn fabrik_and_ccd_agree_with_the_analytic_solver(
        layout in 0usize..7,
        left in any::<bool>(),
        t_theta in 0.0f32..(2.0 * PI), t_phi in 0.0f32..PI,
        frac in 0.05f32..0.95,
        p_theta in 0.0f32..(2.0 * PI), p_phi in 0.0f32..PI, p_dist in 0.05f32..1.0,
        h in prop::array::uniform3(-PI..PI),
        sh_rot in prop::array::uniform3(-0.3f32..0.3),
    ) {
        let skel = &layouts()[layout];
        let side = if left { Side::Left } else { Side::Right };
        let shoulder_rot = Quat::from_euler(EulerRot::XYZ, sh_rot[0], sh_rot[1], sh_rot[2]);
        let (a, b) = arm_lengths(skel, side);
        let mut analytic = ArmSolverState::with_options(skel, ArmSolver::TwoBone, &arm_options(false)).unwrap();
        let base = solve(&mut analytic, skel, side, shoulder_rot, Vec3::ZERO, None, None).upper_joint;
        let d = dir(t_theta, t_phi);
        let r = (a - b).abs() + frac * (a + b - (a - b).abs());
        let target = base + d * r;
        let pole = base + dir(p_theta, p_phi) * p_dist;
        prop_assume!(across(pole - base, d).length() / (pole - base).length() > 12f32.to_radians().sin());
        let hand = Quat::from_euler(EulerRot::YXZ, h[0], h[1], h[2]);
        let mut analytic = ArmSolverState::with_options(skel, ArmSolver::TwoBone, &arm_options(false)).unwrap();
        let reference = solve(&mut analytic, skel, side, shoulder_rot, target, Some(hand), Some(pole));
        // The forearm takes half of the hand's twist about it (`forearmTwist`), taken in
        // (-180, 180]: a twist at the half turn has two equally valid shares 180 degrees apart,
        // and solvers whose forearms differ by a hair may pick either. Skip that branch cut.
        let forearm = skel.rest_local(side.hand()).normalize();
        let share = handrig::math::twist_angle(reference.lower, forearm);
        prop_assume!((share.abs() - core::f32::consts::FRAC_PI_2).abs() > 2f32.to_radians());
        for solver in [ArmSolver::Fabrik, ArmSolver::Ccd] {
            let mut state = converged(skel, solver, &arm_options(false));
            let s = solve(&mut state, skel, side, shoulder_rot, target, Some(hand), Some(pole));
            prop_assert!((s.elbow - reference.elbow).length() < 1e-3, "{solver:?}: elbow {} m off", (s.elbow - reference.elbow).length());
            prop_assert!((s.wrist - reference.wrist).length() < 1e-3, "{solver:?}: wrist {} m off", (s.wrist - reference.wrist).length());
            for (name, x, y) in [("upper", s.upper, reference.upper), ("lower", s.lower, reference.lower), ("hand", s.hand, reference.hand)] {
                prop_assert!(angle(x, y) < 2f32.to_radians(), "{solver:?}: {name} {} deg off", angle(x, y).to_degrees());
            }
            prop_assert!(angle(s.hand_world, hand) < 1e-3);
            prop_assert_eq!(s.reachable, reference.reachable);
        }
    }
}

/// Largest frame-to-frame change (radians) of the elbow's swivel about the shoulder-to-wrist
/// line over a sequence of (upper arm joint, elbow, wrist), ignoring frames whose elbow is on
/// that line (a straight arm has no swivel).
fn largest_swivel_change(frames: &[(Vec3, Vec3, Vec3)]) -> f32 {
    let mut prev: Option<Vec3> = None;
    let mut worst = 0.0f32;
    for &(s, e, w) in frames {
        let axis = (w - s).normalize();
        let bend = across(e - s, axis);
        if bend.length() < 1e-3 {
            prev = None;
            continue;
        }
        let bend = bend.normalize();
        if let Some(p) = prev {
            let p = across(p, axis).normalize();
            worst = worst.max(axis.dot(p.cross(bend)).atan2(p.dot(bend)).abs());
        }
        prev = Some(bend);
    }
    worst
}

/// The hand from in front of the same side's chest across the chest to just in front of the
/// opposite shoulder and back, `n` frames each way, bowed forward so it clears the body.
fn across_the_chest(skel: &Skeleton, side: Side, n: usize) -> Vec<Vec3> {
    let s = skel.rest_world(side.arm()[1]).unwrap();
    let other = skel.rest_world(side.opposite().arm()[1]).unwrap();
    let (a, b) = arm_lengths(skel, side);
    let l = a + b;
    let out = if side == Side::Left { 1.0 } else { -1.0 };
    let start = s + l * Vec3::new(0.1 * out, -0.55, 0.35);
    let end = other + l * Vec3::new(0.0, -0.1, 0.22);
    let point = |t: f32| start.lerp(end, t) + Vec3::Z * (0.1 * l * (PI * t).sin());
    (0..=n)
        .chain((0..n).rev())
        .map(|i| point(i as f32 / n as f32))
        .collect()
}

#[test]
fn no_elbow_flip_across_the_chest_with_any_solver() {
    // Every layout, both sides, each solver, without a pole (the default pole) and with a
    // pose elbow that stays out and down: the largest swivel change per frame is printed;
    // it must stay far from a flip (half a turn) and shrink with finer sampling (a jump does
    // not).
    let mut report = Vec::new();
    for (k, skel) in layouts().iter().enumerate() {
        for side in Side::BOTH {
            let s = skel.rest_world(side.arm()[1]).unwrap();
            let (a, b) = arm_lengths(skel, side);
            let out = if side == Side::Left { 1.0 } else { -1.0 };
            let elbow_pole = s + (a + b) * Vec3::new(0.6 * out, -0.6, -0.1);
            for solver in ArmSolver::ALL {
                for pole in [None, Some(elbow_pole)] {
                    let mut worst = [0.0f32; 2];
                    for (j, n) in [60usize, 240].into_iter().enumerate() {
                        let mut state =
                            ArmSolverState::with_options(skel, solver, &ArmOptions::default())
                                .unwrap();
                        let frames: Vec<_> = across_the_chest(skel, side, n)
                            .into_iter()
                            .map(|t| {
                                let arm =
                                    solve(&mut state, skel, side, Quat::IDENTITY, t, None, pole);
                                assert!(arm.reachable, "layout {k} {side:?} {solver:?}: {t}");
                                assert!((arm.wrist - t).length() < 1e-4);
                                (arm.upper_joint, arm.elbow, arm.wrist)
                            })
                            .collect();
                        worst[j] = largest_swivel_change(&frames);
                    }
                    report.push((k, side, solver, pole.is_some(), worst));
                    assert!(
                        worst[0] < 20f32.to_radians(),
                        "layout {k} {side:?} {solver:?} pole {}: swivel jumped {} deg",
                        pole.is_some(),
                        worst[0].to_degrees()
                    );
                    assert!(
                        worst[1] < 0.5 * worst[0] + 1e-3,
                        "layout {k} {side:?} {solver:?}: change does not shrink: {worst:?}"
                    );
                }
            }
        }
    }
    for solver in ArmSolver::ALL {
        let worst = report
            .iter()
            .filter(|r| r.2 == solver)
            .map(|r| r.4[0])
            .fold(0.0f32, f32::max);
        println!(
            "{solver:?}: largest elbow swivel change per frame across the chest {:.2} deg (60 frames each way)",
            worst.to_degrees()
        );
    }
}

#[test]
fn far_reach_raises_the_shoulder_and_near_reach_does_not() {
    let max = ArmOptions::default().shoulder_angle;
    for skel in layouts() {
        for side in Side::BOTH {
            let s = skel.rest_world(side.arm()[1]).unwrap();
            let (a, b) = arm_lengths(skel, side);
            let l = a + b;
            let out = if side == Side::Left { 1.0 } else { -1.0 };
            for solver in ArmSolver::ALL {
                for d in [
                    Vec3::Y,
                    Vec3::Z,
                    Vec3::new(0.3 * out, 0.5, 0.8).normalize(),
                    Vec3::new(-0.5 * out, 0.0, 0.8).normalize(),
                ] {
                    // Comfortably within reach: the shoulder stays, and the arm is exactly the
                    // plain arm's.
                    let mut on = converged(skel, solver, &arm_options(true));
                    let mut off = converged(skel, solver, &arm_options(false));
                    let t = s + d * (0.7 * l);
                    let x = solve(&mut on, skel, side, Quat::IDENTITY, t, None, None);
                    let y = solve(&mut off, skel, side, Quat::IDENTITY, t, None, None);
                    assert!(
                        angle(x.shoulder_turn, Quat::IDENTITY) < 1e-5,
                        "{solver:?} {d}"
                    );
                    assert!((x.elbow - y.elbow).length() < 1e-4, "{solver:?} {d}");
                    // At the arm's full length: the shoulder turns (at most its limit) and the
                    // elbow keeps a bend instead of locking straight.
                    let t = s + d * l;
                    let x = solve(&mut on, skel, side, Quat::IDENTITY, t, None, None);
                    let turn = angle(x.shoulder_turn, Quat::IDENTITY);
                    assert!(
                        turn > 1f32.to_radians() && turn <= max + 1e-4,
                        "{solver:?} {d}: shoulder {turn}"
                    );
                    let bend = (x.elbow - x.upper_joint)
                        .normalize()
                        .angle_between((x.wrist - x.elbow).normalize());
                    assert!(
                        bend > 10f32.to_radians(),
                        "{solver:?} {d}: elbow bend {} deg",
                        bend.to_degrees()
                    );
                    assert!(
                        (x.wrist - t).length() < 1e-4,
                        "{solver:?} {d}: wrist {}",
                        (x.wrist - t).length()
                    );
                    // The shoulder moved the upper arm joint toward the target.
                    assert!((t - x.upper_joint).length() < l - 1e-3);
                }
            }
        }
    }
}

#[test]
fn forearm_takes_its_share_of_the_twist_without_flipping() {
    // The hand rocks about the forearm axis between -200 and +200 degrees of twist, twice,
    // the arm reaching forward: past a half turn and back, where a twist taken in (-180, 180]
    // would flip the forearm's share. The hand's world rotation is always the target, the
    // forearm turns about its own axis by half the twist (the default share), continuously.
    let skel = skeleton(Vec3::X * 0.28, Vec3::X * 0.25, VrmVersion::V1);
    let side = Side::Left;
    let s = skel.rest_world(side.arm()[1]).unwrap();
    let target = s + Vec3::new(0.2, -0.2, 0.3);
    let share = ArmOptions::default().forearm_twist;
    for solver in ArmSolver::ALL {
        let mut state = ArmSolverState::new(&skel, solver).unwrap();
        let first = solve(&mut state, &skel, side, Quat::IDENTITY, target, None, None);
        let forearm = (first.wrist - first.elbow).normalize();
        let lower_world = first.upper * first.lower; // the forearm's swing only
        let mut prev: Option<Quat> = None;
        let mut worst = 0.0f32;
        for i in 0..=720 {
            let twist = 200f32.to_radians() * (2.0 * PI * i as f32 / 360.0).sin();
            let hand = Quat::from_axis_angle(forearm, twist) * lower_world;
            let arm = solve(
                &mut state,
                &skel,
                side,
                Quat::IDENTITY,
                target,
                Some(hand),
                None,
            );
            assert!(angle(arm.hand_world, hand) < 1e-4, "{solver:?}");
            if let Some(p) = prev {
                worst = worst.max(angle(p, arm.lower));
            }
            prev = Some(arm.lower);
            // The forearm's own turn: `share` of the twist, on the branch it came from.
            let own = arm.lower * first.lower.conjugate();
            let upper_world = first.upper;
            let turned = (upper_world * own * upper_world.conjugate()).to_axis_angle();
            let signed = turned.1 * turned.0.dot(forearm).signum();
            let expect = share * twist;
            let diff = (signed - expect + PI).rem_euclid(2.0 * PI) - PI;
            assert!(
                diff.abs() < 1e-3,
                "{solver:?} frame {i}: forearm {signed} for twist {twist}"
            );
        }
        // 3.5 degrees of twist per frame at most: the forearm turns at most 1.75 per frame.
        assert!(
            worst < 2f32.to_radians(),
            "{solver:?}: forearm jumped {} deg",
            worst.to_degrees()
        );
    }
}

#[test]
fn odd_avatars_give_finite_poses_or_clear_errors() {
    // Wrist targets 1e20 m away on the robot (`../shared/repro/huge-scale-robot.vrm` put such
    // numbers in the rest pose; that file is now refused at load, see tests/it/vrm.rs) and
    // `../shared/avatars/odd-armature-vrm0.vrm` (17 bones, off the T-pose). Every solver
    // solves wrist-target frames without a panic and without NaN.
    let wrists = [
        Vec3::new(1.16e19, 1.51e20, 1.75e19),
        Vec3::new(-4.36e18, 1.17e20, 3.0e18),
    ];
    let odd = arms::recordings::vrm("../shared/avatars/odd-armature-vrm0.vrm");
    let odd_wrists = Side::BOTH.map(|s| {
        let sh = odd.rest_world(s.arm()[1]).unwrap();
        odd.version()
            .position_to_internal(sh + Vec3::new(0.0, -0.2, 0.25))
    });
    let cases = [
        (
            arms::recordings::vrm(arms::recordings::ROBOT),
            wrists,
            false,
        ),
        (odd, odd_wrists, true),
    ];
    for (skel, wrists, must_solve) in cases {
        for solver in ArmSolver::ALL {
            for (side, wrist) in Side::BOTH.into_iter().zip(wrists) {
                let mut options = handrig::RigOptions {
                    arm_solver: solver,
                    ..handrig::RigOptions::default()
                };
                // The arm alone reaches the given wrist: no body collider moves it.
                options.contact.enabled = false;
                let mut rig = match handrig::Rig::new(skel.clone(), options) {
                    Ok(rig) => rig,
                    Err(e) => {
                        assert!(!must_solve && e.to_string().contains("restPose"), "{e}");
                        continue;
                    }
                };
                let mut frame = handrig::FrameInput::default();
                frame.wrists[side.index()] = Some(handrig::mediapipe::WristObservation {
                    position: wrist,
                    rotation: None,
                });
                let mut out = handrig::SolveOutput::default();
                let solved = rig.solve(&frame, &mut out);
                out.turn_to_internal_frame(rig.skeleton().version());
                assert!(
                    solved.is_ok() || !must_solve,
                    "{solver:?} {side:?}: {solved:?}"
                );
                assert!(
                    out.local.iter().all(|q| q.is_finite()),
                    "{solver:?} {side:?}: non-finite rotation"
                );
                if must_solve {
                    let hand = out.world.position[side.hand().index()];
                    let target = skel.version().position_to_internal(wrist);
                    assert!((hand - target).length() < 1e-3, "{solver:?} {side:?}");
                }
            }
        }
    }
}
