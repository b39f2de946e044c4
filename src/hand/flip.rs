//! Witnesses of a MediaPipe hand whose 3D shape is wrong: on real video the hand
//! world landmarks turn, for a few frames, into a hand whose fingers bend backwards (its
//! palm's front and back swapped: the mirror image of the hand) or whose knuckles lie across
//! the palm the other way than the image shows. Three witnesses, all per frame and
//! allocation-free:
//!
//! * [`chirality`]: how far the fingers bend to the palmar side of the palm frame built for
//!   the hand's side. A real hand flexes its fingers toward the palm; a mirrored one "flexes"
//!   them toward the back. Positive on a real hand that is not flat, negative on a mirror.
//! * [`image_agreement`]: whether the world landmarks' knuckle line (little to index MCP)
//!   points the way the image landmarks' does, in the image plane (depth plays no part there,
//!   so this witness is independent of the depth estimate). Negative when the world hand has
//!   the knuckles the other way round.
//! * the image landmarks themselves, made metric by [`image_hand`]: their depth comes from a
//!   separate estimate that flips less often (on the shared ASL clips their palm turns more
//!   than 90 degrees between frames 3 times against the world landmarks' 11). The rig no
//!   longer solves a rejected hand from them (it holds the last good hand): where the world
//!   landmarks fail on the clips, the image landmarks are wrong as often
//!   (`docs/how-it-works/hands-on-video.md`); kept for apps and evaluations.
//!
//! Failure cases: a flat hand has no flexion, so [`chirality`] is near 0 and says nothing
//! (the threshold [`MIRRORED`] leaves it alone); a hand seen edge-on has a short knuckle line
//! in the image and [`image_agreement`] is then unreliable (it returns `None` when the line is
//! under a tenth of the palm); a hand whose label is wrong has the wrong chirality on both
//! witnesses and is held, not solved.

use glam::Vec3;

use crate::humanoid::bones::Side;
use crate::input::mediapipe::{hand_landmark as lm, HAND_LANDMARKS};

use super::palm::palm_frame;

/// [`chirality`] below this is a mirrored hand (mean flexion of the four fingers, as a
/// fraction of the palm length: real hands sit at about 0.15 to 0.7, flat ones near 0, the
/// mirrored frames of the ASL clips at about -0.25 to -0.9).
pub const MIRRORED: f32 = -0.15;

/// The fingers' (index to little) mean palmar offset of the tip from the MCP, over the palm
/// length (wrist to middle MCP), in the palm frame [`palm_frame`] builds for `side`: positive
/// when the fingers bend toward the palm. `None` for a degenerate palm.
#[must_use]
pub fn chirality(side: Side, p: &[Vec3; HAND_LANDMARKS]) -> Option<f32> {
    let w = p[lm::WRIST];
    let frame = palm_frame(
        side,
        w,
        p[lm::INDEX_MCP],
        p[lm::PINKY_MCP],
        p[lm::MIDDLE_MCP],
    )?;
    let n = frame.z_axis;
    let palm = (p[lm::MIDDLE_MCP] - w).length();
    let sum: f32 = [lm::INDEX_MCP, lm::MIDDLE_MCP, lm::RING_MCP, lm::PINKY_MCP]
        .iter()
        .map(|&mcp| (p[mcp + 3] - p[mcp]).dot(n))
        .sum();
    Some(sum / (4.0 * palm))
}

/// The cosine between the world and the image knuckle lines (little MCP to index MCP) in the
/// image plane (x, y of MediaPipe's camera axes, both). `None` when either is too short to
/// tell (a hand seen edge-on).
#[must_use]
pub fn image_agreement(
    world: &[Vec3; HAND_LANDMARKS],
    image: &[Vec3; HAND_LANDMARKS],
) -> Option<f32> {
    let line = |p: &[Vec3; HAND_LANDMARKS]| {
        let v = (p[lm::INDEX_MCP] - p[lm::PINKY_MCP]).truncate();
        let palm = (p[lm::MIDDLE_MCP] - p[lm::WRIST]).truncate().length();
        (v.length() > 0.1 * palm && palm > 0.0).then(|| v.normalize())
    };
    Some(line(world)?.dot(line(image)?))
}

/// The image landmarks as a metric hand in MediaPipe's camera axes, centered on the wrist:
/// x and z scaled so the hand spans as far in x as the world hand does, y so it spans as far
/// in y (the image's x and y are normalized by its width and height, which the rig does not
/// know; its z uses x's scale). Returns `false` (and leaves `out` alone) when either hand has
/// no extent.
pub fn image_hand(
    world: &[Vec3; HAND_LANDMARKS],
    image: &[Vec3; HAND_LANDMARKS],
    out: &mut [Vec3; HAND_LANDMARKS],
) -> bool {
    let span = |p: &[Vec3; HAND_LANDMARKS]| {
        let (lo, hi) = p.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), q| (lo.min(*q), hi.max(*q)),
        );
        hi - lo
    };
    let (sw, si) = (span(world), span(image));
    if !(sw.x > 1e-6 && sw.y > 1e-6 && si.x > 1e-6 && si.y > 1e-6) {
        return false;
    }
    let (kx, ky) = (sw.x / si.x, sw.y / si.y);
    let wrist = image[lm::WRIST];
    for (o, p) in out.iter_mut().zip(image.iter()) {
        let d = *p - wrist;
        *o = Vec3::new(d.x * kx, d.y * ky, d.z * kx);
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A right hand in MediaPipe-like camera axes (x right, y down, z away): fingers up
    /// (forward -y), radial +x, the fingers (`bend`) and thumb bent to the palmar side
    /// (`r x f` for a right hand).
    fn right_hand(bend: f32) -> [Vec3; HAND_LANDMARKS] {
        let mut p = [Vec3::ZERO; HAND_LANDMARKS];
        let f = Vec3::NEG_Y;
        let r = Vec3::X;
        let n = r.cross(f);
        let mcps = [lm::INDEX_MCP, lm::MIDDLE_MCP, lm::RING_MCP, lm::PINKY_MCP];
        for (k, &m) in mcps.iter().enumerate() {
            let base = 0.09 * f + (0.03 - 0.02 * k as f32) * r;
            p[m] = base;
            for j in 1..4 {
                p[m + j] = base + 0.025 * j as f32 * f + bend * 0.02 * j as f32 * n;
            }
        }
        for (j, q) in p.iter_mut().enumerate().take(5).skip(1) {
            *q = 0.02 * j as f32 * (r + 0.5 * f) + 0.01 * j as f32 * n;
        }
        p
    }

    fn mirror_depth(p: &[Vec3; HAND_LANDMARKS]) -> [Vec3; HAND_LANDMARKS] {
        p.map(|q| Vec3::new(q.x, q.y, -q.z))
    }

    #[test]
    fn chirality_tells_a_hand_from_its_mirror() {
        let hand = right_hand(1.0);
        let c = chirality(Side::Right, &hand).unwrap();
        assert!(c > 0.2, "{c}");
        let m = chirality(Side::Right, &mirror_depth(&hand)).unwrap();
        assert!(m < MIRRORED, "{m}");
        // The same points read as a left hand are that hand's mirror.
        assert!(chirality(Side::Left, &hand).unwrap() < MIRRORED);
        // A flat hand says nothing either way.
        let flat = chirality(Side::Right, &right_hand(0.0)).unwrap();
        assert!(flat.abs() < 0.05, "{flat}");
    }

    #[test]
    fn image_agreement_sees_knuckles_the_other_way() {
        let hand = right_hand(1.0);
        assert!(image_agreement(&hand, &hand).unwrap() > 0.99);
        // Depth plays no part.
        assert!(image_agreement(&mirror_depth(&hand), &hand).unwrap() > 0.99);
        // Knuckles swapped across the palm in the image plane.
        let swapped = hand.map(|q| Vec3::new(-q.x, q.y, q.z));
        assert!(image_agreement(&swapped, &hand).unwrap() < -0.99);
        // Edge-on: the knuckle line has no length in the image.
        let edge = hand.map(|q| Vec3::new(0.0, q.y, q.z));
        assert_eq!(image_agreement(&edge, &hand), None);
    }

    #[test]
    fn image_hand_takes_the_world_extent_per_axis() {
        let world = right_hand(1.0);
        // The image: normalized by a 4:3 frame, shifted, depth scaled like x.
        let image = world.map(|q| Vec3::new(q.x / 0.64 + 0.5, q.y / 0.48 + 0.4, q.z / 0.64));
        let mut out = [Vec3::ZERO; HAND_LANDMARKS];
        assert!(image_hand(&world, &image, &mut out));
        for (o, w) in out.iter().zip(world.iter()) {
            assert!((*o - (*w - world[0])).length() < 1e-5, "{o} {w}");
        }
        let flat = [Vec3::ZERO; HAND_LANDMARKS];
        assert!(!image_hand(&world, &flat, &mut out));
    }
}
