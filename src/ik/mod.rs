//! Arm IK: upper arm, lower arm and hand rotations that put the wrist on its target.
//!
//! The shape every method shares (STYLE.md, section 4):
//!
//! * [`ArmChain`]: the geometry of one arm, read once from the avatar's rest pose (which
//!   bones, their rest offsets and lengths). Works from the avatar's own rest directions, so
//!   T-pose (arms along ±X), A-pose or any other rest layout is fine; VRM 0.x avatars are
//!   already turned to face +Z by the [`Skeleton`].
//! * [`ArmGoal`]: what to reach this frame (world, internal frame): the shoulder joint and
//!   its parent's rotation, the wrist target position, the hand's world rotation and an
//!   optional pole (where the elbow should point).
//! * [`ArmIk`]: one type per method ([`TwoBoneIk`] now; FABRIK and CCD fit the same trait),
//!   each with an options struct with a documented `Default` ([`TwoBoneOptions`]). Results
//!   go into caller storage ([`ArmPose`]); a solve allocates nothing.
//! * [`ArmSolverState`]: what the [`crate::Rig`] owns: both arms' chains and solvers, chosen by
//!   the [`ArmSolver`] option, writing straight into the rig's local-rotation array.
//! * [`IkError`]: `#[non_exhaustive]` setup errors (a solve itself never fails: unreachable or
//!   degenerate goals produce the best pose and say so in [`ArmReach`]).
//!
//! Rotations written are *normalized-bone local rotations* (identity = rest pose).

pub mod two_bone;

use core::fmt;

use glam::{Quat, Vec3};
use serde::Deserialize;

use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::error::Result;
use crate::skeleton::{Skeleton, WorldPose};

pub use two_bone::{TwoBoneIk, TwoBoneOptions};

/// Which solver reaches the wrist target (JS: `options.armSolver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "camelCase")]
#[non_exhaustive]
pub enum ArmSolver {
    /// `"twoBone"`: analytic two-bone IK with the elbow swivel from a pole ([`TwoBoneIk`]).
    #[default]
    TwoBone,
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

impl From<IkError> for crate::Error {
    fn from(e: IkError) -> Self {
        match e {
            IkError::MissingBone(b) => crate::Error::MissingRequiredBones(vec![b.as_str()]),
            IkError::InvalidOption { field, problem } => crate::Error::invalid(field, problem),
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
        Ok(ArmChain {
            side,
            bones: [upper, lower, hand],
            parent: skeleton.parent(upper),
            upper: skeleton.rest_local(lower),
            lower: skeleton.rest_local(hand),
            outward,
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
}

/// A solved arm, written by [`ArmIk::solve`] (caller storage).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmPose {
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

/// The method in force for both arms (enum dispatch: no boxing, no allocation).
#[derive(Clone, Debug)]
enum Method {
    TwoBone([TwoBoneIk; 2]),
}

/// Per-avatar arm solver state owned by the [`crate::Rig`]: both arms' chains and solvers.
#[derive(Clone, Debug)]
pub struct ArmSolverState {
    chains: [ArmChain; 2],
    method: Method,
    pose: ArmPose,
}

impl ArmSolverState {
    /// Prepares `solver` with its default options for both arms of `skeleton`.
    ///
    /// # Errors
    /// Missing arm bones (never for a valid [`Skeleton`]).
    pub fn new(skeleton: &Skeleton, solver: ArmSolver) -> Result<Self> {
        match solver {
            ArmSolver::TwoBone => Self::with_two_bone(skeleton, TwoBoneOptions::default()),
        }
    }

    /// Prepares the two-bone solver with explicit options.
    ///
    /// # Errors
    /// Options out of range, missing arm bones.
    pub fn with_two_bone(skeleton: &Skeleton, options: TwoBoneOptions) -> Result<Self> {
        let solver = TwoBoneIk::new(options)?;
        Ok(ArmSolverState {
            chains: [
                ArmChain::new(skeleton, Side::Left)?,
                ArmChain::new(skeleton, Side::Right)?,
            ],
            method: Method::TwoBone([solver.clone(), solver]),
            pose: ArmPose::default(),
        })
    }

    /// Which solver this is.
    #[must_use]
    pub fn solver(&self) -> ArmSolver {
        match self.method {
            Method::TwoBone(_) => ArmSolver::TwoBone,
        }
    }

    /// The chain of `side`.
    #[must_use]
    pub fn chain(&self, side: Side) -> &ArmChain {
        &self.chains[side.index()]
    }

    /// Forgets state carried between frames (the remembered elbow swivel).
    pub fn reset(&mut self) {
        match &mut self.method {
            Method::TwoBone(s) => s.iter_mut().for_each(ArmIk::reset),
        }
    }

    /// Solves one arm: writes upperArm, lowerArm and (with `hand_rotation`) hand local
    /// rotations into `local` so the wrist reaches `target` and the hand's world rotation is
    /// `hand_rotation`. `world` must hold forward kinematics of `local` for the arm's parents
    /// (the shoulder position and parent rotation are read from it); it is not updated.
    /// `pole` is a world point for the elbow (pose elbow landmark). Internal frame throughout.
    /// Allocates nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        side: Side,
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        local: &mut [Quat; BONE_COUNT],
        world: &WorldPose,
    ) -> ArmReach {
        let chain = &self.chains[side.index()];
        let [upper, lower, hand] = chain.bones;
        let goal = ArmGoal {
            shoulder: world.position[upper.index()],
            parent_rotation: chain
                .parent
                .map_or(Quat::IDENTITY, |p| world.rotation[p.index()]),
            target,
            hand_rotation,
            pole,
        };
        let reach = match &mut self.method {
            Method::TwoBone(s) => s[side.index()].solve(chain, &goal, &mut self.pose),
        };
        local[upper.index()] = self.pose.upper;
        local[lower.index()] = self.pose.lower;
        if hand_rotation.is_some() {
            local[hand.index()] = self.pose.hand;
        }
        reach
    }
}

/// The minimal rotation taking unit vector `from` onto unit vector `to` (a swing: its axis
/// is perpendicular to both, so no twist about either). When they are opposite the rotation
/// is half a turn about `fallback_axis` made perpendicular to `from` (any perpendicular if
/// that fails). Always a finite unit quaternion; accurate to f32 rounding at every angle.
#[must_use]
pub fn swing(from: Vec3, to: Vec3, fallback_axis: Vec3) -> Quat {
    // Axis-angle from the cross product and atan2: unlike the half-vector form it keeps full
    // precision near a half turn, where the cross product is still exact.
    let cross = from.cross(to);
    let sin = cross.length();
    let cos = from.dot(to);
    if sin > 1e-7 && sin.is_finite() && cos.is_finite() {
        return Quat::from_axis_angle(cross / sin, sin.atan2(cos));
    }
    if cos.is_nan() || cos >= 0.0 {
        return Quat::IDENTITY;
    }
    let axis = (fallback_axis - from * from.dot(fallback_axis))
        .try_normalize()
        .unwrap_or_else(|| from.any_orthonormal_vector());
    if axis.is_finite() {
        Quat::from_axis_angle(axis, core::f32::consts::PI)
    } else {
        Quat::IDENTITY
    }
}
