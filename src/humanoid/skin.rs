//! An avatar's skinned meshes at rest, as handrig keeps them ([`SkinMesh`]): read from the file
//! (`HandRig.fromVrm` / `fromGltf`, [`super::gltf_skin`]) or passed by the app
//! (`restPoseFromVRM`, from three-vrm's loaded meshes). What self-contact learns the body from.

use glam::Vec3;

use super::bones::HumanBone;
use crate::error::{Error, Result};

/// Largest rest coordinate accepted (meters). Bigger rest poses are rejected at load: a
/// 1e20 m arm overflows `f32` arithmetic in the solvers (squared lengths become infinite).
pub const MAX_REST_COORDINATE: f32 = 1000.0;

/// Most vertices a skin may have.
pub const MAX_VERTICES: usize = 2_000_000;
/// Most triangles a skin may have.
pub const MAX_TRIANGLES: usize = 4_000_000;
/// Added to a bone index in `restPose.skin.bones` ([`SkinMesh::from_flat`]): the vertex's
/// dominant joint is a non-humanoid bone under that humanoid bone ([`SkinMesh::hanging`]).
pub const HANGING: u8 = 0x80;
/// An avatar's skin at rest (what self-contact learns the body from): every vertex's rest
/// position and dominant humanoid bone (non-humanoid bones count as their nearest humanoid
/// ancestor), and the triangles. Internal frame (see [`super::Skeleton::with_skin`]).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SkinMesh {
    /// Rest positions (m).
    pub positions: Vec<Vec3>,
    /// Each vertex's dominant humanoid bone.
    pub bones: Vec<HumanBone>,
    /// Per vertex, whether its dominant joint is a non-humanoid bone under that humanoid bone
    /// (hair, cloth, an accessory) rather than the bone itself. Missing entries are `false`.
    pub hanging: Vec<bool>,
    /// Triangles, indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

impl SkinMesh {
    /// A skin from flat arrays as JS passes them (`restPose.skin`): `positions` 3 per vertex
    /// (meters, the model's own frame), `bones` one [`HumanBone::index`] per vertex, plus
    /// [`HANGING`] when the vertex's dominant joint is a non-humanoid bone under it,
    /// `triangles` 3 vertex indices each.
    ///
    /// # Errors
    /// Lengths that do not match, non-finite or out-of-range positions, unknown bone
    /// indices, triangle indices beyond the vertices (the field named: `restPose.skin.*`).
    pub fn from_flat(positions: &[f32], bones: &[u8], triangles: &[u32]) -> Result<SkinMesh> {
        if positions.len() % 3 != 0 || positions.len() / 3 != bones.len() {
            return Err(Error::invalid(
                "restPose.skin.positions",
                "must hold 3 numbers per vertex, one vertex per entry of restPose.skin.bones",
            ));
        }
        if bones.len() > MAX_VERTICES {
            return Err(Error::invalid(
                "restPose.skin.positions",
                "too many vertices (at most 2,000,000)",
            ));
        }
        if triangles.len() % 3 != 0 || triangles.len() / 3 > MAX_TRIANGLES {
            return Err(Error::invalid(
                "restPose.skin.triangles",
                "must hold 3 vertex indices per triangle (at most 4,000,000 triangles)",
            ));
        }
        let mut mesh = SkinMesh {
            positions: Vec::with_capacity(bones.len()),
            bones: Vec::with_capacity(bones.len()),
            hanging: Vec::with_capacity(bones.len()),
            triangles: Vec::with_capacity(triangles.len() / 3),
        };
        for (p, &b) in positions.chunks_exact(3).zip(bones) {
            let p = Vec3::new(p[0], p[1], p[2]);
            if !p.is_finite() || p.abs().max_element() > MAX_REST_COORDINATE {
                return Err(Error::invalid(
                    "restPose.skin.positions",
                    "every coordinate must be finite and within 1000 m of the origin",
                ));
            }
            let Some(bone) = HumanBone::ALL.get(usize::from(b & !HANGING)) else {
                return Err(Error::invalid(
                    "restPose.skin.bones",
                    "each entry must be a bone index of LAYOUT.bones (+128: hanging)",
                ));
            };
            mesh.positions.push(p);
            mesh.bones.push(*bone);
            mesh.hanging.push(b & HANGING != 0);
        }
        let n = bones.len() as u32;
        for t in triangles.chunks_exact(3) {
            if t.iter().any(|&i| i >= n) {
                return Err(Error::invalid(
                    "restPose.skin.triangles",
                    "a vertex index is beyond the vertices",
                ));
            }
            mesh.triangles.push([t[0], t[1], t[2]]);
        }
        Ok(mesh)
    }
}
