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
//! [`FabrikArm`] is the arm solver built on it ([`super::ArmSolver::Fabrik`]).

use glam::Vec3;

use crate::error::{Error, Result};
use crate::kinematics::chain::{bow_if_straight, turn_toward_pole};
use crate::kinematics::{Chain, Pull, RootFrame};

use super::arm::ChainArm;
use super::{ArmChain, ArmGoal, ArmIk, ArmOptions, ArmPose, ArmReach, ChainGoal, ChainReport};

/// Options of [`Fabrik`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FabrikOptions {
    /// Most backward-and-forward iterations per solve. Default 20: with a warm start from the
    /// previous frame, arm solves on real recordings need a few (see `examples/eval_alignment.rs`).
    pub iterations: u32,
    /// Distance (m) between end and target that counts as reached. Default 1e-5 (0.01 mm).
    pub tolerance: f32,
}

impl Default for FabrikOptions {
    fn default() -> Self {
        FabrikOptions {
            iterations: 20,
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
    /// the root. Allocates nothing; never writes NaN for finite inputs (a non-finite target
    /// leaves the pose as it is and reports an infinite error).
    pub fn solve(
        &self,
        chain: &Chain,
        root: &RootFrame,
        goal: &ChainGoal,
        joints: &mut [Vec3],
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
        let pole = goal.pole.filter(|p| p.is_finite());
        let first = goal.pole_first.clamp(1, last);

        if distance >= reach_length {
            chain.place(root, joints, Pull::Toward(reach_target), end_direction);
            return ChainReport::measure(joints[last], goal.target, reachable, 0, tolerance);
        }

        let side = pole.unwrap_or_else(|| bow_fallback(chain, root, joints, reach_target));
        let mut iterations = 0;
        while iterations < self.options.iterations {
            let turned = pole.map_or(0.0, |p| turn_toward_pole(joints, first, goal.target, p));
            if (joints[last] - goal.target).length() <= tolerance && turned <= angle_tolerance {
                break;
            }
            bow_if_straight(
                joints,
                first,
                lengths,
                reach_target,
                side - joints[first - 1],
            );
            // Backward reach.
            joints[last] = goal.target;
            if let Some(d) = end_direction {
                joints[last - 1] = goal.target - d * lengths[last - 1];
            }
            for i in (0..reach_joint).rev() {
                let away = (joints[i] - joints[i + 1])
                    .try_normalize()
                    .filter(|d| d.is_finite())
                    .unwrap_or(-(root.rotation * chain.rest_directions()[i]));
                joints[i] = joints[i + 1] + away * lengths[i];
            }
            // Forward reach, limits applied bone by bone.
            chain.place(root, joints, Pull::Points, end_direction);
            iterations += 1;
        }
        // Without limits a last turn about the root-to-end line is exact (an isometry that
        // keeps the end where it is): the bend faces the pole to rounding.
        if let Some(p) = pole {
            if rigid_turn_allowed(chain, first) {
                turn_toward_pole(joints, first, joints[last], p);
            }
        }
        ChainReport::measure(joints[last], goal.target, reachable, iterations, tolerance)
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

/// FABRIK for one arm ([`super::ArmSolver::Fabrik`]): the arm chain (upper arm, forearm;
/// with [`ArmOptions::shoulder_angle`] the shoulder bone too, under a cone limit) reaches the
/// wrist target, the elbow turned toward the same bend direction the analytic solver uses
/// (pose elbow or default pole, with its continuity memory). Warm-started from the previous
/// frame. See [`super::arm`] for rotations and twist.
#[derive(Clone, Debug)]
pub struct FabrikArm {
    fabrik: Fabrik,
    arm: ChainArm,
}

impl FabrikArm {
    /// A FABRIK arm solver for `chain`.
    ///
    /// # Errors
    /// Options out of range.
    pub fn new(chain: &ArmChain, options: FabrikOptions, arm: &ArmOptions) -> Result<Self> {
        Ok(FabrikArm {
            fabrik: Fabrik::new(options)?,
            arm: ChainArm::new(chain, arm)?,
        })
    }

    /// The last solve's iteration count and convergence.
    #[must_use]
    pub fn last_report(&self) -> ChainReport {
        self.arm.last_report()
    }
}

impl ArmIk for FabrikArm {
    fn solve(&mut self, chain: &ArmChain, goal: &ArmGoal, out: &mut ArmPose) -> ArmReach {
        let fabrik = self.fabrik;
        self.arm
            .solve(chain, goal, out, |c, root, goal, _effectors, joints| {
                fabrik.solve(c, root, goal, joints)
            })
    }

    fn reset(&mut self) {
        self.arm.reset();
    }
}
