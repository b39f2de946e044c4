//! Cost of chain IK: `ChainSolver` solves (FABRIK and CCD) and arm solves with each
//! `armSolver`.
//!
//! `cargo bench --bench chain` prints the time per solve for:
//! * `chain/<method>/<chain>`: a standalone [`ChainSolver`] following a target around a circle
//!   (warm-started from the previous solve, as frame after frame), on a 2-bone arm, a 6-bone
//!   tail and a 10-bone tail with cone limits, with a pole;
//! * `arm/<solver>`: one arm solve ([`ArmSolverState::solve`], what `Rig::solve` runs per arm)
//!   on the shared robot, the wrist target moving across the chest and back with a hand
//!   rotation, warm-started;
//! * `arm cold/<solver>`: the same solves each from rest ([`ArmSolverState::reset`] before
//!   each): the iteration caps' worst case.
//!
//! FABRIK and CCD iteration counts on real recordings are printed by
//! `cargo run --release --example eval_alignment`.

use handrig_support::recordings;

use core::f32::consts::PI;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::{Quat, Vec3};
use handrig::humanoid::bones::{Side, BONE_COUNT};
use handrig::humanoid::skeleton::WorldPose;
use handrig::ik::{ArmSolver, ArmSolverState, ChainMethod, ChainSolver, ChainSolverOptions};
use handrig::kinematics::JointLimit;

/// Rest joints of an `n`-bone chain hanging down from the origin, each bone 0.3 / n long,
/// slightly bent so that its rest layout is not straight.
fn tail(n: usize) -> Vec<Vec3> {
    (0..=n)
        .map(|k| {
            let t = k as f32 / n as f32;
            Vec3::new(0.02 * (PI * t).sin(), -0.3 * t, 0.0)
        })
        .collect()
}

/// A benchmarked chain: name, rest joints, limits.
type Case = (&'static str, Vec<Vec3>, Vec<Option<JointLimit>>);

fn chains(c: &mut Criterion) {
    let mut group = c.benchmark_group("chain");
    let cone = Some(JointLimit::Cone { max_angle: 0.8 });
    let cases: [Case; 3] = [
        ("2 bones", tail(2), vec![]),
        ("6 bones", tail(6), vec![]),
        ("10 bones, cones", tail(10), vec![cone; 10]),
    ];
    for method in [ChainMethod::Fabrik, ChainMethod::Ccd] {
        for (name, joints, constraints) in &cases {
            let mut solver = ChainSolver::new(&ChainSolverOptions {
                method,
                joints: joints.clone(),
                constraints: constraints.clone(),
                ..ChainSolverOptions::default()
            })
            .expect("chain");
            let mut i = 0u32;
            let label = format!(
                "{}/{name}",
                if method == ChainMethod::Fabrik {
                    "fabrik"
                } else {
                    "ccd"
                }
            );
            group.bench_function(label, |b| {
                b.iter(|| {
                    // 2 degrees per solve around a circle 0.15 m across, below the root.
                    let a = (i as f32 * 2.0).to_radians();
                    i += 1;
                    let target = Vec3::new(0.15 * a.cos(), -0.2, 0.15 * a.sin());
                    solver
                        .solve(target, Some(Vec3::new(0.0, -0.1, 1.0)))
                        .expect("solve")
                        .status
                })
            });
        }
    }
    group.finish();
}

/// The right wrist's path across the chest to the left shoulder and back (internal frame),
/// 240 frames, and a hand rotation turning along it.
fn arm_path(skel: &handrig::Skeleton) -> Vec<(Vec3, Quat)> {
    let s = skel.rest_world(Side::Right.arm()[1]).unwrap();
    let other = skel.rest_world(Side::Left.arm()[1]).unwrap();
    let start = s + Vec3::new(-0.05, -0.28, 0.18);
    let end = other + Vec3::new(0.0, -0.05, 0.11);
    (0..=120)
        .chain((0..120).rev())
        .map(|i| {
            let t = i as f32 / 120.0;
            let p = start.lerp(end, t) + Vec3::Z * (0.05 * (PI * t).sin());
            (
                p,
                Quat::from_rotation_y(0.8 * t) * Quat::from_rotation_z(-0.3),
            )
        })
        .collect()
}

fn arms(c: &mut Criterion) {
    let skel = recordings::vrm(recordings::ROBOT);
    let path = arm_path(&skel);
    let mut world = WorldPose::default();
    skel.forward(&[Quat::IDENTITY; BONE_COUNT], &mut world);
    let pole = skel.rest_world(Side::Right.arm()[2]).unwrap() + Vec3::new(-0.1, -0.2, -0.1);
    for (group_name, cold) in [("arm", false), ("arm cold", true)] {
        let mut group = c.benchmark_group(group_name);
        for solver in ArmSolver::ALL {
            let mut state = ArmSolverState::new(&skel, solver).expect("arm");
            let mut local = [Quat::IDENTITY; BONE_COUNT];
            let mut i = 0usize;
            group.bench_function(solver.as_str(), |b| {
                b.iter(|| {
                    let (target, hand) = path[i % path.len()];
                    i += 1;
                    if cold {
                        state.reset();
                    }
                    let to = handrig::ik::ArmTarget {
                        target,
                        hand_rotation: Some(hand),
                        pole: Some(pole),
                        finger: None,
                    };
                    state.solve(Side::Right, &to, &mut local, &world)
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, chains, arms);
criterion_main!(benches);
