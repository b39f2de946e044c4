//! Torso eval (issue 12): the torso from the app or from tracking, and every arm target right.
//!
//! ```text
//! cargo run --release --example eval_torso            # tables; exit status 1 if acceptance fails
//! cargo run --release --example eval_torso -- --frames   # also every Kinect frame's rotations
//! ```
//!
//! Avatars: the shared robot (`../shared/avatars/debug-robot.vrm`), the generated human-
//! proportioned VRM 1.0 fixture and the VRM 0.x fixture (`tests/fixtures/`).
//!
//! ## 1. Synthetic users (`tests/support/torso_user.rs`)
//! A user whose hips turn, whose upper body pivots rigidly about the hip center (lean forward
//! 20 degrees, turn 30, side bend 15, their combinations), whose head turns and nods, with
//! both hands held in the upper body's frame (hand landmarks from the shared hand video, the
//! left hand its mirror image), 8 frames per pose, 12 poses. Per avatar and torso source:
//! * `app torso (frame.torso), tracker wrists`: the app gives the user's torso as local
//!   rotations (hips, spine, head) and wrists in front of the posed shoulders; error = the
//!   index distal by forward kinematics of the APP's torso plus handrig's arm, hand and finger
//!   bones, to the target DIP `wrist + (hand DIP - hand wrist)` (the seed formula);
//! * `same, torso not given (before issue 12)`: the same frames without `frame.torso`:
//!   handrig solves the arms for a rest torso, the app draws them on its own;
//! * `app torso, pose input`: pose landmarks instead of wrists, the arm placed relative to
//!   the app's torso;
//! * `tracked from pose`, `tracked from body joints`: `torso: "pose"` from the MediaPipe pose
//!   landmarks or from the same body as body-tracker joints.
//!
//! For pose input the target DIP is computed here from the known user: the avatar's upper-
//! arm joint posed by the torso alone, plus `s * T * (user DIP - user shoulder)` with `T` the
//! turn from the user's known upper-torso frame to the avatar's. Torso error: the largest
//! angle over all frames between the avatar's upper-torso frame (the bone the arms hang from,
//! times its rest frame), head and hips and the user's known ones.
//! Acceptance: median <= 0.5 mm, max <= 2 mm (reachable targets), torso within 3 degrees.
//!
//! ## 2. The shared Kinect session (`../shared/data/pose/kinect-upper-body.json`)
//! Body joints (mapping in docs/how-it-works/torso.md; the recording is mirrored: x negated), default
//! options (`torso: "pose"`, filtering and dropout on): per frame the chest (upper torso
//! relative to the hips: lean, side bend, twist), the head (relative to the upper torso:
//! pitch, tilt, turn), the hips' yaw and the shrug, degrees; their ranges, the largest frame-
//! to-frame step of the chest's and head's world rotations (a flip would be a step near 180),
//! and the largest excess over the limits. Plus fingertip alignment on it: Kinect wrists
//! placed relative to the avatar's posed shoulders (`wrist = posed upper-arm joint + s *
//! (kinect wrist - kinect shoulder)`), paired frame by frame with the hand video (right hand
//! with the right wrist; left with `mirror` and the left wrist).
//! Acceptance: no step above 20 degrees, no limit exceeded (0.1 degree slack), alignment median
//! <= 0.5 mm and max <= 2 mm on reachable frames.
//!
//! ## 3. The ASL clips (`../shared/data/asl/*.json`)
//! MediaPipe Pose + Hands of four signers, `torso: "pose"` from the pose, default options:
//! the same ranges and steps, and the rig's own alignment report for the signer's right hand.

use handrig_support::recordings;
use handrig_support::stats;
use handrig_support::torso_user;

use glam::{Quat, Vec3};
use handrig::humanoid::bones::{Finger, HumanBone as B, Side};
use handrig::math::robust_mean;
use handrig::math::{swing_twist, twist_angle};
use handrig::mediapipe::{
    pose_landmark as pl, CameraMapping, FrameInput, HandObservation, Handedness, WristObservation,
    MAX_HANDS,
};
use handrig::torso::{BodyJoint, BodyObservation, TorsoSource, LIMITS, TORSO_BONES};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput, WorldPose, BONE_COUNT};

const AVATARS: [(&str, &str); 3] = [
    ("debug-robot", recordings::ROBOT),
    ("human-proportions", recordings::FIXTURE_VRM1),
    ("vrm0-fingers", recordings::FIXTURE_VRM0),
];

/// Angle (degrees) between rotations, accurate near 0 (q and -q equal).
fn angle_deg(a: Quat, b: Quat) -> f32 {
    let d = a * b.conjugate();
    (2.0 * d.xyz().length().atan2(d.w.abs())).to_degrees()
}

/// `[forward, sideways, twist]` (degrees) of a rotation of a +Y chain: its swing about +X
/// and +Z, its twist about +Y (the split the limits use).
fn components(q: Quat) -> [f32; 3] {
    let (swing, twist) = swing_twist(q, Vec3::Y);
    let s = swing.to_scaled_axis();
    [
        s.x.to_degrees(),
        s.z.to_degrees(),
        twist_angle(twist, Vec3::Y).to_degrees(),
    ]
}

struct Errors {
    mm: Vec<f32>,
    total: usize,
    torso_deg: f32,
}

impl Errors {
    fn new() -> Self {
        Errors {
            mm: Vec::new(),
            total: 0,
            torso_deg: 0.0,
        }
    }
}

/// `reachable/total | median | p95 | max` (mm) and whether median <= 0.5 mm and max <= 2 mm.
fn cells(e: &Errors) -> (String, bool) {
    let s = stats::sorted(e.mm.clone());
    let (median, p95, max) = (
        stats::percentile(&s, 50.0),
        stats::percentile(&s, 95.0),
        s.last().copied().unwrap_or(f32::NAN),
    );
    let ok = !s.is_empty() && median <= 0.5 && max <= 2.0;
    (
        format!(
            "{}/{} | {median:.4} | {p95:.4} | {max:.4}",
            s.len(),
            e.total
        ),
        ok,
    )
}

/// The two hands of frame `k` turned with the user's upper body (camera axes): the recorded
/// right hand (labelled "Left", un-mirrored) and its mirror image as the left.
fn user_hands(video: &[HandObservation], k: usize, upper: Quat) -> [HandObservation; 2] {
    let turn = torso_user::camera_rotation(upper);
    let mut right = video[(7 * k) % video.len()];
    right.image = None;
    right.score = 0.95;
    right.world = right.world.map(|p| turn * p);
    let mut left = right;
    left.handedness = Handedness::Right;
    left.world = video[(7 * k) % video.len()]
        .world
        .map(|p| turn * Vec3::new(-p.x, p.y, p.z));
    [right, left]
}

/// Target DIP of the hand driving `side` for pose input, from the known user (see the docs).
#[allow(clippy::too_many_arguments)]
fn pose_target(
    skel: &Skeleton,
    torso_local: &[Quat; BONE_COUNT],
    side: Side,
    frame: &FrameInput,
    hand: usize,
    camera: CameraMapping,
    scale: f32,
    turn: Quat,
) -> Vec3 {
    let mut world = WorldPose::default();
    skel.forward(torso_local, &mut world);
    let anchor = world.position[side.arm()[1].index()];
    let pose = frame.pose.as_ref().expect("pose input");
    let (sh, wr) = match camera.pose_side_for(side) {
        Side::Left => (pl::LEFT_SHOULDER, pl::LEFT_WRIST),
        Side::Right => (pl::RIGHT_SHOULDER, pl::RIGHT_WRIST),
    };
    let h = &frame.hands[hand].world;
    anchor
        + scale
            * (turn
                * (camera.to_avatar(pose.world[wr] - pose.world[sh])
                    + camera.to_avatar(h[7] - h[0])))
}

/// The index distal's world position for `local`.
fn index_distal(skel: &Skeleton, local: &[Quat; BONE_COUNT], side: Side) -> Vec3 {
    let mut world = WorldPose::default();
    skel.forward(local, &mut world);
    world.position[side.finger(Finger::Index)[2].index()]
}

/// `local` with the arm, hand and finger bones of both sides at rest (the torso alone).
fn torso_only(local: &[Quat; BONE_COUNT]) -> [Quat; BONE_COUNT] {
    let mut t = *local;
    for side in Side::BOTH {
        let [_, upper, lower, hand] = side.arm();
        for b in [upper, lower, hand]
            .into_iter()
            .chain(Finger::ALL.iter().flat_map(|f| side.finger(*f)))
        {
            t[b.index()] = Quat::IDENTITY;
        }
    }
    t
}

#[derive(Clone, Copy, PartialEq)]
enum Synthetic {
    AppWrists,
    NotGiven,
    AppPose,
    TrackedPose,
    TrackedBody,
}

impl Synthetic {
    const ALL: [Synthetic; 5] = [
        Synthetic::AppWrists,
        Synthetic::NotGiven,
        Synthetic::AppPose,
        Synthetic::TrackedPose,
        Synthetic::TrackedBody,
    ];
    fn label(self) -> &'static str {
        match self {
            Synthetic::AppWrists => "app torso (frame.torso), tracker wrists",
            Synthetic::NotGiven => "same, torso not given to handrig (before issue 12)",
            Synthetic::AppPose => "app torso (frame.torso), pose input",
            Synthetic::TrackedPose => "torso: \"pose\", from the pose",
            Synthetic::TrackedBody => "torso: \"pose\", from body joints",
        }
    }
    /// Part of the acceptance (the baseline is not).
    fn accepted(self) -> bool {
        self != Synthetic::NotGiven
    }
}

fn synthetic(skel: &Skeleton, method: Synthetic, video: &[HandObservation]) -> Errors {
    let version = skel.version();
    let mut e = Errors::new();
    for pose in torso_user::poses() {
        let source = match method {
            Synthetic::TrackedPose | Synthetic::TrackedBody => TorsoSource::Pose,
            _ => TorsoSource::Frame,
        };
        let options = RigOptions {
            torso: source,
            contact: no_contact(),
            ..RigOptions::per_frame()
        };
        let mut rig = Rig::new(skel.clone(), options).expect("rig");
        let cam = rig.options().camera();
        let mut out = SolveOutput::default();
        // The app's torso (internal frame): hips yaw, the spine bone, the head bone.
        let mut app = [Quat::IDENTITY; BONE_COUNT];
        app[B::Hips.index()] = pose.hips();
        app[B::Spine.index()] = pose.spine;
        app[B::Head.index()] = pose.head;
        let mut given = [None; 8];
        for (slot, b) in TORSO_BONES.iter().enumerate() {
            given[slot] = Some(version.rotation_to_internal(app[b.index()]));
        }
        let mut app_world = WorldPose::default();
        skel.forward(&app, &mut app_world);
        let top = rig.torso().top();
        for k in 0..8 {
            let u = torso_user::points(&pose, &torso_user::arms(k));
            let hands = user_hands(video, k, pose.upper());
            let mut f = recordings::frame_of(&hands);
            f.time_ms = k as f64 * 1000.0 / 30.0;
            match method {
                Synthetic::AppWrists | Synthetic::NotGiven => {
                    for side in Side::BOTH {
                        let s = if side == Side::Left { 1.0 } else { -1.0 };
                        let reach = Vec3::new(-0.1 * s, -0.14 + 0.01 * k as f32, 0.26);
                        let wrist = app_world.position[side.arm()[1].index()]
                            + app_world.rotation[top.index()] * reach;
                        f.wrists[side.index()] = Some(WristObservation {
                            position: version.position_to_internal(wrist),
                            rotation: None,
                        });
                    }
                    if method == Synthetic::AppWrists {
                        f.torso = given;
                    }
                }
                Synthetic::AppPose => {
                    f.pose = Some(torso_user::pose_landmarks(&u));
                    f.torso = given;
                }
                Synthetic::TrackedPose => f.pose = Some(torso_user::pose_landmarks(&u)),
                Synthetic::TrackedBody => {
                    // Arms from the pose, the torso from the body joints.
                    f.pose = Some(torso_user::pose_landmarks(&u));
                    let mut body = torso_user::body_joints(&u, 0.95);
                    body.position = body.position.map(|p| version.position_to_internal(p));
                    f.body = Some(body);
                }
            }
            rig.solve(&f, &mut out).expect("solve");
            // Compared with the skeleton (internal frame) below.
            out.turn_to_internal_frame(rig.skeleton().version());
            // What the app draws: its torso where it drives it, handrig's bones elsewhere.
            let mut drawn = out.local;
            if source == TorsoSource::Frame {
                for b in TORSO_BONES {
                    if !rig.drives(b) {
                        drawn[b.index()] = app[b.index()];
                    }
                }
            }
            let mut world = WorldPose::default();
            skel.forward(&drawn, &mut world);
            let avatar_upper = world.rotation[top.index()] * rig.torso().rest_upper();
            if source == TorsoSource::Pose {
                e.torso_deg = e
                    .torso_deg
                    .max(angle_deg(avatar_upper, pose.upper()))
                    .max(angle_deg(
                        world.rotation[B::Head.index()],
                        pose.head_world(),
                    ))
                    .max(angle_deg(out.local[B::Hips.index()], pose.hips()));
            }
            for side in Side::BOTH {
                e.total += 1;
                let Some(a) = out.alignment[side.index()] else {
                    continue;
                };
                if !a.reachable {
                    continue;
                }
                let hand = out.hands[side.index()].expect("a hand").index;
                let target = match method {
                    Synthetic::AppWrists | Synthetic::NotGiven => {
                        let h = &f.hands[hand].world;
                        version.position_to_internal(f.wrists[side.index()].unwrap().position)
                            + cam.to_avatar(h[7] - h[0])
                    }
                    _ => {
                        let turn = avatar_upper * pose.upper().inverse();
                        pose_target(
                            skel,
                            &torso_only(&drawn),
                            side,
                            &f,
                            hand,
                            cam,
                            rig.body().scale(),
                            turn,
                        )
                    }
                };
                e.mm.push(1000.0 * (index_distal(skel, &drawn, side) - target).length());
            }
        }
    }
    e
}

/// Torso recovery from the pose under landmark noise: every pose landmark moved by uniform
/// noise in `±amplitude` per coordinate (a fixed pseudo-random sequence), default options
/// (One Euro filtering on), 40 frames per pose, frames 10..40 scored. Returns the upper-torso,
/// head and hips errors (degrees) over all poses and frames.
fn noisy(skel: &Skeleton, amplitude: f32, video: &[HandObservation]) -> [Vec<f32>; 3] {
    let mut seed = 0x2545_f491_u32;
    let mut uniform = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed as f32 / u32::MAX as f32) * 2.0 - 1.0
    };
    let mut errors = [Vec::new(), Vec::new(), Vec::new()];
    for pose in torso_user::poses() {
        let options = RigOptions {
            torso: TorsoSource::Pose,
            contact: no_contact(),
            ..RigOptions::default()
        };
        let mut rig = Rig::new(skel.clone(), options).expect("rig");
        let top = rig.torso().top();
        let mut out = SolveOutput::default();
        for k in 0..40 {
            let u = torso_user::points(&pose, &torso_user::arms(k));
            let mut landmarks = torso_user::pose_landmarks(&u);
            for p in &mut landmarks.world {
                *p += amplitude * Vec3::new(uniform(), uniform(), uniform());
            }
            let mut f = recordings::frame_of(&user_hands(video, k, pose.upper()));
            f.pose = Some(landmarks);
            f.time_ms = k as f64 * 1000.0 / 30.0;
            rig.solve(&f, &mut out).expect("solve");
            // Compared with the skeleton (internal frame) below.
            out.turn_to_internal_frame(rig.skeleton().version());
            if k >= 10 {
                let upper = out.world.rotation[top.index()] * rig.torso().rest_upper();
                errors[0].push(angle_deg(upper, pose.upper()));
                errors[1].push(angle_deg(
                    out.world.rotation[B::Head.index()],
                    pose.head_world(),
                ));
                errors[2].push(angle_deg(out.local[B::Hips.index()], pose.hips()));
            }
        }
    }
    errors
}

/// Kinect joint names for each body joint (`frame.body`).
const KINECT_BODY: [(BodyJoint, &str); 10] = [
    (BodyJoint::Hips, "PELVIS"),
    (BodyJoint::LeftUpperLeg, "HIP_LEFT"),
    (BodyJoint::RightUpperLeg, "HIP_RIGHT"),
    (BodyJoint::LeftUpperArm, "SHOULDER_LEFT"),
    (BodyJoint::RightUpperArm, "SHOULDER_RIGHT"),
    (BodyJoint::Nose, "NOSE"),
    (BodyJoint::LeftEye, "EYE_LEFT"),
    (BodyJoint::RightEye, "EYE_RIGHT"),
    (BodyJoint::LeftEar, "EAR_LEFT"),
    (BodyJoint::RightEar, "EAR_RIGHT"),
];

/// The recording's mirrored frame to the avatar's (subject's left at +X).
fn kinect_point(j: [f32; 4]) -> Vec3 {
    Vec3::new(-j[0], j[1], j[2])
}

/// Per-frame torso readings of a solved avatar, degrees.
#[derive(Clone, Copy, Default)]
struct TorsoRow {
    hips_yaw: f32,
    chest: [f32; 3],
    head: [f32; 3],
    shrug: f32,
    chest_world: Quat,
    head_world: Quat,
}

fn torso_row(rig: &Rig, out: &SolveOutput) -> TorsoRow {
    let skel = rig.skeleton();
    let top = rig.torso().top();
    let hips = out.local[B::Hips.index()];
    let chest_world = out.world.rotation[top.index()];
    let head_parent = skel
        .parent(B::Neck)
        .filter(|_| skel.has(B::Neck))
        .unwrap_or(top);
    let head_parent = out.world.rotation[head_parent.index()];
    let head_world = out.world.rotation[B::Head.index()];
    let shrug = if skel.has(B::LeftShoulder) {
        // The torso's rotation of the shoulder (without the arm solver's turn on far reaches).
        let q = rig.shoulder_base(Side::Left);
        let lift = q * skel.rest_local(B::LeftUpperArm);
        lift.y.atan2(lift.truncate_y().length()).to_degrees()
    } else {
        0.0
    };
    TorsoRow {
        hips_yaw: components(hips)[2],
        chest: components(hips.inverse() * chest_world),
        head: components(head_parent.inverse() * head_world),
        shrug,
        chest_world,
        head_world,
    }
}

trait TruncateY {
    fn truncate_y(self) -> Vec3;
}
impl TruncateY for Vec3 {
    fn truncate_y(self) -> Vec3 {
        Vec3::new(self.x, 0.0, self.z)
    }
}

/// Ranges, largest steps and limit excess of a run of torso rows.
struct Summary {
    min: [f32; 8],
    max: [f32; 8],
    step_chest: f32,
    step_head: f32,
    excess: f32,
}

fn summarize(rows: &[TorsoRow], starts: &[usize]) -> Summary {
    let value = |r: &TorsoRow| {
        [
            r.hips_yaw, r.chest[0], r.chest[1], r.chest[2], r.head[0], r.head[1], r.head[2],
            r.shrug,
        ]
    };
    let mut s = Summary {
        min: [f32::INFINITY; 8],
        max: [f32::NEG_INFINITY; 8],
        step_chest: 0.0,
        step_head: 0.0,
        excess: 0.0,
    };
    let l = LIMITS;
    let limit = [
        (l.hips_yaw, l.hips_yaw),
        (l.spine_extension, l.spine_flexion),
        (l.spine_lateral, l.spine_lateral),
        (l.spine_twist, l.spine_twist),
        (l.head_extension, l.head_flexion),
        (l.head_lateral, l.head_lateral),
        (l.head_twist, l.head_twist),
        (l.shoulder_depression, l.shoulder_elevation),
    ];
    for (i, r) in rows.iter().enumerate() {
        let v = value(r);
        for k in 0..8 {
            s.min[k] = s.min[k].min(v[k]);
            s.max[k] = s.max[k].max(v[k]);
            let (lo, hi) = (-limit[k].0.to_degrees(), limit[k].1.to_degrees());
            s.excess = s.excess.max(lo - v[k]).max(v[k] - hi);
        }
        if i > 0 && !starts.contains(&i) {
            s.step_chest = s
                .step_chest
                .max(angle_deg(r.chest_world, rows[i - 1].chest_world));
            s.step_head = s
                .step_head
                .max(angle_deg(r.head_world, rows[i - 1].head_world));
        }
    }
    s
}

fn summary_row(name: &str, what: &str, s: &Summary) -> String {
    let r = |k: usize| format!("{:.1} .. {:.1}", s.min[k], s.max[k]);
    format!(
        "| {name} | {what} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} |",
        r(0),
        r(1),
        r(2),
        r(3),
        r(4),
        r(5),
        r(6),
        r(7),
        s.step_chest,
        s.step_head,
        s.excess.max(0.0)
    )
}

/// The Kinect session on one avatar: torso rows (right-side run) and alignment errors of both
/// sides (mm, reachable frames), with the frame count.
fn kinect_run(skel: &Skeleton, print_frames: bool) -> (Vec<TorsoRow>, Vec<f32>, usize) {
    let kinect = recordings::kinect();
    let idx = |n: &str| kinect.joint(n).unwrap_or_else(|| panic!("joint {n}"));
    let version = skel.version();
    let bodies: Vec<BodyObservation> = kinect
        .frames
        .iter()
        .map(|f| {
            let mut b = BodyObservation::default();
            for (joint, name) in KINECT_BODY {
                let j = f[idx(name)];
                b.position[joint.index()] = version.position_to_internal(kinect_point(j));
                b.confidence[joint.index()] = j[3];
            }
            b
        })
        .collect();
    // Body scale as eval_alignment: avatar arm over the user's robust arm length.
    let mut lengths = Vec::new();
    for f in &kinect.frames {
        for (s, e, w) in [
            ("SHOULDER_LEFT", "ELBOW_LEFT", "WRIST_LEFT"),
            ("SHOULDER_RIGHT", "ELBOW_RIGHT", "WRIST_RIGHT"),
        ] {
            let [a, b, c] = [s, e, w].map(|n| kinect_point(f[idx(n)]));
            lengths.push((b - a).length() + (c - b).length());
        }
    }
    let mut scratch = vec![0.0; lengths.len()];
    let user_arm = robust_mean(&lengths, &mut scratch).expect("arms");
    let avatar_arm = Side::BOTH
        .iter()
        .map(|s| {
            let [_, _, lower, hand] = s.arm();
            skel.rest_local(lower).length() + skel.rest_local(hand).length()
        })
        .sum::<f32>()
        / 2.0;
    let scale = avatar_arm / user_arm;
    let video = recordings::hand_video();
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    let mut total = 0;
    let mut slowed_frames = 0;
    for side in Side::BOTH {
        let options = RigOptions {
            torso: TorsoSource::Pose,
            mirror: side == Side::Left,
            contact: no_contact(),
            ..RigOptions::default()
        };
        // A second rig with the same options and body input gives the torso alone: where the
        // avatar's shoulders are this frame (what an app with its own FK reads from the model).
        let mut torso_rig = Rig::new(skel.clone(), options).expect("rig");
        let mut rig = Rig::new(skel.clone(), options).expect("rig");
        let (mut t_out, mut out) = (SolveOutput::default(), SolveOutput::default());
        let (sh, wr) = match side {
            Side::Left => ("SHOULDER_LEFT", "WRIST_LEFT"),
            Side::Right => ("SHOULDER_RIGHT", "WRIST_RIGHT"),
        };
        for (i, f) in kinect.frames.iter().enumerate() {
            let time_ms = i as f64 * 1000.0 / 30.0;
            let body_only = FrameInput {
                time_ms,
                body: Some(bodies[i]),
                ..FrameInput::default()
            };
            torso_rig.solve(&body_only, &mut t_out).expect("solve");
            // Compared with the skeleton (internal frame) below.
            t_out.turn_to_internal_frame(torso_rig.skeleton().version());
            let shoulder = t_out.world.position[side.arm()[1].index()];
            let wrist = shoulder + scale * (kinect_point(f[idx(wr)]) - kinect_point(f[idx(sh)]));
            let hands = &video[i % video.len()];
            let mut frame = recordings::frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            frame.time_ms = time_ms;
            frame.body = Some(bodies[i]);
            frame.wrists[side.index()] = Some(WristObservation {
                position: version.position_to_internal(wrist),
                rotation: None,
            });
            let limited = rig.turns_limited(side);
            rig.solve(&frame, &mut out).expect("solve");
            let slowed = rig.turns_limited(side) > limited;
            // Compared with the skeleton (internal frame) below.
            out.turn_to_internal_frame(rig.skeleton().version());
            if side == Side::Right {
                let row = torso_row(&rig, &out);
                if print_frames {
                    println!(
                        "| {i} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |",
                        row.hips_yaw,
                        row.chest[0],
                        row.chest[1],
                        row.chest[2],
                        row.head[0],
                        row.head[1],
                        row.head[2],
                        row.shrug
                    );
                }
                rows.push(row);
            }
            let Some(a) = out.alignment[side.index()] else {
                continue;
            };
            if slowed {
                // The turn limit slowed the arm: shown short of the target by design (the
                // report says how far); not part of the exactness.
                slowed_frames += 1;
                continue;
            }
            total += 1;
            if a.reachable {
                // The rig's target DIP: built from the filtered wrist and hand (filtering is
                // on); the index distal of what is shown (after the easing stage).
                let tip = out.world.position[side.finger(Finger::Index)[2].index()];
                errors.push(1000.0 * (tip - a.target_dip).length());
            }
        }
    }
    if slowed_frames > 0 {
        eprintln!("(not counted in the next row: {slowed_frames} hand-frames the turn limit slowed the arm on)");
    }
    (rows, errors, total)
}

/// Self-contact off: this measures alignment on the torso alone (self-contact moves the hand
/// on purpose near the face and the body; `eval_contact` measures it).
fn no_contact() -> handrig::contact::ContactOptions {
    handrig::contact::ContactOptions {
        enabled: false,
        ..Default::default()
    }
}

fn main() {
    let print_frames = std::env::args().any(|a| a == "--frames");
    let video = recordings::hand_video_first();
    let mut pass = true;

    println!("## 1. Synthetic users: 12 torso poses x 8 frames x both hands\n");
    println!("| avatar | method | reachable | median mm | p95 mm | max mm | torso error deg |");
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: |");
    for (name, path) in AVATARS {
        let skel = recordings::vrm(path);
        for method in Synthetic::ALL {
            let e = synthetic(&skel, method, &video);
            let torso = match method {
                Synthetic::TrackedPose | Synthetic::TrackedBody => {
                    if e.torso_deg > 3.0 {
                        pass = false;
                    }
                    format!("{:.4}", e.torso_deg)
                }
                _ => "given".into(),
            };
            let (c, ok) = cells(&e);
            println!("| {name} | {} | {c} | {torso} |", method.label());
            if method.accepted() && !ok {
                pass = false;
            }
        }
    }

    println!(
        "\nTorso recovery from the pose under landmark noise (uniform per coordinate, default"
    );
    println!(
        "options: One Euro filtering on; 12 poses x frames 10..40), degrees, median / p95 / max:\n"
    );
    println!("| avatar | noise | upper torso | head | hips |");
    println!("| --- | ---: | --- | --- | --- |");
    for (name, path) in &AVATARS[..2] {
        let skel = recordings::vrm(path);
        for amplitude in [0.005, 0.01, 0.02] {
            let e = noisy(&skel, amplitude, &video);
            let cell = |v: &Vec<f32>| {
                let s = stats::sorted(v.clone());
                format!(
                    "{:.2} / {:.2} / {:.2}",
                    stats::percentile(&s, 50.0),
                    stats::percentile(&s, 95.0),
                    s.last().copied().unwrap_or(f32::NAN)
                )
            };
            if amplitude <= 0.01 && stats::percentile(&stats::sorted(e[0].clone()), 95.0) > 3.0 {
                pass = false;
            }
            println!(
                "| {name} | ±{:.0} mm | {} | {} | {} |",
                amplitude * 1000.0,
                cell(&e[0]),
                cell(&e[1]),
                cell(&e[2])
            );
        }
    }

    println!("\n## 2. Kinect session, torso: \"pose\" from body joints (default options)\n");
    if print_frames {
        println!("Every frame, robot (degrees):\n");
        println!("| frame | hips yaw | chest lean | chest side | chest twist | head pitch | head tilt | head turn | shrug |");
        println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    }
    let mut kinect_rows = Vec::new();
    println!("| avatar | reachable | median mm | p95 mm | max mm |");
    println!("| --- | ---: | ---: | ---: | ---: |");
    for (k, (name, path)) in AVATARS.iter().enumerate() {
        let skel = recordings::vrm(path);
        let (rows, errors, total) = kinect_run(&skel, print_frames && k == 0);
        let e = Errors {
            mm: errors,
            total,
            torso_deg: 0.0,
        };
        let (c, ok) = cells(&e);
        println!("| {name} | {c} |");
        pass &= ok;
        kinect_rows.push((name, rows));
    }
    println!(
        "\nEvery 20th frame, robot (degrees; chest relative to the hips, head to the chest):\n"
    );
    println!("| frame | hips yaw | chest lean | chest side | chest twist | head pitch | head tilt | head turn | shrug |");
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (i, r) in kinect_rows[0].1.iter().enumerate().step_by(20) {
        println!(
            "| {i} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |",
            r.hips_yaw,
            r.chest[0],
            r.chest[1],
            r.chest[2],
            r.head[0],
            r.head[1],
            r.head[2],
            r.shrug
        );
    }

    println!("\n## Ranges (degrees), largest frame-to-frame step, limit excess\n");
    println!("| avatar | data | hips yaw | chest lean | chest side | chest twist | head pitch | head tilt | head turn | shrug | chest step | head step | excess |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | ---: | ---: | ---: |");
    for (name, rows) in &kinect_rows {
        let s = summarize(rows, &[0]);
        if s.step_chest > 20.0 || s.step_head > 20.0 || s.excess > 0.1 {
            pass = false;
        }
        println!("{}", summary_row(name, "Kinect", &s));
    }

    // 3. ASL clips, pose input.
    let mut asl_errors = Vec::new();
    let mut asl_total = 0;
    // Frames the turn limit slowed the arm on (shown short of the target by design; the
    // report says how far): counted apart, not in the exactness.
    let mut asl_slowed: Vec<f32> = Vec::new();
    for (name, path) in AVATARS {
        let skel = recordings::vrm(path);
        let mut rows = Vec::new();
        let mut starts = Vec::new();
        for clip in recordings::ASL {
            let frames = recordings::asl(clip);
            let mut rig = Rig::new(
                skel.clone(),
                RigOptions {
                    torso: TorsoSource::Pose,
                    contact: no_contact(),
                    ..RigOptions::default()
                },
            )
            .expect("rig");
            let mut out = SolveOutput::default();
            starts.push(rows.len());
            for f in &frames {
                let limited = rig.turns_limited(Side::Right);
                rig.solve(f, &mut out).expect("solve");
                let slowed = rig.turns_limited(Side::Right) > limited;
                // Compared with the skeleton (internal frame) below.
                out.turn_to_internal_frame(rig.skeleton().version());
                rows.push(torso_row(&rig, &out));
                if name == "debug-robot" {
                    if let Some(a) = out.alignment[Side::Right.index()] {
                        if a.reachable && a.error.is_finite() && slowed {
                            asl_slowed.push(1000.0 * a.error);
                            continue;
                        }
                        asl_total += 1;
                        if a.reachable && a.error.is_finite() {
                            asl_errors.push(1000.0 * a.error);
                        }
                    }
                }
            }
        }
        let s = summarize(&rows, &starts);
        if s.step_chest > 20.0 || s.step_head > 20.0 || s.excess > 0.1 {
            pass = false;
        }
        println!("{}", summary_row(name, "ASL (4 clips)", &s));
    }
    let e = Errors {
        mm: asl_errors,
        total: asl_total,
        torso_deg: 0.0,
    };
    let (c, ok) = cells(&e);
    println!("\nAlignment on the ASL clips, torso: \"pose\" from the pose, the signer's right hand (the rig's report), debug-robot:\n");
    println!("| reachable | median mm | p95 mm | max mm |\n| ---: | ---: | ---: | ---: |\n| {c} |");
    println!(
        "\n(Not counted: {} frames the turn limit slowed the arm on, largest miss {:.1} mm.)",
        asl_slowed.len(),
        asl_slowed.iter().copied().fold(0.0_f32, f32::max)
    );
    pass &= ok;

    if pass {
        println!("\nacceptance: PASS");
    } else {
        println!("\nacceptance: FAIL");
        std::process::exit(1);
    }
}
