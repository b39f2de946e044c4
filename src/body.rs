//! Body mapping and calibration from MediaPipe pose world landmarks.
//!
//! ## Mapping
//! The user's arm is carried onto the avatar's shoulder with one body scale `s`:
//!
//! ```text
//! avatar point = avatar shoulder + s * (user point - user shoulder)      (avatar frame)
//! ```
//!
//! for the wrist and the elbow (the IK pole), and [`crate::align`] applies the same `s` to the
//! hand's wrist-to-DIP offset, so the target DIP is `avatar shoulder + s * (user DIP - user
//! shoulder)`: one similarity transform of the user's whole arm and hand.
//!
//! Why this form: a body tracker such as the Kinect of seed 000 already gives the wrist in
//! the avatar's frame; that is the `wrists` input, where `s = 1` and the target DIP is
//! `pose wrist + (hand DIP - hand wrist)`, exactly the seed formula. MediaPipe pose landmarks
//! are instead in the user's own metric body (origin between the hips), and an avatar may be
//! a 1.2 m chibi or a 1.9 m giant. Anchoring at the shoulder (the IK chain's fixed root) and
//! scaling by `avatar arm / user arm` keeps every point the user can reach within the
//! avatar's reach, and keeps the hand's gesture (a touch on the face) in proportion to the
//! arm that makes it. The residual mismatch, the avatar's hand being proportionally smaller
//! or larger than the user's, is what fingertip alignment then removes.
//!
//! ## Relative to the torso
//! The shoulder is the avatar's upper-arm joint as the torso poses it this frame, and the
//! user's arm (and hand) is measured in the user's upper-torso frame and placed in the
//! avatar's ([`BodyMapper::map_arm_from`], [`ArmAnchor`]):
//!
//! ```text
//! avatar point = posed avatar shoulder + s * T * (user point - user shoulder),
//! T = avatar upper-torso frame * user upper-torso frame^-1                (avatar frame)
//! ```
//!
//! (frames as [`crate::torso`] measures them). When the avatar's torso follows the user's
//! (`torso: "pose"`), `T` is the identity and this is the form above from the posed
//! shoulder. When it does not (the app's torso, or its rest pose), the arm keeps its pose
//! relative to the torso: a user who leans forward with the hands still at the chest keeps
//! the avatar's hands at its chest instead of reaching forward. `torso: "off"` keeps the rest
//! shoulder and world axes ([`BodyMapper::map_arm`]).
//!
//! ## Calibration
//! Lengths only, so a moving torso does not bias it (a lean or a turn changes no length).
//! `s = avatar arm length / user arm length`, arm length = upper + lower arm (shoulder to
//! elbow plus elbow to wrist). The avatar's is the mean of its two arms' rest lengths. The
//! user's is sampled once per visible arm per pose frame (shoulder, elbow and wrist at or
//! above [`CalibrationOptions::min_visibility`]) over [`CalibrationOptions::frames`] frames
//! that had a sample. Samples further than 20% from their median are dropped (a mis-tracked
//! elbow, a foreshortened arm) and the rest averaged. While frames are still being
//! collected, `s` is the same robust estimate over the samples so far (so the first frames
//! are already usable); before any sample it is `avatar arm / 0.52 m`, a typical adult
//! shoulder-to-wrist length as MediaPipe measures it. Once complete, `s` stays fixed until
//! [`BodyMapper::reset`]. A preset [`CalibrationOptions::body_scale`] disables all of this.
//! Samples live in a fixed array: observing a frame allocates nothing.
//!
//! ## Missing or poor input (decided behaviour)
//! * No pose this frame: nothing is observed or mapped; the [`crate::Rig`] then places the arm
//!   of a tracked hand from the hand's image ([`crate::input::hand_wrist`], with this mapper's
//!   body scale) or leaves the arm at rest (the hand still gets its solved world rotation).
//! * Shoulder or wrist of the driving side below `min_visibility`: [`BodyMapper::map_arm`]
//!   returns `None` (MediaPipe guesses landmarks it cannot see; an arm chasing a guess looks
//!   worse than an arm at rest), so the arm rests as above.
//! * Elbow below `min_visibility`: the wrist is still mapped, without a pole; the arm IK then
//!   uses its natural default elbow direction.
//! * Low-visibility arms add no calibration samples; the scale keeps its last value.
//! * Pose present but no hand: the arm reaches the mapped wrist; the hand follows the
//!   forearm (nothing to align).

use glam::{Quat, Vec3};

use crate::humanoid::bones::Side;
use crate::humanoid::measure::avatar_arm_length;
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::{pose_landmark as pl, CameraMapping, PoseObservation};
use crate::math::{insert_sorted, robust_mean_sorted};

/// Largest accepted [`CalibrationOptions::frames`]; sizes the sample buffer.
pub const MAX_CALIBRATION_FRAMES: usize = 300;
/// The user arm length (m) assumed before any calibration sample: a typical adult
/// shoulder-to-wrist distance in MediaPipe pose world landmarks.
pub const REFERENCE_USER_ARM: f32 = 0.52;
/// Shortest user arm (m) taken as a sample; shorter means collapsed landmarks.
const MIN_USER_ARM: f32 = 0.05;

/// Calibration options (JS: `options.calibration`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalibrationOptions {
    /// A preset body scale (avatar arm / user arm), positive; `None` (default) calibrates
    /// automatically from pose landmarks.
    pub body_scale: Option<f32>,
    /// How many pose frames with a visible arm calibration collects before it fixes the
    /// scale; 1..=300. Default 30 (one second at 30 fps).
    pub frames: usize,
    /// Landmarks whose visibility is below this (0..1) are treated as not seen. Default 0.5.
    pub min_visibility: f32,
}

impl CalibrationOptions {}

/// The user's arm mapped onto the avatar (internal frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmMapping {
    /// Mapped wrist.
    pub wrist: Vec3,
    /// Mapped elbow (IK pole), when visible.
    pub elbow: Option<Vec3>,
}

/// Body mapping and calibration state (one per rig).
#[derive(Clone, Debug)]
pub struct BodyMapper {
    options: CalibrationOptions,
    /// Mean rest arm length (upper + lower) of the avatar, m.
    avatar_arm: f32,
    scale: f32,
    /// User arm length samples (m), `count` valid, in ascending order ([`insert_sorted`]).
    samples: [f32; 2 * MAX_CALIBRATION_FRAMES],
    count: usize,
    /// Pose frames that contributed at least one sample.
    frames_seen: usize,
}

impl BodyMapper {
    /// New mapper for `skeleton`. `options` should have passed
    /// [`crate::RigOptions::validate`]; out-of-range `frames` is clamped to 1..=300.
    #[must_use]
    pub fn new(skeleton: &Skeleton, options: &CalibrationOptions) -> Self {
        let mut options = *options;
        options.frames = options.frames.clamp(1, MAX_CALIBRATION_FRAMES);
        let avatar_arm = avatar_arm_length(skeleton);
        let mut m = BodyMapper {
            options,
            avatar_arm,
            scale: 1.0,
            samples: [0.0; 2 * MAX_CALIBRATION_FRAMES],
            count: 0,
            frames_seen: 0,
        };
        m.reset();
        m
    }

    /// The body scale in force (avatar arm / user arm).
    #[must_use]
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The avatar's arm length (m, mean of both arms' upper + lower rest lengths).
    #[must_use]
    pub fn avatar_arm(&self) -> f32 {
        self.avatar_arm
    }

    /// Whether the scale is final: preset, or calibration has collected all its frames.
    #[must_use]
    pub fn is_calibrated(&self) -> bool {
        self.options.body_scale.is_some() || self.frames_seen >= self.options.frames
    }

    /// How many pose frames have contributed samples since the last reset.
    #[must_use]
    pub fn frames_observed(&self) -> usize {
        self.frames_seen
    }

    /// Restarts calibration (a preset scale stays in force).
    pub fn reset(&mut self) {
        self.count = 0;
        self.frames_seen = 0;
        self.scale = match self.options.body_scale {
            Some(s) => s,
            None if self.avatar_arm > 0.0 => self.avatar_arm / REFERENCE_USER_ARM,
            None => 1.0,
        };
    }

    /// Feeds one pose frame to calibration: one arm-length sample per arm whose shoulder,
    /// elbow and wrist are all visible. Does nothing with a preset scale or once calibrated.
    /// Allocates nothing.
    pub fn observe(&mut self, pose: &PoseObservation) {
        if self.is_calibrated() {
            return;
        }
        let mut added = false;
        for [sh, el, wr] in [
            [pl::LEFT_SHOULDER, pl::LEFT_ELBOW, pl::LEFT_WRIST],
            [pl::RIGHT_SHOULDER, pl::RIGHT_ELBOW, pl::RIGHT_WRIST],
        ] {
            // NaN visibility compares false: not seen.
            let seen = [sh, el, wr]
                .iter()
                .all(|&i| pose.visibility[i] >= self.options.min_visibility);
            if !seen {
                continue;
            }
            // The camera mapping is a reflection at most: lengths are the same either way.
            let len = (pose.world[el] - pose.world[sh]).length()
                + (pose.world[wr] - pose.world[el]).length();
            if len.is_finite() && len >= MIN_USER_ARM && self.count < self.samples.len() {
                insert_sorted(&mut self.samples, self.count, len);
                self.count += 1;
                added = true;
            }
        }
        if added {
            self.frames_seen += 1;
            if let Some(user_arm) = robust_mean_sorted(&self.samples[..self.count]) {
                if self.avatar_arm > 0.0 {
                    self.scale = self.avatar_arm / user_arm;
                }
            }
        }
    }

    /// Maps the user's arm driving avatar side `side` onto the avatar at rest (internal
    /// frame): `avatar shoulder + s * (user point - user shoulder)` for the wrist and (when
    /// visible) the elbow, with the avatar's rest upper-arm joint and world axes (the
    /// `torso: "off"` mapping; [`BodyMapper::map_arm_from`] with [`ArmAnchor::rest`]). `None`
    /// when the driving side's shoulder or wrist is below `min_visibility` or the avatar lacks
    /// the upper arm.
    #[must_use]
    pub fn map_arm(
        &self,
        skeleton: &Skeleton,
        side: Side,
        pose: &PoseObservation,
        camera: CameraMapping,
    ) -> Option<ArmMapping> {
        let anchor = ArmAnchor::rest(skeleton, side)?;
        self.map_arm_from(side, pose, camera, anchor)
    }

    /// Maps the user's arm driving avatar side `side` onto the avatar whose upper-arm joint and
    /// torso are `anchor`: `anchor.shoulder + s * anchor.rotation * (user point - user
    /// shoulder)` for the wrist and (when visible) the elbow (internal frame). With
    /// `anchor.rotation` the turn from the user's upper-torso frame to the avatar's, the arm
    /// keeps its pose relative to the torso: a lean or a turn is not read as a reach (see
    /// [`crate::torso`]). `None` when the driving side's shoulder or wrist is below
    /// `min_visibility`.
    #[must_use]
    pub fn map_arm_from(
        &self,
        side: Side,
        pose: &PoseObservation,
        camera: CameraMapping,
        anchor: ArmAnchor,
    ) -> Option<ArmMapping> {
        let user = camera.pose_side_for(side);
        let (sh, el, wr) = match user {
            Side::Left => (pl::LEFT_SHOULDER, pl::LEFT_ELBOW, pl::LEFT_WRIST),
            Side::Right => (pl::RIGHT_SHOULDER, pl::RIGHT_ELBOW, pl::RIGHT_WRIST),
        };
        let seen = |i: usize| pose.visibility[i] >= self.options.min_visibility;
        if !(seen(sh) && seen(wr)) {
            return None;
        }
        let map = |i: usize| {
            anchor.shoulder
                + self.scale * (anchor.rotation * camera.to_avatar(pose.world[i] - pose.world[sh]))
        };
        let wrist = map(wr);
        let elbow = seen(el).then(|| map(el));
        wrist.is_finite().then_some(ArmMapping {
            wrist,
            elbow: elbow.filter(|e| e.is_finite()),
        })
    }
}

/// Where a user's arm is placed on the avatar by [`BodyMapper::map_arm_from`] (internal frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmAnchor {
    /// The avatar's upper-arm joint (posed by the torso), where the user's shoulder lands.
    pub shoulder: Vec3,
    /// Rotation applied to the user's arm vectors (avatar axes): the avatar's upper-torso
    /// frame times the inverse of the user's.
    pub rotation: Quat,
}

impl ArmAnchor {
    /// The avatar's rest upper-arm joint, world axes (`None` without the bone).
    #[must_use]
    pub fn rest(skeleton: &Skeleton, side: Side) -> Option<ArmAnchor> {
        Some(ArmAnchor {
            shoulder: skeleton.rest_world(side.arm()[1])?,
            rotation: Quat::IDENTITY,
        })
    }
}
