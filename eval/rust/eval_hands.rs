//! Real-data evaluation of the hand solver (issue 3).
//!
//! For every frame of the two hand recordings in `../shared/data/hands`, solve the avatar's
//! right hand and compare, per finger bone, the avatar bone direction (forward kinematics of
//! the solved rotations) with the matching MediaPipe segment direction, both expressed in
//! their own palm frame ([`handrig::hand::palm_frame`] on wrist, index, little and middle
//! MCP). Prints median and p95 per finger, with frames where a joint limit of that finger was
//! active reported separately, and checks that every output quaternion is unit and finite.
//!
//! ```text
//! cargo run --release --example eval_hands                 # table
//! cargo run --release --example eval_hands -- --json       # machine-readable (eval/hands.mjs)
//! options: --avatar FILE.vrm | --rest REST.json [--rest-key NAME]   --data DIR
//! ```
//!
//! `--rest` reads rest positions instead of a `.vrm`: `{ "vrmVersion": "1", "bones": { name:
//! [x, y, z] } }` or an object of such entries (first entry, or `--rest-key`).

use finger_dirs::{avatar_bone_dir, mp_segment};
use handrig_support::finger_dirs;
use handrig_support::recordings;
use handrig_support::stats;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{Mat3, Quat, Vec3};
use handrig::hand::{palm_frame, Dof, HandSolver, HandStrategy, DOF_COUNT};
use handrig::mediapipe::{CameraMapping, HAND_LANDMARKS};
use handrig::{Finger, HumanBone, Side, Skeleton, VrmVersion, WorldPose, BONE_COUNT};
use serde_json::{json, Value};
use stats::percentile;

type Landmarks = [Vec3; HAND_LANDMARKS];

struct Args {
    json: bool,
    avatar: PathBuf,
    rest: Option<PathBuf>,
    rest_key: Option<String>,
    data: PathBuf,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        json: false,
        avatar: PathBuf::from("../shared/avatars/debug-robot.vrm"),
        rest: None,
        rest_key: None,
        data: PathBuf::from("../shared/data/hands"),
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--json" => a.json = true,
            "--avatar" => a.avatar = PathBuf::from(value()?),
            "--rest" => a.rest = Some(PathBuf::from(value()?)),
            "--rest-key" => a.rest_key = Some(value()?),
            "--data" => a.data = PathBuf::from(value()?),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

fn read_json(path: &Path) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn vec3(v: &Value) -> Option<Vec3> {
    let a = v.as_array()?;
    Some(Vec3::new(
        a.first()?.as_f64()? as f32,
        a.get(1)?.as_f64()? as f32,
        a.get(2)?.as_f64()? as f32,
    ))
}

fn skeleton_from_rest(v: &Value, key: Option<&str>) -> Result<(Skeleton, String), String> {
    let (entry, name) = if v.get("bones").is_some() {
        (v, "rest".to_string())
    } else {
        let obj = v.as_object().ok_or("rest file: expected an object")?;
        let (k, e) = match key {
            Some(k) => (k, obj.get(k).ok_or(format!("rest file: no entry {k}"))?),
            None => obj
                .iter()
                .next()
                .map(|(k, e)| (k.as_str(), e))
                .ok_or("rest file: empty")?,
        };
        (e, k.to_string())
    };
    let version = match entry.get("vrmVersion").and_then(Value::as_str) {
        Some("0") => VrmVersion::V0,
        _ => VrmVersion::V1,
    };
    let bones = entry
        .get("bones")
        .and_then(Value::as_object)
        .ok_or("rest file: no bones")?;
    let mut list = Vec::new();
    for (n, p) in bones {
        let b = HumanBone::from_name(n).ok_or(format!("unknown bone {n}"))?;
        list.push((b, vec3(p).ok_or(format!("bad position for {n}"))?));
    }
    Ok((
        Skeleton::new(&list, version).map_err(|e| e.to_string())?,
        name,
    ))
}

fn load_skeleton(args: &Args) -> Result<(Skeleton, String), String> {
    match &args.rest {
        Some(path) => {
            let (s, name) = skeleton_from_rest(&read_json(path)?, args.rest_key.as_deref())?;
            Ok((s, format!("{} ({name})", path.display())))
        }
        None => {
            let skel = recordings::read_vrm(&args.avatar)?;
            Ok((skel, args.avatar.display().to_string()))
        }
    }
}

/// One recording as avatar-frame landmarks of the subject's right hand.
struct Recording {
    name: &'static str,
    frames: Vec<Option<(Side, Landmarks)>>,
}

fn load_recordings(dir: &Path) -> Result<Vec<Recording>, String> {
    // Video: MediaPipe world landmarks, unmirrored, default options (the rig's mapping).
    let camera = CameraMapping::default();
    let frames = recordings::read_hand_video(&dir.join("right-hand-video-mediapipe.json"))?
        .iter()
        .map(|hands| {
            // The hand the rig would pick: highest score among the hands (duplicates happen).
            let best = recordings::best_hand(hands)?;
            let lm = best.world.map(|p| camera.to_avatar(p));
            Some((camera.avatar_side(best.handedness), lm))
        })
        .collect();
    // Canonical: wrist-frame landmarks of the same right hand, a proper rotation of
    // MediaPipe's frame; the palm-frame metric ignores the global orientation.
    let cframes = recordings::read_hand_canonical(&dir.join("right-hand-canonical.json"))?
        .into_iter()
        .map(|f| f.map(|lm| (Side::Right, lm)))
        .collect();
    Ok(vec![
        Recording {
            name: "right-hand-video-mediapipe",
            frames,
        },
        Recording {
            name: "right-hand-canonical",
            frames: cframes,
        },
    ])
}

/// The angle between two unit vectors, degrees (`angle_between`: exact near 0, where `acos` of
/// an `f32` dot product cannot resolve angles below about 0.02 degrees).
fn angle_deg(a: Vec3, b: Vec3) -> f32 {
    handrig::math::angle_between(a, b).to_degrees()
}

#[derive(Default)]
struct Bucket {
    errors: Vec<f32>,
    frames: usize,
}

impl Bucket {
    fn stats(&mut self) -> Value {
        self.errors.sort_by(f32::total_cmp);
        json!({
            "frames": self.frames,
            "samples": self.errors.len(),
            "median": percentile(&self.errors, 50.0),
            "p95": percentile(&self.errors, 95.0),
        })
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("eval_hands: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let (skel, avatar_name) = load_skeleton(&args)?;
    let recordings = load_recordings(&args.data)?;
    let mut report = Vec::new();
    let mut bad_quats = 0usize;
    for rec in &recordings {
        let mut solver =
            HandSolver::new(&skel, HandStrategy::Analytic).map_err(|e| e.to_string())?;
        let mut local = [Quat::IDENTITY; BONE_COUNT];
        let mut world = WorldPose::default();
        let mut all: BTreeMap<&str, Bucket> = BTreeMap::new();
        let mut free: BTreeMap<&str, Bucket> = BTreeMap::new();
        let mut limited: BTreeMap<&str, Bucket> = BTreeMap::new();
        let mut per_bone: BTreeMap<String, Bucket> = BTreeMap::new();
        let mut frames_out = Vec::new();
        let mut dof_limited = [[0usize; DOF_COUNT]; 5];
        let mut solved = 0usize;
        let mut skipped = 0usize;
        for frame in &rec.frames {
            let Some((side, lm)) = frame else {
                skipped += 1;
                frames_out.push(Value::Null);
                continue;
            };
            local.fill(Quat::IDENTITY);
            let Some(hand) = solver.solve(&skel, *side, lm, &mut local) else {
                skipped += 1;
                frames_out.push(Value::Null);
                continue;
            };
            solved += 1;
            let rep = *solver.report(*side);
            for (counts, flags) in dof_limited.iter_mut().zip(rep.limited.iter()) {
                for (c, l) in counts.iter_mut().zip(flags) {
                    *c += usize::from(*l);
                }
            }
            for q in local.iter().chain([&hand]) {
                if !q.is_finite() || (q.length() - 1.0).abs() > 1e-4 {
                    bad_quats += 1;
                }
            }
            skel.forward(&local, &mut world);
            let pos = |b: HumanBone| world.position[b.index()];
            let fp = |f: Finger| side.finger(f)[0];
            let avatar_palm = palm_frame(
                *side,
                pos(side.hand()),
                pos(fp(Finger::Index)),
                pos(fp(Finger::Little)),
                pos(fp(Finger::Middle)),
            )
            .ok_or("avatar palm degenerate")?;
            let Some(mp_palm) = palm_frame(*side, lm[0], lm[5], lm[17], lm[9]) else {
                skipped += 1;
                frames_out.push(Value::Null);
                continue;
            };
            let mut fl = Vec::new();
            let mut locals = serde_json::Map::new();
            for finger in Finger::ALL {
                let lim = rep.finger_limited(finger);
                fl.push(lim);
                let name = finger.as_str();
                for b in [&mut all, if lim { &mut limited } else { &mut free }] {
                    b.entry(name).or_default().frames += 1;
                }
                for (slot, bone) in side.finger(finger).into_iter().enumerate() {
                    if !skel.has(bone) {
                        continue;
                    }
                    let q = local[bone.index()];
                    locals.insert(bone.as_str().into(), json!([q.x, q.y, q.z, q.w]));
                    let (Some(a), Some(m)) = (
                        avatar_bone_dir(&skel, &world, *side, finger, slot),
                        mp_segment(&skel, lm, *side, finger, slot),
                    ) else {
                        continue;
                    };
                    let e = angle_deg(avatar_palm.transpose() * a, mp_palm.transpose() * m);
                    all.get_mut(name).unwrap().errors.push(e);
                    let bucket = if lim { &mut limited } else { &mut free };
                    bucket.get_mut(name).unwrap().errors.push(e);
                    let pb = per_bone.entry(format!("{name}{slot}")).or_default();
                    pb.errors.push(e);
                }
            }
            let angles: Vec<Vec<f32>> = rep
                .angles
                .iter()
                .map(|a| a.iter().map(|x| x.to_degrees()).collect())
                .collect();
            frames_out.push(json!({
                "side": side.as_str(),
                "limited": fl,
                "anglesDeg": angles,
                "local": locals,
            }));
        }
        let fingers: Vec<Value> = Finger::ALL
            .iter()
            .map(|f| {
                let n = f.as_str();
                json!({
                    "finger": n,
                    "all": all.entry(n).or_default().stats(),
                    "limitFree": free.entry(n).or_default().stats(),
                    "limited": limited.entry(n).or_default().stats(),
                    "limitedByDof": Dof::ALL.iter().map(|d| json!({
                        "dof": d.name(*f),
                        "frames": dof_limited[f.index()][d.index()],
                    })).filter(|v| v["frames"] != 0).collect::<Vec<_>>(),
                    "bones": (0..3).map(|s| per_bone.entry(format!("{n}{s}")).or_default().stats()).collect::<Vec<_>>(),
                })
            })
            .collect();
        report.push(json!({
            "recording": rec.name,
            "frames": rec.frames.len(),
            "solved": solved,
            "skipped": skipped,
            "fingers": fingers,
            "perFrame": frames_out,
        }));
    }

    if args.json {
        let rest: serde_json::Map<String, Value> = skel
            .bones()
            .map(|b| {
                let p = skel.rest_world(b).unwrap_or(Vec3::ZERO);
                (b.as_str().to_string(), json!([p.x, p.y, p.z]))
            })
            .collect();
        let out = json!({
            "method": "handrig analytic",
            "avatar": avatar_name,
            "restInternal": rest,
            "badQuaternions": bad_quats,
            "recordings": report,
        });
        println!("{out}");
        return Ok(());
    }

    println!("handrig hand solver eval; avatar {avatar_name}");
    println!(
        "per finger: angle (deg) between avatar bone and MediaPipe segment, in the palm frame"
    );
    for rec in &report {
        println!(
            "\n{}: {} frames, {} solved, {} skipped",
            rec["recording"].as_str().unwrap_or(""),
            rec["frames"],
            rec["solved"],
            rec["skipped"]
        );
        println!(
            "{:<8} {:>8} {:>8} | {:>10} {:>8} {:>8} | {:>8} {:>8} {:>8}",
            "finger", "median", "p95", "free frm", "median", "p95", "lim frm", "median", "p95"
        );
        for f in rec["fingers"].as_array().into_iter().flatten() {
            let g = |k: &str, s: &str| f[k][s].as_f64().unwrap_or(f64::NAN);
            println!(
                "{:<8} {:>8.2} {:>8.2} | {:>10} {:>8.2} {:>8.2} | {:>8} {:>8.2} {:>8.2}",
                f["finger"].as_str().unwrap_or(""),
                g("all", "median"),
                g("all", "p95"),
                f["limitFree"]["frames"],
                g("limitFree", "median"),
                g("limitFree", "p95"),
                f["limited"]["frames"],
                g("limited", "median"),
                g("limited", "p95"),
            );
        }
    }
    for rec in &report {
        let mut line = String::new();
        for f in rec["fingers"].as_array().into_iter().flatten() {
            for d in f["limitedByDof"].as_array().into_iter().flatten() {
                line += &format!(
                    " {} {}: {};",
                    f["finger"].as_str().unwrap_or(""),
                    d["dof"].as_str().unwrap_or(""),
                    d["frames"]
                );
            }
        }
        println!(
            "limits active in {} (frames per DOF):{line}",
            rec["recording"].as_str().unwrap_or("")
        );
    }
    println!("\nnon-unit or non-finite output quaternions: {bad_quats}");
    let _ = Mat3::IDENTITY;
    if bad_quats > 0 {
        return Err(format!("{bad_quats} bad quaternions"));
    }
    Ok(())
}
