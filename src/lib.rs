//! # handrig
//!
//! MediaPipe hand and pose tracking to VRM avatar motion, every frame: finger rotations for
//! all 30 finger bones and the hand, a wrist IK target placed so the avatar's index fingertip
//! lands where the user's does (fingertip alignment), and the arm rotations reaching it, from
//! the torso the app draws or the one handrig tracks.
//!
//! ## Conventions
//!
//! Stated once, here and in the README; every public item follows them.
//!
//! * Units: **meters**, **radians**, milliseconds for time.
//! * Frame: **right-handed, +Y up**. The avatar **faces +Z** (VRM 1.0). VRM 0.x models face
//!   -Z; handrig turns them 180 degrees about +Y internally and turns every result back, so
//!   all inputs and outputs are in **the model's own frame** and apply directly to three-vrm's
//!   normalized bones (for VRM 0.x that is three-vrm's "negate quaternion x and z").
//! * Quaternions: **x, y, z, w** order, unit length.
//! * Bones: VRM 1.0 humanoid names (`leftIndexProximal`, ...), normalized: identity rest
//!   rotation, rotations are local to the parent normalized bone.
//! * The avatar's left is +X (VRM 1.0 frame); "left" and "right" without qualification mean the
//!   avatar's sides.
//!
//! ## Layout
//!
//! From the bottom up; a module imports only from those listed before it.
//!
//! * [`error`]: [`Error`], every message naming the offending field.
//! * [`math`]: clamp, angles on the circle, swing-twist, robust statistics.
//! * [`names`]: the declaration of named enumerations (JS names, `ALL`, `index`).
//! * [`humanoid`]: what the avatar is: the 55 humanoid [`humanoid::bones`], the rest
//!   [`Skeleton`] with forward kinematics, its [`SkinMesh`], its measurements, and the readers
//!   of `.vrm` ([`humanoid::vrm`]) and any glTF humanoid ([`humanoid::gltf`]) files.
//! * [`input`]: what a frame carries in: [`input::mediapipe`] (input types and the
//!   camera-to-avatar conversion, also at [`mediapipe`]) and [`input::validate`] (the one check
//!   of a frame every path runs).
//! * [`filter`]: One Euro smoothing and easing over tracking loss.
//! * [`solve`]: small allocation-free numerical solvers (box-constrained Gauss-Newton).
//! * [`kinematics`]: serial chains with fixed bone lengths and joint limits (hinge, cone).
//! * [`ik`]: arm IK solvers (two-bone, FABRIK, CCD) with anatomical wrist limits
//!   ([`ik::wrist`]), and the standalone [`ik::ChainSolver`].
//! * [`hand`]: wrist and finger rotations from 21 hand landmarks.
//! * [`align`]: fingertip alignment (the wrist IK target).
//! * [`body`]: body mapping and calibration from pose landmarks.
//! * [`torso`]: the upper body (hips, spine, chest, neck, head, shoulders) from the app or
//!   from tracking.
//! * [`contact`]: self-contact retargeting (finger on the face, hand on hand, the skin).
//! * [`options`]: [`RigOptions`] and the one table every option is described in.
//! * [`pipeline`]: the per-frame pipeline tying them together ([`Rig`]), one file per stage
//!   (select hands, pose, torso, hands, targets, reach, ease, report) and its output
//!   ([`SolveOutput`]).
//! * [`flat`]: the flat `f32` frame layout of the typed-array path (input and output).
//! * `wasm` (wasm32 only): the raw JavaScript bindings over [`flat`].

#![warn(missing_docs)]

pub mod align;
pub mod body;
pub mod contact;
pub mod error;
pub mod face;
pub mod filter;
pub mod flat;
pub mod hand;
pub mod humanoid;
pub mod ik;
pub mod input;
pub mod kinematics;
pub mod legs;
pub mod math;
pub mod names;
pub mod options;
pub mod pipeline;
pub mod solve;
pub mod torso;

#[cfg(target_arch = "wasm32")]
pub mod wasm;

pub use input::mediapipe;

pub use error::{Error, Result};
pub use humanoid::{Finger, HumanBone, Side, BONE_COUNT};
pub use humanoid::{Skeleton, SkinMesh, VrmVersion, WorldPose};
pub use input::{COORDINATE_LIMIT, HAND_CENTER_LIMIT, POSE_REACH_LIMIT};
pub use mediapipe::{CameraMapping, FrameInput, HandObservation, Handedness, PoseObservation};
pub use options::RigOptions;
pub use pipeline::{Rig, SolveOutput};
