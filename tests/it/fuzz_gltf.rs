//! Structure-aware fuzzing of the glTF readers (issue 49): `.glb` / `.vrm` bytes through
//! `humanoid::vrm::load_skeleton` (`HandRig.fromVrm`), `humanoid::gltf::load_skeleton` by names
//! and by a bone map (`HandRig.fromGltf`), the skin they read from skinned meshes, and the
//! `Skeleton` and `Rig` built from them.
//!
//! proptest draws a corpus file and 1 to 4 edits, each an (operation, two numbers) triple that
//! the edit interprets on the file's unpacked JSON and BIN chunk: truncations and bit flips of
//! the bytes; huge, negative, fractional, string and null numbers; accessor and buffer-view
//! fields (counts, offsets, component types, element types, strides) set to hostile values;
//! sparse accessors; cycles and chains of up to 70,000 nodes; NaN, infinite and zero-scale
//! matrices and TRS; NaN over the BIN chunk (inverse bind matrices, weights); duplicate,
//! missing, empty and huge node names; Draco and meshopt extensions the readers do not decode;
//! skinned primitives of 10,000 to 100,000 vertices; top-level arrays removed. A failing case is
//! shrunk to its smallest edits.
//!
//! Each case must load or fail with an error naming the reader (`vrm:` / `gltf:`); never panic;
//! finish within a time limit (5 s per reader in release builds, 30 s in debug); hold at most 64 MiB plus
//! 40 times the file's size at its peak (this thread's allocations, counted by `no_alloc`'s
//! allocator); and a skeleton that loads must give a rig that solves a frame to finite unit
//! rotations. Corpus: the shared avatars, the generated fixtures (VRM 1.0 and 0.x, Mixamo- and
//! Unreal-named `.glb`) and `tests/fuzz-corpus/`. Cases: `HANDRIG_GLTF_FUZZ_CASES` (default
//! 600 in a release build, 50 in a debug one; `make fuzz` runs 100,000), seed
//! `HANDRIG_FUZZ_SEED`.

use crate::no_alloc::{live_bytes, peak_since_reset, reset_peak};
use crate::support::{recordings, vrm_fixture};

use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use serde_json::{json, Value};

use handrig::{FrameInput, Rig, RigOptions, SolveOutput};

fn cases() -> u32 {
    std::env::var("HANDRIG_GLTF_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        // A debug build (plain `cargo test`, `make test-rust`) reads files about ten times slower.
        .unwrap_or(if cfg!(debug_assertions) { 50 } else { 600 })
}

fn seed() -> u64 {
    std::env::var("HANDRIG_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20_261_206)
}

struct Seed {
    name: String,
    bytes: Vec<u8>,
    /// The file's binding by `gltf::parse` (bone name, node name), for the bone-map reader.
    map: Vec<(String, String)>,
}

fn corpus() -> Vec<Seed> {
    let mut files = vec![
        recordings::ROBOT.to_string(),
        "../shared/avatars/odd-armature-vrm0.vrm".to_string(),
        recordings::FIXTURE_VRM1.to_string(),
        recordings::FIXTURE_VRM0.to_string(),
        "tests/fixtures/avatars/child-mixamo.glb".to_string(),
        "tests/fixtures/avatars/child-unreal.glb".to_string(),
        "tests/fixtures/avatars/child-vrm1.vrm".to_string(),
    ];
    files.extend(recordings::fuzz_corpus(&[".vrm", ".glb"]));
    files
        .into_iter()
        .map(|f| {
            let bytes = std::fs::read(recordings::path(&f)).unwrap_or_else(|e| panic!("{f}: {e}"));
            let map = handrig::humanoid::gltf::parse(&bytes, &[])
                .map(|g| {
                    g.binding
                        .iter()
                        .map(|(b, _, n)| (b.as_str().to_string(), n.clone()))
                        .collect()
                })
                .unwrap_or_default();
            Seed {
                name: f,
                bytes,
                map,
            }
        })
        .collect()
}

/// Hostile numbers for counts, offsets, indices and types.
const NUMBERS: [f64; 14] = [
    0.0,
    -1.0,
    1.5,
    3.0,
    4.0,
    255.0,
    65_535.0,
    4_294_967_295.0,
    4_294_967_296.0,
    9_007_199_254_740_993.0,
    1e30,
    1e300,
    5126.0,
    5125.0,
];

fn hostile(k: u64) -> Value {
    match k % 18 {
        14 => Value::Null,
        15 => json!("1"),
        16 => json!([]),
        17 => json!({}),
        i => json!(NUMBERS[i as usize]),
    }
}

fn array_len(v: &Value, key: &str) -> usize {
    v.get(key).and_then(Value::as_array).map_or(0, Vec::len)
}

fn item<'a>(v: &'a mut Value, key: &str, k: u64) -> Option<&'a mut Value> {
    let a = v.get_mut(key)?.as_array_mut()?;
    if a.is_empty() {
        return None;
    }
    let n = a.len();
    a.get_mut((k % n as u64) as usize)
}

/// Replaces a random number of the JSON with a hostile value (a random walk from the root).
fn edit_number(v: &mut Value, mut r: u64, depth: usize) -> bool {
    r = r.rotate_left(7) ^ 0x9E37_79B9_7F4A_7C15;
    match v {
        Value::Number(_) => {
            *v = hostile(r);
            true
        }
        Value::Array(a) if !a.is_empty() && depth < 16 => {
            let i = (r % a.len() as u64) as usize;
            edit_number(&mut a[i], r / 3, depth + 1)
        }
        Value::Object(o) if !o.is_empty() && depth < 16 => {
            let keys: Vec<String> = o.keys().cloned().collect();
            let k = &keys[(r % keys.len() as u64) as usize];
            edit_number(o.get_mut(k).expect("a key of o"), r / 5, depth + 1)
        }
        _ => false,
    }
}

/// Sets `v[key]` when `v` is an object (an edit may have made it anything).
fn set(v: &mut Value, key: &str, value: Value) {
    if let Some(o) = v.as_object_mut() {
        o.insert(key.to_string(), value);
    }
}

/// Appends `data` to the BIN chunk as a new buffer view (4-aligned); its index.
fn push_view(json: &mut Value, bin: &mut Vec<u8>, data: &[u8]) -> usize {
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let offset = bin.len();
    bin.extend_from_slice(data);
    let views = json
        .as_object_mut()
        .expect("a glTF object")
        .entry("bufferViews")
        .or_insert_with(|| json!([]));
    if !views.is_array() {
        *views = json!([]);
    }
    let views = views.as_array_mut().expect("an array");
    views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": data.len() }));
    views.len() - 1
}

fn push_accessor(json: &mut Value, accessor: Value) -> usize {
    let list = json
        .as_object_mut()
        .expect("a glTF object")
        .entry("accessors")
        .or_insert_with(|| json!([]));
    if !list.is_array() {
        *list = json!([]);
    }
    let list = list.as_array_mut().expect("an array");
    list.push(accessor);
    list.len() - 1
}

/// A skinned primitive of `n` vertices on the first skinned mesh (a ring of triangles around
/// the skin's joints, weights on four joints), with the buffer entry grown to fit.
fn big_skin(json: &mut Value, bin: &mut Vec<u8>, n: usize, r: u64) {
    let joints = json
        .get("skins")
        .and_then(|s| s.get(0))
        .map_or(0, |s| array_len(s, "joints"))
        .max(1);
    let mut pos = Vec::with_capacity(12 * n);
    let mut jnt = Vec::with_capacity(4 * n);
    let mut wgt = Vec::with_capacity(16 * n);
    for i in 0..n {
        let a = i as f32 * 0.001;
        for c in [a.cos() * 0.2, 1.0 + (i % 97) as f32 * 0.01, a.sin() * 0.2] {
            pos.extend_from_slice(&c.to_le_bytes());
        }
        for k in 0..4 {
            jnt.push(((i + k + r as usize) % joints.min(256)) as u8);
        }
        for w in [0.4f32, 0.3, 0.2, 0.1] {
            wgt.extend_from_slice(&w.to_le_bytes());
        }
    }
    let tri: Vec<u8> = (0..n as u32 / 3 * 3)
        .flat_map(|i| i.to_le_bytes())
        .collect();
    let p = push_view(json, bin, &pos);
    let j = push_view(json, bin, &jnt);
    let w = push_view(json, bin, &wgt);
    let t = push_view(json, bin, &tri);
    let pa = push_accessor(
        json,
        json!({ "bufferView": p, "componentType": 5126, "count": n, "type": "VEC3",
                "min": [-0.2, 1.0, -0.2], "max": [0.2, 2.0, 0.2] }),
    );
    let ja = push_accessor(
        json,
        json!({ "bufferView": j, "componentType": 5121, "count": n, "type": "VEC4" }),
    );
    let wa = push_accessor(
        json,
        json!({ "bufferView": w, "componentType": 5126, "count": n, "type": "VEC4" }),
    );
    let ta = push_accessor(
        json,
        json!({ "bufferView": t, "componentType": 5125, "count": n / 3 * 3, "type": "SCALAR" }),
    );
    let prim =
        json!({ "attributes": { "POSITION": pa, "JOINTS_0": ja, "WEIGHTS_0": wa }, "indices": ta });
    if let Some(m) = item(json, "meshes", r) {
        if let Some(ps) = m.get_mut("primitives").and_then(Value::as_array_mut) {
            ps.push(prim);
        }
    }
    if let Some(b) = json.get_mut("buffers").and_then(|b| b.get_mut(0)) {
        set(b, "byteLength", json!(bin.len()));
    }
}

/// One edit of the file: `op` picks it, `a` and `b` parameterize it.
fn apply(json: &mut Value, bin: &mut Vec<u8>, op: u8, a: u64, b: u64) {
    let nodes = array_len(json, "nodes");
    match op {
        // Numbers anywhere.
        0 | 1 => {
            edit_number(json, a ^ b, 0);
        }
        // Accessor fields.
        2 => {
            let fields = [
                "count",
                "byteOffset",
                "componentType",
                "type",
                "bufferView",
                "normalized",
            ];
            let f = fields[(b % 6) as usize];
            if let Some(acc) = item(json, "accessors", a) {
                let value = match f {
                    "type" => [
                        json!("MAT4"),
                        json!("VEC2"),
                        json!("SCALAR"),
                        json!("MAT2"),
                        json!("VEC9"),
                        json!(3),
                    ][(b / 6 % 6) as usize]
                        .clone(),
                    _ => hostile(b / 6),
                };
                set(acc, f, value);
            }
        }
        // Buffer view and buffer fields.
        3 => {
            let fields = ["byteOffset", "byteLength", "byteStride", "buffer"];
            if b % 5 == 4 {
                if let Some(buf) = item(json, "buffers", a) {
                    set(buf, "byteLength", hostile(b / 5));
                    if b % 2 == 0 {
                        set(
                            buf,
                            "uri",
                            json!("data:application/octet-stream;base64,AAAA"),
                        );
                    }
                }
            } else if let Some(v) = item(json, "bufferViews", a) {
                set(v, fields[(b % 5) as usize], hostile(b / 5));
            }
        }
        // A sparse accessor.
        4 => {
            let views = array_len(json, "bufferViews").max(1) as u64;
            if let Some(acc) = item(json, "accessors", a) {
                let sparse = json!({
                    "count": hostile(b),
                    "indices": { "bufferView": b % views, "componentType": 5125 },
                    "values": { "bufferView": (b / 7) % views },
                });
                set(acc, "sparse", sparse);
                if b % 3 == 0 {
                    acc.as_object_mut().map(|o| o.remove("bufferView"));
                }
            }
        }
        // A cycle, or a child listed twice, or under two parents.
        5 if nodes > 0 => {
            let x = (a % nodes as u64) as usize;
            let y = (b % nodes as u64) as usize;
            let n = &mut json["nodes"][x];
            if !n.get("children").is_some_and(Value::is_array) {
                set(n, "children", json!([]));
            }
            if let Some(c) = n.get_mut("children").and_then(Value::as_array_mut) {
                c.push(json!(y));
            }
        }
        // A chain of nodes below a node: up to 300 deep, one time in 16 up to 70,000 (more
        // than MAX_NODES sometimes).
        6 if nodes > 0 => {
            let most = if b % 16 == 0 { 70_000 } else { 300 };
            let depth = 1 + (a % most) as usize;
            let under = (b % nodes as u64) as usize;
            let list = json["nodes"].as_array_mut().expect("nodes");
            let first = list.len();
            for k in 0..depth {
                let child = if k + 1 < depth {
                    json!([first + k + 1])
                } else {
                    json!([])
                };
                list.push(json!({ "name": format!("chain{k}"), "translation": [0, 0.01, 0], "children": child }));
            }
            let n = &mut list[under];
            if !n.get("children").is_some_and(Value::is_array) {
                set(n, "children", json!([]));
            }
            if let Some(c) = n.get_mut("children").and_then(Value::as_array_mut) {
                c.push(json!(first));
            }
        }
        // Degenerate transforms.
        7 if nodes > 0 => {
            let n = &mut json["nodes"][(a % nodes as u64) as usize];
            match b % 8 {
                0 => set(n, "matrix", json!(vec![0.0; 16])),
                1 => set(
                    n,
                    "matrix",
                    json!([1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
                ),
                2 => set(n, "scale", json!([0, 0, 0])),
                3 => set(n, "rotation", json!([0, 0, 0, 0])),
                4 => set(n, "translation", json!([1e39, -1e39, 0])),
                5 => set(n, "scale", json!([1e-30, 1e30, 1])),
                6 => set(
                    n,
                    "matrix",
                    json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0]),
                ),
                _ => set(n, "rotation", json!([1e300, 0, 0, 1])),
            }
        }
        // NaN over part of the BIN chunk (inverse bind matrices, weights, positions).
        8 if !bin.is_empty() => {
            let at = (a % bin.len() as u64) as usize & !3;
            let len = 4 * (1 + (b % 4096) as usize);
            let nan = if b % 2 == 0 { f32::NAN } else { f32::INFINITY };
            for c in bin[at..].chunks_exact_mut(4).take(len / 4) {
                c.copy_from_slice(&nan.to_le_bytes());
            }
        }
        // Node names: duplicated, removed, empty, huge, not a string.
        9 if nodes > 0 => {
            let x = (a % nodes as u64) as usize;
            let y = (b % nodes as u64) as usize;
            let other = json["nodes"][y].get("name").cloned();
            let n = &mut json["nodes"][x];
            match b % 5 {
                0 => set(n, "name", other.unwrap_or(json!(""))),
                1 => {
                    n.as_object_mut().map(|o| o.remove("name"));
                }
                2 => set(n, "name", json!("")),
                3 => set(n, "name", json!("x".repeat(100_000))),
                _ => set(n, "name", json!(7)),
            }
        }
        // Compression extensions the readers do not decode.
        10 => {
            let ext = ["KHR_draco_mesh_compression", "EXT_meshopt_compression"][(a % 2) as usize];
            if b % 2 == 0 {
                set(json, "extensionsRequired", json!([ext]));
                set(json, "extensionsUsed", json!([ext]));
            }
            if let Some(m) = item(json, "meshes", b) {
                if let Some(p) = m.get_mut("primitives").and_then(|p| p.get_mut(0)) {
                    set(
                        p,
                        "extensions",
                        json!({ ext: { "bufferView": 0, "attributes": { "POSITION": 0 } } }),
                    );
                }
            }
            // Draco's accessors have no buffer view.
            if b % 3 == 0 {
                if let Some(list) = json.get_mut("accessors").and_then(Value::as_array_mut) {
                    for acc in list {
                        acc.as_object_mut().map(|o| o.remove("bufferView"));
                    }
                }
            }
        }
        // A big skinned primitive: 100,000 vertices one time in four, else 10,000.
        11 => {
            let n = if b % 4 == 0 { 100_000 } else { 10_000 };
            big_skin(json, bin, n, a);
        }
        // A top-level array removed or replaced.
        12 => {
            let keys = [
                "nodes",
                "accessors",
                "bufferViews",
                "buffers",
                "meshes",
                "skins",
                "extensions",
                "scenes",
            ];
            let k = keys[(a % keys.len() as u64) as usize];
            if let Some(o) = json.as_object_mut() {
                match b % 3 {
                    0 => {
                        o.remove(k);
                    }
                    1 => {
                        o.insert(k.into(), json!({}));
                    }
                    _ => {
                        o.insert(k.into(), json!([null, 1, "x"]));
                    }
                }
            }
        }
        // Every accessor's count huge.
        13 => {
            if let Some(list) = json.get_mut("accessors").and_then(Value::as_array_mut) {
                for acc in list {
                    set(acc, "count", hostile(b));
                }
            }
        }
        // A skin's joints or inverse bind matrices pointing elsewhere.
        14 => {
            let accessors = array_len(json, "accessors") as u64;
            if let Some(s) = item(json, "skins", a) {
                match b % 3 {
                    0 => set(s, "inverseBindMatrices", json!(b % (accessors + 2))),
                    1 => set(s, "joints", json!([b % 1000, a % 1000, 0, 0])),
                    _ => set(s, "skeleton", hostile(b)),
                }
            }
        }
        _ => {}
    }
}

/// Byte-level edits after packing: truncation or flipped bits (the container itself).
fn apply_bytes(bytes: &mut Vec<u8>, op: u8, a: u64, b: u64) {
    match op {
        15 => bytes.truncate((a % (bytes.len() as u64 + 1)) as usize),
        16 if !bytes.is_empty() => {
            for k in 0..1 + b % 8 {
                let i = (a.wrapping_add(k.wrapping_mul(b | 1)) % bytes.len() as u64) as usize;
                bytes[i] ^= 1 << ((b >> (3 * k)) % 8);
            }
        }
        17 if bytes.len() > 20 => {
            // The header's or the JSON chunk's length fields.
            let at = [8usize, 12, 16][(a % 3) as usize];
            let v = [0u32, 1, 3, u32::MAX, 0x7FFF_FFFF][(b % 5) as usize];
            bytes[at..at + 4].copy_from_slice(&v.to_le_bytes());
        }
        _ => {}
    }
}

const OPS: u8 = 18;

/// The mutant of `seed` after `edits`.
fn mutant(seed: &Seed, edits: &[(u8, u64, u64)]) -> Vec<u8> {
    let Some((mut json, bin)) = vrm_fixture::unpack_glb(&seed.bytes) else {
        return seed.bytes.clone();
    };
    let had_bin = bin.is_some();
    let mut bin = bin.unwrap_or_default();
    for &(op, a, b) in edits {
        apply(&mut json, &mut bin, op, a, b);
    }
    let mut bytes = vrm_fixture::glb(&json, (had_bin || !bin.is_empty()).then_some(&bin[..]));
    for &(op, a, b) in edits {
        apply_bytes(&mut bytes, op, a, b);
    }
    bytes
}

/// One case: every reader on `bytes`, each loaded skeleton through a rig; a description of
/// what went wrong, if anything did.
fn check_case(bytes: &[u8], map: &[(String, String)], frame: &FrameInput) -> Result<(), String> {
    let limit = if cfg!(debug_assertions) {
        Duration::from_secs(30)
    } else {
        // A 70,000-node chain takes up to 0.9 s per reader on a loaded 2-core machine.
        Duration::from_secs(5)
    };
    let memory = (64 << 20) + 40 * bytes.len();
    let readers: [(&str, &dyn Fn() -> handrig::Result<handrig::Skeleton>); 3] = [
        ("vrm::load_skeleton", &|| {
            handrig::humanoid::vrm::load_skeleton(bytes)
        }),
        ("gltf::load_skeleton by names", &|| {
            handrig::humanoid::gltf::load_skeleton(bytes, &[]).map(|(s, _)| s)
        }),
        ("gltf::load_skeleton by a bone map", &|| {
            handrig::humanoid::gltf::load_skeleton(bytes, map).map(|(s, _)| s)
        }),
    ];
    for (what, read) in readers {
        let base = live_bytes();
        reset_peak();
        let t = Instant::now();
        let loaded = read();
        let took = t.elapsed();
        let peak = peak_since_reset(base);
        if took > limit {
            return Err(format!("{what}: took {took:?} (limit {limit:?})"));
        }
        if peak > memory {
            return Err(format!(
                "{what}: held {peak} bytes at its peak (limit {memory})"
            ));
        }
        match loaded {
            Err(e) => {
                let m = e.to_string();
                if !(m.starts_with("vrm: ") || m.starts_with("gltf: ")) || m.len() < 12 {
                    return Err(format!(
                        "{what}: error not naming the reader and the problem: {m}"
                    ));
                }
            }
            Ok(skeleton) => {
                let mut rig = Rig::new(skeleton, RigOptions::default())
                    .map_err(|e| format!("{what}: Rig::new refused a loaded skeleton: {e}"))?;
                let mut out = SolveOutput::default();
                rig.solve(frame, &mut out)
                    .map_err(|e| format!("{what}: a good frame failed: {e}"))?;
                for (i, q) in out.local.iter().enumerate() {
                    if !(q.is_finite() && (q.length() - 1.0).abs() < 1e-3) {
                        return Err(format!("{what}: bone {i} rotation {q}"));
                    }
                }
            }
        }
    }
    Ok(())
}

#[test]
fn structure_aware_mutations_of_glb_and_vrm_files() {
    let corpus = corpus();
    let frame = {
        let hands = recordings::hand_video_first();
        let mut f = FrameInput::default();
        recordings::fill_frame(
            &mut f,
            hands[200].world,
            0.9,
            recordings::ArmInput::Pose,
            &recordings::plausible_pose(),
        );
        f
    };
    // Each corpus file once as it is.
    for s in &corpus {
        check_case(&s.bytes, &s.map, &frame).unwrap_or_else(|e| panic!("{}: {e}", s.name));
    }
    let n = cases();
    let config = Config {
        cases: n,
        failure_persistence: None,
        max_shrink_iters: 400,
        ..Config::default()
    };
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed().to_le_bytes());
    let mut runner =
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes));
    // The big human files one case in sixteen (each read takes longer), the small ones otherwise.
    let heavy: Vec<usize> = (0..corpus.len())
        .filter(|&i| corpus[i].bytes.len() > 200_000)
        .collect();
    let light: Vec<usize> = (0..corpus.len())
        .filter(|&i| corpus[i].bytes.len() <= 200_000)
        .collect();
    let file = prop_oneof![
        15 => proptest::sample::select(light.clone()),
        1 => proptest::sample::select(heavy.clone()),
    ];
    let edits = proptest::collection::vec((0..OPS, any::<u64>(), any::<u64>()), 1..5);
    let t0 = Instant::now();
    let slowest = std::cell::RefCell::new((Duration::ZERO, String::new()));
    let result = runner.run(&(file, edits), |(f, edits)| {
        let s = &corpus[f];
        let t = Instant::now();
        let bytes = mutant(s, &edits);
        let r = check_case(&bytes, &s.map, &frame)
            .map_err(|e| TestCaseError::fail(format!("{} {edits:?}: {e}", s.name)));
        let took = t.elapsed();
        if took > slowest.borrow().0 {
            *slowest.borrow_mut() = (took, format!("{} {edits:?}", s.name));
        }
        r
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let (took, what) = slowest.take();
    println!(
        "glTF fuzz (seed {}): {n} cases of structure-aware edits over {} files, 3 readers each, in {:.1} s (slowest case {:.0} ms: {what})",
        seed(),
        corpus.len(),
        t0.elapsed().as_secs_f64(),
        took.as_secs_f64() * 1000.0
    );
}
