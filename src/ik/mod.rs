//! Inverse kinematics: the arm solvers and a standalone chain solver.
//!
//! Methods, one file each (the seeds by name):
//!
//! * [`two_bone`]: analytic two-bone IK with the elbow swivel from a pole ([`TwoBoneIk`]).
//! * [`fabrik`]: FABRIK, seed 002 ([`Fabrik`], arm: [`FabrikArm`]).
//! * [`ccd`]: CCD with limits, damping and priority effectors, seed 004 ([`Ccd`], arm:
//!   [`CcdArm`]).
//! * [`chain_solver`]: [`ChainSolver`], FABRIK or CCD over any chain (tails, spines, custom
//!   rigs), the Rust side of the JS `ChainSolver`.
//! * [`arm`]: what the arm solvers share: [`ArmOptions`] (shoulder, forearm twist, wrist
//!   limits), joint positions to normalized-bone rotations.
//! * [`wrist`]: the wrist's anatomical limits ([`WristFrame`], [`WRIST_RANGE`]) and how the
//!   arm solvers keep fingertip alignment exact while applying them.
//!
//! The chains themselves (lengths, rest directions, joint limits) are
//! [`crate::kinematics::Chain`].
//!
//! ## Arms
//! The shape every arm method shares (STYLE.md, section 4):
//!
//! * [`ArmChain`]: the geometry of one arm, read once from the avatar's rest pose (which
//!   bones, their rest offsets and lengths). Works from the avatar's own rest directions, so
//!   T-pose (arms along ±X), A-pose or any other rest layout is fine; VRM 0.x avatars are
//!   already turned to face +Z by the [`Skeleton`].
//! * [`ArmGoal`]: what to reach this frame (world, internal frame): the shoulder joint and
//!   its parent's rotation, the wrist target position, the hand's world rotation, an
//!   optional pole (where the elbow should point), the shoulder bone's root for the shoulder
//!   option and the aligned finger point's offset.
//! * [`ArmIk`]: one type per method ([`TwoBoneIk`], [`FabrikArm`], [`CcdArm`]), each with an
//!   options struct with a documented `Default`. Results go into caller storage
//!   ([`ArmPose`]); a solve allocates nothing.
//! * [`ArmSolverState`]: what the [`crate::Rig`] owns: both arms' chains and solvers, chosen by
//!   the [`ArmSolver`] option (enum dispatch, no boxing), writing straight into the rig's
//!   local-rotation array.
//! * [`IkError`]: `#[non_exhaustive]` setup errors (a solve itself never fails: unreachable or
//!   degenerate goals produce the best pose and say so in [`ArmReach`]).
//!
//! Every method takes its elbow direction from the same place (the analytic solver's bend
//! direction: pose elbow or default pole, with its continuity memory), so they agree where
//! the arm has one solution and none flips the elbow. Rotations written are *normalized-bone
//! local rotations* (identity = rest pose).

pub mod arm;
pub mod ccd;
pub mod chain_solver;
pub mod fabrik;
pub mod two_bone;
pub mod wrist;

use core::fmt;

use glam::{Quat, Vec3};

use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::error::Result;
use crate::kinematics::RootFrame;
use crate::skeleton::{Skeleton, WorldPose};

pub use crate::kinematics::swing;
pub use arm::{idle_arm, ArmIdle, ArmOptions, ForearmTwist};
pub use ccd::{Ccd, CcdArm, CcdOptions, Effector};
pub use chain_solver::{
    ChainGoal, ChainMethod, ChainReport, ChainSolution, ChainSolver, ChainSolverOptions,
};
pub use fabrik::{Fabrik, FabrikArm, FabrikOptions};
pub use two_bone::{TwoBoneIk, TwoBoneOptions};
pub use wrist::{WristAngles, WristFrame, WristLimited, WristRange, WRIST_RANGE};

/// Which solver reaches the wrist target (JS: `options.armSolver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ArmSolver {
    /// `"twoBone"`: analytic two-bone IK with the elbow swivel from a pole ([`TwoBoneIk`]).
    TwoBone,
    /// `"fabrik"`: FABRIK over the arm chain ([`FabrikArm`], seed 002).
    Fabrik,
    /// `"ccd"`: CCD with priority effectors ([`CcdArm`], seed 004).
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

/// The method in force for both arms (enum dispatch: no boxing, no allocation).
#[derive(Clone, Debug)]
enum Method {
    TwoBone([TwoBoneIk; 2]),
    Fabrik([FabrikArm; 2]),
    Ccd([CcdArm; 2]),
}

/// Per-avatar arm solver state owned by the [`crate::Rig`]: both arms' chains and solvers.
#[derive(Clone, Debug)]
pub struct ArmSolverState {
    chains: [ArmChain; 2],
    method: Method,
    options: ArmOptions,
    pose: ArmPose,
    /// What the wrist limits did in the last solve of each side.
    wrist: [Option<WristLimited>; 2],
}

impl ArmSolverState {
    /// Prepares `solver` with its default options and the default [`ArmOptions`] for both
    /// arms of `skeleton`.
    ///
    /// # Errors
    /// Missing arm bones (never for a valid [`Skeleton`]).
    pub fn new(skeleton: &Skeleton, solver: ArmSolver) -> Result<Self> {
        Self::with_options(skeleton, solver, &ArmOptions::default())
    }

    /// Prepares `solver` with its default options and the shared arm options `arm`.
    ///
    /// # Errors
    /// Options out of range (field named), missing arm bones.
    pub fn with_options(skeleton: &Skeleton, solver: ArmSolver, arm: &ArmOptions) -> Result<Self> {
        match solver {
            ArmSolver::TwoBone => Self::build(skeleton, arm, |_| {
                let s = TwoBoneIk::with_arm_options(TwoBoneOptions::default(), arm)?;
                Ok(Method::TwoBone([s.clone(), s]))
            }),
            ArmSolver::Fabrik => Self::with_fabrik(skeleton, FabrikOptions::default(), arm),
            ArmSolver::Ccd => Self::with_ccd(skeleton, CcdOptions::default(), arm),
        }
    }

    /// Prepares the two-bone solver with explicit options (default [`ArmOptions`]).
    ///
    /// # Errors
    /// Options out of range, missing arm bones.
    pub fn with_two_bone(skeleton: &Skeleton, options: TwoBoneOptions) -> Result<Self> {
        let arm = ArmOptions::default();
        Self::build(skeleton, &arm, |_| {
            let s = TwoBoneIk::with_arm_options(options, &arm)?;
            Ok(Method::TwoBone([s.clone(), s]))
        })
    }

    /// Prepares the FABRIK arm solver with explicit options.
    ///
    /// # Errors
    /// Options out of range, missing arm bones.
    pub fn with_fabrik(
        skeleton: &Skeleton,
        options: FabrikOptions,
        arm: &ArmOptions,
    ) -> Result<Self> {
        Self::build(skeleton, arm, |[l, r]| {
            Ok(Method::Fabrik([
                FabrikArm::new(l, options, arm)?,
                FabrikArm::new(r, options, arm)?,
            ]))
        })
    }

    /// Prepares the CCD arm solver with explicit options.
    ///
    /// # Errors
    /// Options out of range, missing arm bones.
    pub fn with_ccd(skeleton: &Skeleton, options: CcdOptions, arm: &ArmOptions) -> Result<Self> {
        Self::build(skeleton, arm, |[l, r]| {
            Ok(Method::Ccd([
                CcdArm::new(l, options, arm)?,
                CcdArm::new(r, options, arm)?,
            ]))
        })
    }

    /// Checks `arm`, reads both arms' chains and builds the method for them.
    fn build(
        skeleton: &Skeleton,
        arm: &ArmOptions,
        method: impl FnOnce(&[ArmChain; 2]) -> Result<Method>,
    ) -> Result<Self> {
        arm.validate()?;
        let chains = Self::chains(skeleton)?;
        Ok(ArmSolverState {
            method: method(&chains)?,
            chains,
            options: *arm,
            pose: ArmPose::default(),
            wrist: [None, None],
        })
    }

    fn chains(skeleton: &Skeleton) -> Result<[ArmChain; 2]> {
        Ok([
            ArmChain::new(skeleton, Side::Left)?,
            ArmChain::new(skeleton, Side::Right)?,
        ])
    }

    /// Which solver this is.
    #[must_use]
    pub fn solver(&self) -> ArmSolver {
        match self.method {
            Method::TwoBone(_) => ArmSolver::TwoBone,
            Method::Fabrik(_) => ArmSolver::Fabrik,
            Method::Ccd(_) => ArmSolver::Ccd,
        }
    }

    /// The shared arm options in force.
    #[must_use]
    pub fn options(&self) -> &ArmOptions {
        &self.options
    }

    /// The chain of `side`.
    #[must_use]
    pub fn chain(&self, side: Side) -> &ArmChain {
        &self.chains[side.index()]
    }

    /// Whether solves of `side` write the shoulder bone's rotation (the shoulder option is on
    /// and the avatar has the bone).
    #[must_use]
    pub fn moves_shoulder(&self, side: Side) -> bool {
        self.options.shoulder_angle > 0.0 && self.chains[side.index()].shoulder.is_some()
    }

    /// The iterations and convergence of the last solve of `side` (FABRIK and CCD; `None`
    /// for the analytic solver).
    #[must_use]
    pub fn last_report(&self, side: Side) -> Option<ChainReport> {
        match &self.method {
            Method::TwoBone(_) => None,
            Method::Fabrik(s) => Some(s[side.index()].last_report()),
            Method::Ccd(s) => Some(s[side.index()].last_report()),
        }
    }

    /// What the wrist limits changed in the last solve of `side` ([`ArmReach::wrist`]):
    /// `None` when the hand was within them, or they are off.
    #[must_use]
    pub fn last_wrist(&self, side: Side) -> Option<WristLimited> {
        self.wrist[side.index()]
    }

    /// Forgets state carried between frames (the remembered elbow swivel, the forearm twist
    /// branch, the warm start).
    pub fn reset(&mut self) {
        self.wrist = [None, None];
        // The solvers start from what the last solve wrote (the shoulder turn among it).
        self.pose = ArmPose::default();
        match &mut self.method {
            Method::TwoBone(s) => s.iter_mut().for_each(ArmIk::reset),
            Method::Fabrik(s) => s.iter_mut().for_each(ArmIk::reset),
            Method::Ccd(s) => s.iter_mut().for_each(ArmIk::reset),
        }
    }

    /// Solves one arm: writes upperArm, lowerArm and (with `hand_rotation`) hand local
    /// rotations into `local` so the wrist reaches `target` and the hand's world rotation is
    /// `hand_rotation`; with the shoulder option the shoulder's local rotation is turned
    /// further when the reach is far. `world` must hold forward kinematics of `local` for the
    /// arm's parents (the shoulder position and rotations are read from it); it is not
    /// updated. `pole` is a world point for the elbow (pose elbow landmark); `finger` the
    /// offset (world) from the wrist to the aligned finger point, for CCD's first effector.
    /// Internal frame throughout. Allocates nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        side: Side,
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        finger: Option<Vec3>,
        local: &mut [Quat; BONE_COUNT],
        world: &WorldPose,
    ) -> ArmReach {
        let chain = &self.chains[side.index()];
        let [upper, lower, hand] = chain.bones;
        let shoulder_root = chain.shoulder.map(|s| RootFrame {
            position: world.position[s.index()],
            rotation: world.rotation[s.index()],
        });
        let goal = ArmGoal {
            shoulder: world.position[upper.index()],
            parent_rotation: chain
                .parent
                .map_or(Quat::IDENTITY, |p| world.rotation[p.index()]),
            target,
            hand_rotation,
            pole,
            shoulder_root,
            finger,
        };
        let reach = match &mut self.method {
            Method::TwoBone(s) => s[side.index()].solve(chain, &goal, &mut self.pose),
            Method::Fabrik(s) => s[side.index()].solve(chain, &goal, &mut self.pose),
            Method::Ccd(s) => s[side.index()].solve(chain, &goal, &mut self.pose),
        };
        self.wrist[side.index()] = reach.wrist;
        if let (Some(q), Some(s)) = (self.pose.shoulder, chain.shoulder) {
            local[s.index()] = (local[s.index()] * q).normalize();
        }
        local[upper.index()] = self.pose.upper;
        local[lower.index()] = self.pose.lower;
        if hand_rotation.is_some() {
            local[hand.index()] = self.pose.hand;
        }
        reach
    }
}
