//! Legs (issue 51): what the legs stage does on head-and-shoulders video, and on synthetic
//! full-body motion whose truth is known.
//!
//! ```text
//! cargo run --release --example eval_legs [-- --write-frames eval/frames/legs-synthetic.json]
//! ```
//!
//! `--write-frames FILE` also writes the walk and the squat of section 2 as `rig.solve`
//! frames (pose only, MediaPipe's shapes), for `node eval/speed.mjs --frames FILE`.
//!
//! ## 1. Head and shoulders (the shared ASL clips, legs out of frame)
//! Every clip of `../shared/data/asl/` (seven) on the three real avatars and two generated ones with the default options and with `torso: "pose"`:
//! the largest turn of any leg bone from rest and between two frames (degrees), the largest
//! hips offset (mm). The acceptance: no leg bone moves more than 1 degree.
//!
//! ## 2. Synthetic full-body motion (not rendered)
//! Four motions at 30 fps (walking in place, a step sideways and back, a squat, standing on
//! one leg), each given as the room positions of the hip center and of both ankles over time;
//! the user's knees by two-bone IK (thigh 0.42 m, shin 0.40 m, knees forward), the heels and
//! toes flat under the ankles on the floor (toes down 20 degrees on a raised foot). MediaPipe's
//! landmarks from that: world landmarks relative to the hip center (camera axes) with 5 mm of
//! deterministic noise on each coordinate, image landmarks by an orthographic view of 2 m per
//! image height (16:9), the upper body from the first frame of an ASL clip, visibility 0.95.
//! Scored on the avatar (its own lengths): knee and ankle positions against the user's thigh
//! and shin directions at the avatar's lengths from its hip joint (mm), knee angle (degrees),
//! foot sliding (mm per frame on frames where the user's foot stands still on the floor, the
//! avatar's ankle in the room: world position plus `hipsOffset`), frames with a sole more than
//! 2 cm under the floor, frames with a knee bent backwards. These are synthetic landmarks, not
//! MediaPipe's tracking of a rendered video: they test the solve, the limits and the
//! grounding, not MediaPipe's leg errors (the rendered bench is not done for the legs).
use handrig_support::recordings;

use glam::Vec3;
use handrig::humanoid::bones::Side;
use handrig::legs::{leg_bones, leg_landmarks, Soles};
use handrig::{FrameInput, Rig, RigOptions, Skeleton, SolveOutput};

const THIGH: f32 = 0.42;
const SHIN: f32 = 0.40;
const ANKLE_HEIGHT: f32 = 0.07;
const HIP_HALF: f32 = 0.09;
const FPS: f32 = 30.0;

/// The user's room pose at a time: hip center, ankles `[left, right]` (avatar axes: +X the
/// user's left, +Y up, +Z toward the camera).
struct Room {
    hip: Vec3,
    ankles: [Vec3; 2],
}

fn smooth(x: f32) -> f32 {
    let t = x.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

const STAND: f32 = 0.97 * (THIGH + SHIN) + ANKLE_HEIGHT;

fn foot(x: f32, lift: f32, forward: f32) -> Vec3 {
    Vec3::new(x, ANKLE_HEIGHT + lift, forward)
}

/// The four motions: name, frames, pose at frame `i`.
fn motion(name: &str, i: usize) -> Room {
    let t = i as f32 / FPS;
    match name {
        "walk in place" => {
            // 1.2 s per cycle, each foot up 20 cm and 8 cm forward in its half.
            let phase = t / 1.2 * core::f32::consts::TAU;
            let up = |p: f32| p.sin().max(0.0);
            let (l, r) = (up(phase), up(phase + core::f32::consts::PI));
            Room {
                hip: Vec3::new(0.0, STAND, 0.0),
                ankles: [
                    foot(HIP_HALF, 0.2 * l, 0.08 * l),
                    foot(-HIP_HALF, 0.2 * r, 0.08 * r),
                ],
            }
        }
        "step sideways" => {
            // Left foot out 20 cm (0.3-1.0 s), hips over (0.8-1.6 s), right foot follows
            // (1.4-2.1 s); then back the same way from 2.5 s.
            let go = |a: f32, b: f32| smooth((t - a) / (b - a)) - smooth((t - a - 2.2) / (b - a));
            let lift = |a: f32, b: f32| {
                let u = ((t - a) / (b - a)).clamp(0.0, 1.0);
                let v = ((t - a - 2.2) / (b - a)).clamp(0.0, 1.0);
                0.06 * ((u * core::f32::consts::PI).sin() + (v * core::f32::consts::PI).sin())
            };
            Room {
                hip: Vec3::new(0.1 * go(0.8, 1.6), STAND, 0.0),
                ankles: [
                    foot(HIP_HALF + 0.2 * go(0.3, 1.0), lift(0.3, 1.0), 0.0),
                    foot(-HIP_HALF + 0.2 * go(1.4, 2.1), lift(1.4, 2.1), 0.0),
                ],
            }
        }
        "squat" => {
            // Down 35 cm (sitting back 12 cm) over 0.75 s and back up over 0.75 s, standing
            // 1.5 s, again.
            let d = (t / 1.5 * core::f32::consts::PI).sin().max(0.0);
            Room {
                hip: Vec3::new(0.0, STAND - 0.35 * d, -0.12 * d),
                ankles: [foot(HIP_HALF, 0.0, 0.0), foot(-HIP_HALF, 0.0, 0.0)],
            }
        }
        _ => {
            // Standing on the right leg: hips 5 cm over it, the left foot up 30 cm and 15 cm
            // forward from 0.5 to 1.0 s, held.
            let u = smooth((t - 0.5) / 0.5);
            Room {
                hip: Vec3::new(-0.05 * smooth(t / 0.5), STAND, 0.0),
                ankles: [foot(HIP_HALF, 0.3 * u, 0.15 * u), foot(-HIP_HALF, 0.0, 0.0)],
            }
        }
    }
}

const MOTIONS: [&str; 4] = ["walk in place", "step sideways", "squat", "one leg"];
const FRAMES: usize = 135;

/// The user's knee (two-bone IK, the knee forward) for a hip joint and an ankle.
fn user_knee(hip: Vec3, ankle: Vec3) -> Vec3 {
    let d = ankle - hip;
    let r = d.length().min(THIGH + SHIN - 1e-4);
    let dir = d.normalize();
    let along = (THIGH * THIGH - SHIN * SHIN + r * r) / (2.0 * r);
    let h = (THIGH * THIGH - along * along).max(0.0).sqrt();
    let bend = (Vec3::Z - dir * dir.dot(Vec3::Z)).normalize();
    hip + dir * along + bend * h
}

/// Deterministic noise in [-1, 1].
fn noise(seed: &mut u32) -> f32 {
    *seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
    (*seed >> 8) as f32 / (1u32 << 23) as f32 - 1.0
}

/// The frame of the user's room pose (see the module docs), with the joints it was made from
/// (per side: hip joint, knee, ankle, room).
fn frame(base: &FrameInput, room: &Room, i: usize, seed: &mut u32) -> (FrameInput, [[Vec3; 3]; 2]) {
    let mut f = *base;
    f.time_ms = i as f64 * 1000.0 / f64::from(FPS);
    let pose = f.pose.as_mut().expect("pose");
    let mut joints = [[Vec3::ZERO; 3]; 2];
    // Room (avatar axes) to MediaPipe's world (camera axes, relative to the hip center).
    let to_camera = |p: Vec3| {
        let v = p - room.hip;
        Vec3::new(v.x, -v.y, -v.z)
    };
    for side in Side::BOTH {
        let s = side.index();
        let x = if side == Side::Left {
            HIP_HALF
        } else {
            -HIP_HALF
        };
        let hip = room.hip + Vec3::new(x, 0.0, 0.0);
        let ankle = room.ankles[s];
        let knee = user_knee(hip, ankle);
        joints[s] = [hip, knee, ankle];
        // A raised foot points its toes 20 degrees down.
        let raised = smooth((ankle.y - ANKLE_HEIGHT) / 0.05);
        let pitch = (20.0 * raised).to_radians();
        let toe = Vec3::new(0.0, -0.2 * pitch.sin(), 0.2 * pitch.cos());
        let heel = ankle + Vec3::new(0.0, -ANKLE_HEIGHT, -0.05);
        let [h, k, a, he, t] = leg_landmarks(side);
        for (idx, p) in [(h, hip), (k, knee), (a, ankle), (he, heel), (t, heel + toe)] {
            pose.world[idx] = to_camera(p);
        }
    }
    // An upright upper body facing the camera (the subject's left at +x), arms down.
    for (idx, p) in [
        (0, Vec3::new(0.0, 0.62, 0.08)),
        (2, Vec3::new(0.03, 0.65, 0.06)),
        (5, Vec3::new(-0.03, 0.65, 0.06)),
        (7, Vec3::new(0.07, 0.63, 0.0)),
        (8, Vec3::new(-0.07, 0.63, 0.0)),
        (9, Vec3::new(0.025, 0.58, 0.07)),
        (10, Vec3::new(-0.025, 0.58, 0.07)),
        (11, Vec3::new(0.18, 0.5, 0.0)),
        (12, Vec3::new(-0.18, 0.5, 0.0)),
        (13, Vec3::new(0.2, 0.24, 0.0)),
        (14, Vec3::new(-0.2, 0.24, 0.0)),
        (15, Vec3::new(0.21, 0.0, 0.02)),
        (16, Vec3::new(-0.21, 0.0, 0.02)),
    ] {
        pose.world[idx] = to_camera(room.hip + p);
    }
    for p in pose.world.iter_mut() {
        *p += 0.005 * Vec3::new(noise(seed), noise(seed), noise(seed));
    }
    pose.visibility = [0.95; 33];
    let aspect = 16.0 / 9.0;
    f.image_aspect = aspect;
    f.pose_image = Some(pose.world.map(|w| {
        let room_x = room.hip.x + w.x;
        let room_y = room.hip.y - w.y;
        Vec3::new(
            0.5 + room_x / (2.0 * aspect),
            0.5 - (room_y - 0.9) / 2.0,
            0.0,
        )
    }));
    (f, joints)
}

#[derive(Default)]
struct Score {
    knee_mm: Vec<f32>,
    ankle_mm: Vec<f32>,
    knee_deg: Vec<f32>,
    slide_mm: Vec<f32>,
    under: usize,
    backwards: usize,
    frames: usize,
}

fn mean(v: &[f32]) -> f32 {
    if v.is_empty() {
        f32::NAN
    } else {
        v.iter().sum::<f32>() / v.len() as f32
    }
}

fn max(v: &[f32]) -> f32 {
    v.iter().copied().fold(0.0, f32::max)
}

fn synthetic(
    name: &str,
    avatar: &Skeleton,
    options: RigOptions,
    base: &FrameInput,
    score: &mut Score,
) {
    let soles = Soles::new(avatar).expect("soles");
    let mut rig = Rig::new(avatar.clone(), options).expect("rig");
    let mut out = SolveOutput::default();
    let mut seed = 7u32;
    let mut last: [Option<(Vec3, Vec3)>; 2] = [None; 2];
    for i in 0..FRAMES {
        let room = motion(name, i);
        let (f, joints) = frame(base, &room, i, &mut seed);
        rig.solve(&f, &mut out).expect("solve");
        out.turn_to_internal_frame(rig.skeleton().version());
        score.frames += 1;
        for side in Side::BOTH {
            let s = side.index();
            let [up, low, ft, _] = leg_bones(side).map(|b| out.world.position[b.index()]);
            let a = (low - up).length();
            let b = (ft - low).length();
            let [h, k, an] = joints[s];
            let knee = up + a * (k - h).normalize();
            let ankle = knee + b * (an - k).normalize();
            score.knee_mm.push(1000.0 * (low - knee).length());
            score.ankle_mm.push(1000.0 * (ft - ankle).length());
            let truth = (k - h).angle_between(an - k).to_degrees();
            let shown = (low - up).angle_between(ft - low).to_degrees();
            score.knee_deg.push((truth - shown).abs());
            // Backwards: the knee behind the hip-ankle line by more than 5 mm on a bent knee.
            let line = (ft - up).normalize();
            let off = (low - up) - line * line.dot(low - up);
            if shown > 5.0 && off.z < -0.005 {
                score.backwards += 1;
            }
            // Sliding: the avatar's ankle in the room while the user's stands still on the floor.
            let room_ankle = ft + out.hips_offset;
            let standing = an.y < ANKLE_HEIGHT + 0.005;
            if let (true, Some((prev_truth, prev_avatar))) = (standing, last[s]) {
                if (an - prev_truth).length() < 1e-4 {
                    score
                        .slide_mm
                        .push(1000.0 * (room_ankle - prev_avatar).length());
                }
            }
            last[s] = Some((an, room_ankle));
            let foot = leg_bones(side)[2].index();
            let sole = soles.lowest(side, out.world.position[foot], out.world.rotation[foot]);
            if sole.y + out.hips_offset.y < soles.floor - 0.02 {
                score.under += 1;
            }
        }
    }
}

/// The walk and the squat as `rig.solve` frames in MediaPipe's shapes (JSON).
fn write_frames(path: &str, base: &FrameInput) {
    let mut frames = Vec::new();
    let mut seed = 7u32;
    for (m, name) in ["walk in place", "squat"].iter().enumerate() {
        for i in 0..FRAMES {
            let (f, _) = frame(base, &motion(name, i), i, &mut seed);
            let pose = f.pose.expect("pose");
            let image = f.pose_image.expect("image");
            // Five decimals (10 µm, a hundredth of the noise): a smaller file.
            let r = |x: f32| (f64::from(x) * 1e5).round() / 1e5;
            let v = |p: Vec3, k: usize| vec![r(p.x), r(p.y), r(p.z), r(pose.visibility[k])];
            frames.push(serde_json::json!({
                "timeMs": (m * FRAMES + i) as f64 * 1000.0 / f64::from(FPS),
                "hands": [],
                "pose": {
                    "landmarks": image.iter().enumerate().map(|(k, p)| v(*p, k)).collect::<Vec<_>>(),
                    "worldLandmarks": pose.world.iter().enumerate().map(|(k, p)| v(*p, k)).collect::<Vec<_>>(),
                },
            }));
        }
    }
    let doc = serde_json::json!({
        "about": "Synthetic full-body frames of eval/rust/eval_legs.rs (walk in place, then a squat; 30 fps; pose only, legs in view): for node eval/speed.mjs --frames.",
        "width": 1920,
        "height": 1080,
        "frames": frames,
    });
    std::fs::write(path, serde_json::to_string(&doc).expect("json")).expect("write frames");
    println!("wrote {path}: {} frames\n", 2 * FRAMES);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--write-frames") {
        let base = recordings::asl(recordings::ASL[0])[0];
        write_frames(args.get(i + 1).expect("--write-frames FILE"), &base);
    }
    let avatars = [
        ("debug-robot", recordings::ROBOT),
        ("human-proportions", recordings::FIXTURE_VRM1),
        ("vrm0-fingers", recordings::FIXTURE_VRM0),
        ("woman-vrm1", "tests/fixtures/avatars/woman-vrm1.vrm"),
        ("child-vrm1", "tests/fixtures/avatars/child-vrm1.vrm"),
    ];
    println!("## 1. Head and shoulders: the shared ASL clips\n");
    println!("| avatar | options | clip | frames | largest leg turn from rest (deg) | largest leg turn between frames (deg) | largest hips offset (mm) |");
    println!("| --- | --- | --- | ---: | ---: | ---: | ---: |");
    let mut worst = 0.0f32;
    // Every clip of the shared folder (the seven .json files).
    let mut clips: Vec<String> = std::fs::read_dir(recordings::path("../shared/data/asl"))
        .expect("../shared/data/asl")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".json"))
        .map(|n| format!("../shared/data/asl/{n}"))
        .collect();
    clips.sort();
    for (name, path) in avatars {
        let avatar = recordings::vrm(path);
        for options in ["{}", r#"{ "torso": "pose", "mirror": true }"#] {
            let o = RigOptions::from_json(options).expect("options");
            for clip in &clips {
                let frames = recordings::asl(clip);
                let mut rig = Rig::new(avatar.clone(), o).expect("rig");
                let mut out = SolveOutput::default();
                let (mut rest, mut step, mut hips) = (0.0f32, 0.0f32, 0.0f32);
                let mut prev = None;
                for f in &frames {
                    rig.solve(f, &mut out).expect("solve");
                    let q: Vec<_> = Side::BOTH
                        .iter()
                        .flat_map(|s| leg_bones(*s))
                        .map(|b| out.local[b.index()])
                        .collect();
                    for (k, q) in q.iter().enumerate() {
                        rest = rest.max(q.angle_between(glam::Quat::IDENTITY).to_degrees());
                        if let Some(p) = &prev {
                            let p: &Vec<glam::Quat> = p;
                            step = step.max(q.angle_between(p[k]).to_degrees());
                        }
                    }
                    hips = hips.max(1000.0 * out.hips_offset.length());
                    prev = Some(q);
                }
                worst = worst.max(rest);
                let clip = clip.rsplit('/').next().unwrap_or(clip);
                println!(
                    "| {name} | `{options}` | {clip} | {} | {rest:.3} | {step:.3} | {hips:.1} |",
                    frames.len()
                );
            }
        }
    }
    println!("\nLargest leg turn over all: {worst:.3} degrees (acceptance: at most 1).\n");

    println!("## 2. Synthetic full-body motion\n");
    println!("Options: default (grounded: hips moving, feet planted), and the legs as tracked (`legs.moveHips` and `legs.plant` off; sliding and the floor then mean little).\n");
    println!("| motion | options | avatar | knee mm (mean / max) | ankle mm (mean / max) | knee angle deg (mean / max) | sliding mm per standing frame (mean / max, frames) | frames with a sole > 2 cm under the floor | knee bent backwards |");
    println!("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    let base = recordings::asl(recordings::ASL[0])[0];
    let tracked = r#"{ "legs": { "moveHips": false, "plant": false } }"#;
    for motion_name in MOTIONS {
        for (label, options) in [("default", "{}"), ("as tracked", tracked)] {
            for (name, path) in avatars {
                let avatar = recordings::vrm(path);
                let mut s = Score::default();
                let options = RigOptions::from_json(options).expect("options");
                synthetic(motion_name, &avatar, options, &base, &mut s);
                println!(
                "| {motion_name} | {label} | {name} | {:.1} / {:.1} | {:.1} / {:.1} | {:.2} / {:.2} | {:.2} / {:.2} ({}) | {} of {} | {} |",
                mean(&s.knee_mm),
                max(&s.knee_mm),
                mean(&s.ankle_mm),
                max(&s.ankle_mm),
                mean(&s.knee_deg),
                max(&s.knee_deg),
                mean(&s.slide_mm),
                max(&s.slide_mm),
                s.slide_mm.len(),
                s.under,
                s.frames,
                s.backwards
            );
            }
        }
    }
}
