//! Known-answer tests of the hand solver on a synthetic hand posed with known joint angles.

use crate::support::hand_model;

use glam::{Quat, Vec3};
use hand_model::{avatar, place, poses, Angles, HandLayout, HandModel, NO_STRETCH};
use handrig::hand::{Dof, HandSolver, HandStatus, HandStrategy, DOF_COUNT};
use handrig::{Finger, HumanBone, Side, Skeleton, WorldPose, BONE_COUNT};

const TOL_DEG: f32 = 1.0;

fn turn() -> Quat {
    Quat::from_euler(glam::EulerRot::YXZ, 0.9, -0.4, 2.2)
}

/// World direction of each present finger bone of `side` by forward kinematics of `local`
/// (hand and arm at rest): joint to next present joint, the last bone continuing its
/// parent's rest direction.
fn fk_dirs(skel: &Skeleton, side: Side, local: &[Quat; BONE_COUNT]) -> Vec<(Finger, usize, Vec3)> {
    let mut world = WorldPose::default();
    skel.forward(local, &mut world);
    let mut out = Vec::new();
    for finger in Finger::ALL {
        let bones = side.finger(finger);
        for (slot, b) in bones.iter().enumerate() {
            if !skel.has(*b) {
                continue;
            }
            let next = bones[slot + 1..].iter().find(|c| skel.has(**c));
            let dir = match next {
                Some(c) => world.position[c.index()] - world.position[b.index()],
                None => {
                    let p = skel.parent(*b).unwrap();
                    world.rotation[b.index()]
                        * (skel.rest_world(*b).unwrap() - skel.rest_world(p).unwrap())
                }
            };
            out.push((finger, slot, dir.normalize()));
        }
    }
    out
}

/// Direction of the model's landmark span covered by the bone at `slot`.
fn span(skel: &Skeleton, side: Side, lm: &[Vec3; 21], finger: Finger, slot: usize) -> Vec3 {
    let bones = side.finger(finger);
    let end = (slot + 1..3).find(|s| skel.has(bones[*s])).unwrap_or(3);
    let ids = finger.landmarks();
    (lm[ids[end]] - lm[ids[slot]]).normalize()
}

fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
}

fn quat_angle_deg(a: Quat, b: Quat) -> f32 {
    (2.0 * a.dot(b).abs().clamp(0.0, 1.0).acos()).to_degrees()
}

/// Solves the model posed by `angles` (placed by `q`, scale `s`) on `skel` and checks the
/// recovered angles, hand rotation, bone directions, unit outputs and the absence of twist.
fn check(
    skel: &Skeleton,
    model: &HandModel,
    angles: &Angles,
    stretch: &[[f32; 3]; 5],
    q: Quat,
    s: f32,
    what: &str,
) {
    let side = model.side;
    let lm_model = model.landmarks(angles, stretch);
    let lm = place(&lm_model, q, s, Vec3::new(0.3, -0.2, 0.5));
    let mut solver = HandSolver::new(skel, HandStrategy::Analytic).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let hand = solver
        .solve(skel, side, &lm, &mut local)
        .unwrap_or_else(|| panic!("{what}: not solved"));
    let rep = *solver.report(side);
    assert_eq!(rep.status, HandStatus::Solved, "{what}");
    assert!(
        !rep.any_limited(),
        "{what}: limits active {:?}",
        rep.limited
    );
    assert!(
        quat_angle_deg(hand, q) < 0.5,
        "{what}: hand rotation off by {}",
        quat_angle_deg(hand, q)
    );
    for finger in Finger::ALL {
        for dof in [Dof::Base0, Dof::Base1, Dof::Hinge1, Dof::Hinge2] {
            let got = rep.angle(finger, dof).to_degrees();
            let want = angles[finger.index()][dof.index()].to_degrees();
            assert!(
                (got - want).abs() < TOL_DEG,
                "{what}: {side:?} {finger:?} {} = {got:.2}, expected {want:.2}",
                dof.name(finger)
            );
        }
        // Planar fingers: no sideways deviation.
        for dof in [Dof::Deviation1, Dof::Deviation2] {
            let got = rep.angle(finger, dof).to_degrees();
            assert!(
                got.abs() < 0.05,
                "{what}: {side:?} {finger:?} {dof:?} = {got}"
            );
        }
    }
    for q in local.iter().chain([&hand]) {
        assert!(
            q.is_finite() && (q.length() - 1.0).abs() < 1e-4,
            "{what}: {q}"
        );
    }
    for (finger, slot, dir) in fk_dirs(skel, side, &local) {
        let want = span(skel, side, &lm_model, finger, slot);
        let e = angle_deg(dir, want);
        assert!(
            e < TOL_DEG,
            "{what}: {side:?} {finger:?} bone {slot} off by {e:.2} deg"
        );
    }
    // No twist: hinge bones turn only about their rest hinge axis; the first bone of each
    // finger takes its rest hinge axis onto the posed hinge axis.
    for finger in Finger::ALL {
        let bones = side.finger(finger);
        let mut first = true;
        for b in bones.iter().filter(|b| skel.has(**b)) {
            let qb = local[b.index()];
            let axis = solver.rest_hinge_axis(*b).unwrap();
            if first {
                let posed = model.hinge_axis(finger, angles[finger.index()]);
                let carried = qb * axis;
                assert!(
                    carried.dot(posed).abs() > (TOL_DEG.to_radians()).cos(),
                    "{what}: {b} twisted"
                );
                first = false;
            } else {
                let v = Vec3::new(qb.x, qb.y, qb.z);
                assert!(
                    v.cross(axis).length() < 1e-3,
                    "{what}: {b} rotates off its hinge axis"
                );
            }
        }
    }
}

/// [`check`] of every pose of [`poses`] on both hands of `skel`, the landmark hands built on
/// the rest hands of `model_from` (normally `skel` itself), scaled by `s` and turned by
/// [`turn`]; `what` prefixes the pose name in failure messages.
fn check_poses(
    skel: &Skeleton,
    model_from: &Skeleton,
    stretch: &[[f32; 3]; 5],
    s: f32,
    what: &str,
) {
    for side in Side::BOTH {
        let model = HandModel::from_skeleton(model_from, side);
        for (name, angles) in poses() {
            check(
                skel,
                &model,
                &angles,
                stretch,
                turn(),
                s,
                &format!("{what}{name}"),
            );
        }
    }
}

#[test]
fn known_angles_are_recovered_on_both_hands_and_sizes() {
    let skel = avatar(&HandLayout::standard(), &[]);
    for side in Side::BOTH {
        let model = HandModel::from_skeleton(&skel, side);
        for (name, angles) in poses() {
            for (s, q) in [
                (0.6, Quat::IDENTITY),
                (1.0, turn()),
                (1.7, turn().inverse()),
            ] {
                check(
                    &skel,
                    &model,
                    &angles,
                    &NO_STRETCH,
                    q,
                    s,
                    &format!("{name} x{s}"),
                );
            }
        }
    }
}

#[test]
fn finger_proportions_do_not_change_the_angles() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let stretch = [
        [1.3, 0.8, 1.1],
        [0.7, 1.2, 1.4],
        [1.0, 1.0, 0.6],
        [1.2, 0.9, 1.0],
        [0.8, 1.3, 1.2],
    ];
    check_poses(&skel, &skel, &stretch, 1.1, "");
}

#[test]
fn rest_fingers_that_are_not_axis_aligned() {
    let layouts = [
        (
            "rotated",
            HandLayout::standard().rotated(Quat::from_euler(glam::EulerRot::XYZ, 0.5, -0.6, 0.8)),
        ),
        (
            "relaxed",
            HandLayout::standard().relaxed(0.2, [0.1, 0.0, -0.1, -0.2]),
        ),
        ("drooping thumb", HandLayout::standard().drooping_thumb()),
        ("bent thumb", HandLayout::standard().bent_thumb(0.25, 0.7)),
        (
            "all three",
            HandLayout::standard()
                .relaxed(0.15, [0.05, 0.0, -0.05, -0.15])
                .drooping_thumb()
                .rotated(Quat::from_rotation_z(-0.7)),
        ),
    ];
    for (lname, layout) in layouts {
        let skel = avatar(&layout, &[]);
        check_poses(&skel, &skel, &NO_STRETCH, 1.0, &format!("{lname}: "));
    }
}

#[test]
fn missing_bones_are_skipped_and_the_rest_stays_correct() {
    use HumanBone as B;
    let full = avatar(&HandLayout::standard(), &[]);
    let cases: [&[HumanBone]; 8] = [
        // The palm frame falls back to other proximals.
        &[B::LeftMiddleProximal, B::RightIndexProximal],
        &[
            B::LeftIndexProximal,
            B::LeftLittleProximal,
            B::RightMiddleProximal,
            B::RightRingProximal,
        ],
        &[B::LeftIndexIntermediate, B::RightIndexIntermediate],
        &[B::LeftRingDistal, B::RightMiddleDistal],
        &[B::LeftLittleProximal, B::RightRingProximal],
        &[B::LeftThumbProximal, B::RightThumbProximal],
        &[
            B::LeftThumbMetacarpal,
            B::RightMiddleIntermediate,
            B::RightMiddleDistal,
        ],
        &[
            B::LeftThumbDistal,
            B::RightThumbMetacarpal,
            B::RightThumbDistal,
        ],
    ];
    for missing in cases {
        let skel = avatar(&HandLayout::standard(), missing);
        // The landmark hand comes from the complete avatar.
        check_poses(
            &skel,
            &full,
            &NO_STRETCH,
            1.2,
            &format!("missing {missing:?}: "),
        );
    }
}

#[test]
fn limits_clamp_and_are_reported() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let side = Side::Right;
    let model = HandModel::from_skeleton(&skel, side);
    // Index PIP hyperextended 40, middle DIP 120, little MCP abducted 45, thumb IP 100.
    let mut angles = poses()[2].1;
    angles[1][2] = (-40f32).to_radians();
    angles[2][3] = 120f32.to_radians();
    angles[4][1] = (-45f32).to_radians();
    angles[0][3] = 100f32.to_radians();
    let lm = place(
        &model.landmarks(&angles, &NO_STRETCH),
        turn(),
        1.0,
        Vec3::ZERO,
    );
    let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    solver.solve(&skel, side, &lm, &mut local).unwrap();
    let rep = solver.report(side);
    let expect = [
        (Finger::Index, Dof::Hinge1, -10.0),
        (Finger::Middle, Dof::Hinge2, 90.0),
        (Finger::Little, Dof::Base1, -30.0),
        (Finger::Thumb, Dof::Hinge2, 90.0),
    ];
    for finger in Finger::ALL {
        for dof in Dof::ALL {
            let hit = expect.iter().find(|(f, d, _)| *f == finger && *d == dof);
            assert_eq!(
                rep.limited[finger.index()][dof.index()],
                hit.is_some(),
                "{finger:?} {dof:?}"
            );
            if let Some((_, _, bound)) = hit {
                assert!((rep.angle(finger, dof).to_degrees() - bound).abs() < 1e-3);
            }
        }
    }
    assert!(rep.finger_limited(Finger::Index) && !rep.finger_limited(Finger::Ring));
    // Unlimited joints are still recovered.
    assert!(
        (rep.angle(Finger::Ring, Dof::Hinge1) - angles[3][2])
            .abs()
            .to_degrees()
            < TOL_DEG
    );
    for q in &local {
        assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-4);
    }
    // The clamped index PIP really is at -10 degrees on the avatar.
    let inter = local[HumanBone::RightIndexIntermediate.index()];
    let axis = solver
        .rest_hinge_axis(HumanBone::RightIndexIntermediate)
        .unwrap();
    let (got_axis, got_angle) = inter.to_axis_angle();
    let signed = if got_axis.dot(axis) < 0.0 {
        -got_angle
    } else {
        got_angle
    };
    assert!(
        (signed.to_degrees() + 10.0).abs() < 0.5,
        "{}",
        signed.to_degrees()
    );
}

#[test]
fn degenerate_hands_are_skipped_then_held() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let side = Side::Left;
    let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let same = [Vec3::new(0.1, 0.2, 0.3); 21];
    // Nothing to hold yet.
    assert_eq!(solver.solve(&skel, side, &same, &mut local), None);
    assert_eq!(solver.report(side).status, HandStatus::Skipped);
    assert!(local.iter().all(|q| *q == Quat::IDENTITY));

    let model = HandModel::from_skeleton(&skel, side);
    let lm = place(
        &model.landmarks(&poses()[1].1, &NO_STRETCH),
        turn(),
        1.0,
        Vec3::ZERO,
    );
    let good = solver.solve(&skel, side, &lm, &mut local).unwrap();
    let kept = local;

    let collinear: [Vec3; 21] = core::array::from_fn(|i| Vec3::new(0.01 * i as f32, 0.0, 0.0));
    for bad in [same, collinear] {
        let mut out = [Quat::IDENTITY; BONE_COUNT];
        let held = solver.solve(&skel, side, &bad, &mut out);
        assert_eq!(held, Some(good));
        assert_eq!(solver.report(side).status, HandStatus::Held);
        for finger in Finger::ALL {
            for b in side.finger(finger) {
                assert_eq!(out[b.index()], kept[b.index()], "{b}");
            }
        }
        // The other side is untouched.
        assert!(Finger::ALL.iter().all(|f| side
            .opposite()
            .finger(*f)
            .iter()
            .all(|b| out[b.index()] == Quat::IDENTITY)));
    }
}

#[test]
fn rig_without_finger_bones_still_gets_a_hand_rotation() {
    use HumanBone as B;
    let all_fingers: Vec<HumanBone> = HumanBone::ALL
        .iter()
        .copied()
        .filter(|b| b.is_finger())
        .collect();
    let skel = avatar(&HandLayout::standard(), &all_fingers);
    let full = avatar(&HandLayout::standard(), &[]);
    let model = HandModel::from_skeleton(&full, Side::Right);
    let lm = place(
        &model.landmarks(&poses()[0].1, &NO_STRETCH),
        turn(),
        1.0,
        Vec3::ZERO,
    );
    let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let hand = solver.solve(&skel, Side::Right, &lm, &mut local).unwrap();
    // Without fingers the rest palm is assumed facing down with fingers along the forearm:
    // the standard test hand has exactly that, so the rotation is the placement.
    assert!(
        quat_angle_deg(hand, turn()) < 0.5,
        "{}",
        quat_angle_deg(hand, turn())
    );
    assert!(local.iter().all(|q| *q == Quat::IDENTITY));
    let _ = B::Hips;
}

/// `lm` with `finger` bent sideways by `pip` at its middle joint and a further `dip` at its
/// last joint, both toward the radial side of the hand (out of the flexion plane about the
/// axis perpendicular to the phalanx and the hinge axis).
fn deviate(
    model: &HandModel,
    lm: &[Vec3; 21],
    finger: Finger,
    a: [f32; 4],
    pip: f32,
    dip: f32,
) -> [Vec3; 21] {
    let (_, r, _) = model.palm();
    let mut hinge = model.hinge_axis(finger, a);
    if finger != Finger::Thumb && hinge.dot(r) < 0.0 {
        hinge = -hinge;
    }
    let ids = finger.landmarks();
    let mut out = *lm;
    for (joint, angle) in [(1, pip), (2, dip)] {
        let o = out[ids[joint]];
        let dir = (out[ids[joint + 1]] - o).normalize();
        let q = Quat::from_axis_angle(dir.cross(hinge).normalize(), angle);
        for k in joint + 1..4 {
            out[ids[k]] = o + q * (out[ids[k]] - o);
        }
    }
    out
}

/// A finger bent sideways at its hinges: the avatar's hinge bones follow the user's
/// phalanges exactly within the joints' play (the base joint's fitted plane leans part of
/// the way, so the reported deviation carries the rest, with its sign); beyond the play the
/// deviation stops at the limit and says so. A flattening solver (hinges only) misses the
/// middle phalanx by the deviation.
#[test]
fn sideways_bends_at_the_hinges_are_followed_within_their_play() {
    let skel = avatar(&HandLayout::standard(), &[]);
    let angles = hand_model::pose("hook");
    for side in Side::BOTH {
        let model = HandModel::from_skeleton(&skel, side);
        let posed = model.landmarks(&angles, &NO_STRETCH);
        for finger in [Finger::Index, Finger::Ring, Finger::Little] {
            let a = angles[finger.index()];
            for (pip, dip) in [(8.0_f32, 0.0_f32), (-6.0, 5.0), (-10.0, -12.0), (25.0, 0.0)] {
                let what = format!("{side:?} {finger:?} PIP {pip} DIP {dip}");
                let lm_model = deviate(
                    &model,
                    &posed,
                    finger,
                    a,
                    pip.to_radians(),
                    dip.to_radians(),
                );
                let lm = place(&lm_model, turn(), 1.0, Vec3::new(0.1, 0.2, 0.3));
                let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
                let mut local = [Quat::IDENTITY; BONE_COUNT];
                solver.solve(&skel, side, &lm, &mut local).unwrap();
                let rep = solver.report(side);
                let dev1 = rep.angle(finger, Dof::Deviation1).to_degrees();
                let limited = rep.limited[finger.index()];
                let errs: Vec<(usize, f32)> = fk_dirs(&skel, side, &local)
                    .into_iter()
                    .filter(|(f, _, _)| *f == finger)
                    .map(|(_, slot, dir)| {
                        (
                            slot,
                            angle_deg(dir, span(&skel, side, &lm_model, finger, slot)),
                        )
                    })
                    .collect();
                if pip.abs() <= 15.0 {
                    assert_eq!(limited, [false; DOF_COUNT], "{what}");
                    for (slot, e) in &errs {
                        if *slot > 0 {
                            assert!(*e < 0.1, "{what}: bone {slot} off by {e:.3} deg");
                        } else {
                            // The base fit leans on the proximal phalanx: the deviated ones
                            // tilt it by well under half their deviation (fitting all three
                            // alike: up to 0.8 of it).
                            let bound = 0.35 * pip.abs().max(dip.abs());
                            assert!(*e < bound, "{what}: proximal off by {e:.2} deg");
                        }
                    }
                    assert!(
                        dev1 * pip > 0.0 && (0.6..1.05).contains(&(dev1 / pip)),
                        "{what}: PIP deviation {dev1:.2}"
                    );
                } else {
                    assert!((dev1 - 15.0).abs() < 1e-3, "{what}: {dev1}");
                    let expect = [false, false, false, false, false, true, false];
                    assert_eq!(limited, expect, "{what}");
                    // The middle phalanx misses by what the limit held back.
                    let e = errs.iter().find(|(s, _)| *s == 1).unwrap().1;
                    assert!((3.0..12.0).contains(&e), "{what}: {e}");
                }
            }
        }
    }
}
