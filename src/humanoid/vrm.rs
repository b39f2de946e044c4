//! Reading `.vrm` files: glTF 2.0 binary (GLB) with the `VRMC_vrm` (VRM 1.0) or `VRM`
//! (VRM 0.x) extension, down to the humanoid rest pose handrig needs.
//!
//! What is read: the GLB container (header, JSON chunk, optional BIN chunk), the glTF `nodes`
//! (TRS or `matrix`, `children`), and the humanoid bone map; [`load_skeleton`] also reads the
//! skinned meshes for self-contact ([`crate::humanoid::gltf_skin`]: never an error, a primitive it cannot
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
use serde_json::Value as Json;

use super::bones::{HumanBone, BONE_COUNT};
use super::document::{index_value, Document};
use super::gltf_skin::skin_of;
use super::skeleton::{Skeleton, VrmVersion};
use crate::error::{Error, Result};

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
            return Err(Error::vrm(format!(
                "{field}: the world position of node {node} is not finite (a degenerate \
                 transform on it or an ancestor, e.g. a zero-scale matrix)"
            )));
        }
        let p = Vec3::new(x as f32, y as f32, z as f32);
        if !p.is_finite() {
            return Err(Error::vrm(format!(
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
                .with_skin(skin_of(&doc, bytes, &binding))
        })
        .map_err(|e| match e {
            Error::MissingRequiredBones(names) => Error::vrm(format!(
                "humanoid lacks required bone(s) {}",
                names.join(", ")
            )),
            Error::InvalidInput { field, problem } => Error::vrm(format!(
                "humanoid bone {}: {problem}",
                field.strip_prefix("restPose.bones.").unwrap_or(&field)
            )),
            other => other,
        })
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
            return Err(Error::vrm(
                "no VRMC_vrm or VRM extension: this glTF is not a VRM avatar",
            ))
        }
    };
    // A node can carry one bone: two bones on one joint would make a zero-length bone.
    let mut by_node: Vec<(usize, &str)> = Vec::with_capacity(entries.len());
    for (_, node, field) in &entries {
        if let Some((_, other)) = by_node.iter().find(|(m, _)| m == node) {
            return Err(Error::vrm(format!(
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
        return Err(Error::vrm(format!("{BASE}: must be an object")));
    }
    match ext.get("specVersion").and_then(Json::as_str) {
        Some(v) if v == "1.0" || v.starts_with("1.0-") => {}
        Some(v) => {
            return Err(Error::vrm(format!(
                "{BASE}.specVersion: unsupported \"{v}\" (expected \"1.0\")"
            )))
        }
        None => {
            return Err(Error::vrm(format!(
                "{BASE}.specVersion: missing (expected \"1.0\")"
            )))
        }
    }
    let bones = ext
        .get("humanoid")
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid: missing")))?
        .get("humanBones")
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid.humanBones: missing")))?
        .as_object()
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid.humanBones: must be an object")))?;
    // Every entry must be a different bone: more entries than bones is an error whatever they
    // are (and bounds the sort below).
    if bones.len() > BONE_COUNT {
        return Err(Error::vrm(format!(
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
            Error::vrm(format!(
                "{BASE}.humanoid.humanBones: unknown bone name \"{name}\""
            ))
        })?;
        let node = entry
            .get("node")
            .ok_or_else(|| Error::vrm(format!("{field}.node: missing")))?;
        let node = index_value(node, n, &format!("{field}.node"))?;
        if out.iter().any(|(b, _, _)| *b == bone) {
            return Err(Error::vrm(format!("{field}: duplicate bone {bone}")));
        }
        out.push((bone, node, field));
    }
    Ok(out)
}

fn vrm0_bones(ext: &Json, n: usize) -> Result<Vec<BoneEntry>> {
    const BASE: &str = "extensions.VRM";
    let bones = ext
        .get("humanoid")
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid: missing")))?
        .get("humanBones")
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid.humanBones: missing")))?
        .as_array()
        .ok_or_else(|| Error::vrm(format!("{BASE}.humanoid.humanBones: must be an array")))?;
    let mut out: Vec<BoneEntry> = Vec::with_capacity(bones.len().min(BONE_COUNT));
    for (k, entry) in bones.iter().enumerate() {
        let at = format!("{BASE}.humanoid.humanBones[{k}]");
        let name = entry
            .get("bone")
            .and_then(Json::as_str)
            .ok_or_else(|| Error::vrm(format!("{at}.bone: missing or not a string")))?;
        let bone = HumanBone::from_vrm0_name(name).ok_or_else(|| {
            Error::vrm(format!(
                "{at}.bone: unknown bone name \"{name}\" (VRM 0.x names thumbs \
                 thumbProximal/Intermediate/Distal)"
            ))
        })?;
        let node = entry
            .get("node")
            .ok_or_else(|| Error::vrm(format!("{at}.node: missing")))?;
        // 0.x exporters write -1 for "not assigned"; three-vrm skips those bones.
        if node.as_f64().is_some_and(|i| i < 0.0 && i.fract() == 0.0) {
            continue;
        }
        let field = format!("{at} ({name})");
        let node = index_value(node, n, &format!("{at}.node ({name})"))?;
        if let Some((_, _, first)) = out.iter().find(|(b, _, _)| *b == bone) {
            return Err(Error::vrm(format!(
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
    use crate::humanoid::document::{compose, decompose};
    use crate::humanoid::glb::{CHUNK_BIN, CHUNK_JSON};
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
