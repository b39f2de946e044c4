//! Hand solving: the hand (wrist) orientation and the 15 finger rotations of one hand from
//! MediaPipe's 21 world landmarks.
//!
//! FIRST VERSION: hand orientation from the palm frame only; finger rotations follow in the
//! hand-solver work (issue 3).

use glam::{Mat3, Quat, Vec3};
use serde::Deserialize;

use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::error::Result;
use crate::mediapipe::{hand_landmark as lm, HAND_LANDMARKS};
use crate::skeleton::Skeleton;

/// How hands are solved (JS: `options.handStrategy`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "camelCase")]
pub enum HandStrategy {
    /// Closed-form: palm frame for the hand, anatomically constrained joint angles per finger.
    #[default]
    Analytic,
}

/// Per-avatar hand solver state.
#[derive(Clone, Debug)]
pub struct HandSolver {
    rest_palm: [Option<Mat3>; 2],
}

/// An orthonormal palm frame from wrist, index MCP, little MCP and middle MCP: columns are
/// (across the palm toward the index side, palm normal, wrist-to-middle direction). `None`
/// when the points are degenerate.
#[must_use]
pub fn palm_frame(wrist: Vec3, index: Vec3, little: Vec3, middle: Vec3) -> Option<Mat3> {
    let forward = (middle - wrist).try_normalize()?;
    let across = index - little;
    let normal = forward.cross(across).try_normalize()?;
    let across = normal.cross(forward);
    Some(Mat3::from_cols(across, normal, forward))
}

impl HandSolver {
    /// Prepares the solver from the avatar's rest finger layout.
    ///
    /// # Errors
    /// Never for now; reserved for strategies that need finger bones.
    pub fn new(skeleton: &Skeleton, _strategy: HandStrategy) -> Result<Self> {
        let mut rest_palm = [None, None];
        for side in Side::BOTH {
            let p = |b: HumanBone| skeleton.rest_world(b);
            let f = |finger| side.finger(finger)[0];
            use crate::bones::Finger::*;
            rest_palm[side.index()] =
                match (p(side.hand()), p(f(Index)), p(f(Little)), p(f(Middle))) {
                    (Some(w), Some(i), Some(l), Some(m)) => palm_frame(w, i, l, m),
                    _ => None,
                };
        }
        Ok(HandSolver { rest_palm })
    }

    /// Solves one hand. `landmarks` are in the avatar frame. Writes finger local rotations
    /// into `local` and returns the hand's world rotation, or `None` when the hand is
    /// degenerate or the avatar has no fingers to define its palm.
    pub fn solve(
        &mut self,
        _skeleton: &Skeleton,
        side: Side,
        landmarks: &[Vec3; HAND_LANDMARKS],
        _local: &mut [Quat; BONE_COUNT],
    ) -> Option<Quat> {
        let rest = self.rest_palm[side.index()]?;
        let obs = palm_frame(
            landmarks[lm::WRIST],
            landmarks[lm::INDEX_MCP],
            landmarks[lm::PINKY_MCP],
            landmarks[lm::MIDDLE_MCP],
        )?;
        Some(Quat::from_mat3(&(obs * rest.transpose())).normalize())
    }
}
