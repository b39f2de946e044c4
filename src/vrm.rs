//! Reading `.vrm` files: glTF 2.0 binary (GLB) with the `VRMC_vrm` (VRM 1.0) or `VRM`
//! (VRM 0.x) extension, down to the humanoid rest pose handrig needs.
//!
//! What is read: the GLB container (header, JSON chunk, optional BIN chunk), the glTF `nodes`
//! (TRS or `matrix`, `children`), and the humanoid bone map; [`load_skeleton`] also reads the
//! skinned meshes for self-contact ([`crate::gltf_skin`]: never an error, a primitive it cannot
//! read is skipped).
//! Each humanoid bone's rest position is the world position of its node through the **full**
//! node hierarchy: non-humanoid nodes in between, non-identity local rotations (Blender bone
//! rolls), scale. That is exactly what three-vrm's normalized rig reports
//! (`getNormalizedBoneNode(name).getWorldPosition()` on a freshly loaded model), in the
//! model's own frame: a VRM 0.x model stays -Z-facing here; [`crate::Skeleton::new`] turns it.
//!
//! Node transforms follow three.js's `GLTFLoader` (computed in f64 like JavaScript): a `matrix` is
//! decomposed into translation, rotation and scale and recomposed (as `Object3D.applyMatrix4`
//! does, so a sheared matrix loses its shear the same way), `matrix` wins when a node has both,
//! and rotations are used as written (not renormalized).
//!
//! Every malformed input is an [`Error::Vrm`] naming the part of the file and the problem;
//! nothing here panics or indexes out of bounds, whatever the bytes.

use glam::Vec3;
use serde::de::{Deserialize, Deserializer, Error as _, SeqAccess, Visitor};
use serde_json::Value as Json;

use crate::bones::{HumanBone, BONE_COUNT};
use crate::error::{Error, Result};
use crate::skeleton::{Skeleton, VrmVersion};

/// The humanoid part of a VRM file: version and rest world positions in the model's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct VrmHumanoid {
    /// VRM 0.x or 1.0 (decides the facing: 0.x models face -Z).
    pub version: VrmVersion,
    /// Rest world position (meters, the model's own frame) of every humanoid bone the file
    /// maps, in [`HumanBone::ALL`] order (parent-first). VRM 0.x thumbs are already renamed
    /// to their 1.0 names.
    pub bones: Vec<(HumanBone, Vec3)>,
    /// The look-at point (between the eyes) relative to the head bone's rest position,
    /// meters, the model's own frame: `VRMC_vrm.lookAt.offsetFromHeadBone` (VRM 1.0) or
    /// `firstPerson.firstPersonBoneOffset` with z negated (VRM 0.x, as three-vrm reads it),
    /// carried through the head node's rest world transform (three-vrm's
    /// `getLookAtWorldPosition`). `None` when the file has none, or it is malformed (it is a
    /// hint: a bad one does not reject the avatar).
    pub look_at: Option<Vec3>,
}

/// Parses a `.vrm` file (the bytes of a GLB) into its humanoid rest pose.
///
/// VRM 1.0 (`extensions.VRMC_vrm`) is preferred when a file carries both extensions, as
/// three-vrm does. VRM 1.0-beta files that still use the 0.x thumb names
/// (`leftThumbIntermediate`) get the 0.x thumb renaming, as three-vrm does. In VRM 0.x a
/// negative node index means "not assigned" and the bone is skipped (three-vrm's reading).
/// Unlike three-vrm, the extension need not be listed in `extensionsUsed`.
///
/// Does not check that required bones are present; [`load_skeleton`] does.
///
/// # Errors
/// [`Error::Vrm`] naming what is wrong: not a GLB (magic), truncated or inconsistent lengths,
/// misaligned or missing chunks, invalid JSON, malformed `nodes` (wrong types or lengths,
/// child index out of range, a node with two parents, a cycle), no `VRMC_vrm` / `VRM`
/// extension, an unknown or duplicate bone name, a bone node index out of range, two bones
/// on one node, or a bone whose world position is not finite (e.g. a zero-scale `matrix`).
pub fn parse(bytes: &[u8]) -> Result<VrmHumanoid> {
    let doc = Document::read(bytes)?;
    let (version, map) = humanoid_map(doc.extensions.as_ref(), doc.tree.len())?;
    humanoid_from_map(&doc, version, map)
}

/// A GLB's node hierarchy and extensions, checked (what [`parse`] and [`crate::gltf`] read).
pub(crate) struct Document {
    /// The `nodes` as written (for their names).
    pub(crate) nodes: Vec<Json>,
    /// The checked hierarchy with each node's local transform.
    pub(crate) tree: NodeTree,
    /// The top-level `extensions`, if any.
    pub(crate) extensions: Option<Json>,
    /// What the skin is read from ([`crate::gltf_skin`]).
    pub(crate) meshes: crate::gltf_skin::MeshData,
    /// The BIN chunk's byte range in the file (empty when there is none).
    pub(crate) bin: core::ops::Range<usize>,
}

impl Document {
    /// Reads the container, the JSON chunk's `nodes` and `extensions`, and checks the
    /// hierarchy (every error an [`Error::Vrm`]).
    pub(crate) fn read(bytes: &[u8]) -> Result<Document> {
        let glb = Glb::parse(bytes)?;
        let json = glb.json.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(glb.json);
        let top = read_top_level(json)?;
        let tree = NodeTree::parse(&top.nodes.0)?;
        Ok(Document {
            nodes: top.nodes.0,
            tree,
            extensions: top.extensions,
            meshes: crate::gltf_skin::MeshData {
                accessors: top.accessors,
                views: top.buffer_views,
                buffers: top.buffers,
                meshes: top.meshes,
                skins: top.skins,
            },
            bin: glb.bin,
        })
    }

    /// The skin of the file's skinned meshes ([`crate::gltf_skin`]) for the humanoid bound by
    /// `binding` (bone, node); `bytes`: the file this document was read from.
    pub(crate) fn skin(
        &self,
        bytes: &[u8],
        binding: &[(HumanBone, usize)],
    ) -> crate::contact::skin::SkinMesh {
        let bin = bytes.get(self.bin.clone()).unwrap_or(&[]);
        crate::gltf_skin::read(self, bin, binding)
    }
}

/// The humanoid of a bone map (bone, node, field for errors) over a read document: world
/// positions in bone order and the look-at offset.
pub(crate) fn humanoid_from_map(
    doc: &Document,
    version: VrmVersion,
    map: Vec<BoneEntry>,
) -> Result<VrmHumanoid> {
    let nodes = &doc.tree;
    let ext = doc.extensions.as_ref();

    let mut world = vec![None; nodes.len()];
    let head_node = map
        .iter()
        .find(|(b, _, _)| *b == HumanBone::Head)
        .map(|(_, n, _)| *n);
    let look_at = head_node.and_then(|node| {
        let offset = look_at_offset(ext?, version)?;
        let [x, y, z] = nodes.world(node, &mut world).apply_linear(offset);
        let v = Vec3::new(x as f32, y as f32, z as f32);
        v.is_finite().then_some(v)
    });
    // In bone order, by each bone's slot (the map has every bone once): no sort, whose code
    // would be one more copy of the standard library's sort in the `.wasm`.
    let mut positions = [None; BONE_COUNT];
    for (bone, node, field) in map {
        let [x, y, z] = nodes.world(node, &mut world).t;
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return Err(vrm_err(format!(
                "{field}: the world position of node {node} is not finite (a degenerate \
                 transform on it or an ancestor, e.g. a zero-scale matrix)"
            )));
        }
        let p = Vec3::new(x as f32, y as f32, z as f32);
        if !p.is_finite() {
            return Err(vrm_err(format!(
                "{field}: the world position of node {node} is too large for 32-bit floats"
            )));
        }
        positions[bone.index()] = Some(p);
    }
    let bones = HumanBone::ALL
        .iter()
        .zip(positions)
        .filter_map(|(b, p)| Some((*b, p?)))
        .collect();
    Ok(VrmHumanoid {
        version,
        bones,
        look_at,
    })
}

/// The look-at offset as written in the head node's local frame (VRM 0.x: z negated, as
/// three-vrm reads it); `None` when absent or malformed.
fn look_at_offset(ext: &Json, version: VrmVersion) -> Option<[f64; 3]> {
    let v = match version {
        VrmVersion::V1 => {
            let a = ext
                .get("VRMC_vrm")?
                .get("lookAt")?
                .get("offsetFromHeadBone")?;
            let a = a.as_array().filter(|a| a.len() == 3)?;
            [a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?]
        }
        VrmVersion::V0 => {
            let o = ext
                .get("VRM")?
                .get("firstPerson")?
                .get("firstPersonBoneOffset")?;
            let c = |k: &str| o.get(k).and_then(Json::as_f64);
            [c("x")?, c("y")?, -c("z")?]
        }
    };
    v.iter().all(|x| x.is_finite()).then_some(v)
}

/// Parses a `.vrm` file and builds its [`Skeleton`] (internal +Z-facing frame), with the skin
/// of its skinned meshes ([`Skeleton::with_skin`]; none when the file has none it can read).
///
/// # Errors
/// Everything [`parse`] reports, and [`Error::MissingRequiredBones`] when the file lacks any
/// of the 15 bones VRM 1.0 requires.
pub fn load_skeleton(bytes: &[u8]) -> Result<Skeleton> {
    let doc = Document::read(bytes)?;
    let (version, map) = humanoid_map(doc.extensions.as_ref(), doc.tree.len())?;
    let binding: Vec<(HumanBone, usize)> = map.iter().map(|(b, n, _)| (*b, *n)).collect();
    let h = humanoid_from_map(&doc, version, map)?;
    // Name the file, not `restPose`, when the rest pose came from it.
    Skeleton::new(&h.bones, h.version)
        .map(|s| {
            s.with_look_at_offset(h.look_at)
                .with_skin(doc.skin(bytes, &binding))
        })
        .map_err(|e| match e {
            Error::MissingRequiredBones(names) => vrm_err(format!(
                "humanoid lacks required bone(s) {}",
                names.join(", ")
            )),
            Error::InvalidInput { field, problem } => vrm_err(format!(
                "humanoid bone {}: {problem}",
                field.strip_prefix("restPose.bones.").unwrap_or(&field)
            )),
            other => other,
        })
}

/// Most nodes a `.vrm` may have (real avatars have hundreds to a few thousand). Bounds the
/// work and memory of loading hostile files.
pub const MAX_NODES: usize = 65_536;

/// Deepest node hierarchy a `.vrm` may have (real avatars: under 100 levels).
pub const MAX_DEPTH: usize = 1_024;

/// Largest JSON chunk read (real avatars: a few MB).
pub const MAX_JSON_BYTES: usize = 64 << 20;

/// The top-level members handrig reads, read by serde from the JSON chunk: `nodes` and
/// `extensions`, and for the skin `accessors`, `bufferViews`, `buffers`, `meshes`, `skins`
/// (leniently, each entry kept in a compact form, at most [`crate::gltf_skin::MAX_ENTRIES`]).
/// Every other member (materials, animations, extras...) is checked but not kept, and
/// `nodes` is refused beyond [`MAX_NODES`] entries as it is read, so a hostile file with
/// millions of nodes or of other objects costs a scan of its text, not a document tree.
#[derive(serde::Deserialize)]
struct TopLevel {
    #[serde(default)]
    nodes: Nodes,
    #[serde(default)]
    extensions: Option<Json>,
    // Read leniently (a malformed entry is `None`, a bad member empty): the skin is optional.
    #[serde(default)]
    accessors: crate::gltf_skin::List<crate::gltf_skin::Accessor>,
    #[serde(default, rename = "bufferViews")]
    buffer_views: crate::gltf_skin::List<crate::gltf_skin::View>,
    #[serde(default)]
    buffers: crate::gltf_skin::List<crate::gltf_skin::Buffer>,
    #[serde(default)]
    meshes: crate::gltf_skin::List<crate::gltf_skin::Mesh>,
    #[serde(default)]
    skins: crate::gltf_skin::List<crate::gltf_skin::Skin>,
}

/// `nodes`: at most [`MAX_NODES`] JSON values (each checked by [`NodeTree::parse`]).
#[derive(Default)]
struct Nodes(Vec<Json>);

/// Marks the error of a `nodes` array longer than [`MAX_NODES`].
const TOO_MANY_NODES: &str = "more than MAX_NODES nodes";

impl<'de> Deserialize<'de> for Nodes {
    fn deserialize<D: Deserializer<'de>>(d: D) -> core::result::Result<Self, D::Error> {
        struct Bounded;
        impl<'de> Visitor<'de> for Bounded {
            type Value = Nodes;
            fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
                f.write_str("an array")
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
fn read_top_level(json: &[u8]) -> Result<TopLevel> {
    // Check the encoding of the whole chunk up front (skipped members are not decoded).
    let json = std::str::from_utf8(json)
        .map_err(|e| vrm_err(format!("JSON chunk is not valid JSON: not UTF-8 ({e})")))?;
    if !json.trim_start().starts_with('{') {
        // serde would read a struct from an array too: anything but an object is refused here
        // (after checking that it is JSON at all).
        return Err(match serde_json::from_str::<serde::de::IgnoredAny>(json) {
            Ok(_) => vrm_err("JSON chunk: the top level must be an object"),
            Err(e) => vrm_err(format!("JSON chunk is not valid JSON: {e}")),
        });
    }
    let mut de = serde_json::Deserializer::from_str(json);
    let top = serde_path_to_error::deserialize::<_, TopLevel>(&mut de)
        .map_err(|e| (e.path().to_string(), e.into_inner()))
        .and_then(|t| de.end().map(|()| t).map_err(|e| (String::new(), e)));
    top.map_err(|(path, e)| {
        let data = e.classify() == serde_json::error::Category::Data;
        if path == "nodes" && e.to_string().starts_with(TOO_MANY_NODES) {
            vrm_err(format!(
                "nodes: more than the {MAX_NODES} nodes handrig reads"
            ))
        } else if data && path == "nodes" {
            vrm_err("nodes: must be an array")
        } else {
            vrm_err(format!("JSON chunk is not valid JSON: {e}"))
        }
    })
}

fn vrm_err(msg: impl Into<String>) -> Error {
    Error::Vrm(msg.into())
}

// ---------------------------------------------------------------------------------------------
// GLB container

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF", little-endian
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const HEADER_LEN: usize = 12;
const CHUNK_HEADER_LEN: usize = 8;

/// The JSON chunk of a GLB, borrowed from the input, and where the BIN chunk is (its data is
/// read only for the skin).
struct Glb<'a> {
    json: &'a [u8],
    /// The BIN chunk's byte range, empty when there is none.
    bin: core::ops::Range<usize>,
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let end = at.checked_add(4)?;
    let b: [u8; 4] = bytes.get(at..end)?.try_into().ok()?;
    Some(u32::from_le_bytes(b))
}

/// Shows four bytes as text when they are printable, else as hex, for error messages.
fn show_tag(tag: u32) -> String {
    let b = tag.to_le_bytes();
    if b.iter().all(|c| c.is_ascii_graphic() || *c == b' ') {
        format!("\"{}\"", String::from_utf8_lossy(&b))
    } else {
        format!("0x{tag:08X}")
    }
}

impl<'a> Glb<'a> {
    fn parse(bytes: &'a [u8]) -> Result<Self> {
        let got = bytes.len();
        if let Some(magic) = read_u32(bytes, 0) {
            if magic != GLB_MAGIC {
                let hint = if bytes.first() == Some(&b'{') {
                    " (this looks like a JSON .gltf; a .vrm is the binary form)"
                } else {
                    ""
                };
                return Err(vrm_err(format!(
                    "not a glTF binary (magic {}, expected \"glTF\"){hint}",
                    show_tag(magic)
                )));
            }
        }
        let (Some(version), Some(length)) = (read_u32(bytes, 4), read_u32(bytes, 8)) else {
            return Err(vrm_err(format!(
                "truncated: {got} bytes, shorter than the {HEADER_LEN}-byte GLB header"
            )));
        };
        if version != 2 {
            return Err(vrm_err(format!(
                "unsupported glTF binary version {version} (expected 2)"
            )));
        }
        let length = length as usize;
        if length > got {
            return Err(vrm_err(format!(
                "truncated: header says {length} bytes, got {got}"
            )));
        }
        if length < got {
            return Err(vrm_err(format!(
                "header says {length} bytes, got {got} (trailing data after the GLB)"
            )));
        }
        if length % 4 != 0 {
            return Err(vrm_err(format!(
                "GLB length {length} is not a multiple of 4 (chunks must be 4-byte aligned)"
            )));
        }

        let mut json = None;
        let mut bin = 0..0;
        let mut offset = HEADER_LEN;
        let mut index = 0usize;
        while offset < length {
            let what = if index == 0 {
                "JSON chunk".to_string()
            } else {
                format!("chunk {index}")
            };
            let (Some(chunk_len), Some(kind)) =
                (read_u32(bytes, offset), read_u32(bytes, offset + 4))
            else {
                return Err(vrm_err(format!(
                    "truncated: {what} header at byte {offset} needs {CHUNK_HEADER_LEN} bytes, \
                     the file ends at byte {length}"
                )));
            };
            let chunk_len = chunk_len as usize;
            let start = offset + CHUNK_HEADER_LEN;
            let end = start
                .checked_add(chunk_len)
                .filter(|&e| e <= length)
                .ok_or_else(|| {
                    vrm_err(format!(
                        "{what} of {chunk_len} bytes at byte {start} extends past the end of \
                         the file ({length} bytes)"
                    ))
                })?;
            if chunk_len % 4 != 0 {
                return Err(vrm_err(format!(
                    "{what} length {chunk_len} is not a multiple of 4 (chunks must be 4-byte \
                     aligned)"
                )));
            }
            let data = bytes.get(start..end).ok_or_else(|| {
                vrm_err(format!("{what} at bytes {start}..{end} is out of bounds"))
            })?;
            match (index, kind) {
                (0, CHUNK_JSON) if chunk_len > MAX_JSON_BYTES => {
                    return Err(vrm_err(format!(
                    "JSON chunk of {chunk_len} bytes, more than the {MAX_JSON_BYTES} handrig reads"
                )))
                }
                (0, CHUNK_JSON) => json = Some(data),
                (0, other) => {
                    return Err(vrm_err(format!(
                        "the first chunk must be the JSON chunk (type \"JSON\"), found type {}",
                        show_tag(other)
                    )))
                }
                (_, CHUNK_JSON) => {
                    return Err(vrm_err(format!("chunk {index}: a second JSON chunk")));
                }
                (1, CHUNK_BIN) => bin = start..end,
                (_, CHUNK_BIN) => {
                    return Err(vrm_err(format!(
                        "chunk {index}: a BIN chunk must directly follow the JSON chunk"
                    )));
                }
                // The GLB spec says readers skip chunk types they do not know.
                _ => {}
            }
            offset = end;
            index += 1;
        }
        let json = json.ok_or_else(|| {
            vrm_err(format!(
                "JSON chunk missing: the file ends after the {HEADER_LEN}-byte header"
            ))
        })?;
        Ok(Glb { json, bin })
    }
}

// ---------------------------------------------------------------------------------------------
// Node hierarchy

/// `nodes` with their local transforms and the parent of each node, validated to be a forest.
pub(crate) struct NodeTree {
    local: Vec<Affine>,
    pub(crate) parent: Vec<Option<usize>>,
}

impl NodeTree {
    fn parse(nodes: &[Json]) -> Result<Self> {
        let n = nodes.len();
        if n > MAX_NODES {
            return Err(vrm_err(format!(
                "nodes: {n} nodes, more than the {MAX_NODES} handrig reads"
            )));
        }
        let mut local = Vec::with_capacity(n);
        let mut parent: Vec<Option<usize>> = vec![None; n];
        for (i, node) in nodes.iter().enumerate() {
            if node.as_object().is_none() {
                return Err(vrm_err(format!("nodes[{i}]: must be an object")));
            }
            local.push(local_matrix(i, node)?);
            let Some(children) = node.get("children") else {
                continue;
            };
            let children = children
                .as_array()
                .ok_or_else(|| vrm_err(format!("nodes[{i}].children: must be an array")))?;
            for (k, c) in children.iter().enumerate() {
                let field = format!("nodes[{i}].children[{k}]");
                let c = index_value(c, n, &field)?;
                if c == i {
                    return Err(vrm_err(format!(
                        "{field}: node {i} lists itself as a child (a cycle)"
                    )));
                }
                match parent[c] {
                    Some(p) if p == i => {
                        return Err(vrm_err(format!(
                            "nodes[{i}].children: lists node {c} twice"
                        )))
                    }
                    Some(p) => {
                        return Err(vrm_err(format!(
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

    pub(crate) fn len(&self) -> usize {
        self.local.len()
    }

    /// With one parent per node, a cycle is a loop of nodes none of which reaches a root.
    /// Walks up from every node once, marking nodes known to reach a root, so it is linear.
    fn check_acyclic(&self) -> Result<()> {
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
                        return Err(vrm_err(format!(
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
    fn check_depth(&self) -> Result<()> {
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
                    return Err(vrm_err(format!(
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
    pub(crate) fn world(&self, node: usize, cache: &mut [Option<Affine>]) -> Affine {
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
fn describe(v: &Json) -> String {
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
fn index_value(v: &Json, n: usize, field: &str) -> Result<usize> {
    let i = v
        .as_f64()
        .filter(|f| f.fract() == 0.0 && *f >= 0.0 && *f < 9.0e15)
        .map(|f| f as u64);
    let Some(i) = i else {
        // Integers and short strings are quoted back; anything else by kind only, so a huge
        // value cannot blow up the message.
        return Err(vrm_err(format!(
            "{field}: node index must be a non-negative integer, got {}",
            describe(v)
        )));
    };
    usize::try_from(i).ok().filter(|&i| i < n).ok_or_else(|| {
        vrm_err(format!(
            "{field}: node {i} out of range (the file has {n} nodes)"
        ))
    })
}

/// `N` finite numbers from a JSON array field, or `default` when absent.
fn numbers<const N: usize>(
    node: &Json,
    i: usize,
    key: &str,
    default: [f64; N],
) -> Result<[f64; N]> {
    let Some(v) = node.get(key) else {
        return Ok(default);
    };
    let bad = || {
        vrm_err(format!(
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
pub(crate) struct Affine {
    m: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    const IDENTITY: Affine = Affine {
        m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        t: [0.0; 3],
    };

    fn apply_linear(&self, v: [f64; 3]) -> [f64; 3] {
        let c = &self.m;
        [
            c[0][0] * v[0] + c[1][0] * v[1] + c[2][0] * v[2],
            c[0][1] * v[0] + c[1][1] * v[1] + c[2][1] * v[2],
            c[0][2] * v[0] + c[1][2] * v[1] + c[2][2] * v[2],
        ]
    }

    /// A column-major 4x4 matrix's affine part (its last row is taken as 0, 0, 0, 1).
    pub(crate) fn from_cols_array(a: &[f64; 16]) -> Affine {
        Affine {
            m: [[a[0], a[1], a[2]], [a[4], a[5], a[6]], [a[8], a[9], a[10]]],
            t: [a[12], a[13], a[14]],
        }
    }

    /// `m * p + t`.
    pub(crate) fn apply_point(&self, p: [f64; 3]) -> [f64; 3] {
        let l = self.apply_linear(p);
        [l[0] + self.t[0], l[1] + self.t[1], l[2] + self.t[2]]
    }

    /// `self * other`: `other` applied first.
    pub(crate) fn mul(&self, other: &Affine) -> Affine {
        let m = other.m.map(|col| self.apply_linear(col));
        let lt = self.apply_linear(other.t);
        Affine {
            m,
            t: [lt[0] + self.t[0], lt[1] + self.t[1], lt[2] + self.t[2]],
        }
    }

    fn determinant(&self) -> f64 {
        let [a, b, c] = self.m;
        a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1])
            + c[0] * (a[1] * b[2] - a[2] * b[1])
    }
}

fn length(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The node's local transform, as three.js builds it.
fn local_matrix(i: usize, node: &Json) -> Result<Affine> {
    if node.get("matrix").is_some() {
        let a = numbers::<16>(node, i, "matrix", [0.0; 16])?;
        // Column-major; the last row of an affine glTF matrix is 0, 0, 0, 1.
        if [a[3], a[7], a[11], a[15]] != [0.0, 0.0, 0.0, 1.0] {
            return Err(vrm_err(format!(
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
fn compose(t: [f64; 3], q: [f64; 4], s: [f64; 3]) -> Affine {
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
fn decompose(a: &Affine) -> ([f64; 3], [f64; 4], [f64; 3]) {
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
fn quat_from_rotation_columns(c0: [f64; 3], c1: [f64; 3], c2: [f64; 3]) -> [f64; 4] {
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

// ---------------------------------------------------------------------------------------------
// Humanoid bone map

/// One mapped bone: which bone, which node, and the JSON path to cite in errors.
pub(crate) type BoneEntry = (HumanBone, usize, String);

/// Reads the humanoid bone map of `VRMC_vrm` (preferred) or `VRM`.
pub(crate) fn humanoid_map(ext: Option<&Json>, n: usize) -> Result<(VrmVersion, Vec<BoneEntry>)> {
    let v1 = ext.and_then(|e| e.get("VRMC_vrm"));
    let v0 = ext.and_then(|e| e.get("VRM"));
    let (version, entries) = match (v1, v0) {
        (Some(v1), _) => (VrmVersion::V1, vrm1_bones(v1, n)?),
        (None, Some(v0)) => (VrmVersion::V0, vrm0_bones(v0, n)?),
        (None, None) => {
            return Err(vrm_err(
                "no VRMC_vrm or VRM extension: this glTF is not a VRM avatar",
            ))
        }
    };
    // A node can carry one bone: two bones on one joint would make a zero-length bone.
    let mut by_node: Vec<(usize, &str)> = Vec::with_capacity(entries.len());
    for (_, node, field) in &entries {
        if let Some((_, other)) = by_node.iter().find(|(m, _)| m == node) {
            return Err(vrm_err(format!(
                "{field}: node {node} is already used by {other}"
            )));
        }
        by_node.push((*node, field));
    }
    Ok((version, entries))
}

fn vrm1_bones(ext: &Json, n: usize) -> Result<Vec<BoneEntry>> {
    const BASE: &str = "extensions.VRMC_vrm";
    if ext.as_object().is_none() {
        return Err(vrm_err(format!("{BASE}: must be an object")));
    }
    match ext.get("specVersion").and_then(Json::as_str) {
        Some(v) if v == "1.0" || v.starts_with("1.0-") => {}
        Some(v) => {
            return Err(vrm_err(format!(
                "{BASE}.specVersion: unsupported \"{v}\" (expected \"1.0\")"
            )))
        }
        None => {
            return Err(vrm_err(format!(
                "{BASE}.specVersion: missing (expected \"1.0\")"
            )))
        }
    }
    let bones = ext
        .get("humanoid")
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid: missing")))?
        .get("humanBones")
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid.humanBones: missing")))?
        .as_object()
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid.humanBones: must be an object")))?;
    // Every entry must be a different bone: more entries than bones is an error whatever they
    // are (and bounds the sort below).
    if bones.len() > BONE_COUNT {
        return Err(vrm_err(format!(
            "{BASE}.humanoid.humanBones: {} entries, more than the {BONE_COUNT} humanoid bones",
            bones.len()
        )));
    }
    // In name order (serde_json's map is sorted), so that which of two clashing entries an
    // error names does not depend on the file's member order.

    // 1.0-beta files kept the 0.x thumb names; three-vrm renames them when it sees one.
    let beta_thumbs = bones
        .iter()
        .any(|(k, _)| k == "leftThumbIntermediate" || k == "rightThumbIntermediate");
    let mut out = Vec::with_capacity(bones.len().min(BONE_COUNT));
    for (name, entry) in bones {
        let field = format!("{BASE}.humanoid.humanBones.{name}");
        let bone = if beta_thumbs {
            HumanBone::from_vrm0_name(name)
        } else {
            HumanBone::from_name(name)
        }
        .ok_or_else(|| {
            vrm_err(format!(
                "{BASE}.humanoid.humanBones: unknown bone name \"{name}\""
            ))
        })?;
        let node = entry
            .get("node")
            .ok_or_else(|| vrm_err(format!("{field}.node: missing")))?;
        let node = index_value(node, n, &format!("{field}.node"))?;
        if out.iter().any(|(b, _, _)| *b == bone) {
            return Err(vrm_err(format!("{field}: duplicate bone {bone}")));
        }
        out.push((bone, node, field));
    }
    Ok(out)
}

fn vrm0_bones(ext: &Json, n: usize) -> Result<Vec<BoneEntry>> {
    const BASE: &str = "extensions.VRM";
    let bones = ext
        .get("humanoid")
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid: missing")))?
        .get("humanBones")
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid.humanBones: missing")))?
        .as_array()
        .ok_or_else(|| vrm_err(format!("{BASE}.humanoid.humanBones: must be an array")))?;
    let mut out: Vec<BoneEntry> = Vec::with_capacity(bones.len().min(BONE_COUNT));
    for (k, entry) in bones.iter().enumerate() {
        let at = format!("{BASE}.humanoid.humanBones[{k}]");
        let name = entry
            .get("bone")
            .and_then(Json::as_str)
            .ok_or_else(|| vrm_err(format!("{at}.bone: missing or not a string")))?;
        let bone = HumanBone::from_vrm0_name(name).ok_or_else(|| {
            vrm_err(format!(
                "{at}.bone: unknown bone name \"{name}\" (VRM 0.x names thumbs \
                 thumbProximal/Intermediate/Distal)"
            ))
        })?;
        let node = entry
            .get("node")
            .ok_or_else(|| vrm_err(format!("{at}.node: missing")))?;
        // 0.x exporters write -1 for "not assigned"; three-vrm skips those bones.
        if node.as_f64().is_some_and(|i| i < 0.0 && i.fract() == 0.0) {
            continue;
        }
        let field = format!("{at} ({name})");
        let node = index_value(node, n, &format!("{at}.node ({name})"))?;
        if let Some((_, _, first)) = out.iter().find(|(b, _, _)| *b == bone) {
            return Err(vrm_err(format!(
                "{field}: duplicate bone {bone} (already mapped by {first})"
            )));
        }
        out.push((bone, node, field));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::FRAC_PI_2;

    fn glb(json: &str, bin: Option<&[u8]>) -> Vec<u8> {
        let mut j = json.as_bytes().to_vec();
        while j.len() % 4 != 0 {
            j.push(b' ');
        }
        let mut body = Vec::new();
        body.extend_from_slice(&(j.len() as u32).to_le_bytes());
        body.extend_from_slice(&CHUNK_JSON.to_le_bytes());
        body.extend_from_slice(&j);
        if let Some(b) = bin {
            body.extend_from_slice(&(b.len() as u32).to_le_bytes());
            body.extend_from_slice(&CHUNK_BIN.to_le_bytes());
            body.extend_from_slice(b);
        }
        let mut out = b"glTF".to_vec();
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&((body.len() + 12) as u32).to_le_bytes());
        out.extend_from_slice(&body);
        out
    }

    fn msg(r: Result<VrmHumanoid>) -> String {
        match r {
            Err(Error::Vrm(m)) => m,
            other => panic!("expected a vrm error, got {other:?}"),
        }
    }

    #[test]
    fn container_errors_name_the_problem() {
        assert!(msg(parse(b"PK\x03\x04abcdefgh")).contains("not a glTF binary (magic 0x04034B50"));
        assert!(msg(parse(b"{\"asset\":1}")).contains("JSON .gltf"));
        assert!(msg(parse(b"glTF\x02\0\0")).contains("shorter than the 12-byte"));
        let mut g = glb("{}", None);
        g[4] = 1;
        assert!(msg(parse(&g)).contains("version 1"));
        let g = glb("{}", Some(&[1, 2, 3, 4]));
        let m = msg(parse(&g[..g.len() - 4]));
        assert!(
            m.contains(&format!(
                "header says {} bytes, got {}",
                g.len(),
                g.len() - 4
            )),
            "{m}"
        );
        let mut long = g.clone();
        long.extend_from_slice(&[0; 4]);
        assert!(msg(parse(&long)).contains("trailing data"));
        // Chunk length running past the end.
        let mut bad = g.clone();
        bad[12..16].copy_from_slice(&1000u32.to_le_bytes());
        assert!(msg(parse(&bad)).contains("JSON chunk of 1000 bytes"));
        // Misaligned chunk length.
        let mut bad = g.clone();
        bad[12..16].copy_from_slice(&3u32.to_le_bytes());
        assert!(msg(parse(&bad)).contains("not a multiple of 4"));
        // BIN first.
        let mut bad = g.clone();
        bad[16..20].copy_from_slice(&CHUNK_BIN.to_le_bytes());
        assert!(msg(parse(&bad)).contains("first chunk must be the JSON chunk"));
        // Header only.
        let mut header = b"glTF".to_vec();
        header.extend_from_slice(&2u32.to_le_bytes());
        header.extend_from_slice(&12u32.to_le_bytes());
        assert!(msg(parse(&header)).contains("JSON chunk missing"));
        assert!(msg(parse(&glb("[1]", None))).contains("top level must be an object"));
        assert!(msg(parse(&glb("{\"a\":", None))).contains("not valid JSON"));
        assert!(msg(parse(&glb("{}", None))).contains("no VRMC_vrm or VRM extension"));
    }

    fn vrm1(nodes: &str, bones: &str) -> Vec<u8> {
        glb(
            &format!(
                r#"{{"asset":{{"version":"2.0"}},"nodes":{nodes},
                "extensions":{{"VRMC_vrm":{{"specVersion":"1.0","humanoid":{{"humanBones":{bones}}}}}}}}}"#
            ),
            Some(&[0; 8]),
        )
    }

    #[test]
    fn humanoid_bones_come_in_bone_order_and_clashes_in_name_order() {
        // Members in an order that is neither the bones' nor the names'.
        let nodes = r#"[{"children":[1]},{"children":[2]},{"children":[3]},{}]"#;
        let h = parse(&vrm1(
            nodes,
            r#"{"spine":{"node":1},"head":{"node":3},"hips":{"node":0},"chest":{"node":2}}"#,
        ))
        .unwrap();
        let order: Vec<HumanBone> = h.bones.iter().map(|(b, _)| *b).collect();
        let by_index = [
            HumanBone::Hips,
            HumanBone::Spine,
            HumanBone::Chest,
            HumanBone::Head,
        ];
        let mut want = by_index.to_vec();
        want.sort_by_key(|b| b.index());
        assert_eq!(order, want);
        // Two unknown names: the error names the first by name, whatever the member order.
        for bones in [
            r#"{"zeta":{"node":0},"hips":{"node":1},"alpha":{"node":2}}"#,
            r#"{"alpha":{"node":2},"hips":{"node":1},"zeta":{"node":0}}"#,
        ] {
            let m = msg(parse(&vrm1(nodes, bones)));
            assert!(m.contains("unknown bone name \"alpha\""), "{m}");
        }
        // More entries than there are bones: refused before any is read.
        let many: Vec<String> = (0..=BONE_COUNT)
            .map(|k| format!(r#""b{k}":{{"node":0}}"#))
            .collect();
        let m = msg(parse(&vrm1(nodes, &format!("{{{}}}", many.join(",")))));
        assert!(
            m.contains("56 entries, more than the 55 humanoid bones"),
            "{m}"
        );
    }

    #[test]
    fn world_positions_go_through_rotated_scaled_and_matrix_nodes() {
        // root: rotated 90 deg about +Y and scaled 2; a plain helper node; hips below it.
        // A child at local +X of a +Y-rotated parent ends up at world -Z.
        let (qy, c) = ((FRAC_PI_2 / 2.0).sin(), (FRAC_PI_2 / 2.0).cos());
        let nodes = format!(
            r#"[{{"children":[1],"rotation":[0,{qy},0,{c}],"scale":[2,2,2]}},
               {{"children":[2],"translation":[0.5,0,0]}},
               {{"children":[3],"matrix":[0,0,-3,0, 0,3,0,0, 3,0,0,0, 0,0.25,0,1]}},
               {{"translation":[0,0,0.1]}}]"#
        );
        let h = parse(&vrm1(&nodes, r#"{"hips":{"node":2},"spine":{"node":3}}"#)).unwrap();
        assert_eq!(h.version, VrmVersion::V1);
        // hips: R_y(90) * 2 * ((0.5,0,0) + (0,0.25,0)) = 2 * (0, 0.25, -0.5).
        let hips = h.bones[0].1;
        assert!(hips.abs_diff_eq(Vec3::new(0.0, 0.5, -1.0), 1e-6), "{hips}");
        // spine: hips + R_y(90) * 2 * (matrix node: R_y(90) scale 3) * (0,0,0.1)
        //      = hips + R_y(180) * 6 * (0,0,0.1) = hips + (0,0,-0.6).
        let spine = h.bones[1].1;
        assert!(
            spine.abs_diff_eq(Vec3::new(0.0, 0.5, -1.6), 1e-6),
            "{spine}"
        );
    }

    #[test]
    fn mirroring_matrix_keeps_its_reflection() {
        // A reflection in x (negative determinant): three.js gives scale (-1, 1, 1).
        let nodes = r#"[{"children":[1],"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]},
                        {"translation":[0.3,1,0]}]"#;
        let h = parse(&vrm1(nodes, r#"{"hips":{"node":1}}"#)).unwrap();
        assert!(h.bones[0].1.abs_diff_eq(Vec3::new(-0.3, 1.0, 0.0), 1e-6));
    }

    #[test]
    fn node_and_bone_map_errors() {
        let one = r#"[{"translation":[0,1,0]}]"#;
        let m = msg(parse(&vrm1(one, r#"{"hips":{"node":5}}"#)));
        assert!(
            m.contains("humanBones.hips.node: node 5 out of range (the file has 1 nodes)"),
            "{m}"
        );
        let m = msg(parse(&vrm1(one, r#"{"hips":{"node":-1}}"#)));
        assert!(m.contains("non-negative integer"), "{m}");
        let m = msg(parse(&vrm1(one, r#"{"hipz":{"node":0}}"#)));
        assert!(m.contains("unknown bone name \"hipz\""), "{m}");
        let two = r#"[{"children":[1]},{}]"#;
        let m = msg(parse(&vrm1(
            two,
            r#"{"hips":{"node":1},"spine":{"node":1}}"#,
        )));
        assert!(m.contains("node 1 is already used by"), "{m}");
        let m = msg(parse(&vrm1(r#"[{"translation":[0,1]}]"#, r#"{}"#)));
        assert!(
            m.contains("nodes[0].translation: must be an array of 3"),
            "{m}"
        );
        let m = msg(parse(&vrm1(r#"[{"children":[0]}]"#, r#"{}"#)));
        assert!(m.contains("lists itself"), "{m}");
        let m = msg(parse(&vrm1(
            r#"[{"children":[1]},{"children":[2]},{"children":[1]}]"#,
            "{}",
        )));
        assert!(m.contains("node 1 has two parents (nodes 0 and 2)"), "{m}");
        let m = msg(parse(&vrm1(
            r#"[{"children":[1]},{"children":[2]},{"children":[0]}]"#,
            "{}",
        )));
        assert!(m.contains("cycle"), "{m}");
        let m = msg(parse(&vrm1(r#"[{"children":[1,1]},{}]"#, "{}")));
        assert!(m.contains("lists node 1 twice"), "{m}");
        let zero = r#"[{"children":[1],"matrix":[0,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]},{}]"#;
        let m = msg(parse(&vrm1(zero, r#"{"hips":{"node":1}}"#)));
        assert!(
            m.contains("humanBones.hips: the world position of node 1 is not finite"),
            "{m}"
        );
        // A degenerate node that no bone depends on is harmless, as in three.js.
        let side = r#"[{"matrix":[0,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]},{"translation":[0,1,0]}]"#;
        assert!(parse(&vrm1(side, r#"{"hips":{"node":1}}"#)).is_ok());
        let spec = glb(r#"{"extensions":{"VRMC_vrm":{"specVersion":"2.0"}}}"#, None);
        assert!(msg(parse(&spec)).contains("specVersion: unsupported \"2.0\""));
    }

    #[test]
    fn look_at_offsets_go_through_the_head_node() {
        // The head node turned 90 degrees about +Y and scaled 2 (a Blender roll): its local
        // +X offset points along world -Z, twice as long.
        let (qy, c) = ((FRAC_PI_2 / 2.0).sin(), (FRAC_PI_2 / 2.0).cos());
        let nodes = format!(
            r#"[{{"children":[1],"translation":[0,1,0]}},
               {{"translation":[0,0.5,0],"rotation":[0,{qy},0,{c}],"scale":[2,2,2]}}]"#
        );
        let with = |look_at: &str| {
            glb(
                &format!(
                    r#"{{"nodes":{nodes},"extensions":{{"VRMC_vrm":{{"specVersion":"1.0",
                    "humanoid":{{"humanBones":{{"hips":{{"node":0}},"head":{{"node":1}}}}}},
                    "lookAt":{look_at}}}}}}}"#
                ),
                None,
            )
        };
        let h = parse(&with(r#"{"offsetFromHeadBone":[0.03,0.06,0]}"#)).unwrap();
        let o = h.look_at.unwrap();
        assert!(o.abs_diff_eq(Vec3::new(0.0, 0.12, -0.06), 1e-6), "{o}");
        // Malformed or absent: a hint, ignored.
        for bad in [
            r#"{"offsetFromHeadBone":[0,1]}"#,
            r#"{"offsetFromHeadBone":"x"}"#,
            "{}",
        ] {
            assert_eq!(parse(&with(bad)).unwrap().look_at, None, "{bad}");
        }
        // VRM 0.x: firstPersonBoneOffset with z negated, as three-vrm reads it.
        let v0 = glb(
            r#"{"nodes":[{"translation":[0,1,0]},{"translation":[0,1.5,0]}],
               "extensions":{"VRM":{"humanoid":{"humanBones":[{"bone":"hips","node":0},
               {"bone":"head","node":1}]},
               "firstPerson":{"firstPersonBoneOffset":{"x":0,"y":0.06,"z":0.02}}}}}"#,
            None,
        );
        let o = parse(&v0).unwrap().look_at.unwrap();
        assert!(o.abs_diff_eq(Vec3::new(0.0, 0.06, -0.02), 1e-6), "{o}");
    }

    #[test]
    fn vrm0_names_thumbs_negative_nodes_and_duplicates() {
        let nodes =
            r#"[{"translation":[0,1,0]},{"translation":[0.1,1,0]},{"translation":[0.2,1,0]}]"#;
        let v0 = |bones: &str| {
            glb(
                &format!(
                    r#"{{"nodes":{nodes},"extensions":{{"VRM":{{"humanoid":{{"humanBones":{bones}}}}}}}}}"#
                ),
                None,
            )
        };
        let h = parse(&v0(
            r#"[{"bone":"leftThumbIntermediate","node":1},{"bone":"hips","node":0},
                {"bone":"leftThumbProximal","node":2},{"bone":"leftIndexProximal","node":-1}]"#,
        ))
        .unwrap();
        assert_eq!(h.version, VrmVersion::V0);
        let names: Vec<_> = h.bones.iter().map(|(b, _)| *b).collect();
        assert_eq!(
            names,
            [
                HumanBone::Hips,
                HumanBone::LeftThumbMetacarpal,
                HumanBone::LeftThumbProximal
            ]
        );
        assert!(h.bones[1].1.abs_diff_eq(Vec3::new(0.2, 1.0, 0.0), 1e-7));
        let m = msg(parse(&v0(
            r#"[{"bone":"hips","node":0},{"bone":"hips","node":1}]"#,
        )));
        assert!(m.contains("duplicate bone hips"), "{m}");
        let m = msg(parse(&v0(r#"[{"bone":"leftThumbMetacarpal","node":0}]"#)));
        assert!(
            m.contains("unknown bone name \"leftThumbMetacarpal\""),
            "{m}"
        );
        let m = msg(parse(&v0(r#"[{"bone":"hips","node":7}]"#)));
        assert!(
            m.contains("humanBones[0].node (hips): node 7 out of range"),
            "{m}"
        );
    }

    #[test]
    fn decompose_round_trips_a_trs_matrix() {
        // One rotation per branch of the quaternion extraction: small (trace > 0) and near
        // half-turns about x, y and z (each diagonal term largest in turn).
        let quats = [
            glam::Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.3),
            glam::Quat::from_axis_angle(Vec3::new(1.0, 0.1, 0.2).normalize(), 3.1),
            glam::Quat::from_axis_angle(Vec3::new(0.1, 1.0, 0.2).normalize(), 3.1),
            glam::Quat::from_axis_angle(Vec3::new(0.1, 0.2, 1.0).normalize(), 3.1),
        ];
        for q in quats {
            let q = q.to_array().map(f64::from);
            let n = (q.iter().map(|v| v * v).sum::<f64>()).sqrt();
            let q = q.map(|v| v / n);
            let m = compose([1.0, 2.0, 3.0], q, [0.5, 2.0, 3.0]);
            let (t, r, s) = decompose(&m);
            assert_eq!(t, [1.0, 2.0, 3.0]);
            for (a, b) in s.iter().zip([0.5, 2.0, 3.0]) {
                assert!((a - b).abs() < 1e-12, "{s:?}");
            }
            let dot: f64 = r.iter().zip(q).map(|(a, b)| a * b).sum();
            assert!(dot.abs() > 1.0 - 1e-12, "{r:?} vs {q:?}");
            let again = compose(t, r, s);
            for (a, b) in again.m.iter().flatten().zip(m.m.iter().flatten()) {
                assert!((a - b).abs() < 1e-12);
            }
        }
    }
}
