//! What every arm solver shares besides the reach itself: the shoulder option, joint
//! positions to normalized-bone local rotations, the forearm twist, and the chain plumbing of
//! the FABRIK and CCD arms (`ChainArm`, crate-private).
//!
//! ## Shoulder ([`ArmOptions::shoulder_angle`], [`ArmOptions::shoulder_reach`])
//! A far reach raises (or pulls forward) the shoulder instead of locking the elbow straight,
//! as VRIK rotates shoulders. The shoulder bone turns from rest by at most the angle *needed*
//! to bring the target within `shoulder_reach` of the arm's full length from the upper arm
//! joint ([`shoulder_need`], a closed form: 0 while the target is comfortably within reach,
//! growing continuously beyond), and never more than `shoulder_angle`. The analytic solver
//! turns the shoulder by exactly that angle toward the target; FABRIK and CCD put the shoulder
//! bone into the chain as bone 0 under a cone limit of that angle and let the method decide
//! where within it. While the target is comfortably within reach the cone is closed and all
//! three solvers give the plain two-bone arm.
//!
//! ## Rotations
//! Every bone's local rotation is the swing (minimal rotation) from its rest direction to its
//! solved direction in its parent's frame ([`crate::kinematics::Chain::rotations`]). The
//! hand's local rotation makes its world rotation the target rotation; then
//! [`ArmOptions::forearm_twist`] of its twist about the forearm moves into the forearm
//! ([`ForearmTwist`]), which turns about its own axis and so keeps the wrist where it is.
//!
//! ## Forearm twist continuity
//! The hand's twist angle is only known modulo a full turn. Taken in `(-pi, pi]` the
//! forearm's share would jump by `fraction * 2 pi` each time the twist passes a half turn
//! (a forearm flip). [`ForearmTwist`] keeps the last angle and takes the branch nearest to it,
//! so a hand rocking about a half turn moves the forearm smoothly; only after the twist
//! has gone on past a half turn by more than [`TWIST_HYSTERESIS`] in one direction does it
//! wrap back (a hand cannot really twist that far).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use crate::error::{Error, Result};
use crate::kinematics::{angle_between, twist_angle, Chain, JointLimit, RootFrame};
use crate::Side;

use super::ccd::Effector;
use super::two_bone::TwoBoneIk;
use super::wrist::settle;
use super::{ArmChain, ArmGoal, ArmPose, ArmReach, ChainGoal, ChainReport, TwoBoneOptions};
use crate::Skeleton;

/// Slack (m) on the reach limits before a target counts as unreachable.
pub(crate) const REACH_TOLERANCE: f32 = 1e-5;

/// How far past a half turn (radians) the hand's twist may go, in the direction it came
/// from, before the forearm's share wraps to the other side: 60 degrees.
pub const TWIST_HYSTERESIS: f32 = PI / 3.0;

/// Where an arm with nothing to follow rests (JS: `options.arm.idle`): no wrist from the pose
/// or a tracker, hands alone, or tracking lost and eased out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ArmIdle {
    /// `"down"`: hanging by the side, the elbow slightly bent ([`idle_arm`]).
    #[default]
    Down,
    /// `"tpose"`: the avatar's rest pose (the VRM T-pose).
    TPose,
}

/// Angle (radians) of an idle upper arm out from hanging straight down, away from the body:
/// clears the hips of slim and wide avatars alike.
pub const IDLE_ARM_OUT: f32 = 0.2;
/// Angle (radians) an idle arm's elbow bends forward: slightly bent, as a relaxed arm hangs.
pub const IDLE_ELBOW_BEND: f32 = 0.3;

/// The idle arm's local rotations `[upper arm, lower arm]` (internal frame, relative to the
/// rest pose) for `idle`: identity for the T-pose; for `Down` the upper arm turned from its
/// rest direction to hanging down ([`IDLE_ARM_OUT`] away from the body), the forearm bent
/// forward by [`IDLE_ELBOW_BEND`], palms toward the thighs. Directions come from the
/// skeleton's rest offsets, so A-posed rests work alike.
// Out of line: called from the easing and the hands-only plan (.wasm size).
#[inline(never)]
#[must_use]
pub fn idle_arm(skeleton: &Skeleton, side: Side, idle: ArmIdle) -> [Quat; 2] {
    let [_, _, lower, hand] = side.arm();
    // The upper and lower arm's rest directions (the lower arm's and hand's offsets from their
    // parents, required bones).
    let upper_dir = skeleton.rest_local(lower).normalize_or_zero();
    let lower_dir = skeleton.rest_local(hand).normalize_or_zero();
    if idle == ArmIdle::TPose || upper_dir == Vec3::ZERO || lower_dir == Vec3::ZERO {
        return [Quat::IDENTITY; 2];
    }
    // The internal frame: +Y up, facing +Z, the avatar's left on +X.
    let (s, c) = IDLE_ARM_OUT.sin_cos();
    let out = if side == Side::Left { s } else { -s };
    let hang = Vec3::new(out, -c, 0.0);
    let (s, c) = IDLE_ELBOW_BEND.sin_cos();
    let forearm = hang * c + Vec3::Z * s;
    let upper = Quat::from_rotation_arc(upper_dir, hang);
    [
        upper,
        Quat::from_rotation_arc(lower_dir, upper.conjugate() * forearm),
    ]
}

/// Options every arm solver shares (JS: `options.arm`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmOptions {
    /// Largest angle (radians, `0..=pi/2`) the shoulder bone turns from rest to help a far
    /// reach; 0 keeps the shoulders at rest. Needs the avatar's shoulder bones. Default 0.26
    /// (about 15 degrees; a round number of radians, so settings UIs with a 0.01 step can
    /// hold it): a visible shrug or forward reach, well inside the clavicle's range of
    /// roughly 30-40 degrees elevation.
    pub shoulder_angle: f32,
    /// Fraction of the arm's full length (upper + lower arm, `0.5..=1`) beyond which the
    /// shoulder starts to turn. Default 0.9: an arm reaching further keeps some elbow bend
    /// while the shoulder helps, and a relaxed arm never moves the shoulder.
    pub shoulder_reach: f32,
    /// Fraction (`0..=1`) of the hand's twist about the forearm that the forearm takes (the
    /// rest stays at the wrist). Default 0.5: halfway, as forearm pronation spreads along
    /// the forearm; avatars without twist bones then wring at neither end.
    pub forearm_twist: f32,
    /// Clamp the hand's flexion, extension and radial/ulnar deviation against the forearm to
    /// the wrist's anatomical range ([`super::wrist`]; sources there), turning the hand about
    /// the aligned finger point so that fingertip alignment stays exact. Default `true`;
    /// `false` applies the tracked hand rotation as given. Applies where the arm is solved
    /// (hands-only input leaves the arm at rest and the hand unlimited).
    pub wrist_limits: bool,
    /// How fast (radians per second) the shoulder, upper arm, forearm and hand may turn
    /// between two frames, each measured from the chest (its rotation composed down the arm):
    /// a turn faster than that is shown over as many frames as it takes, all four bones
    /// slowed by the same fraction ([`crate::Rig::solve`]'s turn-limit stage). Default 23
    /// (about 1320 degrees per second, 44 degrees between two 30 fps frames): on the
    /// sign-language clips MediaPipe's flips and self-contact's target jumps turn an arm
    /// faster, and one real motion is slowed by a few degrees (`docs/hands-on-video.md`).
    /// 0 = no limit. The arm solvers themselves ignore it.
    pub max_turn_speed: f32,
    /// Where an arm with nothing to follow rests ([`ArmIdle`]). Default [`ArmIdle::Down`]:
    /// by the side, eased into and out of with the dropout timings.
    pub idle: ArmIdle,
}

/// The angle (radians, `0..=max_angle`) the shoulder bone must turn from rest toward the
/// target so that the target is within `reach * arm_length` of the upper arm joint (see the
/// module docs). `root` is the shoulder bone's joint and its parent's rotation, `offset` the
/// rest offset shoulder joint -> upper arm joint in that frame. Also returns the unit axis
/// (world) turning the offset toward the target. 0 when no turn helps.
#[must_use]
pub fn shoulder_need(
    root: &RootFrame,
    offset: Vec3,
    target: Vec3,
    arm_length: f32,
    options: &ArmOptions,
) -> (f32, Vec3) {
    let c = root.rotation * offset;
    let to_target = target - root.position;
    let (cl, d) = (c.length(), to_target.length());
    let r = options.shoulder_reach * arm_length;
    let Some(axis) = c.cross(to_target).try_normalize().filter(|a| a.is_finite()) else {
        return (0.0, Vec3::X);
    };
    if options.shoulder_angle <= 0.0 || (to_target - c).length() <= r || cl <= 0.0 {
        return (0.0, axis);
    }
    let psi = angle_between(c / cl, to_target / d);
    // |T - U(phi)|^2 = d^2 + cl^2 - 2 d cl cos(psi - phi) <= r^2
    let k = (d * d + cl * cl - r * r) / (2.0 * d * cl);
    let need = if k >= 1.0 {
        psi
    } else {
        (psi - k.acos()).max(0.0)
    };
    (need.min(options.shoulder_angle), axis)
}

/// Moves a share of the hand's twist about the forearm into the forearm, continuously from
/// frame to frame (see the module docs). One per arm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForearmTwist {
    fraction: f32,
    last: Option<f32>,
}

impl ForearmTwist {
    /// The forearm takes `fraction` (0..=1) of the twist.
    #[must_use]
    pub fn new(fraction: f32) -> Self {
        ForearmTwist {
            fraction: fraction.clamp(0.0, 1.0),
            last: None,
        }
    }

    /// Splits the twist of `hand` (local, in the forearm's frame) about the forearm's rest
    /// direction `axis` (unit, forearm frame) between `lower` (the forearm's local rotation,
    /// turned about its own axis) and `hand`. The hand's world rotation and the wrist's
    /// position are unchanged.
    pub fn apply(&mut self, axis: Vec3, lower: &mut Quat, hand: &mut Quat) {
        if self.fraction <= 0.0 || !axis.is_normalized() {
            return;
        }
        let mut angle = twist_angle(*hand, axis);
        if let Some(prev) = self.last {
            // The branch nearest the last angle, unless that has run too far past a half turn.
            let near = angle + 2.0 * PI * ((prev - angle) / (2.0 * PI)).round();
            if near.abs() <= PI + TWIST_HYSTERESIS {
                angle = near;
            }
        }
        self.last = Some(angle);
        let share = Quat::from_axis_angle(axis, self.fraction * angle);
        *lower = (*lower * share).normalize();
        *hand = (share.conjugate() * *hand).normalize();
    }

    /// Forgets the last angle.
    pub fn reset(&mut self) {
        self.last = None;
    }
}

/// Fills `out.hand` from the target hand rotation (identity without one) given the forearm's
/// world rotation, and splits the twist.
pub(crate) fn finish_hand(
    chain: &ArmChain,
    lower_world: Quat,
    hand_rotation: Option<Quat>,
    twist: &mut ForearmTwist,
    out: &mut ArmPose,
) {
    out.hand = Quat::IDENTITY;
    if let Some(q) = hand_rotation.filter(|q| q.is_finite() && q.length_squared() > 0.5) {
        out.hand = (lower_world.inverse() * q).normalize();
        if let Some(axis) = chain.lower.try_normalize() {
            twist.apply(axis, &mut out.lower, &mut out.hand);
        }
    }
}

/// The shoulder bone's joint and its parent's rotation when the shoulder option applies to
/// this goal, else `None`.
pub(crate) fn shoulder_root(
    chain: &ArmChain,
    goal: &ArmGoal,
    options: &ArmOptions,
) -> Option<RootFrame> {
    let root = goal.shoulder_root?;
    (options.shoulder_angle > 0.0
        && chain.shoulder.is_some()
        && root.position.is_finite()
        && root.rotation.is_finite())
    .then(|| RootFrame {
        position: root.position,
        rotation: root.rotation.normalize(),
    })
}

/// The method's reach step (FABRIK's or CCD's) as [`ChainArm`] calls it: the chain, its root,
/// the goal and the effectors, the joints to move in place; returns the method's report.
type ReachStep<'a> =
    dyn FnMut(&Chain, &RootFrame, &ChainGoal, &[Effector], &mut [Vec3]) -> ChainReport + 'a;

/// The arm chain with its pose, swivel memory and twist state, shared by [`super::FabrikArm`]
/// and [`super::CcdArm`]: they differ only in the reach step given to [`ChainArm::solve`].
#[derive(Clone, Debug)]
pub(crate) struct ChainArm {
    /// Joints upperArm, lowerArm, hand (the plain arm).
    plain: Chain,
    /// Joints shoulder, upperArm, lowerArm, hand (`None` without a shoulder bone).
    shouldered: Option<Chain>,
    joints: [Vec3; 4],
    /// Which chain `joints` holds (for the warm start), `None` before the first solve.
    last_shouldered: Option<bool>,
    /// The analytic solver, used for its bend direction (pole logic and memory) only.
    swivel: TwoBoneIk,
    twist: ForearmTwist,
    options: ArmOptions,
    report: ChainReport,
}

impl ChainArm {
    pub(crate) fn new(chain: &ArmChain, options: &ArmOptions) -> Result<Self> {
        options.validate()?;
        let [u, l] = [chain.upper, chain.lower];
        let field = |e: Error| match e {
            Error::InvalidInput { problem, .. } => Error::degenerate(
                format!("restPose.bones.{}", chain.bones[0]),
                format!("arm chain: {problem}"),
            ),
            e => e,
        };
        let plain = Chain::new(&[Vec3::ZERO, u, u + l], &[]).map_err(field)?;
        let shouldered = match chain.shoulder {
            Some(_) if chain.shoulder_offset.length() > 1e-6 => Some(
                Chain::new(
                    &[
                        Vec3::ZERO,
                        chain.shoulder_offset,
                        chain.shoulder_offset + u,
                        chain.shoulder_offset + u + l,
                    ],
                    &[Some(JointLimit::Cone { max_angle: 0.0 }), None, None],
                )
                .map_err(field)?,
            ),
            _ => None,
        };
        Ok(ChainArm {
            plain,
            shouldered,
            joints: [Vec3::ZERO; 4],
            last_shouldered: None,
            swivel: TwoBoneIk::new(TwoBoneOptions::default()).map_err(Error::from)?,
            twist: ForearmTwist::new(options.forearm_twist),
            options: *options,
            report: ChainReport::failed(),
        })
    }

    pub(crate) fn last_report(&self) -> ChainReport {
        self.report
    }

    pub(crate) fn reset(&mut self) {
        self.swivel.reset_memory();
        self.twist.reset();
        self.last_shouldered = None;
    }

    /// Solves `goal` with `reach` (the method: FABRIK or CCD) on the arm chain: sets up the
    /// shoulder cone, the warm start, the pole and the effectors, then converts the joints
    /// to local rotations; with the wrist limits on, re-solves for the limited hand
    /// ([`super::wrist`]).
    pub(crate) fn solve(
        &mut self,
        chain: &ArmChain,
        goal: &ArmGoal,
        out: &mut ArmPose,
        mut reach: impl FnMut(&Chain, &RootFrame, &ChainGoal, &[Effector], &mut [Vec3]) -> ChainReport,
    ) -> ArmReach {
        let parent = if goal.parent_rotation.is_finite() {
            goal.parent_rotation.normalize()
        } else {
            Quat::IDENTITY
        };
        if !(goal.target.is_finite() && goal.shoulder.is_finite()) {
            *out = ArmPose {
                elbow: goal.shoulder,
                wrist: goal.shoulder,
                ..ArmPose::default()
            };
            self.report = ChainReport::failed();
            return ArmReach {
                reachable: false,
                residual: f32::INFINITY,
                wrist: None,
            };
        }
        let pole = self.pole_point(chain, goal, parent);
        let (mut result, lower) = self.place(chain, goal, parent, pole, out, &mut reach);
        let mut goal = *goal;
        let mut lower_world = lower;
        if self.options.wrist_limits {
            if let Some(frame) = chain.wrist {
                result.wrist = settle(&frame, &mut goal, lower, &mut |g| {
                    let (r, l) = self.place(chain, g, parent, pole, out, &mut reach);
                    result = r;
                    lower_world = l;
                    l
                });
            }
        }
        finish_hand(chain, lower_world, goal.hand_rotation, &mut self.twist, out);
        result
    }

    /// The point the elbow is turned toward: the analytic solver's bend direction (pose elbow
    /// or default pole, continuity memory, updated here) from the upper arm joint as the
    /// shoulder option would place it for `goal`: the same pole for every method.
    fn pole_point(&mut self, chain: &ArmChain, goal: &ArmGoal, parent: Quat) -> Vec3 {
        let arm_length = chain.upper_length() + chain.lower_length();
        let shoulder =
            shoulder_root(chain, goal, &self.options).filter(|_| self.shouldered.is_some());
        let (upper_joint, rotation) = match shoulder {
            Some(root) => {
                let (need, axis) = shoulder_need(
                    &root,
                    chain.shoulder_offset,
                    goal.target,
                    arm_length,
                    &self.options,
                );
                let turned =
                    Quat::from_axis_angle(axis, need) * (root.rotation * chain.shoulder_offset);
                (root.position + turned, root.rotation)
            }
            None => (goal.shoulder, parent),
        };
        let swivel_goal = ArmGoal {
            shoulder: upper_joint,
            parent_rotation: rotation,
            ..*goal
        };
        let (dir, bend) = self.swivel.swivel(chain, &swivel_goal);
        let distance = (goal.target - upper_joint).length();
        upper_joint + dir * (0.5 * distance) + bend * arm_length
    }

    /// One reach of `goal` toward `pole_point`: the shoulder cone, the warm start, the
    /// effectors, `reach`, then the shoulder, upper and lower arm rotations and the elbow and
    /// wrist positions in `out` (the hand is left to [`finish_hand`]). Returns the reach and
    /// the forearm's world rotation.
    fn place(
        &mut self,
        chain: &ArmChain,
        goal: &ArmGoal,
        parent: Quat,
        pole_point: Vec3,
        out: &mut ArmPose,
        // `dyn`: one copy of this function for both methods (a generic one was two, 3.3 KiB
        // each in the .wasm); the reach step is called once or twice a frame.
        reach: &mut ReachStep<'_>,
    ) -> (ArmReach, Quat) {
        let arm_length = chain.upper_length() + chain.lower_length();
        let shoulder =
            shoulder_root(chain, goal, &self.options).filter(|_| self.shouldered.is_some());

        // The chain and its root.
        let (kc, root) = match shoulder {
            Some(root) => {
                let (need, _) = shoulder_need(
                    &root,
                    chain.shoulder_offset,
                    goal.target,
                    arm_length,
                    &self.options,
                );
                let kc = self.shouldered.as_mut().expect("checked above");
                // The cone limit was validated at setup; `need` is in 0..=pi/2.
                let _ = kc.set_limit(0, Some(JointLimit::Cone { max_angle: need }));
                (&*kc, root)
            }
            None => (
                &self.plain,
                RootFrame {
                    position: goal.shoulder,
                    rotation: parent,
                },
            ),
        };
        let n = kc.joint_count();
        let shouldered = shoulder.is_some();
        let joints = &mut self.joints[..n];
        if self.last_shouldered != Some(shouldered) {
            // First solve, or the chain changed: start from rest (or from the plain arm's
            // last pose carried over, which anchor() then moves to the root).
            let rest = kc.rest_joints();
            for (p, r) in joints.iter_mut().zip(rest) {
                *p = root.position + root.rotation * *r;
            }
        }
        self.last_shouldered = Some(shouldered);

        let upper_index = usize::from(shouldered);
        let chain_goal = ChainGoal {
            target: goal.target,
            pole: Some(pole_point),
            end_rotation: None,
            pole_first: upper_index + 1,
        };
        let wrist = n - 1;
        let finger = goal
            .finger
            .filter(|f| f.is_finite() && goal.hand_rotation.is_some());
        let mut effectors = [Effector {
            joint: wrist,
            offset: Vec3::ZERO,
            target: goal.target,
            first_joint: 0,
        }; 3];
        let mut count = 0;
        if let Some(f) = finger {
            effectors[count].offset = f;
            effectors[count].target = goal.target + f;
            count += 1;
        }
        count += 1; // the wrist itself
        effectors[count] = Effector {
            joint: wrist - 1,
            offset: Vec3::ZERO,
            target: pole_point,
            first_joint: upper_index,
        };
        count += 1;
        self.report = reach(kc, &root, &chain_goal, &effectors[..count], joints);

        // Joints to local rotations (swing chain).
        let mut world = [Quat::IDENTITY; 3];
        kc.rotations(root.rotation, joints, &mut world[..n - 1]);
        let (upper_parent, upper_world, lower_world) = if shouldered {
            out.shoulder = Some((root.rotation.conjugate() * world[0]).normalize());
            (world[0], world[1], world[2])
        } else {
            out.shoulder = None;
            (parent, world[0], world[1])
        };
        out.upper = (upper_parent.conjugate() * upper_world).normalize();
        out.lower = (upper_world.conjugate() * lower_world).normalize();
        // Positions by forward kinematics of the written rotations (the hand's twist, added
        // later, turns the forearm about its own axis and moves neither).
        let upper_at = joints[upper_index];
        out.elbow = upper_at + upper_parent * out.upper * chain.upper;
        out.wrist = out.elbow + upper_parent * out.upper * out.lower * chain.lower;
        let (a, b) = (chain.upper_length(), chain.lower_length());
        let reach_to = (goal.target - upper_at).length();
        (
            ArmReach {
                reachable: reach_to <= a + b + REACH_TOLERANCE
                    && reach_to + REACH_TOLERANCE >= (a - b).abs(),
                residual: (out.wrist - goal.target).length(),
                wrist: None,
            },
            upper_parent * out.upper * out.lower,
        )
    }
}

/// The shoulder bone's local rotation turning it by `need` about `axis` (world), in its
/// parent's frame `root`, used by the analytic solver.
#[must_use]
pub(crate) fn shoulder_turn(root: &RootFrame, need: f32, axis: Vec3) -> Quat {
    let local_axis = root.rotation.conjugate() * axis;
    if need > 0.0 && local_axis.is_finite() {
        Quat::from_axis_angle(local_axis.normalize(), need)
    } else {
        Quat::IDENTITY
    }
}
