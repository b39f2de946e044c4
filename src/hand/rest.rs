//! The avatar's rest hand as the solver reads it: per finger bone its rest direction and hinge
//! axis, per finger the base joint's model, the rest palm frame. Computed once per avatar.

use glam::{Mat3, Vec3};

use crate::humanoid::bones::{Finger, HumanBone, Side};
use crate::humanoid::skeleton::Skeleton;

use super::chain::{Basis, Kind};
use super::palm::*;

/// Rest data of one present finger bone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BoneRest {
    pub(super) bone: HumanBone,
    /// Anatomical slot: 0 base, 1, 2 (index into `Side::finger`).
    pub(super) slot: usize,
    /// Rest direction (unit, internal frame = hand-local at rest).
    pub(super) dir: Vec3,
    /// Rest hinge axis (unit, perpendicular to `dir`).
    pub(super) hinge: Vec3,
    /// Rest flexion direction, `hinge x dir`.
    pub(super) flex: Vec3,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FingerRest {
    pub(super) bones: [Option<BoneRest>; 3],
    pub(super) count: usize,
    /// The base joint's model on the avatar's rest palm (the retargeting's joint model).
    pub(super) kind: Kind,
    pub(super) basis: Basis,
    /// Fingers: longitude of the avatar's wrist-to-knuckle line in `basis`.
    pub(super) lon_prior: f32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SideRest {
    pub(super) palm: PalmDef,
    /// Rest palm frame, columns `(f, r, n)`.
    pub(super) frame: Mat3,
    pub(super) fingers: [FingerRest; 5],
}

/// The rest palm frame and how to build the matching observed frame.
pub(super) fn rest_palm(skeleton: &Skeleton, side: Side) -> Option<(PalmDef, Mat3)> {
    let hand = skeleton.rest_world(side.hand())?;
    let prox: [Option<Vec3>; 4] =
        core::array::from_fn(|i| skeleton.rest_world(side.finger(Finger::ALL[i + 1])[0]));
    let forward_mask: u8 = if prox[1].is_some() {
        0b0010
    } else {
        (0..4)
            .filter(|i| prox[*i].is_some())
            .fold(0, |m, i| m | (1 << i))
    };
    let forward = if forward_mask != 0 {
        let (sum, n) = (0..4)
            .filter(|i| forward_mask & (1 << i) != 0)
            .fold((Vec3::ZERO, 0.0), |(s, n), i| {
                (s + prox[i].unwrap_or(hand), n + 1.0)
            });
        sum / n - hand
    } else {
        // No finger proximals: the hand continues the forearm.
        let elbow = skeleton.rest_world(side.arm()[2]);
        match elbow {
            Some(e) if (hand - e).length() > MIN_LENGTH => hand - e,
            _ => match side {
                Side::Left => Vec3::X,
                Side::Right => Vec3::NEG_X,
            },
        }
    };
    let radial_i = (0..4).find(|i| prox[*i].is_some());
    let ulnar_i = (0..4).rev().find(|i| prox[*i].is_some());
    let (across, pair) = match (radial_i, ulnar_i) {
        (Some(a), Some(b)) if a < b => (prox[a]? - prox[b]?, (a, b)),
        _ => {
            // Fewer than two proximals: VRM's T-pose has the palm facing down.
            let f = forward.try_normalize()?;
            (radial(side, f, Vec3::NEG_Y), (0, 3))
        }
    };
    let frame = frame_from(side, forward, across)?;
    Some((
        PalmDef {
            forward: forward_mask,
            across: pair,
        },
        frame,
    ))
}

pub(super) fn side_rest(skeleton: &Skeleton, side: Side) -> Option<SideRest> {
    let (palm, frame) = rest_palm(skeleton, side)?;
    let hand = skeleton.rest_world(side.hand())?;
    let (f, r, n) = (frame.x_axis, frame.y_axis, frame.z_axis);
    let prox = |finger: Finger| skeleton.rest_world(side.finger(finger)[0]);
    let mut fingers = [FingerRest {
        bones: [None; 3],
        count: 0,
        kind: Kind::Finger,
        basis: Basis { x: f, y: r, z: n },
        lon_prior: 0.0,
    }; 5];
    for finger in Finger::ALL {
        let bones = side.finger(finger);
        let mut present = [(HumanBone::Hips, 0usize, Vec3::ZERO); 3];
        let mut count = 0;
        for (slot, bone) in bones.into_iter().enumerate() {
            if let Some(p) = skeleton.rest_world(bone) {
                present[count] = (bone, slot, p);
                count += 1;
            }
        }
        if count == 0 {
            continue;
        }
        // Rest directions: joint to next joint; the last continues the previous one.
        let mut dirs = [f; 3];
        for i in 0..count {
            dirs[i] = if i + 1 < count {
                (present[i + 1].2 - present[i].2).try_normalize()
            } else if i > 0 {
                Some(dirs[i - 1])
            } else {
                (present[i].2 - hand).try_normalize()
            }
            .unwrap_or(if i > 0 { dirs[i - 1] } else { f });
        }
        let pole = match finger {
            Finger::Thumb => prox(Finger::Index)
                .and_then(|i| (i - hand).try_normalize())
                .unwrap_or(f),
            Finger::Ring => match (prox(Finger::Middle), prox(Finger::Ring)) {
                (Some(a), Some(b)) => local_pole(hand, a, b, n).unwrap_or(n),
                _ => n,
            },
            Finger::Little => match (prox(Finger::Ring), prox(Finger::Little)) {
                (Some(a), Some(b)) => local_pole(hand, a, b, n).unwrap_or(n),
                _ => n,
            },
            _ => n,
        };
        let (kind, basis) = basis_for(finger, f, r, n, pole);
        let (lon, colat) = basis.spherical(dirs[0]);
        let rule = basis
            .frame(kind, lon, colat)
            .hinge
            .try_normalize()
            .unwrap_or(r);
        let base_hinge = rest_hinge(&dirs[..count], rule);
        let mut rest = FingerRest {
            bones: [None; 3],
            count,
            kind,
            basis,
            lon_prior: basis
                .spherical((present[0].2 - hand).try_normalize().unwrap_or(f))
                .0,
        };
        for i in 0..count {
            let d = dirs[i];
            let hinge = (base_hinge - base_hinge.dot(d) * d)
                .try_normalize()
                .unwrap_or(base_hinge);
            rest.bones[i] = Some(BoneRest {
                bone: present[i].0,
                slot: present[i].1,
                dir: d,
                hinge,
                flex: hinge.cross(d),
            });
        }
        fingers[finger.index()] = rest;
    }
    Some(SideRest {
        palm,
        frame,
        fingers,
    })
}

/// Rest bends below this (radians) leave the anatomical hinge axis alone; above
/// [`BENT_REST`] the avatar's own bend plane is used.
pub(super) const STRAIGHT_REST: f32 = 1.0 * core::f32::consts::PI / 180.0;
/// See [`STRAIGHT_REST`].
pub(super) const BENT_REST: f32 = 3.0 * core::f32::consts::PI / 180.0;

/// The rest hinge axis of a finger whose rest bone directions are `dirs` (base first):
/// `rule` (the anatomical axis at the base's rest direction) for a straight rest finger; the
/// normal of the plane the rest finger is bent in when it is bent, so its joints can still
/// follow a planar finger exactly (a rigged thumb usually rests bent). Oriented like `rule`
/// (positive angles flex), perpendicular to the base direction; blended in between.
pub(super) fn rest_hinge(dirs: &[Vec3], rule: Vec3) -> Vec3 {
    let mut bend_normal = Vec3::ZERO;
    let mut bend = 0.0_f32;
    for pair in dirs.windows(2) {
        let c = pair[0].cross(pair[1]);
        bend = bend.max(c.length().clamp(0.0, 1.0).asin());
        bend_normal += if c.dot(rule) < 0.0 { -c } else { c };
    }
    let t = ((bend - STRAIGHT_REST) / (BENT_REST - STRAIGHT_REST)).clamp(0.0, 1.0);
    let w = t * t * (3.0 - 2.0 * t);
    let axis = match bend_normal.try_normalize() {
        Some(p) => rule.lerp(p, w),
        None => rule,
    };
    let d = dirs.first().copied().unwrap_or(Vec3::X);
    (axis - axis.dot(d) * d).try_normalize().unwrap_or(rule)
}
