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
use serde::de::{Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::Value as Json;

use crate::bones::HumanBone;
use crate::contact::skin::{SkinMesh, MAX_TRIANGLES, MAX_VERTICES};
use crate::skeleton::MAX_REST_COORDINATE;
use crate::vrm::{Affine, Document};

/// Most entries kept of each of `accessors`, `bufferViews`, `buffers`, `meshes`, `skins` (real
/// avatars: a few thousand accessors at most); entries beyond are ignored, and primitives using
/// them skipped.
pub const MAX_ENTRIES: usize = 65_536;

/// A top-level glTF array read leniently: each entry as [`FromJson`] gives it (`None` when it
/// is malformed), at most [`MAX_ENTRIES`] kept; anything but an array reads as empty.
pub(crate) struct List<T>(pub(crate) Vec<Option<T>>);

impl<T> Default for List<T> {
    fn default() -> Self {
        List(Vec::new())
    }
}

impl<T> List<T> {
    fn get(&self, i: Option<usize>) -> Option<&T> {
        self.0.get(i?)?.as_ref()
    }
}

/// An entry of a [`List`], from its JSON value.
pub(crate) trait FromJson: Sized {
    fn from_json(v: &Json) -> Option<Self>;
}

impl<'de, T: FromJson> Deserialize<'de> for List<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> core::result::Result<Self, D::Error> {
        struct Lenient<T>(core::marker::PhantomData<T>);
        impl<'de, T: FromJson> Visitor<'de> for Lenient<T> {
            type Value = List<T>;
            fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
                f.write_str("any JSON value")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> core::result::Result<List<T>, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
                while out.len() < MAX_ENTRIES {
                    let Some(v) = seq.next_element::<Json>()? else {
                        return Ok(List(out));
                    };
                    out.push(T::from_json(&v));
                }
                while seq.next_element::<IgnoredAny>()?.is_some() {}
                Ok(List(out))
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> core::result::Result<List<T>, A::Error> {
                while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
                Ok(List::default())
            }
            fn visit_bool<E>(self, _: bool) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_i64<E>(self, _: i64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_u64<E>(self, _: u64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_f64<E>(self, _: f64) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_str<E>(self, _: &str) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
            fn visit_unit<E>(self) -> core::result::Result<List<T>, E> {
                Ok(List::default())
            }
        }
        d.deserialize_any(Lenient(core::marker::PhantomData))
    }
}

/// A non-negative integer (JSON `3` or `3.0`) small enough to be an index or a byte count.
fn uint(v: Option<&Json>) -> Option<usize> {
    let f = v?.as_f64()?;
    (f.fract() == 0.0 && (0.0..9.0e15).contains(&f))
        .then(|| usize::try_from(f as u64).ok())
        .flatten()
}

/// `key` as an index; absent: `default`; present but not an index: `None`.
fn uint_or(v: &Json, key: &str, default: usize) -> Option<usize> {
    match v.get(key) {
        None => Some(default),
        some => uint(some),
    }
}

/// `accessors[i]`.
pub(crate) struct Accessor {
    view: Option<usize>,
    offset: usize,
    component: u32,
    normalized: bool,
    count: usize,
    /// Components per element (SCALAR 1 ... MAT4 16).
    width: usize,
    sparse: bool,
}

impl FromJson for Accessor {
    fn from_json(v: &Json) -> Option<Self> {
        let width = match v.get("type")?.as_str()? {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" | "MAT2" => 4,
            "MAT3" => 9,
            "MAT4" => 16,
            _ => return None,
        };
        Some(Accessor {
            view: match v.get("bufferView") {
                None => None,
                some => Some(uint(some)?),
            },
            offset: uint_or(v, "byteOffset", 0)?,
            component: u32::try_from(uint(v.get("componentType"))?).ok()?,
            normalized: v.get("normalized").and_then(Json::as_bool).unwrap_or(false),
            count: uint(v.get("count"))?,
            width,
            sparse: v.get("sparse").is_some(),
        })
    }
}

/// `bufferViews[i]`.
pub(crate) struct View {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: Option<usize>,
}

impl FromJson for View {
    fn from_json(v: &Json) -> Option<Self> {
        Some(View {
            buffer: uint(v.get("buffer"))?,
            offset: uint_or(v, "byteOffset", 0)?,
            length: uint(v.get("byteLength"))?,
            stride: match v.get("byteStride") {
                None => None,
                some => Some(uint(some)?),
            },
        })
    }
}

/// `buffers[i]`: only a buffer without `uri` (the GLB's BIN chunk) is read.
pub(crate) struct Buffer {
    in_glb: bool,
}

impl FromJson for Buffer {
    fn from_json(v: &Json) -> Option<Self> {
        Some(Buffer {
            in_glb: v.get("uri").is_none(),
        })
    }
}

/// A primitive's accessors (`None`: absent or not an index) and mode.
pub(crate) struct Primitive {
    position: Option<usize>,
    joints: Option<usize>,
    weights: Option<usize>,
    /// `Some(None)`: not indexed; `None`: an `indices` that is not an index.
    indices: Option<Option<usize>>,
    mode: Option<usize>,
}

/// `meshes[i]`: its primitives.
pub(crate) struct Mesh {
    primitives: Vec<Primitive>,
}

impl FromJson for Mesh {
    fn from_json(v: &Json) -> Option<Self> {
        let primitives = v.get("primitives")?.as_array()?;
        Some(Mesh {
            primitives: primitives
                .iter()
                .map(|p| {
                    let attr = |k: &str| uint(p.get("attributes").and_then(|a| a.get(k)));
                    Primitive {
                        position: attr("POSITION"),
                        joints: attr("JOINTS_0"),
                        weights: attr("WEIGHTS_0"),
                        indices: match p.get("indices") {
                            None => Some(None),
                            some => uint(some).map(Some),
                        },
                        mode: uint_or(p, "mode", 4),
                    }
                })
                .collect(),
        })
    }
}

/// `skins[i]`.
pub(crate) struct Skin {
    joints: Vec<usize>,
    /// `Some(None)`: no inverse bind matrices (identity); `None`: not an index.
    inverse_bind: Option<Option<usize>>,
}

impl FromJson for Skin {
    fn from_json(v: &Json) -> Option<Self> {
        let joints = v.get("joints")?.as_array()?;
        Some(Skin {
            joints: joints
                .iter()
                .map(|j| uint(Some(j)))
                .collect::<Option<Vec<_>>>()?,
            inverse_bind: match v.get("inverseBindMatrices") {
                None => Some(None),
                some => uint(some).map(Some),
            },
        })
    }
}

/// The glTF members the skin is read from (a part of [`Document`]).
#[derive(Default)]
pub(crate) struct MeshData {
    pub(crate) accessors: List<Accessor>,
    pub(crate) views: List<View>,
    pub(crate) buffers: List<Buffer>,
    pub(crate) meshes: List<Mesh>,
    pub(crate) skins: List<Skin>,
}

const U8: u32 = 5121;
const U16: u32 = 5123;
const U32: u32 = 5125;
const F32: u32 = 5126;

/// An accessor's elements in the BIN chunk, bounds checked once.
struct Elements<'a> {
    bytes: &'a [u8],
    stride: usize,
    component: u32,
    normalized: bool,
    count: usize,
}

impl Elements<'_> {
    /// Component `k` of element `i` (normalized integers in 0..1), or `None` out of bounds
    /// (never for `i < count`, `k < width`: checked in [`MeshData::elements`]).
    fn get(&self, i: usize, k: usize) -> Option<f32> {
        let size = component_size(self.component)?;
        let at = i.checked_mul(self.stride)?.checked_add(k * size)?;
        let b = self.bytes.get(at..at + size)?;
        Some(match (self.component, self.normalized) {
            (F32, _) => f32::from_le_bytes(b.try_into().ok()?),
            (U8, false) => f32::from(b[0]),
            (U8, true) => f32::from(b[0]) / 255.0,
            (U16, false) => f32::from(u16::from_le_bytes(b.try_into().ok()?)),
            (U16, true) => f32::from(u16::from_le_bytes(b.try_into().ok()?)) / 65535.0,
            _ => return None,
        })
    }

    /// Element `i` of an integer scalar accessor (indices), exactly.
    fn index(&self, i: usize) -> Option<u32> {
        let size = component_size(self.component)?;
        let at = i.checked_mul(self.stride)?;
        let b = self.bytes.get(at..at + size)?;
        Some(match self.component {
            U8 => u32::from(b[0]),
            U16 => u32::from(u16::from_le_bytes(b.try_into().ok()?)),
            U32 => u32::from_le_bytes(b.try_into().ok()?),
            _ => return None,
        })
    }
}

fn component_size(c: u32) -> Option<usize> {
    match c {
        5120 | U8 => Some(1),
        5122 | U16 => Some(2),
        U32 | F32 => Some(4),
        _ => None,
    }
}

impl MeshData {
    /// Accessor `i` if it has `width` components of one of `components` (with `normalized`
    /// when given) and lies in the BIN chunk.
    fn elements<'a>(
        &self,
        bin: &'a [u8],
        i: Option<usize>,
        width: usize,
        components: &[(u32, Option<bool>)],
    ) -> Option<Elements<'a>> {
        let a = self.accessors.get(i)?;
        if a.sparse || a.width != width {
            return None;
        }
        components
            .iter()
            .find(|(c, n)| *c == a.component && n.is_none_or(|n| n == a.normalized))?;
        let view = self.views.get(a.view)?;
        if !self.buffers.get(Some(view.buffer))?.in_glb || view.buffer != 0 {
            return None;
        }
        let size = component_size(a.component)? * width;
        let stride = view.stride.unwrap_or(size);
        if stride < size || stride > 252 {
            return None;
        }
        let view_end = view.offset.checked_add(view.length)?;
        let bytes = bin.get(view.offset..view_end)?;
        let bytes = bytes.get(a.offset..)?;
        if a.count > 0 {
            let need = (a.count - 1).checked_mul(stride)?.checked_add(size)?;
            if need > bytes.len() {
                return None;
            }
        }
        Some(Elements {
            bytes,
            stride,
            component: a.component,
            normalized: a.normalized,
            count: a.count,
        })
    }
}

/// One skin's joints at rest: `jointWorld * inverseBind` and the humanoid bone of each.
struct Joints {
    matrices: Vec<Affine>,
    bones: Vec<Option<HumanBone>>,
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
            read_primitive(data, bin, p, joints, &mut out);
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
        for _ in 0..=crate::vrm::MAX_DEPTH {
            let Some(i) = cur else { break };
            if let Some(b) = bone_of_node.get(i).copied().flatten() {
                bone = Some(b);
                break;
            }
            cur = doc.tree.parent.get(i).copied().flatten();
        }
        bones.push(bone);
    }
    Some(Joints { matrices, bones })
}

/// Appends one primitive's kept vertices and triangles to `out`, or nothing when it cannot be
/// read whole.
fn read_primitive(data: &MeshData, bin: &[u8], p: &Primitive, joints: &Joints, out: &mut SkinMesh) {
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
    if base + count > MAX_VERTICES || out.triangles.len() + corners / 3 > MAX_TRIANGLES {
        return;
    }
    // Every vertex first (a primitive is all or nothing): its index in `out`, or -1.
    let mut keep: Vec<i64> = Vec::with_capacity(count);
    for i in 0..count {
        let mut w = [0.0f32; 4];
        let mut j = [0usize; 4];
        for k in 0..4 {
            let (Some(wk), Some(jk)) = (wi.get(i, k), ji.get(i, k)) else {
                out.truncate_to(base);
                return;
            };
            w[k] = wk;
            j[k] = jk as usize;
        }
        if w.iter().any(|x| !x.is_finite() || *x < 0.0) {
            out.truncate_to(base);
            return;
        }
        // A weighted joint beyond the skin's joints: the primitive is broken.
        if (0..4).any(|k| w[k] > 0.0 && j[k] >= joints.matrices.len()) {
            out.truncate_to(base);
            return;
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
        let Some(bone) = joints.bones.get(j[best]).copied().flatten() else {
            keep.push(-1);
            continue;
        };
        let (Some(x), Some(y), Some(z)) = (pos.get(i, 0), pos.get(i, 1), pos.get(i, 2)) else {
            out.truncate_to(base);
            return;
        };
        let v = [f64::from(x), f64::from(y), f64::from(z)];
        let mut p = [0.0f64; 3];
        for k in 0..4 {
            if w[k] == 0.0 {
                continue;
            }
            let Some(m) = joints.matrices.get(j[k]) else {
                out.truncate_to(base);
                return;
            };
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
    }
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
            // An index beyond the vertices.
            out.triangles.truncate(tri_base);
            out.truncate_to(base);
            return;
        };
        if a >= 0 && b >= 0 && c >= 0 {
            out.triangles.push([a as u32, b as u32, c as u32]);
        }
    }
}

trait Truncate {
    fn truncate_to(&mut self, vertices: usize);
}

impl Truncate for SkinMesh {
    fn truncate_to(&mut self, vertices: usize) {
        self.positions.truncate(vertices);
        self.bones.truncate(vertices);
    }
}
