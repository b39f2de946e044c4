//! Reading any glTF humanoid (`.glb`, or a `.vrm`): Mixamo-named, Unreal-mannequin-named or
//! bound by an explicit bone map, down to the same rest pose the VRM reader ([`crate::humanoid::vrm`])
//! produces.
//!
//! How the humanoid is found, first match wins:
//! 1. an explicit bone map (`options.skeleton.boneMap` in JavaScript: humanoid bone name ->
//!    node name), which is the whole binding;
//! 2. the file's `VRMC_vrm` / `VRM` extension (read exactly as [`crate::humanoid::vrm::parse`] reads it);
//! 3. node names: Mixamo's (`mixamorig:LeftHandIndex1`; the `mixamorig:` / `mixamorig1:` prefix
//!    is optional, and three.js's sanitized `mixamorigLeftHandIndex1` is read too) or the Unreal
//!    mannequin's (`pelvis`, `spine_01`, `upperarm_l`, `index_01_l`, ...), whichever names more
//!    bones.
//!
//! Bone rolls need nothing here: handrig's skeleton is three-vrm's *normalized* one (identity
//! rest rotations), which only needs each bone's rest world position, taken through the full
//! node hierarchy (armature nodes turned or scaled, bone rest rotations, helper nodes between
//! bones) exactly as for a VRM. The rest rotations matter only when the results are written back
//! onto the model's own bones (`handrig/three`'s `applyToSkeleton`: `local = P^-1 q P B`).
//!
//! Facing: a VRM keeps its extension's version (1.0 faces +Z, 0.x faces -Z), so `fromGltf` on a
//! `.vrm` equals `fromVrm`. Any other file's facing comes from its skeleton: its left side (the
//! left upper arm, or the left upper leg) toward +X faces +Z, toward -X faces -Z (handled as a
//! VRM 0.x: turned internally, results in the model's own frame). A skeleton whose left-right
//! axis runs along Z (facing +-X) is refused.
//!
//! Every error is an [`Error::Gltf`] naming the bone, the node or the part of the file.

use glam::Vec3;

use super::bones::{HumanBone, BONE_COUNT};
use super::document::{Document, MAX_DEPTH};
use super::gltf_skin::skin_of;
use super::skeleton::{Skeleton, VrmVersion};
use super::vrm::{self, BoneEntry, VrmHumanoid};
use crate::error::{Error, Num, Result};

/// Where a binding came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Naming {
    /// The caller's bone map.
    BoneMap,
    /// The `VRMC_vrm` extension (VRM 1.0).
    Vrm1,
    /// The `VRM` extension (VRM 0.x).
    Vrm0,
    /// Mixamo node names.
    Mixamo,
    /// Unreal-mannequin node names.
    Unreal,
}

impl Naming {
    /// `"boneMap"`, `"vrm1"`, `"vrm0"`, `"mixamo"` or `"unreal"`.
    pub fn name(self) -> &'static str {
        match self {
            Naming::BoneMap => "boneMap",
            Naming::Vrm1 => "vrm1",
            Naming::Vrm0 => "vrm0",
            Naming::Mixamo => "mixamo",
            Naming::Unreal => "unreal",
        }
    }
}

/// A glTF humanoid: its rest pose (as [`crate::humanoid::vrm::parse`] gives it) and its binding.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfHumanoid {
    /// Rest pose: facing as `version` (`V0`: faces -Z), rest world positions, look-at.
    pub humanoid: VrmHumanoid,
    /// How the bones were found.
    pub naming: Naming,
    /// Every bound bone in [`HumanBone::ALL`] order with its node index and node name (`""`
    /// for a node without a name).
    pub binding: Vec<(HumanBone, usize, String)>,
}

/// A coordinate for a message, to the millimeter (as `{:.3}` would, without the trailing zeros).
fn milli(x: f32) -> Num {
    Num::f32((x * 1000.0).round() / 1000.0)
}

fn err(msg: impl Into<String>) -> Error {
    Error::Gltf(msg.into())
}

/// Reading errors of the shared container/node code say `vrm:`; here they say `gltf:`.
fn as_gltf(e: Error) -> Error {
    match e {
        Error::Vrm(m) => Error::Gltf(m),
        other => other,
    }
}

/// The Mixamo name of a node without its `mixamorig:` / `mixamorig1:` / sanitized
/// `mixamorig` prefix, if it has one; the name itself otherwise.
fn strip_mixamo_prefix(name: &str) -> &str {
    let Some(rest) = name.strip_prefix("mixamorig") else {
        return name;
    };
    let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit());
    rest.strip_prefix(':').unwrap_or(rest)
}

const FINGERS_MIXAMO: [(&str, &str); 5] = [
    ("Thumb", "Thumb"),
    ("Index", "Index"),
    ("Middle", "Middle"),
    ("Ring", "Ring"),
    ("Pinky", "Little"),
];
const FINGERS_UNREAL: [(&str, &str); 5] = [
    ("thumb", "Thumb"),
    ("index", "Index"),
    ("middle", "Middle"),
    ("ring", "Ring"),
    ("pinky", "Little"),
];

/// The VRM names of a finger's three joints (thumbs: metacarpal, proximal, distal).
fn joint_names(vrm_finger: &str) -> [&'static str; 3] {
    if vrm_finger == "Thumb" {
        ["Metacarpal", "Proximal", "Distal"]
    } else {
        ["Proximal", "Intermediate", "Distal"]
    }
}

/// The humanoid bone a Mixamo node name stands for (`mixamorig:LeftHandIndex1` ->
/// `leftIndexProximal`), with or without the `mixamorig` prefix.
pub fn mixamo_bone(name: &str) -> Option<HumanBone> {
    let n = strip_mixamo_prefix(name);
    let fixed = match n {
        "Hips" => Some(HumanBone::Hips),
        "Spine" => Some(HumanBone::Spine),
        "Spine1" => Some(HumanBone::Chest),
        "Spine2" => Some(HumanBone::UpperChest),
        "Neck" => Some(HumanBone::Neck),
        "Head" => Some(HumanBone::Head),
        _ => None,
    };
    if fixed.is_some() {
        return fixed;
    }
    let (side, rest) = if let Some(r) = n.strip_prefix("Left") {
        ("left", r)
    } else {
        ("right", n.strip_prefix("Right")?)
    };
    let part = match rest {
        "Eye" => "Eye",
        "Shoulder" => "Shoulder",
        "Arm" => "UpperArm",
        "ForeArm" => "LowerArm",
        "Hand" => "Hand",
        "UpLeg" => "UpperLeg",
        "Leg" => "LowerLeg",
        "Foot" => "Foot",
        "ToeBase" => "Toes",
        _ => {
            let f = rest.strip_prefix("Hand")?;
            let (finger, vrm_finger) = FINGERS_MIXAMO.iter().find(|(m, _)| f.starts_with(m))?;
            let k = match &f[finger.len()..] {
                "1" => 0,
                "2" => 1,
                "3" => 2,
                _ => return None,
            };
            let joint = joint_names(vrm_finger)[k];
            return HumanBone::from_name(&format!("{side}{vrm_finger}{joint}"));
        }
    };
    HumanBone::from_name(&format!("{side}{part}"))
}

/// The humanoid bone an Unreal-mannequin node name stands for (`upperarm_l` ->
/// `leftUpperArm`, `index_01_l` -> `leftIndexProximal`, `spine_03` -> `upperChest`); ASCII
/// case is ignored.
pub fn unreal_bone(name: &str) -> Option<HumanBone> {
    let n = name.to_ascii_lowercase();
    let fixed = match n.as_str() {
        "pelvis" => Some(HumanBone::Hips),
        "spine_01" => Some(HumanBone::Spine),
        "spine_02" => Some(HumanBone::Chest),
        "spine_03" => Some(HumanBone::UpperChest),
        "neck_01" => Some(HumanBone::Neck),
        "head" => Some(HumanBone::Head),
        _ => None,
    };
    if fixed.is_some() {
        return fixed;
    }
    let (rest, side) = if let Some(r) = n.strip_suffix("_l") {
        (r, "left")
    } else {
        (n.strip_suffix("_r")?, "right")
    };
    let part = match rest {
        "eye" => "Eye",
        "clavicle" => "Shoulder",
        "upperarm" => "UpperArm",
        "lowerarm" => "LowerArm",
        "hand" => "Hand",
        "thigh" => "UpperLeg",
        "calf" => "LowerLeg",
        "foot" => "Foot",
        "ball" => "Toes",
        _ => {
            let (finger, k) = rest.split_once("_0")?;
            let (_, vrm_finger) = FINGERS_UNREAL.iter().find(|(u, _)| *u == finger)?;
            let k = match k {
                "1" => 0,
                "2" => 1,
                "3" => 2,
                _ => return None,
            };
            let joint = joint_names(vrm_finger)[k];
            return HumanBone::from_name(&format!("{side}{vrm_finger}{joint}"));
        }
    };
    HumanBone::from_name(&format!("{side}{part}"))
}

/// three.js's `PropertyBinding.sanitizeNodeName`: whitespace to `_`, `[ ] . : /` removed
/// (what `GLTFLoader` names the node objects).
pub fn sanitize_node_name(name: &str) -> String {
    name.chars()
        .filter(|c| !matches!(c, '[' | ']' | '.' | ':' | '/'))
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}

fn node_name(doc: &Document, i: usize) -> &str {
    doc.nodes
        .get(i)
        .and_then(|n| n.get("name"))
        .and_then(serde_json::Value::as_str)
        .unwrap_or("")
}

/// `node "name"` (or `node 7` when it has none), for messages.
fn show_node(doc: &Document, i: usize) -> String {
    match node_name(doc, i) {
        "" => format!("node {i}"),
        n => format!("node {i} \"{n}\""),
    }
}

/// Binds by the caller's map: humanoid bone name -> node name (as written in the file, or as
/// three.js sanitizes it).
fn bind_by_map(doc: &Document, map: &[(String, String)]) -> Result<Vec<BoneEntry>> {
    const AT: &str = "options.skeleton.boneMap";
    if map.len() > BONE_COUNT {
        return Err(err(format!(
            "{AT}: {} entries, more than the {BONE_COUNT} humanoid bones",
            map.len()
        )));
    }
    let n = doc.nodes.len();
    let mut out: Vec<BoneEntry> = Vec::with_capacity(map.len());
    for (bone_name, node) in map {
        let field = format!("{AT}.{bone_name}");
        let bone = HumanBone::from_name(bone_name).ok_or_else(|| {
            err(format!(
                "{AT}: unknown bone name \"{bone_name}\" (expected a VRM 1.0 humanoid bone name \
                 such as \"leftHand\")"
            ))
        })?;
        let exact: Vec<usize> = (0..n).filter(|&i| node_name(doc, i) == node).collect();
        let found = if exact.is_empty() {
            (0..n)
                .filter(|&i| sanitize_node_name(node_name(doc, i)) == *node)
                .collect()
        } else {
            exact
        };
        let i = match found.as_slice() {
            [i] => *i,
            [] => {
                return Err(err(format!(
                    "{field}: no node named \"{node}\" in the file"
                )))
            }
            [a, b, ..] => {
                return Err(err(format!(
                    "{field}: two nodes are named \"{node}\" (nodes {a} and {b})"
                )))
            }
        };
        out.push((bone, i, field));
    }
    Ok(out)
}

/// Binds by node names (Mixamo or Unreal, whichever names more bones).
fn bind_by_names(doc: &Document) -> Result<(Naming, Vec<BoneEntry>)> {
    let n = doc.nodes.len();
    let count = |f: fn(&str) -> Option<HumanBone>| {
        (0..n).filter(|&i| f(node_name(doc, i)).is_some()).count()
    };
    let (mixamo, unreal) = (count(mixamo_bone), count(unreal_bone));
    if mixamo == 0 && unreal == 0 {
        return Err(err(
            "no humanoid found: no VRMC_vrm or VRM extension, and no node has a Mixamo \
             (\"mixamorig:Hips\", \"mixamorig:LeftArm\", ...) or Unreal-mannequin (\"pelvis\", \
             \"upperarm_l\", ...) bone name; bind the bones with options.skeleton.boneMap",
        ));
    }
    let (naming, f): (Naming, fn(&str) -> Option<HumanBone>) = if mixamo >= unreal {
        (Naming::Mixamo, mixamo_bone)
    } else {
        (Naming::Unreal, unreal_bone)
    };
    let mut slot: [Option<usize>; BONE_COUNT] = [None; BONE_COUNT];
    for i in 0..n {
        let Some(bone) = f(node_name(doc, i)) else {
            continue;
        };
        if let Some(first) = slot[bone.index()] {
            return Err(err(format!(
                "duplicate binding: {bone} matches both {} and {} ({} names)",
                show_node(doc, first),
                show_node(doc, i),
                naming.name()
            )));
        }
        slot[bone.index()] = Some(i);
    }
    let out = HumanBone::ALL
        .iter()
        .zip(slot)
        .filter_map(|(b, s)| Some((*b, s?, format!("{b} ({})", node_name(doc, s?)))))
        .collect();
    Ok((naming, out))
}

/// Whether node `a` is a proper ancestor of node `b`.
fn is_ancestor(doc: &Document, a: usize, b: usize) -> bool {
    let mut cur = doc.tree.parent.get(b).copied().flatten();
    // The hierarchy is acyclic and at most MAX_DEPTH deep (checked when read).
    for _ in 0..=MAX_DEPTH {
        match cur {
            Some(p) if p == a => return true,
            Some(p) => cur = doc.tree.parent.get(p).copied().flatten(),
            None => return false,
        }
    }
    false
}

/// Checks the binding against the humanoid's hierarchy: no node carries two bones, and every
/// bone's node lies below the node of its nearest bound humanoid ancestor (a finger chain in
/// order, arms under the chest, ...).
fn check_binding(doc: &Document, entries: &[BoneEntry]) -> Result<()> {
    let mut node_of: [Option<usize>; BONE_COUNT] = [None; BONE_COUNT];
    for (bone, node, _) in entries {
        if let Some((other, _, _)) = entries
            .iter()
            .find(|(b, n, _)| n == node && b.index() < bone.index())
        {
            return Err(err(format!(
                "duplicate binding: {other} and {bone} are both bound to {}",
                show_node(doc, *node)
            )));
        }
        if node_of[bone.index()].is_some() {
            return Err(err(format!("duplicate binding: {bone} is bound twice")));
        }
        node_of[bone.index()] = Some(*node);
    }
    for bone in HumanBone::ALL {
        let Some(node) = node_of[bone.index()] else {
            continue;
        };
        let mut up = bone.parent();
        while let Some(p) = up {
            if let Some(pnode) = node_of[p.index()] {
                if !is_ancestor(doc, pnode, node) {
                    return Err(err(format!(
                        "wrong hierarchy: {bone} ({}) is not below {p} ({}) in the node \
                         hierarchy (a chain out of order or bound to the wrong node?)",
                        show_node(doc, node),
                        show_node(doc, pnode)
                    )));
                }
                break;
            }
            up = p.parent();
        }
    }
    Ok(())
}

/// Facing from the skeleton: +Z (`V1`) when its left side is toward +X, -Z (`V0`) toward -X.
fn facing(bones: &[(HumanBone, Vec3)]) -> Result<VrmVersion> {
    let at = |b: HumanBone| bones.iter().find(|(x, _)| *x == b).map(|(_, p)| *p);
    let pairs = [
        (HumanBone::LeftUpperArm, HumanBone::RightUpperArm),
        (HumanBone::LeftUpperLeg, HumanBone::RightUpperLeg),
    ];
    for (l, r) in pairs {
        let (Some(lp), Some(rp)) = (at(l), at(r)) else {
            continue;
        };
        let d = lp - rp;
        if d.x.abs() > 2.0 * d.z.abs() {
            return Ok(if d.x > 0.0 {
                VrmVersion::V1
            } else {
                VrmVersion::V0
            });
        }
        return Err(err(format!(
            "facing: the skeleton's left-right axis ({l} - {r} = [{}, {}, {}]) is not \
             along X: the model must face +Z or -Z with +Y up (turn its root node)",
            milli(d.x),
            milli(d.y),
            milli(d.z)
        )));
    }
    // Required bones are missing; Skeleton::new names them.
    Ok(VrmVersion::V1)
}

/// Reads a glTF binary's humanoid. `bone_map` (humanoid bone name -> node name), when not
/// empty, is the whole binding; otherwise the VRM extension, then Mixamo or Unreal names.
///
/// # Errors
/// [`Error::Gltf`]: the container and node errors of [`crate::humanoid::vrm::parse`], no humanoid found,
/// an unknown bone name or missing node in `bone_map`, a duplicate binding, a bone not below
/// its humanoid parent, a model not facing +-Z, a non-finite bone position.
pub fn parse(bytes: &[u8], bone_map: &[(String, String)]) -> Result<GltfHumanoid> {
    parse_document(bytes, bone_map).map(|(_, g)| g)
}

/// [`parse`], with the document read (for the skin).
fn parse_document(bytes: &[u8], bone_map: &[(String, String)]) -> Result<(Document, GltfHumanoid)> {
    let doc = Document::read(bytes).map_err(|e| as_gltf(e.into()))?;
    let ext = doc.extensions.as_ref();
    let has_vrm = ext.is_some_and(|e| e.get("VRMC_vrm").is_some() || e.get("VRM").is_some());
    let (naming, version, entries) = if !bone_map.is_empty() {
        (Naming::BoneMap, None, bind_by_map(&doc, bone_map)?)
    } else if has_vrm {
        let (v, e) = vrm::humanoid_map(ext, doc.tree.len()).map_err(as_gltf)?;
        let naming = match v {
            VrmVersion::V1 => Naming::Vrm1,
            VrmVersion::V0 => Naming::Vrm0,
        };
        (naming, Some(v), e)
    } else {
        let (naming, e) = bind_by_names(&doc)?;
        (naming, None, e)
    };
    check_binding(&doc, &entries)?;
    // In bone order, by each bone's slot (check_binding made every bone appear once): no sort,
    // whose code would be one more copy of the standard library's sort in the `.wasm`.
    let mut slot: [Option<usize>; BONE_COUNT] = [None; BONE_COUNT];
    for (b, n, _) in &entries {
        slot[b.index()] = Some(*n);
    }
    let binding: Vec<(HumanBone, usize, String)> = HumanBone::ALL
        .iter()
        .zip(slot)
        .filter_map(|(b, n)| Some((*b, n?, node_name(&doc, n?).to_string())))
        .collect();
    let mut humanoid = vrm::humanoid_from_map(&doc, version.unwrap_or(VrmVersion::V1), entries)
        .map_err(as_gltf)?;
    if version.is_none() {
        humanoid.version = facing(&humanoid.bones)?;
    }
    Ok((
        doc,
        GltfHumanoid {
            humanoid,
            naming,
            binding,
        },
    ))
}

/// [`parse`], then the [`Skeleton`] (internal +Z-facing frame) with the skin of the file's
/// skinned meshes ([`Skeleton::with_skin`]; read as for a VRM, by the bound bones).
///
/// # Errors
/// Everything [`parse`] reports, and a missing required bone named with the node name the
/// file's naming would use.
pub fn load_skeleton(
    bytes: &[u8],
    bone_map: &[(String, String)],
) -> Result<(Skeleton, GltfHumanoid)> {
    let (doc, g) = parse_document(bytes, bone_map)?;
    let h = &g.humanoid;
    let nodes: Vec<(HumanBone, usize)> = g.binding.iter().map(|(b, n, _)| (*b, *n)).collect();
    let skeleton = Skeleton::new(&h.bones, h.version)
        .map(|s| {
            s.with_look_at_offset(h.look_at)
                .with_skin(skin_of(&doc, bytes, &nodes))
        })
        .map_err(|e| match e {
            Error::MissingRequiredBones(names) => err(format!(
                "missing required bone(s) {} ({} binding{})",
                names.join(", "),
                g.naming.name(),
                if g.naming == Naming::BoneMap {
                    ": add them to options.skeleton.boneMap"
                } else {
                    ""
                }
            )),
            Error::InvalidInput { field, problem } => err(format!(
                "humanoid bone {}: {problem}",
                field.strip_prefix("restPose.bones.").unwrap_or(&field)
            )),
            other => other,
        })?;
    Ok((skeleton, g))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixamo_names() {
        for (name, bone) in [
            ("mixamorig:Hips", "hips"),
            ("mixamorig1:Spine1", "chest"),
            ("mixamorigSpine2", "upperChest"),
            ("LeftArm", "leftUpperArm"),
            ("mixamorig:RightForeArm", "rightLowerArm"),
            ("mixamorig:LeftHandThumb1", "leftThumbMetacarpal"),
            ("mixamorig:LeftHandIndex1", "leftIndexProximal"),
            ("mixamorig:RightHandPinky3", "rightLittleDistal"),
            ("mixamorig:LeftToeBase", "leftToes"),
            ("mixamorig:RightUpLeg", "rightUpperLeg"),
        ] {
            assert_eq!(mixamo_bone(name), HumanBone::from_name(bone), "{name}");
        }
        for name in [
            "mixamorig:LeftHandIndex4",
            "mixamorig:HeadTop_End",
            "mixamorig:LeftToe_End",
            "Armature",
            "LeftHandIndex",
            "mixamorig:Spine3",
        ] {
            assert_eq!(mixamo_bone(name), None, "{name}");
        }
    }

    #[test]
    fn unreal_names() {
        for (name, bone) in [
            ("pelvis", "hips"),
            ("spine_03", "upperChest"),
            ("neck_01", "neck"),
            ("clavicle_l", "leftShoulder"),
            ("upperarm_r", "rightUpperArm"),
            ("lowerarm_l", "leftLowerArm"),
            ("thumb_01_l", "leftThumbMetacarpal"),
            ("index_01_l", "leftIndexProximal"),
            ("pinky_03_r", "rightLittleDistal"),
            ("thigh_l", "leftUpperLeg"),
            ("calf_r", "rightLowerLeg"),
            ("ball_l", "leftToes"),
            ("Hand_R", "rightHand"),
        ] {
            assert_eq!(unreal_bone(name), HumanBone::from_name(bone), "{name}");
        }
        for name in [
            "root",
            "index_03_l_end",
            "spine_04",
            "index_04_l",
            "ik_hand_l",
        ] {
            assert_eq!(unreal_bone(name), None, "{name}");
        }
    }

    #[test]
    fn sanitized_names_are_three_js_s() {
        assert_eq!(
            sanitize_node_name("mixamorig:Left Hand.1/x[0]"),
            "mixamorigLeft_Hand1x0"
        );
    }
}
