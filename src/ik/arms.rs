//! Both arms' solvers as the [`crate::Rig`] owns them ([`ArmSolverState`]): the chains read
//! from the avatar, the method in force (enum dispatch: no boxing), the shared options and the
//! wrist limits' last report per side.

use glam::Quat;

use crate::error::Result;
use crate::humanoid::bones::{Side, BONE_COUNT};
use crate::humanoid::skeleton::{Skeleton, WorldPose};
use crate::kinematics::RootFrame;

use super::arm::{ArmChain, ArmGoal, ArmIk, ArmOptions, ArmPose, ArmReach, ArmSolver, ArmTarget};
use super::ccd::CcdOptions;
use super::chain_arm::{CcdArm, FabrikArm};
use super::fabrik::FabrikOptions;
use super::goal::ChainReport;
use super::two_bone::{TwoBoneIk, TwoBoneOptions};
use super::wrist::WristLimited;

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

    /// Solves one arm: writes upperArm, lowerArm and (with `to.hand_rotation`) hand local
    /// rotations into `local` so the wrist reaches `to.target` and the hand's world rotation is
    /// `to.hand_rotation`; with the shoulder option the shoulder's local rotation is turned
    /// further when the reach is far. `world` must hold forward kinematics of `local` for the
    /// arm's parents (the shoulder position and rotations are read from it); it is not
    /// updated. Internal frame throughout. Allocates nothing.
    pub fn solve(
        &mut self,
        side: Side,
        to: &ArmTarget,
        local: &mut [Quat; BONE_COUNT],
        world: &WorldPose,
    ) -> ArmReach {
        let ArmTarget {
            target,
            hand_rotation,
            pole,
            finger,
        } = *to;
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
