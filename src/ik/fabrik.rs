//! FABRIK, Forward And Backward Reaching Inverse Kinematics (seed 002; Aristidou and
//! Lasenby, "FABRIK: A fast, iterative solver for the Inverse Kinematics problem", Graphical
//! Models 73(5), 2011).
//!
//! The chain is a list of points joined by fixed-length bones. One iteration:
//!
//! 1. **Pole**: turn the middle joints rigidly about the line from the pivot (the joint before
//!    the first turned joint; the root for a plain chain) to the target so that their bend
//!    faces the pole ([`turn_toward_pole`]). Lengths and the angles between bones are kept.
//! 2. **Backward reach**: the end goes to the target; each joint, end to root, slides along
//!    the line to its child until it is one bone length away.
//! 3. **Forward reach**: the root goes back to its fixed place; each bone, root to end,
//!    points toward its child's backward-pass position, *limited by its joint constraint in
//!    its parent's frame* ([`Chain::place`]), as the seed insists: constraints applied during
//!    the forward pass, so no bone snaps backwards and the output always satisfies them.
//!
//! The loop stops early once the end is within `tolerance` of the target and the pole step
//! turned less than `tolerance / chain length` radians. A target beyond the chain's length
//! gives the straight chain toward it (limits permitting) without iterating. With an end
//! rotation the last bone is pinned to that rotation's direction through the target, and the
//! rest of the chain reaches the last bone's root.
//!
//! A chain lying straight along the line to a nearer target is first bowed toward the pole
//! ([`bow_if_straight`]): from a straight chain the passes could only fold it onto the line.
//!
//! [`super::FabrikArm`] is the arm solver built on it ([`super::ArmSolver::Fabrik`]).

use glam::{Quat, Vec3};

use crate::error::Result;
use crate::kinematics::chain::{bow_if_straight, turn_toward_pole};
use crate::kinematics::iterative::{
    anchor, bow_fallback, face_pole, sub_min_reach, validate_iterations,
};
use crate::kinematics::{Chain, JointLimit, Pull, RootFrame};

use super::goal::{ChainGoal, ChainReport};

/// Options of [`Fabrik`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FabrikOptions {
    /// Most backward-and-forward iterations per solve. Default 100, a cap rarely reached:
    /// warm-started from the previous frame, arm solves on the recordings take 1.4 to 3.8 on
    /// average and at most 9 for 95% of frames, but a strongly folded arm (a hand at the face)
    /// converges slowly and needed more than 20 (see `eval/rust/eval_alignment.rs`).
    pub iterations: u32,
    /// Distance (m) between end and target that counts as reached. Default 1e-5 (0.01 mm).
    pub tolerance: f32,
}

impl Default for FabrikOptions {
    fn default() -> Self {
        FabrikOptions {
            iterations: 100,
            tolerance: 1e-5,
        }
    }
}

impl FabrikOptions {
    /// Checks ranges.
    ///
    /// # Errors
    /// `iterations` of 0 (field `iterations`) or a `tolerance` that is not a positive finite
    /// number (field `tolerance`).
    pub fn validate(&self) -> Result<()> {
        validate_iterations(self.iterations, self.tolerance)
    }
}

/// The FABRIK solver (stateless: the chain's pose is the caller's `joints`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fabrik {
    options: FabrikOptions,
}

impl Fabrik {
    /// A solver with `options`.
    ///
    /// # Errors
    /// Options out of range ([`FabrikOptions::validate`]).
    pub fn new(options: FabrikOptions) -> Result<Self> {
        options.validate()?;
        Ok(Fabrik { options })
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &FabrikOptions {
        &self.options
    }

    /// Moves `joints` (one per chain joint: the current pose, the warm start) to reach
    /// `goal` with the root at `root`. The pose is first translated so that joint 0 is at
    /// the root. `frames` (one per bone) receives each bone's world rotation from its rest
    /// direction, in which the limits hold (see [`Chain::place`]). Allocates nothing; never
    /// writes NaN for finite inputs (a non-finite target leaves the pose as it is and reports
    /// an infinite error).
    pub fn solve(
        &self,
        chain: &Chain,
        root: &RootFrame,
        goal: &ChainGoal,
        joints: &mut [Vec3],
        frames: &mut [Quat],
    ) -> ChainReport {
        let n = chain.joint_count();
        debug_assert_eq!(joints.len(), n);
        let last = n - 1;
        let lengths = chain.lengths();
        anchor(joints, root, chain);
        if !goal.target.is_finite() {
            return ChainReport::failed();
        }
        // With an end rotation the last bone is pinned: reach its root instead.
        let end_direction = goal.end_direction(chain);
        let (reach_target, reach_length, reach_joint) = match end_direction {
            Some(d) => (
                goal.target - d * lengths[last - 1],
                chain.total_length() - lengths[last - 1],
                last - 1,
            ),
            None => (goal.target, chain.total_length(), last),
        };
        let distance = (reach_target - root.position).length();
        let reachable = reach_joint > 0
            && distance <= reach_length * (1.0 + 1e-6)
            && distance >= sub_min_reach(&lengths[..reach_joint]) * (1.0 - 1e-6);
        let tolerance = self.options.tolerance;
        let angle_tolerance = tolerance / chain.total_length();
        // Stop a little inside the tolerance: the last pole step re-lays the bones, which
        // moves the end by rounding.
        let converged = 0.9 * tolerance;
        let pole = goal.pole.filter(|p| p.is_finite());
        let first = goal.pole_first.clamp(1, reach_joint.max(1));
        // Limits between bones also act on the backward pass (see `limit_backward`); hinges
        // need the bone frames for their axes.
        let backward_limits = (1..chain.bone_count()).any(|i| chain.limit(i).is_some());
        let hinged =
            (1..chain.bone_count()).any(|i| chain.limit(i).and_then(|l| l.hinge_axis()).is_some());

        if distance >= reach_length {
            chain.place(
                root,
                joints,
                Pull::Toward(reach_target),
                end_direction,
                frames,
            );
            return ChainReport::measure(joints[last], goal.target, reachable, 0, tolerance);
        }

        let side = pole.unwrap_or_else(|| bow_fallback(chain, root, joints, reach_target));
        let mut iterations = 0;
        while iterations < self.options.iterations {
            let turned = pole.map_or(0.0, |p| {
                turn_toward_pole(&mut joints[..=reach_joint], first, reach_target, p, true)
            });
            if (joints[last] - goal.target).length() <= converged && turned <= angle_tolerance {
                break;
            }
            let bow_side = side - joints[first - 1];
            bow_if_straight(
                &mut joints[..=reach_joint],
                first,
                lengths,
                reach_target,
                bow_side,
            );
            if hinged {
                chain.rotations(root.rotation, joints, frames);
            }
            // Backward reach.
            joints[last] = goal.target;
            if let Some(d) = end_direction {
                joints[last - 1] = goal.target - d * lengths[last - 1];
            }
            for i in (0..reach_joint).rev() {
                let mut away = (joints[i] - joints[i + 1])
                    .try_normalize()
                    .filter(|d| d.is_finite())
                    .unwrap_or(-(root.rotation * chain.rest_directions()[i]));
                if backward_limits && i + 1 < chain.bone_count() {
                    if let Some(limit) = chain.limit(i + 1) {
                        let child = (joints[i + 2] - joints[i + 1]).normalize();
                        away = -limit_backward(&limit, -away, child, frames[i]);
                    }
                }
                joints[i] = joints[i + 1] + away * lengths[i];
            }
            // Forward reach, limits applied bone by bone.
            chain.place(root, joints, Pull::Points, end_direction, frames);
            iterations += 1;
        }
        face_pole(chain, joints, first, reach_joint, pole);
        // Lay the bones out once more from the root along their directions: exact lengths
        // after the pole's turns (which round each joint separately; the end moves by
        // rounding only), and `frames` the rotations the limits hold in, also when the loop
        // had nothing to do.
        chain.place(root, joints, Pull::Directions, end_direction, frames);
        ChainReport::measure(joints[last], goal.target, reachable, iterations, tolerance)
    }
}

/// The backward pass's limit: the parent bone's direction (world, unit) nearest `wanted` such
/// that the child bone's direction `child` satisfies the child's `limit` relative to it. A
/// cone is symmetric (the angle between the two bones); a hinge needs the parent in the plane
/// perpendicular to its world axis (`frame`, the parent's rotation in the pose before this
/// pass, carries the axis) with the child's angle about it in range. The forward pass then
/// applies the limits exactly; this keeps the backward pass from proposing shapes the forward
/// pass can only clamp (FABRIK stalls on one-sided hinges without it).
fn limit_backward(limit: &JointLimit, wanted: Vec3, child: Vec3, frame: Quat) -> Vec3 {
    match *limit {
        JointLimit::Cone { .. } => limit.constrain(wanted, child, wanted),
        JointLimit::Hinge { axis, min, max } => {
            let w = (frame * axis).normalize();
            let c = (child - w * w.dot(child)).try_normalize();
            let p = (wanted - w * w.dot(wanted)).try_normalize();
            let Some(c) = c else {
                return wanted;
            };
            // The child's signed angle about the axis from the parent.
            let angle = p.map_or(0.0, |p| w.dot(p.cross(c)).atan2(p.dot(c)));
            let clamped = crate::math::clamp(angle, min, max);
            Quat::from_axis_angle(w, -clamped) * c
        }
    }
}
