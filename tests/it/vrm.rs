//! The VRM reader on real files (the shared avatars), on the generated fixtures, and on
//! broken input: every malformed file is an error naming the problem, and nothing panics.
// Native only: reads ../shared from disk (and uses proptest, not built for wasm32).

use crate::support::vrm_fixture;

use glam::Vec3;
use handrig::humanoid::vrm::{load_skeleton, parse, VrmHumanoid};
use handrig::{Error, HumanBone as B, Skeleton, VrmVersion};
use proptest::prelude::*;
use serde_json::{json, Value};

const ROBOT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/avatars/debug-robot.vrm"
);
const ODD_VRM0: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/avatars/odd-armature-vrm0.vrm"
);

fn read(path: &str) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e} (shared/ must be beside the repo)"))
}

fn pos(h: &VrmHumanoid, bone: B) -> Vec3 {
    h.bones
        .iter()
        .find(|(b, _)| *b == bone)
        .map(|(_, p)| *p)
        .unwrap_or_else(|| panic!("{bone} missing"))
}

fn assert_near(got: Vec3, want: [f32; 3], what: &str) {
    let want = Vec3::from_array(want);
    assert!(
        (got - want).abs().max_element() < 1e-5,
        "{what}: got {got}, want {want}"
    );
}

fn vrm_message(r: Result<VrmHumanoid, Error>) -> String {
    match r {
        Err(Error::Vrm(m)) => m,
        other => panic!("expected a vrm error, got {other:?}"),
    }
}

/// The real file's JSON with `edit` applied, repacked with its BIN chunk.
fn edited(path: &str, edit: impl FnOnce(&mut Value)) -> Vec<u8> {
    let (mut json, bin) = vrm_fixture::unpack_glb(&read(path)).expect("a well-formed GLB");
    edit(&mut json);
    vrm_fixture::glb(&json, bin.as_deref())
}

// ---------------------------------------------------------------------------------------------
// debug-robot.vrm (VRM 1.0, Blender export)

#[test]
fn robot_bones_version_and_missing_optionals() {
    let h = parse(&read(ROBOT)).unwrap();
    assert_eq!(h.version, VrmVersion::V1);
    assert_eq!(h.bones.len(), 53);
    let missing: Vec<B> = B::ALL
        .into_iter()
        .filter(|b| h.bones.iter().all(|(x, _)| x != b))
        .collect();
    assert_eq!(missing, [B::UpperChest, B::Jaw]);
    // Parent-first order, as documented.
    assert!(h.bones.windows(2).all(|w| w[0].0.index() < w[1].0.index()));
}

#[test]
fn robot_positions_follow_the_node_tree() {
    let h = parse(&read(ROBOT)).unwrap();
    // Spine chain: translations only, (0, 0.75, 0) for hips then +0.25, +0.125, +0.3125,
    // +0.125 along +Y under an identity root.
    assert_near(pos(&h, B::Hips), [0.0, 0.75, 0.0], "hips");
    assert_near(pos(&h, B::Spine), [0.0, 1.0, 0.0], "spine");
    assert_near(pos(&h, B::Chest), [0.0, 1.125, 0.0], "chest");
    assert_near(pos(&h, B::Neck), [0.0, 1.4375, 0.0], "neck");
    assert_near(pos(&h, B::Head), [0.0, 1.5625, 0.0], "head");
    // shoulder.L sits at chest + (0.025, 0.375, 0) and is rotated by (-0.5, -0.5, -0.5, 0.5),
    // a 120 degree turn that maps its local +Y to world +X (Blender bone roll): the arm chain,
    // written as +Y translations of 0.1 and 0.25, runs along +X. Ignoring that rotation
    // would put the upper arm at (0.025, 1.6, 0).
    assert_near(pos(&h, B::LeftShoulder), [0.025, 1.5, 0.0], "leftShoulder");
    assert_near(pos(&h, B::LeftUpperArm), [0.125, 1.5, 0.0], "leftUpperArm");
    assert_near(pos(&h, B::LeftLowerArm), [0.375, 1.5, 0.0], "leftLowerArm");
    assert_near(pos(&h, B::LeftHand), [0.625, 1.5, 0.0], "leftHand");
    // The same rotation maps local +X to world +Z: thumb_proximal.L at local (0.05, 0.05, 0)
    // lands in front of the hand, index_proximal.L at local (0.025, 0.125, 0) too.
    assert_near(
        pos(&h, B::LeftThumbMetacarpal),
        [0.675, 1.5, 0.05],
        "leftThumbMetacarpal",
    );
    assert_near(
        pos(&h, B::LeftIndexProximal),
        [0.75, 1.5, 0.025],
        "leftIndexProximal",
    );
    // upper_leg.L is turned 180 degrees about X: its +Y translations go down.
    assert_near(pos(&h, B::LeftUpperLeg), [0.25, 1.0, 0.0], "leftUpperLeg");
    assert_near(pos(&h, B::LeftLowerLeg), [0.25, 0.5, 0.0], "leftLowerLeg");
    assert_near(pos(&h, B::LeftFoot), [0.25, 0.0625, 0.0], "leftFoot");
    // The robot is left-right symmetric: every right bone mirrors its left bone in x.
    for &(b, p) in &h.bones {
        if b.side() == Some(handrig::Side::Right) {
            let l = pos(&h, b.mirrored());
            assert_near(p, [-l.x, l.y, l.z], b.as_str());
        }
    }
}

#[test]
fn robot_skeleton_effective_parents() {
    let s = load_skeleton(&read(ROBOT)).unwrap();
    assert_eq!(s.version(), VrmVersion::V1);
    assert_eq!(s.bones().count(), 53);
    // No upperChest: shoulders and neck hang off the chest, as in three-vrm's normalized rig.
    assert_eq!(s.parent(B::LeftShoulder), Some(B::Chest));
    assert_eq!(s.parent(B::RightShoulder), Some(B::Chest));
    assert_eq!(s.parent(B::Neck), Some(B::Chest));
    assert_eq!(s.parent(B::LeftThumbMetacarpal), Some(B::LeftHand));
    assert_eq!(s.parent(B::LeftIndexDistal), Some(B::LeftIndexIntermediate));
    assert!(!s.has(B::Jaw));
    // VRM 1.0: the internal frame is the model frame.
    assert_near(
        s.rest_world(B::LeftHand).unwrap(),
        [0.625, 1.5, 0.0],
        "leftHand",
    );
    assert!(s
        .rest_local(B::LeftUpperArm)
        .abs_diff_eq(Vec3::new(0.1, 0.0, 0.0), 1e-6));
}

// ---------------------------------------------------------------------------------------------
// odd-armature-vrm0.vrm (VRM 0.x, 17 bones, armature off the T-pose)

#[test]
fn odd_vrm0_positions_are_sums_of_node_translations() {
    let bytes = read(ODD_VRM0);
    let h = parse(&bytes).unwrap();
    assert_eq!(h.version, VrmVersion::V0);
    assert_eq!(h.bones.len(), 17);
    assert!(h.bones.iter().all(|(b, _)| !b.is_finger()));
    // This file's humanoid nodes and their ancestors carry translations only, so a bone's
    // world position is the sum of translations up its node chain. Read the tree from the
    // JSON independently of the reader and check every bone.
    let (json, _) = vrm_fixture::unpack_glb(&bytes).unwrap();
    let nodes = json["nodes"].as_array().unwrap();
    let parent_of = |i: usize| {
        nodes.iter().position(|n| {
            n["children"]
                .as_array()
                .is_some_and(|c| c.iter().any(|c| c.as_u64() == Some(i as u64)))
        })
    };
    for entry in json["extensions"]["VRM"]["humanoid"]["humanBones"]
        .as_array()
        .unwrap()
    {
        let name = entry["bone"].as_str().unwrap();
        let mut node = Some(entry["node"].as_u64().unwrap() as usize);
        let mut sum = [0.0f64; 3];
        while let Some(i) = node {
            let n = &nodes[i];
            assert!(n.get("rotation").is_none() && n.get("matrix").is_none());
            assert!(n.get("scale").is_none());
            if let Some(t) = n["translation"].as_array() {
                for (s, v) in sum.iter_mut().zip(t) {
                    *s += v.as_f64().unwrap();
                }
            }
            node = parent_of(i);
        }
        let bone = B::from_vrm0_name(name).unwrap();
        assert_near(pos(&h, bone), sum.map(|v| v as f32), name);
    }
    // hips is a scene root: its position is its own translation.
    assert_near(
        pos(&h, B::Hips),
        [0.282_380_07, -0.279_608_85, -0.565_592_17],
        "hips",
    );
}

#[test]
fn odd_vrm0_skeleton_turns_to_face_plus_z() {
    let bytes = read(ODD_VRM0);
    let h = parse(&bytes).unwrap();
    let s: Skeleton = load_skeleton(&bytes).unwrap();
    assert_eq!(s.version(), VrmVersion::V0);
    assert_eq!(s.bones().count(), 17);
    // Missing shoulders, upperChest: arms hang off the chest; no fingers below the hands.
    assert_eq!(s.parent(B::LeftUpperArm), Some(B::Chest));
    assert_eq!(s.parent(B::Neck), Some(B::Chest));
    assert_eq!(s.parent(B::Head), Some(B::Neck));
    assert!(!s.has(B::LeftThumbMetacarpal));
    // Model frame -> internal frame: 180 degrees about +Y.
    let m = pos(&h, B::LeftHand);
    assert_eq!(s.rest_world(B::LeftHand), Some(Vec3::new(-m.x, m.y, -m.z)));
}

// ---------------------------------------------------------------------------------------------
// Generated fixtures

fn fixture_path(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn committed_fixtures_equal_generated_bytes() {
    for f in vrm_fixture::all() {
        let committed = std::fs::read(fixture_path(f.file_name)).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run `cargo run --example gen_fixtures`",
                f.file_name
            )
        });
        assert!(
            committed == f.glb(),
            "{} differs from the generator's output; run `cargo run --example gen_fixtures`",
            f.file_name
        );
    }
}

#[test]
fn fixtures_parse_to_the_designed_skeleton() {
    for f in vrm_fixture::all() {
        let h = parse(&std::fs::read(fixture_path(f.file_name)).unwrap()).unwrap();
        let version = if f.vrm_version == "0" {
            VrmVersion::V0
        } else {
            VrmVersion::V1
        };
        assert_eq!(h.version, version, "{}", f.file_name);
        assert_eq!(h.bones.len(), f.bones.len(), "{}", f.file_name);
        for &(name, want) in &f.bones {
            let bone = B::from_name(name).unwrap();
            let want = want.map(|v| v as f32);
            assert_near(pos(&h, bone), want, &format!("{} {name}", f.file_name));
        }
        load_skeleton(&f.glb()).unwrap();
    }
}

#[test]
fn vrm0_fixture_thumbs_are_renamed_and_it_faces_minus_z() {
    let f = vrm_fixture::vrm0_fingers();
    assert_eq!(f.bones.len(), 53);
    // The file names the thumb the 0.x way...
    let map = f.json["extensions"]["VRM"]["humanoid"]["humanBones"]
        .as_array()
        .unwrap();
    let node_of = |bone: &str| {
        map.iter()
            .find(|e| e["bone"] == bone)
            .and_then(|e| e["node"].as_u64())
    };
    assert!(node_of("leftThumbIntermediate").is_some());
    assert!(node_of("leftThumbMetacarpal").is_none());
    let h = parse(&f.glb()).unwrap();
    // ...and the reader maps 0.x thumbProximal (the metacarpal joint) to thumbMetacarpal:
    // the bone at the node the file calls leftThumbProximal.
    let metacarpal_node = node_of("leftThumbProximal").unwrap() as usize;
    assert_eq!(
        f.json["nodes"][metacarpal_node]["name"], "leftThumbProximal",
        "fixture node naming"
    );
    assert_near(
        pos(&h, B::LeftThumbMetacarpal),
        f.bone("leftThumbMetacarpal").unwrap().map(|v| v as f32),
        "leftThumbMetacarpal",
    );
    assert!(!h.bones.iter().any(|(b, _)| *b == B::UpperChest));
    // Facing -Z: the model's left hand is at -X, thumbs point forward = -Z.
    let hand = pos(&h, B::LeftHand);
    assert!(hand.x < -0.5, "{hand}");
    assert!(pos(&h, B::LeftThumbDistal).z < hand.z - 0.03);
    // Internally it faces +Z with the left hand at +X, like a VRM 1.0 model.
    let s = load_skeleton(&f.glb()).unwrap();
    assert!(s.rest_world(B::LeftHand).unwrap().x > 0.5);
    assert_eq!(s.parent(B::LeftShoulder), Some(B::Chest));
    assert_eq!(s.parent(B::LeftThumbMetacarpal), Some(B::LeftHand));
}

#[test]
fn vrm1_fixture_has_human_proportions() {
    let f = vrm_fixture::human_proportions_vrm1();
    let h = parse(&f.glb()).unwrap();
    assert_eq!(h.bones.len(), 55);
    let d = |a: B, b: B| (pos(&h, a) - pos(&h, b)).length();
    for side in handrig::Side::BOTH {
        let [_, upper, lower, hand] = side.arm();
        assert!((d(upper, lower) - 0.28).abs() < 1e-5);
        assert!((d(lower, hand) - 0.26).abs() < 1e-5);
        let mid_tip = Vec3::from_array(
            f.tip(side.finger(handrig::Finger::Middle)[2].as_str())
                .unwrap()
                .map(|v| v as f32),
        );
        let hand_len = (mid_tip - pos(&h, hand)).length();
        assert!((hand_len - 0.19).abs() < 0.002, "{hand_len}");
        // Proximal phalanx longer than the intermediate, index and little shorter than middle.
        let [p, i, di] = side.finger(handrig::Finger::Middle);
        assert!(d(p, i) > 1.5 * d(i, di));
        let [ip, ii, _] = side.finger(handrig::Finger::Index);
        let [lp, li, _] = side.finger(handrig::Finger::Little);
        assert!(d(ip, ii) < d(p, i) && d(lp, li) < d(ip, ii));
    }
    // Fingers spread: the index and little proximal segments diverge.
    let dir = |a: B, b: B| (pos(&h, b) - pos(&h, a)).normalize();
    let spread = dir(B::LeftIndexProximal, B::LeftIndexIntermediate)
        .angle_between(dir(B::LeftLittleProximal, B::LeftLittleIntermediate));
    assert!(spread.to_degrees() > 15.0 && spread.to_degrees() < 25.0);
    // Thumb angled forward (+Z) and palmar (-Y) from the hand axis.
    let thumb = dir(B::LeftThumbMetacarpal, B::LeftThumbProximal);
    assert!(thumb.z > 0.5 && thumb.y < -0.3, "{thumb}");
    let height = pos(&h, B::Head).y;
    assert!((1.5..1.6).contains(&height));
}

// ---------------------------------------------------------------------------------------------
// Broken input

#[test]
fn every_truncation_is_an_error() {
    for path in [ROBOT, ODD_VRM0] {
        let bytes = read(path);
        let n = bytes.len();
        for len in 0..n {
            let m = vrm_message(parse(&bytes[..len]));
            if len >= 12 {
                assert_eq!(m, format!("truncated: header says {n} bytes, got {len}"));
            } else {
                assert!(
                    m.contains("shorter than the 12-byte GLB header"),
                    "{len}: {m}"
                );
            }
        }
    }
}

#[test]
fn truncation_with_a_consistent_header_is_caught_by_the_chunks() {
    for path in [ROBOT, ODD_VRM0] {
        let bytes = read(path);
        let json_end = 20 + u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let whole = parse(&bytes).unwrap();
        for len in (12..bytes.len()).step_by(4) {
            let mut cut = bytes[..len].to_vec();
            cut[8..12].copy_from_slice(&(len as u32).to_le_bytes());
            let r = parse(&cut);
            if len == json_end {
                // Dropping the whole BIN chunk leaves a valid GLB: the humanoid needs no BIN.
                assert_eq!(r.unwrap(), whole);
            } else {
                let m = vrm_message(r);
                assert!(
                    m.contains("JSON chunk") || m.contains("chunk 1"),
                    "{len}: {m}"
                );
            }
        }
    }
}

#[test]
fn flipped_bytes_are_errors_or_harmless() {
    let bytes = read(ROBOT);
    let whole = parse(&bytes).unwrap();
    let json_end = 20 + u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    // Every header byte, then a stride through the JSON and BIN data (each parse of the
    // 16 KB JSON costs about a millisecond in debug builds).
    let positions = (0..20)
        .chain(20..json_end)
        .filter(|&i| i < 20 || i % 7 == 0 || i + 4 >= json_end)
        .chain(json_end..json_end + 8)
        .chain((json_end + 8..bytes.len()).step_by(11));
    for i in positions {
        let mut b = bytes.clone();
        b[i] ^= 0xFF;
        let r = parse(&b);
        match i {
            0..=3 => assert!(vrm_message(r).starts_with("not a glTF binary (magic")),
            4..=7 => assert!(vrm_message(r).contains("unsupported glTF binary version")),
            8..=11 => assert!(vrm_message(r).contains("bytes, got 18728")),
            12..=15 => assert!(vrm_message(r).contains("JSON chunk")),
            16..=19 => assert!(vrm_message(r).contains("first chunk must be the JSON chunk")),
            // Inside the JSON text: 0xFF-flipped ASCII is never valid UTF-8 JSON.
            _ if i < json_end => assert!(vrm_message(r).contains("JSON")),
            // BIN chunk length: breaks the framing.
            _ if i < json_end + 4 => assert!(vrm_message(r).contains("chunk 1")),
            // BIN chunk type: an unknown chunk type is skipped, as the GLB spec says, and the
            // BIN data is not used for the humanoid.
            _ => assert_eq!(r.unwrap(), whole),
        }
    }
}

#[test]
fn plain_gltf_without_vrm_extension() {
    let b = edited(ROBOT, |j| {
        j.as_object_mut().unwrap().remove("extensions");
        j["extensionsUsed"] = json!(["KHR_materials_unlit"]);
    });
    assert_eq!(
        vrm_message(parse(&b)),
        "no VRMC_vrm or VRM extension: this glTF is not a VRM avatar"
    );
    // The message reaches JS as "vrm: ...".
    assert!(parse(&b)
        .unwrap_err()
        .to_string()
        .starts_with("vrm: no VRMC_vrm"));
}

#[test]
fn bad_node_index_names_the_bone() {
    let b = edited(ROBOT, |j| {
        j["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]["leftHand"]["node"] = json!(999);
    });
    assert_eq!(
        vrm_message(parse(&b)),
        "extensions.VRMC_vrm.humanoid.humanBones.leftHand.node: node 999 out of range \
         (the file has 77 nodes)"
    );
    let b = edited(ROBOT, |j| {
        j["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]["leftHand"]["node"] = json!("24");
    });
    assert_eq!(
        vrm_message(parse(&b)),
        "extensions.VRMC_vrm.humanoid.humanBones.leftHand.node: node index must be a \
         non-negative integer, got \"24\""
    );
}

#[test]
fn cycles_and_two_parents_are_errors() {
    // root (75) made a child of hand.L (24): hand.L -> ... -> hips -> root -> hand.L.
    let b = edited(ROBOT, |j| {
        j["nodes"][24]["children"]
            .as_array_mut()
            .unwrap()
            .push(json!(75));
    });
    assert!(vrm_message(parse(&b)).contains("cycle in the node hierarchy"));
    // hips (73, a child of root 75) also listed under hand.L (24).
    let b = edited(ROBOT, |j| {
        j["nodes"][24]["children"]
            .as_array_mut()
            .unwrap()
            .push(json!(73));
    });
    assert_eq!(
        vrm_message(parse(&b)),
        "node 73 has two parents (nodes 24 and 75)"
    );
    let b = edited(ROBOT, |j| {
        j["nodes"][3]["children"] = json!([2, 500]);
    });
    assert!(vrm_message(parse(&b)).contains("nodes[3].children[1]: node 500 out of range"));
}

#[test]
fn unknown_and_duplicate_bones() {
    let b = edited(ROBOT, |j| {
        j["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]["leftWing"] = json!({"node": 76});
    });
    assert!(vrm_message(parse(&b)).contains("unknown bone name \"leftWing\""));
    let b = edited(ODD_VRM0, |j| {
        j["extensions"]["VRM"]["humanoid"]["humanBones"]
            .as_array_mut()
            .unwrap()
            .push(json!({"bone": "leftHand", "node": 29}));
    });
    let m = vrm_message(parse(&b));
    assert!(m.contains("duplicate bone leftHand"), "{m}");
    // Two bones on one node.
    let b = edited(ROBOT, |j| {
        j["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]["jaw"] = json!({"node": 5});
    });
    assert!(vrm_message(parse(&b)).contains("node 5 is already used by"));
}

#[test]
fn missing_required_bone_is_reported_by_the_skeleton() {
    let b = edited(ROBOT, |j| {
        j["extensions"]["VRMC_vrm"]["humanoid"]["humanBones"]
            .as_object_mut()
            .unwrap()
            .remove("head");
    });
    assert_eq!(parse(&b).unwrap().bones.len(), 52);
    // The message names the file, not `restPose` (issue 15).
    assert_eq!(
        load_skeleton(&b).unwrap_err().to_string(),
        "vrm: humanoid lacks required bone(s) head"
    );
}

/// ../shared/repro/huge-scale-robot.vrm: the robot with a node scale of 1e20. It used to load
/// and then panic in the two-bone solver (bone lengths overflow); now it is refused at load.
#[test]
fn absurd_scale_is_refused_at_load() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/repro/huge-scale-robot.vrm"
    );
    let e = load_skeleton(&read(path)).unwrap_err().to_string();
    assert!(
        e.starts_with("vrm: humanoid bone ") && e.contains("position out of range"),
        "{e}"
    );
    // The same robot scaled to 100 m still loads (a giant, not an overflow).
    let b = edited(ROBOT, |j| {
        j["nodes"][0]["scale"] = json!([50.0, 50.0, 50.0]);
    });
    load_skeleton(&b).expect("a 50x robot is a valid avatar");
}

/// A chain of nodes above the humanoid: deep hierarchies and huge node counts are refused
/// with a clear error instead of seconds of work and hundreds of MB
/// (../shared/repro/deep-chain.cjs used 400,000 nodes).
#[test]
fn deep_and_huge_hierarchies_are_refused() {
    let chain = |extra: usize| {
        edited(ROBOT, |j| {
            let nodes = j["nodes"].as_array_mut().unwrap();
            let n = nodes.len();
            // Every root of the scene goes under a chain of `extra` empty nodes.
            let roots: Vec<usize> = j["scenes"][0]["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_u64().unwrap() as usize)
                .collect();
            let nodes = j["nodes"].as_array_mut().unwrap();
            for k in 0..extra {
                let child: Vec<usize> = if k + 1 < extra {
                    vec![n + k + 1]
                } else {
                    roots.clone()
                };
                nodes.push(json!({ "children": child }));
            }
            j["scenes"][0]["nodes"] = json!([n]);
        })
    };
    load_skeleton(&chain(100)).expect("100 extra levels are fine");
    let e = vrm_message(parse(&chain(handrig::humanoid::document::MAX_DEPTH + 10)));
    assert!(e.contains("levels deep"), "{e}");
    let e = vrm_message(parse(&chain(handrig::humanoid::document::MAX_NODES + 1)));
    assert!(e.contains("more than the 65536"), "{e}");
}

#[test]
fn nodes_of_the_wrong_type_are_named() {
    for nodes in [json!({ "0": {} }), json!("nodes"), json!(3)] {
        let b = edited(ROBOT, |j| j["nodes"] = nodes.clone());
        assert_eq!(vrm_message(parse(&b)), "nodes: must be an array", "{nodes}");
    }
    // A syntax error inside `nodes` is not "must be an array".
    let b = edited(ROBOT, |j| {
        j["nodes"][3]["name"] = json!("12345.678");
    });
    let at = b.windows(11).position(|w| w == b"\"12345.678\"").unwrap();
    let mut broken = b.clone();
    broken[at..at + 11].copy_from_slice(b"[1,,2.3456]");
    let e = vrm_message(parse(&broken));
    assert!(e.starts_with("JSON chunk is not valid JSON"), "{e}");
}

#[test]
fn non_finite_and_malformed_numbers() {
    // A zero-scale matrix on the hips: every bone below has no finite position in three.js
    // either (its decomposition divides by zero).
    let b = edited(ROBOT, |j| {
        let hips = j["nodes"][73].as_object_mut().unwrap();
        hips.remove("translation");
        hips.insert(
            "matrix".into(),
            json!([0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.75, 0, 1]),
        );
    });
    assert!(vrm_message(parse(&b)).contains("is not finite"));
    // Huge but finite values overflowing to infinity in the product.
    let b = edited(ROBOT, |j| {
        j["nodes"][75]["scale"] = json!([1e300, 1e300, 1e300]);
        j["nodes"][73]["translation"] = json!([0, 1e300, 0]);
    });
    assert!(vrm_message(parse(&b)).contains("is not finite"));
    // Finite in f64, too large for the f32 rest pose.
    let b = edited(ROBOT, |j| {
        j["nodes"][73]["translation"] = json!([0, 1e39, 0]);
    });
    assert!(vrm_message(parse(&b)).contains("too large for 32-bit floats"));
    // JSON itself cannot hold NaN or Infinity; an overflowing literal is invalid JSON.
    // Swap a marker number for one of the same length, keeping the chunk lengths valid.
    let b = edited(ROBOT, |j| {
        j["nodes"][73]["translation"] = json!([0, 12345.678, 0])
    });
    let at = b
        .windows(9)
        .position(|w| w == b"12345.678")
        .expect("marker in the JSON text");
    let mut overflow = b.clone();
    overflow[at..at + 9].copy_from_slice(b"9.0e99999");
    assert!(vrm_message(parse(&overflow)).contains("not valid JSON"));
    // Wrong shapes name the node and field.
    let b = edited(ROBOT, |j| j["nodes"][10]["rotation"] = json!([0, 0, 1]));
    assert_eq!(
        vrm_message(parse(&b)),
        "nodes[10].rotation: must be an array of 4 finite numbers"
    );
}

// ---------------------------------------------------------------------------------------------
// Fuzzing: whatever the bytes, the reader returns (never panics), and what it returns is sane.

fn check_sane(r: Result<VrmHumanoid, Error>) {
    if let Ok(h) = r {
        assert!(h.bones.len() <= handrig::BONE_COUNT);
        assert!(h.bones.iter().all(|(_, p)| p.is_finite()));
        assert!(h.bones.windows(2).all(|w| w[0].0.index() < w[1].0.index()));
    }
}

/// The shared avatars and the generated fixtures, read once.
fn sample_files() -> &'static [Vec<u8>; 4] {
    static FILES: std::sync::OnceLock<[Vec<u8>; 4]> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let [a, b] = [
            vrm_fixture::vrm0_fingers(),
            vrm_fixture::human_proportions_vrm1(),
        ]
        .map(|f| f.glb());
        [read(ROBOT), read(ODD_VRM0), a, b]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_truncation_and_corruption_never_panics(
        which in 0usize..4,
        keep in 0.0f64..=1.0,
        fix_header in any::<bool>(),
        edits in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..8),
    ) {
        let mut b = sample_files()[which].clone();
        let len = ((b.len() as f64) * keep) as usize;
        b.truncate(len);
        if fix_header && b.len() >= 12 {
            let n = b.len() as u32;
            b[8..12].copy_from_slice(&n.to_le_bytes());
        }
        for (at, value) in edits {
            if !b.is_empty() {
                let i = ((b.len() as f64) * at) as usize;
                let i = i.min(b.len() - 1);
                b[i] = value;
            }
        }
        check_sane(parse(&b));
        let _ = load_skeleton(&b);
    }

}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn random_rewiring_of_the_node_tree_never_panics(
        which in 0usize..2,
        links in proptest::collection::vec((0usize..90, 0usize..90), 1..6),
        retarget in proptest::collection::vec((0usize..60, 0i64..100), 0..4),
    ) {
        let path = [ROBOT, ODD_VRM0][which];
        let b = edited(path, |j| {
            let n = j["nodes"].as_array().unwrap().len();
            for (parent, child) in links {
                if let Some(node) = j["nodes"].get_mut(parent % n) {
                    let obj = node.as_object_mut().unwrap();
                    let children = obj.entry("children").or_insert_with(|| json!([]));
                    children.as_array_mut().unwrap().push(json!(child));
                }
            }
            let ext = &mut j["extensions"];
            if let Some(map) = ext["VRMC_vrm"]["humanoid"]["humanBones"].as_object_mut() {
                let keys: Vec<String> = map.keys().cloned().collect();
                for (k, node) in &retarget {
                    let key = &keys[k % keys.len()];
                    map[key]["node"] = json!(node);
                }
            }
            if let Some(list) = ext["VRM"]["humanoid"]["humanBones"].as_array_mut() {
                let len = list.len();
                for (k, node) in &retarget {
                    list[k % len]["node"] = json!(node);
                }
            }
        });
        check_sane(parse(&b));
        let _ = load_skeleton(&b);
    }
}

#[test]
fn body_forward_kinematics_matches_the_full_pass_and_leaves_the_fingers() {
    let skeleton = load_skeleton(&read(ROBOT)).expect("robot");
    // Every bone turned a little, differently.
    let local: [glam::Quat; handrig::BONE_COUNT] = core::array::from_fn(|i| {
        glam::Quat::from_axis_angle(Vec3::new(1.0, i as f32, 0.5).normalize(), 0.05 * i as f32)
    });
    let mut full = handrig::WorldPose::default();
    skeleton.forward(&local, &mut full);
    let mut body = handrig::WorldPose::default();
    let marker = Vec3::splat(123.0);
    body.position = [marker; handrig::BONE_COUNT];
    skeleton.forward_body(&local, &mut body);
    let mut fingers = 0;
    for bone in B::ALL {
        if !skeleton.has(bone) {
            continue;
        }
        let i = bone.index();
        if bone.is_finger() {
            fingers += 1;
            assert_eq!(body.position[i], marker, "{bone} was posed");
        } else {
            assert_eq!(body.position[i], full.position[i], "{bone}");
            assert_eq!(body.rotation[i], full.rotation[i], "{bone}");
        }
    }
    assert!(fingers >= 15, "the robot has fingers ({fingers})");
}
