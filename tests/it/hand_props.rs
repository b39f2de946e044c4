//! Property tests: random in-limit hand poses on random avatars, placements and proportions
//! are recovered within 1 degree, with unit, finite outputs.

use crate::support::hand_model;

use glam::{EulerRot, Quat, Vec3};
use hand_model::{avatar, place, Angles, HandLayout, HandModel};
use handrig::hand::{Dof, HandSolver, HandStatus, HandStrategy, LIMITS};
use handrig::{Finger, Side, WorldPose, BONE_COUNT};
use proptest::prelude::*;

/// Margin kept from every limit (degrees) so "inside the limits" is unambiguous.
const MARGIN: f32 = 3.0;

fn angles_strategy() -> impl Strategy<Value = Angles> {
    proptest::collection::vec(0.0f32..1.0, 20).prop_map(|u| {
        let mut a = [[0.0f32; 4]; 5];
        for finger in Finger::ALL {
            for dof in [Dof::Base0, Dof::Base1, Dof::Hinge1, Dof::Hinge2] {
                let r = LIMITS[finger.index()][dof.index()];
                let (lo, hi) = (r.min_deg + MARGIN, r.max_deg - MARGIN);
                let mut lo = lo;
                if finger == Finger::Thumb && dof == Dof::Base0 {
                    // The opposition angle is undefined with the thumb along the index
                    // metacarpal; real thumbs never get there.
                    lo = lo.max(10.0);
                }
                let v = lo + (hi - lo) * u[finger.index() * 4 + dof.index()];
                a[finger.index()][dof.index()] = v.to_radians();
            }
            // A straight finger pointing at the palm normal has no defined abduction (the
            // abduction then turns it about its own axis); bend it a little there.
            let f = &mut a[finger.index()];
            if finger != Finger::Thumb
                && (f[0].to_degrees() - 90.0).abs() < 10.0
                && f[2].to_degrees().abs() < 10.0
            {
                f[2] = 20f32.to_radians();
            }
        }
        a
    })
}

fn layout_strategy() -> impl Strategy<Value = HandLayout> {
    (0usize..5, -1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(kind, a, b, c)| {
        let base = HandLayout::standard();
        match kind {
            0 => base,
            1 => base.rotated(Quat::from_euler(EulerRot::XYZ, a, b, c)),
            2 => base.relaxed(
                0.25 * a.abs(),
                [0.1 * b, 0.05 * c, -0.05 * b, -0.15 * c.abs()],
            ),
            _ => base
                .drooping_thumb()
                .rotated(Quat::from_euler(EulerRot::ZXY, a, 0.5 * b, c)),
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_in_limit_poses_are_recovered(
        angles in angles_strategy(),
        layout in layout_strategy(),
        left in any::<bool>(),
        (yaw, pitch, roll) in (-3.1f32..3.1, -1.5f32..1.5, -3.1f32..3.1),
        scale in 0.5f32..2.0,
        stretch in proptest::collection::vec(0.7f32..1.4, 15),
        offset in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
    ) {
        let side = if left { Side::Left } else { Side::Right };
        let skel = avatar(&layout, &[]);
        let model = HandModel::from_skeleton(&skel, side);
        let mut st = [[1.0f32; 3]; 5];
        for (i, s) in stretch.iter().enumerate() {
            st[i / 3][i % 3] = *s;
        }
        let q = Quat::from_euler(EulerRot::YXZ, yaw, pitch, roll);
        let lm_model = model.landmarks(&angles, &st);
        let lm = place(&lm_model, q, scale, Vec3::new(offset.0, offset.1, offset.2));
        let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        let hand = solver.solve(&skel, side, &lm, &mut local);
        prop_assert!(hand.is_some());
        let hand = hand.unwrap();
        let rep = *solver.report(side);
        prop_assert_eq!(rep.status, HandStatus::Solved);
        prop_assert!(!rep.any_limited(), "limits {:?}", rep.limited);
        prop_assert!((2.0 * hand.dot(q).abs().min(1.0).acos()).to_degrees() < 0.5);
        for qq in local.iter().chain([&hand]) {
            prop_assert!(qq.is_finite() && (qq.length() - 1.0).abs() < 1e-4);
        }
        for finger in Finger::ALL {
            for dof in [Dof::Base0, Dof::Base1, Dof::Hinge1, Dof::Hinge2] {
                let got = rep.angle(finger, dof).to_degrees();
                let want = angles[finger.index()][dof.index()].to_degrees();
                prop_assert!((got - want).abs() < 1.0, "{:?} {}: {} vs {}", finger, dof.name(finger), got, want);
            }
        }
        // Avatar bones point along the model's segments (hand at rest orientation).
        let mut world = WorldPose::default();
        skel.forward(&local, &mut world);
        for finger in Finger::ALL {
            let bones = side.finger(finger);
            let ids = finger.landmarks();
            for slot in 0..2 {
                let a = (world.position[bones[slot + 1].index()] - world.position[bones[slot].index()]).normalize();
                let m = (lm_model[ids[slot + 1]] - lm_model[ids[slot]]).normalize();
                prop_assert!(a.dot(m).clamp(-1.0, 1.0).acos().to_degrees() < 1.0, "{:?} {}", finger, slot);
            }
        }
    }

    #[test]
    fn arbitrary_landmarks_never_give_nan(
        pts in proptest::collection::vec((-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0), 21),
        left in any::<bool>(),
        collapse in 0usize..4,
    ) {
        let side = if left { Side::Left } else { Side::Right };
        let skel = avatar(&HandLayout::standard(), &[]);
        let mut lm = [Vec3::ZERO; 21];
        for (l, p) in lm.iter_mut().zip(&pts) {
            *l = Vec3::new(p.0, p.1, p.2) * 0.1;
        }
        // Some degenerate shapes: fingers collapsed onto their base, or onto the wrist.
        match collapse {
            1 => for f in Finger::ALL { let ids = f.landmarks(); for k in 1..4 { lm[ids[k]] = lm[ids[0]]; } },
            2 => { let w = lm[0]; for l in lm.iter_mut().skip(1) { *l = w + (*l - w) * 1e-9; } },
            3 => for f in Finger::ALL { let ids = f.landmarks(); lm[ids[3]] = lm[ids[2]]; },
            _ => {}
        }
        let mut solver = HandSolver::new(&skel, HandStrategy::Analytic).unwrap();
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        if let Some(hand) = solver.solve(&skel, side, &lm, &mut local) {
            prop_assert!(hand.is_finite() && (hand.length() - 1.0).abs() < 1e-4);
        }
        for q in &local {
            prop_assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-4);
        }
        for a in solver.report(side).angles.iter().flatten() {
            prop_assert!(a.is_finite());
        }
    }
}
