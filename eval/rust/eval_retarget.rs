//! Evaluation of optimization-based hand retargeting (issue 11, seed 003) against the analytic
//! strategy, on the two shared hand recordings and three avatars.
//!
//! Per recording, avatar and strategy, every frame is solved by a `HandSolver` (the avatar's
//! right hand, as the rig drives it from these right-hand recordings) and compared with the
//! **targets**: the user's fingertips relative to the wrist, in the solved hand's frame,
//! scaled by the hand scale (`HandSolver::hand_scale`, kept by both strategies, so both get
//! the same targets). Columns:
//!
//! * `tip med / p95`: |avatar fingertip - target| over all fingers and frames, mm (avatar
//!   fingertip: `handrig::align::fingertip`, forward kinematics of the solved rotations).
//! * `pinch n / max`: frames where the scaled user thumb-index tip distance is under 2 cm,
//!   and the largest |avatar thumb-index distance - user's| on them, mm.
//! * `lim`: finger joint angles outside the limits table (`HandSolver::avatar_angles`,
//!   measured on the posed avatar, 0.06 degree slack), counted over frames x fingers x DOFs.
//! * `iter mean / p95`: Gauss-Newton iterations per frame (retarget only).
//! * `us/hand`: solve time per hand (mean, this process, release build; the criterion bench
//!   `cargo bench --bench retarget` is the precise figure).
//! * `jitter`: mean frame-to-frame change of the finger bones' local rotations, degrees per
//!   bone per frame (temporal stability).
//!
//! Scale: `auto` (stable lengths, no calibration) and `calib` (the seed's open-hand bounding
//! box, calibrated on the recording's most open frame, as an app's "hold your hand open"
//! step would).
//!
//! ```text
//! cargo run --release --example eval_retarget            # table
//! cargo run --release --example eval_retarget -- --json  # machine-readable
//! ```

use handrig_support::recordings;
use handrig_support::stats;

use std::time::Instant;

use glam::{Quat, Vec3};
use handrig::align::fingertip;
use handrig::hand::{HandSolver, HandStrategy, RetargetOptions, LIMITS};
use handrig::mediapipe::{CameraMapping, HAND_LANDMARKS};
use handrig::{Finger, Side, Skeleton, WorldPose, BONE_COUNT};
use serde_json::{json, Value};
use stats::{percentile, sorted};

type Landmarks = [Vec3; HAND_LANDMARKS];

/// Limit slack, radians (0.06 degree): rounding of the measurement, not tolerance.
const LIMIT_SLACK: f32 = 1e-3;
/// Pinch frames: scaled user thumb-index distance under this, meters.
const PINCH: f32 = 0.02;

/// The subject's right hand of each frame, in the avatar frame (the rig's default mapping).
fn recordings() -> Vec<(&'static str, Vec<Option<Landmarks>>)> {
    let camera = CameraMapping::default();
    let video = recordings::hand_video()
        .iter()
        .map(|hands| recordings::best_hand(hands).map(|h| h.world.map(|p| camera.to_avatar(p))))
        .collect();
    vec![
        ("video", video),
        ("canonical", recordings::hand_canonical()),
    ]
}

/// The most open frame: largest straightness (knuckle-to-tip over phalanx path) of the least
/// straight of index to little.
fn most_open(frames: &[Option<Landmarks>]) -> Option<usize> {
    let openness = |lm: &Landmarks| {
        Finger::ALL[1..]
            .iter()
            .map(|f| {
                let ids = f.landmarks();
                let path: f32 = (1..4).map(|k| (lm[ids[k]] - lm[ids[k - 1]]).length()).sum();
                (lm[ids[3]] - lm[ids[0]]).length() / path
            })
            .fold(f32::INFINITY, f32::min)
    };
    frames
        .iter()
        .enumerate()
        .filter_map(|(i, f)| f.as_ref().map(|lm| (i, openness(lm))))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// Command-line overrides (tuning runs); the defaults are the library's.
struct Args {
    json: bool,
    options: RetargetOptions,
    only: Option<String>,
    recording: Option<String>,
    mode: Option<String>,
    scale: Option<f32>,
    fingers: bool,
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        json: false,
        options: RetargetOptions::default(),
        only: None,
        recording: None,
        mode: None,
        scale: None,
        fingers: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || -> Result<f32, String> {
            it.next()
                .and_then(|v| v.parse().ok())
                .ok_or(format!("{arg} needs a number"))
        };
        match arg.as_str() {
            "--json" => a.json = true,
            "--fingers" => a.fingers = true,
            "--temporal" => a.options.temporal_weight = value()?,
            "--spatial" => a.options.spatial_weight = value()?,
            "--speed" => a.options.temporal_speed = value()?,
            "--pinch" => a.options.pinch_weight = value()?,
            "--joint" => a.options.joint_weight = value()?,
            "--tol" => a.options.settings.step_tolerance = value()?,
            "--max-iter" => a.options.settings.max_iterations = value()? as u32,
            "--scale" => a.scale = Some(value()?),
            "--only" => a.only = it.next(),
            "--recording" => a.recording = it.next(),
            "--mode" => a.mode = it.next(),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

struct Run {
    finger_errors: [Vec<f32>; 5],
    tip_errors: Vec<f32>,
    pinch_errors: Vec<f32>,
    limit_violations: usize,
    iterations: Vec<f32>,
    micros: f64,
    solved: usize,
    jitter_sum: f64,
    jitter_n: usize,
    residuals: Vec<f32>,
    scale: f32,
    nan: usize,
}

fn run(
    skel: &Skeleton,
    frames: &[Option<Landmarks>],
    strategy: HandStrategy,
    calibration: Option<usize>,
    args: &Args,
) -> Result<Run, String> {
    let side = Side::Right;
    let mut solver = HandSolver::new(skel, strategy).map_err(|e| e.to_string())?;
    solver
        .set_retarget_options(args.options)
        .map_err(|e| e.to_string())?;
    solver.set_hand_scale(side, args.scale);
    let mut local = [Quat::IDENTITY; BONE_COUNT];
    if let Some(i) = calibration {
        let lm = frames[i].as_ref().ok_or("calibration frame has no hand")?;
        solver.solve(skel, side, lm, &mut local);
        solver
            .calibrate_hand_scale(side)
            .ok_or("calibration refused the most open frame")?;
        solver.reset();
    }
    let mut r = Run {
        finger_errors: Default::default(),
        tip_errors: Vec::new(),
        pinch_errors: Vec::new(),
        limit_violations: 0,
        iterations: Vec::new(),
        micros: 0.0,
        solved: 0,
        jitter_sum: 0.0,
        jitter_n: 0,
        residuals: Vec::new(),
        scale: f32::NAN,
        nan: 0,
    };
    let mut world = WorldPose::default();
    let mut previous: Option<[Quat; BONE_COUNT]> = None;
    for frame in frames {
        let Some(lm) = frame else {
            previous = None;
            continue;
        };
        local.fill(Quat::IDENTITY);
        let start = Instant::now();
        let hand = solver.solve(skel, side, lm, &mut local);
        r.micros += start.elapsed().as_secs_f64() * 1e6;
        let Some(hand) = hand else {
            previous = None;
            continue;
        };
        r.solved += 1;
        if local.iter().any(|q| !q.is_finite()) {
            r.nan += 1;
        }
        // Every strategy keeps the hand scale; the same targets for both.
        let scale = solver.hand_scale(side).ok_or("no scale")?;
        r.scale = scale;
        if let Some(rep) = solver.retarget_report(side) {
            r.iterations.push(rep.iterations as f32);
            r.residuals.push(rep.residual);
        }
        // Finger rotations only (the hand bone at rest): fingertips in the hand's frame.
        skel.forward(&local, &mut world);
        let h = side.hand().index();
        let (hp, hr) = (world.position[h], world.rotation[h]);
        let mut avatar_tip = [None; 5];
        let mut user_tip = [Vec3::ZERO; 5];
        for f in Finger::ALL {
            let target = scale * (hand.inverse() * (lm[f.landmarks()[3]] - lm[0]));
            user_tip[f.index()] = target;
            if let Some(t) = fingertip(skel, &world, side, f) {
                let t = hr.inverse() * (t - hp);
                avatar_tip[f.index()] = Some(t);
                r.tip_errors.push((t - target).length());
                r.finger_errors[f.index()].push((t - target).length());
            }
        }
        let user_pinch = (user_tip[0] - user_tip[1]).length();
        if let (true, Some(a), Some(b)) = (user_pinch < PINCH, avatar_tip[0], avatar_tip[1]) {
            r.pinch_errors.push(((a - b).length() - user_pinch).abs());
        }
        for (f, angles) in Finger::ALL.iter().zip(solver.avatar_angles(side, &local)) {
            let Some(a) = angles else { continue };
            for (k, v) in a.iter().enumerate() {
                if !LIMITS[f.index()][k].contains(*v, LIMIT_SLACK) {
                    r.limit_violations += 1;
                }
            }
        }
        if let Some(prev) = &previous {
            for f in Finger::ALL {
                for b in side.finger(f) {
                    if skel.has(b) {
                        let d = prev[b.index()].dot(local[b.index()]).abs().min(1.0);
                        r.jitter_sum += f64::from((2.0 * d.acos()).to_degrees());
                        r.jitter_n += 1;
                    }
                }
            }
        }
        previous = Some(local);
    }
    Ok(r)
}

fn main() {
    if let Err(e) = main_result() {
        eprintln!("eval_retarget: {e}");
        std::process::exit(1);
    }
}

fn main_result() -> Result<(), String> {
    let args = parse_args()?;
    let json_out = args.json;
    let avatars = [
        ("robot", recordings::ROBOT),
        ("human", recordings::FIXTURE_VRM1),
        ("vrm0", recordings::FIXTURE_VRM0),
    ];
    let recs = recordings();
    let mut rows = Vec::new();
    for (rec_name, frames) in &recs {
        if args.recording.as_deref().is_some_and(|o| o != *rec_name) {
            continue;
        }
        let open = most_open(frames).ok_or("no frames")?;
        for (avatar_name, path) in avatars {
            if args.only.as_deref().is_some_and(|o| o != avatar_name) {
                continue;
            }
            let skel = recordings::vrm(path);
            for (scale_name, calibration) in [("auto", None), ("calib", Some(open))] {
                if args.mode.as_deref().is_some_and(|o| o != scale_name) {
                    continue;
                }
                for (strategy_name, strategy) in [
                    ("analytic", HandStrategy::Analytic),
                    ("retarget", HandStrategy::Retarget),
                ] {
                    let mut r = run(&skel, frames, strategy, calibration, &args)?;
                    let per_finger: Vec<f32> = r
                        .finger_errors
                        .iter()
                        .map(|v| percentile(&sorted(v.clone()), 50.0) * 1e3)
                        .collect();
                    let tips = sorted(std::mem::take(&mut r.tip_errors));
                    let pinch = sorted(std::mem::take(&mut r.pinch_errors));
                    let iters = sorted(std::mem::take(&mut r.iterations));
                    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len().max(1) as f32;
                    rows.push(json!({
                        "recording": rec_name,
                        "avatar": avatar_name,
                        "scale": scale_name,
                        "scaleValue": r.scale,
                        "calibrationFrame": calibration,
                        "strategy": strategy_name,
                        "frames": r.solved,
                        "tipMedianMm": percentile(&tips, 50.0) * 1e3,
                        "tipP95Mm": percentile(&tips, 95.0) * 1e3,
                        "pinchFrames": pinch.len(),
                        "pinchMaxMm": pinch.last().map(|v| v * 1e3),
                        "limitViolations": r.limit_violations,
                        "iterationsMean": (!iters.is_empty()).then(|| mean(&iters)),
                        "iterationsP95": (!iters.is_empty()).then(|| percentile(&iters, 95.0)),
                        "residualMeanMm": (!r.residuals.is_empty()).then(|| mean(&r.residuals) * 1e3),
                        "microsPerHand": r.micros / r.solved.max(1) as f64,
                        "jitterDeg": r.jitter_sum / r.jitter_n.max(1) as f64,
                        "nonFinite": r.nan,
                        "fingerMedianMm": per_finger,
                    }));
                }
            }
        }
    }
    if json_out {
        println!("{}", Value::Array(rows));
        return Ok(());
    }
    println!(
        "handrig retargeting eval (right hand; targets = scaled user fingertips in the hand frame)"
    );
    println!(
        "{:<10} {:<6} {:<6} {:>6} {:<9} | {:>7} {:>7} | {:>5} {:>7} | {:>4} | {:>5} {:>5} | {:>7} | {:>7}",
        "recording", "avatar", "scale", "s", "strategy", "tip med", "p95", "pinch", "max", "lim",
        "iter", "p95", "us/hand", "jitter"
    );
    let f = |v: &Value, d: usize| v.as_f64().map_or("-".to_string(), |x| format!("{x:.d$}"));
    for r in &rows {
        println!(
            "{:<10} {:<6} {:<6} {:>6} {:<9} | {:>7} {:>7} | {:>5} {:>7} | {:>4} | {:>5} {:>5} | {:>7} | {:>7}",
            r["recording"].as_str().unwrap_or(""),
            r["avatar"].as_str().unwrap_or(""),
            r["scale"].as_str().unwrap_or(""),
            f(&r["scaleValue"], 3),
            r["strategy"].as_str().unwrap_or(""),
            f(&r["tipMedianMm"], 2),
            f(&r["tipP95Mm"], 2),
            r["pinchFrames"],
            f(&r["pinchMaxMm"], 2),
            r["limitViolations"],
            f(&r["iterationsMean"], 1),
            f(&r["iterationsP95"], 0),
            f(&r["microsPerHand"], 1),
            f(&r["jitterDeg"], 3),
        );
        if args.fingers {
            let v: Vec<String> = r["fingerMedianMm"]
                .as_array()
                .into_iter()
                .flatten()
                .map(|x| f(x, 2))
                .collect();
            println!("    per finger median (thumb..little) mm: {}", v.join(" "));
        }
    }
    let bad: usize = rows
        .iter()
        .map(|r| r["nonFinite"].as_u64().unwrap_or(0) as usize)
        .sum();
    println!("\nframes with non-finite rotations: {bad}");
    Ok(())
}
