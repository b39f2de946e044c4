//! CCD, Cyclic Coordinate Descent (seed 004; Wang and Chen, "A combined optimization method
//! for solving the inverse kinematics problem of mechanical manipulators", IEEE Trans.
//! Robotics and Automation 7(4), 1991).
//!
//! One iteration visits the joints from the end toward the root. At joint `k`, in the space
//! of its parent (the joint is the origin, as the seed transforms effector and target into
//! the parent's space), `v_c` is the direction to the effector and `v_d` the direction to
//! its target: the rotation axis is `v_c × v_d` and the angle comes from `v_c · v_d` (here
//! through `atan2` of both, accurate at every angle). The bone and everything after it turn
//! by that rotation about the joint, then:
//!
//! * **Hinge axes**: a hinged bone turns about its hinge axis only (carried by its parent):
//!   both vectors are projected onto the plane perpendicular to it first.
//! * **Limits**: the bone's direction is then limited in its parent's frame
//!   ([`crate::kinematics::JointLimit::constrain`]); after the sweep the chain is re-placed
//!   from the root with its directions kept ([`Chain::place`]), so the output satisfies every
//!   limit even where a turn moved a hinge's frame.
//! * **Damping**: no single turn exceeds [`CcdOptions::max_step_angle`].
//! * **Enforced priority** (the seed's priority effectors): several [`Effector`]s, highest
//!   priority first. At each joint the first effector turns freely; every later one may only
//!   turn about the line from the joint to the points of the higher-priority effectors it
//!   shares that joint with (a turn that leaves them where they are), and not at all when
//!   those points do not lie on one line through the joint. For an arm: the aligned finger
//!   point first, the wrist second, the elbow toward the pose elbow last, which leaves the
//!   elbow only the swivel about the shoulder-to-wrist line: it never pulls the hand off its
//!   target.
//!
//! An effector sits at a joint plus a *world-fixed* offset (the hand's world rotation is
//! prescribed by tracking, so the aligned finger point is the wrist plus a fixed vector while
//! the arm moves): turning joint `k` moves the joint, and the offset comes along unrotated.
//!
//! The loop stops once the first effector is within `tolerance` of its target and no turn of
//! the last sweep exceeded `tolerance / chain length` radians. A first effector whose target is
//! beyond its sub-chain's length gives the straight chain toward it without iterating.
//!
//! [`super::CcdArm`] is the arm solver built on it ([`super::ArmSolver::Ccd`]).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use crate::error::{Error, Result};
use crate::kinematics::chain::{angle_about, bow_if_straight, turn_toward_pole};
use crate::kinematics::iterative::{
    anchor, bow_fallback, face_pole, sub_min_reach, validate_iterations,
};
use crate::kinematics::{Chain, Pull, RootFrame};
use crate::math::angle_between;

use super::goal::{ChainReport, Effector};

/// Options of [`Ccd`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcdOptions {
    /// Most sweeps (end to root) per solve. Default 200, a cap: CCD converges more slowly
    /// than FABRIK, slowest near full stretch; warm-started arm solves on the recordings take
    /// 9 to 22 on average and at most 53 for 95% of frames (see `eval/rust/eval_alignment.rs`).
    pub iterations: u32,
    /// Distance (m) between the first effector and its target that counts as reached.
    /// Default 1e-5 (0.01 mm).
    pub tolerance: f32,
    /// Damping: the largest angle (radians, in `(0, pi]`) one joint turns in one step.
    /// Default 0.5 (about 29 degrees): a big jump of the target is spread over several
    /// sweeps, distal joints first, instead of swinging the root around in one step.
    pub max_step_angle: f32,
}

impl Default for CcdOptions {
    fn default() -> Self {
        CcdOptions {
            iterations: 200,
            tolerance: 1e-5,
            max_step_angle: 0.5,
        }
    }
}

impl CcdOptions {
    /// Checks ranges.
    ///
    /// # Errors
    /// `iterations` of 0, a `tolerance` that is not positive, a `max_step_angle` outside
    /// `(0, pi]` (field `maxStepAngle`).
    pub fn validate(&self) -> Result<()> {
        validate_iterations(self.iterations, self.tolerance)?;
        if !(self.max_step_angle > 0.0 && self.max_step_angle <= PI) {
            return Err(Error::invalid(
                "maxStepAngle",
                "must be an angle in (0, pi] radians",
            ));
        }
        Ok(())
    }
}

/// The CCD solver (stateless: the chain's pose is the caller's `joints`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ccd {
    options: CcdOptions,
}

/// What guides a [`Ccd::solve`] besides its effectors: both optional.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Guides {
    /// A world point the chain's bend turns toward, and the first joint it turns.
    pub pole: Option<(Vec3, usize)>,
    /// The last bone's direction (world, unit), pinned.
    pub end_direction: Option<Vec3>,
}

impl Ccd {
    /// A solver with `options`.
    ///
    /// # Errors
    /// Options out of range ([`CcdOptions::validate`]).
    pub fn new(options: CcdOptions) -> Result<Self> {
        options.validate()?;
        Ok(Ccd { options })
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &CcdOptions {
        &self.options
    }

    /// Moves `joints` (the current pose: the warm start) so the `effectors` (highest
    /// priority first; at least one) reach their targets with the root at `root`.
    ///
    /// `guides.pole` (a world point and the first joint it turns, as [`super::ChainGoal::pole_first`])
    /// turns the chain's bend toward it before each sweep, about the line from the pivot to
    /// the first effector's target. `guides.end_direction` (world, unit) pins the last bone's
    /// direction (the first effector should then sit on the last bone's root). `frames` (one
    /// per bone) receives each bone's world rotation from its rest direction, in which the
    /// limits hold (see [`Chain::place`]). Allocates nothing; never writes NaN for finite
    /// inputs (a non-finite target leaves the pose unchanged and reports an infinite error).
    pub fn solve(
        &self,
        chain: &Chain,
        root: &RootFrame,
        effectors: &[Effector],
        guides: Guides,
        joints: &mut [Vec3],
        frames: &mut [Quat],
    ) -> ChainReport {
        let Guides {
            pole,
            end_direction,
        } = guides;
        let n = chain.joint_count();
        debug_assert_eq!(joints.len(), n);
        anchor(joints, root, chain);
        let Some(primary) = effectors.first().copied() else {
            return ChainReport::failed();
        };
        if !(effectors
            .iter()
            .all(|e| e.target.is_finite() && e.offset.is_finite() && (1..n).contains(&e.joint)))
        {
            return ChainReport::failed();
        }
        let lengths = chain.lengths();
        let tolerance = self.options.tolerance;
        let angle_tolerance = tolerance / chain.total_length();
        // Stop a little inside the tolerance: the last pole step re-lays the bones, which
        // moves the end by rounding.
        let converged = 0.9 * tolerance;
        let goal = primary.target - primary.offset;
        let first = primary.first_joint.min(primary.joint - 1);
        let span = &lengths[first..primary.joint];
        let sub_root = joints[first];
        let distance = (goal - sub_root).length();
        let span_length: f32 = span.iter().sum();
        let reachable = distance <= span_length * (1.0 + 1e-6)
            && distance >= sub_min_reach(span) * (1.0 - 1e-6);
        let measure = |joints: &[Vec3], iterations| {
            ChainReport::measure(
                joints[primary.joint] + primary.offset,
                primary.target,
                reachable,
                iterations,
                tolerance,
            )
        };
        if first == 0 && primary.joint == n - 1 && distance >= span_length {
            chain.place(root, joints, Pull::Toward(goal), end_direction, frames);
            return measure(joints, 0);
        }

        let pole = pole.filter(|(p, _)| p.is_finite());
        let side = match pole {
            Some((p, _)) => p,
            None => bow_fallback(chain, root, joints, goal),
        };
        let bow_first = pole.map_or(1, |(_, k)| k).clamp(1, primary.joint.max(1));
        let last_turning = match end_direction {
            Some(_) => n.saturating_sub(3),
            None => n - 2,
        };
        let mut iterations = 0;
        while iterations < self.options.iterations {
            let reach = &mut joints[..=primary.joint];
            let mut largest = pole.map_or(0.0, |(p, _)| {
                turn_toward_pole(reach, bow_first, goal, p, true)
            });
            let bow_side = side - reach[bow_first - 1];
            bow_if_straight(reach, bow_first, lengths, goal, bow_side);
            chain.rotations(root.rotation, joints, frames);
            for k in (0..=last_turning).rev() {
                largest = largest.max(self.turn_joint(chain, root, k, effectors, joints, frames));
            }
            chain.place(root, joints, Pull::Directions, end_direction, frames);
            iterations += 1;
            let error = (joints[primary.joint] + primary.offset - primary.target).length();
            if error <= converged && largest <= angle_tolerance {
                break;
            }
        }
        if let Some((p, _)) = pole {
            face_pole(chain, joints, bow_first, primary.joint, Some(p));
        }
        // Exact lengths after the pole's turns, and `frames` the rotations the limits hold in.
        chain.place(root, joints, Pull::Directions, end_direction, frames);
        measure(joints, iterations)
    }

    /// One CCD step at joint `k`: the effectors it serves, in priority order, then its limit.
    /// Returns the largest angle turned.
    fn turn_joint(
        &self,
        chain: &Chain,
        root: &RootFrame,
        k: usize,
        effectors: &[Effector],
        joints: &mut [Vec3],
        frames: &[Quat],
    ) -> f32 {
        let pivot = joints[k];
        let parent = if k == 0 { root.rotation } else { frames[k - 1] };
        let hinge = chain
            .limit(k)
            .and_then(|l| l.hinge_axis())
            .map(|a| parent * a);
        // The line higher-priority effectors allow turning about (through the pivot).
        let mut keep: Option<Vec3> = None;
        let mut blocked = false;
        let mut largest = 0.0f32;
        for e in effectors {
            if !(e.first_joint <= k && k < e.joint) {
                continue;
            }
            if !blocked {
                let axis = match (hinge, keep) {
                    (None, None) => None,
                    (Some(a), None) | (None, Some(a)) => Some(a),
                    (Some(h), Some(l)) if h.cross(l).length() < 1e-5 => Some(h),
                    (Some(_), Some(_)) => {
                        blocked = true;
                        None
                    }
                };
                if !blocked {
                    let from = joints[e.joint] - pivot;
                    let to = e.target - e.offset - pivot;
                    if let Some(q) = self.step(from, to, axis) {
                        largest = largest.max(2.0 * q.xyz().length().atan2(q.w.abs()));
                        rotate_after(joints, k, q);
                    }
                }
            }
            // Lower priorities must leave this effector's point where it is.
            if let Some(p) = (joints[e.joint] - pivot).try_normalize() {
                match keep {
                    None => keep = Some(p),
                    Some(l) if l.cross(p).length() < 1e-5 => {}
                    Some(_) => blocked = true,
                }
            }
        }
        if let Some(limit) = chain.limit(k) {
            let dir = (joints[k + 1] - pivot).normalize();
            let local = parent.conjugate() * dir;
            let limited = limit.constrain(local, chain.reference(k), local);
            let world = parent * limited;
            if angle_between(dir, world) > 0.0 {
                let q = crate::kinematics::swing(dir, world, hinge.unwrap_or(Vec3::ZERO));
                largest = largest.max(angle_between(dir, world));
                rotate_after(joints, k, q);
            }
        }
        largest
    }

    /// The damped rotation turning `from` toward `to` (about `axis` when given: a hinge or a
    /// priority line), or `None` when there is nothing to turn.
    fn step(&self, from: Vec3, to: Vec3, axis: Option<Vec3>) -> Option<Quat> {
        let (axis, angle) = match axis {
            Some(a) => (a, angle_about(a, from, to)?),
            None => {
                let (f, t) = (from.try_normalize()?, to.try_normalize()?);
                let axis = f
                    .cross(t)
                    .try_normalize()
                    .unwrap_or_else(|| f.any_orthonormal_vector());
                (axis, angle_between(f, t))
            }
        };
        let step = self.options.max_step_angle;
        let angle = crate::math::clamp(angle, -step, step);
        (angle.abs() > 0.0 && angle.is_finite() && axis.is_finite())
            .then(|| Quat::from_axis_angle(axis, angle))
    }
}

/// Turns every joint after `k` by `q` about joint `k`.
fn rotate_after(joints: &mut [Vec3], k: usize, q: Quat) {
    let pivot = joints[k];
    for p in &mut joints[k + 1..] {
        *p = pivot + q * (*p - pivot);
    }
}
