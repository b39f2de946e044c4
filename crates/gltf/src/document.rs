//! The glTF document of a GLB, general to every glTF humanoid (VRM or not): the `nodes` checked
//! to be a forest, each node's local transform as three.js's `GLTFLoader` builds it (in f64,
//! like JavaScript: a `matrix` decomposed and recomposed as `Object3D.applyMatrix4` does, so a
//! sheared matrix loses its shear the same way; `matrix` wins over TRS; rotations used as
//! written), world transforms through the whole hierarchy, the top-level `extensions`, and the
//! mesh data the skin is read from ([`crate::accessors`]).
//!
//! Every malformed input is an [`Error::Vrm`] naming the part of the file and the problem;
//! nothing here panics or indexes out of bounds, whatever the bytes.

use serde::de::{Deserialize, Deserializer, Error as _, SeqAccess, Visitor};
use serde_json::Value as Json;

use crate::accessors::{Accessor, Buffer, List, Mesh, MeshData, Skin, View};
use crate::error::{Error, Result};
use crate::glb::Glb;

/// A GLB's node hierarchy, extensions and mesh data, checked (what handrig's `humanoid::vrm` and
/// `humanoid::gltf` read).
pub struct Document {
    /// The `nodes` as written (for their names).
    pub nodes: Vec<Json>,
    /// The checked hierarchy with each node's local transform.
    pub tree: NodeTree,
    /// The top-level `extensions`, if any.
    pub extensions: Option<Json>,
    /// What the skin is read from (handrig's `humanoid::gltf_skin`).
    pub meshes: MeshData,
    /// The BIN chunk's byte range in the file (empty when there is none).
    pub bin: core::ops::Range<usize>,
}

impl Document {
    /// Reads the container, the JSON chunk's `nodes` and `extensions`, and checks the
    /// hierarchy (every error an [`Error::Vrm`]).
    pub fn read(bytes: &[u8]) -> Result<Document> {
        let glb = Glb::parse(bytes)?;
        let json = glb.json.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(glb.json);
        let top = read_top_level(json)?;
        let tree = NodeTree::parse(&top.nodes.0)?;
        Ok(Document {
            nodes: top.nodes.0,
            tree,
            extensions: top.extensions,
            meshes: MeshData {
                accessors: top.accessors,
                views: top.buffer_views,
                buffers: top.buffers,
                meshes: top.meshes,
                skins: top.skins,
            },
            bin: glb.bin,
        })
    }
}

/// Most nodes a `.vrm` may have (real avatars have hundreds to a few thousand). Bounds the
/// work and memory of loading hostile files.
pub const MAX_NODES: usize = 65_536;

/// Deepest node hierarchy a `.vrm` may have (real avatars: under 100 levels).
pub const MAX_DEPTH: usize = 1_024;

/// The top-level members handrig reads, read by serde from the JSON chunk: `nodes` and
/// `extensions`, and for the skin `accessors`, `bufferViews`, `buffers`, `meshes`, `skins`
/// (leniently, each entry kept in a compact form, at most [`crate::accessors::MAX_ENTRIES`]).
/// Every other member (materials, animations, extras...) is checked but not kept, and
/// `nodes` is refused beyond [`MAX_NODES`] entries as it is read, so a hostile file with
/// millions of nodes or of other objects costs a scan of its text, not a document tree.
#[derive(serde::Deserialize)]
pub struct TopLevel {
    #[serde(default)]
    pub nodes: Nodes,
    #[serde(default)]
    pub extensions: Option<Json>,
    // Read leniently (a malformed entry is `None`, a bad member empty): the skin is optional.
    #[serde(default)]
    pub accessors: List<Accessor>,
    #[serde(default, rename = "bufferViews")]
    pub buffer_views: List<View>,
    #[serde(default)]
    pub buffers: List<Buffer>,
    #[serde(default)]
    pub meshes: List<Mesh>,
    #[serde(default)]
    pub skins: List<Skin>,
}

/// `nodes`: at most [`MAX_NODES`] JSON values (each checked by [`NodeTree::parse`]).
#[derive(Default)]
pub struct Nodes(Vec<Json>);

/// Marks the error of a `nodes` array longer than [`MAX_NODES`].
pub const TOO_MANY_NODES: &str = "more than MAX_NODES nodes";

/// What `nodes` must be, in serde's type errors: marks an error as the `nodes` member's (no
/// other member reads as this), without tracking every error's path.
const NODES_EXPECTED: &str = "the nodes array";

impl<'de> Deserialize<'de> for Nodes {
    fn deserialize<D: Deserializer<'de>>(d: D) -> core::result::Result<Self, D::Error> {
        struct Bounded;
        impl<'de> Visitor<'de> for Bounded {
            type Value = Nodes;
            fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
                f.write_str(NODES_EXPECTED)
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> core::result::Result<Nodes, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
                while let Some(v) = seq.next_element::<Json>()? {
                    if out.len() == MAX_NODES {
                        return Err(A::Error::custom(TOO_MANY_NODES));
                    }
                    out.push(v);
                }
                Ok(Nodes(out))
            }
        }
        d.deserialize_seq(Bounded)
    }
}

/// Reads the JSON chunk's `nodes` and `extensions` (serde_json; errors name the problem).
pub fn read_top_level(json: &[u8]) -> Result<TopLevel> {
    // Check the encoding of the whole chunk up front (skipped members are not decoded).
    let json = std::str::from_utf8(json)
        .map_err(|e| Error::vrm(format!("JSON chunk is not valid JSON: not UTF-8 ({e})")))?;
    if !json.trim_start().starts_with('{') {
        // serde would read a struct from an array too: anything but an object is refused here
        // (after checking that it is JSON at all).
        return Err(match serde_json::from_str::<serde::de::IgnoredAny>(json) {
            Ok(_) => Error::vrm("JSON chunk: the top level must be an object"),
            Err(e) => Error::vrm(format!("JSON chunk is not valid JSON: {e}")),
        });
    }
    let mut de = serde_json::Deserializer::from_str(json);
    let top = TopLevel::deserialize(&mut de).and_then(|t| de.end().map(|()| t));
    top.map_err(|e| {
        let data = e.classify() == serde_json::error::Category::Data;
        let message = e.to_string();
        if data && message.starts_with(TOO_MANY_NODES) {
            Error::vrm(format!(
                "nodes: more than the {MAX_NODES} nodes handrig reads"
            ))
        } else if data && message.contains(NODES_EXPECTED) {
            Error::vrm("nodes: must be an array")
        } else {
            Error::vrm(format!("JSON chunk is not valid JSON: {e}"))
        }
    })
}

/// `nodes` with their local transforms and the parent of each node, validated to be a forest.
pub struct NodeTree {
    pub local: Vec<Affine>,
    pub parent: Vec<Option<usize>>,
}

impl NodeTree {
    pub fn parse(nodes: &[Json]) -> Result<Self> {
        let n = nodes.len();
        if n > MAX_NODES {
            return Err(Error::vrm(format!(
                "nodes: {n} nodes, more than the {MAX_NODES} handrig reads"
            )));
        }
        let mut local = Vec::with_capacity(n);
        let mut parent: Vec<Option<usize>> = vec![None; n];
        for (i, node) in nodes.iter().enumerate() {
            if node.as_object().is_none() {
                return Err(Error::vrm(format!("nodes[{i}]: must be an object")));
            }
            local.push(local_matrix(i, node)?);
            let Some(children) = node.get("children") else {
                continue;
            };
            let children = children
                .as_array()
                .ok_or_else(|| Error::vrm(format!("nodes[{i}].children: must be an array")))?;
            for (k, c) in children.iter().enumerate() {
                let field = format!("nodes[{i}].children[{k}]");
                let c = index_value(c, n, &field)?;
                if c == i {
                    return Err(Error::vrm(format!(
                        "{field}: node {i} lists itself as a child (a cycle)"
                    )));
                }
                match parent[c] {
                    Some(p) if p == i => {
                        return Err(Error::vrm(format!(
                            "nodes[{i}].children: lists node {c} twice"
                        )))
                    }
                    Some(p) => {
                        return Err(Error::vrm(format!(
                            "node {c} has two parents (nodes {p} and {i})"
                        )))
                    }
                    None => parent[c] = Some(i),
                }
            }
        }
        let tree = NodeTree { local, parent };
        tree.check_acyclic()?;
        tree.check_depth()?;
        Ok(tree)
    }

    /// How many nodes.
    pub fn len(&self) -> usize {
        self.local.len()
    }

    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.local.is_empty()
    }

    /// With one parent per node, a cycle is a loop of nodes none of which reaches a root.
    /// Walks up from every node once, marking nodes known to reach a root, so it is linear.
    pub fn check_acyclic(&self) -> Result<()> {
        const UNSEEN: u8 = 0;
        const ON_PATH: u8 = 1;
        const ROOTED: u8 = 2;
        let n = self.len();
        let mut state = vec![UNSEEN; n];
        let mut path = Vec::new();
        for start in 0..n {
            path.clear();
            let mut cur = Some(start);
            while let Some(i) = cur {
                match state.get(i).copied() {
                    Some(UNSEEN) => {
                        state[i] = ON_PATH;
                        path.push(i);
                        cur = self.parent.get(i).copied().flatten();
                    }
                    Some(ON_PATH) => {
                        return Err(Error::vrm(format!(
                            "nodes: cycle in the node hierarchy through node {i}"
                        )));
                    }
                    _ => break,
                }
            }
            for &i in &path {
                state[i] = ROOTED;
            }
        }
        Ok(())
    }

    /// Rejects hierarchies deeper than [`MAX_DEPTH`]. Linear: each node's depth is its
    /// parent's plus one, memoized (the hierarchy is known to be acyclic).
    pub fn check_depth(&self) -> Result<()> {
        let n = self.len();
        let mut depth = vec![0usize; n];
        let mut known = vec![false; n];
        let mut path = Vec::new();
        for start in 0..n {
            path.clear();
            let mut cur = Some(start);
            let mut base = 0;
            while let Some(i) = cur {
                if known[i] {
                    base = depth[i];
                    break;
                }
                path.push(i);
                cur = self.parent[i];
            }
            for (k, &i) in path.iter().rev().enumerate() {
                depth[i] = base + k + 1;
                known[i] = true;
                if depth[i] > MAX_DEPTH {
                    return Err(Error::vrm(format!(
                        "nodes: node {i} is {} levels deep, more than the {MAX_DEPTH} handrig reads",
                        depth[i]
                    )));
                }
            }
        }
        Ok(())
    }

    /// World matrix of `node` (memoized in `cache`): product of the local matrices from the
    /// root down. The hierarchy is known to be acyclic, so the walk ends.
    pub fn world(&self, node: usize, cache: &mut [Option<Affine>]) -> Affine {
        let mut chain = Vec::new();
        let mut cur = Some(node);
        let mut base = Affine::IDENTITY;
        while let Some(i) = cur {
            if let Some(m) = cache.get(i).copied().flatten() {
                base = m;
                break;
            }
            chain.push(i);
            // Defensive bound; check_acyclic already guarantees termination.
            if chain.len() > self.len() {
                break;
            }
            cur = self.parent.get(i).copied().flatten();
        }
        let mut m = base;
        for &i in chain.iter().rev() {
            m = m.mul(&self.local.get(i).copied().unwrap_or(Affine::IDENTITY));
            if let Some(slot) = cache.get_mut(i) {
                *slot = Some(m);
            }
        }
        m
    }
}

/// The value for an error message, short whatever its size: integers and short strings as
/// written, anything else by kind (`a number`, `a string`, `an array`, ...).
pub fn describe(v: &Json) -> String {
    match v {
        Json::Null => "null".into(),
        Json::Bool(b) => b.to_string(),
        Json::Number(x) => match x.as_f64() {
            Some(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{}", f as i64),
            _ => "a number".into(),
        },
        Json::String(s) if s.len() <= 32 => format!("\"{s}\""),
        Json::String(_) => "a string".into(),
        Json::Array(_) => "an array".into(),
        Json::Object(_) => "an object".into(),
    }
}

/// A non-negative integer index below `n` (JSON numbers such as `3.0` count as integers).
pub fn index_value(v: &Json, n: usize, field: &str) -> Result<usize> {
    let i = v
        .as_f64()
        .filter(|f| f.fract() == 0.0 && *f >= 0.0 && *f < 9.0e15)
        .map(|f| f as u64);
    let Some(i) = i else {
        // Integers and short strings are quoted back; anything else by kind only, so a huge
        // value cannot blow up the message.
        return Err(Error::vrm(format!(
            "{field}: node index must be a non-negative integer, got {}",
            describe(v)
        )));
    };
    usize::try_from(i).ok().filter(|&i| i < n).ok_or_else(|| {
        Error::vrm(format!(
            "{field}: node {i} out of range (the file has {n} nodes)"
        ))
    })
}

/// `N` finite numbers from a JSON array field, or `default` when absent.
pub fn numbers<const N: usize>(
    node: &Json,
    i: usize,
    key: &str,
    default: [f64; N],
) -> Result<[f64; N]> {
    let Some(v) = node.get(key) else {
        return Ok(default);
    };
    let bad = || {
        Error::vrm(format!(
            "nodes[{i}].{key}: must be an array of {N} finite numbers"
        ))
    };
    let arr = v.as_array().filter(|a| a.len() == N).ok_or_else(bad)?;
    let mut out = [0.0; N];
    for (o, x) in out.iter_mut().zip(arr) {
        *o = x.as_f64().filter(|f| f.is_finite()).ok_or_else(bad)?;
    }
    Ok(out)
}

/// An affine transform in f64 (three.js computes in doubles; so do we, to agree to the last
/// digits): `p -> m * p + t`, `m` stored as columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    pub m: [[f64; 3]; 3],
    pub t: [f64; 3],
}

impl Affine {
    const IDENTITY: Affine = Affine {
        m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        t: [0.0; 3],
    };

    pub fn apply_linear(&self, v: [f64; 3]) -> [f64; 3] {
        let c = &self.m;
        [
            c[0][0] * v[0] + c[1][0] * v[1] + c[2][0] * v[2],
            c[0][1] * v[0] + c[1][1] * v[1] + c[2][1] * v[2],
            c[0][2] * v[0] + c[1][2] * v[1] + c[2][2] * v[2],
        ]
    }

    /// A column-major 4x4 matrix's affine part (its last row is taken as 0, 0, 0, 1).
    pub fn from_cols_array(a: &[f64; 16]) -> Affine {
        Affine {
            m: [[a[0], a[1], a[2]], [a[4], a[5], a[6]], [a[8], a[9], a[10]]],
            t: [a[12], a[13], a[14]],
        }
    }

    /// `m * p + t`.
    pub fn apply_point(&self, p: [f64; 3]) -> [f64; 3] {
        let l = self.apply_linear(p);
        [l[0] + self.t[0], l[1] + self.t[1], l[2] + self.t[2]]
    }

    /// `self * other`: `other` applied first.
    pub fn mul(&self, other: &Affine) -> Affine {
        let m = other.m.map(|col| self.apply_linear(col));
        let lt = self.apply_linear(other.t);
        Affine {
            m,
            t: [lt[0] + self.t[0], lt[1] + self.t[1], lt[2] + self.t[2]],
        }
    }

    pub fn determinant(&self) -> f64 {
        let [a, b, c] = self.m;
        a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1])
            + c[0] * (a[1] * b[2] - a[2] * b[1])
    }
}

pub fn length(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The node's local transform, as three.js builds it.
pub fn local_matrix(i: usize, node: &Json) -> Result<Affine> {
    if node.get("matrix").is_some() {
        let a = numbers::<16>(node, i, "matrix", [0.0; 16])?;
        // Column-major; the last row of an affine glTF matrix is 0, 0, 0, 1.
        if [a[3], a[7], a[11], a[15]] != [0.0, 0.0, 0.0, 1.0] {
            return Err(Error::vrm(format!(
                "nodes[{i}].matrix: not an affine transform (the last row must be 0, 0, 0, 1)"
            )));
        }
        let m = Affine {
            m: [[a[0], a[1], a[2]], [a[4], a[5], a[6]], [a[8], a[9], a[10]]],
            t: [a[12], a[13], a[14]],
        };
        // Object3D.applyMatrix4: decompose into TRS, then the object's matrix is recomposed.
        let (t, r, s) = decompose(&m);
        return Ok(compose(t, r, s));
    }
    let t = numbers(node, i, "translation", [0.0; 3])?;
    let r = numbers(node, i, "rotation", [0.0, 0.0, 0.0, 1.0])?;
    let s = numbers(node, i, "scale", [1.0; 3])?;
    Ok(compose(t, r, s))
}

/// Translation * rotation * scale with the quaternion `[x, y, z, w]` used as given (three.js
/// `Matrix4.compose`; a non-unit quaternion is not renormalized there either).
pub fn compose(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> Affine {
    let [x, y, z, w] = q;
    let (x2, y2, z2) = (x + x, y + y, z + z);
    let (xx, xy, xz) = (x * x2, x * y2, x * z2);
    let (yy, yz, zz) = (y * y2, y * z2, z * z2);
    let (wx, wy, wz) = (w * x2, w * y2, w * z2);
    Affine {
        m: [
            [(1.0 - (yy + zz)) * s[0], (xy + wz) * s[0], (xz - wy) * s[0]],
            [(xy - wz) * s[1], (1.0 - (xx + zz)) * s[1], (yz + wx) * s[1]],
            [(xz + wy) * s[2], (yz - wx) * s[2], (1.0 - (xx + yy)) * s[2]],
        ],
        t,
    }
}

/// Splits a transform into translation, rotation `[x, y, z, w]` and scale the way three.js
/// `Matrix4.decompose` does: scale = column lengths, the x scale negated when the determinant
/// is negative, and the rotation read from the scaled-back columns. A zero column gives
/// non-finite values, which surface later as a non-finite bone position error.
pub fn decompose(a: &Affine) -> ([f64; 3], [f64; 4], [f64; 3]) {
    let mut sx = length(a.m[0]);
    let sy = length(a.m[1]);
    let sz = length(a.m[2]);
    if a.determinant() < 0.0 {
        sx = -sx;
    }
    let c0 = a.m[0].map(|v| v / sx);
    let c1 = a.m[1].map(|v| v / sy);
    let c2 = a.m[2].map(|v| v / sz);
    (a.t, quat_from_rotation_columns(c0, c1, c2), [sx, sy, sz])
}

/// Quaternion `[x, y, z, w]` of a rotation matrix given by columns (Shepperd's method: branch
/// on the largest diagonal term for stability), the same branches as three.js
/// `setFromRotationMatrix`.
pub fn quat_from_rotation_columns(c0: [f64; 3], c1: [f64; 3], c2: [f64; 3]) -> [f64; 4] {
    // mRC: row R, column C.
    let [m11, m21, m31] = c0;
    let [m12, m22, m32] = c1;
    let [m13, m23, m33] = c2;
    let trace = m11 + m22 + m33;
    if trace > 0.0 {
        let s = 0.5 / (trace + 1.0).sqrt();
        [(m32 - m23) * s, (m13 - m31) * s, (m21 - m12) * s, 0.25 / s]
    } else if m11 > m22 && m11 > m33 {
        let s = 2.0 * (1.0 + m11 - m22 - m33).sqrt();
        [0.25 * s, (m12 + m21) / s, (m13 + m31) / s, (m32 - m23) / s]
    } else if m22 > m33 {
        let s = 2.0 * (1.0 + m22 - m11 - m33).sqrt();
        [(m12 + m21) / s, 0.25 * s, (m23 + m32) / s, (m13 - m31) / s]
    } else {
        let s = 2.0 * (1.0 + m33 - m11 - m22).sqrt();
        [(m13 + m31) / s, (m23 + m32) / s, 0.25 * s, (m21 - m12) / s]
    }
}
