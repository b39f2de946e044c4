//! Shared support of handrig's integration tests (`tests/it/`), benches and evals (`eval/rust/`):
//! real recordings, rig fixtures, synthetic hands and arms, geometry and statistics helpers. A
//! dev-only crate (`handrig-support`, a dev-dependency of handrig), so every user imports it the
//! same way: `use handrig_support::recordings;`.

pub mod arms;
pub mod finger_dirs;
pub mod fist;
pub mod geometry;
pub mod hand_model;
pub mod kinect_wrists;
pub mod motion;
pub mod recordings;
pub mod rigs;
pub mod stats;
pub mod torso_user;
pub mod vrm_fixture;
