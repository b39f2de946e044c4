//! The avatar's own body as simple colliders (as XR Animator's body colliders): a capsule for
//! the torso, one for the neck, a sphere for the head. Hand targets inside them are pushed out
//! (the hand moves rigidly, so the arm IK reaches a hand that rests on the body rather than in
//! it). Shapes are attached to bones and placed every frame from forward kinematics, so they
//! follow a moving torso and head.
//!
//! Sizes (documented defaults; `contact.torsoRadius` and `contact.headRadius` override them):
//! * torso: capsule from the hips joint to the highest chest bone (upperChest, chest or
//!   spine), radius 0.6 x the shoulder half-width (the upper-arm joints' mean distance from
//!   that line): about 0.105 m on an adult whose upper arms are 0.175 m from the spine;
//! * neck: capsule from the neck joint (or the torso's top) to the head joint, radius 0.45 x
//!   the torso's;
//! * head: sphere about the skull's center (0.1 head breadths below and 0.55 behind the point
//!   between the eyes, see [`super::face`]), radius half a head breadth.
//!
//! No collider may cover a face anchor: every radius is shrunk until each avatar anchor is at
//! least the fingertip's margin plus 2 mm outside it (so a finger on an anchor is never pushed
//! off it), and a collider shrunk to nothing is dropped.
//!
//! Hand points and their margins (half their thickness): wrist and palm center 0.2 x the
//! avatar's palm length, the aligned fingertip 0.1 x.

use glam::{Quat, Vec3};

use super::face::{AvatarFace, ANCHORS};
use crate::humanoid::bones::{HumanBone, Side};
use crate::humanoid::measure::avatar_palm_length;
use crate::humanoid::skeleton::{Skeleton, WorldPose};

/// Torso radius over shoulder half-width.
pub const TORSO_PER_SHOULDER: f32 = 0.6;
/// Neck radius over torso radius.
pub const NECK_PER_TORSO: f32 = 0.45;
/// Head sphere radius in head breadths.
pub const HEAD_RADIUS: f32 = 0.5;
/// Head sphere center relative to the point between the eyes, head breadths.
pub const HEAD_CENTER: Vec3 = Vec3::new(0.0, -0.1, -0.55);
/// Margin of the wrist and palm center over the avatar's palm length.
pub const HAND_MARGIN: f32 = 0.2;
/// Margin of the fingertip over the avatar's palm length.
pub const TIP_MARGIN: f32 = 0.1;
/// Clearance kept between a face anchor and every collider beyond the fingertip margin (m).
const ANCHOR_CLEARANCE: f32 = 0.002;

/// A collider placed in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A ball.
    Sphere {
        /// Center, world.
        center: Vec3,
        /// Radius, meters.
        radius: f32,
    },
    /// Every point within `radius` of the segment `a`-`b`.
    Capsule {
        /// One end of the core segment, world.
        a: Vec3,
        /// The other end.
        b: Vec3,
        /// Radius, meters.
        radius: f32,
    },
}

impl Shape {
    /// How deep a ball of radius `margin` at `p` is inside, and the outward direction
    /// (depth <= 0: outside).
    #[must_use]
    pub fn penetration(&self, p: Vec3, margin: f32) -> (f32, Vec3) {
        let (core, radius) = match *self {
            Shape::Sphere { center, radius } => (center, radius),
            Shape::Capsule { a, b, radius } => (closest_on_segment(p, a, b), radius),
        };
        let v = p - core;
        let d = v.length();
        // At the core itself any direction is out: forward (+Z), the likeliest side.
        let n = if d > 1e-9 { v / d } else { Vec3::Z };
        (radius + margin - d, n)
    }
}

fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 < 1e-12 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
}

/// A capsule between two bones' joints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoneCapsule {
    /// Bone whose joint is one end.
    pub from: HumanBone,
    /// Bone whose joint is the other end.
    pub to: HumanBone,
    /// Radius, meters.
    pub radius: f32,
}

/// The avatar's body colliders (rest definition; [`BodyColliders::shapes`] places them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyColliders {
    /// Torso capsule.
    pub torso: Option<BoneCapsule>,
    /// Neck capsule.
    pub neck: Option<BoneCapsule>,
    /// Head sphere: center relative to the head bone (head rest axes) and radius.
    pub head: Option<(Vec3, f32)>,
    /// Margins: wrist and palm center, fingertip (meters).
    pub hand_margin: f32,
    /// Fingertip margin (meters).
    pub tip_margin: f32,
}

impl BodyColliders {
    /// Derives the colliders from the rig (see the module docs), with the app's radii where
    /// given (`torso_radius`, `head_radius`, meters; 0 drops the collider).
    #[must_use]
    pub fn from_rig(
        skeleton: &Skeleton,
        face: &AvatarFace,
        torso_radius: Option<f32>,
        head_radius: Option<f32>,
    ) -> BodyColliders {
        let palm = avatar_palm_length(skeleton);
        let hand_margin = HAND_MARGIN * palm;
        let tip_margin = TIP_MARGIN * palm;
        let head_bone = skeleton.rest_world(HumanBone::Head).unwrap_or(Vec3::ZERO);
        let anchors: [Vec3; ANCHORS] = face.anchors.map(|a| head_bone + a);
        let keep = tip_margin + ANCHOR_CLEARANCE;
        // Largest radius about `core` (a point or segment) leaving every anchor outside.
        let fit = |radius: f32, a: Vec3, b: Vec3| {
            let room = anchors
                .iter()
                .map(|p| (*p - closest_on_segment(*p, a, b)).length() - keep)
                .fold(f32::INFINITY, f32::min);
            let r = radius.min(room);
            (r.is_finite() && r > 1e-4).then_some(r)
        };
        let top = [HumanBone::UpperChest, HumanBone::Chest, HumanBone::Spine]
            .into_iter()
            .find(|b| skeleton.has(*b));
        let rest = |b: HumanBone| skeleton.rest_world(b).unwrap_or(Vec3::ZERO);
        let torso = top.and_then(|top| {
            let (a, b) = (rest(HumanBone::Hips), rest(top));
            let half_width = Side::BOTH
                .iter()
                .filter_map(|s| skeleton.rest_world(s.arm()[1]))
                .map(|p| (p - closest_on_line(p, a, b)).length())
                .sum::<f32>()
                / 2.0;
            let r = torso_radius.unwrap_or(TORSO_PER_SHOULDER * half_width);
            fit(r, a, b).map(|radius| BoneCapsule {
                from: HumanBone::Hips,
                to: top,
                radius,
            })
        });
        let torso_r = torso.map_or(0.0, |t| t.radius);
        let neck = top.and_then(|top| {
            let from = if skeleton.has(HumanBone::Neck) {
                HumanBone::Neck
            } else {
                top
            };
            let r = NECK_PER_TORSO * torso_r;
            fit(r, rest(from), head_bone).map(|radius| BoneCapsule {
                from,
                to: HumanBone::Head,
                radius,
            })
        });
        let center = face.origin + HEAD_CENTER * face.size;
        let head = fit(
            head_radius.unwrap_or(HEAD_RADIUS * face.size),
            head_bone + center,
            head_bone + center,
        )
        .map(|r| (center, r));
        BodyColliders {
            torso,
            neck,
            head,
            hand_margin,
            tip_margin,
        }
    }

    /// The colliders placed by a posed avatar `world`: torso, neck, head (`None` where
    /// dropped).
    #[must_use]
    pub fn shapes(&self, world: &WorldPose) -> [Option<Shape>; 3] {
        let capsule = |c: &Option<BoneCapsule>| {
            c.map(|c| Shape::Capsule {
                a: world.position[c.from.index()],
                b: world.position[c.to.index()],
                radius: c.radius,
            })
        };
        let h = HumanBone::Head.index();
        let (hp, hr): (Vec3, Quat) = (world.position[h], world.rotation[h]);
        [
            capsule(&self.torso),
            capsule(&self.neck),
            self.head.map(|(c, radius)| Shape::Sphere {
                center: hp + hr * c,
                radius,
            }),
        ]
    }

    /// The translation that moves the hand (points with margins, world) out of every
    /// collider: each point in turn pushed straight out of each collider it is in
    /// (Gauss-Seidel projections, three passes, so that a push out of one collider into
    /// another is resolved). Continuous in the points (taking only the deepest point's push
    /// would jump where two points are equally deep), except on a collider's core line.
    #[must_use]
    pub fn push(&self, shapes: &[Option<Shape>; 3], points: &[(Vec3, f32)]) -> Vec3 {
        push_out(shapes.len(), points, |k, p, margin| {
            shapes[k].map(|shape| shape.penetration(p, margin))
        })
    }
}

/// Gauss-Seidel projections out of `count` bodies, three passes: for each body in turn, each
/// point (center, margin) moved with the translation so far and pushed straight out of it
/// when `depth(body, point, margin)` says it is in (depth > 0, outward normal). Shared by the
/// bone colliders (one body per shape) and the skin ([`super::skin::BodySurface::push`]: one
/// body, the deepest map). A non-finite result is zero.
pub(crate) fn push_out(
    count: usize,
    points: &[(Vec3, f32)],
    mut depth: impl FnMut(usize, Vec3, f32) -> Option<(f32, Vec3)>,
) -> Vec3 {
    let mut total = Vec3::ZERO;
    for _ in 0..3 {
        let mut moved = false;
        for k in 0..count {
            for (p, margin) in points {
                if let Some((d, n)) = depth(k, *p + total, *margin) {
                    if d > 0.0 {
                        total += n * d;
                        moved = true;
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
    if total.is_finite() {
        total
    } else {
        Vec3::ZERO
    }
}

fn closest_on_line(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let len2 = ab.length_squared();
    if len2 < 1e-12 {
        return a;
    }
    a + ab * ((p - a).dot(ab) / len2)
}
