//! The avatar's skin read from a glTF binary (`HandRig.fromVrm`, `HandRig.fromGltf`): the
//! [`SkinMesh`] that self-contact learns the body from, the same one `restPoseFromVRM` builds
//! from three-vrm's loaded meshes.
//!
//! What is read: every primitive (triangles, `mode` 4, indexed or not) of every node that has
//! both a `mesh` and a `skin`: `POSITION` (VEC3 float), `JOINTS_0` (VEC4 unsigned byte or
//! short), `WEIGHTS_0` (VEC4 float, or normalized unsigned byte or short), the indices (unsigned
//! byte, short or int), the skin's `joints` and `inverseBindMatrices` (MAT4 float; absent:
//! identity), from buffer views of the GLB's BIN chunk (with or without `byteStride`).
//!
//! A vertex's rest position is glTF's skinned position at rest, `sum_i w_i * jointWorld_i *
//! inverseBind_i * v`, the joints' world transforms through the node hierarchy with every node
//! at its own TRS (weights normalized to sum 1 as three.js's `GLTFLoader` does; all zero: the
//! first joint's). In a file in bind pose this is three's `bindMatrix * v`, what
//! `restPoseFromVRM` passes; otherwise it is still the mesh at rest. Its bone is the nearest
//! humanoid ancestor (itself included) of the joint with the largest weight (the first such
//! when weights tie); a vertex without one is left out, and a triangle is kept when its three
//! corners are. Morph targets are not applied (three's `position` attribute either).
//!
//! Anything this cannot read (a sparse or quantized accessor, a missing attribute, an
//! accessor, view or buffer index out of range, data past the end of the buffer, a joint
//! index beyond the skin's joints, an index beyond the vertices, an external buffer) skips
//! that primitive, never the file: the skin is a refinement, the bones are what the rig
//! needs. Nothing here panics whatever the bytes.

use glam::Vec3;

use super::accessors::{uint, Elements, MeshData, Primitive, F32, U16, U32, U8};
use super::bones::HumanBone;
use super::document::MAX_DEPTH;
use super::document::{Affine, Document};
use super::skin::{SkinMesh, MAX_REST_COORDINATE, MAX_TRIANGLES, MAX_VERTICES};

/// The skin of a read document's skinned meshes for the humanoid bound by `binding` (bone,
/// node); `bytes`: the file the document was read from.
pub(crate) fn skin_of(doc: &Document, bytes: &[u8], binding: &[(HumanBone, usize)]) -> SkinMesh {
    let bin = bytes.get(doc.bin.clone()).unwrap_or(&[]);
    read(doc, bin, binding)
}

/// One skin's joints at rest: `jointWorld * inverseBind` and the humanoid bone of each (and
/// whether the joint is a non-humanoid bone under it).
struct Joints {
    matrices: Vec<Affine>,
    bones: Vec<Option<(HumanBone, bool)>>,
}

/// Reads the skin of a GLB whose humanoid binds `binding` (bone, node). `bin`: the BIN chunk
/// (empty when there is none). Empty when nothing could be read.
pub(crate) fn read(doc: &Document, bin: &[u8], binding: &[(HumanBone, usize)]) -> SkinMesh {
    let data = &doc.meshes;
    let n = doc.tree.len();
    let mut bone_of_node: Vec<Option<HumanBone>> = vec![None; n];
    for &(b, node) in binding {
        if let Some(slot) = bone_of_node.get_mut(node) {
            *slot = Some(b);
        }
    }
    let mut world = vec![None; n];
    let mut joints_of_skin: Vec<Option<Option<Joints>>> = Vec::new();
    joints_of_skin.resize_with(data.skins.0.len(), || None);
    let mut out = SkinMesh::default();
    let mut last: Last = (NONE, Vec::new());
    for node in &doc.nodes {
        let (Some(mesh), Some(skin)) = (uint(node.get("mesh")), uint(node.get("skin"))) else {
            continue;
        };
        let Some(mesh) = data.meshes.get(Some(mesh)) else {
            continue;
        };
        let Some(slot) = joints_of_skin.get_mut(skin) else {
            continue;
        };
        let joints = slot
            .get_or_insert_with(|| skin_joints(doc, data, bin, skin, &bone_of_node, &mut world));
        let Some(joints) = joints.as_ref() else {
            continue;
        };
        for p in &mesh.primitives {
            read_primitive(data, bin, p, (skin, joints), &mut last, &mut out);
        }
    }
    out
}

/// A skin's joints, or `None` when the skin cannot be read (a joint out of range, bad inverse
/// bind matrices).
fn skin_joints(
    doc: &Document,
    data: &MeshData,
    bin: &[u8],
    skin: usize,
    bone_of_node: &[Option<HumanBone>],
    world: &mut [Option<Affine>],
) -> Option<Joints> {
    let s = data.skins.get(Some(skin))?;
    let n = doc.tree.len();
    if s.joints.iter().any(|&j| j >= n) {
        return None;
    }
    let inverse = match s.inverse_bind? {
        None => None,
        some => {
            let e = data.elements(bin, some, 16, &[(F32, None)])?;
            if e.count < s.joints.len() {
                return None;
            }
            Some(e)
        }
    };
    let mut matrices = Vec::with_capacity(s.joints.len());
    let mut bones = Vec::with_capacity(s.joints.len());
    for (k, &j) in s.joints.iter().enumerate() {
        let w = doc.tree.world(j, world);
        let m = match &inverse {
            None => w,
            Some(e) => {
                let mut a = [0.0f64; 16];
                for (c, v) in a.iter_mut().enumerate() {
                    *v = f64::from(e.get(k, c)?);
                }
                w.mul(&Affine::from_cols_array(&a))
            }
        };
        matrices.push(m);
        // The nearest humanoid ancestor, the joint itself included.
        let mut cur = Some(j);
        let mut bone = None;
        for _ in 0..=MAX_DEPTH {
            let Some(i) = cur else { break };
            if let Some(b) = bone_of_node.get(i).copied().flatten() {
                bone = Some((b, i != j));
                break;
            }
            cur = doc.tree.parent.get(i).copied().flatten();
        }
        bones.push(bone);
    }
    Some(Joints { matrices, bones })
}

/// The last primitive's vertices: their accessors `(POSITION, JOINTS_0, WEIGHTS_0, skin)` and
/// each one's index in the skin (-1: left out). The primitives of a mesh often share one vertex
/// buffer (the generated avatars' body and eyes; UniVRM writes a mesh's submeshes so), and a
/// vertex is one point of the skin however many primitives use it.
type Last = ((usize, usize, usize, usize), Vec<i64>);

/// No primitive's accessors.
const NONE: (usize, usize, usize, usize) = (usize::MAX, usize::MAX, usize::MAX, usize::MAX);

/// Appends one primitive's kept vertices and triangles to `out` (its vertices only when they
/// are not the last primitive's, `last`), or nothing when it cannot be read whole.
fn read_primitive(
    data: &MeshData,
    bin: &[u8],
    p: &Primitive,
    (skin, joints): (usize, &Joints),
    last: &mut Last,
    out: &mut SkinMesh,
) {
    if p.mode != Some(4) {
        return;
    }
    let Some(pos) = data.elements(bin, p.position, 3, &[(F32, None)]) else {
        return;
    };
    let Some(ji) = data.elements(bin, p.joints, 4, &[(U8, Some(false)), (U16, Some(false))]) else {
        return;
    };
    let Some(wi) = data.elements(
        bin,
        p.weights,
        4,
        &[(F32, None), (U8, Some(true)), (U16, Some(true))],
    ) else {
        return;
    };
    let Some(indices) = p.indices else { return };
    let indices = match indices {
        None => None,
        some => match data.elements(
            bin,
            some,
            1,
            &[(U8, Some(false)), (U16, Some(false)), (U32, Some(false))],
        ) {
            Some(e) => Some(e),
            None => return,
        },
    };
    let count = pos.count;
    if ji.count != count || wi.count != count {
        return;
    }
    let corners = indices.as_ref().map_or(count, |e| e.count);
    let base = out.positions.len();
    let key = (
        p.position.unwrap_or(usize::MAX),
        p.joints.unwrap_or(usize::MAX),
        p.weights.unwrap_or(usize::MAX),
        skin,
    );
    let known = last.0 == key;
    if base + if known { 0 } else { count } > MAX_VERTICES
        || out.triangles.len() + corners / 3 > MAX_TRIANGLES
    {
        return;
    }
    if !known {
        last.0 = NONE;
        if read_vertices(&pos, &ji, &wi, joints, out, &mut last.1).is_none() {
            out.truncate_to(base);
            return;
        }
    }
    let keep = &last.1;
    let tri_base = out.triangles.len();
    let corner = |t: usize| -> Option<i64> {
        let i = match &indices {
            Some(e) => e.index(t)? as usize,
            None => t,
        };
        keep.get(i).copied()
    };
    for t in (0..corners / 3).map(|t| 3 * t) {
        let (Some(a), Some(b), Some(c)) = (corner(t), corner(t + 1), corner(t + 2)) else {
            // An index beyond the vertices: the primitive is left out (and its vertices, if
            // they were its own).
            out.triangles.truncate(tri_base);
            out.truncate_to(base);
            return;
        };
        if a >= 0 && b >= 0 && c >= 0 {
            out.triangles.push([a as u32, b as u32, c as u32]);
        }
    }
    last.0 = key;
}

/// Appends a primitive's vertices to `out` and each one's index there (-1: left out) to `keep`
/// (emptied first); `None` when one cannot be read (the caller takes back what was appended).
fn read_vertices(
    pos: &Elements,
    ji: &Elements,
    wi: &Elements,
    joints: &Joints,
    out: &mut SkinMesh,
    keep: &mut Vec<i64>,
) -> Option<()> {
    let count = pos.count;
    // Every vertex first (a primitive is all or nothing): its index in `out`, or -1.
    keep.clear();
    keep.reserve(count);
    for i in 0..count {
        let mut w = [0.0f32; 4];
        let mut j = [0usize; 4];
        for k in 0..4 {
            w[k] = wi.get(i, k)?;
            j[k] = ji.get(i, k)? as usize;
        }
        if w.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return None;
        }
        // A weighted joint beyond the skin's joints: the primitive is broken.
        if (0..4).any(|k| w[k] > 0.0 && j[k] >= joints.matrices.len()) {
            return None;
        }
        // The dominant joint: the first of the largest weight (restPoseFromVRM's choice).
        let mut best = 0;
        for k in 1..4 {
            if w[k] > w[best] {
                best = k;
            }
        }
        let sum: f32 = w.iter().sum();
        if sum > 0.0 {
            w = w.map(|x| x / sum);
        } else {
            w = [1.0, 0.0, 0.0, 0.0];
        }
        let Some((bone, hanging)) = joints.bones.get(j[best]).copied().flatten() else {
            keep.push(-1);
            continue;
        };
        let (x, y, z) = (pos.get(i, 0)?, pos.get(i, 1)?, pos.get(i, 2)?);
        let v = [f64::from(x), f64::from(y), f64::from(z)];
        let mut p = [0.0f64; 3];
        for k in 0..4 {
            if w[k] == 0.0 {
                continue;
            }
            let m = joints.matrices.get(j[k])?;
            let q = m.apply_point(v);
            for c in 0..3 {
                p[c] += f64::from(w[k]) * q[c];
            }
        }
        let p = Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
        if !p.is_finite() || p.abs().max_element() > MAX_REST_COORDINATE {
            keep.push(-1);
            continue;
        }
        keep.push(out.positions.len() as i64);
        out.positions.push(p);
        out.bones.push(bone);
        out.hanging.push(hanging);
    }
    Some(())
}

trait Truncate {
    fn truncate_to(&mut self, vertices: usize);
}

impl Truncate for SkinMesh {
    fn truncate_to(&mut self, vertices: usize) {
        self.positions.truncate(vertices);
        self.bones.truncate(vertices);
        self.hanging.truncate(vertices);
    }
}
