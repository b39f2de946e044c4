//! Two-bone arm IK: unit tests with known answers, property tests over random reachable
//! targets on several rest layouts, unreachable and degenerate goals, and elbow continuity
//! when the target or the pole passes the shoulder's pole axis.

// Native only: proptest and the shared files are not available on wasm32.

use crate::support::arms;
use crate::support::geometry;

use core::f32::consts::{FRAC_PI_2, PI};

use arms::{arm_lengths as lengths, layouts, skeleton};
use geometry::{across, dir};
use glam::{Quat, Vec3};
use handrig::humanoid::bones::{HumanBone as B, Side, BONE_COUNT};
use handrig::humanoid::skeleton::{Skeleton, VrmVersion, WorldPose};
use handrig::ik::{
    swing, ArmChain, ArmGoal, ArmIk, ArmOptions, ArmPose, ArmSolver, ArmSolverState, TwoBoneIk,
    TwoBoneOptions,
};
use proptest::prelude::*;

/// The analytic solver with the shoulder option and the wrist limits off: these tests check
/// the two-bone geometry from a fixed upper arm joint with the hand rotation as given (the
/// shoulder option is tested in `tests/it/arm_solvers.rs`, the wrist limits in
/// `tests/it/wrist_limits.rs`).
fn two_bone(skel: &Skeleton) -> ArmSolverState {
    let arm = ArmOptions {
        shoulder_angle: 0.0,
        wrist_limits: false,
        ..ArmOptions::default()
    };
    ArmSolverState::with_options(skel, ArmSolver::TwoBone, &arm).unwrap()
}

struct Solved {
    shoulder: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    hand_world: Quat,
    reach: handrig::ik::ArmReach,
    local: [Quat; BONE_COUNT],
}

/// Solves through the public pipeline entry ([`ArmSolverState::solve`]) and measures the
/// result by forward kinematics of the written local rotations.
fn solve_fk(
    state: &mut ArmSolverState,
    skel: &Skeleton,
    side: Side,
    shoulder_rot: Quat,
    target: Vec3,
    hand: Option<Quat>,
    pole: Option<Vec3>,
) -> Solved {
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    local[side.arm()[0].index()] = shoulder_rot;
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
    let [_, up, low, h] = side.arm();
    for q in local.iter() {
        assert!(q.is_finite(), "non-finite rotation {q}");
    }
    Solved {
        shoulder: world.position[up.index()],
        elbow: world.position[low.index()],
        wrist: world.position[h.index()],
        hand_world: world.rotation[h.index()],
        reach,
        local,
    }
}

fn quat_close(a: Quat, b: Quat, tol: f32) -> bool {
    a.dot(b).abs() > 1.0 - tol
}

#[test]
fn known_answer_right_angle_elbow() {
    // Left arm along +X, 0.25 + 0.25, pole on the +X side of a target straight ahead.
    let skel = skeleton(Vec3::X * 0.25, Vec3::X * 0.25, VrmVersion::V1);
    let mut state = two_bone(&skel);
    let sh = skel.rest_world(B::LeftUpperArm).unwrap();
    // Target at distance 0.25*sqrt(2) along +Z: isoceles right triangle, elbow angle 90deg,
    // the elbow 45 degrees off the line toward the pole (+X).
    let target = sh + Vec3::Z * 0.25 * 2f32.sqrt();
    let pole = sh + Vec3::new(1.0, 0.0, 0.5);
    let s = solve_fk(
        &mut state,
        &skel,
        Side::Left,
        Quat::IDENTITY,
        target,
        None,
        Some(pole),
    );
    let expected_elbow = sh + Vec3::new(0.25 / 2f32.sqrt(), 0.0, 0.25 / 2f32.sqrt());
    assert!((s.elbow - expected_elbow).length() < 1e-5, "{}", s.elbow);
    assert!((s.wrist - target).length() < 1e-5);
    assert!(s.reach.reachable && s.reach.residual < 1e-5);
    // Minimal twist: the upper arm's rotation is a pure swing about Y (no component along
    // the bone), here -45 degrees about +Y taking +X to (+X+Z)/sqrt2.
    let up = s.local[B::LeftUpperArm.index()];
    assert!(
        quat_close(up, Quat::from_rotation_y(-PI / 4.0), 1e-6),
        "{up}"
    );
    let low = s.local[B::LeftLowerArm.index()];
    assert!(
        quat_close(low, Quat::from_rotation_y(-FRAC_PI_2), 1e-6),
        "{low}"
    );
}

#[test]
fn hand_world_rotation_is_the_target_rotation() {
    let skel = &layouts()[1];
    let mut state = two_bone(skel);
    let sh = skel.rest_world(B::RightUpperArm).unwrap();
    let q = Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.4, 1.9);
    let s = solve_fk(
        &mut state,
        skel,
        Side::Right,
        Quat::from_rotation_z(0.2),
        sh + Vec3::new(0.1, -0.2, 0.3),
        Some(q),
        None,
    );
    assert!(quat_close(s.hand_world, q, 1e-6), "{} vs {q}", s.hand_world);
    // Without a hand rotation the hand's local rotation stays identity.
    let s = solve_fk(
        &mut state,
        skel,
        Side::Right,
        Quat::IDENTITY,
        sh + Vec3::new(0.1, -0.2, 0.3),
        None,
        None,
    );
    assert_eq!(s.local[B::RightHand.index()], Quat::IDENTITY);
}

#[test]
fn default_pole_hangs_the_elbow_down_and_back() {
    let skel = &layouts()[0];
    for side in Side::BOTH {
        let mut state = two_bone(skel);
        let sh = skel.rest_world(side.arm()[1]).unwrap();
        // Reaching forward with a bent arm: the elbow hangs below the shoulder-wrist line.
        let t = sh + Vec3::new(0.0, 0.0, 0.35);
        let s = solve_fk(&mut state, skel, side, Quat::IDENTITY, t, None, None);
        let off = across(s.elbow - sh, Vec3::Z);
        assert!(off.y < -0.1 && off.x.abs() < 1e-4, "{side:?} {off}");
        // Hand lowered in front of the belly: the elbow goes back (and down).
        let t = sh + Vec3::new(0.0, -0.35, 0.0);
        let s = solve_fk(&mut state, skel, side, Quat::IDENTITY, t, None, None);
        let off = across(s.elbow - sh, Vec3::NEG_Y);
        assert!(off.z < -0.1, "{side:?} {off}");
    }
}

#[test]
fn unreachable_target_stretches_the_arm_toward_it() {
    for skel in layouts() {
        for side in Side::BOTH {
            let mut state = two_bone(skel);
            let (a, b) = lengths(skel, side);
            let sh = skel.rest_world(side.arm()[1]).unwrap();
            let d = Vec3::new(0.3, -0.5, 0.8).normalize();
            let target = sh + d * 2.0 * (a + b);
            let s = solve_fk(&mut state, skel, side, Quat::IDENTITY, target, None, None);
            assert!(!s.reach.reachable);
            assert!(
                (s.reach.residual - (a + b)).abs() < 1e-4,
                "{}",
                s.reach.residual
            );
            // Straight: elbow and wrist on the shoulder-target line.
            let off = across(s.elbow - sh, d).length();
            assert!(off < 1e-5, "{side:?}: elbow {off} m off the line");
            assert!((s.wrist - (sh + d * (a + b))).length() < 1e-5);
        }
    }
}

#[test]
fn too_close_target_folds_and_reports() {
    let skel = &layouts()[2]; // 0.30 + 0.22: targets nearer than 0.08 m are out of reach
    let mut state = two_bone(skel);
    let sh = skel.rest_world(B::LeftUpperArm).unwrap();
    let (a, b) = lengths(skel, Side::Left);
    let target = sh + Vec3::new(0.0, 0.0, 0.03);
    let s = solve_fk(
        &mut state,
        skel,
        Side::Left,
        Quat::IDENTITY,
        target,
        None,
        None,
    );
    assert!(!s.reach.reachable);
    let folded = (a - b).abs();
    assert!(
        (s.reach.residual - (folded - 0.03)).abs() < 1e-4,
        "{}",
        s.reach.residual
    );
}

#[test]
fn degenerate_goals_give_finite_poses() {
    for skel in layouts() {
        let mut state = two_bone(skel);
        let sh = skel.rest_world(B::LeftUpperArm).unwrap();
        // Target exactly at the shoulder, pole at the shoulder, pole at the target.
        for (t, p) in [
            (sh, None),
            (sh, Some(sh)),
            (sh + Vec3::Z * 0.3, Some(sh + Vec3::Z * 0.3)),
            (sh + Vec3::Z * 0.3, Some(sh + Vec3::Z * 0.6)),
        ] {
            let s = solve_fk(&mut state, skel, Side::Left, Quat::IDENTITY, t, None, p);
            assert!(s.reach.residual.is_finite() && s.elbow.is_finite() && s.wrist.is_finite());
        }
    }
    // Zero-length bones: the elbow on the shoulder, or the wrist on the elbow, or both.
    for (u, l) in [
        (Vec3::ZERO, Vec3::X * 0.25),
        (Vec3::X * 0.25, Vec3::ZERO),
        (Vec3::ZERO, Vec3::ZERO),
    ] {
        let skel = skeleton(u, l, VrmVersion::V1);
        let mut state = two_bone(&skel);
        let sh = skel.rest_world(B::LeftUpperArm).unwrap();
        let q = Quat::from_rotation_x(0.5);
        for t in [sh, sh + Vec3::new(0.0, -0.25, 0.0), sh + Vec3::Z] {
            let s = solve_fk(
                &mut state,
                &skel,
                Side::Left,
                Quat::IDENTITY,
                t,
                Some(q),
                None,
            );
            assert!(s.reach.residual.is_finite());
            assert!(quat_close(s.hand_world, q, 1e-6));
        }
        // A single non-zero bone of length 0.25 reaches exactly the sphere of radius 0.25.
        if u != l {
            let t = sh + Vec3::new(0.0, -0.25, 0.0);
            let s = solve_fk(&mut state, &skel, Side::Left, Quat::IDENTITY, t, None, None);
            assert!(
                s.reach.reachable && s.reach.residual < 1e-5,
                "{:?}",
                s.reach
            );
        }
    }
}

#[test]
fn swing_is_minimal_and_handles_opposites() {
    let a = Vec3::new(0.3, 0.4, -0.2).normalize();
    let b = Vec3::new(-0.5, 0.1, 0.7).normalize();
    let q = swing(a, b, Vec3::Y);
    assert!((q * a - b).length() < 1e-6);
    // A swing's axis is perpendicular to both vectors: no twist about either.
    let axis = Vec3::new(q.x, q.y, q.z);
    assert!(axis.dot(a).abs() < 1e-6 && axis.dot(b).abs() < 1e-6);
    // Opposite vectors: half a turn about the fallback axis (made perpendicular).
    let q = swing(Vec3::X, Vec3::NEG_X, Vec3::new(0.3, 1.0, 0.0));
    assert!((q * Vec3::X - Vec3::NEG_X).length() < 1e-6);
    assert!(
        (q * Vec3::Z - Vec3::NEG_Z).length() < 1e-6,
        "{}",
        q * Vec3::Z
    );
    assert!((q * Vec3::Y - Vec3::Y).length() < 1e-6, "{}", q * Vec3::Y);
    // Nearly opposite: still accurate.
    let near = Quat::from_rotation_z(PI - 1e-3) * Vec3::X;
    let q = swing(Vec3::X, near, Vec3::Y);
    assert!((q * Vec3::X - near).length() < 1e-5);
}

#[test]
fn options_are_validated() {
    let bad = TwoBoneOptions {
        collinear_cone: 2.0,
        ..TwoBoneOptions::default()
    };
    assert!(TwoBoneIk::new(bad).is_err());
    let bad = TwoBoneOptions {
        default_pole: Vec3::ZERO,
        ..TwoBoneOptions::default()
    };
    let err = TwoBoneIk::new(bad).unwrap_err();
    assert!(err.to_string().contains("defaultPole"), "{err}");
    let d = TwoBoneOptions::default();
    assert!((d.default_pole.length() - 1.0).abs() < 1e-6 && d.default_pole.y < -0.9);
    assert!(d.default_pole.z < 0.0 && d.default_pole.x == 0.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Random reachable targets, random poles off the target line, random hand rotations and
    /// shoulder rotations, on every layout and both sides: the wrist lands on the target
    /// (1e-4 m), bone lengths are kept, the elbow is exactly on the pole's side, and the
    /// hand's world rotation is the target rotation.
    #[test]
    fn random_reachable_targets(
        layout in 0usize..7,
        left in any::<bool>(),
        t_theta in 0.0f32..(2.0 * PI), t_phi in 0.0f32..PI,
        frac in 0.02f32..0.98,
        p_theta in 0.0f32..(2.0 * PI), p_phi in 0.0f32..PI, p_dist in 0.05f32..1.0,
        h in prop::array::uniform4(-1.0f32..1.0),
        sh_rot in prop::array::uniform3(-0.4f32..0.4),
        warm in any::<bool>(),
    ) {
        let skel = &layouts()[layout];
        let side = if left { Side::Left } else { Side::Right };
        let mut state = two_bone(skel);
        let shoulder_rot = Quat::from_euler(glam::EulerRot::XYZ, sh_rot[0], sh_rot[1], sh_rot[2]);
        let (a, b) = lengths(skel, side);
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        local[side.arm()[0].index()] = shoulder_rot;
        let mut world = WorldPose::default();
        skel.forward(&local, &mut world);
        let sh = world.position[side.arm()[1].index()];
        let d = dir(t_theta, t_phi);
        let r = (a - b).abs() + frac * (a + b - (a - b).abs());
        let target = sh + d * r;
        let pole = sh + dir(p_theta, p_phi) * p_dist;
        // Poles within the collinear cone (10 degrees) deliberately do not decide the side.
        let pole_off = across(pole - sh, d);
        prop_assume!(pole_off.length() / (pole - sh).length() > 12f32.to_radians().sin());
        let hq = Quat::from_xyzw(h[0], h[1], h[2], h[3]);
        prop_assume!(hq.length() > 0.1);
        let hq = hq.normalize();
        if warm {
            // History must not matter outside the cones.
            let _ = solve_fk(&mut state, skel, side, shoulder_rot, sh - d * r, None, None);
        }
        let s = solve_fk(&mut state, skel, side, shoulder_rot, target, Some(hq), Some(pole));
        prop_assert!(s.reach.reachable);
        prop_assert!((s.wrist - target).length() < 1e-4, "wrist off by {}", (s.wrist - target).length());
        prop_assert!(s.reach.residual < 1e-4);
        prop_assert!(((s.elbow - s.shoulder).length() - a).abs() < 1e-5);
        prop_assert!(((s.wrist - s.elbow).length() - b).abs() < 1e-5);
        let elbow_off = across(s.elbow - sh, d);
        if elbow_off.length() > 1e-3 {
            let cos = elbow_off.normalize().dot(pole_off.normalize());
            prop_assert!(cos > 1.0 - 1e-5, "elbow not on the pole side: cos {cos}");
        }
        prop_assert!(quat_close(s.hand_world, hq, 1e-5), "{} vs {hq}", s.hand_world);
    }
}

/// Largest elbow displacement between consecutive solves along a target path, and the
/// elbow's distance from the target line at the path's middle (the size of a flip).
fn sweep(
    ik: &mut TwoBoneIk,
    chain: &ArmChain,
    shoulder: Vec3,
    path: impl Iterator<Item = Vec3>,
    pole: impl Fn(Vec3) -> Option<Vec3>,
) -> (f32, f32) {
    let mut out = ArmPose::default();
    let mut prev: Option<Vec3> = None;
    let mut max_step = 0.0f32;
    let mut max_offset = 0.0f32;
    for target in path {
        let goal = ArmGoal {
            shoulder,
            parent_rotation: Quat::IDENTITY,
            target,
            hand_rotation: None,
            pole: pole(target),
            shoulder_root: None,
            finger: None,
        };
        let reach = ik.solve(chain, &goal, &mut out);
        assert!(reach.reachable && reach.residual < 1e-4);
        if let Some(p) = prev {
            max_step = max_step.max((out.elbow - p).length());
        }
        let d = (target - shoulder).normalize();
        max_offset = max_offset.max(across(out.elbow - shoulder, d).length());
        prev = Some(out.elbow);
    }
    (max_step, max_offset)
}

#[test]
fn no_flip_when_the_target_passes_the_default_pole_axis() {
    let skel = &layouts()[0];
    let chain = ArmChain::new(skel, Side::Left).unwrap();
    let sh = skel.rest_world(B::LeftUpperArm).unwrap();
    let axis = TwoBoneOptions::default().default_pole.normalize();
    // Sweep a bent arm's target (0.3 m from the shoulder) straight through the pole axis and
    // through its opposite, crossing in 12 directions, 30 cm long, sampled at 1 mm and at
    // 0.25 mm. A flip is a jump whose size does not depend on the sampling; a continuous
    // swivel's largest step shrinks with the step.
    for sign in [1.0f32, -1.0] {
        for k in 0..12 {
            let c = sh + axis * sign * 0.3;
            let across_dir =
                Quat::from_axis_angle(axis, k as f32 * PI / 12.0) * axis.any_orthonormal_vector();
            let mut steps = [0.0f32; 2];
            let mut offset = 0.0;
            for (j, n) in [150i32, 600].into_iter().enumerate() {
                let path = (-n..=n).map(|i| c + across_dir * (i as f32 * 0.15 / n as f32));
                let mut ik = TwoBoneIk::new(TwoBoneOptions::default()).unwrap();
                (steps[j], offset) = sweep(&mut ik, &chain, sh, path, |_| None);
            }
            println!(
                "sign {sign} dir {k}: max elbow step {:.4} m (1 mm) {:.4} m (0.25 mm), elbow offset {offset:.3} m",
                steps[0], steps[1]
            );
            // A flip would move the elbow across the arm: twice its offset from the line.
            assert!(offset > 0.15);
            assert!(
                steps[0] < 0.1 * 2.0 * offset,
                "sign {sign} dir {k}: elbow jumped {} m",
                steps[0]
            );
            assert!(
                steps[1] < 0.4 * steps[0],
                "sign {sign} dir {k}: step does not shrink: {steps:?}"
            );
        }
    }
}

/// Largest elbow step while the pose elbow (pole) moves along `pole_at(i)` for
/// `i in -n..=n`, the target fixed; the final elbow offset from the target line; and the
/// cosine between the final elbow's and the final pole's directions across that line.
fn pole_sweep(
    chain: &ArmChain,
    sh: Vec3,
    target: Vec3,
    n: i32,
    pole_at: impl Fn(f32) -> Vec3,
) -> (f32, f32, f32) {
    let mut ik = TwoBoneIk::new(TwoBoneOptions::default()).unwrap();
    let mut out = ArmPose::default();
    let mut prev: Option<Vec3> = None;
    let mut max_step = 0.0f32;
    for i in -n..=n {
        let goal = ArmGoal {
            shoulder: sh,
            parent_rotation: Quat::IDENTITY,
            target,
            hand_rotation: None,
            pole: Some(pole_at(i as f32 / n as f32)),
            shoulder_root: None,
            finger: None,
        };
        ik.solve(chain, &goal, &mut out);
        if let Some(p) = prev {
            max_step = max_step.max((out.elbow - p).length());
        }
        prev = Some(out.elbow);
    }
    let d = (target - sh).normalize();
    let elbow_off = across(out.elbow - sh, d);
    let pole_off = across(pole_at(1.0) - sh, d);
    (
        max_step,
        elbow_off.length(),
        elbow_off.normalize().dot(pole_off.normalize()),
    )
}

#[test]
fn no_flip_when_the_pole_is_collinear() {
    let skel = &layouts()[1];
    let chain = ArmChain::new(skel, Side::Right).unwrap();
    let sh = skel.rest_world(B::RightUpperArm).unwrap();
    // The pose elbow passing through the shoulder-wrist line (a straightening arm whose
    // elbow landmark jitters across): the pole sweeps 20 cm, the target stays. Sampled at
    // 0.5 mm and 0.125 mm: the largest step must shrink with the sampling (no jump).
    let target = sh + Vec3::new(-0.1, -0.2, 0.25);
    let d = (target - sh).normalize();
    for k in 0..6 {
        let side_dir = Quat::from_axis_angle(d, k as f32 * PI / 6.0) * d.any_orthonormal_vector();
        let pole_at = |f: f32| sh + d * 0.2 + side_dir * (f * 0.1);
        let (coarse, offset, side) = pole_sweep(&chain, sh, target, 200, pole_at);
        let (fine, _, _) = pole_sweep(&chain, sh, target, 800, pole_at);
        println!("pole sweep {k}: max elbow step {coarse:.4} m (0.5 mm) {fine:.4} m (0.125 mm), elbow offset {offset:.3} m");
        assert!(coarse < 0.1 * 2.0 * offset, "elbow jumped {coarse} m");
        assert!(fine < 0.4 * coarse, "step does not shrink: {coarse} {fine}");
        // Once the pole is clear of the line again, the elbow is exactly on its side.
        assert!(
            side > 1.0 - 1e-5,
            "elbow not on the pole side at the end: {side}"
        );
    }
    // And the target sweeping through a fixed pole's line.
    let pole = sh + Vec3::new(-0.2, -0.3, 0.1);
    let pd = (pole - sh).normalize();
    let perp = pd.any_orthonormal_vector();
    let mut steps = [0.0f32; 2];
    let mut offset = 0.0;
    for (j, n) in [150i32, 600].into_iter().enumerate() {
        let path = (-n..=n).map(|i| sh + pd * 0.3 + perp * (i as f32 * 0.15 / n as f32));
        let mut ik = TwoBoneIk::new(TwoBoneOptions::default()).unwrap();
        (steps[j], offset) = sweep(&mut ik, &chain, sh, path, |_| Some(pole));
    }
    println!("target through the pole line: max elbow step {steps:?}, offset {offset:.3}");
    assert!(steps[0] < 0.1 * 2.0 * offset, "elbow jumped {} m", steps[0]);
    assert!(steps[1] < 0.4 * steps[0], "step does not shrink: {steps:?}");
}

#[test]
fn classic_projection_would_flip_here() {
    // The geometry the continuity tests use is a real flip case for the textbook rule
    // `bend = normalize(pole - projection)`: its bend direction reverses across the path.
    let sh = Vec3::ZERO;
    let axis = TwoBoneOptions::default().default_pole.normalize();
    let across_dir = axis.any_orthonormal_vector();
    let bend = |t: Vec3| across(axis, (t - sh).normalize()).normalize();
    let before = bend(axis * 0.3 - across_dir * 0.01);
    let after = bend(axis * 0.3 + across_dir * 0.01);
    assert!(before.dot(after) < -0.99);
}

#[test]
fn swing_is_exact_at_every_angle() {
    // Against the axis-angle construction (cross product, atan2), from tiny turns to nearly
    // half a turn.
    let axis = Vec3::new(0.2, -0.9, 0.4).normalize();
    let a = axis.any_orthonormal_vector();
    for k in 1..=2000 {
        let angle = PI * (k as f32 / 2000.0).powi(2) * 0.99999;
        let b = Quat::from_axis_angle(axis, angle) * a;
        let q = swing(a, b, Vec3::Y);
        let cross = a.cross(b);
        let reference = match cross.try_normalize() {
            Some(n) => Quat::from_axis_angle(n, cross.length().atan2(a.dot(b))),
            None => Quat::IDENTITY,
        };
        assert!(q.is_normalized(), "{angle}: {q}");
        assert!(
            q.dot(reference).abs() > 1.0 - 1e-6,
            "{angle}: {q} vs {reference}"
        );
        if angle < PI - 1e-3 {
            assert!(
                (q * a - b).length() < 2e-6,
                "{angle}: {}",
                (q * a - b).length()
            );
        }
    }
}
