//! Shared support of the integration tests (`tests/it/`, one binary): real recordings, rig
//! fixtures, synthetic hands and arms, geometry and statistics helpers. Benches and examples
//! include single files of it with `#[path = "../tests/support/<file>.rs"]`.

pub mod arms;
pub mod geometry;
pub mod hand_model;
pub mod kinect_wrists;
pub mod motion;
pub mod recordings;
pub mod rigs;
pub mod stats;
pub mod torso_user;
pub mod vrm_fixture;
