//! A serial chain of joints with fixed bone lengths: what FABRIK, CCD and the arm solvers
//! share.
//!
//! ```text
//!   joints[0] ---bone 0--- joints[1] ---bone 1--- joints[2] ... joints[N-1]  (end)
//!     root (fixed)
//! ```
//!
//! Read once from rest joint positions (root first): each bone's length and rest direction,
//! and an optional [`JointLimit`] per bone. The root sits at a [`RootFrame`] (position and
//! rotation; the rest directions are in that frame, identity = the rest layout).
//!
//! ## Bone frames
//! A pose is N joint positions. Each bone's world rotation (from its rest direction) is its
//! parent's rotation followed by the *minimal* rotation (a swing, [`swing`]) taking its rest
//! direction onto its current direction, in the parent's frame; bone 0's parent is the root
//! frame. These are exactly normalized-bone local rotations without twist (the convention of
//! [`crate::ik::TwoBoneIk`]), and they carry each bone's limit frame: a hinge axis given in
//! bone `i - 1`'s frame turns with bone `i - 1`. Positions therefore determine rotations, so
//! the solvers work on positions and [`Chain::rotations`] reads the rotations off at the end.

use glam::{Quat, Vec3};

use crate::error::{Error, Result};

use super::limits::JointLimit;

/// Bones shorter than this (m) are rejected; directions shorter than this are undefined.
pub const MIN_BONE_LENGTH: f32 = 1e-6;

/// Where a chain's root is and how its frame is turned (world). The rest directions of the
/// bones are given in this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RootFrame {
    /// World position of joint 0.
    pub position: Vec3,
    /// World rotation of the root frame (the parent of bone 0); identity = rest layout.
    pub rotation: Quat,
}

/// How [`Chain::place`] decides where each bone points before its limit applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pull {
    /// Toward the next joint's current position (FABRIK's forward pass).
    Points,
    /// Along the bone's current direction (re-placing a chain after an upstream change).
    Directions,
    /// Toward one point (a straight chain toward an unreachable target).
    Toward(Vec3),
}

/// A chain of `N >= 2` joints: bone lengths, rest directions and limits (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    rest: Vec<Vec3>,
    lengths: Vec<f32>,
    directions: Vec<Vec3>,
    limits: Vec<Option<JointLimit>>,
    total: f32,
}

impl Chain {
    /// Reads a chain from rest joint positions (root first) and per-bone limits (`limits`
    /// empty for none, else one entry per bone, `None` for a free bone).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the field: fewer than 2 joints (`joints`), a non-finite
    /// joint, a zero-length bone or one whose length overflows f32 (`joints[k]`), a limit count other than 0 or N - 1
    /// (`constraints`), an invalid limit (`constraints[i].maxAngle`, ...).
    pub fn new(joints: &[Vec3], limits: &[Option<JointLimit>]) -> Result<Chain> {
        if joints.len() < 2 {
            return Err(Error::invalid("joints", "needs at least 2 joints"));
        }
        let bones = joints.len() - 1;
        if let Some(k) = joints.iter().position(|p| !p.is_finite()) {
            return Err(Error::invalid(
                format!("joints[{k}]"),
                "must be three finite numbers",
            ));
        }
        if !(limits.is_empty() || limits.len() == bones) {
            return Err(Error::invalid(
                "constraints",
                format!("must have one entry per bone ({bones}), or be omitted"),
            ));
        }
        let mut lengths = Vec::with_capacity(bones);
        let mut directions = Vec::with_capacity(bones);
        for k in 1..joints.len() {
            let d = joints[k] - joints[k - 1];
            let len = d.length();
            if len.is_nan() || len < MIN_BONE_LENGTH {
                return Err(Error::invalid(
                    format!("joints[{k}]"),
                    format!("coincides with joints[{}]: bones need a length", k - 1),
                ));
            }
            if !len.is_finite() {
                return Err(Error::invalid(
                    format!("joints[{k}]"),
                    "too far from the previous joint: the bone's length overflows f32",
                ));
            }
            lengths.push(len);
            directions.push(d / len);
        }
        let total: f32 = lengths.iter().sum();
        if !total.is_finite() {
            return Err(Error::invalid("joints", "the chain's length overflows f32"));
        }
        let mut checked = vec![None; bones];
        for (i, l) in limits.iter().enumerate() {
            if let Some(l) = l {
                checked[i] = Some(l.validated(&format!("constraints[{i}]"))?);
            }
        }
        Ok(Chain {
            rest: joints.to_vec(),
            total,
            lengths,
            directions,
            limits: checked,
        })
    }

    /// Number of joints `N`.
    #[inline]
    #[must_use]
    pub fn joint_count(&self) -> usize {
        self.rest.len()
    }

    /// Number of bones `N - 1`.
    #[inline]
    #[must_use]
    pub fn bone_count(&self) -> usize {
        self.lengths.len()
    }

    /// Rest joint positions, root first.
    #[inline]
    #[must_use]
    pub fn rest_joints(&self) -> &[Vec3] {
        &self.rest
    }

    /// The root at its rest position with identity rotation.
    #[inline]
    #[must_use]
    pub fn rest_root(&self) -> RootFrame {
        RootFrame {
            position: self.rest[0],
            rotation: Quat::IDENTITY,
        }
    }

    /// Bone lengths (m).
    #[inline]
    #[must_use]
    pub fn lengths(&self) -> &[f32] {
        &self.lengths
    }

    /// Unit rest direction of each bone (root frame).
    #[inline]
    #[must_use]
    pub fn rest_directions(&self) -> &[Vec3] {
        &self.directions
    }

    /// The sum of the bone lengths: the farthest the end gets from the root.
    #[inline]
    #[must_use]
    pub fn total_length(&self) -> f32 {
        self.total
    }

    /// The nearest the end gets to the root (0 unless one bone is longer than all the others
    /// together), ignoring limits.
    #[must_use]
    pub fn min_reach(&self) -> f32 {
        let longest = self.lengths.iter().copied().fold(0.0, f32::max);
        (2.0 * longest - self.total).max(0.0)
    }

    /// The limit of bone `i`, if any.
    #[inline]
    #[must_use]
    pub fn limit(&self, bone: usize) -> Option<JointLimit> {
        self.limits[bone]
    }

    /// Whether any bone has a limit.
    #[must_use]
    pub fn has_limits(&self) -> bool {
        self.limits.iter().any(Option::is_some)
    }

    /// Replaces the limit of `bone` (no allocation: for limits that change per solve, such as
    /// the arm solvers' shoulder cone). `bone` must be `< bone_count()`.
    ///
    /// # Errors
    /// An invalid limit (field `constraints[bone]`).
    pub fn set_limit(&mut self, bone: usize, limit: Option<JointLimit>) -> Result<()> {
        self.limits[bone] = match limit {
            Some(l) => Some(l.validated("constraints")?),
            None => None,
        };
        Ok(())
    }

    /// The reference direction of bone `i` in its parent's frame, the one its limit measures
    /// from: the parent bone's rest direction, for bone 0 its own rest direction.
    #[inline]
    #[must_use]
    pub fn reference(&self, bone: usize) -> Vec3 {
        self.directions[bone.saturating_sub(1)]
    }

    /// World rotation of bone `i` given its parent's world rotation `parent` and its direction
    /// `local` in the parent's frame: `parent * swing(rest direction -> local)`. A half turn
    /// swings about the hinge axis (for hinged bones) or a fixed perpendicular.
    #[inline]
    #[must_use]
    pub fn bone_rotation(&self, bone: usize, parent: Quat, local: Vec3) -> Quat {
        let rest = self.directions[bone];
        let fallback = self.limits[bone]
            .and_then(|l| l.hinge_axis())
            .unwrap_or_else(|| rest.any_orthonormal_vector());
        (parent * swing(rest, local, fallback)).normalize()
    }

    /// Each bone's world rotation (from its rest direction) for the pose `joints`, with the
    /// root frame turned by `root_rotation` (see the module docs). `out` holds one per bone.
    /// A zero-length bone in `joints` (never produced by the solvers) keeps its parent's
    /// rotation.
    pub fn rotations(&self, root_rotation: Quat, joints: &[Vec3], out: &mut [Quat]) {
        let mut frame = root_rotation;
        for (i, slot) in out.iter_mut().enumerate().take(self.bone_count()) {
            let dir = (joints[i + 1] - joints[i])
                .try_normalize()
                .filter(|d| d.is_finite())
                .unwrap_or(frame * self.directions[i]);
            frame = self.bone_rotation(i, frame, frame.conjugate() * dir);
            *slot = frame;
        }
    }

    /// Forward kinematics: joint positions from per-bone *local* rotations (each in its
    /// parent's frame; bone 0's in the root frame), like [`crate::Skeleton::forward`] for
    /// this sub-chain. `out` holds one position per joint.
    pub fn forward(&self, root: &RootFrame, local: &[Quat], out: &mut [Vec3]) {
        let mut frame = root.rotation;
        out[0] = root.position;
        for i in 0..self.bone_count() {
            frame *= local[i];
            out[i + 1] = out[i] + frame * (self.directions[i] * self.lengths[i]);
        }
    }

    /// The largest limit violation (radians) of the pose `joints` with bone rotations
    /// `rotations` (as a solve reports them: each limit is measured in its parent's reported
    /// frame). 0 for a chain without limits.
    #[must_use]
    pub fn max_violation(&self, root_rotation: Quat, joints: &[Vec3], rotations: &[Quat]) -> f32 {
        let mut worst = 0.0f32;
        for i in 0..self.bone_count() {
            let frame = if i == 0 {
                root_rotation
            } else {
                rotations[i - 1]
            };
            let Some(limit) = self.limits[i] else {
                continue;
            };
            let dir = (joints[i + 1] - joints[i])
                .try_normalize()
                .unwrap_or(frame * self.directions[i]);
            worst = worst.max(limit.violation(frame.conjugate() * dir, self.reference(i)));
        }
        worst
    }

    /// Places the chain from the root outward, each bone pointing as `pull` says and then
    /// limited: the constrained forward pass. `end_direction` (world, unit) overrides the
    /// last bone's wanted direction. Bone lengths come out exact; the result satisfies every
    /// limit, measured in the bone rotations written to `frames` (one per bone, the frames
    /// the limits were applied in: near a half-turn from rest, where a swing's twist is
    /// ill-conditioned, they are more accurate than [`Chain::rotations`] of the rounded
    /// positions). Where a wanted direction is undefined (coincident points) the bone keeps
    /// its previous direction.
    pub fn place(
        &self,
        root: &RootFrame,
        joints: &mut [Vec3],
        pull: Pull,
        end_direction: Option<Vec3>,
        frames: &mut [Quat],
    ) {
        let last = self.bone_count() - 1;
        let mut frame = root.rotation;
        let mut old = joints[0];
        joints[0] = root.position;
        for i in 0..=last {
            let old_next = joints[i + 1];
            let previous = (old_next - old)
                .try_normalize()
                .filter(|d| d.is_finite())
                .unwrap_or(frame * self.directions[i]);
            let wanted = match (end_direction, pull) {
                (Some(d), _) if i == last => d,
                (_, Pull::Points) => old_next - joints[i],
                (_, Pull::Directions) => previous,
                (_, Pull::Toward(t)) => t - joints[i],
            };
            let wanted = wanted
                .try_normalize()
                .filter(|d| d.is_finite())
                .unwrap_or(previous);
            let inverse = frame.conjugate();
            let mut local = inverse * wanted;
            if let Some(limit) = self.limits[i] {
                local = limit.constrain(local, self.reference(i), inverse * previous);
            }
            joints[i + 1] = joints[i] + (frame * local) * self.lengths[i];
            frame = self.bone_rotation(i, frame, local);
            frames[i] = frame;
            old = old_next;
        }
    }
}

/// The minimal rotation taking unit vector `from` onto unit vector `to` (a swing: its axis
/// is perpendicular to both, so no twist about either). When they are opposite the rotation
/// is half a turn about `fallback_axis` made perpendicular to `from` (any perpendicular if
/// that fails). Always a finite unit quaternion; accurate to f32 rounding at every angle.
#[must_use]
pub fn swing(from: Vec3, to: Vec3, fallback_axis: Vec3) -> Quat {
    // The half-angle quaternion `(from x to, 1 + cos) / |from + to|` without trigonometry,
    // with `1 + cos = |from + to|^2 / 2` (unit vectors): that keeps full precision near a half
    // turn, where `1 + from.to` would cancel and `from + to` (like the cross product) does not.
    let cross = from.cross(to);
    let sin = cross.length();
    let cos = from.dot(to);
    if sin > 1e-7 && sin.is_finite() && cos.is_finite() {
        let sum = (from + to).length_squared();
        return Quat::from_xyzw(cross.x, cross.y, cross.z, 0.5 * sum).normalize();
    }
    if cos.is_nan() || cos >= 0.0 {
        return Quat::IDENTITY;
    }
    let axis = (fallback_axis - from * from.dot(fallback_axis))
        .try_normalize()
        .unwrap_or_else(|| from.any_orthonormal_vector());
    if axis.is_finite() {
        Quat::from_axis_angle(axis, core::f32::consts::PI)
    } else {
        Quat::IDENTITY
    }
}

/// Turns joints `first..N-1` (and the end joint `N-1` too with `include_end`) rigidly about
/// the line from joint `first - 1` (the pivot) to `target` so that the bend of the middle
/// joints `first..N-1` (the sum of their offsets across that line) faces `pole`: the pole
/// step of seed 002, generalized from the elbow to any number of middle joints. With the end
/// on the line (or turned along) lengths and the angles between bones are kept. Returns the
/// angle turned (radians, 0 when the pole or the bend is undefined: pole or all middle
/// joints on the line).
pub fn turn_toward_pole(
    joints: &mut [Vec3],
    first: usize,
    target: Vec3,
    pole: Vec3,
    include_end: bool,
) -> f32 {
    let n = joints.len();
    if first == 0 || first + 1 >= n {
        return 0.0;
    }
    let pivot = joints[first - 1];
    let Some(axis) = (target - pivot).try_normalize().filter(|a| a.is_finite()) else {
        return 0.0;
    };
    let across = |v: Vec3| v - axis * axis.dot(v);
    let want = across(pole - pivot);
    let bend: Vec3 = joints[first..n - 1]
        .iter()
        .map(|&p| across(p - pivot))
        .sum();
    let scale = (pole - pivot).length() + bend.length();
    if !(want.length() > 1e-6 * scale && bend.length() > 1e-6 * scale) {
        return 0.0;
    }
    let angle = axis.dot(bend.cross(want)).atan2(bend.dot(want));
    if angle.abs() < 1e-7 {
        return 0.0;
    }
    let q = Quat::from_axis_angle(axis, angle);
    let end = if include_end { n } else { n - 1 };
    for p in &mut joints[first..end] {
        *p = pivot + q * (*p - pivot);
    }
    angle.abs()
}

/// Turns each middle joint `first..N-1` about the line through its two neighbours (which
/// keeps both its bones' lengths and every other joint) to the point of that circle furthest
/// toward the pole, across the line from joint `first - 1` to the end; sweeps until no joint
/// moves (at most N sweeps). With two bones this is the plain pole rule; with more it takes
/// middle joints that the reaching passes left on the far side (a zigzag) over to the
/// pole's side where their circle reaches it. Changes the angles between bones: only for
/// bones without limits.
pub fn settle_on_pole_side(joints: &mut [Vec3], first: usize, pole: Vec3) {
    let n = joints.len();
    if first == 0 || first + 1 >= n {
        return;
    }
    let pivot = joints[first - 1];
    let Some(axis) = (joints[n - 1] - pivot)
        .try_normalize()
        .filter(|a| a.is_finite())
    else {
        return;
    };
    let Some(toward) = (pole - pivot - axis * axis.dot(pole - pivot))
        .try_normalize()
        .filter(|d| d.is_finite())
    else {
        return;
    };
    for _ in 0..n {
        let mut moved = false;
        for j in first..n - 1 {
            let (a, b) = (joints[j - 1], joints[j + 1]);
            let Some(u) = (b - a).try_normalize() else {
                continue;
            };
            let foot = a + u * u.dot(joints[j] - a);
            let radius = (joints[j] - foot).length();
            let Some(out) = (toward - u * u.dot(toward)).try_normalize() else {
                continue;
            };
            let moved_to = foot + out * radius;
            if (moved_to - joints[j]).dot(toward) > 1e-7 * radius {
                joints[j] = moved_to;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
}

/// When the middle joints `first..N-1` lie on the line from joint `first - 1` to the end
/// (a straight chain) while `target` is nearer than the chain is long, bows them out toward
/// `side` (any vector with a component across that line) by a small arc, so that the
/// reaching passes can fold the chain in a defined plane instead of collapsing it along the
/// line. Does nothing otherwise. The lengths are restored by the next pass.
pub fn bow_if_straight(
    joints: &mut [Vec3],
    first: usize,
    lengths: &[f32],
    target: Vec3,
    side: Vec3,
) {
    let n = joints.len();
    if first == 0 || first + 1 >= n {
        return;
    }
    let pivot = joints[first - 1];
    let end = joints[n - 1];
    let Some(axis) = (end - pivot).try_normalize().filter(|a| a.is_finite()) else {
        return;
    };
    let span: f32 = lengths[first - 1..].iter().sum();
    if (target - pivot).length() > span * (1.0 - 1e-4) {
        return;
    }
    let across = |v: Vec3| v - axis * axis.dot(v);
    let straight = joints[first..n - 1]
        .iter()
        .all(|&p| across(p - pivot).length() <= 1e-4 * span);
    let Some(out) = across(side).try_normalize().filter(|d| d.is_finite()) else {
        return;
    };
    if !straight {
        return;
    }
    let mut s = 0.0;
    for k in first..n - 1 {
        s += lengths[k - 1];
        let t = s / span;
        joints[k] += out * (0.05 * span * (core::f32::consts::PI * t).sin());
    }
}

/// The angle (radians) between unit vectors `a` and `b` measured about the unit `axis`
/// after projecting both onto the plane perpendicular to it (signed, right hand), or `None`
/// when either projection vanishes.
#[must_use]
pub fn angle_about(axis: Vec3, a: Vec3, b: Vec3) -> Option<f32> {
    let pa = a - axis * axis.dot(a);
    let pb = b - axis * axis.dot(b);
    let scale = a.length() * b.length();
    if scale.is_nan() || scale <= 0.0 || pa.length() * pb.length() <= 1e-10 * scale {
        return None;
    }
    Some(axis.dot(pa.cross(pb)).atan2(pa.dot(pb)))
}
