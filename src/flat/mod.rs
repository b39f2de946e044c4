//! The flat frame layout: one frame's input and output as fixed arrays of `f32`, so a caller
//! can exchange them with [`crate::Rig`] without building any object per frame.
//!
//! This is what the npm package's typed-array path is made of (rapier.js style): the rig owns
//! one input and one output buffer in wasm memory, JavaScript writes the input and reads the
//! output through `Float32Array` views, and nothing is allocated or serialized per frame. The
//! object API (`rig.solve(frame)`) is a thin JavaScript layer that packs MediaPipe shapes into
//! the same input and builds its result from the same output, so the two paths cannot drift.
//!
//! Offsets are the constants of [`input`] and [`output`], declared once in [`layout`] (exported
//! to JavaScript as `LAYOUT`); [`VERSION`] changes whenever an offset changes. Conventions as everywhere: the
//! output is in **the model's own frame** (VRM 0.x outputs are turned back), quaternions
//! `x y z w`, meters. Hand landmarks are MediaPipe's, in MediaPipe's axes, as given.
//!
//! Flags are numbers: `0` for no or absent, `1` for yes or present (anything else in an input
//! flag is an error). Unused slots (hands past `HAND_COUNT`, absent sections) are ignored.

use glam::{Quat, Vec3};

use crate::error::{Error, Num, Result};
use crate::hand::HandStatus;
use crate::humanoid::bones::{HumanBone, Side};
use crate::input::mediapipe::{
    FrameInput, HandObservation, Handedness, PoseObservation, TrackerFace, WristObservation,
    HAND_LANDMARKS, MAX_HANDS, POSE_LANDMARKS,
};
use crate::input::torso::{BodyJoint, BodyObservation, BODY_JOINT_COUNT, TORSO_BONES};
use crate::input::validate::validate_frame_with;
use crate::pipeline::{HandCheck, HandResolved, HandUse, Rig, SolveOutput};

mod declare;
#[cfg(not(target_arch = "wasm32"))]
pub mod generated;
pub mod layout;

pub use declare::{Detail, Row, RowKind};
pub use layout::{input, output, VERSION};

/// The names of `output.side.handStatus`'s codes, indexed by code (`LAYOUT.handStatus`; 0: no
/// hand this frame): what the JS result's `hand.status` reads.
pub const HAND_STATUS_NAMES: [&str; 4] = ["none", "solved", "held", "skipped"];

/// The names of `output.side.handCheck`'s codes (JavaScript's `LAYOUT.handCheck`).
pub const HAND_CHECK_NAMES: [&str; 2] = ["good", "mirrored"];

/// The names of `output.side.handResolved`'s codes (JavaScript's `LAYOUT.handResolved`; 0:
/// nothing resolved, or no hand).
pub const HAND_RESOLVED_NAMES: [&str; 4] = ["none", "swapped", "jumped", "duplicate"];

/// The names of `output.handUse`'s codes, indexed by code (`LAYOUT.handUse`; 0: no such hand):
/// what became of each tracked hand, as the JS result's `handUse` reads it.
pub const HAND_USE_NAMES: [&str; 6] = [
    "none",
    "left",
    "right",
    "lowScore",
    "duplicate",
    "contradicted",
];

/// The code of `name` in `names` (the tables above), as the output stores it.
const fn code(names: &[&str], name: &str) -> f32 {
    let mut k = 0;
    while k < names.len() {
        if const_str_eq(names[k], name) {
            return k as f32;
        }
        k += 1;
    }
    panic!("no such code name")
}

const fn const_str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Every named offset of the layout as `(path, value)` (JavaScript's `LAYOUT`, nested by the
/// dotted paths): [`layout`]'s rows.
pub fn fields() -> impl Iterator<Item = (&'static str, usize)> {
    layout::rows().map(|r| (r.path, r.offset))
}

/// A flag slot: exactly `0` or `1`.
fn flag(buf: &[f32], at: usize, field: impl FnOnce() -> String) -> Result<bool> {
    match buf[at] {
        0.0 => Ok(false),
        1.0 => Ok(true),
        _ => Err(Error::invalid(field(), "must be 0 or 1")),
    }
}

fn vec3_at(buf: &[f32], at: usize) -> Vec3 {
    Vec3::new(buf[at], buf[at + 1], buf[at + 2])
}

pub use crate::input::validate::HAND_SPAN_LIMIT;

/// Reads `N` points of `stride` floats at `at` (the first three are `x y z`), unchecked (the
/// shared validation checks them).
fn points<const N: usize>(buf: &[f32], at: usize, stride: usize, out: &mut [Vec3; N]) {
    for (k, p) in out.iter_mut().enumerate() {
        *p = vec3_at(buf, at + k * stride);
    }
}

/// A quaternion `x y z w` at `at`, unchecked.
fn quat_at(buf: &[f32], at: usize) -> Quat {
    Quat::from_xyzw(buf[at], buf[at + 1], buf[at + 2], buf[at + 3])
}

/// Decodes a flat input array into `frame` (reused: nothing is allocated unless the input is
/// rejected). The layout's own slots (length, flags, hand count, handedness, image aspect)
/// are checked here; every number then goes through the same validation as a native frame
/// ([`crate::input::validate`]). Errors name the field as the object API spells it
/// (`frame.hands[1].worldLandmarks[7]`), and `frame` is left cleared on error.
///
/// # Errors
/// Wrong length, a flag other than 0 or 1, a hand count out of range, non-finite numbers,
/// landmarks beyond [`crate::input::COORDINATE_LIMIT`], a hand's world landmarks more than
/// [`HAND_SPAN_LIMIT`] from its wrist, an image aspect outside `0.01..=100`, scores,
/// visibilities or confidences outside `0..=1`, non-unit wrist or torso rotations.
pub fn read_input(buf: &[f32], time_ms: f64, frame: &mut FrameInput) -> Result<()> {
    frame.clear();
    let r = read_input_inner(buf, time_ms, frame);
    if r.is_err() {
        frame.clear();
    }
    r
}

fn read_input_inner(buf: &[f32], time_ms: f64, frame: &mut FrameInput) -> Result<()> {
    if buf.len() != input::LEN {
        return Err(Error::invalid(
            "input",
            format!(
                "must have {} numbers (layout version {VERSION}), got {}",
                input::LEN,
                buf.len()
            ),
        ));
    }
    frame.time_ms = time_ms;
    let count = buf[input::HAND_COUNT];
    if !(count >= 0.0 && count <= MAX_HANDS as f32 && count.fract() == 0.0) {
        return Err(Error::invalid(
            "frame.hands",
            format!(
                "hand count must be a whole number in 0..={MAX_HANDS}, got {}",
                Num::f32(count)
            ),
        ));
    }
    let aspect = match buf[input::IMAGE_ASPECT] {
        0.0 => 16.0 / 9.0,
        // Image landmarks are scaled by it: a frame is not 100 times wider than high.
        a if (0.01..=100.0).contains(&a) => a,
        _ => {
            return Err(Error::invalid(
                "frame.imageAspect",
                "must be a number in 0.01..100 (width / height)",
            ))
        }
    };
    frame.image_aspect = aspect;
    // Which hands' world landmarks are given as meters (the others are made from image
    // landmarks below).
    let mut metric_world = [false; MAX_HANDS];
    frame.world_from_image = [false; MAX_HANDS];
    for (i, metric) in metric_world.iter_mut().enumerate().take(count as usize) {
        let at = input::HANDS + i * input::HAND_STRIDE;
        let name = |f: &str| format!("frame.hands[{i}]{f}");
        let handedness = match buf[at + input::hand::HANDEDNESS] {
            0.0 => Handedness::Left,
            1.0 => Handedness::Right,
            _ => {
                return Err(Error::invalid(
                    name(".handedness"),
                    "must be 0 (\"Left\") or 1 (\"Right\")",
                ))
            }
        };
        let has_world = flag(buf, at + input::hand::HAS_WORLD, || name(".hasWorld"))?;
        let has_image = flag(buf, at + input::hand::HAS_IMAGE, || name(".hasImage"))?;
        let mut hand = HandObservation {
            handedness,
            score: buf[at + input::hand::SCORE],
            world: [Vec3::ZERO; HAND_LANDMARKS],
            image: None,
        };
        if has_image {
            let mut image = [Vec3::ZERO; HAND_LANDMARKS];
            points(buf, at + input::hand::IMAGE, 3, &mut image);
            hand.image = Some(image);
        }
        match (has_world, hand.image) {
            (true, _) => {
                points(buf, at + input::hand::WORLD, 3, &mut hand.world);
                *metric = true;
            }
            (false, Some(image)) => {
                // The image landmarks must be valid before they are turned into points.
                if let Some((k, e)) = crate::input::validate::points_problem(&image) {
                    return Err(Error::invalid(name(&format!(".landmarks[{k}]")), e));
                }
                hand.world = image;
                crate::input::mediapipe::image_to_pseudo_world(&mut hand.world, aspect);
                frame.world_from_image[i] = true;
                if hand.world.iter().any(|p| !p.is_finite()) {
                    return Err(Error::invalid(
                        name(".landmarks"),
                        "image landmarks too large to use",
                    ));
                }
            }
            (false, None) => {
                return Err(Error::invalid(
                    name(".worldLandmarks"),
                    "is missing (21 points [x, y, z] in meters, or image landmarks)",
                ))
            }
        }
        frame.hands[i] = hand;
        frame.hand_count = i + 1;
    }
    if flag(buf, input::POSE_PRESENT, || "frame.pose".into())? {
        let mut pose = PoseObservation {
            world: [Vec3::ZERO; POSE_LANDMARKS],
            visibility: [1.0; POSE_LANDMARKS],
        };
        points(buf, input::POSE, input::POSE_STRIDE, &mut pose.world);
        for (k, v) in pose.visibility.iter_mut().enumerate() {
            *v = buf[input::POSE + k * input::POSE_STRIDE + 3];
        }
        frame.pose = Some(pose);
        if flag(buf, input::POSE_HAS_IMAGE, || "frame.pose.landmarks".into())? {
            let mut image = [Vec3::ZERO; POSE_LANDMARKS];
            points(buf, input::POSE_IMAGE, 3, &mut image);
            frame.pose_image = Some(image);
        }
    }
    for side in Side::BOTH {
        let at = input::WRISTS + side.index() * input::WRIST_STRIDE;
        let name = |f: &str| format!("frame.wrists.{}{f}", side.as_str());
        if !flag(buf, at + input::wrist::PRESENT, || name(""))? {
            continue;
        }
        let position = vec3_at(buf, at + input::wrist::POSITION);
        let rotation = flag(buf, at + input::wrist::HAS_ROTATION, || name(".rotation"))?
            .then(|| quat_at(buf, at + input::wrist::ROTATION));
        frame.wrists[side.index()] = Some(WristObservation { position, rotation });
    }
    for (slot, bone) in TORSO_BONES.iter().enumerate() {
        let at = input::TORSO + slot * input::TORSO_STRIDE;
        if flag(buf, at + input::torso_bone::PRESENT, || {
            format!("frame.torso.{bone}")
        })? {
            frame.torso[slot] = Some(quat_at(buf, at + input::torso_bone::ROTATION));
        }
    }
    if flag(buf, input::BODY_PRESENT, || "frame.body".into())? {
        let mut body = BodyObservation::default();
        for joint in BodyJoint::ALL {
            let k = joint.index();
            let at = input::BODY + k * input::BODY_STRIDE;
            body.position[k] = vec3_at(buf, at);
            body.confidence[k] = buf[at + 3];
        }
        frame.body = Some(body);
    }
    let mut face = TrackerFace::default();
    for k in 0..TrackerFace::POINTS {
        let at = input::FACE + k * input::FACE_STRIDE;
        let name = || format!("frame.face.{}", TrackerFace::NAMES[k]);
        if flag(buf, at + input::face_point::PRESENT, name)? {
            face.set_point(k, Some(vec3_at(buf, at + input::face_point::POSITION)));
        }
    }
    if !face.is_empty() {
        frame.face = Some(face);
    }
    read_face_tracking(buf, frame)?;
    // Every number: the same check as a native frame.
    validate_frame_with(frame, metric_world)?;
    // The rotations were checked to be unit within 1e-2: make them exactly unit.
    for w in frame.wrists.iter_mut().flatten() {
        w.rotation = w.rotation.map(Quat::normalize);
    }
    for q in frame.torso.iter_mut().flatten() {
        *q = q.normalize();
    }
    Ok(())
}

/// The face tracker's face (issue 50).
fn read_face_tracking(buf: &[f32], frame: &mut FrameInput) -> Result<()> {
    use crate::face::{FaceObservation, MESH_POINTS, SHAPES};
    // (the npm package writes only 0 and 1 here)
    let on = |at: usize| buf[at] == 1.0;
    if !on(input::FACE_TRACKED) {
        return Ok(());
    }
    let mut face = FaceObservation {
        shapes: None,
        matrix: None,
        mesh: None,
    };
    if flag(buf, input::FACE_HAS_SHAPES, || {
        "frame.faceBlendshapes".into()
    })? {
        let mut s = [0.0; SHAPES];
        s.copy_from_slice(&buf[input::FACE_SHAPES..input::FACE_SHAPES + SHAPES]);
        face.shapes = Some(s);
    }
    if on(input::FACE_HAS_MATRIX) {
        let mut m = [0.0; 16];
        m.copy_from_slice(&buf[input::FACE_MATRIX..input::FACE_MATRIX + 16]);
        face.matrix = Some(m);
    }
    if on(input::FACE_HAS_MESH) {
        let mut p = [Vec3::ZERO; MESH_POINTS];
        points(buf, input::FACE_MESH, 3, &mut p);
        face.mesh = Some(p);
    }
    frame.face_tracking = Some(face);
    Ok(())
}

fn put_vec3(buf: &mut [f32], at: usize, v: Vec3) {
    buf[at..at + 3].copy_from_slice(&v.to_array());
}

fn put_quat(buf: &mut [f32], at: usize, q: Quat) {
    buf[at..at + 4].copy_from_slice(&q.to_array());
}

fn put_flag(buf: &mut [f32], at: usize, on: bool) {
    buf[at] = if on { 1.0 } else { 0.0 };
}

/// Writes `out` (from [`Rig::solve`] on `rig`, already in the model's own frame) into a flat
/// output array. Allocates nothing.
///
/// # Panics
/// When `buf` is shorter than [`output::LEN`] (a caller bug, not an input problem).
pub fn write_output(rig: &Rig, out: &SolveOutput, buf: &mut [f32]) {
    let skeleton = rig.skeleton();
    for bone in HumanBone::ALL {
        let i = bone.index();
        // (the face turns the neck and head in frames with a face: issue 50)
        let face_turned = out.face.head && matches!(bone, HumanBone::Neck | HumanBone::Head);
        let driven = skeleton.has(bone) && (rig.drives(bone) || face_turned);
        let q = if driven { out.local[i] } else { Quat::IDENTITY };
        put_quat(buf, output::BONE_ROTATIONS + 4 * i, q);
        buf[output::BONE_FLAGS + i] = match (driven, out.solved[i]) {
            (false, _) => 0.0,
            (true, true) => 1.0,
            (true, false) => 2.0,
        };
        put_vec3(buf, output::BONE_POSITIONS + 3 * i, out.world.position[i]);
    }
    for side in Side::BOTH {
        let at = output::SIDES + side.index() * output::SIDE_STRIDE;
        let s = side.index();
        let (status, score) = match &out.hands[s] {
            None => (const { code(&HAND_STATUS_NAMES, "none") }, 0.0),
            Some(h) => (
                match h.status {
                    HandStatus::Solved => const { code(&HAND_STATUS_NAMES, "solved") },
                    HandStatus::Held => const { code(&HAND_STATUS_NAMES, "held") },
                    HandStatus::Skipped | HandStatus::NotSolved => {
                        const { code(&HAND_STATUS_NAMES, "skipped") }
                    }
                },
                h.score,
            ),
        };
        buf[at + output::side::HAND_STATUS] = status;
        buf[at + output::side::HAND_SCORE] = score;
        let target = out.ik_targets[s];
        put_flag(buf, at + output::side::TARGET_PRESENT, target.is_some());
        let t = target.unwrap_or(crate::pipeline::IkTarget {
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        });
        put_vec3(buf, at + output::side::TARGET_POSITION, t.position);
        put_quat(buf, at + output::side::TARGET_ROTATION, t.rotation);
        let a = out.alignment[s];
        put_flag(buf, at + output::side::ALIGNMENT_PRESENT, a.is_some());
        let (dip, ik, pose, error, reachable, aligned) = a.map_or(
            (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, f32::NAN, false, false),
            |a| {
                (
                    a.target_dip,
                    a.ik_wrist,
                    a.pose_wrist,
                    a.error,
                    a.reachable,
                    a.aligned,
                )
            },
        );
        put_vec3(buf, at + output::side::TARGET_DIP, dip);
        put_vec3(buf, at + output::side::IK_WRIST, ik);
        put_vec3(buf, at + output::side::POSE_WRIST, pose);
        buf[at + output::side::ALIGNMENT_ERROR] = if error.is_finite() { error } else { f32::NAN };
        put_flag(buf, at + output::side::REACHABLE, reachable);
        put_flag(buf, at + output::side::ALIGNED, aligned);
        let configured = rig.options().alignment.finger;
        buf[at + output::side::ALIGNED_BONE] = match a {
            Some(a) if !a.part.is_configured(configured) => 1.0 + a.part.bone(side).index() as f32,
            _ => 0.0,
        };
        let (index, reassigned) =
            out.hands[s].map_or((-1.0, false), |h| (h.index as f32, h.reassigned));
        buf[at + output::side::HAND_INDEX] = index;
        put_flag(buf, at + output::side::HAND_REASSIGNED, reassigned);
        let (confidence, check) =
            out.hands[s].map_or((0.0, HandCheck::Good), |h| (h.confidence, h.check));
        buf[at + output::side::HAND_CONFIDENCE] = confidence;
        buf[at + output::side::HAND_CHECK] = match check {
            HandCheck::Good => const { code(&HAND_CHECK_NAMES, "good") },
            HandCheck::Mirrored => const { code(&HAND_CHECK_NAMES, "mirrored") },
        };
        let resolved = out.hands[s].map_or(HandResolved::None, |h| h.resolved);
        buf[at + output::side::HAND_RESOLVED] = match resolved {
            HandResolved::None => const { code(&HAND_RESOLVED_NAMES, "none") },
            HandResolved::Swapped => const { code(&HAND_RESOLVED_NAMES, "swapped") },
            HandResolved::Jumped => const { code(&HAND_RESOLVED_NAMES, "jumped") },
            HandResolved::Duplicate => const { code(&HAND_RESOLVED_NAMES, "duplicate") },
        };
        let point = |p: Option<Vec3>| p.map_or(Vec3::NAN, |p| p);
        for (f, tip) in out.fingertips[s].iter().enumerate() {
            put_vec3(buf, at + output::side::FINGERTIPS + 3 * f, point(*tip));
        }
        let r = out.retarget[s];
        put_flag(buf, at + output::side::RETARGET_PRESENT, r.is_some());
        for f in 0..5 {
            let t = r.and_then(|r| r.targets[f]);
            put_vec3(buf, at + output::side::RETARGET_TARGETS + 3 * f, point(t));
        }
        let (scale, iterations, residual) = r.map_or((0.0, 0.0, 0.0), |r| {
            (r.scale, r.iterations as f32, r.residual)
        });
        buf[at + output::side::RETARGET_SCALE] = scale;
        buf[at + output::side::RETARGET_ITERATIONS] = iterations;
        buf[at + output::side::RETARGET_RESIDUAL] = residual;
        let c = out.contact[s];
        put_flag(buf, at + output::side::CONTACT_PRESENT, c.is_some());
        let c = c.unwrap_or_default();
        buf[at + output::side::CONTACT_ANCHOR] = c.anchor.map_or(-1.0, |a| a.index() as f32);
        buf[at + output::side::CONTACT_WEIGHT] = c.weight;
        buf[at + output::side::CONTACT_DISTANCE] = if c.distance.is_finite() {
            c.distance
        } else {
            f32::NAN
        };
        buf[at + output::side::CONTACT_HAND_WEIGHT] = c.hand_weight;
        buf[at + output::side::CONTACT_PUSH] = c.push;
    }
    for (slot, using) in out.hand_use.iter().enumerate() {
        buf[output::HAND_USE + slot] = match using {
            HandUse::Unused => const { code(&HAND_USE_NAMES, "none") },
            HandUse::Drove(Side::Left) => const { code(&HAND_USE_NAMES, "left") },
            HandUse::Drove(Side::Right) => const { code(&HAND_USE_NAMES, "right") },
            HandUse::LowScore => const { code(&HAND_USE_NAMES, "lowScore") },
            HandUse::Duplicate => const { code(&HAND_USE_NAMES, "duplicate") },
            HandUse::Contradicted => const { code(&HAND_USE_NAMES, "contradicted") },
        };
    }
    // The face (issue 50).
    let face = &out.face;
    buf[output::FACE_STATE] = f32::from(face.state);
    buf[output::EXPRESSIONS..output::EXPRESSIONS + face.presets.len()]
        .copy_from_slice(&face.presets);
    buf[output::ARKIT..output::ARKIT + face.arkit.len()].copy_from_slice(&face.arkit);
    buf[output::LOOK_AT..output::LOOK_AT + 2].copy_from_slice(&face.look_at);
    // Legs (issue 51).
    put_vec3(buf, output::HIPS_OFFSET, out.hips_offset);
    for (k, planted) in out.planted.iter().enumerate() {
        buf[output::FEET_PLANTED + k] = f32::from(u8::from(*planted));
    }
}

/// Packs `frame` into a flat input array (the inverse of [`read_input`], for native callers
/// and tests; the npm package packs in JavaScript). Allocates nothing.
///
/// # Panics
/// When `buf` is shorter than [`input::LEN`].
pub fn write_input(frame: &FrameInput, buf: &mut [f32]) {
    buf[..input::LEN].fill(0.0);
    buf[input::HAND_COUNT] = frame.hands().len() as f32;
    for (i, h) in frame.hands().iter().enumerate() {
        let at = input::HANDS + i * input::HAND_STRIDE;
        buf[at + input::hand::HANDEDNESS] = match h.handedness {
            Handedness::Left => 0.0,
            Handedness::Right => 1.0,
        };
        buf[at + input::hand::SCORE] = h.score;
        buf[at + input::hand::HAS_WORLD] = 1.0;
        for (k, p) in h.world.iter().enumerate() {
            put_vec3(buf, at + input::hand::WORLD + 3 * k, *p);
        }
        if let Some(image) = &h.image {
            buf[at + input::hand::HAS_IMAGE] = 1.0;
            for (k, p) in image.iter().enumerate() {
                put_vec3(buf, at + input::hand::IMAGE + 3 * k, *p);
            }
        }
    }
    if let Some(pose) = &frame.pose {
        buf[input::POSE_PRESENT] = 1.0;
        for k in 0..POSE_LANDMARKS {
            let at = input::POSE + k * input::POSE_STRIDE;
            put_vec3(buf, at, pose.world[k]);
            buf[at + 3] = pose.visibility[k];
        }
        if let Some(image) = &frame.pose_image {
            buf[input::POSE_HAS_IMAGE] = 1.0;
            for (k, p) in image.iter().enumerate() {
                put_vec3(buf, input::POSE_IMAGE + 3 * k, *p);
            }
        }
    }
    for side in Side::BOTH {
        let Some(w) = &frame.wrists[side.index()] else {
            continue;
        };
        let at = input::WRISTS + side.index() * input::WRIST_STRIDE;
        buf[at + input::wrist::PRESENT] = 1.0;
        put_vec3(buf, at + input::wrist::POSITION, w.position);
        if let Some(q) = w.rotation {
            buf[at + input::wrist::HAS_ROTATION] = 1.0;
            put_quat(buf, at + input::wrist::ROTATION, q);
        }
    }
    for (slot, q) in frame.torso.iter().enumerate() {
        if let Some(q) = q {
            let at = input::TORSO + slot * input::TORSO_STRIDE;
            buf[at + input::torso_bone::PRESENT] = 1.0;
            put_quat(buf, at + input::torso_bone::ROTATION, *q);
        }
    }
    if let Some(body) = &frame.body {
        buf[input::BODY_PRESENT] = 1.0;
        for k in 0..BODY_JOINT_COUNT {
            let at = input::BODY + k * input::BODY_STRIDE;
            put_vec3(buf, at, body.position[k]);
            buf[at + 3] = body.confidence[k];
        }
    }
    if let Some(face) = &frame.face {
        for k in 0..TrackerFace::POINTS {
            if let Some(p) = face.point(k) {
                let at = input::FACE + k * input::FACE_STRIDE;
                buf[at + input::face_point::PRESENT] = 1.0;
                put_vec3(buf, at + input::face_point::POSITION, p);
            }
        }
    }
    if let Some(face) = &frame.face_tracking {
        buf[input::FACE_TRACKED] = 1.0;
        if let Some(s) = &face.shapes {
            buf[input::FACE_HAS_SHAPES] = 1.0;
            buf[input::FACE_SHAPES..input::FACE_SHAPES + s.len()].copy_from_slice(s);
        }
        if let Some(m) = &face.matrix {
            buf[input::FACE_HAS_MATRIX] = 1.0;
            buf[input::FACE_MATRIX..input::FACE_MATRIX + 16].copy_from_slice(m);
        }
        if let Some(mesh) = &face.mesh {
            buf[input::FACE_HAS_MESH] = 1.0;
            for (k, p) in mesh.iter().enumerate() {
                put_vec3(buf, input::FACE_MESH + 3 * k, *p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every named offset lies inside its buffer, and no name is used twice.
    #[test]
    fn fields_fit_their_buffers_and_strides() {
        let all: Vec<(&str, usize)> = fields().collect();
        for &(name, v) in &all {
            let len = if name.starts_with("input") {
                input::LEN
            } else {
                output::LEN
            };
            assert!(v <= len, "{name} = {v} beyond {len}");
        }
        let mut names: Vec<&str> = all.iter().map(|(n, _)| *n).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all.len(), "duplicate field name");
    }

    #[test]
    fn rejects_a_wrong_length_and_bad_flags() {
        let mut frame = FrameInput::default();
        let e = read_input(&[0.0; 3], 0.0, &mut frame).unwrap_err();
        assert!(e.to_string().starts_with("input: must have"), "{e}");
        let mut buf = vec![0.0; input::LEN];
        buf[input::POSE_PRESENT] = 0.5;
        let e = read_input(&buf, 0.0, &mut frame).unwrap_err();
        assert_eq!(e.to_string(), "frame.pose: must be 0 or 1");
        buf[input::POSE_PRESENT] = 0.0;
        buf[input::HAND_COUNT] = 5.0;
        let e = read_input(&buf, 0.0, &mut frame).unwrap_err();
        assert!(e.to_string().starts_with("frame.hands: hand count"), "{e}");
        buf[input::HAND_COUNT] = f32::NAN;
        assert!(read_input(&buf, 0.0, &mut frame).is_err());
        buf[input::HAND_COUNT] = 0.0;
        assert!(read_input(&buf, f64::INFINITY, &mut frame).is_err());
        read_input(&buf, 5.0, &mut frame).unwrap();
        assert_eq!(frame.time_ms, 5.0);
    }

    #[test]
    fn a_frame_round_trips_and_a_bad_number_is_named() {
        let mut frame = FrameInput {
            time_ms: 12.5,
            hand_count: 2,
            ..FrameInput::default()
        };
        for (i, h) in frame.hands.iter_mut().take(2).enumerate() {
            h.handedness = if i == 0 {
                Handedness::Right
            } else {
                Handedness::Left
            };
            h.score = 0.75;
            // Meters around the hand, as MediaPipe gives them (not image-normalized).
            for (k, p) in h.world.iter_mut().enumerate() {
                *p = Vec3::new(k as f32 * 0.01, 0.1 * i as f32, -0.02 * k as f32 - 0.01);
            }
        }
        frame.hands[1].image = Some([Vec3::splat(0.5); HAND_LANDMARKS]);
        let mut pose = PoseObservation {
            world: [Vec3::ONE; POSE_LANDMARKS],
            visibility: [0.25; POSE_LANDMARKS],
        };
        pose.world[3] = Vec3::new(1.0, 2.0, 3.0);
        frame.pose = Some(pose);
        frame.wrists[1] = Some(WristObservation {
            position: Vec3::new(0.1, 0.2, 0.3),
            rotation: Some(Quat::from_rotation_y(0.5)),
        });
        frame.torso[1] = Some(Quat::from_rotation_x(0.25));
        frame.torso[5] = Some(Quat::from_rotation_y(-0.5));
        let mut body = BodyObservation::default();
        body.position[3] = Vec3::new(0.2, 1.4, 0.05);
        body.confidence[3] = 0.6;
        frame.body = Some(body);
        frame.face = Some(TrackerFace {
            nose: Some(Vec3::new(0.0, 1.6, 0.1)),
            ears: [Some(Vec3::new(0.07, 1.62, 0.0)), None],
            ..TrackerFace::default()
        });
        let mut buf = vec![0.0; input::LEN];
        write_input(&frame, &mut buf);
        let mut back = FrameInput::default();
        read_input(&buf, 12.5, &mut back).unwrap();
        assert_eq!(back, frame);

        let k = input::HANDS + input::HAND_STRIDE + input::hand::WORLD + 7 * 3 + 1;
        let was = buf[k];
        buf[k] = f32::NAN;
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame.hands[1].worldLandmarks[7]: must be three finite numbers"
        );
        assert_eq!(
            back.hand_count, 0,
            "a rejected frame leaves the input cleared"
        );
        buf[k] = was;

        let q = input::TORSO + 5 * input::TORSO_STRIDE + input::torso_bone::ROTATION;
        buf[q + 3] = 2.0;
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame.torso.head: must be a unit quaternion [x, y, z, w]"
        );
        buf[q + 3] = Quat::from_rotation_y(-0.5).w;
        let c = input::BODY + 3 * input::BODY_STRIDE + 3;
        buf[c] = 1.5;
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame.body.leftUpperArm.confidence: must be a number in 0..1"
        );
        buf[c] = 0.6;
        buf[input::TORSO + input::torso_bone::PRESENT] = 2.0;
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(e.to_string(), "frame.torso.hips: must be 0 or 1");
        buf[input::TORSO + input::torso_bone::PRESENT] = 0.0;
        read_input(&buf, 0.0, &mut back).unwrap();
        assert_eq!(back.torso, frame.torso);
        assert_eq!(back.body, frame.body);
        let ear = input::FACE + 3 * input::FACE_STRIDE + input::face_point::POSITION + 2;
        buf[ear] = f32::INFINITY;
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame.face.leftEar: must be three finite numbers"
        );
        buf[ear] = 0.0;

        // The image aspect scales image landmarks: 0.01..100.
        let aspect = input::IMAGE_ASPECT;
        for (value, ok) in [(0.01, true), (100.0, true), (0.009, false), (101.0, false)] {
            buf[aspect] = value;
            let r = read_input(&buf, 0.0, &mut back);
            assert_eq!(r.is_ok(), ok, "aspect {value}: {r:?}");
            if let Err(e) = r {
                assert_eq!(
                    e.to_string(),
                    "frame.imageAspect: must be a number in 0.01..100 (width / height)"
                );
            }
        }
        buf[aspect] = 0.0;

        // A hand in centimeters: refused; a (large) hand within 1 m of its wrist: read.
        let world = input::HANDS + input::HAND_STRIDE + input::hand::WORLD;
        // Landmark 8 at (x, 1, -0.16), its wrist at (0, 1, 0).
        for (value, ok) in [(0.95, true), (1.0, false)] {
            buf[world + 8 * 3] = value;
            let r = read_input(&buf, 0.0, &mut back);
            assert_eq!(r.is_ok(), ok, "{value}: {r:?}");
        }
        let e = read_input(&buf, 0.0, &mut back).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame.hands[1].worldLandmarks: the hand is more than 1 m across: world landmarks are meters (centimeters given?)"
        );
    }
}
