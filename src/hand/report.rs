//! What the hand solver reports per side, and its strategies.

use crate::humanoid::bones::Finger;

use super::limits::{Dof, DOF_COUNT};

/// How hands are solved (JS: `options.handStrategy`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HandStrategy {
    /// Closed-form palm frame for the hand; per finger a least-squares fit of an anatomical
    /// joint model with literature joint limits (see the module docs).
    Analytic,
    /// Optimization-based retargeting (seed 003, section 3.1): the analytic solve, then
    /// finger angles fitted so the avatar's fingertips land on the user's, scaled to the
    /// avatar's hand, within the same joint limits (see [`super::retarget`]).
    Retarget,
}

/// What the last [`super::HandSolver::solve`] did for one side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HandStatus {
    /// Nothing solved yet (or the avatar has no usable palm).
    #[default]
    NotSolved,
    /// Solved from this frame's landmarks.
    Solved,
    /// This frame's hand was degenerate; the previous rotations were written again.
    Held,
    /// This frame's hand was degenerate and there was nothing to hold.
    Skipped,
}

/// Anatomical angles and active limits of the last solve of one side.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct HandReport {
    /// What happened.
    pub status: HandStatus,
    /// Joint angles of the tracked hand after limits, radians, `[finger][dof]` (finger order
    /// of [`Finger::ALL`], DOF order of [`Dof::ALL`]). Meaningful when `status` is `Solved`.
    pub angles: [[f32; DOF_COUNT]; 5],
    /// Whether the tracked angle was outside [`super::LIMITS`] and clamped, `[finger][dof]`.
    pub limited: [[bool; DOF_COUNT]; 5],
}

impl HandReport {
    /// Whether any limit of `finger` was active.
    #[must_use]
    pub fn finger_limited(&self, finger: Finger) -> bool {
        self.limited[finger.index()].iter().any(|l| *l)
    }

    /// Whether any limit of the hand was active.
    #[must_use]
    pub fn any_limited(&self) -> bool {
        Finger::ALL.iter().any(|f| self.finger_limited(*f))
    }

    /// The angle of `dof` on `finger`, radians.
    #[must_use]
    pub fn angle(&self, finger: Finger, dof: Dof) -> f32 {
        self.angles[finger.index()][dof.index()]
    }
}
