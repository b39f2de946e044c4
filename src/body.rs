//! Body mapping and calibration from MediaPipe pose world landmarks.
//!
//! The user's arm is mapped onto the avatar's shoulder with one body scale `s`:
//! `avatar point = avatar shoulder + s * (user point - user shoulder)`.
//!
//! FIRST VERSION: fixed scale from options; calibration follows (issue 4).

use glam::Vec3;
use serde::Deserialize;

use crate::bones::Side;
use crate::error::{Error, Result};
use crate::mediapipe::{pose_landmark as pl, CameraMapping, PoseObservation};
use crate::skeleton::Skeleton;

/// Calibration options (JS: `options.calibration`).
#[derive(Clone, Copy, Debug, PartialEq, Default, Deserialize)]
#[serde(rename_all = "camelCase", default, deny_unknown_fields)]
pub struct CalibrationOptions {
    /// A preset body scale; `None` (default) calibrates automatically.
    pub body_scale: Option<f32>,
}

impl CalibrationOptions {
    /// Checks ranges.
    ///
    /// # Errors
    /// A preset scale that is not positive and finite.
    pub fn validate(&self) -> Result<()> {
        if let Some(s) = self.body_scale {
            if !(s.is_finite() && s > 0.0) {
                return Err(Error::invalid(
                    "options.calibration.bodyScale",
                    "must be a positive number",
                ));
            }
        }
        Ok(())
    }
}

/// The user's arm mapped onto the avatar (internal frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArmMapping {
    /// Mapped wrist.
    pub wrist: Vec3,
    /// Mapped elbow (IK pole), when visible.
    pub elbow: Option<Vec3>,
}

/// Body mapping state.
#[derive(Clone, Debug)]
pub struct BodyMapper {
    scale: f32,
    preset: Option<f32>,
}

impl BodyMapper {
    /// New mapper for `skeleton`.
    #[must_use]
    pub fn new(_skeleton: &Skeleton, options: &CalibrationOptions) -> Self {
        BodyMapper {
            scale: options.body_scale.unwrap_or(1.0),
            preset: options.body_scale,
        }
    }

    /// The body scale in force.
    #[must_use]
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Restarts calibration.
    pub fn reset(&mut self) {
        self.scale = self.preset.unwrap_or(1.0);
    }

    /// Feeds one pose frame to calibration.
    pub fn observe(
        &mut self,
        _skeleton: &Skeleton,
        _pose: &PoseObservation,
        _camera: CameraMapping,
    ) {
    }

    /// Maps the user's arm driving avatar side `side` onto the avatar.
    #[must_use]
    pub fn map_arm(
        &self,
        skeleton: &Skeleton,
        side: Side,
        pose: &PoseObservation,
        camera: CameraMapping,
    ) -> Option<ArmMapping> {
        let user = camera.pose_side_for(side);
        let (sh, el, wr) = match user {
            Side::Left => (pl::LEFT_SHOULDER, pl::LEFT_ELBOW, pl::LEFT_WRIST),
            Side::Right => (pl::RIGHT_SHOULDER, pl::RIGHT_ELBOW, pl::RIGHT_WRIST),
        };
        let shoulder = skeleton.rest_world(side.arm()[1])?;
        let map =
            |i: usize| shoulder + self.scale * camera.to_avatar(pose.world[i] - pose.world[sh]);
        Some(ArmMapping {
            wrist: map(wr),
            elbow: (pose.visibility[el] >= 0.5).then(|| map(el)),
        })
    }
}
