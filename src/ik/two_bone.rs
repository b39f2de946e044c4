//! Analytic two-bone IK: shoulder fixed, wrist on the target, elbow swivel from a pole.
//!
//! ```text
//!            E (elbow)
//!        a  / \  b
//!          /   \
//!   S ----------- W  (wrist = target when reachable)
//!    shoulder  r = |W - S|
//! ```
//!
//! The law of cosines gives the shoulder angle `alpha`; the elbow lies at
//! `S + a (cos alpha * d + sin alpha * n)`, `d` the unit shoulder-to-target direction and `n`
//! the *bend direction*, a unit vector perpendicular to `d` saying where the elbow points.
//!
//! ## Bend direction (swivel) and why it never flips
//! The textbook `n = normalize(pole - its projection onto the target line)` is undefined when
//! the pole is on that line and reverses as the target (or the pole) passes it: the elbow
//! jumps to the other side of the arm. No stateless rule can avoid that everywhere (a
//! continuous field of directions perpendicular to `d` over all `d` must vanish somewhere,
//! the hairy-ball theorem), so the solver remembers its last swivel:
//!
//! * The pole is the pose elbow landmark when given, else the default pole
//!   [`TwoBoneOptions::default_pole`] (down and slightly back, in the torso's frame).
//! * Outside a cone of half-angle [`TwoBoneOptions::collinear_cone`] around the
//!   shoulder-to-target line, `n` is *exactly* the pole's side, whatever came before.
//! * Inside it the pole's weight `w` fades smoothly to 0 on the line. The elbow starts from
//!   its last swivel (carried to the new arm direction) and turns toward the pole's side at
//!   a rate that grows with `w` per radian the target and pole directions move
//!   (see `relax_fraction`): on the line it holds still; leaving the cone it has fully turned.
//!   Because the rate is per radian of motion, the elbow's path does not depend on the frame
//!   rate or on how finely the motion is sampled: it is continuous, never a jump.
//! * The first solve (or after [`ArmIk::reset`]) has no last swivel: it starts from
//!   "outward" (away from the body) and, with a pose elbow, from the default pole's side.
//!
//! ## Rotations
//! The upper arm's local rotation is the swing (minimal rotation, no twist) from its rest
//! direction to the solved direction, in its parent's frame; the lower arm's likewise in the
//! upper arm's frame. The hand's local rotation is then whatever makes its world rotation
//! equal the target rotation, and [`super::ArmOptions::forearm_twist`] of its twist moves
//! into the forearm (see [`super::arm`]).
//!
//! ## Shoulder
//! With [`super::ArmOptions::shoulder_angle`] and the goal's shoulder bone, the shoulder
//! first turns toward the target by the closed-form angle of [`super::arm::shoulder_need`]
//! (0 unless the reach is far), then the arm solves from the turned upper arm joint.

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use super::arm::{
    finish_hand, shoulder_need, shoulder_root, shoulder_turn, ForearmTwist, REACH_TOLERANCE,
};
use super::arm::{ArmChain, ArmGoal, ArmIk, ArmOptions, ArmPose, ArmReach, IkError};
use super::settle::settle;
use crate::kinematics::swing;
use crate::math::angle_between;

/// Lengths and distances below this (m) are treated as zero.
const EPS: f32 = 1e-6;

/// Options of [`TwoBoneIk`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoBoneOptions {
    /// Where the elbow points when no pole is given, as a direction in the upper arm's parent
    /// frame (torso axes; +Y up, +Z the avatar's front). Any non-zero length.
    /// Default: down and 15 degrees back, `(0, -cos 15°, -sin 15°)`: an arm reaching forward
    /// hangs its elbow down, a hand lowered in front of the belly puts it back.
    pub default_pole: Vec3,
    /// Half-angle (radians) of the cone around the shoulder-to-target line in which a pole
    /// is too close to collinear to define the swivel; inside it the pole's influence fades
    /// smoothly to zero and the last swivel is kept. Must be in `(0, pi/2)`. Default 10
    /// degrees: wide enough to absorb pose-landmark noise of a straight arm's elbow.
    pub collinear_cone: f32,
}

impl Default for TwoBoneOptions {
    fn default() -> Self {
        let back = 15f32.to_radians();
        TwoBoneOptions {
            default_pole: Vec3::new(0.0, -back.cos(), -back.sin()),
            collinear_cone: 10f32.to_radians(),
        }
    }
}

impl TwoBoneOptions {
    /// Checks ranges.
    ///
    /// # Errors
    /// A zero or non-finite `default_pole`, a `collinear_cone` outside `(0, pi/2)`.
    pub fn validate(&self) -> Result<(), IkError> {
        if !(self.default_pole.is_finite() && self.default_pole.length() > EPS) {
            return Err(IkError::InvalidOption {
                field: "options.armSolver.defaultPole",
                problem: "must be a non-zero finite direction",
            });
        }
        if !(self.collinear_cone > 0.0 && self.collinear_cone < PI / 2.0) {
            return Err(IkError::InvalidOption {
                field: "options.armSolver.collinearCone",
                problem: "must be an angle in (0, pi/2) radians",
            });
        }
        Ok(())
    }
}

/// Analytic two-bone IK for one arm. Keeps the last bend direction (for continuity inside
/// the collinear cones), so use one per arm.
#[derive(Clone, Debug)]
pub struct TwoBoneIk {
    options: TwoBoneOptions,
    /// `sin(collinear_cone)`, precomputed.
    cone_sin: f32,
    /// The last solve, for continuity inside the cones.
    last: Option<Memory>,
    /// Shoulder and forearm twist options.
    arm: ArmOptions,
    twist: ForearmTwist,
}

impl TwoBoneIk {
    /// A solver with `options`.
    ///
    /// # Errors
    /// Options out of range (see [`TwoBoneOptions::validate`]).
    pub fn new(options: TwoBoneOptions) -> Result<Self, IkError> {
        Self::with_arm_options(options, &ArmOptions::default())
    }

    /// A solver with `options` and the shared arm options `arm` (shoulder, forearm twist;
    /// [`TwoBoneIk::new`] uses their defaults). `arm` should have passed
    /// [`ArmOptions::validate`]; out-of-range fractions are clamped.
    ///
    /// # Errors
    /// Options out of range (see [`TwoBoneOptions::validate`]).
    pub fn with_arm_options(options: TwoBoneOptions, arm: &ArmOptions) -> Result<Self, IkError> {
        options.validate()?;
        Ok(TwoBoneIk {
            options,
            cone_sin: options.collinear_cone.sin(),
            last: None,
            arm: *arm,
            twist: ForearmTwist::new(arm.forearm_twist),
        })
    }

    /// The shoulder-to-target direction (unit) for `goal` with the upper arm joint at
    /// `goal.shoulder` and the arm's parent turned by `parent`: the target's direction, or at
    /// the shoulder itself the last direction, else the rest direction.
    fn target_direction(&self, chain: &ArmChain, goal: &ArmGoal, parent: Quat) -> Vec3 {
        let to_target = goal.target - goal.shoulder;
        let dist = to_target.length();
        if dist > EPS {
            to_target / dist
        } else {
            self.last
                .map(|m| m.dir)
                .or_else(|| (parent * (chain.upper + chain.lower)).try_normalize())
                .unwrap_or(parent * chain.outward)
        }
    }

    /// The shoulder-to-target direction and the bend direction (where the elbow points,
    /// unit, perpendicular to it) this solver would use for `goal`, remembered for continuity
    /// as by a solve: the FABRIK and CCD arms take their pole from here, so every method
    /// swivels the elbow the same way. `goal.target` and `goal.shoulder` must be finite.
    pub(crate) fn swivel(&mut self, chain: &ArmChain, goal: &ArmGoal) -> (Vec3, Vec3) {
        let parent = if goal.parent_rotation.is_finite() {
            goal.parent_rotation.normalize()
        } else {
            Quat::IDENTITY
        };
        let goal = ArmGoal {
            parent_rotation: parent,
            ..*goal
        };
        let dir = self.target_direction(chain, &goal, parent);
        let (bend, memory) = self.bend_direction(chain, &goal, dir);
        self.last = Some(memory);
        (dir, bend)
    }

    /// Forgets the swivel memory only (the FABRIK and CCD arms keep their own twist state).
    pub(crate) fn reset_memory(&mut self) {
        self.last = None;
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &TwoBoneOptions {
        &self.options
    }

    /// The bend direction for shoulder-to-target direction `dir` (unit), see the module docs,
    /// and what to remember of this solve.
    fn bend_direction(&self, chain: &ArmChain, goal: &ArmGoal, dir: Vec3) -> (Vec3, Memory) {
        let across = |v: Vec3| (v - dir * dir.dot(v)).try_normalize();
        let parent = goal.parent_rotation;
        let last = self.last.as_ref();
        let mut bend = last
            .and_then(|m| across(m.bend))
            .or_else(|| across(parent * chain.outward))
            // Target straight outward: the default pole is perpendicular there anyway, but
            // keep a defined start.
            .or_else(|| across(parent * Vec3::NEG_Z))
            .unwrap_or_else(|| dir.any_orthonormal_vector());
        let memory = self.memory(goal, dir, bend);
        let (default_pole, pole) = (memory.default_pole, memory.pole);
        let moved = last.map(|m| angle_between(m.dir, dir));
        match pole {
            // The pose elbow decides; near-collinear, the last swivel is kept (or, on a first
            // solve, the default pole's side).
            Some(p) => {
                if last.is_none() {
                    bend = self.steer(bend, dir, default_pole, None);
                }
                let motion = moved
                    .zip(last.and_then(|m| m.pole))
                    .map(|(d, q)| d + angle_between(q, p));
                bend = self.steer(bend, dir, p, motion);
            }
            None => {
                let motion = moved
                    .zip(last)
                    .map(|(d, m)| d + angle_between(m.default_pole, default_pole));
                bend = self.steer(bend, dir, default_pole, motion);
            }
        }
        (bend, Memory { bend, ..memory })
    }

    /// What to remember of a solve toward `dir` with elbow bend `bend`.
    fn memory(&self, goal: &ArmGoal, dir: Vec3, bend: Vec3) -> Memory {
        Memory {
            bend,
            dir,
            default_pole: (goal.parent_rotation * self.options.default_pole).normalize(),
            pole: goal
                .pole
                .and_then(|p| (p - goal.shoulder).try_normalize())
                .filter(|p| p.is_finite()),
        }
    }

    /// Turns `bend` about `dir` toward the side the unit vector `toward` lies on: fully
    /// outside the collinear cone; inside it by the fraction of the angle given by
    /// [`relax_fraction`] for `motion` (radians the target and pole directions moved since the
    /// last solve; `None` without a last solve: the fraction is the cone weight itself).
    fn steer(&self, bend: Vec3, dir: Vec3, toward: Vec3, motion: Option<f32>) -> Vec3 {
        let side = toward - dir * dir.dot(toward);
        let side_len = side.length();
        let w = smoothstep(self.cone_sin, side_len);
        if w <= 0.0 || side_len <= EPS {
            return bend;
        }
        let u = side / side_len;
        if w >= 1.0 {
            return u;
        }
        let f = match motion {
            Some(m) => relax_fraction(w, m, self.options.collinear_cone * RELAX_PER_CONE),
            None => w,
        };
        let angle = dir.dot(bend.cross(u)).atan2(bend.dot(u));
        (Quat::from_axis_angle(dir, f * angle) * bend).normalize()
    }
}

/// What a [`TwoBoneIk`] remembers of its last solve (world unit vectors).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Memory {
    bend: Vec3,
    dir: Vec3,
    default_pole: Vec3,
    pole: Option<Vec3>,
}

/// Relaxation length of the swivel inside a cone, as a fraction of the cone angle.
const RELAX_PER_CONE: f32 = 1.0 / 3.0;

/// Fraction of the way to turn toward the pole's side after the directions moved by
/// `motion` radians with cone weight `w` (0 on the line, 1 at the cone's edge).
///
/// The swivel relaxes toward the pole's side at rate `w / ((1 - w) * scale)` per radian of
/// motion, so consecutive solves compose (`f(m1) then f(m2)` equals `f(m1 + m2)` at constant
/// `w`): the elbow's path does not depend on how finely the motion is sampled, only on the
/// motion, which is what makes it continuous. The rate grows without bound toward the cone's
/// edge, so the elbow has fully arrived on the pole's side when it leaves the cone; on the
/// line (`w = 0`) it keeps its swivel.
fn relax_fraction(w: f32, motion: f32, scale: f32) -> f32 {
    if w >= 1.0 {
        return 1.0;
    }
    let rate = w / ((1.0 - w) * scale.max(EPS));
    1.0 - (-(rate * motion.max(0.0))).exp()
}

/// 0 at `x <= 0`, 1 at `x >= edge`, smooth (C1) between.
#[inline]
fn smoothstep(edge: f32, x: f32) -> f32 {
    let t = (x / edge).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl TwoBoneIk {
    /// The geometric solve of `goal`: shoulder turn, upper and lower arm rotations, elbow and
    /// wrist positions into `out` (the hand is left to [`finish_hand`]). Reads but does not
    /// update the swivel memory; returns the reach, what to remember (`None` for a degenerate
    /// goal, which leaves the arm at rest) and the forearm's world rotation. `bend` overrides
    /// the bend direction (made perpendicular to this goal's target line): the wrist limits'
    /// re-solves keep the first solve's swivel, as the FABRIK and CCD arms keep its pole.
    fn place(
        &self,
        chain: &ArmChain,
        goal: &ArmGoal,
        out: &mut ArmPose,
        bend: Option<Vec3>,
    ) -> (ArmReach, Option<Memory>, Quat) {
        let a = chain.upper_length();
        let b = chain.lower_length();
        let mut parent = if goal.parent_rotation.is_finite() {
            goal.parent_rotation.normalize()
        } else {
            Quat::IDENTITY
        };
        let mut shoulder = goal.shoulder;
        out.shoulder = None;
        if let Some(root) =
            shoulder_root(chain, goal, &self.arm).filter(|_| goal.target.is_finite())
        {
            let (need, axis) =
                shoulder_need(&root, chain.shoulder_offset, goal.target, a + b, &self.arm);
            let local = shoulder_turn(&root, need, axis);
            out.shoulder = Some(local);
            parent = (root.rotation * local).normalize();
            shoulder = root.position + parent * chain.shoulder_offset;
        }
        let goal = ArmGoal {
            parent_rotation: parent,
            shoulder,
            ..*goal
        };
        let to_target = goal.target - shoulder;
        let dist = to_target.length();
        if !(dist.is_finite() && shoulder.is_finite() && (a + b).is_finite()) {
            // Only reachable through misuse (the Rig validates input) or an avatar so large
            // that its squared bone lengths overflow f32: rest pose, no NaN, no panic.
            *out = ArmPose {
                elbow: shoulder,
                wrist: shoulder,
                ..ArmPose::default()
            };
            let reach = ArmReach {
                reachable: false,
                residual: f32::INFINITY,
                wrist: None,
            };
            return (reach, None, Quat::IDENTITY);
        }
        // Target at the shoulder: keep the last direction, else the rest direction.
        let dir = self.target_direction(chain, &goal, parent);

        let reach_min = (a - b).abs();
        let reach_max = a + b;
        let reachable = dist <= reach_max + REACH_TOLERANCE && dist + REACH_TOLERANCE >= reach_min;
        // Unreachable: stretched straight toward the target, or folded as far as it goes.
        // max/min rather than clamp: total even when a bound is NaN or they cross.
        let r = dist.max(reach_min).min(reach_max);

        // A given bend (the wrist search's re-solves) made perpendicular to this target line;
        // the computed one where it is along the line.
        let given = bend.and_then(|b| (b - dir * dir.dot(b)).try_normalize());
        let (bend, memory) = match given {
            Some(bend) => (bend, self.memory(&goal, dir, bend)),
            None => self.bend_direction(chain, &goal, dir),
        };
        // The elbow's offset along the target line (`along`) and away from it (`height`).
        // Heron's form with the reach-limit factors written out keeps `height` exact (0) at
        // full stretch and full fold, where `sqrt(1 - cos^2)` would be off by ~1e-3 rad.
        let (along, height) = if a > EPS && r > EPS {
            let along = ((a - b) * (a + b) + r * r) / (2.0 * r);
            let h2 = (reach_max + r) * (reach_max - r) * (r - reach_min) * (r + reach_min);
            (along, h2.max(0.0).sqrt() / (2.0 * r))
        } else if a > EPS {
            // Equal bones folded onto the shoulder: the elbow points along the bend.
            (0.0, a)
        } else {
            (0.0, 0.0)
        };
        let upper_dir = (dir * along + bend * height).try_normalize().unwrap_or(dir);
        let lower_dir = (dir * r - upper_dir * a)
            .try_normalize()
            .unwrap_or(upper_dir);
        // The elbow's hinge axis: the normal of the bend plane. Used only to pick a half-turn
        // axis when a bone must point exactly opposite its rest direction.
        let hinge = dir.cross(bend);

        let inv_parent = parent.inverse();
        let upper = if a > EPS {
            swing(chain.upper / a, inv_parent * upper_dir, inv_parent * bend)
        } else {
            Quat::IDENTITY
        };
        let upper_world = parent * upper;
        let inv_upper = upper_world.inverse();
        let lower = if b > EPS {
            swing(chain.lower / b, inv_upper * lower_dir, inv_upper * hinge)
        } else {
            Quat::IDENTITY
        };
        let lower_world = upper_world * lower;

        out.upper = upper;
        out.lower = lower;
        out.elbow = shoulder + upper_world * chain.upper;
        out.wrist = out.elbow + lower_world * chain.lower;
        let reach = ArmReach {
            reachable,
            residual: (out.wrist - goal.target).length(),
            wrist: None,
        };
        (reach, Some(memory), lower_world)
    }
}

impl ArmIk for TwoBoneIk {
    fn solve(&mut self, chain: &ArmChain, goal: &ArmGoal, out: &mut ArmPose) -> ArmReach {
        let (mut reach, mut memory, mut lower_world) = self.place(chain, goal, out, None);
        let mut goal = *goal;
        if let (true, Some(frame), Some(first)) = (self.arm.wrist_limits, chain.wrist, memory) {
            let this = &*self;
            let limited = settle(&frame, &mut goal, lower_world, &mut |g| {
                let (r, m, l) = this.place(chain, g, out, Some(first.bend));
                reach = r;
                memory = m;
                lower_world = l;
                l
            });
            reach.wrist = limited;
        }
        let Some(memory) = memory else {
            return reach;
        };
        // The hand's twist turns the forearm about its own axis: positions stay.
        finish_hand(chain, lower_world, goal.hand_rotation, &mut self.twist, out);
        self.last = Some(memory);
        reach
    }

    fn reset(&mut self) {
        self.last = None;
        self.twist.reset();
    }
}
