//! What a frame carries in, at the bottom of the crate's imports (nothing here imports the
//! pipeline, body, torso or contact stages):
//!
//! * [`mediapipe`]: the input types ([`FrameInput`] and its parts) and the camera-to-avatar
//!   conversion ([`CameraMapping`]).
//! * [`torso`]: the app's torso rotations and body-tracker joints (re-exported by
//!   [`crate::torso`]).
//! * [`hand_wrist`]: the wrist from a hand's image position and size, for arms from hands
//!   alone.
//! * [`validate`]: the one check of a frame every path runs (native [`crate::Rig::solve`] and
//!   the flat decoder, [`crate::flat::read_input`]).

pub mod hand_wrist;
pub mod mediapipe;
pub mod torso;
pub mod validate;

pub use mediapipe::{
    CameraMapping, FrameInput, HandObservation, Handedness, PoseObservation, TrackerFace,
    WristObservation,
};
pub use torso::{BodyJoint, BodyObservation, TorsoRotations};
pub use validate::{COORDINATE_LIMIT, HAND_CENTER_LIMIT, POSE_REACH_LIMIT};
