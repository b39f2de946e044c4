//! Inverse kinematics: the arm solvers and a standalone chain solver.
//!
//! Methods, one file each (the seeds by name):
//!
//! * [`two_bone`]: analytic two-bone IK with the elbow swivel from a pole ([`TwoBoneIk`]).
//! * [`fabrik`]: FABRIK, seed 002 ([`Fabrik`]).
//! * [`ccd`]: CCD with limits, damping and priority effectors, seed 004 ([`Ccd`]).
//! * [`chain_solver`]: [`ChainSolver`], FABRIK or CCD over any chain (tails, spines, custom
//!   rigs), the Rust side of the JS `ChainSolver`.
//!
//! Around them, from the bottom up:
//!
//! * [`goal`]: what a chain solve is asked and reports ([`ChainGoal`], [`Effector`],
//!   [`ChainReport`]).
//! * [`wrist`]: the wrist's anatomical limits ([`WristFrame`], [`WRIST_RANGE`]) and how the
//!   arm solvers keep fingertip alignment exact while applying them.
//! * [`arm`]: what the arm solvers share: the arm's vocabulary (below), [`ArmOptions`]
//!   (shoulder, forearm twist, wrist limits), joint positions to normalized-bone rotations.
//! * [`chain_arm`]: FABRIK and CCD as arm solvers ([`FabrikArm`], [`CcdArm`]).
//! * [`arms`]: both arms' solvers as the rig owns them ([`ArmSolverState`]).
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
//!   already turned to face +Z by the [`crate::Skeleton`].
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
pub mod arms;
pub mod ccd;
pub mod chain_arm;
pub mod chain_solver;
pub mod fabrik;
pub mod goal;
pub(crate) mod settle;
pub mod two_bone;
pub mod wrist;

pub use crate::kinematics::swing;
pub use arm::{
    idle_arm, ArmChain, ArmGoal, ArmIdle, ArmIk, ArmOptions, ArmPose, ArmReach, ArmSolver,
    ArmTarget, ForearmTwist, IkError,
};
pub use arms::ArmSolverState;
pub use ccd::{Ccd, CcdOptions};
pub use chain_arm::{CcdArm, FabrikArm};
pub use chain_solver::{ChainMethod, ChainSolution, ChainSolver, ChainSolverOptions};
pub use fabrik::{Fabrik, FabrikOptions};
pub use goal::{ChainGoal, ChainReport, Effector};
pub use two_bone::{TwoBoneIk, TwoBoneOptions};
pub use wrist::{WristAngles, WristFrame, WristLimited, WristRange, WRIST_RANGE};
