//! Stage 2, **pose**: the pose landmarks, One Euro filtered ([`crate::filter`]), feed
//! body-scale calibration ([`crate::body`]).

use crate::mediapipe::{pose_landmark, FrameInput};

use super::Rig;

impl Rig {
    /// Stage 2: this frame's pose, filtered, observed for body-scale calibration.
    pub(super) fn observe_pose(&mut self, frame: &FrameInput, dt: Option<f32>) {
        self.scratch.pose = frame.pose;
        if let Some(pose) = self.scratch.pose.as_mut() {
            if self.options.filter.enabled {
                let o = self.options.filter.one_euro();
                // Only the landmarks the rig reads: the pose's hands and legs are not used.
                self.pose_filters.apply_to(
                    &mut pose.world,
                    &pose_landmark::READ,
                    frame.time_ms,
                    dt,
                    &o,
                );
            }
            self.body.observe(pose);
        }
    }
}
