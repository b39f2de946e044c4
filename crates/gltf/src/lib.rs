//! The glTF document of a GLB, as handrig reads avatars (`HandRig.fromVrm`, `fromGltf`): the
//! container ([`glb`]), the mesh data's accessors ([`accessors`]) and the document with its node
//! hierarchy and transforms ([`document`]). handrig re-exports the three modules under
//! `handrig::humanoid`; see there for how they are used.
//!
//! A crate of its own only for the build: everything here runs once, when an avatar is loaded,
//! and most of its code is serde's derived readers, which a crate instantiates at its own
//! optimization level. The root `Cargo.toml` builds this crate for size and handrig's per-frame
//! code at opt-level 3.

pub mod accessors;
pub mod document;
pub mod error;
pub mod glb;
