//! Helpers shared by the iterative chain solvers ([`crate::ik::fabrik`] and
//! [`crate::ik::ccd`]): their options' check, the warm start's anchoring, the pole step and the
//! bow of a straight chain, so each solver file imports them from here and not from the other.

use glam::Vec3;

use super::chain::{settle_on_pole_side, turn_toward_pole};
use super::{Chain, RootFrame};
use crate::error::{Error, Result};

/// Checks an iteration count and a tolerance (shared by FABRIK and CCD options).
pub(crate) fn validate_iterations(iterations: u32, tolerance: f32) -> Result<()> {
    if iterations == 0 {
        return Err(Error::invalid("iterations", "must be at least 1"));
    }
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::invalid("tolerance", "must be a positive number"));
    }
    Ok(())
}

/// The last pole step on the sub-chain `..=reach_joint`, where the chain's limits allow it:
/// a turn about the pivot-to-end line (an isometry keeping the end where it is) so the bend
/// faces the pole to rounding, and without any limit past the pivot each middle joint turned
/// to the pole's side of its neighbours' line ([`settle_on_pole_side`]).
pub(crate) fn face_pole(
    chain: &Chain,
    joints: &mut [Vec3],
    first: usize,
    reach_joint: usize,
    pole: Option<Vec3>,
) {
    let Some(p) = pole else {
        return;
    };
    let sub = &mut joints[..=reach_joint];
    let end = sub[reach_joint];
    let pinned_free = reach_joint == chain.bone_count() || chain.limit(reach_joint).is_none();
    if rigid_turn_allowed(chain, first) && pinned_free {
        turn_toward_pole(sub, first, end, p, false);
    }
    if (first - 1..chain.bone_count()).all(|i| chain.limit(i).is_none()) {
        settle_on_pole_side(sub, first, p);
        turn_toward_pole(sub, first, end, p, false);
    }
}

/// Translates a warm-start pose so that joint 0 is at the root (the chain follows its root).
pub(crate) fn anchor(joints: &mut [Vec3], root: &RootFrame, chain: &Chain) {
    let shift = root.position - joints[0];
    if shift.is_finite() && joints.iter().all(|p| p.is_finite()) {
        joints.iter_mut().for_each(|p| *p += shift);
    } else {
        // A broken warm start (never produced by the solvers): back to rest.
        let rest = chain.rest_joints();
        for (p, r) in joints.iter_mut().zip(rest) {
            *p = root.position + root.rotation * (*r - rest[0]);
        }
    }
}

/// The nearest a sub-chain with `lengths` reaches toward its root.
pub(crate) fn sub_min_reach(lengths: &[f32]) -> f32 {
    let total: f32 = lengths.iter().sum();
    let longest = lengths.iter().copied().fold(0.0, f32::max);
    (2.0 * longest - total).max(0.0)
}

/// Whether turning joints `first..` rigidly about their pivot keeps every limit: no limit on
/// the bone into the first turned joint, and no hinges after it (hinge frames follow the
/// swing of each parent, which a rigid turn does not carry exactly). Cones between turned
/// bones measure angles the turn keeps.
pub(crate) fn rigid_turn_allowed(chain: &Chain, first: usize) -> bool {
    chain.limit(first - 1).is_none()
        && (first..chain.bone_count())
            .all(|i| chain.limit(i).and_then(|l| l.hinge_axis()).is_none())
}

/// A point to bow a straight chain toward when there is no pole: across the line to
/// `target`, on the side of the rest layout's bend (carried by the root frame), else any side.
pub(crate) fn bow_fallback(chain: &Chain, root: &RootFrame, joints: &[Vec3], target: Vec3) -> Vec3 {
    let rest = chain.rest_joints();
    let rest_line = (rest[rest.len() - 1] - rest[0]).normalize_or_zero();
    let rest_bend: Vec3 = rest[1..rest.len() - 1]
        .iter()
        .map(|p| {
            let v = *p - rest[0];
            v - rest_line * rest_line.dot(v)
        })
        .sum();
    let axis = (target - joints[0]).normalize_or_zero();
    let bend = root.rotation * rest_bend;
    let across = bend - axis * axis.dot(bend);
    let dir = if across.length() > 1e-6 * chain.total_length() {
        across
    } else {
        axis.any_orthonormal_vector()
    };
    joints[0] + dir
}
