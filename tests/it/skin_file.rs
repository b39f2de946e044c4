//! The skin read from the file (`vrm::load_skeleton`, `gltf::load_skeleton`: what
//! `HandRig.fromVrm` / `fromGltf` give self-contact), on the generated avatars
//! (`tests/fixtures/avatars/`, every body in VRM 1.0, VRM 0.x, Mixamo and Unreal naming),
//! against sums written here: the vertex positions as stored (the files are in bind pose and
//! their mesh node has no transform, so three's `bindMatrix * v` is `v`), each vertex's bone
//! the nearest bound ancestor of its largest-weight joint. Then the same file re-encoded
//! (strided positions, 16-bit joints, normalized 16-bit weights, no indices) reads the same;
//! a file out of its bind pose gives the mesh where its joints are; broken primitives (bad
//! accessor index, a joint beyond the skin's, sparse accessors, missing weights, lines, an
//! index past the vertices, an external buffer) are skipped and the rig still loads.
//!
//! The three.js side (`restPoseFromVRM`) is compared on the packed package:
//! tests/node/consumer/skin-file.test.mjs.

use crate::support::recordings;
use crate::support::vrm_fixture::{glb, unpack_glb};

use glam::Vec3;
use handrig::humanoid::{gltf, vrm};
use handrig::{HumanBone, Rig, RigOptions, Skeleton, SkinMesh};
use serde_json::{json, Value};

const BODIES: [&str; 3] = ["woman", "man", "child"];
const KINDS: [&str; 4] = ["vrm1.vrm", "vrm0.vrm", "mixamo.glb", "unreal.glb"];

fn avatar(name: &str) -> Vec<u8> {
    std::fs::read(recordings::path(&format!("tests/fixtures/avatars/{name}")))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The skeleton as `fromVrm` (a `.vrm`) or `fromGltf` (a `.glb`) reads it.
fn load(name: &str, bytes: &[u8]) -> Skeleton {
    if name.ends_with(".vrm") {
        vrm::load_skeleton(bytes).unwrap_or_else(|e| panic!("{name}: {e}"))
    } else {
        gltf::load_skeleton(bytes, &[])
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .0
    }
}

fn index(v: &Value) -> usize {
    v.as_u64().expect("an index") as usize
}

/// Accessor `i`'s elements as f32 (normalized integers in 0..1), `width` per element.
fn read_accessor(json: &Value, bin: &[u8], i: usize) -> Vec<Vec<f32>> {
    let a = &json["accessors"][i];
    let v = &json["bufferViews"][index(&a["bufferView"])];
    let width = match a["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT4" => 16,
        t => panic!("type {t}"),
    };
    let (size, normalized) = (
        match a["componentType"].as_u64().unwrap() {
            5121 => 1,
            5123 => 2,
            _ => 4,
        },
        a["normalized"].as_bool().unwrap_or(false),
    );
    let stride = v["byteStride"]
        .as_u64()
        .map_or(size * width, |s| s as usize);
    let start = v["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    (0..index(&a["count"]))
        .map(|e| {
            (0..width)
                .map(|k| {
                    let at = start + e * stride + k * size;
                    let b = &bin[at..at + size];
                    match (a["componentType"].as_u64().unwrap(), normalized) {
                        (5126, _) => f32::from_le_bytes(b.try_into().unwrap()),
                        (5121, false) => f32::from(b[0]),
                        (5121, true) => f32::from(b[0]) / 255.0,
                        (5123, false) => f32::from(u16::from_le_bytes(b.try_into().unwrap())),
                        (5123, true) => {
                            f32::from(u16::from_le_bytes(b.try_into().unwrap())) / 65535.0
                        }
                        (5125, _) => u32::from_le_bytes(b.try_into().unwrap()) as f32,
                        other => panic!("component {other:?}"),
                    }
                })
                .collect()
        })
        .collect()
}

/// What the file's skin should read as, computed here: per primitive of the skinned mesh node,
/// every vertex (model frame) whose largest-weight joint has a bound humanoid ancestor, with
/// that bone, and the triangles whose corners are all kept.
fn expected(name: &str, bytes: &[u8]) -> SkinMesh {
    let (json, bin) = unpack_glb(bytes).unwrap();
    let bin = bin.unwrap();
    let binding: Vec<(HumanBone, usize)> = gltf::parse(bytes, &[])
        .unwrap()
        .binding
        .iter()
        .map(|(b, n, _)| (*b, *n))
        .collect();
    let nodes = json["nodes"].as_array().unwrap();
    let mut parent = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        for c in n["children"].as_array().into_iter().flatten() {
            parent[index(c)] = Some(i);
        }
    }
    // The nearest bound ancestor (the node itself included), and whether it is an ancestor.
    let humanoid = |start: usize| {
        let mut node = start;
        loop {
            if let Some((b, _)) = binding.iter().find(|(_, n)| *n == node) {
                return Some((*b, node != start));
            }
            node = parent[node]?;
        }
    };
    let mut out = SkinMesh::default();
    let skinned: Vec<&Value> = nodes.iter().filter(|n| n.get("skin").is_some()).collect();
    assert_eq!(skinned.len(), 1, "{name}: one skinned mesh node");
    let node = skinned[0];
    for k in ["translation", "rotation", "scale", "matrix"] {
        assert!(node.get(k).is_none(), "{name}: the mesh node has no {k}");
    }
    let joints = json["skins"][index(&node["skin"])]["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(index)
        .collect::<Vec<_>>();
    // Primitives over the same accessors share their vertices (each vertex once).
    type Read = ((usize, usize, usize), u32, Vec<Option<u32>>);
    let mut read: Vec<Read> = Vec::new();
    for p in json["meshes"][index(&node["mesh"])]["primitives"]
        .as_array()
        .unwrap()
    {
        let at = |k: &str| index(&p["attributes"][k]);
        let pos = read_accessor(&json, &bin, at("POSITION"));
        let key = (at("POSITION"), at("JOINTS_0"), at("WEIGHTS_0"));
        if !read.iter().any(|(k, ..)| *k == key) {
            let ji = read_accessor(&json, &bin, at("JOINTS_0"));
            let wi = read_accessor(&json, &bin, at("WEIGHTS_0"));
            let base = out.positions.len() as u32;
            let mut keep = Vec::new();
            for ((v, j), w) in pos.iter().zip(&ji).zip(&wi) {
                let best = (0..4).fold(0, |b, k| if w[k] > w[b] { k } else { b });
                match humanoid(joints[j[best] as usize]) {
                    Some((bone, hanging)) => {
                        keep.push(Some(out.positions.len() as u32 - base));
                        out.positions.push(Vec3::new(v[0], v[1], v[2]));
                        out.bones.push(bone);
                        out.hanging.push(hanging);
                    }
                    None => keep.push(None),
                }
            }
            read.push((key, base, keep));
        }
        let (_, base, keep) = read.iter().find(|(k, ..)| *k == key).unwrap();
        let (base, keep) = (*base, keep.clone());
        let corners: Vec<usize> = match p.get("indices") {
            Some(i) => read_accessor(&json, &bin, index(i))
                .iter()
                .map(|e| e[0] as usize)
                .collect(),
            None => (0..pos.len()).collect(),
        };
        for t in corners.chunks_exact(3) {
            if let (Some(a), Some(b), Some(c)) = (keep[t[0]], keep[t[1]], keep[t[2]]) {
                out.triangles.push([base + a, base + b, base + c]);
            }
        }
    }
    out
}

/// The skeleton's skin back in the model's frame.
fn skin_in_model_frame(s: &Skeleton) -> SkinMesh {
    let mut skin = s.skin().expect("a skin").clone();
    for p in &mut skin.positions {
        *p = s.version().position_to_internal(*p);
    }
    skin
}

/// Largest distance between the two skins' vertices (same count asserted), meters.
fn largest_gap(a: &SkinMesh, b: &SkinMesh, what: &str) -> f32 {
    assert_eq!(a.positions.len(), b.positions.len(), "{what}: vertices");
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f32::max)
}

#[test]
fn generated_avatars_skin_is_the_stored_mesh_with_its_bones() {
    for body in BODIES {
        for kind in KINDS {
            let name = format!("{body}-{kind}");
            let bytes = avatar(&name);
            let got = skin_in_model_frame(&load(&name, &bytes));
            let want = expected(&name, &bytes);
            // Two primitives (body, eyes) over one vertex buffer: 13,524 vertices read once,
            // and every vertex has a humanoid bone (the rig's root joint carries no weight).
            assert_eq!(got.positions.len(), 13_524, "{name}");
            let gap = largest_gap(&got, &want, &name);
            assert!(gap < 2e-6, "{name}: a vertex {gap} m from the stored one");
            assert!(got.bones == want.bones, "{name}: bones differ");
            assert!(got.hanging == want.hanging, "{name}: hanging flags differ");
            assert!(got.triangles == want.triangles, "{name}: triangles differ");
            assert_eq!(got.triangles.len(), 26_756 + 280, "{name}");
            // Skin on the head and on both hands (what self-contact needs).
            for b in [
                HumanBone::Head,
                HumanBone::LeftHand,
                HumanBone::RightIndexDistal,
            ] {
                assert!(got.bones.contains(&b), "{name}: no {b} skin");
            }
        }
    }
}

/// Appends `data` to the BIN chunk (4-byte aligned) as a new buffer view; its index.
fn push_view(json: &mut Value, bin: &mut Vec<u8>, data: &[u8], stride: Option<usize>) -> usize {
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let views = json["bufferViews"].as_array_mut().unwrap();
    let mut v = json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": data.len()});
    if let Some(s) = stride {
        v["byteStride"] = json!(s);
    }
    views.push(v);
    let view = views.len() - 1;
    bin.extend_from_slice(data);
    json["buffers"][0]["byteLength"] = json!(bin.len());
    view
}

fn push_accessor(json: &mut Value, a: Value) -> usize {
    let list = json["accessors"].as_array_mut().unwrap();
    list.push(a);
    list.len() - 1
}

#[test]
fn re_encoded_attributes_read_the_same() {
    let name = "man-vrm1.vrm";
    let bytes = avatar(name);
    let reference = skin_in_model_frame(&load(name, &bytes));
    let (mut json, bin) = unpack_glb(&bytes).unwrap();
    let mut bin = bin.unwrap();
    let prim = json["meshes"][0]["primitives"][0].clone();
    let at = |k: &str| index(&prim["attributes"][k]);
    let pos = read_accessor(&json, &bin, at("POSITION"));
    let ji = read_accessor(&json, &bin, at("JOINTS_0"));
    let wi = read_accessor(&json, &bin, at("WEIGHTS_0"));
    let n = pos.len();
    // Positions interleaved with 4 junk bytes (stride 16), joints as u16, weights as
    // normalized u16 (rounded so the largest stays the largest).
    let mut p16 = Vec::new();
    for v in &pos {
        for x in v {
            p16.extend_from_slice(&x.to_le_bytes());
        }
        p16.extend_from_slice(&[0xAB; 4]);
    }
    let mut j16 = Vec::new();
    for j in &ji {
        for x in j {
            j16.extend_from_slice(&(*x as u16).to_le_bytes());
        }
    }
    let mut w16 = Vec::new();
    for w in &wi {
        for x in w {
            w16.extend_from_slice(&((x * 65535.0).round() as u16).to_le_bytes());
        }
    }
    let vp = push_view(&mut json, &mut bin, &p16, Some(16));
    let vj = push_view(&mut json, &mut bin, &j16, None);
    let vw = push_view(&mut json, &mut bin, &w16, None);
    let ap = push_accessor(
        &mut json,
        json!({"bufferView": vp, "componentType": 5126, "count": n, "type": "VEC3"}),
    );
    let aj = push_accessor(
        &mut json,
        json!({"bufferView": vj, "componentType": 5123, "count": n, "type": "VEC4"}),
    );
    let aw = push_accessor(
        &mut json,
        json!({"bufferView": vw, "componentType": 5123, "normalized": true, "count": n,
               "type": "VEC4"}),
    );
    // Primitive 1 replaced by primitive 0's triangles, not indexed: one vertex per corner.
    let indices = read_accessor(&json, &bin, index(&prim["indices"]));
    let mut flat_p = Vec::new();
    let mut flat_j = Vec::new();
    let mut flat_w = Vec::new();
    for i in &indices {
        let i = i[0] as usize;
        flat_p.extend_from_slice(&p16[16 * i..16 * i + 12]);
        flat_j.extend_from_slice(&j16[8 * i..8 * i + 8]);
        flat_w.extend_from_slice(&w16[8 * i..8 * i + 8]);
    }
    let m = indices.len();
    let fp = push_view(&mut json, &mut bin, &flat_p, None);
    let fj = push_view(&mut json, &mut bin, &flat_j, None);
    let fw = push_view(&mut json, &mut bin, &flat_w, None);
    let afp = push_accessor(
        &mut json,
        json!({"bufferView": fp, "componentType": 5126, "count": m, "type": "VEC3"}),
    );
    let afj = push_accessor(
        &mut json,
        json!({"bufferView": fj, "componentType": 5123, "count": m, "type": "VEC4"}),
    );
    let afw = push_accessor(
        &mut json,
        json!({"bufferView": fw, "componentType": 5123, "normalized": true, "count": m,
               "type": "VEC4"}),
    );
    let p0 = &mut json["meshes"][0]["primitives"][0]["attributes"];
    p0["POSITION"] = json!(ap);
    p0["JOINTS_0"] = json!(aj);
    p0["WEIGHTS_0"] = json!(aw);
    let p1 = &mut json["meshes"][0]["primitives"][1];
    p1["attributes"]["POSITION"] = json!(afp);
    p1["attributes"]["JOINTS_0"] = json!(afj);
    p1["attributes"]["WEIGHTS_0"] = json!(afw);
    p1.as_object_mut().unwrap().remove("indices");
    // The mouth's primitive (the faces across the lips' slit, over primitive 0's vertices)
    // left out: here the body and the flat primitive are compared.
    json["meshes"][0]["primitives"]
        .as_array_mut()
        .unwrap()
        .truncate(2);
    let edited = glb(&json, Some(&bin));
    let got = skin_in_model_frame(&load(name, &edited));
    // Primitive 0: the same vertices (to rounding: the weights are not the same numbers),
    // bones and triangles.
    let gap = (0..n)
        .map(|i| got.positions[i].distance(reference.positions[i]))
        .fold(0.0, f32::max);
    assert!(gap < 1e-6, "a vertex moved {gap} m");
    let differ = (0..n)
        .filter(|&i| got.bones[i] != reference.bones[i])
        .count();
    assert_eq!(differ, 0, "vertices whose bone changed");
    // The reference's first triangles are primitive 0's (both primitives share its n vertices).
    let first: Vec<_> = reference.triangles[..m / 3].iter().collect();
    assert_eq!(
        got.triangles[..first.len()].iter().collect::<Vec<_>>(),
        first
    );
    // Primitive 1: one vertex per corner, one triangle per three.
    assert_eq!(got.positions.len(), n + m);
    assert_eq!(got.triangles.len(), first.len() + m / 3);
    for (k, i) in indices.iter().enumerate() {
        let i = i[0] as usize;
        let gap = got.positions[n + k].distance(reference.positions[i]);
        assert!(gap < 1e-6, "corner {k}: {gap} m");
        assert_eq!(got.bones[n + k], reference.bones[i], "corner {k}");
    }
}

#[test]
fn a_file_out_of_its_bind_pose_gives_the_mesh_where_its_joints_are() {
    // The left upper arm's node turned 90 degrees about +Z (arm down): its skin turns with it
    // about the joint; the head's stays. The rest positions of the bones turn too.
    let name = "woman-vrm1.vrm";
    let bytes = avatar(name);
    let reference = skin_in_model_frame(&load(name, &bytes));
    let (mut json, bin) = unpack_glb(&bytes).unwrap();
    let arm = gltf::parse(&bytes, &[])
        .unwrap()
        .binding
        .iter()
        .find(|(b, _, _)| *b == HumanBone::LeftUpperArm)
        .unwrap()
        .1;
    let h = std::f32::consts::FRAC_PI_4;
    json["nodes"][arm]["rotation"] = json!([0.0, 0.0, -h.sin(), h.cos()]);
    let s = load(name, &glb(&json, bin.as_deref()));
    let got = skin_in_model_frame(&s);
    let shoulder = s.rest_world(HumanBone::LeftUpperArm).unwrap();
    let turn = glam::Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
    let (mut arm_vertices, mut worst_arm, mut worst_head) = (0, 0.0f32, 0.0f32);
    for ((p, q), b) in got
        .positions
        .iter()
        .zip(&reference.positions)
        .zip(&got.bones)
    {
        if *b == HumanBone::LeftLowerArm {
            // Entirely weighted below the turned joint? Only those move rigidly; the elbow's
            // skin is blended with the upper arm's, turned the same.
            arm_vertices += 1;
            worst_arm = worst_arm.max(p.distance(shoulder + turn * (*q - shoulder)));
        }
        if *b == HumanBone::Head {
            worst_head = worst_head.max(p.distance(*q));
        }
    }
    assert!(arm_vertices > 100, "{arm_vertices}");
    assert!(
        worst_arm < 1e-4,
        "lower arm skin {worst_arm} m off the turned arm"
    );
    assert!(worst_head < 1e-6, "head skin moved {worst_head} m");
    // The hand's rest position turned: below the shoulder now.
    let hand = s.rest_world(HumanBone::LeftHand).unwrap();
    assert!(hand.y < shoulder.y - 0.3, "{hand} {shoulder}");
}

/// Triangles of the third primitive (the faces across the lips' slit, material `mouth`, over
/// the body's vertices), 0 when the file has none.
fn mouth_triangles(json: &Value) -> usize {
    json["meshes"][0]["primitives"].get(2).map_or(0, |p| {
        json["accessors"][index(&p["indices"])]["count"]
            .as_u64()
            .unwrap() as usize
            / 3
    })
}

/// The woman VRM 1.0 with `edit` applied to its JSON and BIN chunk.
fn broken(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Vec<u8> {
    let (mut json, bin) = unpack_glb(&avatar("woman-vrm1.vrm")).unwrap();
    let mut bin = bin.unwrap();
    edit(&mut json, &mut bin);
    glb(&json, Some(&bin))
}

#[test]
fn broken_primitives_are_skipped_and_the_rig_still_loads() {
    let whole = skin_in_model_frame(&load("woman-vrm1.vrm", &avatar("woman-vrm1.vrm")));
    let n = 13_524;
    let mouth = mouth_triangles(&unpack_glb(&avatar("woman-vrm1.vrm")).unwrap().0);
    assert!(mouth > 0, "the woman has the mouth's primitive");
    // The two primitives (body, eyes) share one vertex buffer, read once: with either one
    // read, the vertices are the whole skin's; the triangles tell which.
    let one_primitive =
        |s: &SkinMesh| s.positions[..] == whole.positions[..] && s.bones[..] == whole.bones[..];
    type Edit = Box<dyn Fn(&mut Value, &mut Vec<u8>)>;
    let body_broken: Vec<(&str, Edit)> = vec![
        (
            "POSITION accessor index out of range",
            Box::new(|j, _| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99)),
        ),
        (
            "POSITION not an index",
            Box::new(|j, _| {
                j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!("zero")
            }),
        ),
        (
            "WEIGHTS_0 missing",
            Box::new(|j, _| {
                j["meshes"][0]["primitives"][0]["attributes"]
                    .as_object_mut()
                    .unwrap()
                    .remove("WEIGHTS_0");
            }),
        ),
        (
            "lines (mode 1)",
            Box::new(|j, _| j["meshes"][0]["primitives"][0]["mode"] = json!(1)),
        ),
        (
            "a joint beyond the skin's joints",
            Box::new(|j, bin| {
                // Primitive 0's joints: a copy with vertex 7's weighted joints set to 200.
                let a = index(&j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"]);
                let v = &j["bufferViews"][index(&j["accessors"][a]["bufferView"])];
                let (o, l) = (index(&v["byteOffset"]), index(&v["byteLength"]));
                let mut data = bin[o..o + l].to_vec();
                data[28..32].copy_from_slice(&[200; 4]);
                let view = push_view(j, bin, &data, None);
                let mut acc = j["accessors"][a].clone();
                acc["bufferView"] = json!(view);
                let acc = push_accessor(j, acc);
                j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(acc);
            }),
        ),
        (
            "an index past the vertices",
            Box::new(|j, bin| {
                let a = index(&j["meshes"][0]["primitives"][0]["indices"]);
                let v = &j["bufferViews"][index(&j["accessors"][a]["bufferView"])];
                let o = index(&v["byteOffset"])
                    + j["accessors"][a]["byteOffset"].as_u64().unwrap_or(0) as usize;
                bin[o + 10..o + 12].copy_from_slice(&60_000u16.to_le_bytes());
            }),
        ),
        (
            "sparse positions",
            Box::new(|j, _| {
                let a = index(&j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]);
                let mut acc = j["accessors"][a].clone();
                acc["sparse"] = json!({"count": 1, "indices": {"bufferView": 0,
                    "componentType": 5123}, "values": {"bufferView": 0}});
                let acc = push_accessor(j, acc);
                j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(acc);
            }),
        ),
        (
            "positions past the end of their view",
            Box::new(|j, _| {
                let a = index(&j["meshes"][0]["primitives"][0]["attributes"]["POSITION"]);
                let mut acc = j["accessors"][a].clone();
                acc["byteOffset"] = json!(12);
                let acc = push_accessor(j, acc);
                j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(acc);
            }),
        ),
    ];
    for (what, edit) in body_broken {
        // The body's primitive broken: only the eyes' (over all the vertices) stays.
        let s = load("woman-vrm1.vrm", &broken(&*edit));
        let skin = skin_in_model_frame(&s);
        assert!(
            one_primitive(&skin),
            "{what}: {} vertices",
            skin.positions.len()
        );
        assert_eq!(
            skin.triangles.len(),
            280 + mouth,
            "{what}: the eyes' and the mouth's triangles"
        );
        Rig::new(s, RigOptions::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
    }
    // Both broken, or the skin, the view or the buffer: no skin, the bones still load.
    let everything: Vec<(&str, Edit)> = vec![
        (
            "the skin's joints out of range",
            Box::new(|j, _| j["skins"][0]["joints"][3] = json!(100_000)),
        ),
        (
            "inverse bind matrices of the wrong type",
            Box::new(|j, _| {
                let a = index(&j["skins"][0]["inverseBindMatrices"]);
                j["accessors"][a]["type"] = json!("VEC4");
            }),
        ),
        (
            "an external buffer",
            Box::new(|j, _| j["buffers"][0]["uri"] = json!("body.bin")),
        ),
        (
            "view past the BIN chunk",
            Box::new(|j, _| j["bufferViews"][0]["byteLength"] = json!(1 << 30)),
        ),
        (
            "stride shorter than the element",
            Box::new(|j, _| j["bufferViews"][0]["byteStride"] = json!(8)),
        ),
        (
            "meshes not an array",
            Box::new(|j, _| j["meshes"] = json!({"a": 1})),
        ),
        (
            "skin not an index",
            Box::new(|j, _| {
                for n in j["nodes"].as_array_mut().unwrap() {
                    if n.get("skin").is_some() {
                        n["skin"] = json!(-1);
                    }
                }
            }),
        ),
        ("no BIN chunk data", Box::new(|_, bin| bin.truncate(16))),
    ];
    for (what, edit) in everything {
        let s = load("woman-vrm1.vrm", &broken(&*edit));
        assert!(s.skin().is_none(), "{what}: a skin was read");
        Rig::new(s, RigOptions::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
    }
    // The whole file: both primitives over the same vertices, each vertex once.
    assert_eq!(whole.positions.len(), n);
    assert_eq!(whole.triangles.len(), 26_756 + 280);
}

/// One random edit of the skin's JSON: a field of an accessor, buffer view, primitive or skin
/// set to a random value (index, huge, negative, fraction, string, array).
fn edit_skin_json(json: &mut Value, which: usize, field: usize, value: usize, raw: u64) {
    let values = [
        json!(raw % 8),
        json!(raw % 100_000),
        json!(u64::MAX),
        json!(-1),
        json!(0.5),
        json!("x"),
        json!([1, 2]),
        Value::Null,
    ];
    let v = values[value % values.len()].clone();
    let (list, keys): (&str, &[&str]) = match which % 4 {
        0 => (
            "accessors",
            &[
                "bufferView",
                "byteOffset",
                "componentType",
                "count",
                "type",
                "normalized",
                "sparse",
            ],
        ),
        1 => (
            "bufferViews",
            &["buffer", "byteOffset", "byteLength", "byteStride"],
        ),
        2 => ("skins", &["joints", "inverseBindMatrices"]),
        _ => ("meshes", &["primitives"]),
    };
    let key = keys[field % keys.len()];
    let Some(entries) = json[list].as_array_mut() else {
        return;
    };
    let n = entries.len();
    let entry = &mut entries[(raw as usize) % n];
    if list == "meshes" {
        // A primitive's attribute, indices or mode instead of the whole list.
        let p = &mut entry["primitives"][(raw as usize) % 2];
        let k = ["POSITION", "JOINTS_0", "WEIGHTS_0", "indices", "mode"][field % 5];
        if k == "indices" || k == "mode" {
            p[k] = v;
        } else {
            p["attributes"][k] = v;
        }
    } else {
        entry[key] = v;
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

    /// Random edits of the skin's accessors, views, primitives and skins, and random bytes in
    /// the BIN chunk: the file loads (the bones are intact) and whatever skin is read is sane.
    #[test]
    fn random_skin_edits_never_panic_and_keep_the_rig(
        edits in proptest::collection::vec(
            (0usize..4, 0usize..8, 0usize..8, proptest::prelude::any::<u64>()), 0..4),
        bytes in proptest::collection::vec((0.0f64..1.0, proptest::prelude::any::<u8>()), 0..16),
    ) {
        let (mut json, bin) = unpack_glb(&avatar("child-vrm0.vrm")).unwrap();
        let mut bin = bin.unwrap();
        for (which, field, value, raw) in edits {
            edit_skin_json(&mut json, which, field, value, raw);
        }
        for (at, b) in bytes {
            let last = bin.len() - 1;
            let i = ((bin.len() as f64) * at) as usize;
            bin[i.min(last)] = b;
        }
        let s = vrm::load_skeleton(&glb(&json, Some(&bin))).expect("the bones are intact");
        if let Some(skin) = s.skin() {
            let n = skin.positions.len();
            proptest::prop_assert_eq!(n, skin.bones.len());
            proptest::prop_assert!(skin.positions.iter().all(|p| p.is_finite()));
            proptest::prop_assert!(skin.triangles.iter().flatten().all(|&i| (i as usize) < n));
        }
        Rig::new(s, RigOptions::default()).expect("a rig");
    }
}

#[test]
fn vertices_on_non_humanoid_bones_are_marked_hanging() {
    // The woman with her eyes left out of the humanoid: the eye nodes are then bones of their
    // own under the head, as hair or an accessory would be, and their vertices hang on it.
    let bytes = broken(|json, _| {
        let bones = json["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]
            .as_object_mut()
            .unwrap();
        bones.remove("leftEye");
        bones.remove("rightEye");
    });
    let got = skin_in_model_frame(&load("woman-vrm1.vrm", &bytes));
    let want = expected("woman-vrm1.vrm (no eye bones)", &bytes);
    assert!(got.bones == want.bones, "bones differ");
    assert!(got.hanging == want.hanging, "hanging flags differ");
    let hanging = got.hanging.iter().filter(|h| **h).count();
    // The eyeballs' vertices (280 triangles' worth), all on the head.
    assert!(hanging > 100, "{hanging} vertices hanging");
    assert!(got
        .bones
        .iter()
        .zip(&got.hanging)
        .all(|(b, h)| !h || *b == HumanBone::Head));
    // With the eyes mapped, nothing hangs.
    let whole = skin_in_model_frame(&load("woman-vrm1.vrm", &avatar("woman-vrm1.vrm")));
    assert!(whole.hanging.iter().all(|h| !h));
}
