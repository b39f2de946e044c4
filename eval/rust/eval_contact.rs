//! Self-contact eval on the shared recordings: the avatar's finger-to-face distance with and
//! without contact retargeting.
//!
//! ```text
//! cargo run --release --example eval_contact
//! ```
//!
//! Data:
//! * the Azure Kinect session `../shared/data/pose/kinect-upper-body.json` paired frame by
//!   frame with the hand video `../shared/data/hands/right-hand-video-mediapipe.json`, as
//!   `eval/rust/eval_alignment.rs` pairs them (right side: the video's right hand on the Kinect
//!   right wrist; left side: the same video with `mirror: true` on the Kinect LEFT wrist, the
//!   arm that comes to the face around frames 130-160). Tracker input: `wrists` and the
//!   Kinect's `NOSE`, `EYE_*`, `EAR_*` joints as `face`, all carried into the avatar's frame
//!   by one similarity (the recording's x negated; the shoulders' midpoint onto the avatar's
//!   upper-arm joints' midpoint; scale = avatar arm / user arm, the user's the robust mean
//!   over the session);
//! * the four ASL clips `../shared/data/asl/*.json` (MediaPipe Pose and Hands of one signer:
//!   `eat` fingertips to the mouth, `thanks` fingers from the chin, `brother` hand at the
//!   forehead, `sister` hand at the chin), pose input (face landmarks from the pose),
//!   automatic body-scale calibration, both hands;
//!
//! on three avatars: the shared robot (its face 3-4 times a person's), the human-proportioned
//! VRM 1.0 fixture and the VRM 0.x fixture. Each frame is solved twice, by a rig with the
//! defaults (contact on) and one with `contact.enabled: false` (plain fingertip alignment),
//! both without filtering and dropout easing (every frame on its own data).
//!
//! Measure, per side and frame whose user fingertip (index tip: the pose or tracker wrist plus
//! the hand landmarks' wrist-to-tip offset) is within `contact.radius` (0.5 head breadths) of
//! the user's face: the user's face frame and anchors as handrig builds them
//! (`UserFace::from_pose` / `from_tracker`), the nearest anchor `a` and the fingertip's
//! offset from it in face-local coordinates; the **expected** avatar distance is that offset's
//! length times the avatar's face size (the same place on the avatar's face); the **avatar**
//! distance is from the avatar's index fingertip after IK (forward kinematics of the returned
//! rotations) to the avatar's anchor `a`. Columns: frames (side-frames near the face; in
//! parentheses those within half the radius, where contact is in full), the median expected
//! distance, the median avatar distance without and with contact, and the median and p95 of
//! |avatar - expected| without and with contact (mm).

use handrig_support::recordings;

use glam::Vec3;
use handrig::contact::face::pose_tip;
use handrig::contact::{ImageFit, UserFace, ANCHORS};
use handrig::humanoid::bones::{Finger, Side};
use handrig::math::robust_mean;
use handrig::mediapipe::{
    pose_landmark as pl, CameraMapping, FrameInput, TrackerFace, WristObservation, MAX_HANDS,
};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput};

/// Distances (m) of one side-frame near the face.
#[derive(Clone, Copy)]
struct Sample {
    expected: f32,
    plain: f32,
    contact: f32,
    full: bool,
}

fn median(v: &mut [f32]) -> f32 {
    if v.is_empty() {
        return f32::NAN;
    }
    v.sort_by(f32::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn p95(v: &mut [f32]) -> f32 {
    if v.is_empty() {
        return f32::NAN;
    }
    v.sort_by(f32::total_cmp);
    let k = ((0.95 * v.len() as f32).ceil() as usize).clamp(1, v.len());
    v[k - 1]
}

fn row(data: &str, avatar: &str, samples: &[Sample]) {
    let col = |f: &dyn Fn(&Sample) -> f32| samples.iter().map(f).collect::<Vec<f32>>();
    let mm = |x: f32| format!("{:.1}", x * 1e3);
    let full = samples.iter().filter(|s| s.full).count();
    println!(
        "| {data} | {avatar} | {} ({full}) | {} | {} | {} | {} / {} | {} / {} |",
        samples.len(),
        mm(median(&mut col(&|s| s.expected))),
        mm(median(&mut col(&|s| s.plain))),
        mm(median(&mut col(&|s| s.contact))),
        mm(median(&mut col(&|s| (s.plain - s.expected).abs()))),
        mm(p95(&mut col(&|s| (s.plain - s.expected).abs()))),
        mm(median(&mut col(&|s| (s.contact - s.expected).abs()))),
        mm(p95(&mut col(&|s| (s.contact - s.expected).abs()))),
    );
}

/// Where the user's fingertip is for a side: the space the rig measures it in (pose: user
/// space; tracker: the avatar's frame) and the user's face there.
struct UserSide {
    tip: Vec3,
    face: UserFace,
}

/// Solves `frame` with both rigs and, when the side's user fingertip is near the face,
/// records a sample.
fn measure(
    rigs: &mut [Rig; 2],
    outs: &mut [SolveOutput; 2],
    frame: &FrameInput,
    user: impl Fn(Side, &SolveOutput) -> Option<UserSide>,
    samples: &mut Vec<Sample>,
) {
    for (rig, out) in rigs.iter_mut().zip(outs.iter_mut()) {
        rig.solve(frame, out).expect("solve");
        // Compared with the skeleton (internal frame) below.
        out.turn_to_internal_frame(rig.skeleton().version());
    }
    let radius = rigs[0].options().contact.radius;
    for side in Side::BOTH {
        let s = side.index();
        let Some(u) = user(side, &outs[0]) else {
            continue;
        };
        let local = u.face.frame.to_local(u.tip);
        let (anchor, e) = handrig::contact::face::nearest(local, &u.face.anchors);
        if e >= radius {
            continue;
        }
        let fresh = |o: &SolveOutput| o.alignment[s].is_some_and(|a| a.reachable);
        if !(fresh(&outs[0]) && fresh(&outs[1])) {
            continue;
        }
        let size = rigs[0].contact().face().size;
        let dist = |rig: &Rig, o: &SolveOutput| {
            let tip = o.fingertips[s][Finger::Index.index()].expect("index tip");
            (tip - rig.contact().anchor_world(anchor, &o.world)).length()
        };
        samples.push(Sample {
            expected: e * size,
            contact: dist(&rigs[0], &outs[0]),
            plain: dist(&rigs[1], &outs[1]),
            full: e <= 0.5 * radius,
        });
    }
}

fn rigs(skel: &Skeleton, mirror: bool, depth_trust: f32) -> [Rig; 2] {
    let mut on = RigOptions {
        mirror,
        ..RigOptions::per_frame()
    };
    on.contact.depth_trust = depth_trust;
    let mut off = on;
    off.contact.enabled = false;
    [on, off].map(|o| Rig::new(skel.clone(), o).expect("rig"))
}

/// Kinect point (mirrored recording frame) to a right-handed frame facing +Z, left = +X.
fn kinect_point(j: [f32; 4]) -> Vec3 {
    Vec3::new(-j[0], j[1], j[2])
}

/// Mean rest arm length (upper + lower) of the avatar's two arms.
fn avatar_arm(skel: &Skeleton) -> f32 {
    handrig::humanoid::measure::avatar_arm_length(skel)
}

fn kinect_samples(skel: &Skeleton) -> Vec<Sample> {
    let kinect = recordings::kinect();
    let j = |n: &str| kinect.joint(n).unwrap_or_else(|| panic!("joint {n}"));
    let shoulders = [j("SHOULDER_LEFT"), j("SHOULDER_RIGHT")];
    let elbows = [j("ELBOW_LEFT"), j("ELBOW_RIGHT")];
    let wrists = [j("WRIST_LEFT"), j("WRIST_RIGHT")];
    let face_joints = [
        j("NOSE"),
        j("EYE_LEFT"),
        j("EYE_RIGHT"),
        j("EAR_LEFT"),
        j("EAR_RIGHT"),
    ];
    let mut lengths = Vec::new();
    for f in &kinect.frames {
        for k in 0..2 {
            let p = |i: usize| kinect_point(f[i]);
            lengths.push(
                (p(elbows[k]) - p(shoulders[k])).length() + (p(wrists[k]) - p(elbows[k])).length(),
            );
        }
    }
    let mut scratch = vec![0.0; lengths.len()];
    let user_arm = robust_mean(&lengths, &mut scratch).expect("arm samples");
    let scale = avatar_arm(skel) / user_arm;
    let avatar_mid = Side::BOTH
        .iter()
        .map(|s| skel.rest_world(s.arm()[1]).unwrap())
        .sum::<Vec3>()
        / 2.0;
    let video = recordings::hand_video();
    let mut samples = Vec::new();
    for mirror in [false, true] {
        // Right side: the video's hand as is; left side: mirrored onto the avatar's left.
        let side = if mirror { Side::Left } else { Side::Right };
        let camera = CameraMapping {
            input_mirrored: false,
            mirror,
        };
        let mut rigs = rigs(skel, mirror, 1.0);
        let mut outs = [SolveOutput::default(), SolveOutput::default()];
        for (i, f) in kinect.frames.iter().enumerate() {
            let user_mid = (kinect_point(f[shoulders[0]]) + kinect_point(f[shoulders[1]])) / 2.0;
            let map = |p: Vec3| {
                let p = avatar_mid + scale * (p - user_mid);
                skel.version().position_to_internal(p)
            };
            let hands = &video[i];
            let mut frame = recordings::frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            frame.time_ms = i as f64 * 1000.0 / 30.0;
            let wrist = map(kinect_point(f[wrists[side.index()]]));
            frame.wrists[side.index()] = Some(WristObservation {
                position: wrist,
                rotation: None,
            });
            let p = |k: usize| Some(map(kinect_point(f[face_joints[k]])));
            let face = TrackerFace {
                nose: p(0),
                eyes: [p(1), p(2)],
                ears: [p(3), p(4)],
                mouth: None,
            };
            frame.face = Some(face);
            let user = |s: Side, out: &SolveOutput| {
                if s != side {
                    return None;
                }
                let h = frame.hands()[out.hands[s.index()]?.index];
                let tip = skel.version().position_to_internal(wrist)
                    + camera.to_avatar(h.world[8] - h.world[0]);
                let face = UserFace::from_tracker(&face, skel.version())?;
                Some(UserSide { tip, face })
            };
            measure(&mut rigs, &mut outs, &frame, user, &mut samples);
        }
    }
    samples
}

fn asl_samples(skel: &Skeleton, clip: &str, depth_trust: f32) -> Vec<Sample> {
    let frames = recordings::asl(clip);
    let mut rigs = rigs(skel, false, depth_trust);
    let mut outs = [SolveOutput::default(), SolveOutput::default()];
    let camera = rigs[0].options().camera();
    let min_visibility = rigs[0].options().calibration.min_visibility;
    let mut samples = Vec::new();
    for frame in &frames {
        let user = |side: Side, out: &SolveOutput| {
            let pose = frame.pose.as_ref()?;
            let h = frame.hands()[out.hands[side.index()]?.index];
            let k = match camera.pose_side_for(side) {
                Side::Left => pl::LEFT_WRIST,
                Side::Right => pl::RIGHT_WRIST,
            };
            let tip = camera.to_avatar(pose.world[k]) + camera.to_avatar(h.world[8] - h.world[0]);
            let face = UserFace::from_pose(pose, camera, min_visibility)?;
            // Where handrig measures the fingertip for pose input: across the camera from
            // the image, the depth trusted `depth_trust`.
            let fit = frame
                .pose_image
                .as_ref()
                .and_then(|img| ImageFit::from_pose(pose, img, min_visibility));
            let image_tip = h.image.map(|img| img[8]);
            let tip = pose_tip(&face, tip, image_tip, fit.as_ref(), camera, depth_trust);
            Some(UserSide { tip, face })
        };
        measure(&mut rigs, &mut outs, frame, user, &mut samples);
    }
    samples
}

fn main() {
    let avatars = [
        ("debug-robot", recordings::vrm(recordings::ROBOT)),
        (
            "human-proportions",
            recordings::vrm(recordings::FIXTURE_VRM1),
        ),
        ("vrm0-fingers", recordings::vrm(recordings::FIXTURE_VRM0)),
    ];
    println!("Avatar faces (derived defaults: head breadth, anchors from the head bone):");
    for (name, skel) in &avatars {
        let rig = Rig::new(skel.clone(), RigOptions::default()).expect("rig");
        let f = rig.contact().face();
        let c = rig.contact().colliders();
        println!(
            "  {name}: head breadth {:.3} m, nose {:.3} m in front of the head bone, chin {:.3} m below it; torso radius {:.3} m, head sphere {:.3} m",
            f.size,
            f.anchors[0].z,
            -f.anchors[1].y,
            c.torso.map_or(0.0, |t| t.radius),
            c.head.map_or(0.0, |h| h.1)
        );
        let _ = ANCHORS;
    }
    println!();
    println!("| data | avatar | side-frames near the face (full) | expected mm | plain mm | contact mm | plain error median / p95 mm | contact error median / p95 mm |");
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut worst_gain = f32::INFINITY;
    for (name, skel) in &avatars {
        let samples = kinect_samples(skel);
        row("Kinect + hand video", name, &samples);
        for clip in recordings::ASL {
            let label = std::path::Path::new(clip)
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or(clip);
            let as_tracked = asl_samples(skel, clip, 1.0);
            row(&format!("ASL {label}, depthTrust 1"), name, &as_tracked);
            let samples = asl_samples(skel, clip, 0.1);
            row(&format!("ASL {label}"), name, &samples);
            let err = |f: &dyn Fn(&Sample) -> f32| {
                median(&mut samples.iter().map(f).collect::<Vec<f32>>())
            };
            let plain = err(&|s| (s.plain - s.expected).abs());
            let contact = err(&|s| (s.contact - s.expected).abs());
            if !samples.is_empty() {
                worst_gain = worst_gain.min(plain / contact.max(1e-6));
            }
        }
    }
    println!();
    println!("Smallest ratio of plain to contact median error over the ASL rows: {worst_gain:.1}");
}
