//! JavaScript bindings (wasm32 only): the raw `HandRig` class under the npm package's JS layer.
//!
//! Thin by design (rapier.js style). Per frame no JS value crosses the boundary: the rig owns
//! a flat input and a flat output buffer ([`crate::flat`]) in wasm memory, JavaScript writes
//! and reads them through `Float32Array` views (`inputPtr`, `outputPtr`, `memory`), and
//! `solveFlat(timeMs)` takes and returns plain numbers. The package's TypeScript layer
//! (`pkg-config/src/`: `frame*.ts` packs MediaPipe's result shapes into the input, `results.ts`
//! builds result objects from the output).
//!
//! No user JS code runs while Rust is on the stack: the constructor takes rest positions as a
//! typed array and the options as a plain object the JS layer built (its own copy of the
//! user's, so a throwing getter or a lying `length` throws in JavaScript before wasm is
//! entered and cannot leave a rig half-borrowed); serde-wasm-bindgen reads that object, and
//! the option table ([`crate::options`]) checks it.

mod chain;

pub use chain::RawChainSolver;

use glam::Vec3;
use js_sys::{Array, Object, Reflect};
use wasm_bindgen::prelude::*;

use crate::error::Error;
use crate::flat;
use crate::humanoid::bones::{HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::{Skeleton, VrmVersion};
use crate::input::mediapipe::FrameInput;
use crate::options::RigOptions;
use crate::pipeline::{Rig, SolveOutput};

type JsResult<T> = Result<T, JsError>;

fn js_err(e: Error) -> JsError {
    JsError::new(&e.to_string())
}

fn set(o: &Object, k: &str, v: &JsValue) {
    // Setting a property on a plain object we created cannot fail.
    let _ = Reflect::set(o, &JsValue::from_str(k), v);
}

/// Options from the JS object (`undefined` or `null`: the defaults), read with
/// serde-wasm-bindgen and checked by the option table.
fn rig_options(options: JsValue) -> Result<RigOptions, Error> {
    if options.is_undefined() || options.is_null() {
        return Ok(RigOptions::default());
    }
    let value: serde_json::Value = serde_wasm_bindgen::from_value(options)
        .map_err(|e| Error::invalid("options", e.to_string()))?;
    RigOptions::from_value(&value)
}

/// Which WebAssembly build this is: `"simd128"` (compiled with `-C target-feature=+simd128`,
/// loaded where the engine has WebAssembly SIMD) or `"baseline"` (the fallback). The package
/// ships both and its loader picks one (see `pkg-config/build.mjs`).
#[wasm_bindgen(js_name = wasmBuild)]
#[must_use]
pub fn wasm_build() -> String {
    if cfg!(target_feature = "simd128") {
        "simd128".into()
    } else {
        "baseline".into()
    }
}

/// The solver for one avatar with its flat input and output buffers. Create it once, write
/// the input, call `solveFlat` every frame, read the output; `free()` when done.
#[wasm_bindgen]
pub struct HandRig {
    rig: Rig,
    frame: FrameInput,
    out: SolveOutput,
    input: Box<[f32]>,
    output: Box<[f32]>,
    error: Option<String>,
    /// `HandRig.fromGltf` rigs: each bound bone's node name (`boneMap()`).
    binding: Vec<(HumanBone, String)>,
}

#[wasm_bindgen]
impl HandRig {
    /// `new HandRig(rest, vrmVersion, options)`: `rest` is a `Float64Array` of
    /// `4 * 55` numbers, per bone in `LAYOUT.bones` order `[present, x, y, z]` (rest world
    /// positions of three-vrm's normalized bones, meters, the model's own frame); `vrmVersion`
    /// 0 or 1; `options` the options object (the JS layer's plain copy of the user's) or
    /// undefined.
    ///
    /// `skinPositions`, `skinBones`, `skinTriangles` (optional, together): the avatar's skin
    /// at rest (`restPose.skin`: 3 floats per vertex in the model's own frame, each vertex's
    /// dominant bone as a `LAYOUT.bones` index, 3 vertex indices per triangle), from which
    /// self-contact learns the body ([`crate::contact::skin`]). `lookAt` (optional, 3 floats):
    /// `restPose.lookAtOffset`, the point between the eyes from the head bone (model frame).
    #[wasm_bindgen(constructor)]
    pub fn new(
        rest: &[f64],
        vrm_version: u8,
        options: JsValue,
        skin_positions: Option<Vec<f32>>,
        skin_bones: Option<Vec<u8>>,
        skin_triangles: Option<Vec<u32>>,
        look_at: Option<Vec<f32>>,
    ) -> JsResult<HandRig> {
        if rest.len() != 4 * BONE_COUNT {
            return Err(js_err(Error::invalid(
                "restPose",
                format!(
                    "internal: expected {} numbers, got {}",
                    4 * BONE_COUNT,
                    rest.len()
                ),
            )));
        }
        let version = match vrm_version {
            0 => VrmVersion::V0,
            1 => VrmVersion::V1,
            _ => {
                return Err(js_err(Error::invalid(
                    "restPose.vrmVersion",
                    "must be \"0\" or \"1\"",
                )))
            }
        };
        let bones: Vec<(HumanBone, Vec3)> = HumanBone::ALL
            .iter()
            .zip(rest.chunks_exact(4))
            .filter(|(_, r)| r[0] != 0.0)
            .map(|(b, r)| (*b, Vec3::new(r[1] as f32, r[2] as f32, r[3] as f32)))
            .collect();
        let mut skeleton = Skeleton::new(&bones, version).map_err(js_err)?;
        if let Some([x, y, z]) = look_at.as_deref() {
            skeleton = skeleton.with_look_at_offset(Some(Vec3::new(*x, *y, *z)));
        }
        if let (Some(p), Some(b)) = (skin_positions, skin_bones) {
            let mesh = crate::humanoid::SkinMesh::from_flat(
                &p,
                &b,
                skin_triangles.as_deref().unwrap_or(&[]),
            )
            .map_err(js_err)?;
            skeleton = skeleton.with_skin(mesh);
        }
        Self::with_skeleton(skeleton, options)
    }

    /// `HandRig.fromVrm(bytes, options)`: reads a `.vrm` file (VRM 1.0 or 0.x) directly.
    #[wasm_bindgen(js_name = fromVrm)]
    pub fn from_vrm(bytes: &[u8], options: JsValue) -> JsResult<HandRig> {
        let skeleton = crate::humanoid::vrm::load_skeleton(bytes).map_err(js_err)?;
        Self::with_skeleton(skeleton, options)
    }

    /// `HandRig.fromGltf(bytes, boneMap, options)`: reads a glTF binary (`.glb`, or a `.vrm`)
    /// whose humanoid is found by [`crate::humanoid::gltf`]. `boneMap`: an array of strings, pairs of
    /// humanoid bone name and node name (empty: find the humanoid by the VRM extension or by
    /// Mixamo / Unreal names); the JS layer read it from `options.skeleton.boneMap`.
    #[wasm_bindgen(js_name = fromGltf)]
    pub fn from_gltf(bytes: &[u8], bone_map: Array, options: JsValue) -> JsResult<HandRig> {
        let strings: Vec<String> = bone_map.iter().filter_map(|v| v.as_string()).collect();
        if strings.len() != bone_map.length() as usize || strings.len() % 2 != 0 {
            return Err(js_err(Error::invalid(
                "options.skeleton.boneMap",
                "internal: expected pairs of strings",
            )));
        }
        let pairs: Vec<(String, String)> = strings
            .chunks_exact(2)
            .map(|p| (p[0].clone(), p[1].clone()))
            .collect();
        let (skeleton, g) = crate::humanoid::gltf::load_skeleton(bytes, &pairs).map_err(js_err)?;
        let mut rig = Self::with_skeleton(skeleton, options)?;
        rig.binding = g.binding.into_iter().map(|(b, _, n)| (b, n)).collect();
        Ok(rig)
    }

    /// `{ humanBone: nodeName }` of a `fromGltf` rig (every bound bone); `undefined` for rigs
    /// made otherwise.
    #[wasm_bindgen(js_name = boneMap)]
    pub fn bone_map(&self) -> Option<Object> {
        if self.binding.is_empty() {
            return None;
        }
        let o = Object::new();
        for (b, n) in &self.binding {
            set(&o, b.as_str(), &JsValue::from_str(n));
        }
        Some(o)
    }

    fn with_skeleton(skeleton: Skeleton, options: JsValue) -> JsResult<HandRig> {
        let options = rig_options(options).map_err(js_err)?;
        let rig = Rig::new(skeleton, options).map_err(js_err)?;
        Ok(HandRig {
            rig,
            frame: FrameInput::default(),
            out: SolveOutput::default(),
            input: vec![0.0; flat::input::LEN].into_boxed_slice(),
            output: vec![0.0; flat::output::LEN].into_boxed_slice(),
            error: None,
            binding: Vec::new(),
        })
    }

    /// The module's `WebAssembly.Memory`, for typed-array views of the rig's buffers.
    pub fn memory() -> JsValue {
        wasm_bindgen::memory()
    }

    /// Byte offset of the input buffer (`LAYOUT.input.length` floats) in `memory`.
    #[wasm_bindgen(js_name = inputPtr)]
    pub fn input_ptr(&self) -> u32 {
        self.input.as_ptr() as u32
    }

    /// Byte offset of the output buffer (`LAYOUT.output.length` floats) in `memory`.
    #[wasm_bindgen(js_name = outputPtr)]
    pub fn output_ptr(&self) -> u32 {
        self.output.as_ptr() as u32
    }

    /// Solves the frame in the input buffer into the output buffer. `timeMs`: the frame's
    /// timestamp in milliseconds. Returns 0, or 1 when the input was rejected: `takeError()`
    /// then gives the message naming the field, and the rig and its output are unchanged.
    /// Allocates nothing on success, in wasm (so its memory never grows here) or in JS (a
    /// number crosses the boundary, not a result array or an exception object).
    #[wasm_bindgen(js_name = solveFlat)]
    pub fn solve_flat(&mut self, time_ms: f64) -> u32 {
        let solved = flat::read_input(&self.input, time_ms, &mut self.frame)
            .map(|()| self.rig.solve_valid(&self.frame, &mut self.out));
        match solved {
            Ok(()) => {
                flat::write_output(&self.rig, &self.out, &mut self.output);
                0
            }
            Err(e) => {
                self.error = Some(e.to_string());
                1
            }
        }
    }

    /// The message of the last rejected `solveFlat` (once; `undefined` afterwards).
    #[wasm_bindgen(js_name = takeError)]
    pub fn take_error(&mut self) -> Option<String> {
        self.error.take()
    }

    /// `"0"` or `"1"`.
    #[wasm_bindgen(getter, js_name = vrmVersion)]
    pub fn vrm_version(&self) -> String {
        self.rig.skeleton().version().as_str().to_string()
    }

    /// The body scale in force for pose input: avatar arm / user arm. Before any calibration
    /// sample it is avatar arm / 0.52 m (a typical adult arm); a preset `bodyScale` wins.
    #[wasm_bindgen(getter, js_name = bodyScale)]
    pub fn body_scale(&self) -> f32 {
        self.rig.body().scale()
    }

    /// Restarts body-scale calibration.
    #[wasm_bindgen(js_name = resetCalibration)]
    pub fn reset_calibration(&mut self) {
        self.rig.reset_calibration();
    }

    /// Forgets all history (held hands, elbow swivel, calibration).
    pub fn reset(&mut self) {
        self.rig.reset();
    }

    /// Starts the neutral face's calibration again (issue 50).
    #[wasm_bindgen(js_name = calibrateFace)]
    pub fn calibrate_face(&mut self) {
        self.rig.calibrate_face();
    }

    /// Calibrates the retargeting's hand scale from the last hand solved on each side (an
    /// open, flat hand): `[left, right]`, the new scale or NaN where nothing changed.
    #[wasm_bindgen(js_name = calibrateHandScale)]
    pub fn calibrate_hand_scale(&mut self) -> Vec<f32> {
        self.rig
            .calibrate_hand_scale()
            .iter()
            .map(|s| s.unwrap_or(f32::NAN))
            .collect()
    }

    /// Per bone in `LAYOUT.bones` order: 0 absent, 1 present and not driven, 2 driven by the
    /// rig (written every frame).
    #[wasm_bindgen(js_name = boneStates)]
    pub fn bone_states(&self) -> Vec<u8> {
        HumanBone::ALL
            .iter()
            .map(
                |&b| match (self.rig.skeleton().has(b), self.rig.drives(b)) {
                    (false, _) => 0,
                    (true, false) => 1,
                    (true, true) => 2,
                },
            )
            .collect()
    }

    /// Per side (`[left, right]`), the index (`LAYOUT.bones`) of the bone that carries the
    /// aligned point: `alignment.finger`'s distal bone, or what stands in for it on an avatar
    /// without it (another bone of that finger, another finger's, the hand for the palm); then
    /// per side `1` when it is such a stand-in, else `0`.
    #[wasm_bindgen(js_name = alignedBones)]
    pub fn aligned_bones(&self) -> Vec<u8> {
        let configured = self.rig.options().alignment.finger;
        let parts = Side::BOTH.map(|s| (s, self.rig.aligned_part(s)));
        let bones = parts.map(|(s, p)| p.bone(s).index() as u8);
        let stand_in = parts.map(|(_, p)| u8::from(!p.is_configured(configured)));
        [bones, stand_in].concat()
    }

    /// What the avatar lacks for fingertip alignment and what is used instead (one message for
    /// both sides), or `undefined` when it has `alignment.finger`'s distal bones.
    #[wasm_bindgen(getter, js_name = alignmentWarning)]
    pub fn alignment_warning(&self) -> Option<String> {
        self.rig.alignment_warning()
    }

    /// The avatar's self-contact model at rest (meters, the model's own frame), flat: the 8
    /// face anchors `x y z` (nose, chin, mouth, leftCheek, rightCheek, leftEar, rightEar,
    /// forehead), the head breadth, then the torso and neck capsules `[present, ax, ay, az,
    /// bx, by, bz, radius]` and the head sphere `[present, cx, cy, cz, radius]`.
    #[wasm_bindgen(js_name = contactModel)]
    pub fn contact_model(&self) -> Vec<f32> {
        use crate::contact::Shape;
        let (anchors, shapes) = self.rig.contact().rest_model(self.rig.skeleton());
        let mut v = Vec::with_capacity(8 * 3 + 1 + 8 + 8 + 5);
        for a in anchors {
            v.extend(self.rig.export_position(a).to_array());
        }
        v.push(self.rig.contact().face().size);
        for (k, shape) in shapes.into_iter().enumerate() {
            match shape {
                Some(Shape::Capsule { a, b, radius }) => {
                    v.push(1.0);
                    v.extend(self.rig.export_position(a).to_array());
                    v.extend(self.rig.export_position(b).to_array());
                    v.push(radius);
                }
                Some(Shape::Sphere { center, radius }) => {
                    v.push(1.0);
                    v.extend(self.rig.export_position(center).to_array());
                    v.push(radius);
                }
                None => {
                    // Torso and neck (capsule slots) are 8 wide, the head sphere's 5.
                    let width = if k < 2 { 8 } else { 5 };
                    v.extend(std::iter::repeat_n(0.0, width));
                }
            }
        }
        // The skin's model, when the rig has one: flag, samples, finger radius and palm
        // half-thickness per side (left, right).
        match self.rig.contact().surface() {
            Some(s) => {
                v.push(1.0);
                v.push(s.samples as f32);
                v.extend(s.finger_radius);
                v.extend(s.palm_half);
            }
            None => v.extend([0.0; 6]),
        }
        v
    }

    /// Rest world positions, `3 * 55` numbers in `LAYOUT.bones` order (meters, the model's
    /// own frame; zeros for absent bones).
    #[wasm_bindgen(js_name = restPositions)]
    pub fn rest_positions(&self) -> Vec<f32> {
        let skeleton = self.rig.skeleton();
        HumanBone::ALL
            .iter()
            .flat_map(|&b| {
                let p = skeleton
                    .rest_world(b)
                    .map_or(Vec3::ZERO, |p| self.rig.export_position(p));
                p.to_array()
            })
            .collect()
    }
}
