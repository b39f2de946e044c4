//! What the avatar is: its bones, its rest skeleton with forward kinematics, its skin, its
//! measurements, and the readers that get them from files.
//!
//! Layers, each importing only from those above it in this list:
//!
//! * [`bones`]: the 55 VRM 1.0 humanoid bones, parent map, sides and fingers (the vocabulary).
//! * [`skin`]: [`SkinMesh`], the skinned meshes at rest that self-contact learns the body from.
//! * [`skeleton`]: [`Skeleton`], rest pose and forward kinematics over normalized bones.
//! * [`measure`]: the avatar's arm and palm lengths.
//! * [`glb`]: the GLB container (glTF binary).
//! * [`accessors`] and [`document`]: the glTF document, general to every glTF humanoid: the
//!   node hierarchy with three.js's transforms, extensions, mesh data.
//! * [`gltf_skin`]: the skin read from a document's skinned meshes.
//! * [`vrm`]: the VRM 1.0 / 0.x extensions on top of the document (`HandRig.fromVrm`).
//! * [`gltf`]: any glTF humanoid by bone names or a map (Mixamo, Unreal, a VRM; `fromGltf`).

pub mod bones;
pub mod gltf;
pub mod gltf_skin;
pub mod measure;
pub mod skeleton;
pub mod skin;
pub mod vrm;

// The glTF document's reader is its own crate (compiled for size: crates/gltf), under its old paths.
pub use handrig_gltf::{accessors, document, glb};

pub use bones::{Finger, HumanBone, Side, BONE_COUNT};
pub use skeleton::{Skeleton, VrmVersion, WorldPose};
pub use skin::SkinMesh;
