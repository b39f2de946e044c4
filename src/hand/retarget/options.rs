//! The retargeting's options and its per-side report.

use glam::Vec3;

use crate::solve::least_squares::Settings;

/// Weights and stopping rule of the retargeting objective (see the module docs). Costs are
/// in m^2 (feature weights are dimensionless), so a regularization weight `w` in m^2/rad^2
/// makes one radian cost as much as a fingertip `sqrt(w)` meters off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RetargetOptions {
    /// Fingertip feature weights, thumb to little. Default: thumb and index 2, the others
    /// 1 (thumb and index emphasized for pinching, as the seed does).
    pub tip_weights: [f32; 5],
    /// Weight of each intermediate joint feature (the two joints between base and tip, hung
    /// back from the fingertip target along the user's phalanges). Default 0.02.
    pub joint_weight: f32,
    /// Weight of the pinch feature (the thumb tip relative to the index tip) when the user's
    /// scaled tips are within half of [`RetargetOptions::pinch_distance`]; it fades out
    /// smoothly to 0 at that distance. Default 10.
    pub pinch_weight: f32,
    /// Scaled thumb-index tip distance (m) below which the pinch feature starts to count.
    /// Default 0.04.
    pub pinch_distance: f32,
    /// Spatial term (DIP toward two thirds of PIP), m^2/rad^2. Default `2e-6` (a radian
    /// costs like a fingertip 1.4 mm off).
    pub spatial_weight: f32,
    /// Temporal term (toward the previous frame's angles), m^2/rad^2 per parameter, for a
    /// finger whose target stood still; it falls off as `1 / (1 + (v / temporal_speed)^2)`
    /// with the target's move `v` since the previous frame, so tracking noise is smoothed and
    /// real motion (a pinch closing) is followed with little lag. Default `4e-3` (a radian
    /// costs like a fingertip 63 mm off). Without a previous frame only a negligible
    /// [`DAMPING`] toward the starting point remains.
    pub temporal_weight: f32,
    /// The target move (m per frame) at which the temporal weight has halved. Default 3 mm
    /// (MediaPipe's fingertip noise is about 1 mm a frame, finger motion several).
    pub temporal_speed: f32,
    /// Gauss-Newton stopping rule. Default: at most 50 iterations, done when a step is
    /// under `1e-4` rad (a fingertip moves less than 10 micrometers).
    pub settings: Settings,
}

impl RetargetOptions {
    /// Whether every weight is finite and non-negative, the temporal weight, the temporal
    /// speed and the pinch distance positive (the temporal term keeps the Gauss-Newton model
    /// positive definite) and at least one iteration allowed.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        let finite = |v: &f32| v.is_finite() && *v >= 0.0;
        self.tip_weights.iter().all(finite)
            && [
                self.joint_weight,
                self.pinch_weight,
                self.spatial_weight,
                self.settings.step_tolerance,
            ]
            .iter()
            .all(finite)
            && [
                self.temporal_weight,
                self.temporal_speed,
                self.pinch_distance,
            ]
            .iter()
            .all(|v| finite(v) && *v > 0.0)
            && self.settings.max_iterations > 0
    }
}

/// Frames the automatic scale averages (about a second of video); afterwards it follows
/// slow changes as an exponential average over as many frames.
pub const SCALE_FRAMES: u32 = 30;
/// The straight extent of a user's open hand over its wrist-to-fingertip path length: the
/// automatic scale compares path lengths, the calibration extents (fingers never lie
/// perfectly straight; 0.94 to 0.97 on the shared recordings' most open frames).
pub const OPEN_EXTENT: f32 = 0.95;
/// Calibration needs every finger (index to little) this straight: the knuckle-to-tip
/// distance over the summed phalanx lengths.
pub const OPEN_HAND_STRAIGHTNESS: f32 = 0.9;
/// Weight (m^2/rad^2) toward the starting point on a frame without a previous solution:
/// keeps the Gauss-Newton model positive definite, moves a fingertip by well under a
/// micrometer.
pub const DAMPING: f32 = 1e-9;
/// What the retargeting did for one hand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RetargetReport {
    /// The scaled user fingertips placed on the avatar, thumb to little (`None` where the
    /// avatar lacks the finger's distal bone). From [`crate::hand::HandSolver::retarget_report`]:
    /// relative to the hand joint in the hand bone's frame; in [`crate::SolveOutput`]: world
    /// positions in the internal frame.
    pub targets: [Option<Vec3>; 5],
    /// Avatar hand size over user hand size (the uniform scale applied to the user's hand).
    pub scale: f32,
    /// Gauss-Newton iterations: the most any finger needed.
    pub iterations: u32,
    /// Weighted RMS distance between the avatar's fingertips and the targets, meters:
    /// `sqrt(sum w_f |tip_f - target_f|^2 / sum w_f)` with [`RetargetOptions::tip_weights`].
    pub residual: f32,
}
