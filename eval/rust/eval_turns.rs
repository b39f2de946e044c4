//! Hand turns on real video (issue 27): how far the avatar's hand turns between consecutive
//! 30 fps frames on the shared ASL clips and the hand video, against how far the MediaPipe
//! hand's palm turns, with every default option on; and the avatar palm's agreement with the
//! hand-made palm-facing labels (`eval/labels/palm-facing.json`).
//!
//! `cargo run --release --example eval_turns [-- --json] [-- --worst N] [-- --options JSON]`
//! (about 1 s in a release build; `node eval/hand-turns.mjs` adds Kalidokit 1.1.5 and prints the
//! docs table). `--options` replaces the default options (every default on), e.g.
//! `--options '{"contact":{"enabled":false}}'` to see what self-contact adds.
//!
//! Per side-frame (a side whose hand drove the avatar in this frame and the one before), the
//! turn is the largest of the world rotations' angles of change of the upper arm, forearm and
//! hand; the input's is the change of the MediaPipe hand's palm frame (world landmarks, the
//! palm frame of `handrig::hand::palm_frame`).
//!
//! It also prints the hand alone against the input palm (the median turn per frame and over
//! [`SPAN`] frames: jitter against motion; and per frame against the input's motion, the input
//! after a centered [`SPAN`]-frame mean, [`motion_turn`]), the same turns on the hand video paired with the
//! Kinect session's wrists (an arm from a real body tracker) with the frames the turn limit
//! slowed, and counts what the hand selection resolved (`TrackedHand::resolved`: swapped
//! labels, label jumps, duplicates) per side on the clips and the hand video.

use handrig_support::kinect_wrists;
use handrig_support::recordings;

use glam::{Quat, Vec3, Vec4};
use handrig::hand::palm_frame;
use handrig::mediapipe::{FrameInput, HandObservation};
use handrig::pipeline::{HandResolved, HandUse};
use handrig::{Rig, RigOptions, Side, SolveOutput};
use serde_json::{json, Value};

/// The shared ASL clips (all six) and the hand video.
const CLIPS: [&str; 6] = ["again", "brother", "eat", "please", "sister", "thanks"];
const AVATARS: [&str; 7] = [
    "tests/fixtures/avatars/woman-vrm1.vrm",
    "tests/fixtures/avatars/man-vrm1.vrm",
    "tests/fixtures/avatars/child-vrm1.vrm",
    "tests/fixtures/avatars/woman-vrm0.vrm",
    "tests/fixtures/avatars/man-vrm0.vrm",
    "tests/fixtures/avatars/child-vrm0.vrm",
    recordings::ROBOT,
];
const LABELS: &str = "eval/labels/palm-facing.json";
const BONES: [&str; 3] = ["upperArm", "lowerArm", "hand"];

/// A turn of one side between two frames.
#[derive(Clone, Debug)]
struct Turn {
    clip: String,
    frame: usize,
    side: Side,
    avatar: f32,
    /// Which bone turned most: 0 upper arm, 1 forearm, 2 hand.
    bone: usize,
    input: f32,
    /// The turn limit (`arm.maxTurnSpeed`) slowed this side's arm this frame.
    limited: bool,
    /// The hand's own world rotation's turn (the like-for-like of `input`).
    hand: f32,
    /// The hand's and the input palm's turn over the last [`SPAN`] frames, where this side's
    /// hand drove the avatar in every one of them.
    span: Option<(f32, f32)>,
    /// The input palm's turn between the [`SPAN`]-frame centered means of its rotation around
    /// this frame and the one before ([`motion_turn`]), where this side's hand drove the avatar
    /// on all of those frames: the input's motion with most of its jitter taken out.
    motion: Option<f32>,
}

/// A side-frame whose arm was solved in it and the frame before while its hand came or went
/// (fingertip alignment in one of the two frames, not both): the hand lost or back with the
/// pose still placing the arm.
#[derive(Clone, Debug)]
struct Handover {
    clip: String,
    frame: usize,
    side: Side,
    /// The hand came back (aligned now, not before); otherwise it was lost.
    back: bool,
    /// How far the avatar's wrist (hand joint) moved between the two frames (cm).
    moved: f32,
    /// The arm's largest turn (upper arm, forearm, hand world rotations; degrees).
    turn: f32,
}

/// Frames of the span turn: a sixth of a second at 30 fps. Over a span a motion adds up while
/// MediaPipe's frame-to-frame jitter does not (two noisy ends, not `SPAN` noisy steps), so the
/// span turn tells a hand that follows the motion from one that is frozen, jitter aside.
const SPAN: usize = 5;

/// The mean of `qs` (unit quaternions close together): each on the first one's hemisphere,
/// summed and normalized.
fn mean_rotation(qs: &[Quat]) -> Quat {
    let c = qs[0];
    let sum = qs.iter().fold(Vec4::ZERO, |acc, q| {
        let v = Vec4::from(*q);
        acc + if q.dot(c) < 0.0 { -v } else { v }
    });
    Quat::from_vec4(sum.normalize())
}

/// The input palm's turn from frame `i - 1` to `i` after a centered (non-causal) mean over
/// [`SPAN`] frames: the rotation averaged over frames `i - 1 - SPAN / 2 ..= i - 1 + SPAN / 2`
/// against the one over `i - SPAN / 2 ..= i + SPAN / 2` (`None` unless all were tracked).
/// The difference of two such means is the input's change from `i - 1 - SPAN / 2` to
/// `i + SPAN / 2` divided by `SPAN` for a steady motion, while uncorrelated frame-to-frame
/// jitter is cut by about that factor: an offline, zero-lag stand-in for the motion the user's
/// hand made, which a causal filter cannot see.
fn motion_turn(series: &[Option<Quat>], i: usize) -> Option<f32> {
    let half = SPAN / 2;
    let first = i.checked_sub(1 + half)?;
    let window = series.get(first..=i + half)?;
    let qs: Vec<Quat> = window.iter().copied().collect::<Option<_>>()?;
    Some(angle(mean_rotation(&qs[..SPAN]), mean_rotation(&qs[1..])))
}

fn angle(a: Quat, b: Quat) -> f32 {
    let d = a.dot(b).abs().min(1.0);
    (2.0 * d.acos()).to_degrees()
}

/// The palm frame of a MediaPipe hand for the avatar side it drives, as a rotation.
fn input_palm(side: Side, h: &HandObservation) -> Option<Quat> {
    let w = &h.world;
    // The palm frame's forward and palmar axes as a proper rotation (its columns are
    // forward, radial, palmar: left-handed for one side).
    palm_frame(side, w[0], w[5], w[17], w[9]).map(|m| {
        let (f, n) = (m.x_axis, m.z_axis);
        Quat::from_mat3(&glam::Mat3::from_cols(f, n, f.cross(n)))
    })
}

/// Where `side`'s hand drove the avatar: the world rotations of its upper arm, forearm and
/// hand (internal frame), and the palm of the input hand that drove it.
fn shown_and_input(out: &SolveOutput, side: Side, f: &FrameInput) -> Option<([Quat; 3], Quat)> {
    let t = out.hands[side.index()]?;
    let [_, upper, lower, hand] = side.arm();
    let input = input_palm(side, &f.hands()[t.index])?;
    Some((
        [upper, lower, hand].map(|b| out.world.rotation[b.index()]),
        input,
    ))
}

fn hand_video() -> Vec<FrameInput> {
    recordings::hand_video()
        .iter()
        .enumerate()
        .map(|(i, hands)| {
            let mut f = recordings::frame_of(&hands[..hands.len().min(2)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f
        })
        .collect()
}

/// The data sets: name and frames.
fn data() -> Vec<(String, Vec<FrameInput>)> {
    let mut d: Vec<(String, Vec<FrameInput>)> = CLIPS
        .iter()
        .map(|c| {
            (
                c.to_string(),
                recordings::asl(&format!("../shared/data/asl/{c}.json")),
            )
        })
        .collect();
    d.push(("hand-video".into(), hand_video()));
    d
}

/// The avatar palm's facing (internal frame: the avatar faces +Z, toward the camera): the
/// rest palm of a normalized hand faces down (-Y).
fn palm_normal(out: &SolveOutput, side: Side) -> Vec3 {
    out.world.rotation[side.hand().index()] * Vec3::NEG_Y
}

/// One labelled hand-frame.
struct Label {
    clip: String,
    frame: usize,
    /// The signer's side.
    signer: Side,
    toward: bool,
}

fn labels() -> Vec<Label> {
    let Ok(text) = std::fs::read_to_string(recordings::path(LABELS)) else {
        return Vec::new();
    };
    let v: Value = serde_json::from_str(&text).expect("labels: JSON");
    v["labels"]
        .as_array()
        .expect("labels: a labels array")
        .iter()
        .filter_map(|l| {
            let toward = match l["facing"].as_str()? {
                "toward" => true,
                "away" => false,
                _ => return None,
            };
            Some(Label {
                clip: l["clip"].as_str()?.to_string(),
                frame: l["frame"].as_u64()? as usize,
                signer: if l["hand"].as_str()? == "right" {
                    Side::Right
                } else {
                    Side::Left
                },
                toward,
            })
        })
        .collect()
}

/// The input hand that is the signer's `signer` hand in `f`: the one whose image wrist is
/// nearest the pose's image wrist of that side (pose 15 left, 16 right).
fn signer_hand(f: &FrameInput, signer: Side) -> Option<usize> {
    let pose = f.pose_image?;
    let w = pose[if signer == Side::Right { 16 } else { 15 }];
    f.hands()
        .iter()
        .enumerate()
        .filter_map(|(i, h)| h.image.map(|im| (i, (im[0] - w).truncate().length())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// Side-frames per resolution: `[ASL, hand video][left, right][swapped, jumped, duplicate]`.
type Resolutions = [[[usize; 3]; 2]; 2];

/// What [`run`] measures on one avatar.
struct Run {
    /// Every side-frame's turn.
    turns: Vec<Turn>,
    /// The palm-label agreement of the avatar (agree, total) and of the input hand that drove
    /// the side (its world landmarks' palm normal, agree).
    labels: (usize, usize, usize),
    /// The labelled frames the avatar's palm disagrees on.
    misses: Vec<String>,
    /// The hand selection's resolutions.
    resolved: Resolutions,
    /// Every hand lost or back with the arm still solved from the pose.
    handovers: Vec<Handover>,
    /// Arm-frames the turn limit slowed, all clips and the hand video.
    arm_slowed: u32,
}

/// Per avatar, on every clip and the hand video: see [`Run`].
fn run(
    options: RigOptions,
    avatar: &str,
    data: &[(String, Vec<FrameInput>)],
    labels: &[Label],
) -> Run {
    let mut resolutions: Resolutions = [[[0; 3]; 2]; 2];
    let skeleton = recordings::vrm(avatar);
    let version = skeleton.version();
    let mut turns = Vec::new();
    let (mut agree, mut total, mut input_agree) = (0, 0, 0);
    let camera = handrig::mediapipe::CameraMapping::default();
    let mut misses = Vec::new();
    let mut handovers = Vec::new();
    let mut arm_frames_slowed = 0;
    for (name, frames) in data {
        let mut rig = Rig::new(skeleton.clone(), options).unwrap();
        let mut out = SolveOutput::default();
        let mut last: [Option<([Quat; 3], Quat)>; 2] = [None, None];
        // Per side, this side's hand and input palm on the last SPAN + 1 frames.
        let mut history: [Vec<Option<(Quat, Quat)>>; 2] = Default::default();
        // Per side, last frame's arm (world rotations), IK target and whether it was aligned.
        let mut arm: [Option<([Quat; 3], Vec3, bool)>; 2] = [None, None];
        // Per side, the input palm of every frame whose hand drove that side.
        let mut palms: [Vec<Option<Quat>>; 2] = Default::default();
        let first_turn = turns.len();
        for (i, f) in frames.iter().enumerate() {
            let before = Side::BOTH.map(|s| rig.turns_limited(s));
            rig.solve(f, &mut out).unwrap();
            let slowed = Side::BOTH.map(|s| rig.turns_limited(s) > before[s.index()]);
            let mut o = out.clone();
            o.turn_to_internal_frame(version);
            if std::env::var("TURNS_TRACE").is_ok_and(|c| c == *name) && avatar == recordings::ROBOT
            {
                for side in Side::BOTH {
                    if let Some(t) = o.hands[side.index()] {
                        eprintln!("{name}:{i} {side:?} {:?} {:?}", t.status, t.check);
                    }
                }
            }
            for side in Side::BOTH {
                let kind = match o.hands[side.index()].map(|t| t.resolved) {
                    Some(HandResolved::Swapped) => Some(0),
                    Some(HandResolved::Jumped) => Some(1),
                    Some(HandResolved::Duplicate) => Some(2),
                    _ => None,
                };
                if let Some(k) = kind {
                    resolutions[usize::from(name == "hand-video")][side.index()][k] += 1;
                }
                let now = shown_and_input(&o, side, f);
                palms[side.index()].push(now.map(|(_, i)| i));
                let h = &mut history[side.index()];
                h.push(now.map(|(b, i)| (b[2], i)));
                if h.len() > SPAN + 1 {
                    h.remove(0);
                }
                let span = (h.len() == SPAN + 1 && h.iter().all(Option::is_some))
                    .then(|| {
                        let ((a0, i0), (a1, i1)) = (h[0]?, h[SPAN]?);
                        Some((angle(a0, a1), angle(i0, i1)))
                    })
                    .flatten();
                if let (Some((a, ia)), Some((b, ib))) = (last[side.index()], now) {
                    let (bone, avatar) = (0..3)
                        .map(|k| (k, angle(a[k], b[k])))
                        .fold((0, 0.0), |m, t| if t.1 > m.1 { t } else { m });
                    turns.push(Turn {
                        clip: name.clone(),
                        frame: i,
                        side,
                        avatar,
                        bone,
                        input: angle(ia, ib),
                        limited: slowed[side.index()],
                        hand: angle(a[2], b[2]),
                        span,
                        motion: None,
                    });
                }
                last[side.index()] = now;
                let [_, upper, lower, hand] = side.arm();
                let shown = o.solved[upper.index()].then(|| {
                    (
                        [upper, lower, hand].map(|b| o.world.rotation[b.index()]),
                        o.world.position[hand.index()],
                        o.alignment[side.index()].is_some(),
                    )
                });
                if let (Some((a, ta, was)), Some((b, tb, is))) = (arm[side.index()], shown) {
                    if was != is {
                        handovers.push(Handover {
                            clip: name.clone(),
                            frame: i,
                            side,
                            back: is,
                            moved: 100.0 * (tb - ta).length(),
                            turn: (0..3).map(|k| angle(a[k], b[k])).fold(0.0, f32::max),
                        });
                    }
                }
                arm[side.index()] = shown;
            }
            for l in labels.iter().filter(|l| &l.clip == name && l.frame == i) {
                let Some(k) = signer_hand(f, l.signer) else {
                    continue;
                };
                let HandUse::Drove(side) = o.hand_use[k] else {
                    continue;
                };
                total += 1;
                // The input's palm normal in the avatar frame (+Z toward the camera).
                let w = f.hands()[k].world.map(|p| camera.to_avatar(p));
                if palm_frame(side, w[0], w[5], w[17], w[9])
                    .is_some_and(|m| (m.z_axis.z > 0.0) == l.toward)
                {
                    input_agree += 1;
                }
                let toward = palm_normal(&o, side).z > 0.0;
                if toward == l.toward {
                    agree += 1;
                } else {
                    misses.push(format!(
                        "{name}:{i} {} {}",
                        if l.signer == Side::Right {
                            "right"
                        } else {
                            "left"
                        },
                        if l.toward { "toward" } else { "away" }
                    ));
                }
            }
        }
        arm_frames_slowed += rig.turns_limited(Side::Left) + rig.turns_limited(Side::Right);
        for t in &mut turns[first_turn..] {
            t.motion = motion_turn(&palms[t.side.index()], t.frame);
        }
    }
    Run {
        turns,
        labels: (agree, total, input_agree),
        misses,
        resolved: resolutions,
        handovers,
        arm_slowed: arm_frames_slowed,
    }
}

/// The hand video paired with the Kinect session's wrists (the avatar's right arm solved from
/// a real body tracker, `tests/support/kinect_wrists.rs`, 281 frames): per side-frame the
/// avatar's turn (as [`run`]) and the input palm's, and the frames the turn limit slowed.
fn kinect_turns(options: RigOptions, avatar: &str) -> (Vec<f32>, Vec<f32>, Vec<usize>) {
    let skeleton = recordings::vrm(avatar);
    let version = skeleton.version();
    let frames = kinect_wrists::paired_frames(&skeleton, Side::Right);
    let mut rig = Rig::new(skeleton, options).unwrap();
    let mut out = SolveOutput::default();
    let (mut avatar_turns, mut input_turns, mut slowed) = (Vec::new(), Vec::new(), Vec::new());
    let mut last: Option<([Quat; 3], Quat)> = None;
    let side = Side::Right;
    for (i, f) in frames.iter().enumerate() {
        let before = rig.turns_limited(side);
        rig.solve(f, &mut out).unwrap();
        if rig.turns_limited(side) > before {
            slowed.push(i);
        }
        out.turn_to_internal_frame(version);
        let now = shown_and_input(&out, side, f);
        if let (Some((a, ia)), Some((b, ib))) = (last, now) {
            avatar_turns.push((0..3).map(|k| angle(a[k], b[k])).fold(0.0, f32::max));
            input_turns.push(angle(ia, ib));
        }
        last = now;
    }
    (avatar_turns, input_turns, slowed)
}

/// The hand coming and going with the arm solved: per direction (lost, back) the count, the
/// median and largest wrist move (cm) and arm turn (degrees), and the largest moves.
fn handover_figures(h: &[Handover]) -> Value {
    let of = |back: bool| {
        let set: Vec<&Handover> = h.iter().filter(|x| x.back == back).collect();
        let moved: Vec<f32> = set.iter().map(|x| x.moved).collect();
        let turn: Vec<f32> = set.iter().map(|x| x.turn).collect();
        json!({ "n": set.len(), "moved": { "median": median(moved.clone()),
                "max": moved.iter().copied().fold(0.0, f32::max) },
            "turn": { "median": median(turn.clone()), "max": turn.iter().copied().fold(0.0, f32::max) } })
    };
    let mut sorted: Vec<&Handover> = h.iter().collect();
    sorted.sort_by(|a, b| b.moved.total_cmp(&a.moved));
    let largest: Vec<String> = sorted
        .iter()
        .take(5)
        .map(|x| {
            format!(
                "{}:{} {} {} {:.1} cm {:.0} deg",
                x.clip,
                x.frame,
                if x.side == Side::Right {
                    "right"
                } else {
                    "left"
                },
                if x.back { "back" } else { "lost" },
                x.moved,
                x.turn
            )
        })
        .collect();
    json!({ "lost": of(false), "back": of(true), "largest": largest })
}

/// Frames whose hands [`dropped_hands`] removes: one in [`DROP_EVERY`], from the fifth.
const DROP_EVERY: usize = 10;

/// MediaPipe losing a hand for a frame, made on real sessions: the six ASL clips and the hand
/// video paired with the Kinect session's wrists, every hand removed on one frame in
/// [`DROP_EVERY`] (the pose or the tracker still placing the arm). Per avatar side whose
/// hand was aligned the frame before the drop: how far the avatar's wrist moves into the
/// dropped frame and out of it (cm), and the arm's largest turn there (degrees).
fn dropped_hands(options: RigOptions, avatar: &str) -> (Vec<f32>, Vec<f32>) {
    let skeleton = recordings::vrm(avatar);
    let mut sessions: Vec<Vec<FrameInput>> = CLIPS
        .iter()
        .map(|c| recordings::asl(&format!("../shared/data/asl/{c}.json")))
        .collect();
    sessions.push(kinect_wrists::paired_frames(&skeleton, Side::Right));
    let (mut moves, mut turns) = (Vec::new(), Vec::new());
    for mut frames in sessions {
        for f in frames.iter_mut().skip(5).step_by(DROP_EVERY) {
            f.hand_count = 0;
        }
        let mut rig = Rig::new(skeleton.clone(), options).unwrap();
        let mut out = SolveOutput::default();
        let mut last: [Option<(Vec3, [Quat; 3], bool)>; 2] = [None, None];
        for (i, f) in frames.iter().enumerate() {
            rig.solve(f, &mut out).unwrap();
            let near_drop = i % DROP_EVERY == 5 || i % DROP_EVERY == 6;
            for side in Side::BOTH {
                let [_, upper, lower, hand] = side.arm();
                let now = out.solved[upper.index()].then(|| {
                    (
                        out.world.position[hand.index()],
                        [upper, lower, hand].map(|b| out.world.rotation[b.index()]),
                        out.alignment[side.index()].is_some(),
                    )
                });
                if let (Some((ta, a, aligned)), Some((tb, b, _))) = (last[side.index()], now) {
                    // Into the drop from an aligned hand, or out of it.
                    if near_drop && (aligned || i % DROP_EVERY == 6) {
                        moves.push(100.0 * (tb - ta).length());
                        turns.push((0..3).map(|k| angle(a[k], b[k])).fold(0.0, f32::max));
                    }
                }
                last[side.index()] = now;
            }
        }
    }
    (moves, turns)
}

fn median(mut v: Vec<f32>) -> f32 {
    if v.is_empty() {
        return f32::NAN;
    }
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

/// Count, > 90, % > 45, median, max of a set of turns.
fn figures(v: &[f32]) -> Value {
    let n = v.len();
    json!({
        "sideFrames": n,
        "over90": v.iter().filter(|a| **a > 90.0).count(),
        "pctOver45": 100.0 * v.iter().filter(|a| **a > 45.0).count() as f64 / n.max(1) as f64,
        "median": median(v.to_vec()),
        "max": v.iter().copied().fold(0.0, f32::max),
    })
}

/// The side-frames the turn limit slowed, per data set (`asl`, `video`), with the ASL ones
/// listed as `clip:frame side`.
fn limited_frames(turns: &[Turn]) -> Value {
    let asl: Vec<String> = turns
        .iter()
        .filter(|t| t.limited && t.clip != "hand-video")
        .map(|t| {
            let side = if t.side == Side::Right {
                "right"
            } else {
                "left"
            };
            format!("{}:{} {side} (input {:.0})", t.clip, t.frame, t.input)
        })
        .collect();
    let video = turns
        .iter()
        .filter(|t| t.limited && t.clip == "hand-video")
        .count();
    json!({ "asl": asl, "video": video })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let as_json = args.iter().any(|a| a == "--json");
    let worst = args
        .iter()
        .position(|a| a == "--worst")
        .and_then(|i| args.get(i + 1))
        .and_then(|n| n.parse().ok())
        .unwrap_or(10usize);
    let options = args
        .iter()
        .position(|a| a == "--options")
        .and_then(|i| args.get(i + 1))
        .map_or_else(RigOptions::default, |json| {
            RigOptions::from_json(json).unwrap_or_else(|e| panic!("--options: {e}"))
        });
    let data = data();
    let labels = labels();
    let mut rows = Vec::new();
    let mut input_rows = None;
    let mut selection = None;
    // The largest turns of the first avatar (woman-vrm1) and of the robot.
    let mut worst_human = Vec::new();
    let mut worst_rows = Vec::new();
    for avatar in AVATARS {
        let Run {
            turns,
            labels: (agree, total, input_agree),
            misses,
            resolved,
            handovers,
            arm_slowed,
        } = run(options, avatar, &data, &labels);
        // The selection reads the input only: the same on every avatar.
        let counts = |g: usize| {
            json!(Side::BOTH.map(|s| {
                let c = resolved[g][s.index()];
                json!({ "swapped": c[0], "jumped": c[1], "duplicate": c[2] })
            }))
        };
        selection.get_or_insert_with(|| json!({ "asl": counts(0), "video": counts(1) }));
        let pick = |asl: bool, f: &dyn Fn(&Turn) -> f32| -> Vec<f32> {
            turns
                .iter()
                .filter(|t| (t.clip != "hand-video") == asl)
                .map(f)
                .collect()
        };
        // Median turns of the hand alone: per frame, and over SPAN frames.
        let motion = |asl: bool, input: bool| -> Value {
            let set = |f: &dyn Fn(&Turn) -> Option<f32>| -> Vec<f32> {
                turns
                    .iter()
                    .filter(|t| (t.clip != "hand-video") == asl)
                    .filter_map(f)
                    .collect()
            };
            let frame = set(&|t| Some(if input { t.input } else { t.hand }));
            let span = set(&|t| t.span.map(|(a, i)| if input { i } else { a }));
            let spans = span.len();
            // The input's motion (centered mean) and the hand's turn on the same side-frames.
            let moving = set(&|t| t.motion.map(|m| if input { m } else { t.hand }));
            let moving_n = moving.len();
            json!({ "frame": median(frame), "span": median(span), "spans": spans,
                "motion": median(moving), "motionFrames": moving_n })
        };
        if input_rows.is_none() {
            input_rows = Some(json!({
                "palm": { "agree": input_agree, "labelled": total },
                "asl": figures(&pick(true, &|t| t.input)),
                "video": figures(&pick(false, &|t| t.input)),
                "motion": { "asl": motion(true, true), "video": motion(false, true) },
            }));
        }
        let name = avatar.rsplit('/').next().unwrap().trim_end_matches(".vrm");
        if avatar == recordings::ROBOT || worst_human.is_empty() {
            let mut sorted: Vec<&Turn> = turns.iter().collect();
            sorted.sort_by(|a, b| b.avatar.total_cmp(&a.avatar));
            let list: Vec<Value> = sorted
                .iter()
                .take(worst)
                .map(|t| {
                    json!({ "avatar": name, "clip": t.clip, "frame": t.frame,
                        "side": if t.side == Side::Right { "right" } else { "left" },
                        "avatar_turn": t.avatar, "input_turn": t.input, "limited": t.limited,
                        "bone": BONES[t.bone] })
                })
                .collect();
            if worst_human.is_empty() {
                worst_human = list;
            } else {
                worst_rows = list;
            }
        }
        let (kinect, kinect_input, kinect_slowed) = kinect_turns(options, avatar);
        let (drop_moves, drop_turns) = dropped_hands(options, avatar);
        rows.push(json!({
            "avatar": name,
            "kinect": { "turns": figures(&kinect), "input": figures(&kinect_input),
                "slowed": kinect_slowed },
            "asl": figures(&pick(true, &|t| t.avatar)),
            "limited": limited_frames(&turns),
            "video": figures(&pick(false, &|t| t.avatar)),
            "palm": { "agree": agree, "labelled": total, "misses": misses },
            "motion": { "asl": motion(true, false), "video": motion(false, false) },
            "handovers": handover_figures(&handovers),
            "armFramesSlowed": arm_slowed,
            "dropped": { "n": drop_moves.len(), "moved": { "median": median(drop_moves.clone()),
                    "max": drop_moves.iter().copied().fold(0.0, f32::max) },
                "turn": { "median": median(drop_turns.clone()),
                    "max": drop_turns.iter().copied().fold(0.0, f32::max) } },
        }));
    }
    let result = json!({ "input": input_rows, "avatars": rows, "worst": worst_rows,
        "worstHuman": worst_human, "selection": selection });
    if as_json {
        println!("{result}");
        return;
    }
    print_table(&result);
}

/// A JSON list of strings or numbers as `a, b, c`.
fn joined(v: &[Value]) -> String {
    v.iter()
        .map(|x| x.as_str().map_or_else(|| x.to_string(), str::to_string))
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_table(r: &Value) {
    let cell = |f: &Value| {
        format!(
            "{:>5} {:>4} {:>6.1} {:>6.1} {:>6.1}",
            f["sideFrames"],
            f["over90"],
            f["pctOver45"].as_f64().unwrap_or(0.0),
            f["median"].as_f64().unwrap_or(f64::NAN),
            f["max"].as_f64().unwrap_or(0.0)
        )
    };
    println!(
        "Turn between consecutive frames, degrees (side-frames, count > 90, % > 45, median, max)"
    );
    println!(
        "{:<22} | {:^31} | {:^31} | palm labels",
        "", "ASL clips (6)", "hand video"
    );
    println!(
        "{:<22} | {:>5} {:>4} {:>6} {:>6} {:>6} | {:>5} {:>4} {:>6} {:>6} {:>6} | agree",
        "", "n", ">90", "%>45", "med", "max", "n", ">90", "%>45", "med", "max"
    );
    let input = &r["input"];
    println!(
        "{:<22} | {} | {} | {}/{}",
        "input (MediaPipe palm)",
        cell(&input["asl"]),
        cell(&input["video"]),
        input["palm"]["agree"],
        input["palm"]["labelled"]
    );
    for a in r["avatars"].as_array().unwrap() {
        let p = &a["palm"];
        println!(
            "{:<22} | {} | {} | {}/{}",
            a["avatar"].as_str().unwrap(),
            cell(&a["asl"]),
            cell(&a["video"]),
            p["agree"],
            p["labelled"]
        );
    }
    println!(
        "\nThe hand alone (avatar hand world rotation; input palm), median turn in degrees: \
         per frame, and over {SPAN} frames (1/6 s), with its ratio to the input's"
    );
    println!(
        "{:<22} | {:^25} | {:^25}",
        "", "ASL clips (6)", "hand video"
    );
    // A median turn `k` of `v` (width `w`) and its ratio to the input's.
    let turn = |v: &Value, input: &Value, k: &str, w: usize| {
        let (f, i) = (v[k].as_f64(), input[k].as_f64());
        let (f, i) = (f.unwrap_or(f64::NAN), i.unwrap_or(f64::NAN));
        format!("{f:>w$.1} {:>4.0}%", 100.0 * f / i)
    };
    let m = |v: &Value, input: &Value| {
        format!(
            "{} {}",
            turn(v, input, "frame", 5),
            turn(v, input, "span", 6)
        )
    };
    let im = &r["input"]["motion"];
    println!(
        "{:<22} | {:>11} {:>12} | {:>11} {:>12}",
        "",
        "frame",
        format!("{SPAN} frames"),
        "frame",
        format!("{SPAN} frames")
    );
    println!(
        "{:<22} | {:>25} | {:>25}",
        format!("input ({} spans)", im["asl"]["spans"]),
        m(&im["asl"], &im["asl"]),
        m(&im["video"], &im["video"])
    );
    // One row per avatar: its ASL and hand-video cells (`cell(avatar's, input's)`).
    let avatar_rows = |cell: &dyn Fn(&Value, &Value) -> String, width: usize| {
        for a in r["avatars"].as_array().unwrap() {
            println!(
                "{:<22} | {:>width$} | {:>width$}",
                a["avatar"].as_str().unwrap(),
                cell(&a["motion"]["asl"], &im["asl"]),
                cell(&a["motion"]["video"], &im["video"])
            );
        }
    };
    avatar_rows(&m, 25);
    println!(
        "\nThe hand alone per frame against the input's motion: the input palm's per-frame turn \
         after a centered {SPAN}-frame mean (zero lag, jitter cut about {SPAN} times; \
         side-frames with {SPAN} + 1 tracked frames around them), median in degrees and the \
         hand's ratio to it"
    );
    let mm = |v: &Value, input: &Value| turn(v, input, "motion", 5);
    println!("{:<22} | {:>11} | {:>11}", "", "ASL clips", "hand video");
    println!(
        "{:<22} | {:>11} | {:>11}",
        format!(
            "input motion ({} / {})",
            im["asl"]["motionFrames"], im["video"]["motionFrames"]
        ),
        mm(&im["asl"], &im["asl"]),
        mm(&im["video"], &im["video"])
    );
    avatar_rows(&mm, 11);
    println!(
        "\nHand video with the Kinect session's wrists (right arm solved from a body tracker), \
         turns as above; frames the turn limit slowed"
    );
    if let Some(first) = r["avatars"].as_array().unwrap().first() {
        println!(
            "{:<22} | {} |",
            "input (MediaPipe palm)",
            cell(&first["kinect"]["input"])
        );
    }
    for a in r["avatars"].as_array().unwrap() {
        let k = &a["kinect"];
        let slowed = k["slowed"].as_array().unwrap();
        println!(
            "{:<22} | {} | slowed {}: {}",
            a["avatar"].as_str().unwrap(),
            cell(&k["turns"]),
            slowed.len(),
            joined(slowed)
        );
    }
    println!("\nSide-frames slowed by the turn limit (arm.maxTurnSpeed): ASL clips / hand video");
    for a in r["avatars"].as_array().unwrap() {
        let l = &a["limited"];
        let asl = l["asl"].as_array().unwrap();
        println!(
            "  {:<20} {} / {}: {}",
            a["avatar"].as_str().unwrap(),
            asl.len(),
            l["video"],
            joined(asl)
        );
    }
    println!(
        "\nThe hand lost or back with the arm still solved from the pose (ASL clips and hand \
         video): side-frames, wrist move (cm) and arm turn (degrees), median / max; \
         arm-frames the turn limit slowed in all"
    );
    for a in r["avatars"].as_array().unwrap() {
        let h = &a["handovers"];
        let part = |k: &str| {
            let x = &h[k];
            format!(
                "{k} {:>3}: {:>4.1} / {:>4.1} cm, {:>4.1} / {:>4.1} deg",
                x["n"],
                x["moved"]["median"].as_f64().unwrap_or(f64::NAN),
                x["moved"]["max"].as_f64().unwrap_or(0.0),
                x["turn"]["median"].as_f64().unwrap_or(f64::NAN),
                x["turn"]["max"].as_f64().unwrap_or(0.0)
            )
        };
        println!(
            "  {:<20} {} | {} | slowed {:>3} | largest: {}",
            a["avatar"].as_str().unwrap(),
            part("lost"),
            part("back"),
            a["armFramesSlowed"],
            joined(h["largest"].as_array().unwrap())
        );
    }
    println!(
        "\nA hand dropped for one frame in {DROP_EVERY} (ASL clips and the Kinect-paired session, \
         the arm still placed): into and out of the drop, wrist move (cm) and arm turn \
         (degrees), median / max"
    );
    for a in r["avatars"].as_array().unwrap() {
        let d = &a["dropped"];
        let f = |k: &str, m: &str| d[k][m].as_f64().unwrap_or(f64::NAN);
        println!(
            "  {:<20} {:>4} side-frames: {:>4.1} / {:>4.1} cm, {:>4.1} / {:>4.1} deg",
            a["avatar"].as_str().unwrap(),
            d["n"],
            f("moved", "median"),
            f("moved", "max"),
            f("turn", "median"),
            f("turn", "max")
        );
    }
    println!("\nHand selection, side-frames resolved (left / right):");
    for (title, key) in [("ASL clips (6)", "asl"), ("hand video", "video")] {
        let c = &r["selection"][key];
        let pair = |k: &str| format!("{} / {}", c[0][k], c[1][k]);
        println!(
            "  {title:<14} swapped {}, jumped {}, duplicate {}",
            pair("swapped"),
            pair("jumped"),
            pair("duplicate")
        );
    }
    for (title, key) in [("robot", "worst"), ("woman-vrm1", "worstHuman")] {
        println!("\nLargest avatar turns ({title}):");
        for w in r[key].as_array().unwrap() {
            println!(
                "  {}:{} {} {} avatar {:.1} input {:.1}{}",
                w["clip"].as_str().unwrap(),
                w["frame"],
                w["side"].as_str().unwrap(),
                w["bone"].as_str().unwrap(),
                w["avatar_turn"].as_f64().unwrap(),
                w["input_turn"].as_f64().unwrap(),
                if w["limited"].as_bool() == Some(true) {
                    " (slowed)"
                } else {
                    ""
                }
            );
        }
    }
}
