//! Arms from hands alone: where the user's wrist is, relative to their shoulder, from a hand
//! tracker's result (no pose).
//!
//! A hand's normalized image landmarks say in which direction from the camera it is; its world
//! landmarks (meters, camera axes, about the hand's center) say how large it is. A pinhole
//! camera of vertical field of view `fov` sees a hand of metric size `S` (the landmarks' RMS
//! distance from their centroid, in the image plane's axes) at depth `Z` as `S * f / Z`
//! image heights, `f = 0.5 / tan(fov / 2)`; so `Z = f * S / s` from the image size `s`
//! (para-perspective: the hand is small against its distance, and a point nearer the camera by
//! `dz` off the optical axis shifts along its ray, which the world offsets are projected
//! with). Both sizes are measured on all
//! 21 points projected on the image plane, so a palm turned edge-on shrinks in both and the
//! ratio holds. The wrist is then `Z` along its image ray (its depth offset from the hand's
//! center from the world landmarks).
//!
//! The user's shoulders are assumed where a webcam framing puts them
//! ([`HandsOnlyOptions`]: the shoulder line at `shoulderY` of the image height, centered,
//! `distance` from the camera, shoulders 0.36 m apart as MediaPipe's pose measures an adult's);
//! the result is the wrist relative to the shoulder of the side, in camera axes. The rig maps
//! it onto the avatar as it maps a pose wrist (`avatar shoulder + body scale * offset`, the
//! scale calibrated from an earlier pose or assumed, [`crate::body`]). Pure functions,
//! nothing allocated.

use glam::Vec3;

use super::mediapipe::{CameraMapping, HandObservation, HAND_LANDMARKS};
use crate::humanoid::bones::Side;

/// Half the distance between the user's shoulder joints assumed (m): MediaPipe's pose world
/// landmarks put adults' shoulders 0.33-0.36 m apart (the sign-language clips).
pub const HALF_SHOULDERS: f32 = 0.18;
/// A hand smaller than this (m, RMS radius in the image plane) or its image (image heights)
/// is not measured: collapsed landmarks.
const MIN_WORLD_SIZE: f32 = 0.005;
const MIN_IMAGE_SIZE: f32 = 1e-4;

/// The camera and framing assumed for arms from hands alone (JS: `options.handsOnly`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandsOnlyOptions {
    /// Place the arms from the hands when no pose is given. Default `true`.
    pub enabled: bool,
    /// The camera's vertical field of view (radians). Default 1.05 (60°), a webcam's.
    pub fov: f32,
    /// The user's shoulders from the camera (m). Default 0.9: a user at a desk (the
    /// sign-language clips' signers are 0.90-0.97 m from theirs, seen with 60°).
    pub distance: f32,
    /// Where the shoulder line is in the image, 0 (top) to 1 (bottom). Default 0.7: a webcam
    /// framing the head and shoulders (the clips' upper-body framing has them at 0.34-0.49).
    pub shoulder_y: f32,
}

/// `tan(fov / 2)`, from `sin_cos` (which the crate uses anyway: `tan` alone would add libm's
/// `tanf` to the .wasm).
fn half_tan(fov: f32) -> f32 {
    let (s, c) = (0.5 * fov).sin_cos();
    s / c
}

/// The user's wrist from the camera (m, MediaPipe's camera axes: x right, y down, z away),
/// from a hand's image landmarks (`x, y` in 0..1 of the image, `aspect` = width / height) and
/// world landmarks. `None` without image landmarks, for a collapsed hand, or a non-finite
/// result.
#[must_use]
pub fn wrist_from_camera(hand: &HandObservation, fov: f32, aspect: f32) -> Option<Vec3> {
    let image = hand.image.as_ref()?;
    // Image points in image heights, about the image center.
    let at = |p: Vec3| Vec3::new((p.x - 0.5) * aspect, p.y - 0.5, 0.0);
    let n = HAND_LANDMARKS as f32;
    let image_center = image.iter().map(|p| at(*p)).sum::<Vec3>() / n;
    let world_center = hand.world.iter().sum::<Vec3>() / n;
    let f = 0.5 / half_tan(fov);
    // Off the optical axis a point nearer by `dz` also shifts by `ray * dz` in the image
    // (para-perspective): the world offsets are projected so before they are measured.
    let ray = image_center / f;
    let mut image_size = 0.0;
    let mut world_size = 0.0;
    for (i, w) in image.iter().zip(hand.world.iter()) {
        let d = *w - world_center;
        image_size += (at(*i) - image_center).length_squared();
        world_size += (d - ray * d.z).truncate().length_squared();
    }
    let (image_size, world_size) = ((image_size / n).sqrt(), (world_size / n).sqrt());
    if !(image_size > MIN_IMAGE_SIZE && world_size > MIN_WORLD_SIZE) {
        return None;
    }
    let depth = f * world_size / image_size + (hand.world[0].z - world_center.z);
    let w = at(image[0]);
    let p = Vec3::new(w.x / f, w.y / f, 1.0) * depth;
    (p.is_finite() && depth > 0.0).then_some(p)
}

/// The user's shoulder from the camera (m, camera axes) that drives avatar side `side`,
/// as [`HandsOnlyOptions`] assume it.
#[must_use]
pub fn assumed_shoulder(side: Side, camera: CameraMapping, o: &HandsOnlyOptions) -> Vec3 {
    let tan = half_tan(o.fov);
    // The avatar's left (+X) is camera +x unless the mapping flips x.
    let x = if (side == Side::Left) ^ camera.flips_x() {
        HALF_SHOULDERS
    } else {
        -HALF_SHOULDERS
    };
    Vec3::new(x, (o.shoulder_y - 0.5) * 2.0 * tan * o.distance, o.distance)
}

/// The furthest a wrist is placed from its shoulder (m): a long adult arm as MediaPipe's pose
/// measures it (0.52 m typical, [`crate::body`]).
pub const REACH: f32 = 0.6;
/// The furthest a wrist is placed behind its shoulder (m, along the camera's axis).
pub const BEHIND: f32 = 0.05;

/// The wrist moved along its camera ray (its image position is sure, its depth is not) to the
/// nearest depth within [`REACH`] of the shoulder and at most [`BEHIND`] behind it; where the
/// ray passes further than that from the shoulder, its nearest point to it.
#[must_use]
pub fn within_reach(wrist: Vec3, shoulder: Vec3) -> Vec3 {
    let depth = wrist.length();
    let ray = wrist / depth;
    // |t ray - shoulder| <= REACH: t within b -+ r.
    let b = ray.dot(shoulder);
    let disc = b * b - shoulder.length_squared() + REACH * REACH;
    let mut t = if disc > 0.0 {
        let r = disc.sqrt();
        // (min/max: `clamp` asserts its bounds, which NaN would fail.)
        depth.max(b - r).min(b + r)
    } else {
        b
    };
    if ray.z > 0.0 {
        t = t.min((shoulder.z + BEHIND) / ray.z);
    }
    ray * t.max(0.0)
}

/// Where the elbow goes, relative to the shoulder of `side` (m, the avatar's axes: down, a
/// little out and forward, as elbows are under hands raised in front of the body): the IK pole
/// of an arm placed from its hand alone. Without it the arm solver's default bend puts the
/// elbow out sideways when the hand comes near the shoulder, and an arm turning from rest to a
/// raised hand (eased in, or slowed by `arm.maxTurnSpeed`) passes through the T-pose.
#[must_use]
pub fn elbow_hint(side: Side) -> Vec3 {
    let out = if side == Side::Left { 0.1 } else { -0.1 };
    Vec3::new(out, -0.3, 0.1)
}

/// The user's wrist relative to their shoulder, in the avatar's axes (m): what
/// [`crate::body`] scales onto the avatar's shoulder. `None` when the rig is told not to
/// (`enabled: false`) or the hand cannot be measured ([`wrist_from_camera`]).
#[must_use]
pub fn wrist_offset(
    hand: &HandObservation,
    side: Side,
    camera: CameraMapping,
    o: &HandsOnlyOptions,
    aspect: f32,
) -> Option<Vec3> {
    if !o.enabled {
        return None;
    }
    let wrist = wrist_from_camera(hand, o.fov, aspect)?;
    let shoulder = assumed_shoulder(side, camera, o);
    Some(camera.to_avatar(within_reach(wrist, shoulder) - shoulder))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::mediapipe::Handedness;

    /// A flat hand-like spread of 21 points (m, about its center), turned by `tilt` radians
    /// about x (edge-on at pi/2), filmed by a camera of `fov` and `aspect` with its wrist at
    /// `wrist` (camera axes).
    fn filmed(wrist: Vec3, tilt: f32, fov: f32, aspect: f32) -> HandObservation {
        let rot = glam::Quat::from_rotation_x(tilt);
        let shape: [Vec3; HAND_LANDMARKS] = core::array::from_fn(|i| {
            let finger = (i as f32 - 1.0) / 4.0;
            let along = if i == 0 {
                0.0
            } else {
                0.03 + 0.025 * ((i - 1) % 4) as f32
            };
            rot * Vec3::new(
                0.02 * (finger - 2.0) * 0.6,
                -along - 0.01 * (i % 3) as f32,
                0.004 * (i % 5) as f32,
            )
        });
        let center = shape.iter().sum::<Vec3>() / HAND_LANDMARKS as f32;
        let world = shape.map(|p| p - center);
        let f = 0.5 / (0.5 * fov).tan();
        let image = shape.map(|p| {
            let c = wrist + p - shape[0]; // camera axes
            Vec3::new(c.x / c.z * f / aspect + 0.5, c.y / c.z * f + 0.5, 0.0)
        });
        HandObservation {
            handedness: Handedness::Left,
            score: 1.0,
            world,
            image: Some(image),
        }
    }

    #[test]
    fn a_filmed_wrist_is_found_within_a_few_centimeters() {
        for (wrist, tilt, fov, aspect) in [
            (Vec3::new(0.1, 0.05, 0.6), 0.0, 1.05, 16.0 / 9.0),
            (Vec3::new(-0.2, 0.2, 0.9), 0.8, 1.05, 4.0 / 3.0),
            (Vec3::new(0.0, -0.1, 0.45), 1.2, 0.8, 1.0),
        ] {
            let hand = filmed(wrist, tilt, fov, aspect);
            let got = wrist_from_camera(&hand, fov, aspect).unwrap();
            // Weak perspective: the error grows with the hand's size against its depth.
            assert!(
                (got - wrist).length() < 0.03 * wrist.z,
                "{wrist} {tilt}: {got}"
            );
            // The wrong field of view scales the depth.
            let wide = wrist_from_camera(&hand, fov * 1.3, aspect).unwrap();
            assert!(wide.z < got.z * 0.85, "{wide} vs {got}");
        }
    }

    #[test]
    fn no_image_or_a_collapsed_hand_gives_none() {
        let mut hand = filmed(Vec3::new(0.0, 0.0, 0.6), 0.0, 1.05, 1.0);
        let good = hand;
        hand.image = None;
        assert_eq!(wrist_from_camera(&hand, 1.05, 1.0), None);
        let mut hand = good;
        hand.image = Some([Vec3::splat(0.5); HAND_LANDMARKS]);
        assert_eq!(wrist_from_camera(&hand, 1.05, 1.0), None);
        let mut hand = good;
        hand.world = [Vec3::ZERO; HAND_LANDMARKS];
        assert_eq!(wrist_from_camera(&hand, 1.05, 1.0), None);
    }

    #[test]
    fn a_wrist_out_of_reach_or_behind_moves_along_its_ray() {
        let shoulder = Vec3::new(-0.18, 0.25, 0.7);
        // Within reach and in front: unchanged.
        let w = Vec3::new(-0.1, 0.1, 0.45);
        assert!((within_reach(w, shoulder) - w).length() < 1e-6);
        for w in [
            Vec3::new(-0.5, 0.4, 1.6),
            Vec3::new(-0.1, 0.1, 0.05),
            Vec3::new(-0.3, 0.35, 0.95),
        ] {
            let got = within_reach(w, shoulder);
            // Still on the wrist's ray (the image position kept)...
            assert!(got.normalize().dot(w.normalize()) > 0.9999, "{w}: {got}");
            // ...within reach, and not behind the shoulder.
            assert!((got - shoulder).length() <= REACH + 1e-4, "{w}: {got}");
            assert!(got.z <= shoulder.z + BEHIND + 1e-4, "{w}: {got}");
        }
        // A ray that passes further than the reach: its nearest point to the shoulder.
        let far = Vec3::new(1.5, -0.5, 1.0);
        let got = within_reach(far, shoulder);
        let ray = far.normalize();
        assert!((got - ray * ray.dot(shoulder)).length() < 1e-5, "{got}");
    }

    #[test]
    fn offsets_follow_the_side_and_the_mirroring() {
        let o = HandsOnlyOptions {
            enabled: true,
            fov: 1.05,
            distance: 0.7,
            shoulder_y: 0.8,
        };
        let plain = CameraMapping::default();
        let mirrored = CameraMapping {
            input_mirrored: false,
            mirror: true,
        };
        // A hand at the shoulder's own place gives a zero offset, on every side and mapping.
        for camera in [plain, mirrored] {
            for side in Side::BOTH {
                let s = assumed_shoulder(side, camera, &o);
                let hand = filmed(s, 0.0, o.fov, 1.5);
                let off = wrist_offset(&hand, side, camera, &o, 1.5).unwrap();
                assert!(off.length() < 0.03, "{side:?} {camera:?}: {off}");
                // The avatar's left shoulder is at +X in the avatar's axes.
                let x = camera.to_avatar(s).x;
                assert_eq!(x > 0.0, side == Side::Left);
            }
        }
        // A hand raised in front of the shoulder line's middle: up and forward for the avatar,
        // inward for either arm.
        let hand = filmed(Vec3::new(0.0, 0.0, 0.5), 0.0, o.fov, 1.5);
        let left = wrist_offset(&hand, Side::Left, plain, &o, 1.5).unwrap();
        let right = wrist_offset(&hand, Side::Right, plain, &o, 1.5).unwrap();
        assert!(left.y > 0.15 && left.z > 0.15 && left.x < -0.15, "{left}");
        assert!(right.x > 0.15, "{right}");
        let off = HandsOnlyOptions {
            enabled: false,
            ..o
        };
        assert_eq!(wrist_offset(&hand, Side::Left, plain, &off, 1.5), None);
    }
}
