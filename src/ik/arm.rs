//! What every arm solver shares besides the reach itself: the arm's vocabulary ([`ArmChain`],
//! [`ArmGoal`], [`ArmPose`], [`ArmReach`], the [`ArmIk`] trait, [`ArmSolver`], [`IkError`]),
//! the shoulder option, joint positions to normalized-bone local rotations and the forearm
//! twist.
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
use core::fmt;

use glam::{Quat, Vec3};

use crate::error::Result;
use crate::humanoid::bones::{HumanBone, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::kinematics::RootFrame;
use crate::math::{angle_between, twist_angle};

use super::wrist::{WristFrame, WristLimited};

/// Which solver reaches the wrist target (JS: `options.armSolver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ArmSolver {
    /// `"twoBone"`: analytic two-bone IK with the elbow swivel from a pole ([`super::TwoBoneIk`]).
    TwoBone,
    /// `"fabrik"`: FABRIK over the arm chain ([`super::FabrikArm`], seed 002).
    Fabrik,
    /// `"ccd"`: CCD with priority effectors ([`super::CcdArm`], seed 004).
    Ccd,
}

impl ArmSolver {
    /// Every solver, in the order of [`ArmSolver::as_str`]'s values in the options.
    pub const ALL: [ArmSolver; 3] = [ArmSolver::TwoBone, ArmSolver::Fabrik, ArmSolver::Ccd];

    /// The JS name: `"twoBone"`, `"fabrik"` or `"ccd"`.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            ArmSolver::TwoBone => "twoBone",
            ArmSolver::Fabrik => "fabrik",
            ArmSolver::Ccd => "ccd",
        }
    }
}

/// What an arm solver achieved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmReach {
    /// Whether the target lies within the arm's reach (between the fully folded and the
    /// fully stretched wrist distance from the shoulder, within 1e-5 m).
    pub reachable: bool,
    /// Distance (m) between the solved wrist (forward kinematics of the written rotations)
    /// and the target. About 0 when reachable; the shortfall when not.
    pub residual: f32,
    /// What the wrist limits changed ([`ArmOptions::wrist_limits`]): the target and hand
    /// rotation actually reached; `None` when the hand was within the limits (or they are
    /// off, or there was no hand rotation).
    pub wrist: Option<WristLimited>,
}

/// Setup errors of the arm solvers.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum IkError {
    /// The avatar lacks a bone the chain needs.
    MissingBone(HumanBone),
    /// An option is out of range.
    InvalidOption {
        /// JS-style path of the option (`options.armSolver...`).
        field: &'static str,
        /// What is wrong with it.
        problem: &'static str,
    },
}

impl fmt::Display for IkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IkError::MissingBone(b) => write!(f, "restPose.bones: arm IK needs bone {b}"),
            IkError::InvalidOption { field, problem } => write!(f, "{field}: {problem}"),
        }
    }
}

impl std::error::Error for IkError {}

impl From<IkError> for crate::error::Error {
    fn from(e: IkError) -> Self {
        match e {
            IkError::MissingBone(b) => crate::error::Error::MissingRequiredBones(vec![b.as_str()]),
            IkError::InvalidOption { field, problem } => {
                crate::error::Error::invalid(field, problem)
            }
        }
    }
}

/// The geometry of one arm (internal frame), read from the avatar's rest pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmChain {
    /// Which arm.
    pub side: Side,
    /// `upperArm`, `lowerArm`, `hand` of this side.
    pub bones: [HumanBone; 3],
    /// The upper arm's effective parent (usually `shoulder`), whose world rotation is the
    /// frame of the upper arm's local rotation. `None` only on a degenerate skeleton.
    pub parent: Option<HumanBone>,
    /// Rest offset upperArm joint -> lowerArm joint (m; the upper arm's rest direction and
    /// length, in the parent's frame).
    pub upper: Vec3,
    /// Rest offset lowerArm joint -> hand joint (m; in the upper arm's frame).
    pub lower: Vec3,
    /// Unit vector, in the parent's frame, pointing away from the body on this side (+X for
    /// the left arm, -X for the right): where "outward" is for the elbow fallbacks.
    pub outward: Vec3,
    /// The shoulder bone, when the avatar has one as the upper arm's parent (the shoulder
    /// option turns it).
    pub shoulder: Option<HumanBone>,
    /// Rest offset shoulder joint -> upperArm joint (m, in the shoulder's frame; normalized
    /// bones: the rest world offset); zero without a shoulder bone.
    pub shoulder_offset: Vec3,
    /// The wrist's anatomical axes ([`WristFrame::new`]) for the wrist limits; `None` on a
    /// degenerate rest pose (the hand is then not limited).
    pub wrist: Option<WristFrame>,
}

impl ArmChain {
    /// Reads the arm of `side` from `skeleton`.
    ///
    /// # Errors
    /// [`IkError::MissingBone`] when upperArm, lowerArm or hand is absent (VRM requires them;
    /// a [`Skeleton`] always has them).
    pub fn new(skeleton: &Skeleton, side: Side) -> Result<Self, IkError> {
        let [_, upper, lower, hand] = side.arm();
        for b in [upper, lower, hand] {
            if !skeleton.has(b) {
                return Err(IkError::MissingBone(b));
            }
        }
        let outward = match side {
            Side::Left => Vec3::X,
            Side::Right => Vec3::NEG_X,
        };
        let parent = skeleton.parent(upper);
        let shoulder = parent.filter(|p| *p == side.arm()[0]);
        Ok(ArmChain {
            side,
            bones: [upper, lower, hand],
            parent,
            upper: skeleton.rest_local(lower),
            lower: skeleton.rest_local(hand),
            outward,
            shoulder,
            shoulder_offset: if shoulder.is_some() {
                skeleton.rest_local(upper)
            } else {
                Vec3::ZERO
            },
            wrist: WristFrame::new(skeleton, side),
        })
    }

    /// Upper arm length (m).
    #[inline]
    #[must_use]
    pub fn upper_length(&self) -> f32 {
        self.upper.length()
    }

    /// Lower arm length (m).
    #[inline]
    #[must_use]
    pub fn lower_length(&self) -> f32 {
        self.lower.length()
    }
}

/// What one arm reaches this frame, as the rig gives it to [`super::ArmSolverState::solve`]
/// (world, internal frame); the solver adds what it reads from the posed parents to make the
/// [`ArmGoal`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmTarget {
    /// Where the wrist should go.
    pub target: Vec3,
    /// The hand's world rotation; `None` leaves the hand bone alone.
    pub hand_rotation: Option<Quat>,
    /// A world point the elbow points toward (the pose elbow landmark).
    pub pole: Option<Vec3>,
    /// The offset (world) from the wrist to the aligned finger point (CCD's first effector;
    /// the wrist limits turn the hand about it).
    pub finger: Option<Vec3>,
}

/// What one arm must reach this frame (world, internal frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmGoal {
    /// World position of the upperArm joint (fixed: the solver does not move it).
    pub shoulder: Vec3,
    /// World rotation of the upper arm's effective parent (identity with the torso at rest).
    pub parent_rotation: Quat,
    /// Where the hand joint (wrist) should be.
    pub target: Vec3,
    /// World rotation the hand bone should have; `None` leaves the hand's local rotation at
    /// identity (it follows the forearm).
    pub hand_rotation: Option<Quat>,
    /// A world point the elbow should point toward (the pose elbow landmark); `None` uses the
    /// solver's natural default.
    pub pole: Option<Vec3>,
    /// The shoulder bone's joint and world rotation as posed before the arm solve, for the
    /// shoulder option ([`ArmOptions::shoulder_angle`]); the solver turns the shoulder from
    /// there ([`ArmPose::shoulder`]). `None` leaves the shoulder alone. When given, `shoulder`
    /// and `parent_rotation` are the upper arm joint and the shoulder's rotation of that pose.
    pub shoulder_root: Option<RootFrame>,
    /// Offset (world, m) from the wrist to the aligned finger point for this frame's hand
    /// rotation (fingertip alignment): CCD's first-priority effector. `None` without one.
    pub finger: Option<Vec3>,
}

/// A solved arm, written by [`ArmIk::solve`] (caller storage).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmPose {
    /// The shoulder option's turn of the shoulder bone, in the shoulder's own frame as posed
    /// before the solve (its new local rotation is the old one times this); `None` leaves it
    /// alone.
    pub shoulder: Option<Quat>,
    /// Local rotation of the upper arm (in its parent's frame).
    pub upper: Quat,
    /// Local rotation of the lower arm (in the upper arm's frame).
    pub lower: Quat,
    /// Local rotation of the hand (in the lower arm's frame): the target hand rotation
    /// expressed there, identity without one.
    pub hand: Quat,
    /// World position of the elbow (lowerArm joint) by forward kinematics of the above.
    pub elbow: Vec3,
    /// World position of the wrist (hand joint) by forward kinematics of the above.
    pub wrist: Vec3,
}

impl Default for ArmPose {
    fn default() -> Self {
        ArmPose {
            shoulder: None,
            upper: Quat::IDENTITY,
            lower: Quat::IDENTITY,
            hand: Quat::IDENTITY,
            elbow: Vec3::ZERO,
            wrist: Vec3::ZERO,
        }
    }
}

/// One arm IK method. Implementations keep whatever per-arm state they need (the two-bone
/// solver remembers the last elbow swivel for continuity), so use one instance per arm.
pub trait ArmIk {
    /// Solves `goal` for `chain` into `out`. Never panics and never writes NaN: unreachable
    /// or degenerate goals give the closest pose and report it in the returned [`ArmReach`].
    /// Allocates nothing.
    fn solve(&mut self, chain: &ArmChain, goal: &ArmGoal, out: &mut ArmPose) -> ArmReach;

    /// Forgets per-arm state carried between frames.
    fn reset(&mut self);
}

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
    /// (hands-only input with `handsOnly.enabled: false` leaves the arm at rest and the hand
    /// unlimited).
    pub wrist_limits: bool,
    /// How fast (radians per second) the shoulder, upper arm, forearm and hand may turn
    /// between two frames, each measured from the chest (its rotation composed down the arm):
    /// a turn faster than that is shown over as many frames as it takes, all four bones
    /// slowed by the same fraction ([`crate::Rig::solve`]'s turn-limit stage). Default 23
    /// (about 1320 degrees per second, 44 degrees between two 30 fps frames): on the
    /// sign-language clips MediaPipe's flips and self-contact's target jumps turn an arm
    /// faster, and one real motion is slowed by a few degrees (`docs/how-it-works/hands-on-video.md`).
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
