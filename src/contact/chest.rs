//! Chest contact: a hand resting on the user's chest or belly rests on the avatar's.
//!
//! MediaPipe's depth cannot tell a hand on the chest from one in front of it: on the shared
//! sign-language clips the pose puts the wrist of a hand flat on the chest 32-35 cm in front
//! of the shoulders, farther than the hands signing in front of the body (median 26 cm), and
//! the hand's image size against the shoulders' separates the two no better (chest
//! hand-frames 0.89-1.04 shoulder widths, others over the torso 0.37-1.27). What does
//! decide ([`weight`]), each cue a smooth ramp:
//!
//! * **over the torso** in the image: the palm's center within the shoulders' width of the
//!   torso's middle (`|u| <= 0.5`, fading out by 0.6) and between the shoulders' and 45% of the
//!   way to the hips (`v` in -0.05..0.45, fading over 0.05), `u`, `v` measured along the
//!   image's shoulder line and shoulder-to-hip line ([`TorsoImage::coordinates`]);
//! * **the hand on the body**, either of:
//!   * **a flat palm turned to the body** (its back to the camera: the hand's image chirality
//!     against its label, [`HandCue::facing`]), its fingertips' mean distance from the wrist
//!     at least 1.55 palm lengths (fading from 1.35), from the world landmarks; a bent hand
//!     in front of the chest (the other hand's palm in `again`) is not resting on it;
//!   * **a hand of any shape that looks as near as the body** ([`HandCue::scale`] against
//!     [`TorsoImage::scale`]: each one's image size over its metric size from MediaPipe's
//!     world landmarks, the hand's from its palm, the body's from the shoulders): at least
//!     1.3 times the body's (fading from 1.1). Chosen on the tune half of the labeled clips
//!     (`again`, `eat`, `please`, `sister`: 49 of 50 chest hand-frames at 1.2, 6 of 142 other
//!     hand-frames over the torso), reported on the other half (`brother`, `hungry`,
//!     `thanks`: 24 of 32 chest hand-frames of `hungry`'s curved hand, 15 of 54 others over
//!     the torso, 11 of them hands touching each other, which the next cue leaves out);
//!     **and at most 1.85 times (fading out by 2.0)**: the reading measures nearness to the
//!     camera, and a hand held well before the chest with its palm to the body reads far
//!     higher than one resting on it (the ground-truth bench, `eval/bench/chest-cue.mjs`, on
//!     the tuning avatar, the woman: 0.87-1.52 on the chest, 1.99-3.9 held 18 cm before it,
//!     flat, curved, fist or at the collar; the real tuning clips' chest hand-frames, flat
//!     palms, up to 1.87 on 48 of 50). The upper edge lies between the two; chosen on the
//!     woman and the tuning clips only, reported on the bench's man and child and the real
//!     report half (docs/measurements/2026-12-06-contact-any-avatar.md, "Chest cue for every
//!     hand shape"). It does not take a fist on the chest (0.87-0.97 on the woman) nor
//!     `hungry`'s curved hand at the collar (0.9-1.0): no reading of the hand's shape found
//!     on the tuning data takes them without putting signing hands on the chest. What it
//!     costs: real hands on the chest that read above the edge (on the report half `hungry`'s
//!     curved hand low on the chest, 63% -> 58% of its chest hand-frames; `please`'s flat hand
//!     curled into a fist 87% -> 83%): on real video the readings above 1.85 were all hands on
//!     the chest, on the bench's renders most hands before it (MediaPipe reads the rendered
//!     hand with the wrong chirality there). A recording of a real hand held before the chest
//!     would settle which edge is right;
//! * **the other hand away**: its palm center more than 0.5 shoulder widths off (fading from
//!   0.4): two hands together over the torso are touching each other (hand-to-hand contact).
//!
//! Measured on the labeled clips (eval/labels): these cues select all 50 hand-frames labeled
//! chest and 1 of the 290 labeled none whose hand is in the image (docs/how-it-works/contact.md). With the
//! size cue, also most of a curved hand's (`hungry`: docs/measurements/2026-12-06-contact-speed.md).
//!
//! Where: the palm's `(u, v)` carried onto the avatar's torso (its upper-arm joints for the
//! shoulders, upper-leg joints for the hips), then the hand settled onto the chest skin along
//! the torso's normal ([`super::skin::BodySurface::settle`]).

use glam::Vec3;

use crate::math::clamp;

/// The user's torso in the image: the pose's image shoulders and hips (normalized image
/// coordinates), `[pose left, pose right]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsoImage {
    /// Pose landmarks 11 and 12.
    pub shoulders: [Vec3; 2],
    /// Pose landmarks 23 and 24.
    pub hips: [Vec3; 2],
    /// The shoulders' image distance (x scaled by the image aspect) over their metric
    /// distance across the camera (the pose's world landmarks' x and y): how large the body
    /// looks for its size. 0 when unknown.
    pub scale: f32,
}

impl TorsoImage {
    /// `(u, v)` of an image point: `u` along the shoulder line from its middle, in shoulder
    /// widths, positive toward the pose's left shoulder; `v` down from the shoulders' middle
    /// toward the hips' middle, in that distance. `None` for a degenerate torso.
    #[must_use]
    pub fn coordinates(&self, p: Vec3) -> Option<(f32, f32)> {
        let mid = 0.5 * (self.shoulders[0] + self.shoulders[1]);
        let across = (self.shoulders[0] - self.shoulders[1]).truncate();
        let down = (0.5 * (self.hips[0] + self.hips[1]) - mid).truncate();
        let (a2, d2) = (across.length_squared(), down.length_squared());
        if a2.is_nan() || d2.is_nan() || a2 <= 1e-8 || d2 <= 1e-8 {
            return None;
        }
        let q = (p - mid).truncate();
        Some((q.dot(across) / a2, q.dot(down) / d2))
    }
}

/// What the image says about one hand, for chest contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandCue {
    /// The palm's center in the image (normalized; the mean of the wrist and four knuckles).
    pub palm: Vec3,
    /// How much the palm faces away from the camera: the image-plane sine between the
    /// wrist-to-index and wrist-to-little knuckle lines, signed by the hand's label (positive:
    /// the palm turned away from the camera, toward the body).
    pub facing: f32,
    /// The four fingertips' mean distance from the wrist over the palm's length (world
    /// landmarks): about 1.9 for a flat hand, under 1 for a fist.
    pub extension: f32,
    /// The palm's image size (wrist to index, middle and little knuckles, index to little
    /// knuckle; x scaled by the image aspect) over its metric size (the same lengths of the
    /// world landmarks): how large the hand looks for its size, as [`TorsoImage::scale`].
    /// 0 when unknown.
    pub scale: f32,
}

/// [`HandCue::scale`] of a hand's image and world landmarks.
#[must_use]
pub fn hand_scale(image: &[Vec3; 21], world: &[Vec3; 21], aspect: f32) -> f32 {
    const SEGMENTS: [(usize, usize); 4] = [(0, 5), (0, 9), (0, 17), (5, 17)];
    let (mut seen, mut size) = (0.0, 0.0);
    for (a, b) in SEGMENTS {
        let d = image[b] - image[a];
        seen += (d.x * aspect).hypot(d.y);
        size += (world[b] - world[a]).length();
    }
    let s = seen / size;
    if s.is_finite() {
        s
    } else {
        0.0
    }
}

/// [`TorsoImage::scale`] of the shoulders' image and world landmarks.
#[must_use]
pub fn torso_scale(image: [Vec3; 2], world: [Vec3; 2], aspect: f32) -> f32 {
    let d = image[0] - image[1];
    let w = world[0] - world[1];
    let s = (d.x * aspect).hypot(d.y) / w.x.hypot(w.y);
    if s.is_finite() {
        s
    } else {
        0.0
    }
}

/// Smoothstep from 0 at `edge0` to 1 at `edge1` (0 for NaN).
#[must_use]
pub fn smooth(edge0: f32, edge1: f32, x: f32) -> f32 {
    let t = clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    if t.is_nan() {
        return 0.0;
    }
    t * t * (3.0 - 2.0 * t)
}

/// How sure the image is that this hand rests on the torso (0..1; see the module docs), and
/// its `(u, v)`; `other`: the other hand's cue, if seen.
#[must_use]
pub fn weight(torso: &TorsoImage, hand: &HandCue, other: Option<&HandCue>) -> (f32, f32, f32) {
    let Some((u, v)) = torso.coordinates(hand.palm) else {
        return (0.0, 0.0, 0.0);
    };
    let over =
        (1.0 - smooth(0.5, 0.6, u.abs())) * smooth(-0.1, -0.05, v) * (1.0 - smooth(0.45, 0.5, v));
    let facing = smooth(0.05, 0.25, hand.facing);
    let flat = smooth(1.35, 1.55, hand.extension);
    let near = if torso.scale > 0.0 {
        let s = hand.scale / torso.scale;
        smooth(1.1, 1.3, s) * (1.0 - smooth(1.85, 2.0, s))
    } else {
        0.0
    };
    let apart = other
        .and_then(|o| torso.coordinates(o.palm))
        .map_or(1.0, |(ou, ov)| {
            let d = ((ou - u).powi(2) + (1.4 * (ov - v)).powi(2)).sqrt();
            smooth(0.4, 0.5, d)
        });
    let w = over * (facing * flat).max(near) * apart;
    (if w.is_finite() { w } else { 0.0 }, u, v)
}
