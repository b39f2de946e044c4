//! Arm IK: upper arm, lower arm and hand rotations that put the wrist on its target.
//!
//! FIRST VERSION: the arm stays at rest and only the hand rotation is set; the two-bone
//! solver follows (issue 4).

use glam::{Quat, Vec3};
use serde::Deserialize;

use crate::bones::{Side, BONE_COUNT};
use crate::error::Result;
use crate::skeleton::{Skeleton, WorldPose};

/// Which solver reaches the wrist target (JS: `options.armSolver`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum ArmSolver {
    /// Analytic two-bone IK with the elbow swivel from a pole.
    #[default]
    TwoBone,
}

/// What the arm solver achieved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmReach {
    /// Whether the target was within reach.
    pub reachable: bool,
    /// Distance (m) between the wrist and its target after solving.
    pub residual: f32,
}

/// Per-avatar arm solver state.
#[derive(Clone, Debug)]
pub struct ArmSolverState {
    solver: ArmSolver,
}

impl ArmSolverState {
    /// Prepares the solver.
    ///
    /// # Errors
    /// Reserved.
    pub fn new(_skeleton: &Skeleton, solver: ArmSolver) -> Result<Self> {
        Ok(ArmSolverState { solver })
    }

    /// Solves one arm: writes upperArm, lowerArm and hand local rotations into `local`.
    /// `world` holds forward kinematics of the current `local` (for the arm's parents).
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        skeleton: &Skeleton,
        side: Side,
        target: Vec3,
        hand_rotation: Option<Quat>,
        _pole: Option<Vec3>,
        local: &mut [Quat; BONE_COUNT],
        world: &WorldPose,
    ) -> ArmReach {
        let _ = self.solver;
        let hand = side.hand();
        if let Some(r) = hand_rotation {
            let lower = side.arm()[2];
            local[hand.index()] = world.rotation[lower.index()].inverse() * r;
        }
        ArmReach {
            reachable: false,
            residual: (world.position[hand.index()] - target).length(),
        }
        .with_skeleton(skeleton)
    }
}

impl ArmReach {
    fn with_skeleton(self, _s: &Skeleton) -> Self {
        self
    }
}
