//! Finger accuracy against the goals of issue 27, on every shared real recording and avatar.
//!
//! * **Bone directions**: for every finger bone-frame (every finger bone the avatar has, every
//!   frame a hand is solved, frames with an active joint limit included), the angle between the
//!   avatar bone (forward kinematics of the solved rotations) and the matching MediaPipe
//!   segment, both in their own palm frame ([`handrig::hand::palm_frame`]); median and p95 per
//!   recording and over all. Goal: median within 5 degrees, p95 within 15. The default
//!   strategy (`analytic`), one [`HandSolver`] per recording fed every frame in order (the
//!   rig's hand stage without its input checks and filters).
//!   Data: the hand video (the highest-scored hand, as the rig picks) and both hands of the six
//!   shared ASL clips (per frame and label the highest-scored hand), world landmarks through
//!   the rig's default camera mapping.
//! * **Pinches** (`retarget` strategy, automatic hand scale, the hand video): pinch frames are
//!   those whose user thumb and index tips are within 2 cm in MediaPipe's world landmarks
//!   (unscaled); the error is |avatar thumb-index tip distance - the user's, scaled to the
//!   avatar's hand| (fingertips: [`handrig::align::fingertip`]). Goal: at most 2 mm on every
//!   pinch frame.
//!
//! Avatars: the shared robot and the generated woman, man and child (VRM 1.0) and the woman as
//! VRM 0.x (`tests/fixtures/avatars`).
//!
//! ```text
//! cargo run --release --example eval_fingers            # tables
//! cargo run --release --example eval_fingers -- --json  # machine-readable
//! options: --avatar NAME (one of the five), --detail (per bone, limit-free / limit-active)
//! ```

use finger_dirs::{avatar_bone_dir, mp_segment};
use handrig_support::finger_dirs;
use handrig_support::recordings;
use handrig_support::stats;

use glam::{Quat, Vec3};
use handrig::align::fingertip;
use handrig::hand::{flip, palm_frame, Dof, HandSolver, HandStrategy, DOF_COUNT};
use handrig::mediapipe::{CameraMapping, HandObservation, HAND_LANDMARKS};
use handrig::{Finger, Rig, RigOptions, Side, Skeleton, SolveOutput, WorldPose, BONE_COUNT};
use serde_json::{json, Value};
use stats::{percentile, sorted};

type Landmarks = [Vec3; HAND_LANDMARKS];

/// Pinch frames: user thumb-index tip distance (world landmarks) under this, meters.
const PINCH: f32 = 0.02;

const AVATARS: [(&str, &str); 5] = [
    ("robot", recordings::ROBOT),
    ("woman", "tests/fixtures/avatars/woman-vrm1.vrm"),
    ("man", "tests/fixtures/avatars/man-vrm1.vrm"),
    ("child", "tests/fixtures/avatars/child-vrm1.vrm"),
    ("woman-vrm0", "tests/fixtures/avatars/woman-vrm0.vrm"),
];

/// One recording: per frame, the hand of each avatar side (`[left, right]`), avatar frame.
struct Recording {
    name: String,
    frames: Vec<[Option<Landmarks>; 2]>,
}

/// Per avatar side, the highest-scored hand of that side among `hands`.
fn by_side(hands: &[HandObservation], camera: CameraMapping) -> [Option<Landmarks>; 2] {
    let mut out: [Option<(f32, Landmarks)>; 2] = [None, None];
    for h in hands {
        let s = camera.avatar_side(h.handedness).index();
        if out[s].is_none_or(|(score, _)| h.score > score) {
            out[s] = Some((h.score, h.world.map(|p| camera.to_avatar(p))));
        }
    }
    out.map(|o| o.map(|(_, lm)| lm))
}

fn load_recordings() -> Vec<Recording> {
    let camera = CameraMapping::default();
    let mut recs = vec![Recording {
        name: "hand-video".into(),
        frames: recordings::hand_video()
            .iter()
            .map(|hands| {
                let mut f = [None, None];
                if let Some(h) = recordings::best_hand(hands) {
                    f[camera.avatar_side(h.handedness).index()] =
                        Some(h.world.map(|p| camera.to_avatar(p)));
                }
                f
            })
            .collect(),
    }];
    for path in recordings::ASL.iter().chain(recordings::ASL_MORE.iter()) {
        let name = path
            .rsplit('/')
            .next()
            .unwrap_or(path)
            .trim_end_matches(".json");
        recs.push(Recording {
            name: format!("asl/{name}"),
            frames: recordings::asl(path)
                .iter()
                .map(|f| by_side(&f.hands[..f.hand_count], camera))
                .collect(),
        });
    }
    recs
}

#[derive(Default)]
struct Directions {
    /// Angle per finger bone-frame, degrees.
    all: Vec<f32>,
    /// The same, per finger.
    per_finger: [Vec<f32>; 5],
    /// Bone-frames of fingers with an active limit.
    limited: usize,
    side_frames: usize,
    /// Angles of bone-frames whose hand the rig's chirality check passes (not mirrored).
    unmirrored: Vec<f32>,
    /// Side-frames the chirality check calls mirrored.
    mirrored_frames: usize,
    /// Angles per (finger, slot), split limit-free / limit-active (`--detail`).
    by_bone: [[[Vec<f32>; 2]; 3]; 5],
    /// Side-frames with each (finger, DOF) limit active (`--detail`).
    dof_limited: [[usize; DOF_COUNT]; 5],
}

fn directions(skel: &Skeleton, rec: &Recording) -> Result<Directions, String> {
    let mut solver = HandSolver::new(skel, HandStrategy::Analytic).map_err(|e| e.to_string())?;
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let mut world = WorldPose::default();
    let mut d = Directions::default();
    for frame in &rec.frames {
        local.fill(Quat::IDENTITY);
        let mut solved = [false; 2];
        for side in Side::BOTH {
            let Some(lm) = &frame[side.index()] else {
                continue;
            };
            solved[side.index()] = solver.solve(skel, side, lm, &mut local).is_some()
                && solver.report(side).status == handrig::hand::HandStatus::Solved;
        }
        skel.forward(&local, &mut world);
        for side in Side::BOTH {
            if !solved[side.index()] {
                continue;
            }
            let Some(lm) = &frame[side.index()] else {
                continue;
            };
            let pos = |b: handrig::HumanBone| world.position[b.index()];
            let fp = |f: Finger| side.finger(f)[0];
            let (Some(avatar_palm), Some(mp_palm)) = (
                palm_frame(
                    side,
                    pos(side.hand()),
                    pos(fp(Finger::Index)),
                    pos(fp(Finger::Little)),
                    pos(fp(Finger::Middle)),
                ),
                palm_frame(side, lm[0], lm[5], lm[17], lm[9]),
            ) else {
                continue;
            };
            d.side_frames += 1;
            let mirrored = flip::chirality(side, lm).is_some_and(|c| c < flip::MIRRORED);
            d.mirrored_frames += usize::from(mirrored);
            let rep = *solver.report(side);
            for (counts, flags) in d.dof_limited.iter_mut().zip(rep.limited.iter()) {
                for (c, l) in counts.iter_mut().zip(flags) {
                    *c += usize::from(*l);
                }
            }
            for finger in Finger::ALL {
                let lim = rep.finger_limited(finger);
                for (slot, bone) in side.finger(finger).into_iter().enumerate() {
                    if !skel.has(bone) {
                        continue;
                    }
                    let (Some(a), Some(m)) = (
                        avatar_bone_dir(skel, &world, side, finger, slot),
                        mp_segment(skel, lm, side, finger, slot),
                    ) else {
                        continue;
                    };
                    // `angle_between`, not `acos`: an f32 dot product cannot resolve
                    // angles below about 0.02 degrees.
                    let e = handrig::math::angle_between(
                        avatar_palm.transpose() * a,
                        mp_palm.transpose() * m,
                    )
                    .to_degrees();
                    d.all.push(e);
                    if !mirrored {
                        d.unmirrored.push(e);
                    }
                    d.by_bone[finger.index()][slot][usize::from(lim)].push(e);
                    d.per_finger[finger.index()].push(e);
                    d.limited += usize::from(lim);
                }
            }
        }
    }
    Ok(d)
}

struct Pinches {
    /// (frame, user distance mm, error mm) per pinch frame.
    frames: Vec<(usize, f32, f32)>,
    /// |avatar fingertip - scaled user fingertip| in the hand frame, every finger and frame, mm.
    tips: Vec<f32>,
}

fn pinches(skel: &Skeleton, rec: &Recording) -> Result<Pinches, String> {
    let mut solver = HandSolver::new(skel, HandStrategy::Retarget).map_err(|e| e.to_string())?;
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    let mut world = WorldPose::default();
    let mut out = Pinches {
        frames: Vec::new(),
        tips: Vec::new(),
    };
    for (i, frame) in rec.frames.iter().enumerate() {
        for side in Side::BOTH {
            let Some(lm) = &frame[side.index()] else {
                continue;
            };
            local.fill(Quat::IDENTITY);
            let Some(hand) = solver.solve(skel, side, lm, &mut local) else {
                continue;
            };
            if solver.report(side).status != handrig::hand::HandStatus::Solved {
                continue;
            }
            let scale = solver.hand_scale(side).ok_or("no hand scale")?;
            skel.forward(&local, &mut world);
            let h = side.hand().index();
            let (hp, hr) = (world.position[h], world.rotation[h]);
            let mut tip = [None; 5];
            for f in Finger::ALL {
                let target = scale * (hand.inverse() * (lm[f.landmarks()[3]] - lm[0]));
                if let Some(t) = fingertip(skel, &world, side, f) {
                    let t = hr.inverse() * (t - hp);
                    out.tips.push((t - target).length() * 1e3);
                    tip[f.index()] = Some(t);
                }
            }
            let user =
                (lm[Finger::Thumb.landmarks()[3]] - lm[Finger::Index.landmarks()[3]]).length();
            if let (true, Some(a), Some(b)) = (user < PINCH, tip[0], tip[1]) {
                out.frames
                    .push((i, user * 1e3, ((a - b).length() - scale * user).abs() * 1e3));
            }
        }
    }
    Ok(out)
}

/// The same pinch frames through the whole rig (`Rig::solve`, every default but
/// `handStrategy: "retarget"`, the hand video as 30 fps frames): the avatar's right thumb-index
/// fingertip distance (`SolveOutput::fingertips`) against the user's raw world distance times
/// the rig's hand scale. (frame, error mm) per pinch frame the rig solved, and the finger
/// jitter (mean turn of a right finger bone between frames, degrees). With
/// `HandStrategy::Analytic` the pinch list is empty (no retargeting report): the jitter only.
fn rig_pinches(
    skel: &Skeleton,
    filter: bool,
    strategy: HandStrategy,
) -> Result<(Vec<(usize, f32)>, f32), String> {
    let mut options = RigOptions {
        hand_strategy: strategy,
        ..RigOptions::default()
    };
    options.filter.enabled = filter;
    let mut rig = Rig::new(skel.clone(), options).map_err(|e| e.to_string())?;
    let mut out = SolveOutput::default();
    let raw = recordings::hand_video();
    let mut pinches = Vec::new();
    let (mut jitter, mut n) = (0.0_f64, 0usize);
    let mut previous: Option<[Quat; BONE_COUNT]> = None;
    for (i, frame) in recordings::hand_video_frames().iter().enumerate() {
        rig.solve(frame, &mut out).map_err(|e| e.to_string())?;
        // Jitter: mean change of the right finger bones' local rotations between frames.
        if let Some(prev) = &previous {
            for b in Finger::ALL.iter().flat_map(|f| Side::Right.finger(*f)) {
                if skel.has(b) {
                    let d = prev[b.index()].dot(out.local[b.index()]).abs().min(1.0);
                    jitter += f64::from((2.0 * d.acos()).to_degrees());
                    n += 1;
                }
            }
        }
        previous = Some(out.local);
        let Some(h) = recordings::best_hand(&raw[i]) else {
            continue;
        };
        let user = (h.world[Finger::Thumb.landmarks()[3]] - h.world[Finger::Index.landmarks()[3]])
            .length();
        let s = Side::Right.index();
        if let (true, Some(rep), Some(a), Some(b)) = (
            user < PINCH,
            out.retarget[s],
            out.fingertips[s][0],
            out.fingertips[s][1],
        ) {
            pinches.push((i, ((a - b).length() - rep.scale * user).abs() * 1e3));
        }
    }
    Ok((pinches, (jitter / n.max(1) as f64) as f32))
}

/// Gauss-Newton iterations of the retargeting through the rig (`handStrategy: "retarget"`,
/// every other default) over the hand video and the six ASL clips, both sides: mean, p95,
/// largest and how many side-frames hit the cap (50).
fn rig_iterations(skel: &Skeleton) -> Result<Value, String> {
    let options = RigOptions {
        hand_strategy: HandStrategy::Retarget,
        ..RigOptions::default()
    };
    let mut it = Vec::new();
    let mut clips = vec![recordings::hand_video_frames()];
    for path in recordings::ASL.iter().chain(recordings::ASL_MORE.iter()) {
        clips.push(recordings::asl(path));
    }
    for frames in &clips {
        let mut rig = Rig::new(skel.clone(), options).map_err(|e| e.to_string())?;
        let mut out = SolveOutput::default();
        for frame in frames {
            rig.solve(frame, &mut out).map_err(|e| e.to_string())?;
            it.extend(out.retarget.iter().flatten().map(|r| r.iterations as f32));
        }
    }
    let it = sorted(it);
    Ok(json!({
        "sideFrames": it.len(),
        "mean": it.iter().sum::<f32>() / it.len().max(1) as f32,
        "p95": percentile(&it, 95.0),
        "max": it.last(),
        "atCap": it.iter().filter(|v| **v >= 50.0).count(),
    }))
}

fn main() {
    if let Err(e) = run() {
        eprintln!("eval_fingers: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let json_out = std::env::args().any(|a| a == "--json");
    let detail = std::env::args().any(|a| a == "--detail");
    let recs = load_recordings();
    let mut rows = Vec::new();
    let only = std::env::args().skip_while(|a| a != "--avatar").nth(1);
    for (avatar, path) in AVATARS {
        if only.as_deref().is_some_and(|o| o != avatar) {
            continue;
        }
        let skel = recordings::vrm(path);
        let mut total = Directions::default();
        let mut per_rec = Vec::new();
        for rec in &recs {
            let d = directions(&skel, rec)?;
            let s = sorted(d.all.clone());
            per_rec.push(json!({
                "recording": rec.name,
                "sideFrames": d.side_frames,
                "boneFrames": s.len(),
                "limitActiveBoneFrames": d.limited,
                "medianDeg": percentile(&s, 50.0),
                "p95Deg": percentile(&s, 95.0),
            }));
            total.all.extend(&d.all);
            for (t, f) in total.per_finger.iter_mut().zip(&d.per_finger) {
                t.extend(f);
            }
            total.limited += d.limited;
            total.side_frames += d.side_frames;
            total.unmirrored.extend(&d.unmirrored);
            total.mirrored_frames += d.mirrored_frames;
            for f in 0..5 {
                for k in 0..3 {
                    for l in 0..2 {
                        total.by_bone[f][k][l].extend(&d.by_bone[f][k][l]);
                    }
                }
                for k in 0..DOF_COUNT {
                    total.dof_limited[f][k] += d.dof_limited[f][k];
                }
            }
        }
        if detail {
            println!("{avatar}: per bone (slot 0..2) median/p95 deg [bone-frames], limit-free | limit-active");
            for f in Finger::ALL {
                for k in 0..3 {
                    let st = |v: &Vec<f32>| {
                        let v = sorted(v.clone());
                        format!(
                            "{:6.2} {:6.2} [{:5}]",
                            percentile(&v, 50.0),
                            percentile(&v, 95.0),
                            v.len()
                        )
                    };
                    let b = &total.by_bone[f.index()][k];
                    println!("  {:<7} {k}: {} | {}", f.as_str(), st(&b[0]), st(&b[1]));
                }
                let lims: Vec<String> = Dof::ALL
                    .iter()
                    .filter(|d| total.dof_limited[f.index()][d.index()] > 0)
                    .map(|d| format!("{} {}", d.name(f), total.dof_limited[f.index()][d.index()]))
                    .collect();
                println!(
                    "  {:<7} limits active (side-frames): {}",
                    f.as_str(),
                    lims.join(", ")
                );
            }
        }
        let um = sorted(total.unmirrored);
        let s = sorted(total.all);
        let fingers: Vec<Value> = Finger::ALL
            .iter()
            .map(|f| {
                let v = sorted(total.per_finger[f.index()].clone());
                json!({ "finger": f.as_str(), "medianDeg": percentile(&v, 50.0), "p95Deg": percentile(&v, 95.0) })
            })
            .collect();
        let p = pinches(&skel, &recs[0])?;
        let tips = sorted(p.tips);
        let (rp, rig_jitter) = rig_pinches(&skel, true, HandStrategy::Retarget)?;
        let (rpu, _) = rig_pinches(&skel, false, HandStrategy::Retarget)?;
        let (_, analytic_jitter) = rig_pinches(&skel, true, HandStrategy::Analytic)?;
        let iterations = rig_iterations(&skel)?;
        let unfiltered = rpu.iter().map(|w| w.1).fold(f32::NAN, f32::max);
        let rig_worst = rp.iter().copied().max_by(|a, b| a.1.total_cmp(&b.1));
        let worst = p.frames.iter().copied().max_by(|a, b| a.2.total_cmp(&b.2));
        rows.push(json!({
            "avatar": avatar,
            "recordings": per_rec,
            "all": {
                "sideFrames": total.side_frames,
                "boneFrames": s.len(),
                "limitActiveBoneFrames": total.limited,
                "medianDeg": percentile(&s, 50.0),
                "p95Deg": percentile(&s, 95.0),
            },
            "unmirrored": {
                "recording": "ALL unmirrored",
                "sideFrames": total.side_frames - total.mirrored_frames,
                "boneFrames": um.len(),
                "limitActiveBoneFrames": Value::Null,
                "medianDeg": percentile(&um, 50.0),
                "p95Deg": percentile(&um, 95.0),
            },
            "fingers": fingers,
            "analyticJitterDeg": analytic_jitter,
            "pinch": {
                "frames": p.frames.len(),
                "maxErrorMm": worst.map(|w| w.2),
                "worstFrame": worst.map(|w| w.0),
                "perFrame": p.frames.iter().map(|(i, u, e)| json!({ "frame": i, "userMm": u, "errorMm": e })).collect::<Vec<_>>(),
                "tipMedianMm": percentile(&tips, 50.0),
                "rigFrames": rp.len(),
                "rigMaxErrorMm": rig_worst.map(|w| w.1),
                "rigWorstFrame": rig_worst.map(|w| w.0),
                "rigUnfilteredMaxErrorMm": unfiltered,
                "rigJitterDeg": rig_jitter,
                "rigIterations": iterations,
                "rigPerFrame": rp.iter().map(|(i, e)| json!({ "frame": i, "errorMm": e })).collect::<Vec<_>>(),
            },
        }));
    }
    if json_out {
        println!("{}", Value::Array(rows));
        return Ok(());
    }
    let f = |v: &Value, d: usize| v.as_f64().map_or("-".to_string(), |x| format!("{x:.d$}"));
    println!("finger bone directions in the palm frame (analytic), degrees, every finger bone-frame incl. limit-active");
    println!(
        "{:<11} {:<15} {:>6} {:>7} {:>7} {:>7} {:>7}",
        "avatar", "recording", "sides", "bones", "limit", "median", "p95"
    );
    for r in &rows {
        for x in r["recordings"]
            .as_array()
            .into_iter()
            .flatten()
            .chain([&r["all"], &r["unmirrored"]])
        {
            println!(
                "{:<11} {:<15} {:>6} {:>7} {:>7} {:>7} {:>7}",
                r["avatar"].as_str().unwrap_or(""),
                x["recording"].as_str().unwrap_or("ALL"),
                x["sideFrames"].to_string(),
                x["boneFrames"].to_string(),
                x["limitActiveBoneFrames"].to_string(),
                f(&x["medianDeg"], 2),
                f(&x["p95Deg"], 2),
            );
        }
        let per: Vec<String> = r["fingers"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|x| {
                format!(
                    "{} {}/{}",
                    x["finger"].as_str().unwrap_or(""),
                    f(&x["medianDeg"], 2),
                    f(&x["p95Deg"], 2)
                )
            })
            .collect();
        println!("{:<11} per finger median/p95: {}", "", per.join(", "));
        println!(
            "{:<11} finger jitter through the rig (analytic, hand video): {} deg per bone-frame",
            "",
            f(&r["analyticJitterDeg"], 3)
        );
    }
    println!("\npinches on the hand video (retarget, auto scale): user thumb-index tips < 2 cm in world landmarks");
    println!(
        "{:<11} {:>6} {:>9} {:>6} {:>12} | {:>10} {:>9} {:>6} {:>13} {:>10}",
        "avatar",
        "frames",
        "max mm",
        "frame",
        "tip med mm",
        "rig frames",
        "max mm",
        "frame",
        "no filter max",
        "jitter deg"
    );
    for r in &rows {
        let p = &r["pinch"];
        println!(
            "{:<11} {:>6} {:>9} {:>6} {:>12} | {:>10} {:>9} {:>6} {:>13} {:>10}",
            r["avatar"].as_str().unwrap_or(""),
            p["frames"].to_string(),
            f(&p["maxErrorMm"], 2),
            p["worstFrame"].to_string(),
            f(&p["tipMedianMm"], 2),
            p["rigFrames"].to_string(),
            f(&p["rigMaxErrorMm"], 2),
            p["rigWorstFrame"].to_string(),
            f(&p["rigUnfilteredMaxErrorMm"], 2),
            f(&p["rigJitterDeg"], 3),
        );
        let it = &p["rigIterations"];
        println!(
            "{:<11} rig retarget iterations over every clip: {} side-frames, mean {}, p95 {}, max {}, at the cap {}",
            "",
            it["sideFrames"],
            f(&it["mean"], 2),
            f(&it["p95"], 0),
            f(&it["max"], 0),
            it["atCap"]
        );
    }
    Ok(())
}
