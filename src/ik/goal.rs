//! What a chain solve is asked and what it reports, shared by every chain method: the goal
//! ([`ChainGoal`]: target, pole, tolerance), the points that reach ([`Effector`]) and the
//! report ([`ChainReport`]).

use glam::{Quat, Vec3};

use crate::kinematics::Chain;

/// What a chain must reach (world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainGoal {
    /// Where the end joint should go.
    pub target: Vec3,
    /// A point the chain's bend should face (the middle joints turn about the line from the
    /// pivot to the target toward it); `None` for no preference.
    pub pole: Option<Vec3>,
    /// World rotation the last bone should have (from its rest direction): its direction
    /// is pinned through the target, and its reported rotation is this one (corrected
    /// minimally if a limit bends the bone). `None` leaves the last bone free.
    pub end_rotation: Option<Quat>,
    /// The first joint the pole turns (1 for a plain chain: every middle joint about the
    /// root-to-target line; the arm with its shoulder bone uses 2, turning only the elbow about
    /// the upper-arm-to-target line).
    pub pole_first: usize,
}

impl ChainGoal {
    /// Reach `target` with `pole`, the last bone free, the pole turning every middle joint.
    #[must_use]
    pub fn new(target: Vec3, pole: Option<Vec3>) -> Self {
        ChainGoal {
            target,
            pole,
            end_rotation: None,
            pole_first: 1,
        }
    }

    /// The last bone's pinned world direction (unit), from `end_rotation`.
    #[must_use]
    pub fn end_direction(&self, chain: &Chain) -> Option<Vec3> {
        let q = self
            .end_rotation
            .filter(|q| q.is_finite() && q.length_squared() > 0.5)?;
        let last = chain.bone_count() - 1;
        (chain.bone_count() >= 2)
            .then(|| (q.normalize() * chain.rest_directions()[last]).normalize())
    }
}

/// What a chain solve achieved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainReport {
    /// Whether the target is within the chain's reach by its bone lengths (limits ignored).
    pub reachable: bool,
    /// Whether the end ended within the tolerance of the target.
    pub reached: bool,
    /// Distance (m) between the end and the target after the solve.
    pub error: f32,
    /// Iterations run (0 when the pose was already within tolerance, or for a target beyond
    /// reach: the straight chain needs none).
    pub iterations: u32,
}

impl ChainReport {
    /// A report for `end` against `target`.
    #[must_use]
    pub fn measure(
        end: Vec3,
        target: Vec3,
        reachable: bool,
        iterations: u32,
        tolerance: f32,
    ) -> Self {
        let error = (end - target).length();
        ChainReport {
            reachable,
            reached: error <= tolerance,
            error: if error.is_finite() {
                error
            } else {
                f32::INFINITY
            },
            iterations,
        }
    }

    /// Nothing solved (non-finite input, or no solve yet).
    #[must_use]
    pub fn failed() -> Self {
        ChainReport {
            reachable: false,
            reached: false,
            error: f32::INFINITY,
            iterations: 0,
        }
    }
}

/// One point CCD moves toward a target (see the module docs for priorities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effector {
    /// The chain joint it is attached to (`1..N`).
    pub joint: usize,
    /// World-fixed offset (m) from that joint to the effector point (zero: the joint itself).
    pub offset: Vec3,
    /// Where the effector point should go (world).
    pub target: Vec3,
    /// The first joint whose turns serve this effector (0: every joint before `joint`).
    pub first_joint: usize,
}

impl Effector {
    /// The chain's end joint reaching `target` with every joint.
    #[must_use]
    pub fn end(chain: &Chain, target: Vec3) -> Self {
        Effector {
            joint: chain.joint_count() - 1,
            offset: Vec3::ZERO,
            target,
            first_joint: 0,
        }
    }
}
