//! Reading `.vrm` files (glTF 2.0 binary with the `VRMC_vrm` or `VRM` extension).
//!
//! FIRST VERSION: not yet implemented (issue 2, in progress).

use glam::Vec3;

use crate::bones::HumanBone;
use crate::error::{Error, Result};
use crate::skeleton::VrmVersion;

/// The humanoid part of a VRM file: version and rest world positions in the model's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct VrmHumanoid {
    /// VRM 0.x or 1.0.
    pub version: VrmVersion,
    /// Rest world position of every humanoid bone the file maps, model frame.
    pub bones: Vec<(HumanBone, Vec3)>,
}

/// Parses a `.vrm` file.
///
/// # Errors
/// Not implemented yet.
pub fn parse(_bytes: &[u8]) -> Result<VrmHumanoid> {
    Err(Error::Vrm("not implemented".into()))
}

/// Parses a `.vrm` file into a [`crate::Skeleton`].
///
/// # Errors
/// See [`parse`] and [`crate::Skeleton::new`].
pub fn load_skeleton(bytes: &[u8]) -> Result<crate::Skeleton> {
    let h = parse(bytes)?;
    crate::Skeleton::new(&h.bones, h.version)
}
