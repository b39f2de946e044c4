//! The shared real data, read the same way by every native test, the bench and the evals:
//! the MediaPipe hand recordings, the Kinect body session and the VRM avatars (the shared
//! robot and the generated fixtures), plus the frame builders the solve loops share.
//!
//! Paths are relative to the repository root; `../shared` is the read-only data beside the
//! repo.

use std::path::{Path, PathBuf};

use glam::Vec3;
use handrig::mediapipe::{
    FrameInput, HandObservation, Handedness, PoseObservation, WristObservation, HAND_LANDMARKS,
    MAX_HANDS, POSE_LANDMARKS,
};
use handrig::Skeleton;
use serde_json::Value;

/// The MediaPipe HandLandmarker video of a subject's right hand (un-mirrored, labelled "Left").
pub const HAND_VIDEO: &str = "../shared/data/hands/right-hand-video-mediapipe.json";
/// Wrist-frame landmarks of the same right hand (`{ "frames": [21 x [x, y, z] | null] }`).
pub const HAND_CANONICAL: &str = "../shared/data/hands/right-hand-canonical.json";
/// The Azure Kinect upper-body session (`jointNames`, `frames[i].joints[j] = [x, y, z, conf]`).
pub const KINECT: &str = "../shared/data/pose/kinect-upper-body.json";
/// The shared debug robot (VRM 1.0, symmetric, straight fingers).
pub const ROBOT: &str = "../shared/avatars/debug-robot.vrm";
/// The generated human-proportioned VRM 1.0 fixture (spread fingers, forward-palmar thumb).
pub const FIXTURE_VRM1: &str = "tests/fixtures/human-proportions-vrm1.vrm";
/// The generated VRM 0.x fixture with fingers (Blender-style rolls, faces -Z).
pub const FIXTURE_VRM0: &str = "tests/fixtures/vrm0-fingers.vrm";

/// `relative` (to the repository root, two folders above this crate's) as an absolute path,
/// so tests run from any directory.
pub fn path(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(relative)
}

/// The committed fuzz seeds (`tests/fuzz-corpus/`) whose names end with one of `extensions`,
/// as repository-relative paths in name order.
pub fn fuzz_corpus(extensions: &[&str]) -> Vec<String> {
    let mut files: Vec<String> = std::fs::read_dir(path("tests/fuzz-corpus"))
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| format!("tests/fuzz-corpus/{}", e.file_name().to_string_lossy()))
                .filter(|f| extensions.iter().any(|x| f.ends_with(x)))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

fn read_json(path: &Path) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn landmarks(v: &Value, what: &str) -> Result<[Vec3; HAND_LANDMARKS], String> {
    let a = v
        .as_array()
        .filter(|a| a.len() == HAND_LANDMARKS)
        .ok_or(format!("{what}: expected {HAND_LANDMARKS} landmarks"))?;
    let mut out = [Vec3::ZERO; HAND_LANDMARKS];
    for (i, (o, p)) in out.iter_mut().zip(a).enumerate() {
        let c = |k: usize| {
            p.get(k)
                .and_then(Value::as_f64)
                .map(|x| x as f32)
                .ok_or(format!("{what}[{i}]: expected [x, y, z]"))
        };
        *o = Vec3::new(c(0)?, c(1)?, c(2)?);
    }
    Ok(out)
}

/// The hands of recording frame `f` (number `i`) in file order: world landmarks, label,
/// score, and the image landmarks when the file has them. Errors name the frame and field.
fn hands_of(f: &Value, i: usize) -> Result<Vec<HandObservation>, String> {
    let hands = f["hands"]
        .as_array()
        .ok_or(format!("frame {i}: no hands array"))?;
    hands
        .iter()
        .enumerate()
        .map(|(k, h)| {
            let what = format!("frame {i} hands[{k}]");
            let handedness = h["handedness"]
                .as_str()
                .and_then(Handedness::from_label)
                .ok_or(format!("{what}.handedness: expected Left or Right"))?;
            let score = h["score"]
                .as_f64()
                .ok_or(format!("{what}.score: expected a number"))? as f32;
            let world = landmarks(&h["worldLandmarks"], &format!("{what}.worldLandmarks"))?;
            let image = match &h["landmarks"] {
                Value::Null => None,
                v => Some(landmarks(v, &format!("{what}.landmarks"))?),
            };
            Ok(HandObservation {
                handedness,
                score,
                world,
                image,
            })
        })
        .collect()
}

/// Every frame of a MediaPipe hand recording at `path`: each frame's hands in file order
/// (world and image landmarks, label, score). Errors name the frame and field.
pub fn read_hand_video(path: &Path) -> Result<Vec<Vec<HandObservation>>, String> {
    let v = read_json(path)?;
    let frames = v
        .as_array()
        .ok_or(format!("{}: expected an array of frames", path.display()))?;
    frames
        .iter()
        .enumerate()
        .map(|(i, f)| hands_of(f, i))
        .collect()
}

/// The four sign-language clips: MediaPipe Pose and Hands of one person on the same frames
/// (un-mirrored video: "Left" is the signer's right hand).
pub const ASL: [&str; 4] = [
    "../shared/data/asl/eat.json",
    "../shared/data/asl/thanks.json",
    "../shared/data/asl/brother.json",
    "../shared/data/asl/sister.json",
];

/// The two clips shared after the first four ([`ASL`]): a hand on the chest (`please`) and a
/// hand into the other palm (`again`).
pub const ASL_MORE: [&str; 2] = [
    "../shared/data/asl/please.json",
    "../shared/data/asl/again.json",
];

/// The hand video ([`hand_video`]) as rig input at 30 fps, hands only.
pub fn hand_video_frames() -> Vec<FrameInput> {
    hand_video()
        .iter()
        .enumerate()
        .map(|(i, hands)| {
            let mut f = frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f
        })
        .collect()
}

/// Every frame of an ASL clip at `path` (or of a hands-only recording such as [`HAND_VIDEO`])
/// as rig input: its hands (at most [`MAX_HANDS`], in file order, world and image landmarks),
/// the pose world landmarks with their visibilities and its image landmarks, and the time.
pub fn read_asl(path: &Path) -> Result<Vec<FrameInput>, String> {
    let v = read_json(path)?;
    // `{ frames: [...] }`, or a bare array of frames (the hand video's format).
    let frames = v["frames"]
        .as_array()
        .or(v.as_array())
        .ok_or(format!("{}: no frames array", path.display()))?;
    frames
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let hands = hands_of(f, i)?;
            let mut frame = frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            frame.time_ms = f["timeMs"].as_f64().unwrap_or(i as f64 * 1000.0 / 30.0);
            // Hands-only recordings (the hand video) have no pose: the frame is hands alone.
            if f.get("pose").is_none_or(Value::is_null) {
                return Ok(frame);
            }
            let world = f["pose"]["worldLandmarks"]
                .as_array()
                .filter(|a| a.len() == POSE_LANDMARKS)
                .ok_or(format!(
                    "frame {i}: pose.worldLandmarks: expected {POSE_LANDMARKS}"
                ))?;
            let mut pose = PoseObservation {
                world: [Vec3::ZERO; POSE_LANDMARKS],
                visibility: [1.0; POSE_LANDMARKS],
            };
            for (k, p) in world.iter().enumerate() {
                let c = |j: usize| {
                    p.get(j)
                        .and_then(Value::as_f64)
                        .map(|x| x as f32)
                        .ok_or(format!("frame {i}: pose.worldLandmarks[{k}]"))
                };
                pose.world[k] = Vec3::new(c(0)?, c(1)?, c(2)?);
                pose.visibility[k] = c(3).unwrap_or(1.0);
            }
            frame.pose = Some(pose);
            if let Some(image) = f["pose"]["landmarks"]
                .as_array()
                .filter(|a| a.len() == POSE_LANDMARKS)
            {
                let mut points = [Vec3::ZERO; POSE_LANDMARKS];
                for (k, p) in image.iter().enumerate() {
                    let c = |j: usize| {
                        p.get(j)
                            .and_then(Value::as_f64)
                            .map(|x| x as f32)
                            .ok_or(format!("frame {i}: pose.landmarks[{k}]"))
                    };
                    points[k] = Vec3::new(c(0)?, c(1)?, c(2)?);
                }
                frame.pose_image = Some(points);
            }
            Ok(frame)
        })
        .collect()
}

/// The ASL clip at `relative` (panics if it is unreadable).
/// The visual contact labels of a shared ASL clip (`eval/labels/contact-<clip>.json`: per side
/// and frame `face`, `chest`, `hand`, `none` or `unsure`).
#[allow(dead_code)]
pub fn contact_labels(clip: &str) -> Value {
    read_json(&path(&format!("eval/labels/contact-{clip}.json")))
        .unwrap_or_else(|e| panic!("contact labels of {clip}: {e}"))
}

pub fn asl(relative: &str) -> Vec<FrameInput> {
    read_asl(&path(relative)).unwrap_or_else(|e| panic!("{e}"))
}

/// Every frame of a canonical (wrist-frame) hand recording at `path`; `None` for frames the
/// file marks `null` (hand not found).
pub fn read_hand_canonical(path: &Path) -> Result<Vec<Option<[Vec3; HAND_LANDMARKS]>>, String> {
    let v = read_json(path)?;
    let frames = v["frames"]
        .as_array()
        .ok_or(format!("{}: no frames array", path.display()))?;
    frames
        .iter()
        .enumerate()
        .map(|(i, f)| {
            if f.is_null() {
                Ok(None)
            } else {
                landmarks(f, &format!("frames[{i}]")).map(Some)
            }
        })
        .collect()
}

/// [`HAND_VIDEO`], every frame's hands in file order (panics if the file is unreadable).
pub fn hand_video() -> Vec<Vec<HandObservation>> {
    read_hand_video(&path(HAND_VIDEO)).unwrap_or_else(|e| panic!("{e}"))
}

/// The first hand of every frame of [`HAND_VIDEO`] (each frame has at least one; a few have
/// a second, lower- or higher-scored duplicate).
pub fn hand_video_first() -> Vec<HandObservation> {
    hand_video()
        .into_iter()
        .map(|hands| *hands.first().expect("every frame has a hand"))
        .collect()
}

/// [`HAND_CANONICAL`] (panics if the file is unreadable).
pub fn hand_canonical() -> Vec<Option<[Vec3; HAND_LANDMARKS]>> {
    read_hand_canonical(&path(HAND_CANONICAL)).unwrap_or_else(|e| panic!("{e}"))
}

/// The highest-scored hand of a frame (the rig's pick among duplicates of one side).
pub fn best_hand(hands: &[HandObservation]) -> Option<&HandObservation> {
    hands.iter().max_by(|a, b| a.score.total_cmp(&b.score))
}

/// A Kinect body session: joint names and, per frame, `[x, y, z, confidence]` per joint in
/// the recording's own (mirrored) frame.
pub struct Kinect {
    pub joint_names: Vec<String>,
    pub frames: Vec<Vec<[f32; 4]>>,
}

impl Kinect {
    /// Index of the joint called `name` (e.g. `"WRIST_LEFT"`).
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joint_names.iter().position(|n| n == name)
    }
}

/// The Kinect session at `path`.
pub fn read_kinect(path: &Path) -> Result<Kinect, String> {
    #[derive(serde::Deserialize)]
    #[serde(rename_all = "camelCase")]
    struct File {
        joint_names: Vec<String>,
        frames: Vec<Frame>,
    }
    #[derive(serde::Deserialize)]
    struct Frame {
        joints: Vec<[f32; 4]>,
    }
    let file: File =
        serde_json::from_value(read_json(path)?).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Kinect {
        joint_names: file.joint_names,
        frames: file.frames.into_iter().map(|f| f.joints).collect(),
    })
}

/// [`KINECT`] (panics if the file is unreadable).
pub fn kinect() -> Kinect {
    read_kinect(&path(KINECT)).unwrap_or_else(|e| panic!("{e}"))
}

/// The VRM file at `path` as a skeleton.
pub fn read_vrm(path: &Path) -> Result<Skeleton, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    handrig::humanoid::vrm::load_skeleton(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The VRM at `relative` (to the crate root; e.g. [`ROBOT`]) as a skeleton (panics if it
/// cannot be read or loaded).
pub fn vrm(relative: &str) -> Skeleton {
    read_vrm(&path(relative)).unwrap_or_else(|e| panic!("{e}"))
}

/// The real files, in this order: the shared robot, the human-proportioned VRM 1.0 fixture
/// and the VRM 0.x fixture.
pub fn real_avatars() -> [Skeleton; 3] {
    [ROBOT, FIXTURE_VRM1, FIXTURE_VRM0].map(vrm)
}

/// One observed hand with world landmarks only.
pub fn hand(handedness: Handedness, score: f32, world: [Vec3; HAND_LANDMARKS]) -> HandObservation {
    HandObservation {
        handedness,
        score,
        world,
        image: None,
    }
}

/// A frame carrying `hands` (at most [`MAX_HANDS`]) and nothing else.
pub fn frame_of(hands: &[HandObservation]) -> FrameInput {
    assert!(hands.len() <= MAX_HANDS);
    let mut f = FrameInput::default();
    f.hands[..hands.len()].copy_from_slice(hands);
    f.hand_count = hands.len();
    f
}

/// What a solve-loop frame carries besides the hand (the paths `Rig::solve` takes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ArmInput {
    /// Hand only: hand and fingers solved, arms untouched.
    None,
    /// [`RIGHT_WRIST`] as `wrists.right`: fingertip alignment and arm IK.
    Wrist,
    /// [`plausible_pose`] landmarks: body mapping, calibration, alignment and arm IK.
    Pose,
}

impl ArmInput {
    /// All three, in the order the solve loops cycle through them.
    pub const ALL: [ArmInput; 3] = [ArmInput::None, ArmInput::Wrist, ArmInput::Pose];
}

/// A reachable right-wrist target in front of a human-sized avatar (model frame, meters).
pub const RIGHT_WRIST: Vec3 = Vec3::new(-0.45, 1.3, 0.2);

/// A plausible MediaPipe pose (camera axes: y down, z away): shoulders, elbows and wrists of a
/// user facing the camera, arms forward; every landmark fully visible.
pub fn plausible_pose() -> PoseObservation {
    let mut pose = PoseObservation {
        world: [Vec3::ZERO; POSE_LANDMARKS],
        visibility: [1.0; POSE_LANDMARKS],
    };
    pose.world[11] = Vec3::new(0.18, -0.45, 0.0);
    pose.world[12] = Vec3::new(-0.18, -0.45, 0.0);
    pose.world[13] = Vec3::new(0.25, -0.2, -0.05);
    pose.world[14] = Vec3::new(-0.25, -0.2, -0.05);
    pose.world[15] = Vec3::new(0.2, -0.3, -0.25);
    pose.world[16] = Vec3::new(-0.2, -0.3, -0.25);
    pose
}

/// Resets `frame` in place (no allocation: used inside allocation-counted loops) to one hand
/// labelled "Left" (the subject's right hand, un-mirrored) with `world` and `score`, plus the
/// `arm` input (`pose` for [`ArmInput::Pose`]).
pub fn fill_frame(
    frame: &mut FrameInput,
    world: [Vec3; HAND_LANDMARKS],
    score: f32,
    arm: ArmInput,
    pose: &PoseObservation,
) {
    frame.clear();
    frame.hands[0] = hand(Handedness::Left, score, world);
    frame.hand_count = 1;
    match arm {
        ArmInput::None => {}
        ArmInput::Wrist => {
            frame.wrists[1] = Some(WristObservation {
                position: RIGHT_WRIST,
                rotation: None,
            })
        }
        ArmInput::Pose => frame.pose = Some(*pose),
    }
}
