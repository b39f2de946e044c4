//! JavaScript bindings (wasm32 only): the `HandRig` class.
//!
//! Thin by design (rapier.js style): parse JS input into the fixed-size [`FrameInput`] the
//! rig owns, call [`Rig::solve`], and build the result object. Every input problem becomes a
//! JS `Error` whose message names the field (`frame.hands[0].worldLandmarks[7]: ...`); the rig
//! is untouched by a rejected frame and keeps working.
//!
//! Accepted input shapes (see the README): handrig's own `{ handedness, score, worldLandmarks,
//! landmarks }` hands, MediaPipe tasks-vision `HandLandmarkerResult`, legacy `Hands` results
//! (`multiHandWorldLandmarks`, ...), legacy `Holistic` results (image landmarks only, see
//! [`image_to_pseudo_world`]), points as `{x, y, z}` or `[x, y, z]`, landmark lists as arrays
//! or flat `Float32Array`/`Float64Array` (21*3 or 33*3).

use glam::{Quat, Vec3};
use js_sys::{Array, Float32Array, Float64Array, Object, Reflect};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::error::Error;
use crate::hand::HandStatus;
use crate::mediapipe::{
    hand_landmark, FrameInput, HandObservation, Handedness, PoseObservation, WristObservation,
    HAND_LANDMARKS, MAX_HANDS, POSE_LANDMARKS,
};
use crate::rig::{option_descriptions, Rig, RigOptions, SolveOutput};
use crate::skeleton::{Skeleton, VrmVersion};

type JsResult<T> = Result<T, JsError>;

fn js_err(e: Error) -> JsError {
    JsError::new(&e.to_string())
}

fn invalid(field: &str, problem: &str) -> JsError {
    js_err(Error::invalid(field, problem))
}

/// Property names as JS strings, created once per rig instead of once per lookup.
struct Keys {
    time_ms: JsValue,
    hands: JsValue,
    pose: JsValue,
    wrists: JsValue,
    handedness: JsValue,
    handednesses: JsValue,
    score: JsValue,
    world_landmarks: JsValue,
    landmarks: JsValue,
    multi_hand_world_landmarks: JsValue,
    multi_hand_landmarks: JsValue,
    multi_handedness: JsValue,
    left_hand_landmarks: JsValue,
    right_hand_landmarks: JsValue,
    pose_world_landmarks: JsValue,
    visibility: JsValue,
    position: JsValue,
    rotation: JsValue,
    label: JsValue,
    category_name: JsValue,
    image_aspect: JsValue,
    x: JsValue,
    y: JsValue,
    z: JsValue,
    left: JsValue,
    right: JsValue,
    bones: JsValue,
    world_positions: JsValue,
    ik_targets: JsValue,
    alignment: JsValue,
    target_dip: JsValue,
    ik_wrist: JsValue,
    pose_wrist: JsValue,
    error: JsValue,
    reachable: JsValue,
    aligned: JsValue,
    status: JsValue,
    status_names: [JsValue; 3],
    bone_names: [JsValue; BONE_COUNT],
}

impl Keys {
    fn new() -> Keys {
        let s = |k: &str| JsValue::from_str(k);
        Keys {
            time_ms: s("timeMs"),
            hands: s("hands"),
            pose: s("pose"),
            wrists: s("wrists"),
            handedness: s("handedness"),
            handednesses: s("handednesses"),
            score: s("score"),
            world_landmarks: s("worldLandmarks"),
            landmarks: s("landmarks"),
            multi_hand_world_landmarks: s("multiHandWorldLandmarks"),
            multi_hand_landmarks: s("multiHandLandmarks"),
            multi_handedness: s("multiHandedness"),
            left_hand_landmarks: s("leftHandLandmarks"),
            right_hand_landmarks: s("rightHandLandmarks"),
            pose_world_landmarks: s("poseWorldLandmarks"),
            visibility: s("visibility"),
            position: s("position"),
            rotation: s("rotation"),
            label: s("label"),
            category_name: s("categoryName"),
            image_aspect: s("imageAspect"),
            x: s("x"),
            y: s("y"),
            z: s("z"),
            left: s("left"),
            right: s("right"),
            bones: s("bones"),
            world_positions: s("worldPositions"),
            ik_targets: s("ikTargets"),
            alignment: s("alignment"),
            target_dip: s("targetDip"),
            ik_wrist: s("ikWrist"),
            pose_wrist: s("poseWrist"),
            error: s("error"),
            reachable: s("reachable"),
            aligned: s("aligned"),
            status: s("status"),
            status_names: [s("solved"), s("held"), s("skipped")],
            bone_names: HumanBone::ALL.map(|b| s(b.as_str())),
        }
    }
}

/// Reads `obj[key]`; `undefined` and `null` are `None`.
fn get(obj: &JsValue, key: &JsValue) -> Option<JsValue> {
    if !obj.is_object() {
        return None;
    }
    Reflect::get(obj, key)
        .ok()
        .filter(|v| !v.is_undefined() && !v.is_null())
}

fn number(v: &JsValue, field: &dyn Fn() -> String) -> JsResult<f32> {
    match v.as_f64() {
        Some(n) if n.is_finite() => Ok(n as f32),
        Some(_) => Err(invalid(&field(), "must be a finite number")),
        None => Err(invalid(&field(), "must be a number")),
    }
}

/// A point as `[x, y, z]`, `{x, y, z}` or a 3-element typed array.
fn vec3(v: &JsValue, keys: &Keys, field: &dyn Fn() -> String) -> JsResult<Vec3> {
    let mut c = [0.0f32; 3];
    if Array::is_array(v) {
        let a: &Array = v.unchecked_ref();
        if a.length() != 3 {
            return Err(invalid(
                &field(),
                &format!("must have 3 numbers [x, y, z], got {}", a.length()),
            ));
        }
        for (i, slot) in c.iter_mut().enumerate() {
            *slot = number(&a.get(i as u32), &|| format!("{}[{i}]", field()))?;
        }
    } else if let Some(t) = v.dyn_ref::<Float32Array>() {
        if t.length() != 3 {
            return Err(invalid(&field(), "typed array must have 3 numbers"));
        }
        for (i, slot) in c.iter_mut().enumerate() {
            *slot = number(&JsValue::from_f64(t.get_index(i as u32) as f64), &|| {
                format!("{}[{i}]", field())
            })?;
        }
    } else if v.is_object() {
        for (slot, (k, name)) in c
            .iter_mut()
            .zip([(&keys.x, "x"), (&keys.y, "y"), (&keys.z, "z")])
        {
            let item = get(v, k).ok_or_else(|| {
                invalid(
                    &format!("{}.{name}", field()),
                    "is missing (expected a number)",
                )
            })?;
            *slot = number(&item, &|| format!("{}.{name}", field()))?;
        }
    } else {
        return Err(invalid(
            &field(),
            "must be [x, y, z] or {x, y, z} (three finite numbers)",
        ));
    }
    Ok(Vec3::from_array(c))
}

/// A quaternion `[x, y, z, w]`, normalized if within 1% of unit length.
fn quat(v: &JsValue, field: &dyn Fn() -> String) -> JsResult<Quat> {
    let a = v
        .dyn_ref::<Array>()
        .filter(|a| a.length() == 4)
        .ok_or_else(|| invalid(&field(), "must be a quaternion [x, y, z, w]"))?;
    let mut c = [0.0f32; 4];
    for (i, slot) in c.iter_mut().enumerate() {
        *slot = number(&a.get(i as u32), &|| format!("{}[{i}]", field()))?;
    }
    let q = Quat::from_array(c);
    if (q.length() - 1.0).abs() > 1e-2 {
        return Err(invalid(&field(), "must be a unit quaternion [x, y, z, w]"));
    }
    Ok(q.normalize())
}

/// Reads `N` points (and optional visibilities) from an array of points or a flat typed array
/// of `N * 3` numbers.
fn points<const N: usize>(
    v: &JsValue,
    keys: &Keys,
    field: &dyn Fn() -> String,
    out: &mut [Vec3; N],
    mut visibility: Option<&mut [f32; N]>,
) -> JsResult<()> {
    let flat = |len: u32, at: &dyn Fn(u32) -> f64, out: &mut [Vec3; N]| -> JsResult<()> {
        if len as usize != N * 3 {
            return Err(invalid(
                &field(),
                &format!(
                    "flat array must have {} numbers ({N} points x 3), got {len}",
                    N * 3
                ),
            ));
        }
        for (i, p) in out.iter_mut().enumerate() {
            let mut c = [0.0f32; 3];
            for (j, slot) in c.iter_mut().enumerate() {
                let n = at((i * 3 + j) as u32);
                if !n.is_finite() {
                    return Err(invalid(
                        &format!("{}[{}]", field(), i * 3 + j),
                        "must be a finite number",
                    ));
                }
                *slot = n as f32;
            }
            *p = Vec3::from_array(c);
        }
        Ok(())
    };
    if let Some(t) = v.dyn_ref::<Float32Array>() {
        return flat(t.length(), &|i| t.get_index(i) as f64, out);
    }
    if let Some(t) = v.dyn_ref::<Float64Array>() {
        return flat(t.length(), &|i| t.get_index(i), out);
    }
    let Some(a) = v.dyn_ref::<Array>() else {
        return Err(invalid(
            &field(),
            &format!(
                "must be an array of {N} points or a Float32Array of {}",
                N * 3
            ),
        ));
    };
    if a.length() as usize == N * 3 && a.get(0).as_f64().is_some() {
        return flat(a.length(), &|i| a.get(i).as_f64().unwrap_or(f64::NAN), out);
    }
    if a.length() as usize != N {
        return Err(invalid(
            &field(),
            &format!("must have {N} points, got {}", a.length()),
        ));
    }
    for (i, p) in out.iter_mut().enumerate() {
        let item = a.get(i as u32);
        *p = vec3(&item, keys, &|| format!("{}[{i}]", field()))?;
        if let Some(vis) = visibility.as_deref_mut() {
            vis[i] = match get(&item, &keys.visibility) {
                Some(x) => number(&x, &|| format!("{}[{i}].visibility", field()))?,
                None => 1.0,
            };
        }
    }
    Ok(())
}

fn handedness_label(
    v: &JsValue,
    keys: &Keys,
    field: &dyn Fn() -> String,
) -> JsResult<(Handedness, Option<f32>)> {
    // Accept "Left", {label|categoryName, score}, or tasks-vision's [{categoryName, score}].
    let item = match v.dyn_ref::<Array>() {
        Some(a) if a.length() > 0 => a.get(0),
        Some(_) => return Err(invalid(&field(), "is an empty array")),
        None => v.clone(),
    };
    let (label, score) = if let Some(s) = item.as_string() {
        (s, None)
    } else {
        let l = get(&item, &keys.category_name)
            .or_else(|| get(&item, &keys.label))
            .and_then(|l| l.as_string())
            .ok_or_else(|| invalid(&field(), "must be \"Left\" or \"Right\""))?;
        let s = match get(&item, &keys.score) {
            Some(s) => Some(number(&s, &|| format!("{}.score", field()))?),
            None => None,
        };
        (l, s)
    };
    let h = Handedness::from_label(&label).ok_or_else(|| {
        invalid(
            &field(),
            &format!("must be \"Left\" or \"Right\", got \"{label}\""),
        )
    })?;
    Ok((h, score))
}

/// Converts normalized image landmarks (Holistic legacy results carry no hand world
/// landmarks) into approximate metric hand-centered points: x is scaled by the image aspect
/// (width / height) so both axes are in the same unit, then everything is scaled so the
/// wrist-to-middle-MCP distance is 9 cm, an average adult's (rotations do not depend on the
/// scale; positions from it are approximate).
pub fn image_to_pseudo_world(points: &mut [Vec3; HAND_LANDMARKS], aspect: f32) {
    for p in points.iter_mut() {
        p.x *= aspect;
        p.z *= aspect;
    }
    let wrist = points[hand_landmark::WRIST];
    let palm = (points[hand_landmark::MIDDLE_MCP] - wrist).length();
    let k = if palm > 1e-6 { 0.09 / palm } else { 1.0 };
    for p in points.iter_mut() {
        *p = (*p - wrist) * k;
    }
}

/// The solver for one avatar. Create it once, call `solve` every frame, `free()` when done.
#[wasm_bindgen]
pub struct HandRig {
    rig: Rig,
    frame: FrameInput,
    out: SolveOutput,
    keys: Keys,
}

#[wasm_bindgen]
impl HandRig {
    /// `new HandRig(restPose, options?)`: `restPose = { bones: { [boneName]: [x, y, z] },
    /// vrmVersion?: "0" | "1" }`, rest world positions of three-vrm's normalized bones in the
    /// model's own frame. Throws an `Error` naming the field on bad input.
    #[wasm_bindgen(constructor)]
    pub fn new(rest_pose: JsValue, options: JsValue) -> JsResult<HandRig> {
        let keys = Keys::new();
        if !rest_pose.is_object() {
            return Err(invalid(
                "restPose",
                "must be an object { bones: { [boneName]: [x, y, z] }, vrmVersion?: \"0\" | \"1\" }",
            ));
        }
        let version = match get(&rest_pose, &JsValue::from_str("vrmVersion")) {
            None => VrmVersion::V1,
            Some(v) => match v.as_string().as_deref().or(v.as_f64().map(|n| {
                if n == 0.0 {
                    "0"
                } else if n == 1.0 {
                    "1"
                } else {
                    "?"
                }
            })) {
                Some("0") => VrmVersion::V0,
                Some("1") => VrmVersion::V1,
                _ => return Err(invalid("restPose.vrmVersion", "must be \"0\" or \"1\"")),
            },
        };
        let bones_obj = get(&rest_pose, &keys.bones)
            .filter(|b| b.is_object())
            .ok_or_else(|| {
                invalid(
                    "restPose.bones",
                    "must be an object { [boneName]: [x, y, z] }",
                )
            })?;
        let entries = Object::entries(bones_obj.unchecked_ref());
        let mut bones = Vec::with_capacity(entries.length() as usize);
        for entry in entries.iter() {
            let pair: Array = entry.unchecked_into();
            let name = pair.get(0).as_string().unwrap_or_default();
            let bone = HumanBone::from_name(&name)
                .ok_or_else(|| js_err(Error::UnknownBone(name.clone())))?;
            let p = vec3(&pair.get(1), &keys, &|| format!("restPose.bones.{name}"))?;
            bones.push((bone, p));
        }
        let skeleton = Skeleton::new(&bones, version).map_err(js_err)?;
        Self::with_skeleton(skeleton, options, keys)
    }

    /// `HandRig.fromVrm(bytes, options?)`: reads a `.vrm` file (VRM 1.0 or 0.x) directly.
    #[wasm_bindgen(js_name = fromVrm)]
    pub fn from_vrm(bytes: &[u8], options: JsValue) -> JsResult<HandRig> {
        let skeleton = crate::vrm::load_skeleton(bytes).map_err(js_err)?;
        Self::with_skeleton(skeleton, options, Keys::new())
    }

    fn with_skeleton(skeleton: Skeleton, options: JsValue, keys: Keys) -> JsResult<HandRig> {
        let options: RigOptions = if options.is_undefined() || options.is_null() {
            RigOptions::default()
        } else {
            check_option_keys(&options)?;
            serde_wasm_bindgen::from_value(options)
                .map_err(|e| invalid("options", &e.to_string()))?
        };
        let rig = Rig::new(skeleton, options).map_err(js_err)?;
        Ok(HandRig {
            rig,
            frame: FrameInput::default(),
            out: SolveOutput::default(),
            keys,
        })
    }

    /// Every option with its path, type, range, default and description.
    #[wasm_bindgen(js_name = optionDescriptions)]
    pub fn option_descriptions() -> Array {
        use crate::rig::OptionKind;
        let s = |v: &str| JsValue::from_str(v);
        option_descriptions()
            .into_iter()
            .map(|d| {
                let o = Object::new();
                set(&o, &s("path"), &s(d.path));
                set(&o, &s("description"), &s(d.description));
                match d.kind {
                    OptionKind::Boolean { default } => {
                        set(&o, &s("type"), &s("boolean"));
                        set(&o, &s("default"), &JsValue::from_bool(default));
                    }
                    OptionKind::Enum { values, default } => {
                        set(&o, &s("type"), &s("enum"));
                        let v: Array = values.iter().map(|v| s(v)).collect();
                        set(&o, &s("values"), &v);
                        set(&o, &s("default"), &s(default));
                    }
                    OptionKind::Number {
                        min,
                        max,
                        default,
                        step,
                    } => {
                        set(&o, &s("type"), &s("number"));
                        set(&o, &s("min"), &JsValue::from_f64(min as f64));
                        set(&o, &s("max"), &JsValue::from_f64(max as f64));
                        set(&o, &s("step"), &JsValue::from_f64(step as f64));
                        let dv = default.map_or(JsValue::NULL, |v| JsValue::from_f64(v as f64));
                        set(&o, &s("default"), &dv);
                    }
                }
                JsValue::from(o)
            })
            .collect()
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

    /// The bones this avatar has, parent-first, VRM 1.0 names.
    #[wasm_bindgen(js_name = boneNames)]
    pub fn bone_names(&self) -> Array {
        self.rig
            .skeleton()
            .bones()
            .map(|b| self.keys.bone_names[b.index()].clone())
            .collect()
    }

    /// `{ [boneName]: [x, y, z] }`: rest world positions in the model's own frame.
    #[wasm_bindgen(js_name = restWorldPositions)]
    pub fn rest_world_positions(&self) -> Object {
        let o = Object::new();
        for b in self.rig.skeleton().bones() {
            if let Some(p) = self.rig.skeleton().rest_world(b) {
                self.set_position(&o, &self.keys.bone_names[b.index()], p);
            }
        }
        o
    }

    /// Solves one frame: `frame = { timeMs, hands?, pose?, wrists? }`. Returns `{ bones,
    /// worldPositions, ikTargets, alignment }` in the model's own frame. Throws an `Error`
    /// naming the field on bad input; the rig is unchanged by a rejected frame.
    pub fn solve(&mut self, frame: JsValue) -> JsResult<Object> {
        self.read_frame(&frame)?;
        self.rig.solve(&self.frame, &mut self.out).map_err(js_err)?;
        Ok(self.result())
    }

    fn read_frame(&mut self, frame: &JsValue) -> JsResult<()> {
        let keys = &self.keys;
        if !frame.is_object() {
            return Err(invalid(
                "frame",
                "must be an object { timeMs, hands?, pose?, wrists? }",
            ));
        }
        let f = &mut self.frame;
        f.clear();
        f.time_ms = match get(frame, &keys.time_ms) {
            Some(t) => t
                .as_f64()
                .filter(|t| t.is_finite())
                .ok_or_else(|| invalid("frame.timeMs", "must be a finite number"))?,
            None => 0.0,
        };
        let aspect = match get(frame, &keys.image_aspect) {
            Some(a) => {
                let a = number(&a, &|| "frame.imageAspect".into())?;
                if a <= 0.0 {
                    return Err(invalid(
                        "frame.imageAspect",
                        "must be positive (width / height)",
                    ));
                }
                a
            }
            None => 16.0 / 9.0,
        };
        read_hands(frame, keys, f, aspect)?;
        // Pose: `frame.pose` (handrig or PoseLandmarker shape) or legacy `poseWorldLandmarks`.
        let pose_src = get(frame, &keys.pose).map(|p| (p, "frame.pose"));
        let pose_src =
            pose_src.or_else(|| get(frame, &keys.pose_world_landmarks).map(|p| (p, "frame")));
        if let Some((p, name)) = pose_src {
            let list = if name == "frame" {
                p
            } else {
                get(&p, &keys.world_landmarks)
                    .or_else(|| get(&p, &keys.pose_world_landmarks))
                    .unwrap_or(p)
            };
            // PoseLandmarker: one list per person; take the first.
            let list = first_if_nested(&list);
            if let Some(list) = list {
                let mut pose = PoseObservation {
                    world: [Vec3::ZERO; POSE_LANDMARKS],
                    visibility: [1.0; POSE_LANDMARKS],
                };
                points(
                    &list,
                    keys,
                    &|| format!("{name}.worldLandmarks"),
                    &mut pose.world,
                    Some(&mut pose.visibility),
                )?;
                f.pose = Some(pose);
            }
        }
        if let Some(w) = get(frame, &keys.wrists) {
            for (side, key) in [(Side::Left, &keys.left), (Side::Right, &keys.right)] {
                let Some(wv) = get(&w, key) else { continue };
                let s = side.as_str();
                let pos = get(&wv, &keys.position).ok_or_else(|| {
                    invalid(
                        &format!("frame.wrists.{s}.position"),
                        "is missing (expected [x, y, z])",
                    )
                })?;
                let position = vec3(&pos, keys, &|| format!("frame.wrists.{s}.position"))?;
                let rotation = match get(&wv, &keys.rotation) {
                    Some(r) => Some(quat(&r, &|| format!("frame.wrists.{s}.rotation"))?),
                    None => None,
                };
                f.wrists[side.index()] = Some(WristObservation { position, rotation });
            }
        }
        Ok(())
    }

    /// `o[key] = p` as `[x, y, z]` in the model's own frame.
    fn set_position(&self, o: &Object, key: &JsValue, p: Vec3) {
        set(o, key, &vec3_js(self.rig.export_position(p)));
    }

    /// `o[key] = q` as `[x, y, z, w]` in the model's own frame.
    fn set_rotation(&self, o: &Object, key: &JsValue, q: Quat) {
        set(o, key, &quat_js(self.rig.export_rotation(q)));
    }

    fn result(&self) -> Object {
        let k = &self.keys;
        let out = &self.out;
        let skel = self.rig.skeleton();
        let result = Object::new();
        let bones = Object::new();
        let world = Object::new();
        for b in skel.bones() {
            let i = b.index();
            if out.solved[i] {
                self.set_rotation(&bones, &k.bone_names[i], out.local[i]);
            }
            self.set_position(&world, &k.bone_names[i], out.world.position[i]);
        }
        set(&result, &k.time_ms, &JsValue::from_f64(self.frame.time_ms));
        set(&result, &k.bones, &bones);
        set(&result, &k.world_positions, &world);
        let targets = Object::new();
        let alignment = Object::new();
        for side in Side::BOTH {
            let key = if side == Side::Left {
                &k.left
            } else {
                &k.right
            };
            if let Some(t) = &out.ik_targets[side.index()] {
                let o = Object::new();
                self.set_position(&o, &k.position, t.position);
                self.set_rotation(&o, &k.rotation, t.rotation);
                set(&targets, key, &o);
            }
            if let Some(a) = &out.alignment[side.index()] {
                let o = Object::new();
                self.set_position(&o, &k.target_dip, a.target_dip);
                self.set_position(&o, &k.ik_wrist, a.ik_wrist);
                self.set_position(&o, &k.pose_wrist, a.pose_wrist);
                let err = if a.error.is_finite() {
                    JsValue::from_f64(a.error as f64)
                } else {
                    JsValue::NULL
                };
                set(&o, &k.error, &err);
                set(&o, &k.reachable, &JsValue::from_bool(a.reachable));
                set(&o, &k.aligned, &JsValue::from_bool(a.aligned));
                set(&alignment, key, &o);
            }
        }
        let hands = Object::new();
        for side in Side::BOTH {
            let Some(h) = &out.hands[side.index()] else {
                continue;
            };
            let o = Object::new();
            let status = match h.status {
                HandStatus::Solved => &k.status_names[0],
                HandStatus::Held => &k.status_names[1],
                HandStatus::Skipped | HandStatus::NotSolved => &k.status_names[2],
            };
            set(&o, &k.status, status);
            set(&o, &k.score, &JsValue::from_f64(h.score as f64));
            set(
                &hands,
                if side == Side::Left {
                    &k.left
                } else {
                    &k.right
                },
                &o,
            );
        }
        set(&result, &k.ik_targets, &targets);
        set(&result, &k.alignment, &alignment);
        set(&result, &k.hands, &hands);
        result
    }
}

/// Rejects option names handrig does not know (serde-wasm-bindgen ignores them), so a typo
/// is an error rather than a silently ignored setting. Known names come from
/// [`option_descriptions`].
fn check_option_keys(options: &JsValue) -> JsResult<()> {
    if !options.is_object() || Array::is_array(options) {
        return Err(invalid("options", "must be an object"));
    }
    let descriptions = option_descriptions();
    let known = |prefix: &str, key: &str| {
        descriptions.iter().any(|d| {
            let path = d.path;
            match prefix {
                "" => path == key || path.strip_prefix(key).is_some_and(|r| r.starts_with('.')),
                p => path.strip_prefix(p).and_then(|r| r.strip_prefix('.')) == Some(key),
            }
        })
    };
    for key in Object::keys(options.unchecked_ref::<Object>()).iter() {
        let key = key.as_string().unwrap_or_default();
        if !known("", &key) {
            return Err(invalid(&format!("options.{key}"), "unknown option"));
        }
        let value = get(options, &JsValue::from_str(&key));
        if let Some(nested) = value.filter(|v| v.is_object() && !Array::is_array(v)) {
            for sub in Object::keys(nested.unchecked_ref::<Object>()).iter() {
                let sub = sub.as_string().unwrap_or_default();
                if !known(&key, &sub) {
                    return Err(invalid(&format!("options.{key}.{sub}"), "unknown option"));
                }
            }
        }
    }
    Ok(())
}

fn set(o: &Object, k: &JsValue, v: &JsValue) {
    // Setting a property on a plain object we created cannot fail.
    let _ = Reflect::set(o, k, v);
}

// One boundary crossing per vector (`Array.of`), not one per element: result building is most
// of the per-frame cost of the object API.
fn vec3_js(p: Vec3) -> JsValue {
    let c = |v: f32| JsValue::from_f64(v as f64);
    Array::of3(&c(p.x), &c(p.y), &c(p.z)).into()
}

fn quat_js(q: Quat) -> JsValue {
    let c = |v: f32| JsValue::from_f64(v as f64);
    Array::of4(&c(q.x), &c(q.y), &c(q.z), &c(q.w)).into()
}

/// `[[...points]]` (one list per person/hand) -> the first list; a flat list stays as is.
/// `None` for an empty outer list (nothing detected).
fn first_if_nested(v: &JsValue) -> Option<JsValue> {
    match v.dyn_ref::<Array>() {
        Some(a) if a.length() == 0 => None,
        Some(a)
            if Array::is_array(&a.get(0))
                && a.get(0)
                    .dyn_ref::<Array>()
                    .is_some_and(|i| i.length() > 0 && i.get(0).as_f64().is_none()) =>
        {
            Some(a.get(0))
        }
        _ => Some(v.clone()),
    }
}

fn read_hands(frame: &JsValue, keys: &Keys, f: &mut FrameInput, aspect: f32) -> JsResult<()> {
    // 1. handrig's own shape: frame.hands = [{ handedness, score?, worldLandmarks, landmarks? }]
    //    or frame.hands = a tasks-vision HandLandmarkerResult.
    if let Some(hands) = get(frame, &keys.hands) {
        if let Some(a) = hands.dyn_ref::<Array>() {
            if a.length() as usize > MAX_HANDS {
                return Err(invalid(
                    "frame.hands",
                    &format!("at most {MAX_HANDS} hands per frame, got {}", a.length()),
                ));
            }
            for (i, h) in a.iter().enumerate() {
                let field = || format!("frame.hands[{i}]");
                if !h.is_object() {
                    return Err(invalid(
                        &field(),
                        "must be an object { handedness, worldLandmarks }",
                    ));
                }
                let hv = get(&h, &keys.handedness).ok_or_else(|| {
                    invalid(
                        &format!("{}.handedness", field()),
                        "is missing (\"Left\" or \"Right\")",
                    )
                })?;
                let (label, label_score) =
                    handedness_label(&hv, keys, &|| format!("{}.handedness", field()))?;
                let score = match get(&h, &keys.score) {
                    Some(s) => number(&s, &|| format!("{}.score", field()))?,
                    None => label_score.unwrap_or(1.0),
                };
                push_hand(
                    get(&h, &keys.world_landmarks),
                    get(&h, &keys.landmarks),
                    &|| format!("{}.worldLandmarks", field()),
                    &|| format!("{}.landmarks", field()),
                    keys,
                    f,
                    empty_hand(label, score),
                    aspect,
                )?;
            }
            return Ok(());
        }
        if hands.is_object() {
            return read_result_shape(&hands, keys, f, "frame.hands", aspect);
        }
        return Err(invalid(
            "frame.hands",
            "must be an array of hands or a HandLandmarker result",
        ));
    }
    // 2. A MediaPipe result passed as the frame itself.
    read_result_shape(frame, keys, f, "frame", aspect)
}

/// tasks-vision `HandLandmarkerResult` ({ landmarks, worldLandmarks, handedness |
/// handednesses }), legacy Hands ({ multiHandLandmarks, multiHandWorldLandmarks,
/// multiHandedness }) or legacy Holistic ({ leftHandLandmarks, rightHandLandmarks }).
fn read_result_shape(
    r: &JsValue,
    keys: &Keys,
    f: &mut FrameInput,
    name: &str,
    aspect: f32,
) -> JsResult<()> {
    let (world_key, image_key, label_key, label_name) = if get(r, &keys.multi_handedness).is_some()
    {
        (
            &keys.multi_hand_world_landmarks,
            &keys.multi_hand_landmarks,
            &keys.multi_handedness,
            "multiHandedness",
        )
    } else if let Some(_h) = get(r, &keys.handedness) {
        (
            &keys.world_landmarks,
            &keys.landmarks,
            &keys.handedness,
            "handedness",
        )
    } else if get(r, &keys.handednesses).is_some() {
        (
            &keys.world_landmarks,
            &keys.landmarks,
            &keys.handednesses,
            "handednesses",
        )
    } else {
        // Holistic legacy: image landmarks per side, labelled like MediaPipe's hand labels
        // (rotations from image landmarks differ from world-landmark ones by up to ~30 degrees).
        for (key, label, lname) in [
            (
                &keys.left_hand_landmarks,
                Handedness::Left,
                "leftHandLandmarks",
            ),
            (
                &keys.right_hand_landmarks,
                Handedness::Right,
                "rightHandLandmarks",
            ),
        ] {
            if let Some(list) = get(r, key) {
                let field = || format!("{name}.{lname}");
                let hand = empty_hand(label, 1.0);
                push_hand(None, Some(list), &field, &field, keys, f, hand, aspect)?;
            }
        }
        return Ok(());
    };
    let labels = get(r, label_key)
        .and_then(|l| l.dyn_into::<Array>().ok())
        .ok_or_else(|| invalid(&format!("{name}.{label_name}"), "must be an array"))?;
    let world = get(r, world_key).and_then(|l| l.dyn_into::<Array>().ok());
    let image = get(r, image_key).and_then(|l| l.dyn_into::<Array>().ok());
    let n = labels.length() as usize;
    if n > MAX_HANDS {
        return Err(invalid(
            &format!("{name}.{label_name}"),
            &format!("at most {MAX_HANDS} hands per frame, got {n}"),
        ));
    }
    for i in 0..n {
        let field = || format!("{name}.{label_name}[{i}]");
        let (label, score) = handedness_label(&labels.get(i as u32), keys, &field)?;
        let world_list = world
            .as_ref()
            .map(|w| w.get(i as u32))
            .filter(|v| !v.is_undefined());
        let image_list = image
            .as_ref()
            .map(|w| w.get(i as u32))
            .filter(|v| !v.is_undefined());
        push_hand(
            world_list,
            image_list,
            &|| format!("{name}.worldLandmarks[{i}]"),
            &|| format!("{name}.landmarks[{i}]"),
            keys,
            f,
            empty_hand(label, score.unwrap_or(1.0)),
            aspect,
        )?;
    }
    Ok(())
}

fn empty_hand(label: Handedness, score: f32) -> HandObservation {
    HandObservation {
        handedness: label,
        score,
        world: [Vec3::ZERO; HAND_LANDMARKS],
        image: None,
    }
}

/// Reads one hand's world and image landmarks (either may be absent, not both) into the next
/// slot of `f.hands`. Without world landmarks the image ones stand in, see
/// [`image_to_pseudo_world`].
#[allow(clippy::too_many_arguments)]
fn push_hand(
    world: Option<JsValue>,
    image: Option<JsValue>,
    world_field: &dyn Fn() -> String,
    image_field: &dyn Fn() -> String,
    keys: &Keys,
    f: &mut FrameInput,
    mut hand: HandObservation,
    aspect: f32,
) -> JsResult<()> {
    if let Some(img) = image {
        let mut p = [Vec3::ZERO; HAND_LANDMARKS];
        points(&img, keys, image_field, &mut p, None)?;
        hand.image = Some(p);
    }
    match (world, hand.image) {
        (Some(w), _) => points(&w, keys, world_field, &mut hand.world, None)?,
        (None, Some(img)) => {
            hand.world = img;
            image_to_pseudo_world(&mut hand.world, aspect);
        }
        (None, None) => {
            return Err(invalid(
                &world_field(),
                "is missing (21 points [x, y, z] in meters, or image landmarks)",
            ))
        }
    }
    f.hands[f.hand_count] = hand;
    f.hand_count += 1;
    Ok(())
}
