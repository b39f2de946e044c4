//! Chain IK (FABRIK, CCD) through the standalone [`ChainSolver`]: property tests on random
//! chains of 2 to 10 bones with random lengths (reach, straight out of reach, lengths, limits,
//! pole side), known answers, degenerate setups and goals.

// Native only: proptest is not built for wasm32.

use crate::support::geometry;

use core::f32::consts::PI;

use geometry::{across, dir};
use glam::{Quat, Vec3};
use handrig::ik::{
    Ccd, CcdOptions, ChainGoal, ChainMethod, ChainSolver, ChainSolverOptions, Effector,
};
use handrig::kinematics::{Chain, JointLimit};
use handrig::math::angle_between;
use proptest::prelude::*;

const METHODS: [ChainMethod; 2] = [ChainMethod::Fabrik, ChainMethod::Ccd];

/// Rest joints from a root and per-bone (direction angles, length).
fn joints_from(root: Vec3, bones: &[(f32, f32, f32)]) -> Vec<Vec3> {
    let mut joints = vec![root];
    for &(t, p, len) in bones {
        let last = *joints.last().unwrap();
        joints.push(last + dir(t, p) * len);
    }
    joints
}

fn solver(
    method: ChainMethod,
    joints: &[Vec3],
    constraints: Vec<Option<JointLimit>>,
    iterations: u32,
) -> ChainSolver {
    ChainSolver::new(&ChainSolverOptions {
        method,
        joints: joints.to_vec(),
        constraints,
        iterations: Some(iterations),
        ..ChainSolverOptions::default()
    })
    .expect("valid chain")
}

fn lengths(joints: &[Vec3]) -> Vec<f32> {
    joints.windows(2).map(|w| (w[1] - w[0]).length()).collect()
}

fn bones_strategy() -> impl Strategy<Value = Vec<(f32, f32, f32)>> {
    prop::collection::vec((0.0f32..2.0 * PI, 0.0f32..PI, 0.02f32..1.0), 2..=10)
}

/// Checks what every solve must give: finite joints, the root in place, every bone length
/// kept to 1e-5 relative (or, for a bone so short that this is below f32 resolution at the
/// chain's coordinates, to 8 units in the last place of the largest coordinate), rotations
/// that carry each rest direction onto the solved bone.
fn check_pose(s: &ChainSolver, rest: &[Vec3], what: &str) -> Result<(), TestCaseError> {
    let sol = s.solution();
    prop_assert!(
        sol.joints.iter().all(|p| p.is_finite()),
        "{what}: non-finite joint"
    );
    prop_assert!(
        sol.rotations.iter().all(|q| q.is_finite()),
        "{what}: non-finite rotation"
    );
    prop_assert!(
        (sol.joints[0] - rest[0]).length() < 1e-6,
        "{what}: root moved"
    );
    let scale = sol
        .joints
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f32::max);
    for (k, (l, r)) in lengths(sol.joints).iter().zip(lengths(rest)).enumerate() {
        let tolerance = (1e-5 * r).max(8.0 * f32::EPSILON * scale);
        prop_assert!(
            (l - r).abs() <= tolerance,
            "{what}: bone {k} length {l} vs {r}"
        );
    }
    let rest_dirs = s.chain().rest_directions();
    for (k, q) in sol.rotations.iter().enumerate() {
        let got = (sol.joints[k + 1] - sol.joints[k]).normalize();
        prop_assert!(
            (*q * rest_dirs[k] - got).length() < 1e-4,
            "{what}: rotation {k}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Reachable targets (between the nearest and farthest reach, clear of both by 2% of the
    /// chain's length) are reached within 1e-4 of the chain's length; the bend (the sum of the
    /// middle joints' offsets across the root-to-target line) faces the pole, and with two
    /// bones the elbow is on the pole's side. (Every middle joint on the pole's side of a
    /// longer chain is not always reachable from the chain's previous shape by turning
    /// joints; `middle_joints_on_the_pole_side` measures how often it holds.)
    #[test]
    fn reachable_targets_are_reached_with_the_bend_toward_the_pole(
        bones in bones_strategy(),
        t_theta in 0.0f32..(2.0 * PI), t_phi in 0.0f32..PI, frac in 0.0f32..1.0,
        p_theta in 0.0f32..(2.0 * PI), p_phi in 0.0f32..PI, p_dist in 0.1f32..2.0,
        root in prop::array::uniform3(-1.0f32..1.0),
    ) {
        let rest = joints_from(Vec3::from_array(root), &bones);
        let total: f32 = lengths(&rest).iter().sum();
        let longest = lengths(&rest).into_iter().fold(0.0, f32::max);
        let min_reach = (2.0 * longest - total).max(0.0);
        let d = dir(t_theta, t_phi);
        let r = min_reach + 0.02 * total + frac * (0.96 * total - min_reach);
        prop_assume!(r < 0.98 * total);
        let target = rest[0] + d * r;
        let pole = rest[0] + d * (0.5 * r) + dir(p_theta, p_phi) * p_dist * total;
        let pole_across = across(pole - rest[0], d);
        prop_assume!(pole_across.length() > 0.05 * total);
        for method in METHODS {
            // CCD converges slowly where the chain must fold far back (short bones before a
            // long one: thousands of sweeps from rest) and near full stretch, where its
            // error only falls like 1 / sweeps (a 7-bone chain at 97.5% of its length is
            // still 0.4 mm per 1 m of chain off after 20 000 sweeps): it gets a large budget
            // and targets up to 95% of the length; FABRIK up to 98%.
            let (budget, farthest) = match method {
                ChainMethod::Ccd => (20_000, 0.95),
                _ => (2_000, 0.98),
            };
            if r > farthest * total {
                continue;
            }
            let mut s = solver(method, &rest, vec![], budget);
            let status = s.solve(target, Some(pole)).unwrap().status;
            check_pose(&s, &rest, &format!("{method:?}"))?;
            let sol = s.solution();
            let error = (sol.joints[rest.len() - 1] - target).length();
            prop_assert!(error <= 1e-4 * total, "{method:?}: error {error} of {total} ({} iterations)", status.iterations);
            prop_assert!(status.reachable);
            // The bend (middle joints' offsets across the line) faces the pole, and no middle
            // joint sits on the far side.
            let pole_dir = pole_across.normalize();
            let bend: Vec3 = sol.joints[1..rest.len() - 1].iter().map(|p| across(*p - rest[0], d)).sum();
            if bend.length() > 1e-3 * total {
                let cos = bend.normalize().dot(pole_dir);
                prop_assert!(cos > 1.0 - 1e-3, "{method:?}: bend off the pole by {} rad", cos.clamp(-1.0, 1.0).acos());
            }
            if rest.len() == 3 {
                let side = across(sol.joints[1] - rest[0], d).dot(pole_dir);
                prop_assert!(side >= -1e-5 * total, "{method:?}: elbow on the far side ({side})");
            }
        }
    }

    /// Targets beyond reach: the chain lies straight toward the target, joint k at the
    /// cumulative length along the line.
    #[test]
    fn unreachable_targets_give_a_straight_chain(
        bones in bones_strategy(),
        t_theta in 0.0f32..(2.0 * PI), t_phi in 0.0f32..PI, beyond in 1.001f32..3.0,
        warm in prop::option::of((0.0f32..(2.0 * PI), 0.0f32..PI, 0.1f32..0.9)),
    ) {
        let rest = joints_from(Vec3::ZERO, &bones);
        let total: f32 = lengths(&rest).iter().sum();
        let d = dir(t_theta, t_phi);
        let target = d * (beyond * total);
        for method in METHODS {
            let mut s = solver(method, &rest, vec![], 50);
            if let Some((a, b, f)) = warm {
                // History must not matter.
                s.solve(dir(a, b) * f * total, None).unwrap();
            }
            let status = s.solve(target, None).unwrap().status;
            check_pose(&s, &rest, &format!("{method:?}"))?;
            prop_assert!(!status.reachable && !status.reached);
            let mut along = 0.0;
            for (k, p) in s.solution().joints.iter().enumerate() {
                prop_assert!(across(*p, d).length() <= 1e-5 * total, "{method:?}: joint {k} off the line");
                prop_assert!((p.dot(d) - along).abs() <= 1e-5 * total, "{method:?}: joint {k} not stretched");
                if k + 1 < rest.len() {
                    along += (rest[k + 1] - rest[k]).length();
                }
            }
            prop_assert!((status.error - (beyond - 1.0) * total).abs() <= 1e-4 * total);
        }
    }

    /// Random cones and hinges on every bone (or none), random targets near and far: no limit
    /// is broken by more than 1e-4 rad in the output, lengths are kept, nothing is NaN, and
    /// a warm-started sequence of solves stays within the limits too.
    #[test]
    fn limits_hold_in_the_output(
        bones in bones_strategy(),
        limits in prop::collection::vec(
            prop::option::of(prop_oneof![
                (0.05f32..2.5).prop_map(|a| (0, a, 0.0, 0.0, 0.0, 0.0)),
                (0.0f32..(2.0 * PI), 0.0f32..PI, -3.0f32..3.0, 0.0f32..3.0)
                    .prop_map(|(t, p, lo, span)| (1, t, p, lo, span, 0.0)),
            ]),
            10,
        ),
        targets in prop::collection::vec((0.0f32..(2.0 * PI), 0.0f32..PI, 0.0f32..1.5), 1..4),
        pole in prop::option::of((0.0f32..(2.0 * PI), 0.0f32..PI)),
    ) {
        let rest = joints_from(Vec3::ZERO, &bones);
        let total: f32 = lengths(&rest).iter().sum();
        let constraints: Vec<Option<JointLimit>> = limits[..rest.len() - 1]
            .iter()
            .map(|l| l.map(|(kind, a, b, lo, span, _)| {
                if kind == 0 {
                    JointLimit::Cone { max_angle: a }
                } else {
                    let min = lo.clamp(-PI, PI);
                    JointLimit::Hinge { axis: dir(a, b), min, max: (min + span).min(PI) }
                }
            }))
            .collect();
        for method in METHODS {
            let mut s = solver(method, &rest, constraints.clone(), 60);
            for &(a, b, f) in &targets {
                let target = dir(a, b) * f * total;
                let pole = pole.map(|(pa, pb)| dir(pa, pb) * total);
                s.solve(target, pole).unwrap();
                check_pose(&s, &rest, &format!("{method:?}"))?;
                let sol = s.solution();
                let v = s.chain().max_violation(Quat::IDENTITY, sol.joints, sol.rotations);
                prop_assert!(v <= 1e-4, "{method:?}: a limit is broken by {v} rad");
            }
        }
    }
}

/// Deterministic random chains (3 to 10 bones, random 3D rest layouts) with reachable
/// targets and poles: the share of solves with *every* middle joint on the pole's side of
/// the root-to-target line (within 1e-3 of the chain length) is printed and must be at least
/// 95%; the misses are chains the reaching passes leave zigzagged through the line.
#[test]
fn middle_joints_on_the_pole_side() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for method in METHODS {
        let (mut all_on_side, mut cases) = (0, 0);
        while cases < 500 {
            let bones: Vec<(f32, f32, f32)> = (0..3 + (next() * 8.0) as usize)
                .map(|_| (next() * 2.0 * PI, next() * PI, 0.2 + 0.8 * next()))
                .collect();
            let rest = joints_from(Vec3::ZERO, &bones);
            let total: f32 = lengths(&rest).iter().sum();
            let longest = lengths(&rest).into_iter().fold(0.0, f32::max);
            let min_reach = (2.0 * longest - total).max(0.0);
            let r = min_reach + 0.02 * total + next() * (0.96 * total - min_reach);
            let d = dir(next() * 2.0 * PI, next() * PI);
            let pole = d * (0.5 * r) + dir(next() * 2.0 * PI, next() * PI) * total;
            let pole_across = across(pole, d);
            if r >= 0.98 * total || pole_across.length() < 0.05 * total {
                continue;
            }
            cases += 1;
            let budget = match method {
                ChainMethod::Ccd => 20_000,
                _ => 2_000,
            };
            let mut s = solver(method, &rest, vec![], budget);
            let sol = s.solve(d * r, Some(pole)).unwrap();
            let w = pole_across.normalize();
            if sol.joints[1..rest.len() - 1]
                .iter()
                .all(|p| across(*p, d).dot(w) >= -1e-3 * total)
            {
                all_on_side += 1;
            }
        }
        let share = all_on_side as f32 / cases as f32;
        println!("{method:?}: every middle joint on the pole's side in {all_on_side}/{cases} solves ({:.1}%)", 100.0 * share);
        assert!(share >= 0.95, "{method:?}: {share}");
    }
}

#[test]
fn two_bones_known_answer_matches_the_law_of_cosines() {
    // 0.3 + 0.4 along +X, target at 0.5 along +Z: a 3-4-5 triangle, right angle at the elbow;
    // pole toward +X: the upper arm at angle a from the target line with cos a = 0.3 / 0.5,
    // so the elbow is at 0.3 * (sin a, 0, cos a) = (0.24, 0, 0.18).
    let rest = [Vec3::ZERO, Vec3::X * 0.3, Vec3::X * 0.7];
    for method in METHODS {
        let mut s = solver(method, &rest, vec![], 500);
        let sol = s
            .solve(Vec3::Z * 0.5, Some(Vec3::new(1.0, 0.0, 0.25)))
            .unwrap();
        let elbow = sol.joints[1];
        assert!(
            (elbow - Vec3::new(0.24, 0.0, 0.18)).length() < 1e-5,
            "{method:?}: {elbow}"
        );
        assert!(sol.status.reached && sol.status.error < 1e-5);
        // Rotations: bone 0 turns +X onto (0.8, 0, 0.6), a swing about -Y; bone 1's world
        // rotation takes +X onto the forearm's direction.
        let up = sol.rotations[0];
        let expect = Quat::from_rotation_y(-(0.6f32.atan2(0.8)));
        assert!(up.dot(expect).abs() > 1.0 - 1e-6, "{method:?}: {up}");
        let fore = (Vec3::new(0.0, 0.0, 0.5) - elbow).normalize();
        assert!((sol.rotations[1] * Vec3::X - fore).length() < 1e-4);
    }
}

#[test]
fn hinge_chain_stays_in_its_plane_and_range() {
    // A planar finger: three bones along +X, each hinged about +Z (the previous bone's
    // frame), flexing 0..90 degrees. A reachable target in the plane is reached; for one out
    // of the plane the chain stays in the XY plane with every joint angle in range (CCD then
    // finds the nearest reachable point; FABRIK, whose passes are not projections, a
    // farther one).
    let rest = [Vec3::ZERO, Vec3::X * 0.05, Vec3::X * 0.08, Vec3::X * 0.1];
    let hinge = Some(JointLimit::Hinge {
        axis: Vec3::Z,
        min: 0.0,
        max: PI / 2.0,
    });
    let constraints = vec![hinge, hinge, hinge];
    for method in METHODS {
        for target in [Vec3::new(0.04, 0.05, 0.0), Vec3::new(0.04, 0.05, 0.03)] {
            let mut s = solver(method, &rest, constraints.clone(), 200);
            let sol = s.solve(target, None).unwrap();
            for p in sol.joints {
                assert!(p.z.abs() < 1e-5, "{method:?}: joint off the plane {p}");
            }
            // Each bone turned counter-clockwise (about +Z) from its parent by 0..90 degrees.
            let mut prev = Vec3::X;
            for w in sol.joints.windows(2) {
                let d = (w[1] - w[0]).normalize();
                let a = prev.cross(d).z.atan2(prev.dot(d));
                assert!(
                    (-1e-4..=PI / 2.0 + 1e-4).contains(&a),
                    "{method:?}: angle {a}"
                );
                prev = d;
            }
            let end = sol.joints[3];
            if target.z == 0.0 || method == ChainMethod::Ccd {
                // Reachable in the plane (10, 67 and 66 degrees): reached, or its projection.
                assert!(
                    (end.truncate() - target.truncate()).length() < 1e-4,
                    "{method:?}: {end}"
                );
            }
        }
    }
}

#[test]
fn cone_on_bone_zero_is_measured_from_its_rest_direction() {
    let rest = [Vec3::ZERO, Vec3::Y * 0.5, Vec3::Y * 1.0];
    let constraints = vec![Some(JointLimit::Cone { max_angle: 0.3 }), None];
    for method in METHODS {
        let mut s = solver(method, &rest, constraints.clone(), 100);
        // Straight out sideways, out of reach: bone 0 stops at the cone's edge.
        let sol = s.solve(Vec3::X * 3.0, None).unwrap();
        let d0 = (sol.joints[1] - sol.joints[0]).normalize();
        assert!(
            (angle_between(d0, Vec3::Y) - 0.3).abs() < 1e-5,
            "{method:?}: {d0}"
        );
        assert!(d0.x > 0.0 && d0.z.abs() < 1e-5);
        // Bone 1 is free: it points at the target.
        let d1 = (sol.joints[2] - sol.joints[1]).normalize();
        assert!((d1 - (Vec3::X * 3.0 - sol.joints[1]).normalize()).length() < 1e-3);
    }
}

#[test]
fn end_rotation_pins_the_last_bone() {
    let rest = [Vec3::ZERO, Vec3::X * 0.3, Vec3::X * 0.55, Vec3::X * 0.65];
    let q = Quat::from_rotation_z(-PI / 2.0); // last bone pointing down (-Y)
    let target = Vec3::new(0.35, -0.1, 0.1);
    for method in METHODS {
        let mut s = solver(method, &rest, vec![], 500);
        let goal = ChainGoal {
            end_rotation: Some(q),
            ..ChainGoal::new(target, None)
        };
        let sol = s.solve_goal(&goal).unwrap();
        let last = (sol.joints[3] - sol.joints[2]).normalize();
        assert!((last - Vec3::NEG_Y).length() < 1e-5, "{method:?}: {last}");
        assert!(sol.status.error < 1e-4, "{method:?}: {}", sol.status.error);
        assert!(sol.rotations[2].dot(q).abs() > 1.0 - 1e-6);
    }
}

#[test]
fn degenerate_setups_are_errors_naming_the_field() {
    let ok = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0];
    let make = |joints: Vec<Vec3>, constraints: Vec<Option<JointLimit>>| {
        ChainSolver::new(&ChainSolverOptions {
            joints,
            constraints,
            ..ChainSolverOptions::default()
        })
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    let e = make(ok[..2].to_vec(), vec![]);
    assert!(e.starts_with("joints:") && e.contains("at least 3"), "{e}");
    let mut zero = ok.clone();
    zero[3] = zero[2];
    let e = make(zero, vec![]);
    assert!(e.starts_with("joints[3]:"), "{e}");
    let mut nan = ok.clone();
    nan[1].y = f32::NAN;
    let e = make(nan, vec![]);
    assert!(e.starts_with("joints[1]:"), "{e}");
    // Finite but beyond the coordinate limit (a bone that long overflows f32's squares).
    let mut huge = ok.clone();
    huge[2] = Vec3::splat(3e19);
    let e = make(huge, vec![]);
    assert!(
        e.starts_with("joints[2]:") && e.contains("within -1e9..1e9"),
        "{e}"
    );
    let mut far = ok.clone();
    far[3].x = 1.01e9;
    assert!(make(far, vec![]).starts_with("joints[3]:"));
    let mut at_limit = ok.clone();
    at_limit[3].x = 1e9;
    let mut solver = ChainSolver::new(&ChainSolverOptions {
        joints: at_limit,
        ..ChainSolverOptions::default()
    })
    .expect("a joint at the limit");
    let sol = solver
        .solve(Vec3::new(1e9, 0.0, 0.0), None)
        .expect("a target at the limit");
    assert!(sol.joints.iter().all(|p| p.is_finite()) && sol.status.error.is_finite());
    for bad in [Vec3::new(1.01e9, 0.0, 0.0), Vec3::new(0.0, -2e19, 0.0)] {
        let e = solver.solve(bad, None).map(|_| ()).unwrap_err().to_string();
        assert_eq!(e, "target: must be three numbers within -1e9..1e9");
        let e = solver
            .solve(Vec3::Y, Some(bad))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert_eq!(e, "pole: must be three numbers within -1e9..1e9");
    }
    let e = make(ok.clone(), vec![None]);
    assert!(e.starts_with("constraints:"), "{e}");
    let e = make(
        ok.clone(),
        vec![None, Some(JointLimit::Cone { max_angle: -1.0 }), None],
    );
    assert!(e.starts_with("constraints[1].maxAngle:"), "{e}");
    let e = make(
        ok.clone(),
        vec![
            None,
            None,
            Some(JointLimit::Hinge {
                axis: Vec3::ZERO,
                min: 0.0,
                max: 1.0,
            }),
        ],
    );
    assert!(e.starts_with("constraints[2].axis:"), "{e}");
    for (iterations, tolerance, step, field) in [
        (Some(0), None, None, "iterations"),
        (None, Some(0.0), None, "tolerance"),
        (None, Some(f32::NAN), None, "tolerance"),
    ] {
        for method in METHODS {
            let e = ChainSolver::new(&ChainSolverOptions {
                method,
                joints: ok.clone(),
                iterations,
                tolerance,
                max_step_angle: step,
                ..ChainSolverOptions::default()
            })
            .map(|_| ())
            .unwrap_err()
            .to_string();
            assert!(e.starts_with(field), "{method:?}: {e}");
        }
    }
    let e = ChainSolver::new(&ChainSolverOptions {
        method: ChainMethod::Ccd,
        joints: ok,
        max_step_angle: Some(0.0),
        ..ChainSolverOptions::default()
    })
    .map(|_| ())
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("maxStepAngle"), "{e}");
}

#[test]
fn degenerate_goals_give_finite_poses_or_errors() {
    let rest = [Vec3::ZERO, Vec3::X * 0.4, Vec3::X * 0.7, Vec3::X * 0.9];
    for method in METHODS {
        let mut s = solver(method, &rest, vec![], 50);
        let on_line = Vec3::X * 0.5;
        for (target, pole) in [
            (Vec3::ZERO, None),                         // target at the root
            (Vec3::ZERO, Some(Vec3::Y)),                // ... with a pole
            (on_line, Some(Vec3::X * 0.25)),            // pole on the root-to-target line
            (on_line, Some(on_line)),                   // pole on the target
            (on_line, Some(Vec3::ZERO)),                // pole at the root
            (Vec3::X * 0.9, Some(Vec3::Y)),             // exactly at full reach
            (Vec3::new(0.2, 0.3, -0.1), Some(Vec3::Y)), // an ordinary one after all that
        ] {
            let sol = s.solve(target, pole).unwrap();
            assert!(
                sol.joints.iter().all(|p| p.is_finite())
                    && sol.rotations.iter().all(|q| q.is_finite())
                    && sol.status.error.is_finite(),
                "{method:?}: {target} {pole:?}"
            );
            for (l, r) in lengths(sol.joints).iter().zip(lengths(&rest)) {
                assert!((l - r).abs() < 1e-5, "{method:?}: {target} {pole:?}");
            }
        }
        // The chain is 0.4 + 0.3 + 0.2: folded, the end reaches the root exactly.
        let sol = s.solve(Vec3::ZERO, Some(Vec3::Y)).unwrap();
        assert!(sol.status.error < 1e-3, "{method:?}: {}", sol.status.error);
        let before = s.solution().joints.to_vec();
        let e = s.solve(Vec3::new(f32::NAN, 0.0, 0.0), None).unwrap_err();
        assert!(e.to_string().starts_with("target:"), "{e}");
        let e = s
            .solve(Vec3::X, Some(Vec3::splat(f32::INFINITY)))
            .unwrap_err();
        assert!(e.to_string().starts_with("pole:"), "{e}");
        assert_eq!(s.solution().joints, &before[..], "an error leaves the pose");
    }
}

#[test]
fn solve_into_writes_the_same_numbers_and_checks_lengths() {
    let rest = [Vec3::ZERO, Vec3::Y * 0.3, Vec3::Y * 0.5, Vec3::Y * 0.6];
    for method in METHODS {
        let mut a = solver(method, &rest, vec![], 40);
        let mut b = a.clone();
        let target = Vec3::new(0.2, 0.2, 0.1);
        let sol = a.solve(target, Some(Vec3::Z)).unwrap();
        let mut joints = [0.0f32; 12];
        let mut rotations = [0.0f32; 12];
        let status = b
            .solve_into(target, Some(Vec3::Z), &mut joints, &mut rotations)
            .unwrap();
        assert_eq!(status, sol.status);
        for (k, p) in sol.joints.iter().enumerate() {
            assert_eq!(p.to_array(), joints[3 * k..3 * k + 3]);
        }
        for (k, q) in sol.rotations.iter().enumerate() {
            assert_eq!(q.to_array(), rotations[4 * k..4 * k + 4]);
        }
        let e = b
            .solve_into(target, None, &mut joints[..9], &mut rotations)
            .unwrap_err();
        assert!(e.to_string().starts_with("out.joints"), "{e}");
        let e = b
            .solve_into(target, None, &mut joints, &mut rotations[..8])
            .unwrap_err();
        assert!(e.to_string().starts_with("out.rotations"), "{e}");
    }
}

#[test]
fn options_deserialize_from_the_js_shape() {
    let json = r#"{
        "method": "ccd",
        "joints": [[0, 0, 0], [0, 1, 0], [0, 2, 0]],
        "constraints": [null, { "type": "hinge", "axis": [0, 0, 1], "min": -1, "max": 1 }],
        "iterations": 12,
        "tolerance": 0.001
    }"#;
    let o = ChainSolverOptions::from_json(json).unwrap();
    assert_eq!(o.method, ChainMethod::Ccd);
    assert_eq!(o.joints[2], Vec3::new(0.0, 2.0, 0.0));
    assert_eq!(
        o.constraints[1],
        Some(JointLimit::Hinge {
            axis: Vec3::Z,
            min: -1.0,
            max: 1.0
        })
    );
    let s = ChainSolver::new(&o).unwrap();
    assert_eq!(s.method(), ChainMethod::Ccd);
    // A limit as the first constraint of otherwise valid options.
    let limit = |text: &str| {
        ChainSolverOptions::from_json(&format!(r#"{{ "joints": [], "constraints": [{text}] }}"#))
            .map(|o| o.constraints[0])
    };
    let cone = limit(r#"{ "type": "cone", "maxAngle": 0.5 }"#).unwrap();
    assert_eq!(cone, Some(JointLimit::Cone { max_angle: 0.5 }));
    // Each message names the field, down to the limit's own.
    for (text, field, problem) in [
        (
            r#"{ "type": "ball" }"#,
            "options.constraints[0].type",
            r#"must be "cone" or "hinge", got "ball""#,
        ),
        (
            r#"{ "maxAngle": 0.5 }"#,
            "options.constraints[0].type",
            "got nothing",
        ),
        (
            r#"{ "type": "cone", "maxAngle": 0.5, "axis": [0, 0, 1] }"#,
            "options.constraints[0].axis",
            "unknown field (expected one of type, maxAngle)",
        ),
        (
            r#"{ "type": "hinge", "axis": [0, 0, 1], "min": -1 }"#,
            "options.constraints[0].max",
            "missing",
        ),
        (
            r#"{ "type": "hinge", "axis": [0, 1], "min": -1, "max": 1 }"#,
            "options.constraints[0].axis",
            "must be three numbers [x, y, z], got an array of 2",
        ),
        (
            r#"{ "type": "cone", "maxAngle": "1" }"#,
            "options.constraints[0].maxAngle",
            r#"must be a number, got "1""#,
        ),
        ("3", "options.constraints[0]", "or null, got 3"),
    ] {
        let m = limit(text).unwrap_err().to_string();
        assert!(m.starts_with(field) && m.contains(problem), "{text}: {m}");
    }
    for (text, field, problem) in [
        (
            r#"{ "joints": [], "extra": 1 }"#,
            "options.extra",
            "unknown option (expected one of method, joints,",
        ),
        (
            r#"{ "method": "ccd" }"#,
            "options.joints",
            "must be an array of [x, y, z] rest joint positions, root first, got nothing",
        ),
        (
            r#"{ "joints": [[0, 0, 0], [0, 1, "2"]] }"#,
            "options.joints[1][2]",
            r#"must be a number, got "2""#,
        ),
        (
            r#"{ "joints": [], "method": "jacobian" }"#,
            "options.method",
            r#"must be "fabrik" or "ccd", got "jacobian""#,
        ),
        (
            r#"{ "joints": [], "iterations": 1.5 }"#,
            "options.iterations",
            "must be a whole number, got 1.5",
        ),
        (
            r#"{ "joints": [], "iterations": -2 }"#,
            "options.iterations",
            "must be a whole number, got -2",
        ),
        (
            r#"{ "joints": [], "tolerance": true }"#,
            "options.tolerance",
            "must be a number, got true",
        ),
        ("[1, 2]", "options", "must be an object"),
        ("{ not json", "options", "key must be a string"),
    ] {
        let m = ChainSolverOptions::from_json(text).unwrap_err().to_string();
        assert!(m.starts_with(field) && m.contains(problem), "{text}: {m}");
    }
    // null for an optional number: unset.
    let o = ChainSolverOptions::from_json(r#"{ "joints": [], "tolerance": null }"#).unwrap();
    assert_eq!(o.tolerance, None);
    // null constraints: none, as when left out (issue 49: from JS, `constraints: null` or
    // `undefined` failed with a serde type error).
    let o = ChainSolverOptions::from_json(r#"{ "joints": [], "constraints": null }"#).unwrap();
    assert!(o.constraints.is_empty());
}

#[test]
fn warm_start_follows_a_moving_target_continuously() {
    // A 6-bone tail following a target around a circle: consecutive poses move little (no
    // jumps between solutions), for both methods.
    let rest: Vec<Vec3> = (0..7).map(|k| Vec3::Y * (0.1 * k as f32)).collect();
    for method in METHODS {
        let mut s = solver(method, &rest, vec![], 100);
        let mut prev: Option<Vec<Vec3>> = None;
        let mut worst = 0.0f32;
        for i in 0..=360 {
            let a = (i as f32).to_radians();
            let target = Vec3::new(0.3 * a.cos(), 0.35, 0.3 * a.sin());
            let sol = s
                .solve(target, Some(Vec3::new(0.0, 0.3, 0.0) - target))
                .unwrap();
            assert!(
                sol.status.reached,
                "{method:?} frame {i}: {}",
                sol.status.error
            );
            if let Some(p) = &prev {
                for (a, b) in p.iter().zip(sol.joints) {
                    worst = worst.max((*a - *b).length());
                }
            }
            prev = Some(sol.joints.to_vec());
        }
        println!("{method:?}: largest joint step {worst:.4} m for a 5.2 mm target step");
        assert!(worst < 0.03, "{method:?}: a joint jumped {worst} m");
    }
}

#[test]
fn ccd_priority_effectors_keep_the_first_and_use_what_is_left() {
    // Three bones along +X. Two effectors that cannot both be met: the end toward `t`, and
    // joint 1 toward `p` (straight down from the root, one bone length away).
    let chain = Chain::new(
        &[Vec3::ZERO, Vec3::X * 0.3, Vec3::X * 0.6, Vec3::X * 0.8],
        &[],
    )
    .unwrap();
    let root = chain.rest_root();
    let ccd = Ccd::new(CcdOptions {
        iterations: 500,
        ..CcdOptions::default()
    })
    .unwrap();
    let t = Vec3::new(0.4, 0.3, 0.1);
    let p = Vec3::new(0.0, -0.3, 0.0);
    let end = Effector::end(&chain, t);
    let elbow = Effector {
        joint: 1,
        offset: Vec3::ZERO,
        target: p,
        first_joint: 0,
    };
    let mut frames = [Quat::IDENTITY; 3];
    let solve = |effectors: &[Effector], frames: &mut [Quat]| {
        let mut joints = chain.rest_joints().to_vec();
        let report = ccd.solve(
            &chain,
            &root,
            effectors,
            handrig::ik::ccd::Guides::default(),
            &mut joints,
            frames,
        );
        (joints, report)
    };
    // The end alone, then the end first and joint 1 second: the end is reached either way,
    // and the second effector pulls joint 1 toward p with the freedom the first leaves it at
    // the root, the turn about the root-to-end line: joint 1 ends at the point of its circle
    // about that line nearest p.
    let (alone, _) = solve(&[end], &mut frames);
    let (both, report) = solve(&[end, elbow], &mut frames);
    assert!(
        report.reached && (both[3] - t).length() < 1e-4,
        "{report:?}"
    );
    let axis = t.normalize();
    let (height, radius) = (axis.dot(both[1]), across(both[1], axis).length());
    let nearest =
        ((height - axis.dot(p)).powi(2) + (radius - across(p, axis).length()).powi(2)).sqrt();
    let (d_alone, d_both) = ((alone[1] - p).length(), (both[1] - p).length());
    assert!(
        (d_both - nearest).abs() < 1e-4,
        "joint 1 {d_both} m from p, nearest {nearest}"
    );
    assert!(
        d_both < d_alone - 0.01,
        "joint 1 {d_both} m from p, {d_alone} without it"
    );
    // Joint 1 first: it lands on p (exactly one bone length away); the end, second, gets as
    // close as the remaining 0.5 m allow from there: |t - p| = 0.73 m.
    let (swapped, report) = solve(&[elbow, end], &mut frames);
    assert!((swapped[1] - p).length() < 1e-4 && report.reached);
    let gap = (swapped[3] - t).length();
    assert!(
        (gap - ((t - p).length() - 0.5)).abs() < 1e-3,
        "end {gap} m from t"
    );
}
