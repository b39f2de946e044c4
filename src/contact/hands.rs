//! Hand-to-hand contact: when the user's hands touch, the avatar's do too.
//!
//! Both aligned wrists come from pose or tracker wrists with their own errors, and the
//! avatar's hands have their own proportions, so two plainly aligned hands that touch on the
//! user may overlap or miss each other on the avatar. Each hand has [`POINTS`] contact points
//! (the palm's center and the five fingertips) on the user (landmarks) and on the avatar
//! (forward kinematics of this frame's hand). For every pair of a left and a right point the
//! user's gap vector `c` (right point minus left point) is known; the avatar's should be
//! `k c`, `k` = avatar palm length / user palm length (the hands' own scale: a thinner
//! avatar hand keeps a proportionally thinner gap, so touching stays touching).
//!
//! The correction of the avatar's gap is one translation `D` between the hands, the
//! inverse-distance weighted mean (power 2, over pairs within the contact radius, each also
//! weighted by its blend) of the pairs' gap errors, so the touching pair is kept exactly.
//! Both hands move, half each, by `beta D`, with `beta` the largest pair blend: the
//! correction fades out continuously as the hands separate and is zero beyond the radius.

use glam::{Quat, Vec3};

use super::face::blend;

/// Contact points per hand: palm center, then the thumb to little fingertips.
pub const POINTS: usize = 6;

/// Finger landmarks per hand that face contact compares with the face: MediaPipe hand
/// landmarks 1-20 (finger `f`'s landmark `k`, base first, at `4 f + k`; the avatar's match is
/// `joints[3 f + k]` for `k < 3`, the fingertip `avatar[1 + f]` for `k = 3`).
pub const PARTS: usize = 20;

/// Where a side's wrist target, and so its user-space points, came from: decides which user
/// face its finger is measured against, and whether two hands can be compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// A body tracker's wrist (`frame.wrists`): the tracker's space (the avatar's frame).
    Tracker,
    /// MediaPipe pose landmarks: user space (meters, avatar axes, origin between the hips).
    Pose,
}

/// One hand's contact points, for face and hand-to-hand contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandPoints {
    /// Where the wrist came from.
    pub source: Source,
    /// The user's points (palm center, thumb..little tips) in the source's space: the wrist
    /// plus the hand landmarks' offsets from the hand's wrist landmark (avatar axes).
    pub user: [Vec3; POINTS],
    /// The avatar's points relative to the wrist IK target (world axes, this frame's hand
    /// and finger rotations); `None` where the avatar lacks the finger. A finger without its
    /// distal bone has its tip extrapolated ([`crate::align::part_offset`]); on an avatar
    /// without finger bones the aligned finger's slot holds the palm's front, which stands in
    /// for it ([`crate::align::AlignedPart::Palm`]).
    pub avatar: [Option<Vec3>; POINTS],
    /// The avatar's finger joints relative to the wrist IK target (world axes, this frame's
    /// rotations): per finger (thumb first) its three bones' joints, base first; `None` where
    /// the avatar lacks the bone. For keeping the whole hand out of the body.
    pub joints: [Option<Vec3>; 15],
    /// The user's palm length (wrist to middle MCP landmark), meters.
    pub user_palm: f32,
    /// The avatar's palm length (hand joint to middle proximal joint), meters.
    pub avatar_palm: f32,
    /// The aligned fingertip's image landmark (normalized, MediaPipe's), when the hand has
    /// image landmarks: with pose input, where on the face the finger is.
    pub image_tip: Option<Vec3>,
    /// The user's finger landmarks (MediaPipe hand landmarks 1-20: per finger, thumb first,
    /// its base, two joints and tip; [`PARTS`]) in the source's space like `user`, for face
    /// contact with the hand part nearest the face (a fist's knuckles on the forehead). Only
    /// with a skin, like `joints`; else zero.
    pub user_parts: [Vec3; PARTS],
    /// The image landmarks of `user_parts`, when the hand has image landmarks (with a skin).
    pub image_parts: Option<[Vec3; PARTS]>,
    /// What the image says about the hand for chest contact, when it has image landmarks.
    pub cue: Option<super::chest::HandCue>,
}

impl HandPoints {
    /// The avatar's points (`avatar`, `joints`) turned by `q` about the wrist target: the
    /// hand shown with another rotation. The user's points are left as they are.
    #[must_use]
    pub fn turned(mut self, q: Quat) -> HandPoints {
        for p in self
            .avatar
            .iter_mut()
            .chain(self.joints.iter_mut())
            .flatten()
        {
            *p = q * *p;
        }
        self
    }
}

/// The hand-to-hand correction of one frame (see [`solve`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandContact {
    /// Translations of the left and right wrist targets.
    pub shift: [Vec3; 2],
    /// The blend applied, `beta` (0..1).
    pub weight: f32,
    /// Where each hand meets the other, `[left, right]`, relative to its wrist target (world
    /// axes): the touching pair's points, or the mean of the near pairs' points with the
    /// correction's weights. The point each hand's wrist limits turn it about.
    pub meet: [Vec3; 2],
}

/// The hand-to-hand correction, or `None` when no pair is within the radius. `unit` is the
/// length the radius is measured in (the user's head breadth); `left_wrist` and
/// `right_wrist` are the wrist targets.
#[must_use]
pub fn solve(
    left: &HandPoints,
    left_wrist: Vec3,
    right: &HandPoints,
    right_wrist: Vec3,
    unit: f32,
    radius: f32,
    weight: f32,
) -> Option<HandContact> {
    if left.source != right.source || unit.is_nan() || unit <= 0.0 {
        return None;
    }
    let k = (left.avatar_palm + right.avatar_palm) / (left.user_palm + right.user_palm);
    if !(k.is_finite() && k > 0.0) {
        return None;
    }
    let mut sum = Vec3::ZERO;
    let mut total = 0.0f32;
    let mut beta = 0.0f32;
    let mut exact: Option<Vec3> = None;
    let mut meet = [Vec3::ZERO; 2];
    let mut exact_meet: Option<[Vec3; 2]> = None;
    for (i, lp) in left.avatar.iter().enumerate() {
        let Some(lp) = lp else { continue };
        for (j, rp) in right.avatar.iter().enumerate() {
            let Some(rp) = rp else { continue };
            let c = right.user[j] - left.user[i];
            let e = c.length() / unit;
            let b = blend(e, radius);
            if b <= 0.0 {
                continue;
            }
            beta = beta.max(b);
            let error = k * c - ((right_wrist + *rp) - (left_wrist + *lp));
            if e < 1e-6 {
                // Touching exactly: this pair decides (the first one found, if several).
                exact.get_or_insert(error);
                exact_meet.get_or_insert([*lp, *rp]);
                continue;
            }
            let w = b / (e * e);
            sum += w * error;
            meet[0] += w * *lp;
            meet[1] += w * *rp;
            total += w;
        }
    }
    let (d, meet) = match (exact, exact_meet) {
        (Some(d), Some(m)) => (d, m),
        _ if total > 0.0 => (sum / total, meet.map(|m| m / total)),
        _ => return None,
    };
    let beta = weight * beta;
    if !(beta > 0.0 && d.is_finite()) {
        return None;
    }
    let half = 0.5 * beta * d;
    Some(HandContact {
        shift: [-half, half],
        weight: beta,
        meet,
    })
}

/// How far apart two hands are in the image: the smallest distance between a landmark of
/// one and a landmark of the other over the larger image palm length (wrist to middle
/// knuckle); `None` for a degenerate hand. On the labeled sign-language clips, hands that
/// touch measure at most 0.35 (90% under 0.24); hands apart almost always over 0.5.
#[must_use]
pub fn image_apart(a: &[Vec3; 21], b: &[Vec3; 21]) -> Option<f32> {
    let palm = |h: &[Vec3; 21]| (h[9] - h[0]).truncate().length();
    let size = palm(a).max(palm(b));
    if size.is_nan() || size <= 1e-6 {
        return None;
    }
    let mut min = f32::INFINITY;
    for p in a {
        for q in b {
            min = min.min((*p - *q).truncate().length());
        }
    }
    let r = min / size;
    r.is_finite().then_some(r)
}
