//! Palm frames: the hand's forward, radial and palmar axes from the wrist and knuckles (of the
//! landmarks and of the avatar's rest hand), and the small frame helpers the solver shares.

use glam::{Mat3, Quat, Vec3};

use crate::humanoid::bones::{Finger, Side};
use crate::input::mediapipe::HAND_LANDMARKS;

use super::chain::{Basis, Kind};

/// Shortest segment (m) treated as a direction: below it a segment carries no information.
pub(super) const MIN_LENGTH: f32 = 1e-6;
/// Smallest sine between the palm's forward and across vectors (about 5.7 degrees): below it
/// the palm is treated as collinear.
pub(super) const MIN_PALM_SINE: f32 = 0.1;
/// MediaPipe MCP landmarks of index, middle, ring, little.
pub(super) const MCP: [usize; 4] = [5, 9, 13, 17];

/// Palmar normal from forward and radial: a left hand is the mirror image of a right hand.
#[inline]
pub(super) fn palmar(side: Side, f: Vec3, r: Vec3) -> Vec3 {
    match side {
        Side::Right => r.cross(f),
        Side::Left => f.cross(r),
    }
}

/// Radial direction from forward and palmar (inverse of [`palmar`]).
#[inline]
pub(super) fn radial(side: Side, f: Vec3, n: Vec3) -> Vec3 {
    match side {
        Side::Right => f.cross(n),
        Side::Left => n.cross(f),
    }
}

/// The palm frame of a hand: columns `(f, r, n)` = forward (wrist to `middle`), radial
/// (`little` to `index`, made perpendicular to forward), palmar normal. All points in one
/// frame (meters). Orthonormal; determinant -1 on a right hand and +1 on a left hand (mirror
/// images), so the rotation between two frames of the same side is proper. `None` when degenerate: coincident points or a palm whose forward and
/// across directions are within about 6 degrees of each other.
#[must_use]
pub fn palm_frame(
    side: Side,
    wrist: Vec3,
    index: Vec3,
    little: Vec3,
    middle: Vec3,
) -> Option<Mat3> {
    frame_from(side, middle - wrist, index - little)
}

pub(super) fn frame_from(side: Side, forward: Vec3, across: Vec3) -> Option<Mat3> {
    let fl = forward.length();
    let al = across.length();
    if !(fl > MIN_LENGTH && al > MIN_LENGTH) {
        return None;
    }
    let f = forward / fl;
    let perp = across - across.dot(f) * f;
    if perp.length() < MIN_PALM_SINE * al {
        return None;
    }
    let r = perp.normalize();
    Some(Mat3::from_cols(f, r, palmar(side, f, r)))
}

/// Which points define the palm frame, chosen from the bones the avatar has; the same choice
/// is applied to the landmarks so both frames mean the same thing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PalmDef {
    /// Bit i: MCP i (index, middle, ring, little) is averaged into the forward point.
    pub(super) forward: u8,
    /// Radial and ulnar MCP (0..4) of the across vector.
    pub(super) across: (usize, usize),
}

impl PalmDef {
    pub(super) fn observed(&self, side: Side, lm: &[Vec3; HAND_LANDMARKS]) -> Option<Mat3> {
        let mut sum = Vec3::ZERO;
        let mut n = 0.0;
        for (i, &m) in MCP.iter().enumerate() {
            if self.forward & (1 << i) != 0 {
                sum += lm[m];
                n += 1.0;
            }
        }
        let fwd = if n > 0.0 { sum / n } else { lm[MCP[1]] };
        frame_from(
            side,
            fwd - lm[0],
            lm[MCP[self.across.0]] - lm[MCP[self.across.1]],
        )
    }
}

/// Palmar normal of the triangle (wrist, a, b), oriented like `n`; `None` when thin.
pub(super) fn local_pole(wrist: Vec3, a: Vec3, b: Vec3, n: Vec3) -> Option<Vec3> {
    let (u, v) = (a - wrist, b - wrist);
    let c = u.cross(v);
    if c.length() < MIN_PALM_SINE * 0.5 * u.length() * v.length() || c.length() <= 0.0 {
        return None;
    }
    let c = c.normalize();
    Some(if c.dot(n) < 0.0 { -c } else { c })
}

/// The finger's base basis and model kind, given palm axes `(f, r, n)`, the pole and (thumb)
/// the index metacarpal line.
pub(super) fn basis_for(finger: Finger, f: Vec3, r: Vec3, n: Vec3, pole: Vec3) -> (Kind, Basis) {
    let fallback = Basis { x: f, y: r, z: n };
    match finger {
        Finger::Thumb => (
            Kind::Thumb,
            Basis::from_hints(pole, r, n).unwrap_or(Basis { x: r, y: n, z: f }),
        ),
        _ => (
            Kind::Finger,
            Basis::from_hints(pole, f, r).unwrap_or(fallback),
        ),
    }
}

/// The orthonormal frame `(x, y', x cross y')` of `x` and `y` made perpendicular to it;
/// `None` when degenerate.
pub(super) fn orthonormal_frame(x: Vec3, y: Vec3) -> Option<Mat3> {
    let x = x.try_normalize()?;
    let y = (y - y.dot(x) * x).try_normalize()?;
    Some(Mat3::from_cols(x, y, x.cross(y)))
}

/// Rotation taking `(a, b)` to `(c, d)`: `a`, `c` exactly, `b`, `d` after making them
/// perpendicular. Both pairs must be non-degenerate.
pub(super) fn frame_rotation(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Option<Quat> {
    let m = orthonormal_frame(c, d)? * orthonormal_frame(a, b)?.transpose();
    let q = Quat::from_mat3(&m).normalize();
    q.is_finite().then_some(q)
}
