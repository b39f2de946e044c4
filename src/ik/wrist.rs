//! Anatomical wrist limits: the hand's rotation against the forearm, clamped to the wrist's
//! range of motion ([`ArmOptions::wrist_limits`](super::ArmOptions::wrist_limits)).
//!
//! ## Angles
//! The hand's local rotation `q` (in the forearm's normalized frame) is split into a twist
//! about the forearm's rest direction and a swing: `q = twist * swing`, the twist first (the
//! forearm's pronation/supination, carried by the radius) and the swing in the twisted
//! frame (the wrist's flexion and deviation, about the radiocarpal and midcarpal joints,
//! which turn with the radius). The swing's rotation vector, with its axis perpendicular to
//! the forearm, has two components ([`WristAngles`]):
//!
//! * **flexion** (+, toward the palm) / extension (-), about the palm's across axis;
//! * **radial deviation** (+, toward the thumb) / ulnar deviation (-), about the palm normal.
//!
//! The palm's axes come from the avatar's rest pose ([`WristFrame::new`]): the across
//! direction from the little finger's to the index finger's proximal joint (the radial
//! side), the palmar side from the hand's chirality. The twist is not limited here: the arm
//! solvers share it between the forearm and the hand
//! ([`ArmOptions::forearm_twist`](super::ArmOptions::forearm_twist), [`super::ForearmTwist`]).
//!
//! ## Range ([`WRIST_RANGE`])
//!
//! | motion | limit (deg) | source |
//! | --- | ---: | --- |
//! | flexion | 80 | AAOS 1965 (80); Ryu et al. 1991 (activities of daily living need 54) |
//! | extension | 70 | AAOS 1965 (70); Ryu et al. 1991 (daily living needs 60) |
//! | radial deviation | 20 | AAOS 1965 (20); Ryu et al. 1991 (daily living needs 17) |
//! | ulnar deviation | 40 | Ryu et al. 1991 (daily living needs 40, more than AAOS's normal 30) |
//!
//! Combined motions (circumduction) stay inside the ellipse through the four limits in each
//! quadrant of (flexion, deviation): the wrist's circumduction cone is flattened, wider in
//! flexion-extension than in deviation (Kapandji 2007). A swing outside is scaled back toward
//! rest onto the ellipse, keeping its direction: continuous, and the identity inside.
//!
//! Sources:
//! * American Academy of Orthopaedic Surgeons. "Joint Motion: Method of Measuring and
//!   Recording." 1965 (normal wrist values: flexion 80, extension 70, radial deviation 20,
//!   ulnar deviation 30).
//! * Ryu J., Cooney W.P., Askew L.J., An K.N., Chao E.Y. "Functional ranges of motion of the
//!   wrist joint." J Hand Surg Am 16(3):409-419, 1991 (40 subjects, biaxial electrogoniometer:
//!   every task of daily living within 60 extension, 54 flexion, 40 ulnar and 17 radial
//!   deviation).
//! * Kapandji A.I. "The Physiology of the Joints", vol. 1, upper limb, 6th ed., 2007 (the
//!   wrist's two axes; the cone of circumduction).
//!
//! ## Keeping the fingertip where it was going
//! Limiting the hand's rotation moves the aligned finger point unless the wrist moves too.
//! The arm solvers turn the hand about the aligned point (the goal's `finger`, scaled by the
//! alignment weight) instead, so the wrist target follows the hand and the index distal still
//! lands on the target DIP; but the arm, solved again for the moved wrist, moves the forearm,
//! which moves the limit. A plain fixed-point iteration (limit against the new forearm,
//! re-solve, repeat) does not converge: measured on the recordings, turning the hand about
//! its fingertip often swings the forearm as far as the hand, or further (the wrist moves
//! sideways by hand length times the turn, and the elbow's bend changes with the reach).
//!
//! So the arm solvers search along one path instead (`settle`): the hand turned about the aligned
//! point by `t` times the turn that would bring it within the range of the *first* forearm (`t = 0`
//! is the tracked rotation, `t = 1` that turn), each `t` with its own arm solve, for the least `t`
//! at which the hand is within the range of the forearm it gets. It scans outward in steps of at
//! most 30 degrees of hand rotation and at most half the turn (a first probe straight at `t = 1`
//! saves 0.4 re-solves a limited hand but finds later roots: ASL arm jitter 274 -> 294
//! rad/s^2), then narrows the bracket by regula falsi (Illinois) on the
//! signed distance from the range's boundary ([`WristFrame::margin`]), to [`SETTLE_TOLERANCE`],
//! keeping the end within the range. The re-solves keep the first solve's elbow swivel (pole), so
//! the path is continuous. On the shared recordings it takes 3-7 arm re-solves per limited hand on
//! average (at most 10), and every shown hand ends within the range (`eval/rust/eval_wrist.rs`). Where no `t` up
//! to a half turn (or 4) works, the hand with the least excess found is kept and the excess
//! reported ([`WristLimited::residual`]).

use core::f32::consts::PI;

use glam::{Quat, Vec3};

use crate::humanoid::bones::{Finger, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::math::swing_twist;

/// Lengths below this are treated as zero.
const EPS: f32 = 1e-6;

/// The wrist's range of motion (radians, each a magnitude from the straight wrist).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristRange {
    /// Largest flexion (toward the palm).
    pub flexion: f32,
    /// Largest extension (toward the back of the hand).
    pub extension: f32,
    /// Largest radial deviation (toward the thumb).
    pub radial: f32,
    /// Largest ulnar deviation (toward the little finger).
    pub ulnar: f32,
}

/// The anatomical range handrig clamps to; sources in the module docs.
pub const WRIST_RANGE: WristRange = WristRange {
    flexion: 80.0 * PI / 180.0,
    extension: 70.0 * PI / 180.0,
    radial: 20.0 * PI / 180.0,
    ulnar: 40.0 * PI / 180.0,
};

/// Re-solves of the arm the wrist search may do after limiting the hand (besides the final one).
pub const SETTLE_ITERATIONS: usize = 24;

/// How precisely (radians of hand rotation) the wrist search finds the least turn that brings the
/// hand within the range: 0.5 degree (it errs on the side within the range; 0.2 degree took
/// 0.5 more arm solves per limited hand on the shared recordings).
pub const SETTLE_TOLERANCE: f32 = 0.5 * PI / 180.0;

/// The hand's angles against the forearm (radians), see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristAngles {
    /// Flexion (+) or extension (-).
    pub flexion: f32,
    /// Radial (+) or ulnar (-) deviation.
    pub deviation: f32,
    /// The swing's whole angle: how far the hand's axis is bent from the forearm's, `0..=pi`.
    pub bend: f32,
    /// Twist about the forearm, `(-pi, pi]`.
    pub twist: f32,
}

/// The wrist's anatomical axes for one arm, in the forearm's normalized frame (at rest all
/// normalized frames have world axes, so these are rest world directions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristFrame {
    /// The forearm's rest direction (unit): the twist axis.
    pub axis: Vec3,
    /// Rotating about this (unit, perpendicular to `axis`) by a positive angle flexes the hand
    /// (turns its axis toward the palm).
    pub flexion_axis: Vec3,
    /// Rotating about this (unit, perpendicular to both) by a positive angle deviates the hand
    /// radially (toward the thumb).
    pub radial_axis: Vec3,
}

impl WristFrame {
    /// The wrist frame of `side` from the avatar's rest pose: the forearm's direction
    /// (lowerArm to hand), the radial direction from the little (else ring) to the index
    /// (else middle) proximal joint, or the avatar's front (+Z: a T-pose thumb) without finger
    /// bones. `None` for a degenerate rest pose (zero forearm, radial side along it).
    #[must_use]
    pub fn new(skeleton: &Skeleton, side: Side) -> Option<Self> {
        let axis = skeleton.rest_local(side.hand()).try_normalize()?;
        let proximal = |f: Finger| skeleton.rest_world(side.finger(f)[0]);
        let radial = proximal(Finger::Index)
            .or_else(|| proximal(Finger::Middle))
            .zip(proximal(Finger::Little).or_else(|| proximal(Finger::Ring)))
            .map(|(r, u)| r - u)
            .filter(|d| d.length() > EPS)
            .unwrap_or(Vec3::Z);
        Self::from_axes(axis, radial, side)
    }

    /// The wrist frame for a forearm along `axis` with the thumb's side toward `radial` (any
    /// vector not along `axis`), for the hand of `side` (which decides the palmar side).
    #[must_use]
    pub fn from_axes(axis: Vec3, radial: Vec3, side: Side) -> Option<Self> {
        let axis = axis.try_normalize()?;
        let radial = (radial - axis * axis.dot(radial)).try_normalize()?;
        // Palmar side: a left hand with its forearm along +X and thumb toward +Z has its palm
        // down (-Y) = axis x radial; a right hand is the mirror image.
        let palmar = match side {
            Side::Left => axis.cross(radial),
            Side::Right => radial.cross(axis),
        };
        Some(WristFrame {
            axis,
            flexion_axis: axis.cross(palmar),
            radial_axis: axis.cross(radial),
        })
    }

    /// The angles of the hand's local rotation `hand` (in the forearm's frame).
    #[must_use]
    pub fn angles(&self, hand: Quat) -> WristAngles {
        let (twist, swing) = self.split(hand);
        let t = 2.0 * twist.xyz().dot(self.axis).atan2(twist.w);
        let v = swing_vector(swing);
        WristAngles {
            flexion: v.dot(self.flexion_axis),
            deviation: v.dot(self.radial_axis),
            bend: v.length(),
            twist: t,
        }
    }

    /// How far (radians) `hand` (local, forearm frame) is beyond `range`, along its own
    /// swing direction: 0 inside.
    #[must_use]
    pub fn excess(&self, hand: Quat, range: &WristRange) -> f32 {
        self.margin(hand, range).max(0.0)
    }

    /// The signed distance (radians) of `hand`'s swing from `range`'s boundary along its own
    /// direction: positive beyond the range (the excess), negative inside (how much more it
    /// could bend that way).
    #[must_use]
    pub fn margin(&self, hand: Quat, range: &WristRange) -> f32 {
        let (_, swing) = self.split(hand);
        let (f, d) = self.components(swing_vector(swing));
        let (n, r) = polar(f, d, range);
        n - r
    }

    /// `hand` (local, forearm frame) with its swing scaled back onto `range`'s boundary when
    /// beyond it (twist kept), and the angle it was beyond; `None` when within the range.
    #[must_use]
    pub fn limit(&self, hand: Quat, range: &WristRange) -> Option<(Quat, f32)> {
        let (twist, swing) = self.split(hand);
        let (f, d) = self.components(swing_vector(swing));
        let (n, r) = polar(f, d, range);
        if n <= r || !n.is_finite() || r.is_nan() {
            return None;
        }
        let limited = (self.flexion_axis * f + self.radial_axis * d) * (r / n);
        Some(((twist * Quat::from_scaled_axis(limited)).normalize(), n - r))
    }

    /// A swing's rotation vector as (flexion, radial deviation).
    fn components(&self, v: Vec3) -> (f32, f32) {
        (v.dot(self.flexion_axis), v.dot(self.radial_axis))
    }

    /// `q = twist * swing` (twist about `axis` first, swing in the twisted frame); both
    /// with `w >= 0`.
    fn split(&self, q: Quat) -> (Quat, Quat) {
        let q = q.normalize();
        let (_, twist) = swing_twist(q, self.axis);
        let swing = (twist.conjugate() * q).normalize();
        (positive(twist), positive(swing))
    }
}

/// The swing `(f, d)` (flexion, radial deviation) in polar form: its angle `n` and the
/// range's boundary radius `r` in its direction (the ellipse through the quadrant's two
/// limits); along the smaller limit when `n` is 0.
fn polar(f: f32, d: f32, range: &WristRange) -> (f32, f32) {
    let n = (f * f + d * d).sqrt();
    let fl = if f >= 0.0 {
        range.flexion
    } else {
        range.extension
    };
    let dl = if d >= 0.0 { range.radial } else { range.ulnar };
    if n <= EPS {
        return (n, fl.min(dl));
    }
    let (a, b) = (f / (n * fl.max(EPS)), d / (n * dl.max(EPS)));
    (n, 1.0 / (a * a + b * b).sqrt())
}

/// `q` or `-q`, whichever has `w >= 0` (the shorter way round).
pub(crate) fn positive(q: Quat) -> Quat {
    if q.w < 0.0 {
        -q
    } else {
        q
    }
}

/// The rotation vector (axis * angle, angle in `0..=pi`) of a unit quaternion with `w >= 0`.
fn swing_vector(q: Quat) -> Vec3 {
    let v = q.xyz();
    let s = v.length();
    if s <= EPS {
        return 2.0 * v;
    }
    v * (2.0 * s.atan2(q.w) / s)
}

/// What the wrist search changed: the goal the arm finally reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristLimited {
    /// The wrist target the arm reached (moved so that the aligned finger point stays put).
    pub target: Vec3,
    /// The hand's world rotation, within the limit.
    pub hand_rotation: Quat,
    /// How far (radians) the tracked hand was beyond the limit of the first solve's forearm.
    pub excess: f32,
    /// How far (radians) the final hand is beyond the limit of the final forearm: 0, unless
    /// no turn along the search path brought it within (see the module docs).
    pub residual: f32,
    /// Arm re-solves done.
    pub iterations: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn left() -> WristFrame {
        WristFrame::from_axes(Vec3::X, Vec3::Z, Side::Left).unwrap()
    }

    #[test]
    fn flexion_turns_the_hand_toward_the_palm() {
        // Left hand, T-pose: forearm +X, thumb +Z, palm down.
        let f = left();
        let flexed = Quat::from_axis_angle(f.flexion_axis, 0.5);
        assert!((flexed * Vec3::X).y < -0.4, "{}", flexed * Vec3::X);
        let radial = Quat::from_axis_angle(f.radial_axis, 0.3);
        assert!((radial * Vec3::X).z > 0.25);
        let a = f.angles(flexed);
        assert!((a.flexion - 0.5).abs() < 1e-5 && a.deviation.abs() < 1e-5);
        // The right hand mirrors it: palm down too.
        let r = WristFrame::from_axes(Vec3::NEG_X, Vec3::Z, Side::Right).unwrap();
        let flexed = Quat::from_axis_angle(r.flexion_axis, 0.5);
        assert!((flexed * Vec3::NEG_X).y < -0.4);
    }

    #[test]
    fn angles_ignore_the_twist_and_flex_in_the_twisted_frame() {
        let f = left();
        // Pronate 90 degrees, then flex 30 in the twisted frame.
        let q = Quat::from_axis_angle(Vec3::X, 1.2) * Quat::from_axis_angle(f.flexion_axis, 0.5);
        let a = f.angles(q);
        assert!((a.flexion - 0.5).abs() < 1e-5, "{a:?}");
        assert!(a.deviation.abs() < 1e-5);
        assert!((a.twist - 1.2).abs() < 1e-5);
        assert!((a.bend - 0.5).abs() < 1e-5);
    }

    #[test]
    fn limit_scales_onto_the_ellipse_and_keeps_the_twist() {
        let f = left();
        let r = WRIST_RANGE;
        // 80 degrees of flexion (1.396 rad) but only 70 of extension (1.222).
        assert!(f
            .limit(Quat::from_axis_angle(f.flexion_axis, 1.39), &r)
            .is_none());
        assert!(f
            .limit(Quat::from_axis_angle(f.flexion_axis, 1.40), &r)
            .is_some());
        assert!(f
            .limit(Quat::from_axis_angle(f.flexion_axis, -1.3), &r)
            .is_some());
        // 40 degrees of ulnar deviation, 20 radial.
        assert!(f
            .limit(Quat::from_axis_angle(f.radial_axis, -0.6), &r)
            .is_none());
        assert!(f
            .limit(Quat::from_axis_angle(f.radial_axis, 0.4), &r)
            .is_some());
        let twist = Quat::from_axis_angle(Vec3::X, -2.0);
        let bent = Quat::from_scaled_axis(f.flexion_axis * -2.0 + f.radial_axis * 0.7);
        let (q, excess) = f.limit(twist * bent, &r).unwrap();
        let a = f.angles(q);
        let e = (a.flexion / r.extension).powi(2) + (a.deviation / r.radial).powi(2);
        assert!((e - 1.0).abs() < 1e-4, "{a:?}");
        assert!((a.twist + 2.0).abs() < 1e-4);
        // Direction kept: extension and radial deviation in the same ratio.
        assert!((a.flexion / a.deviation - (-2.0 / 0.7)).abs() < 1e-3);
        assert!((excess - (bent.to_axis_angle().1 - a.bend)).abs() < 1e-4);
        assert!(f.excess(q, &r) < 1e-5);
    }
}
