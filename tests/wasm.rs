//! wasm-bindgen tests of the JS bindings, run in Node by `wasm-pack test --node`.
#![cfg(target_arch = "wasm32")]

use handrig::wasm::HandRig;
use js_sys::{Array, Float32Array, Object, Reflect};
use serde::Serialize;
use serde_json::{json, Value};
use wasm_bindgen::prelude::*;
use wasm_bindgen_test::wasm_bindgen_test;

const RECORDING: &str = include_str!("../../shared/data/hands/right-hand-video-mediapipe.json");

fn js(v: &Value) -> JsValue {
    v.serialize(&serde_wasm_bindgen::Serializer::json_compatible())
        .unwrap()
}

fn get(o: &JsValue, k: &str) -> JsValue {
    Reflect::get(o, &JsValue::from_str(k)).unwrap()
}

fn message(e: JsValue) -> String {
    let e: js_sys::Error = e.into();
    String::from(e.message())
}

/// A T-pose avatar facing +Z with a full right hand (fingers along -X).
fn rest_pose(version: &str) -> Value {
    let mut bones = serde_json::Map::new();
    let mut put = |n: &str, p: [f32; 3]| {
        // VRM 0.x models face -Z: the same body turned 180 degrees about +Y.
        let p = if version == "0" {
            [-p[0], p[1], -p[2]]
        } else {
            p
        };
        bones.insert(n.to_string(), json!(p));
    };
    put("hips", [0.0, 1.0, 0.0]);
    put("spine", [0.0, 1.1, 0.0]);
    put("chest", [0.0, 1.25, 0.0]);
    put("neck", [0.0, 1.45, 0.0]);
    put("head", [0.0, 1.55, 0.0]);
    for (s, side) in [(1.0f32, "left"), (-1.0, "right")] {
        put(&format!("{side}UpperLeg"), [0.1 * s, 0.95, 0.0]);
        put(&format!("{side}LowerLeg"), [0.1 * s, 0.5, 0.0]);
        put(&format!("{side}Foot"), [0.1 * s, 0.08, 0.0]);
        put(&format!("{side}Shoulder"), [0.05 * s, 1.4, 0.0]);
        put(&format!("{side}UpperArm"), [0.18 * s, 1.4, 0.0]);
        put(&format!("{side}LowerArm"), [0.46 * s, 1.4, 0.0]);
        put(&format!("{side}Hand"), [0.72 * s, 1.4, 0.0]);
        for (f, z) in [
            ("Index", 0.025f32),
            ("Middle", 0.0),
            ("Ring", -0.02),
            ("Little", -0.04),
        ] {
            put(&format!("{side}{f}Proximal"), [0.81 * s, 1.4, z]);
            put(&format!("{side}{f}Intermediate"), [0.855 * s, 1.4, z]);
            put(&format!("{side}{f}Distal"), [0.88 * s, 1.4, z]);
        }
        put(&format!("{side}ThumbMetacarpal"), [0.74 * s, 1.39, 0.03]);
        put(&format!("{side}ThumbProximal"), [0.78 * s, 1.39, 0.055]);
        put(&format!("{side}ThumbDistal"), [0.81 * s, 1.39, 0.07]);
    }
    json!({ "bones": bones, "vrmVersion": version })
}

fn recording_frame(i: usize) -> Value {
    let frames: Value = serde_json::from_str(RECORDING).unwrap();
    frames[i].clone()
}

#[wasm_bindgen_test]
fn constructs_and_reports_rest_pose() {
    let rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let names: Vec<String> = rig
        .bone_names()
        .iter()
        .map(|v| v.as_string().unwrap())
        .collect();
    assert_eq!(names.len(), 49);
    assert_eq!(names[0], "hips");
    let rest = rig.rest_world_positions();
    let hand = get(&rest, "rightHand");
    assert_eq!(Array::from(&hand).get(0).as_f64().unwrap() as f32, -0.72);
    assert_eq!(rig.vrm_version(), "1");
}

#[wasm_bindgen_test]
fn vrm0_rest_pose_round_trips_in_the_model_frame() {
    let rig = HandRig::new(js(&rest_pose("0")), JsValue::UNDEFINED).unwrap();
    let hand = Array::from(&get(&rig.rest_world_positions(), "rightHand"));
    // Given at +X in the -Z-facing model frame, reported back unchanged.
    assert!((hand.get(0).as_f64().unwrap() - 0.72).abs() < 1e-6);
    assert_eq!(rig.vrm_version(), "0");
}

#[wasm_bindgen_test]
fn solves_a_real_frame_onto_the_right_hand() {
    let mut rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let result = rig.solve(js(&recording_frame(0))).unwrap();
    let bones = get(&result, "bones");
    let q = get(&bones, "rightHand");
    assert!(
        !q.is_undefined(),
        "the subject's right hand drives the avatar's right hand"
    );
    assert!(get(&bones, "leftHand").is_undefined());
    let q: Vec<f64> = Array::from(&q)
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let len = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    assert!((len - 1.0).abs() < 1e-5, "unit quaternion, got {q:?}");
    let world: Object = get(&result, "worldPositions").unchecked_into();
    assert_eq!(Object::keys(&world).length(), 49);
}

#[wasm_bindgen_test]
fn accepts_mediapipe_result_shapes_and_flat_arrays() {
    let frame = recording_frame(3);
    let hand = &frame["hands"][0];
    let world: Vec<Value> = hand["worldLandmarks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| json!({"x": p[0], "y": p[1], "z": p[2]}))
        .collect();
    let mut rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let reference = rig.solve(js(&frame)).unwrap();
    let reference = Array::from(&get(&get(&reference, "bones"), "rightIndexProximal"));

    // tasks-vision HandLandmarkerResult passed as the frame.
    let tasks = json!({
        "worldLandmarks": [world],
        "handedness": [[{"categoryName": "Left", "score": 0.97, "index": 0, "displayName": "Left"}]],
    });
    // legacy Hands result.
    let legacy = json!({
        "multiHandWorldLandmarks": [world],
        "multiHandedness": [{"label": "Left", "score": 0.97, "index": 0}],
    });
    for shape in [tasks, legacy] {
        let r = rig.solve(js(&shape)).unwrap();
        let q = Array::from(&get(&get(&r, "bones"), "rightIndexProximal"));
        for i in 0..4 {
            assert!((q.get(i).as_f64().unwrap() - reference.get(i).as_f64().unwrap()).abs() < 1e-6);
        }
    }
    // Flat Float32Array of 63 numbers.
    let flat: Vec<f32> = hand["worldLandmarks"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|p| (0..3).map(move |k| p[k].as_f64().unwrap() as f32))
        .collect();
    let h = Object::new();
    Reflect::set(&h, &"handedness".into(), &"Left".into()).unwrap();
    Reflect::set(&h, &"worldLandmarks".into(), &Float32Array::from(&flat[..])).unwrap();
    let f = Object::new();
    Reflect::set(&f, &"hands".into(), &Array::of1(&h)).unwrap();
    let r = rig.solve(f.into()).unwrap();
    assert!(!get(&get(&r, "bones"), "rightIndexProximal").is_undefined());
}

#[wasm_bindgen_test]
fn bad_input_names_the_field_and_the_rig_keeps_working() {
    let mut bad = rest_pose("1");
    bad["bones"]["leftPinkyProximal"] = json!([0, 0, 0]);
    let e = HandRig::new(js(&bad), JsValue::UNDEFINED).err().unwrap();
    assert!(message(e.into()).contains("leftPinkyProximal"));

    let mut missing = rest_pose("1");
    missing["bones"].as_object_mut().unwrap().remove("head");
    let e = HandRig::new(js(&missing), JsValue::UNDEFINED)
        .err()
        .unwrap();
    assert!(message(e.into()).contains("head"));

    let e = HandRig::new(js(&rest_pose("1")), js(&json!({"mirorr": true})))
        .err()
        .unwrap();
    assert!(message(e.into()).contains("mirorr"));
    let e = HandRig::new(
        js(&rest_pose("1")),
        js(&json!({"alignment": {"weight": 2}})),
    )
    .err()
    .unwrap();
    assert!(message(e.into()).contains("alignment.weight"));

    let mut rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let mut f = recording_frame(0);
    f["hands"][0]["worldLandmarks"]
        .as_array_mut()
        .unwrap()
        .pop();
    let e = rig.solve(js(&f)).err().unwrap();
    let m = message(e.into());
    assert!(
        m.contains("frame.hands[0].worldLandmarks") && m.contains("21"),
        "{m}"
    );

    // NaN cannot travel through JSON: build it in JS.
    let f = js(&recording_frame(0));
    // (Array::from would copy: cast instead, to edit in place.)
    let hands: Array = get(&f, "hands").unchecked_into();
    let world: Array = get(&hands.get(0), "worldLandmarks").unchecked_into();
    let p: Array = world.get(7).unchecked_into();
    p.set(1, JsValue::from_f64(f64::NAN));
    let m = message(rig.solve(f).err().unwrap().into());
    assert!(m.contains("frame.hands[0].worldLandmarks[7][1]"), "{m}");

    let m = message(
        rig.solve(js(
            &json!({"hands": [{"handedness": "Up", "worldLandmarks": []}]}),
        ))
        .err()
        .unwrap()
        .into(),
    );
    assert!(m.contains("frame.hands[0].handedness"), "{m}");
    let m = message(rig.solve(JsValue::from_f64(3.0)).err().unwrap().into());
    assert!(m.starts_with("frame"), "{m}");

    // Still works.
    let r = rig.solve(js(&recording_frame(1))).unwrap();
    assert!(!get(&get(&r, "bones"), "rightHand").is_undefined());
}

#[wasm_bindgen_test]
fn option_descriptions_cover_every_option() {
    let d = HandRig::option_descriptions();
    let paths: Vec<String> = d
        .iter()
        .map(|o| get(&o, "path").as_string().unwrap())
        .collect();
    for p in [
        "mirror",
        "inputMirrored",
        "alignment.weight",
        "alignment.finger",
        "armSolver",
    ] {
        assert!(paths.iter().any(|x| x == p), "{p} missing from {paths:?}");
    }
    // Every described option, set to its default, is accepted by the constructor, and an
    // option that is not described is rejected.
    for o in d.iter() {
        let path = get(&o, "path").as_string().unwrap();
        let default = get(&o, "default");
        let options = Object::new();
        match path.split_once('.') {
            Some((group, key)) => {
                let inner = Object::new();
                Reflect::set(&inner, &key.into(), &default).unwrap();
                Reflect::set(&options, &group.into(), &inner).unwrap();
            }
            None => {
                Reflect::set(&options, &path.as_str().into(), &default).unwrap();
            }
        }
        let r = HandRig::new(js(&rest_pose("1")), options.into());
        assert!(r.is_ok(), "option {path} with its default is rejected");
    }
    let e = HandRig::new(
        js(&rest_pose("1")),
        js(&json!({"alignment": {"fingr": "index"}})),
    );
    assert!(message(e.err().unwrap().into()).contains("options.alignment.fingr"));
}

const ROBOT: &[u8] = include_bytes!("../../shared/avatars/debug-robot.vrm");
const ODD_VRM0: &[u8] = include_bytes!("../../shared/avatars/odd-armature-vrm0.vrm");
const VRM0_FINGERS: &[u8] = include_bytes!("fixtures/vrm0-fingers.vrm");

#[wasm_bindgen_test]
fn from_vrm_reads_vrm1_and_vrm0_files() {
    let robot = HandRig::from_vrm(ROBOT, JsValue::UNDEFINED).unwrap();
    assert_eq!(robot.vrm_version(), "1");
    assert_eq!(robot.bone_names().length(), 53);
    let hand = Array::from(&get(&robot.rest_world_positions(), "leftHand"));
    assert!((hand.get(0).as_f64().unwrap() - 0.625).abs() < 1e-5);

    let odd = HandRig::from_vrm(ODD_VRM0, JsValue::UNDEFINED).unwrap();
    assert_eq!(odd.vrm_version(), "0");
    assert_eq!(odd.bone_names().length(), 17);

    // VRM 0.x with fingers: the recording drives its right hand, rotations come back finite.
    let mut rig = HandRig::from_vrm(VRM0_FINGERS, JsValue::UNDEFINED).unwrap();
    let r = rig.solve(js(&recording_frame(5))).unwrap();
    let q = Array::from(&get(&get(&r, "bones"), "rightIndexIntermediate"));
    assert_eq!(q.length(), 4);
    assert!(q.iter().all(|c| c.as_f64().unwrap().is_finite()));
}

#[wasm_bindgen_test]
fn from_vrm_rejects_broken_files_and_keeps_working() {
    let m = message(
        HandRig::from_vrm(&ROBOT[..100], JsValue::UNDEFINED)
            .err()
            .unwrap()
            .into(),
    );
    assert!(m.starts_with("vrm:") && m.contains("truncated"), "{m}");
    let m = message(
        HandRig::from_vrm(b"not a vrm at all", JsValue::UNDEFINED)
            .err()
            .unwrap()
            .into(),
    );
    assert!(m.starts_with("vrm:"), "{m}");
    assert!(HandRig::from_vrm(ROBOT, JsValue::UNDEFINED).is_ok());
}

fn quat_of(result: &JsValue, bone: &str) -> [f64; 4] {
    let a = Array::from(&get(&get(result, "bones"), bone));
    [0, 1, 2, 3].map(|i| a.get(i).as_f64().unwrap())
}

fn angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    2.0 * d.abs().min(1.0).acos().to_degrees()
}

#[wasm_bindgen_test]
fn holistic_image_landmarks_stand_in_for_world_landmarks() {
    // Legacy Holistic results carry only normalized image landmarks per hand, labelled like
    // MediaPipe's hand labels. The recording's image landmarks (1280x720) must drive the same
    // avatar hand as its world landmarks, with rotations close to the world-landmark solution.
    let mut rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let mut worst = 0.0f64;
    for i in [0usize, 150, 300, 450, 600] {
        let frame = recording_frame(i);
        let image: Vec<Value> = frame["hands"][0]["landmarks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| json!({"x": p[0], "y": p[1], "z": p[2]}))
            .collect();
        let reference = rig.solve(js(&frame)).unwrap();
        let holistic = json!({ "leftHandLandmarks": image, "imageAspect": 1280.0 / 720.0 });
        let r = rig.solve(js(&holistic)).unwrap();
        assert!(get(&get(&r, "bones"), "leftHand").is_undefined());
        for bone in [
            "rightHand",
            "rightIndexProximal",
            "rightMiddleProximal",
            "rightThumbMetacarpal",
        ] {
            let a = angle_deg(quat_of(&reference, bone), quat_of(&r, bone));
            worst = worst.max(a);
        }
    }
    // Measured 29 degrees worst (perspective and MediaPipe's rough image depth scale); a wrong
    // side, chirality or aspect handling gives differences far beyond 40.
    assert!(
        worst < 40.0,
        "image-vs-world rotation difference {worst} deg"
    );
}

#[wasm_bindgen_test]
fn degenerate_hands_are_reported_held_or_skipped() {
    let mut collapsed = recording_frame(0);
    collapsed["hands"][0]["worldLandmarks"] = json!(vec![[0.01, 0.02, 0.03]; 21]);
    collapsed["hands"][0]
        .as_object_mut()
        .unwrap()
        .remove("landmarks");

    // Nothing solved yet: skipped, no bones for that hand.
    let mut rig = HandRig::new(js(&rest_pose("1")), JsValue::UNDEFINED).unwrap();
    let r = rig.solve(js(&collapsed)).unwrap();
    let status = get(&get(&get(&r, "hands"), "right"), "status");
    assert_eq!(status.as_string().as_deref(), Some("skipped"));
    assert!(get(&get(&r, "bones"), "rightIndexProximal").is_undefined());

    // After a good frame: held, with the good frame's rotations repeated.
    let good = rig.solve(js(&recording_frame(0))).unwrap();
    let hands = get(&good, "hands");
    assert_eq!(
        get(&get(&hands, "right"), "status").as_string().as_deref(),
        Some("solved")
    );
    assert!((get(&get(&hands, "right"), "score").as_f64().unwrap() - 0.9668).abs() < 1e-4);
    assert!(get(&hands, "left").is_undefined());
    let held = rig.solve(js(&collapsed)).unwrap();
    let status = get(&get(&get(&held, "hands"), "right"), "status");
    assert_eq!(status.as_string().as_deref(), Some("held"));
    for bone in ["rightHand", "rightIndexProximal", "rightThumbDistal"] {
        // Repeated exactly, so compare components (acos near 1 is ill-conditioned).
        let (a, b) = (quat_of(&good, bone), quat_of(&held, bone));
        assert!(
            a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-7),
            "{bone}: {a:?} vs {b:?}"
        );
    }
}
