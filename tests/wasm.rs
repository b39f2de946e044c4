//! wasm-bindgen tests of the raw JS bindings, run in Node by `wasm-pack test --node`: the flat
//! typed-array path exactly as the npm package's JS layer uses it (Float32Array views over
//! wasm memory at `inputPtr` / `outputPtr`, `solveFlat`), and that it allocates nothing per
//! frame. MediaPipe result shapes, option paths and the result object are the JS layer's and
//! are tested in Node against the packed package (tests/node).
#![cfg(target_arch = "wasm32")]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Quat, Vec3};
use handrig::flat::{self, input, output};
use handrig::mediapipe::{FrameInput, HandObservation, Handedness, HAND_LANDMARKS};
use handrig::wasm::HandRig;
use handrig::{HumanBone, Side};
use js_sys::{Array, Float32Array, Reflect, WebAssembly};
use serde_json::{json, Value};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_test::wasm_bindgen_test;

/// Counts every allocation of the test module (the same allocator the package uses underneath).
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

const RECORDING: &str = include_str!("../../shared/data/hands/right-hand-video-mediapipe.json");
const ROBOT: &[u8] = include_bytes!("../../shared/avatars/debug-robot.vrm");
const ODD_VRM0: &[u8] = include_bytes!("../../shared/avatars/odd-armature-vrm0.vrm");
const HUGE_SCALE: &[u8] = include_bytes!("../../shared/repro/huge-scale-robot.vrm");
const VRM0_FINGERS: &[u8] = include_bytes!("fixtures/vrm0-fingers.vrm");
const MIXAMO_MAN: &[u8] = include_bytes!("fixtures/avatars/man-mixamo.glb");
const VRM1_MAN: &[u8] = include_bytes!("fixtures/avatars/man-vrm1.vrm");

/// A JSON value as the plain JS object the JS layer would pass.
fn js(v: Value) -> JsValue {
    js_text(&v.to_string())
}

/// JSON text as a plain JS object.
fn js_text(text: &str) -> JsValue {
    js_sys::JSON::parse(text).expect("JSON")
}

fn get(o: &JsValue, k: &str) -> JsValue {
    Reflect::get(o, &JsValue::from_str(k)).unwrap()
}

fn message(e: JsError) -> String {
    let e: js_sys::Error = JsValue::from(e).into();
    String::from(e.message())
}

/// The message of an expected error (HandRig has no Debug for `unwrap_err`).
fn failure<T>(r: Result<T, JsError>) -> String {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => message(e),
    }
}

/// A T-pose avatar facing +Z with full hands, as `[present, x, y, z]` per bone (the raw
/// constructor's input). VRM 0.x models face -Z: the same body turned 180 degrees about +Y.
fn rest_pose(version: u8) -> Vec<f64> {
    let mut rest = vec![0.0; 4 * handrig::BONE_COUNT];
    let mut put = |name: &str, p: [f64; 3]| {
        let b = HumanBone::from_name(name).unwrap().index();
        let p = if version == 0 {
            [-p[0], p[1], -p[2]]
        } else {
            p
        };
        rest[4 * b..4 * b + 4].copy_from_slice(&[1.0, p[0], p[1], p[2]]);
    };
    put("hips", [0.0, 1.0, 0.0]);
    put("spine", [0.0, 1.1, 0.0]);
    put("chest", [0.0, 1.25, 0.0]);
    put("neck", [0.0, 1.45, 0.0]);
    put("head", [0.0, 1.55, 0.0]);
    for (s, side) in [(1.0f64, "left"), (-1.0, "right")] {
        put(&format!("{side}UpperLeg"), [0.1 * s, 0.95, 0.0]);
        put(&format!("{side}LowerLeg"), [0.1 * s, 0.5, 0.0]);
        put(&format!("{side}Foot"), [0.1 * s, 0.08, 0.0]);
        put(&format!("{side}Shoulder"), [0.05 * s, 1.4, 0.0]);
        put(&format!("{side}UpperArm"), [0.18 * s, 1.4, 0.0]);
        put(&format!("{side}LowerArm"), [0.46 * s, 1.4, 0.0]);
        put(&format!("{side}Hand"), [0.72 * s, 1.4, 0.0]);
        for (f, z) in [
            ("Index", 0.025f64),
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
    rest
}

/// Frame `i` of the real recording (first hand) as a [`FrameInput`].
fn recording_frame(i: usize) -> FrameInput {
    let frames: Value = serde_json::from_str(RECORDING).unwrap();
    let h = &frames[i]["hands"][0];
    let mut world = [Vec3::ZERO; HAND_LANDMARKS];
    for (k, p) in world.iter_mut().enumerate() {
        let c = &h["worldLandmarks"][k];
        *p = Vec3::new(
            c[0].as_f64().unwrap() as f32,
            c[1].as_f64().unwrap() as f32,
            c[2].as_f64().unwrap() as f32,
        );
    }
    let mut frame = FrameInput {
        time_ms: frames[i]["timeMs"].as_f64().unwrap(),
        hand_count: 1,
        ..FrameInput::default()
    };
    frame.hands[0] = HandObservation {
        handedness: Handedness::from_label(h["handedness"].as_str().unwrap()).unwrap(),
        score: h["score"].as_f64().unwrap() as f32,
        world,
        image: None,
    };
    frame
}

/// The rig's buffers through Float32Array views of wasm memory, as the JS layer sees them.
fn view(ptr: u32, len: usize) -> Float32Array {
    let memory: WebAssembly::Memory = HandRig::memory().unchecked_into();
    Float32Array::new_with_byte_offset_and_length(&memory.buffer(), ptr, len as u32)
}

fn write_frame(rig: &HandRig, frame: &FrameInput) {
    let mut buf = vec![0.0f32; input::LEN];
    flat::write_input(frame, &mut buf);
    view(rig.input_ptr(), input::LEN).copy_from(&buf);
}

fn read_output(rig: &HandRig) -> Vec<f32> {
    view(rig.output_ptr(), output::LEN).to_vec()
}

/// Bit patterns, so that NaN slots (an unknown alignment error) compare equal.
fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn rotation(out: &[f32], bone: HumanBone) -> Quat {
    let at = output::BONE_ROTATIONS + 4 * bone.index();
    Quat::from_slice(&out[at..at + 4])
}

fn flag(out: &[f32], bone: HumanBone) -> f32 {
    out[output::BONE_FLAGS + bone.index()]
}

fn side_field(out: &[f32], side: Side, field: usize) -> f32 {
    out[output::SIDES + side.index() * output::SIDE_STRIDE + field]
}

/// The wasm memory's size (bytes) and the allocation count: what a per-frame loop must leave
/// unchanged.
fn heap_mark() -> (u32, usize) {
    let memory: WebAssembly::Memory = HandRig::memory().unchecked_into();
    let bytes = memory
        .buffer()
        .unchecked_into::<js_sys::ArrayBuffer>()
        .byte_length();
    (bytes, ALLOCATIONS.load(Ordering::SeqCst))
}

/// Asserts that nothing was allocated and wasm memory did not grow since `mark`.
fn assert_no_allocation_since(mark: (u32, usize)) {
    let (bytes, allocations) = heap_mark();
    assert_eq!(
        allocations - mark.1,
        0,
        "solveFlat allocated {} times",
        allocations - mark.1
    );
    assert_eq!(bytes, mark.0, "wasm memory grew");
}

#[wasm_bindgen_test]
fn constructs_from_flat_rest_positions_in_the_model_frame() {
    for version in [0u8, 1] {
        let rig = HandRig::new(
            &rest_pose(version),
            version,
            JsValue::UNDEFINED,
            None,
            None,
            None,
            None,
        )
        .unwrap();
        let states = rig.bone_states();
        assert_eq!(states.iter().filter(|s| **s != 0).count(), 49);
        // Arms, hands and fingers are driven (2); the rest are present (1).
        assert_eq!(states[HumanBone::RightIndexDistal.index()], 2);
        assert_eq!(states[HumanBone::RightUpperArm.index()], 2);
        assert_eq!(states[HumanBone::Head.index()], 1);
        assert_eq!(states[HumanBone::Jaw.index()], 0);
        let rest = rig.rest_positions();
        let hand = HumanBone::RightHand.index();
        // Given in the model's own frame, reported back unchanged.
        let want = if version == 0 { 0.72 } else { -0.72 };
        assert!((rest[3 * hand] - want).abs() < 1e-6, "{}", rest[3 * hand]);
        assert_eq!(rig.vrm_version(), version.to_string());
    }
}

#[wasm_bindgen_test]
fn solves_a_real_frame_through_the_memory_views() {
    let mut rig =
        HandRig::new(&rest_pose(1), 1, JsValue::UNDEFINED, None, None, None, None).unwrap();
    write_frame(&rig, &recording_frame(0));
    assert_eq!(rig.solve_flat(0.0), 0);
    let out = read_output(&rig);
    // The subject's right hand ("Left" on an unmirrored video) drives the avatar's right hand.
    assert_eq!(flag(&out, HumanBone::RightHand), 1.0);
    assert_eq!(flag(&out, HumanBone::RightIndexProximal), 1.0);
    assert_eq!(flag(&out, HumanBone::LeftHand), 2.0, "driven, not solved");
    assert_eq!(flag(&out, HumanBone::Head), 0.0, "not driven");
    let q = rotation(&out, HumanBone::RightIndexProximal);
    assert!((q.length() - 1.0).abs() < 1e-5 && q.w.abs() < 0.9999, "{q}");
    assert_eq!(rotation(&out, HumanBone::LeftHand), Quat::IDENTITY);
    assert_eq!(
        side_field(&out, Side::Right, output::side::HAND_STATUS),
        1.0
    );
    assert!((side_field(&out, Side::Right, output::side::HAND_SCORE) - 0.9668).abs() < 1e-4);
    assert_eq!(side_field(&out, Side::Left, output::side::HAND_STATUS), 0.0);
    // Finite everywhere but where NaN means "none": an unknown alignment error or contact
    // distance, and the retargeting targets of the analytic strategy.
    let nan_ok = |i: usize| {
        (output::SIDES..output::HAND_USE).contains(&i) && {
            let k = (i - output::SIDES) % output::SIDE_STRIDE;
            k == output::side::ALIGNMENT_ERROR
                || k == output::side::CONTACT_DISTANCE
                || (output::side::RETARGET_TARGETS..output::side::RETARGET_TARGETS + 15)
                    .contains(&k)
        }
    };
    assert!(out
        .iter()
        .enumerate()
        .all(|(i, v)| v.is_finite() || nan_ok(i)));
    let tips = output::SIDES + output::SIDE_STRIDE + output::side::FINGERTIPS;
    assert!(
        out[tips..tips + 15].iter().all(|v| v.is_finite()),
        "right fingertips"
    );
}

#[wasm_bindgen_test]
fn bad_input_names_the_field_and_leaves_the_rig_working() {
    let mut rig =
        HandRig::new(&rest_pose(1), 1, JsValue::UNDEFINED, None, None, None, None).unwrap();
    write_frame(&rig, &recording_frame(3));
    assert_eq!(rig.solve_flat(1.0), 0);
    let before = read_output(&rig);

    let input_view = view(rig.input_ptr(), input::LEN);
    let k = input::HANDS + input::hand::WORLD + 7 * 3 + 1;
    input_view.set_index(k as u32, f32::NAN);
    assert_eq!(rig.solve_flat(2.0), 1);
    let m = rig.take_error().unwrap();
    assert_eq!(
        m,
        "frame.hands[0].worldLandmarks[7]: must be three finite numbers"
    );
    assert_eq!(
        bits(&read_output(&rig)),
        bits(&before),
        "a rejected frame leaves the output"
    );
    input_view.set_index(input::HAND_COUNT as u32, 7.0);
    assert_eq!(rig.solve_flat(2.0), 1);
    let m = rig.take_error().unwrap();
    assert!(m.starts_with("frame.hands: hand count"), "{m}");
    assert_eq!(rig.solve_flat(f64::NAN), 1);
    let m = rig.take_error().unwrap();
    assert!(m.starts_with("frame"), "{m}");

    write_frame(&rig, &recording_frame(3));
    assert_eq!(rig.solve_flat(1.0), 0);
    assert_eq!(
        bits(&read_output(&rig)),
        bits(&before),
        "the same frame solves the same afterwards"
    );
}

#[wasm_bindgen_test]
fn options_are_checked_and_every_described_default_is_accepted() {
    let m = failure(HandRig::new(
        &rest_pose(1),
        1,
        js(json!({"mirorr": true})),
        None,
        None,
        None,
        None,
    ));
    assert!(
        m.starts_with("options.mirorr: unknown option (did you mean mirror?)"),
        "{m}"
    );
    let m = failure(HandRig::new(
        &rest_pose(1),
        1,
        JsValue::from_str("mirror"),
        None,
        None,
        None,
        None,
    ));
    assert!(m.starts_with("options: must be an object"), "{m}");
    let m = failure(HandRig::new(
        &rest_pose(1),
        1,
        js(json!({"arm": {"shoulderAngle": "0.3"}})),
        None,
        None,
        None,
        None,
    ));
    assert_eq!(
        m,
        "options.arm.shoulderAngle: must be a number in 0..1.5707964, got \"0.3\""
    );
    let e = HandRig::new(
        &rest_pose(1),
        1,
        js(json!({"alignment": {"weight": 2}})),
        None,
        None,
        None,
        None,
    );
    assert!(failure(e).contains("options.alignment.weight"));
    // The descriptions the package serves (generated from the option table; the .wasm carries
    // no list): each default goes through the constructor as the JS layer passes options.
    let rows: Vec<Value> =
        serde_json::from_str(include_str!("../pkg-config/src/options.json")).expect("options.json");
    assert!(rows.len() > 40, "every option is described");
    for o in &rows {
        let path = o["path"].as_str().unwrap();
        let default = o["default"].clone();
        // `{ "a": { "b": default } }` for the path "a.b".
        let options = path
            .split('.')
            .rev()
            .fold(default, |inner, key| json!({ key: inner }));
        let r = HandRig::new(
            &rest_pose(1),
            1,
            js(options.clone()),
            None,
            None,
            None,
            None,
        );
        assert!(
            r.is_ok(),
            "option {path} with its default is rejected: {:?}",
            r.err().map(message)
        );
    }
}

#[wasm_bindgen_test]
fn rest_pose_errors_name_the_bone() {
    let mut missing = rest_pose(1);
    missing[4 * HumanBone::Head.index()] = 0.0;
    let m = failure(HandRig::new(
        &missing,
        1,
        JsValue::UNDEFINED,
        None,
        None,
        None,
        None,
    ));
    assert_eq!(m, "restPose.bones: missing required bone(s) head");
    let mut huge = rest_pose(1);
    huge[4 * HumanBone::LeftHand.index() + 1] = 1e20;
    let m = failure(HandRig::new(
        &huge,
        1,
        JsValue::UNDEFINED,
        None,
        None,
        None,
        None,
    ));
    assert!(
        m.starts_with("restPose.bones.leftHand: position out of range"),
        "{m}"
    );
    assert!(HandRig::new(&rest_pose(1), 2, JsValue::UNDEFINED, None, None, None, None).is_err());
}

#[wasm_bindgen_test]
fn from_vrm_reads_vrm1_and_vrm0_and_rejects_broken_files() {
    let robot = HandRig::from_vrm(ROBOT, JsValue::UNDEFINED).unwrap();
    assert_eq!(robot.vrm_version(), "1");
    assert_eq!(robot.bone_states().iter().filter(|s| **s != 0).count(), 53);
    let hand = HumanBone::LeftHand.index();
    assert!((robot.rest_positions()[3 * hand] - 0.625).abs() < 1e-5);

    let odd = HandRig::from_vrm(ODD_VRM0, JsValue::UNDEFINED).unwrap();
    assert_eq!(odd.vrm_version(), "0");
    assert_eq!(odd.bone_states().iter().filter(|s| **s != 0).count(), 17);

    // VRM 0.x with fingers: the recording drives its right hand, finite unit rotations.
    let mut rig = HandRig::from_vrm(VRM0_FINGERS, JsValue::UNDEFINED).unwrap();
    write_frame(&rig, &recording_frame(5));
    assert_eq!(rig.solve_flat(5.0), 0);
    let q = rotation(&read_output(&rig), HumanBone::RightIndexIntermediate);
    assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-5);

    let m = failure(HandRig::from_vrm(&ROBOT[..100], JsValue::UNDEFINED));
    assert!(m.starts_with("vrm:") && m.contains("truncated"), "{m}");
    let m = failure(HandRig::from_vrm(b"not a vrm at all", JsValue::UNDEFINED));
    assert!(m.starts_with("vrm:"), "{m}");
    // ../shared/repro/huge-scale-robot.vrm: refused at load instead of a panic later.
    let m = failure(HandRig::from_vrm(HUGE_SCALE, JsValue::UNDEFINED));
    assert!(m.contains("position out of range"), "{m}");
    assert!(HandRig::from_vrm(ROBOT, JsValue::UNDEFINED).is_ok());
}

#[wasm_bindgen_test]
fn from_gltf_binds_mixamo_names_and_reports_the_bone_map() {
    let mut mixamo = HandRig::from_gltf(MIXAMO_MAN, Array::new(), JsValue::UNDEFINED).unwrap();
    let mut vrm = HandRig::from_vrm(VRM1_MAN, JsValue::UNDEFINED).unwrap();
    assert_eq!(mixamo.vrm_version(), "1");
    let map: JsValue = mixamo.bone_map().expect("a bone map").into();
    assert_eq!(
        get(&map, "leftUpperArm").as_string().as_deref(),
        Some("mixamorig:LeftArm")
    );
    let keys = js_sys::Object::keys(map.unchecked_ref::<js_sys::Object>());
    assert_eq!(keys.length(), 54);
    assert!(vrm.bone_map().is_none());
    // Same rest pose (through the Armature's turn and 0.01 scale), same solve.
    let (ra, rb) = (mixamo.rest_positions(), vrm.rest_positions());
    assert!(ra.iter().zip(&rb).all(|(a, b)| (a - b).abs() < 1e-6));
    write_frame(&mixamo, &recording_frame(5));
    write_frame(&vrm, &recording_frame(5));
    assert_eq!(mixamo.solve_flat(5.0), 0);
    assert_eq!(vrm.solve_flat(5.0), 0);
    let (a, b) = (read_output(&mixamo), read_output(&vrm));
    let bone = HumanBone::RightIndexIntermediate;
    assert!(rotation(&a, bone).angle_between(rotation(&b, bone)) < 1e-6);

    // A bone map (pairs of strings) naming a node twice: an error naming both bones.
    let pairs = Array::of4(
        &"leftHand".into(),
        &"mixamorig:LeftHand".into(),
        &"rightHand".into(),
        &"mixamorig:LeftHand".into(),
    );
    let m = failure(HandRig::from_gltf(MIXAMO_MAN, pairs, JsValue::UNDEFINED));
    assert!(
        m.starts_with("gltf: duplicate binding: leftHand and rightHand"),
        "{m}"
    );
    let m = failure(HandRig::from_gltf(
        b"not a glb",
        Array::new(),
        JsValue::UNDEFINED,
    ));
    assert!(m.starts_with("gltf: not a glTF binary"), "{m}");
}

#[wasm_bindgen_test]
fn degenerate_hands_are_reported_held_or_skipped() {
    let mut collapsed = recording_frame(0);
    collapsed.hands[0].world = [Vec3::new(0.01, 0.02, 0.03); HAND_LANDMARKS];
    // Frames solved on their own (no smoothing across them).
    let per_frame = r#"{ "filter": { "enabled": false }, "dropout": { "enabled": false } }"#;
    let mut rig =
        HandRig::new(&rest_pose(1), 1, js_text(per_frame), None, None, None, None).unwrap();
    // Nothing solved yet: skipped (3), the finger at rest, not solved (2).
    write_frame(&rig, &collapsed);
    assert_eq!(rig.solve_flat(0.0), 0);
    let out = read_output(&rig);
    assert_eq!(
        side_field(&out, Side::Right, output::side::HAND_STATUS),
        3.0
    );
    assert_eq!(flag(&out, HumanBone::RightIndexProximal), 2.0);
    // After a good frame: held (2), with the good frame's rotations repeated.
    write_frame(&rig, &recording_frame(0));
    assert_eq!(rig.solve_flat(33.0), 0);
    let good = read_output(&rig);
    write_frame(&rig, &collapsed);
    assert_eq!(rig.solve_flat(66.0), 0);
    let held = read_output(&rig);
    assert_eq!(
        side_field(&held, Side::Right, output::side::HAND_STATUS),
        2.0
    );
    for bone in [
        HumanBone::RightHand,
        HumanBone::RightIndexProximal,
        HumanBone::RightThumbDistal,
    ] {
        assert_eq!(rotation(&good, bone), rotation(&held, bone), "{bone}");
    }
    // reset() forgets the held solve: the next degenerate hand is skipped again.
    rig.reset();
    assert_eq!(rig.solve_flat(99.0), 0);
    assert_eq!(
        side_field(&read_output(&rig), Side::Right, output::side::HAND_STATUS),
        3.0
    );
}

/// The flat path allocates nothing per frame in wasm either, so wasm memory never grows and
/// the JS layer's typed-array views stay valid.
#[wasm_bindgen_test]
fn the_flat_path_allocates_nothing_per_frame() {
    let frames: Vec<FrameInput> = (0..60).map(|i| recording_frame(i * 10)).collect();
    let mut rig = HandRig::from_vrm(ROBOT, JsValue::UNDEFINED).unwrap();
    let mut bufs: Vec<Vec<f32>> = frames
        .iter()
        .map(|f| {
            let mut b = vec![0.0; input::LEN];
            flat::write_input(f, &mut b);
            b
        })
        .collect();
    // Every path once: a hand, a hand with a wrist (IK and alignment).
    bufs[1][input::WRISTS + input::WRIST_STRIDE + input::wrist::PRESENT] = 1.0;
    bufs[1][input::WRISTS + input::WRIST_STRIDE + input::wrist::POSITION] = -0.4;
    bufs[1][input::WRISTS + input::WRIST_STRIDE + input::wrist::POSITION + 1] = 1.2;
    let input_view = view(rig.input_ptr(), input::LEN);
    for b in &bufs[..2] {
        input_view.copy_from(b);
        assert_eq!(rig.solve_flat(0.0), 0);
    }
    let mark = heap_mark();
    for (i, b) in bufs.iter().cycle().take(600).enumerate() {
        input_view.copy_from(b);
        assert_eq!(rig.solve_flat(i as f64 * 33.3), 0);
    }
    assert_no_allocation_since(mark);
    // The frames were solved (the count is not vacuous): the last one moved the fingers.
    assert_eq!(flag(&read_output(&rig), HumanBone::RightIndexDistal), 1.0);
    // The counter sees allocations at all.
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    let probe = std::hint::black_box(vec![0u8; 64]);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) > after && probe.len() == 64);
}

/// The torso sections through the flat path in wasm (`torso: "pose"`): body-tracker joints
/// drive the torso bones, the app's spine wins, nothing is allocated per frame.
#[wasm_bindgen_test]
fn the_torso_sections_drive_the_torso_without_allocating() {
    use handrig::torso::{BodyJoint, TORSO_BONES};
    let mut rig = HandRig::from_vrm(ROBOT, js(json!({"torso": "pose"}))).unwrap();
    let joints = [
        (BodyJoint::Hips, [0.0, 1.0, 0.0]),
        (BodyJoint::LeftUpperLeg, [0.09, 1.0, 0.02]),
        (BodyJoint::RightUpperLeg, [-0.09, 1.0, -0.02]),
        (BodyJoint::LeftUpperArm, [0.18, 1.48, 0.15]),
        (BodyJoint::RightUpperArm, [-0.18, 1.46, -0.05]),
        (BodyJoint::Nose, [0.0, 1.62, 0.12]),
        (BodyJoint::LeftEye, [0.03, 1.65, 0.09]),
        (BodyJoint::RightEye, [-0.03, 1.65, 0.09]),
        (BodyJoint::LeftEar, [0.075, 1.64, 0.0]),
        (BodyJoint::RightEar, [-0.075, 1.64, 0.01]),
    ];
    let mut buf = vec![0.0f32; input::LEN];
    buf[input::BODY_PRESENT] = 1.0;
    for (j, p) in joints {
        let at = input::BODY + j.index() * input::BODY_STRIDE;
        buf[at..at + 3].copy_from_slice(&p);
        buf[at + 3] = 0.9;
    }
    let spine = TORSO_BONES
        .iter()
        .position(|b| *b == HumanBone::Spine)
        .unwrap();
    let at = input::TORSO + spine * input::TORSO_STRIDE;
    buf[at + input::torso_bone::PRESENT] = 1.0;
    buf[at + input::torso_bone::ROTATION..at + input::torso_bone::ROTATION + 4]
        .copy_from_slice(&Quat::from_rotation_x(0.2).to_array());
    let input_view = view(rig.input_ptr(), input::LEN);
    input_view.copy_from(&buf);
    assert_eq!(rig.solve_flat(0.0), 0);
    let out = read_output(&rig);
    for b in [
        HumanBone::Hips,
        HumanBone::Spine,
        HumanBone::Chest,
        HumanBone::Head,
    ] {
        assert_eq!(flag(&out, b), 1.0, "{b} solved");
    }
    assert!(rotation(&out, HumanBone::Spine).abs_diff_eq(Quat::from_rotation_x(0.2), 1e-6));
    assert!(rotation(&out, HumanBone::Chest).angle_between(Quat::IDENTITY) > 0.05);
    let mark = heap_mark();
    for i in 0..300 {
        // Every third frame the shoulders are lost (held, then eased).
        let c = if i % 3 == 0 { 0.0 } else { 0.9 };
        for j in [BodyJoint::LeftUpperArm, BodyJoint::RightUpperArm] {
            buf[input::BODY + j.index() * input::BODY_STRIDE + 3] = c;
        }
        input_view.copy_from(&buf);
        assert_eq!(rig.solve_flat(i as f64 * 33.3), 0);
    }
    assert_no_allocation_since(mark);
}
