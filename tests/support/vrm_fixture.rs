//! Test-fixture generator: `.vrm` (GLB) bytes built from a skeleton chosen here, so tests have
//! avatars whose rest pose is known by construction.
//!
//! Two avatars, both loadable by three.js `GLTFLoader` + `@pixiv/three-vrm`:
//!
//! * [`vrm0_fingers`]: VRM 0.x (`VRM` extension, `specVersion "0.0"`), 53 bones with all 30
//!   finger bones, thumbs named the 0.x way (`thumbProximal/Intermediate/Distal`), **facing -Z**
//!   (its left hand is at -X). The node tree has what real exports have: a root `matrix` node
//!   turned -90 degrees about X and scaled 0.01 (Unity FBX style, so bone translations are in
//!   centimeters), a bone roll on every node, non-humanoid helper nodes between humanoid bones
//!   (shoulder adjust, forearm twist) and fingertip leaves. No `upperChest` and no `jaw`.
//! * [`human_proportions_vrm1`]: VRM 1.0 (`VRMC_vrm`, `specVersion "1.0"`), all 55 bones,
//!   human proportions: 1.70 m tall, upper arm 0.28 m, forearm 0.26 m, wrist to middle fingertip
//!   0.19 m, phalanx lengths after hand anatomy (proximal : intermediate : distal about
//!   1 : 0.6 : 0.45), fingers slightly spread, the thumb angled forward and palmar. Forearm twist
//!   helpers are written as `matrix` nodes.
//!
//! The skeleton is designed as world positions (meters, the model's own frame); each node gets
//! a chosen world rotation (its +Y aimed at its first child, rolled about it, as Blender bones
//! are) and the local TRS is derived from the parent's world transform. Tests check that
//! reading the file gives back the designed positions, which is independent of the reader's
//! forward pass. The JSON is canonical (sorted keys, numbers rounded to 1e-9) so the bytes are
//! reproducible: `cargo run --example gen_fixtures` writes them to `tests/fixtures/`.
//!
//! Also: [`glb`] packs any glTF JSON (+ BIN) into a GLB and [`unpack_glb`] reads one back, for
//! tests that edit real files.

use handrig::HumanBone;
use serde_json::{json, Map, Value};

/// A 3-vector, meters.
pub type V3 = [f64; 3];
/// A quaternion `[x, y, z, w]`.
pub type Q = [f64; 4];
/// Named points: `(VRM 1.0 bone name, position)`.
pub type Points = Vec<(&'static str, V3)>;

/// One generated avatar: what the file says, and what a reader must get out of it.
#[derive(Clone, Debug)]
pub struct Fixture {
    /// File name under `tests/fixtures/`.
    pub file_name: &'static str,
    /// `"0"` or `"1"`.
    pub vrm_version: &'static str,
    /// Designed rest world position of every humanoid bone, **VRM 1.0 names** (0.x thumbs
    /// already renamed), the model's own frame, meters.
    pub bones: Vec<(&'static str, V3)>,
    /// Fingertip world positions (leaf nodes `<distal node>_end`), keyed by the distal bone's
    /// VRM 1.0 name (`"leftIndexDistal"`), model frame.
    pub tips: Vec<(&'static str, V3)>,
    /// The glTF JSON (canonical form).
    pub json: Value,
}

impl Fixture {
    /// The `.vrm` bytes.
    #[must_use]
    pub fn glb(&self) -> Vec<u8> {
        glb(&self.json, None)
    }

    /// Designed position of a bone (VRM 1.0 name).
    #[must_use]
    pub fn bone(&self, name: &str) -> Option<V3> {
        self.bones.iter().find(|(n, _)| *n == name).map(|(_, p)| *p)
    }

    /// Designed fingertip position, keyed by the distal bone (`"leftIndexDistal"`).
    #[must_use]
    pub fn tip(&self, distal: &str) -> Option<V3> {
        self.tips
            .iter()
            .find(|(n, _)| *n == distal)
            .map(|(_, p)| *p)
    }
}

/// Both fixtures, in the order `gen_fixtures` writes them.
#[must_use]
pub fn all() -> Vec<Fixture> {
    vec![vrm0_fingers(), human_proportions_vrm1()]
}

// ---------------------------------------------------------------------------------------------
// Small f64 vector / quaternion helpers (the crate's glam is built without f64 types).

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mul(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn normalize(a: V3) -> V3 {
    mul(a, 1.0 / dot(a, a).sqrt())
}
fn q_mul(a: Q, b: Q) -> Q {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}
fn q_conj(q: Q) -> Q {
    [-q[0], -q[1], -q[2], q[3]]
}
fn q_rotate(q: Q, v: V3) -> V3 {
    let u = [q[0], q[1], q[2]];
    let t = mul(cross(u, v), 2.0);
    add(add(v, mul(t, q[3])), cross(u, t))
}
fn q_axis_angle(axis: V3, angle: f64) -> Q {
    let a = normalize(axis);
    let (s, c) = (angle / 2.0).sin_cos();
    [a[0] * s, a[1] * s, a[2] * s, c]
}
/// Shortest rotation taking unit `from` to unit `to`.
fn q_arc(from: V3, to: V3) -> Q {
    let d = dot(from, to);
    if d < -1.0 + 1e-12 {
        // Half turn about any axis perpendicular to `from`.
        let side = if from[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        return q_axis_angle(cross(from, side), core::f64::consts::PI);
    }
    let c = cross(from, to);
    let q = [c[0], c[1], c[2], 1.0 + d];
    let n = dot([q[0], q[1], q[2]], [q[0], q[1], q[2]]) + q[3] * q[3];
    let n = n.sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

// ---------------------------------------------------------------------------------------------
// The designed human (VRM 1.0 frame: faces +Z, left = +X, 1.70 m tall)

/// Finger layout of the left hand, relative to the wrist: hand axis +X, thumb side +Z, palm
/// down (-Y). `(finger, base offset, [segment lengths: base, middle, to tip], [(yaw, pitch) of
/// each segment in degrees])`; yaw turns toward the thumb side (+Z), pitch turns palmar (-Y).
type FingerDesign = (&'static str, V3, [f64; 3], [(f64, f64); 3]);

fn finger_designs() -> [FingerDesign; 5] {
    [
        // Thumb: CMC joint near the wrist on the radial, palmar side; metacarpal 46 mm,
        // proximal 32 mm, distal to the tip 27 mm; angled forward and down, straightening.
        (
            "Thumb",
            [0.022, -0.012, 0.021],
            [0.046, 0.032, 0.027],
            [(38.0, 25.0), (30.0, 20.0), (25.0, 15.0)],
        ),
        // Index .. little: MCP knuckles on a shallow arc; proximal : intermediate : distal
        // (to the tip) after hand anatomy; fingers fanned a few degrees.
        (
            "Index",
            [0.093, -0.004, 0.024],
            [0.0400, 0.0225, 0.0200],
            [(7.0, 0.0); 3],
        ),
        (
            "Middle",
            [0.097, 0.000, 0.004],
            [0.0450, 0.0265, 0.0215],
            [(1.0, 0.0); 3],
        ),
        (
            "Ring",
            [0.090, -0.003, -0.015],
            [0.0415, 0.0258, 0.0210],
            [(-5.0, 0.0); 3],
        ),
        (
            "Little",
            [0.081, -0.009, -0.032],
            [0.0328, 0.0182, 0.0195],
            [(-12.0, 0.0); 3],
        ),
    ]
}

fn segment_dir(yaw_deg: f64, pitch_deg: f64) -> V3 {
    let (y, p) = (yaw_deg.to_radians(), pitch_deg.to_radians());
    [p.cos() * y.cos(), -p.sin(), p.cos() * y.sin()]
}

/// Rest world positions (VRM 1.0 names, VRM 1.0 frame) and fingertips of the designed human.
fn human() -> (Points, Points) {
    let mut bones: Vec<(&'static str, V3)> = vec![
        ("hips", [0.0, 0.960, 0.000]),
        ("spine", [0.0, 1.060, -0.012]),
        ("chest", [0.0, 1.190, -0.015]),
        ("upperChest", [0.0, 1.310, -0.010]),
        ("neck", [0.0, 1.450, -0.020]),
        ("head", [0.0, 1.560, -0.005]),
        ("jaw", [0.0, 1.585, 0.020]),
    ];
    let mut tips = Vec::new();
    for (side, s) in [("left", 1.0), ("right", -1.0)] {
        let m = |p: V3| [p[0] * s, p[1], p[2]];
        let name = |part: &str| -> &'static str {
            HumanBone::from_name(&format!("{side}{part}"))
                .expect("designed bone names are VRM 1.0 names")
                .as_str()
        };
        bones.push((name("Eye"), m([0.031, 1.625, 0.075])));
        bones.push((name("UpperLeg"), m([0.088, 0.905, 0.005])));
        bones.push((name("LowerLeg"), m([0.092, 0.490, 0.010])));
        bones.push((name("Foot"), m([0.095, 0.080, -0.020])));
        bones.push((name("Toes"), m([0.100, 0.015, 0.115])));
        bones.push((name("Shoulder"), m([0.022, 1.400, -0.005])));
        let upper_arm = [0.175, 1.405, -0.025];
        let lower_arm = add(upper_arm, [0.280, 0.0, 0.0]);
        let wrist = add(lower_arm, [0.260, 0.0, 0.0]);
        bones.push((name("UpperArm"), m(upper_arm)));
        bones.push((name("LowerArm"), m(lower_arm)));
        bones.push((name("Hand"), m(wrist)));
        for (finger, base, lengths, dirs) in finger_designs() {
            let segments = if finger == "Thumb" {
                ["Metacarpal", "Proximal", "Distal"]
            } else {
                ["Proximal", "Intermediate", "Distal"]
            };
            let mut p = add(wrist, base);
            for k in 0..3 {
                bones.push((name(&format!("{finger}{}", segments[k])), m(p)));
                p = add(p, mul(segment_dir(dirs[k].0, dirs[k].1), lengths[k]));
            }
            tips.push((name(&format!("{finger}Distal")), m(p)));
        }
    }
    (bones, tips)
}

// ---------------------------------------------------------------------------------------------
// Node tree construction

struct NodeSpec {
    name: String,
    parent: Option<usize>,
    /// World transform: position, rotation, uniform scale.
    pos: V3,
    rot: Q,
    scale: f64,
    /// Bone name as written in the file (0.x thumb names for VRM 0.x).
    bone: Option<String>,
    as_matrix: bool,
}

/// How the node tree around the humanoid bones looks.
struct Layout {
    /// Root node ("Armature") world rotation and uniform scale.
    root_rot: Q,
    root_scale: f64,
    /// Write the root and the helper nodes as `matrix` instead of TRS.
    root_matrix: bool,
    helper_matrix: bool,
    /// VRM 0.x thumb names in the bone map.
    vrm0_names: bool,
}

fn vrm0_bone_name(bone: &str) -> String {
    for side in ["left", "right"] {
        for (v1, v0) in [
            ("ThumbMetacarpal", "ThumbProximal"),
            ("ThumbProximal", "ThumbIntermediate"),
        ] {
            if bone == format!("{side}{v1}") {
                return format!("{side}{v0}");
            }
        }
    }
    bone.to_string()
}

/// Builds the nodes for bones at `bones` (model-frame world positions) with fingertip leaves.
fn build_nodes(
    bones: &[(&'static str, V3)],
    tips: &[(&'static str, V3)],
    layout: &Layout,
) -> Vec<NodeSpec> {
    let pos_of = |name: &str| bones.iter().find(|(n, _)| *n == name).map(|(_, p)| *p);
    let present: Vec<HumanBone> = HumanBone::ALL
        .into_iter()
        .filter(|b| pos_of(b.as_str()).is_some())
        .collect();
    let effective_parent = |b: HumanBone| {
        let mut p = b.parent();
        while let Some(c) = p {
            if present.contains(&c) {
                return Some(c);
            }
            p = c.parent();
        }
        None
    };
    // Where a bone's +Y axis points: its first child (parent-first order), else its fingertip,
    // else straight on from its parent.
    let aim = |b: HumanBone| -> V3 {
        let here = pos_of(b.as_str()).unwrap_or_default();
        let target = present
            .iter()
            .find(|c| effective_parent(**c) == Some(b))
            .and_then(|c| pos_of(c.as_str()))
            .or_else(|| tips.iter().find(|(n, _)| *n == b.as_str()).map(|(_, p)| *p));
        match target {
            Some(t) => normalize(sub(t, here)),
            None => match effective_parent(b).and_then(|p| pos_of(p.as_str())) {
                Some(pp) => normalize(sub(here, pp)),
                None => [0.0, 1.0, 0.0],
            },
        }
    };

    let mut nodes = vec![NodeSpec {
        name: "Armature".into(),
        parent: None,
        pos: [0.0; 3],
        rot: layout.root_rot,
        scale: layout.root_scale,
        bone: None,
        as_matrix: layout.root_matrix,
    }];
    let mut node_of: Vec<(HumanBone, usize)> = Vec::new();
    for (i, &b) in present.iter().enumerate() {
        let name = b.as_str();
        let here = pos_of(name).unwrap_or_default();
        let mut parent = effective_parent(b)
            .and_then(|p| node_of.iter().find(|(q, _)| *q == p).map(|(_, n)| *n))
            .unwrap_or(0);
        // Non-humanoid nodes between humanoid bones, as real rigs have them.
        let helper = if name.ends_with("Shoulder") {
            Some(("ShoulderAdjust", add(here, [0.0, -0.02, 0.01])))
        } else if name.ends_with("Hand") {
            let elbow = effective_parent(b).and_then(|p| pos_of(p.as_str()));
            elbow.map(|e| ("ForearmTwist", mul(add(e, here), 0.5)))
        } else {
            None
        };
        if let Some((kind, p)) = helper {
            nodes.push(NodeSpec {
                name: format!("{name}_{kind}"),
                parent: Some(parent),
                pos: p,
                rot: q_axis_angle([1.0, 2.0, 3.0], 0.7 + 0.5 * i as f64),
                scale: layout.root_scale,
                bone: None,
                as_matrix: layout.helper_matrix,
            });
            parent = nodes.len() - 1;
        }
        let roll = q_axis_angle([0.0, 1.0, 0.0], 0.37 * (i + 1) as f64);
        let file_name = if layout.vrm0_names {
            vrm0_bone_name(name)
        } else {
            name.to_string()
        };
        nodes.push(NodeSpec {
            name: file_name.clone(),
            parent: Some(parent),
            pos: here,
            rot: q_mul(q_arc([0.0, 1.0, 0.0], aim(b)), roll),
            scale: layout.root_scale,
            bone: Some(file_name.clone()),
            as_matrix: false,
        });
        let me = nodes.len() - 1;
        node_of.push((b, me));
        if let Some((_, tip)) = tips.iter().find(|(n, _)| *n == name) {
            nodes.push(NodeSpec {
                name: format!("{file_name}_end"),
                parent: Some(me),
                pos: *tip,
                rot: nodes[me].rot,
                scale: layout.root_scale,
                bone: None,
                as_matrix: false,
            });
        }
    }
    nodes
}

/// Rounds to 1e-9 so the text is stable (and writes -0 as 0).
fn r9(v: f64) -> f64 {
    let r = (v * 1e9).round() / 1e9;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn nums(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|x| json!(r9(*x))).collect())
}

/// glTF `nodes` array (local TRS derived from world transforms) and the root indices.
fn nodes_json(nodes: &[NodeSpec]) -> Vec<Value> {
    let mut out = Vec::with_capacity(nodes.len());
    for (i, n) in nodes.iter().enumerate() {
        let (t, r, s) = match n.parent {
            None => (n.pos, n.rot, n.scale),
            Some(p) => {
                let p = &nodes[p];
                let inv = q_conj(p.rot);
                (
                    mul(q_rotate(inv, sub(n.pos, p.pos)), 1.0 / p.scale),
                    q_mul(inv, n.rot),
                    n.scale / p.scale,
                )
            }
        };
        let mut o = Map::new();
        o.insert("name".into(), json!(n.name));
        let children: Vec<Value> = nodes
            .iter()
            .enumerate()
            .filter(|(_, c)| c.parent == Some(i))
            .map(|(k, _)| json!(k))
            .collect();
        if !children.is_empty() {
            o.insert("children".into(), Value::Array(children));
        }
        if n.as_matrix {
            let cols = [
                mul(q_rotate(r, [1.0, 0.0, 0.0]), s),
                mul(q_rotate(r, [0.0, 1.0, 0.0]), s),
                mul(q_rotate(r, [0.0, 0.0, 1.0]), s),
            ];
            let mut m = Vec::with_capacity(16);
            for c in cols {
                m.extend_from_slice(&c);
                m.push(0.0);
            }
            m.extend_from_slice(&t);
            m.push(1.0);
            o.insert("matrix".into(), nums(&m));
        } else {
            o.insert("translation".into(), nums(&t));
            o.insert("rotation".into(), nums(&r));
            if (s - 1.0).abs() > 1e-12 {
                o.insert("scale".into(), nums(&[s, s, s]));
            }
        }
        out.push(Value::Object(o));
    }
    out
}

/// Sorts object keys recursively so the text does not depend on serde_json's map type.
fn canonical(v: Value) -> Value {
    match v {
        Value::Object(m) => {
            let mut entries: Vec<(String, Value)> = m.into_iter().collect();
            entries.sort_by(|a, b| a.0.cmp(&b.0));
            Value::Object(
                entries
                    .into_iter()
                    .map(|(k, v)| (k, canonical(v)))
                    .collect(),
            )
        }
        Value::Array(a) => Value::Array(a.into_iter().map(canonical).collect()),
        other => other,
    }
}

fn bone_nodes(nodes: &[NodeSpec]) -> impl Iterator<Item = (usize, &str)> {
    nodes
        .iter()
        .enumerate()
        .filter_map(|(i, n)| n.bone.as_deref().map(|b| (i, b)))
}

// ---------------------------------------------------------------------------------------------
// The two avatars

/// VRM 0.x avatar with fingers, facing -Z, 0.x thumb names, 1.56 m (the designed human scaled
/// by 0.92 and turned 180 degrees about +Y), no `upperChest` / `jaw`.
#[must_use]
pub fn vrm0_fingers() -> Fixture {
    const SCALE: f64 = 0.92;
    let turn = |p: V3| [-p[0] * SCALE, p[1] * SCALE, -p[2] * SCALE];
    let (body, tips) = human();
    let bones: Vec<(&'static str, V3)> = body
        .into_iter()
        .filter(|(n, _)| *n != "upperChest" && *n != "jaw")
        .map(|(n, p)| (n, turn(p)))
        .collect();
    let tips: Vec<(&'static str, V3)> = tips.into_iter().map(|(n, p)| (n, turn(p))).collect();
    let layout = Layout {
        root_rot: q_axis_angle([1.0, 0.0, 0.0], -core::f64::consts::FRAC_PI_2),
        root_scale: 0.01,
        root_matrix: true,
        helper_matrix: false,
        vrm0_names: true,
    };
    let nodes = build_nodes(&bones, &tips, &layout);
    let head = bone_nodes(&nodes)
        .find(|(_, b)| *b == "head")
        .map_or(0, |(i, _)| i);
    let human_bones: Vec<Value> = bone_nodes(&nodes)
        .map(|(i, b)| json!({ "bone": b, "node": i, "useDefaultValues": true }))
        .collect();
    let curve = json!({ "curve": [0, 0, 0, 1, 1, 1, 1, 0], "xRange": 90, "yRange": 10 });
    let json = json!({
        "asset": { "version": "2.0", "generator": "handrig tests/support/vrm_fixture.rs" },
        "extensionsUsed": ["VRM"],
        "scene": 0,
        "scenes": [{ "name": "Scene", "nodes": [0] }],
        "nodes": nodes_json(&nodes),
        "extensions": { "VRM": {
            "specVersion": "0.0",
            "exporterVersion": "handrig-vrm-fixture-1",
            "meta": {
                "title": "handrig VRM 0.x fingers fixture",
                "version": "1",
                "author": "handrig tests",
                "contactInformation": "",
                "reference": "",
                "allowedUserName": "Everyone",
                "violentUssageName": "Disallow",
                "sexualUssageName": "Disallow",
                "commercialUssageName": "Allow",
                "otherPermissionUrl": "",
                "licenseName": "CC0",
                "otherLicenseUrl": ""
            },
            "humanoid": {
                "humanBones": human_bones,
                "armStretch": 0.05,
                "legStretch": 0.05,
                "upperArmTwist": 0.5,
                "lowerArmTwist": 0.5,
                "upperLegTwist": 0.5,
                "lowerLegTwist": 0.5,
                "feetSpacing": 0,
                "hasTranslationDoF": false
            },
            "firstPerson": {
                "firstPersonBone": head,
                "firstPersonBoneOffset": { "x": 0, "y": 0.06, "z": 0 },
                "meshAnnotations": [],
                "lookAtTypeName": "Bone",
                "lookAtHorizontalInner": curve,
                "lookAtHorizontalOuter": curve,
                "lookAtVerticalDown": curve,
                "lookAtVerticalUp": curve
            },
            "blendShapeMaster": { "blendShapeGroups": [] },
            "secondaryAnimation": { "boneGroups": [], "colliderGroups": [] },
            "materialProperties": []
        }}
    });
    Fixture {
        file_name: "vrm0-fingers.vrm",
        vrm_version: "0",
        bones,
        tips,
        json: canonical(json),
    }
}

/// VRM 1.0 avatar with human proportions and all 55 bones (see the module docs).
#[must_use]
pub fn human_proportions_vrm1() -> Fixture {
    let (bones, tips) = human();
    let layout = Layout {
        root_rot: [0.0, 0.0, 0.0, 1.0],
        root_scale: 1.0,
        root_matrix: false,
        helper_matrix: true,
        vrm0_names: false,
    };
    let nodes = build_nodes(&bones, &tips, &layout);
    let human_bones: Map<String, Value> = bone_nodes(&nodes)
        .map(|(i, b)| (b.to_string(), json!({ "node": i })))
        .collect();
    let json = json!({
        "asset": { "version": "2.0", "generator": "handrig tests/support/vrm_fixture.rs" },
        "extensionsUsed": ["VRMC_vrm"],
        "scene": 0,
        "scenes": [{ "name": "Scene", "nodes": [0] }],
        "nodes": nodes_json(&nodes),
        "extensions": { "VRMC_vrm": {
            "specVersion": "1.0",
            "meta": {
                "name": "handrig human proportions fixture",
                "version": "1",
                "authors": ["handrig tests"],
                "copyrightInformation": "",
                "licenseUrl": "https://vrm.dev/licenses/1.0/",
                "avatarPermission": "everyone",
                "allowExcessivelyViolentUsage": false,
                "allowExcessivelySexualUsage": false,
                "commercialUsage": "corporation",
                "allowPoliticalOrReligiousUsage": false,
                "allowAntisocialOrHateUsage": false,
                "creditNotation": "unnecessary",
                "allowRedistribution": true,
                "modification": "allowModificationRedistribution"
            },
            "humanoid": { "humanBones": human_bones }
        }}
    });
    Fixture {
        file_name: "human-proportions-vrm1.vrm",
        vrm_version: "1",
        bones,
        tips,
        json: canonical(json),
    }
}

// ---------------------------------------------------------------------------------------------
// GLB packing

/// Packs glTF JSON and an optional BIN chunk into GLB bytes (JSON padded with spaces, BIN
/// with zeros, both to 4 bytes).
#[must_use]
pub fn glb(json: &Value, bin: Option<&[u8]>) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).expect("a JSON value serializes");
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut body = Vec::new();
    body.extend_from_slice(
        &u32::try_from(j.len())
            .expect("JSON under 4 GiB")
            .to_le_bytes(),
    );
    body.extend_from_slice(b"JSON");
    body.extend_from_slice(&j);
    if let Some(b) = bin {
        let mut b = b.to_vec();
        while b.len() % 4 != 0 {
            b.push(0);
        }
        body.extend_from_slice(
            &u32::try_from(b.len())
                .expect("BIN under 4 GiB")
                .to_le_bytes(),
        );
        body.extend_from_slice(b"BIN\0");
        body.extend_from_slice(&b);
    }
    let mut out = Vec::with_capacity(12 + body.len());
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(
        &u32::try_from(12 + body.len())
            .expect("GLB under 4 GiB")
            .to_le_bytes(),
    );
    out.extend_from_slice(&body);
    out
}

/// Reads a well-formed GLB's JSON and BIN chunk (for tests that edit real files); `None` if
/// the bytes are not laid out as [`glb`] writes them.
#[must_use]
pub fn unpack_glb(bytes: &[u8]) -> Option<(Value, Option<Vec<u8>>)> {
    let u32_at = |at: usize| -> Option<usize> {
        Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize)
    };
    if bytes.get(0..4)? != b"glTF" {
        return None;
    }
    let json_len = u32_at(12)?;
    let json = serde_json::from_slice(bytes.get(20..20 + json_len)?).ok()?;
    let bin_at = 20 + json_len;
    let bin = match u32_at(bin_at) {
        Some(len) => Some(bytes.get(bin_at + 8..bin_at + 8 + len)?.to_vec()),
        None => None,
    };
    Some((json, bin))
}
