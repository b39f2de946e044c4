//! The **touch hold**, in the contact stage: a hand that MediaPipe loses while it touches the other hand stays
//! against it. Stacked or clasped hands are where the hand tracker loses one of them most
//! often (on the shared `sister` clip the signer's right hand, resting on the left, is lost
//! for 24 frames while the pose still sees both wrists); without this the lost hand would
//! hold, then ease to rest, its wrist following the pose's, and come apart from the other.
//!
//! While both hands are tracked and touch (the hand-to-hand blend at least
//! [`TOUCH_WEIGHT`]), each side's wrist target and hand rotation are kept relative to the
//! other hand's (in the other hand's frame). When one is then lost and the other is still
//! tracked, the lost side reaches that same place and rotation relative to the other hand,
//! and its fingers keep their last pose, for at most [`TOUCH_HOLD_MS`], and only while the
//! pose's wrist of the lost side (when the pose sees it) stays within [`TOUCH_RELEASE_M`] of
//! the held wrist across the camera (the pose's depth is not trusted): a hand that leaves is
//! let go, and the dropout easing takes over. The held side reports a hand-to-hand weight of 1
//! (`SolveOutput::contact`, flat `contactHandWeight`) and no tracked hand.

use glam::{Quat, Vec3};

use crate::contact::ContactReport;
use crate::humanoid::bones::{Finger, Side, BONE_COUNT};

use super::frame::{Frame, Plan};
use super::output::SolveOutput;

/// The hand-to-hand blend from which two tracked hands count as touching.
pub const TOUCH_WEIGHT: f32 = 0.5;
/// Longest a lost hand is held against the other (ms).
pub const TOUCH_HOLD_MS: f64 = 1500.0;
/// How far (m, across the camera: avatar x and y) the pose's wrist of the lost side may be
/// from the held wrist before the hand is let go.
pub const TOUCH_RELEASE_M: f32 = 0.2;

/// One side's touch history.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct TouchHold {
    /// Last touching frame's wrist target and hand rotation relative to the other hand's
    /// (in the other hand's frame).
    relative: Option<(Vec3, Quat)>,
    /// Since when (ms) the side has been held, while it is.
    since: Option<f64>,
}

impl TouchHold {
    /// Whether the side is held against the other this frame.
    pub(super) fn held(&self) -> bool {
        self.since.is_some()
    }
}

/// A side's wrist target and hand rotation, when its hand was placed with contact points this
/// frame.
fn tracked(f: &Frame, s: usize) -> Option<(Vec3, Quat)> {
    match f.plans[s] {
        Plan::Reach {
            target,
            hand_rotation: Some(q),
            ..
        } if f.points[s].is_some() => Some((target, q)),
        _ => None,
    }
}

/// Records touching hands and holds a lost one against the other (see the module), with
/// `shown` the rotations shown last frame. Runs after contact has placed both targets.
pub(super) fn hold(
    holds: &mut [TouchHold; 2],
    shown: &[Quat; BONE_COUNT],
    now_ms: f64,
    f: &mut Frame,
    out: &mut SolveOutput,
) {
    for side in Side::BOTH {
        let (s, o) = (side.index(), 1 - side.index());
        let other = tracked(f, o);
        let hold = &mut holds[s];
        if let Some((target, rotation)) = tracked(f, s) {
            let touching = out.contact[s].is_some_and(|c| c.hand_weight >= TOUCH_WEIGHT);
            hold.relative = match other {
                Some((t, q)) if touching => {
                    let back = q.conjugate();
                    Some((back * (target - t), (back * rotation).normalize()))
                }
                _ => None,
            };
            hold.since = None;
            continue;
        }
        let (Some((offset, turn)), Some((t, q))) = (hold.relative, other) else {
            *hold = TouchHold::default();
            continue;
        };
        let since = *hold.since.get_or_insert(now_ms);
        let target = t + q * offset;
        let (pose_wrist, pole) = match f.plans[s] {
            Plan::Reach {
                target: wrist,
                pole,
                ..
            } => (Some(wrist), pole),
            _ => (None, None),
        };
        let left = pose_wrist.is_some_and(|w| (w - target).truncate().length() > TOUCH_RELEASE_M);
        if now_ms - since > TOUCH_HOLD_MS || left || !target.is_finite() {
            *hold = TouchHold::default();
            continue;
        }
        f.plans[s] = Plan::Reach {
            target,
            hand_rotation: Some((q * turn).normalize()),
            pole,
            carried: false,
        };
        f.points[s] = None;
        // The fingers keep the pose they were shown with (the easing stage holds them).
        for f in Finger::ALL {
            for b in side.finger(f) {
                out.local[b.index()] = shown[b.index()];
            }
        }
        out.contact[s]
            .get_or_insert_with(ContactReport::default)
            .hand_weight = 1.0;
    }
}
