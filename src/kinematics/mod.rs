//! Kinematics shared by every solver: serial chains with fixed bone lengths and joint limits.
//!
//! * [`chain`]: [`Chain`], N joints read from rest positions (lengths, rest directions,
//!   limits), bone frames, sub-chain forward kinematics and the constrained placement pass
//!   FABRIK and CCD share.
//! * [`limits`]: [`JointLimit`] (hinge and cone, each in the parent bone's frame).
//!
//! * `iterative` (crate-internal): helpers FABRIK and CCD share (options check, warm-start
//!   anchoring, pole step, bow of a straight chain).
//!
//! The IK methods built on these live in [`crate::ik`].

pub mod chain;
pub(crate) mod iterative;
pub mod limits;

pub use chain::{swing, Chain, Pull, RootFrame};
pub use limits::JointLimit;
