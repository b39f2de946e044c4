//! Fingertip-alignment acceptance eval on the shared recordings.
//!
//! ```text
//! cargo run --release --example eval_alignment
//! ```
//!
//! Data: the Azure Kinect body session `../shared/data/pose/kinect-upper-body.json` (281
//! frames) paired frame by frame (frame i with frame i) with the MediaPipe hand video
//! `../shared/data/hands/right-hand-video-mediapipe.json`, fed to the rig as `wrists` input,
//! on two avatars with different hand-to-arm ratios: the shared robot
//! (`../shared/avatars/debug-robot.vrm`) and a human-proportioned VRM 1.0 rig
//! (`tests/fixtures/human-proportions-vrm1.vrm`).
//!
//! Sides: the hand video is the subject's right hand (labelled "Left", un-mirrored), which
//! drives the avatar's right hand, paired with the Kinect RIGHT wrist. The left side reuses
//! the same video with `mirror: true` (the hand drives the avatar's left, reflected), paired
//! with the Kinect LEFT wrist: that is the arm that touches the face around frames 130-160.
//!
//! Kinect wrists to the avatar frame (what an app feeding `wrists` does):
//! 1. The recording's frame is mirrored (the subject faces +Z with their left shoulder at
//!    -X): negate x to get a right-handed frame where the subject's left is +X, +Y up,
//!    facing +Z, i.e. the avatar's frame.
//! 2. Take the wrist relative to the same side's Kinect shoulder, scale it by
//!    `avatar arm / user arm`, and add the avatar's upperArm rest position:
//!    `wrist = avatar shoulder + s * (kinect wrist - kinect shoulder)`. The user arm is the
//!    robust mean (samples beyond 20% of the median dropped, as handrig's calibration does)
//!    of shoulder-elbow + elbow-wrist over every frame and both arms; the avatar arm is the
//!    mean of its two arms' upper + lower rest lengths. So the user's reach maps onto the
//!    avatar's and targets are mostly reachable.
//!
//! Methods, each a fresh rig over the whole session:
//! * (a) aligned: handrig's default (the lag-free seed-000 formula): IK wrist = target DIP -
//!   avatar wrist-to-index-distal from this frame's forward kinematics.
//! * (b) plain: `alignment.enabled = false`: the pose wrist is the IK target.
//! * (c) late: seed 000's V1: the avatar vector read from the PREVIOUS frame's solved pose,
//!   given to the rig as the wrist with alignment disabled. Frame 0 has no previous frame: it
//!   only primes the vector and is not scored for this method (280 frames).
//!
//! Self-contact (`contact.enabled`) is off in every rig here, and so are the wrist limits in
//! the method comparison and in the solvers' agreement: this eval measures alignment alone (`eval/rust/eval_contact.rs`
//! measures contact, `eval/rust/eval_wrist.rs` the limits and alignment under them).
//!
//! Error: distance between the avatar's index distal joint by forward kinematics of the
//! returned rotations and the target DIP `pose wrist + (hand DIP - hand wrist)` (MediaPipe
//! offset in the avatar frame, computed here independently of the rig). Statistics over the
//! frames where that method's IK target is within the arm's reach.
//!
//! Acceptance: (a) median <= 0.5 mm and max <= 2 mm for every avatar and side; the process
//! exits with status 1 otherwise.
//!
//! ## Arm solvers
//! A second table runs method (a) with every `armSolver` (twoBone, fabrik, ccd; default
//! options, so the shoulder option is on) on two data sets: the Kinect session above
//! (`wrists` input, both sides) and the four ASL clips `../shared/data/asl/*.json` (MediaPipe
//! Pose + Hands of one signer, fed as pose input with automatic body-scale calibration; a
//! fresh rig per clip; the signer's right hand, which drives the avatar's right), on the two
//! avatars above and the VRM 0.x fixture `tests/fixtures/vrm0-fingers.vrm`. ASL errors are
//! the rig's own report (distance from the avatar's index distal to the target DIP it built).
//! Columns: the index distal error on reachable frames; agreement with twoBone given the same
//! pole (each solver rerun with the shoulder option off, as twoBone: the largest elbow or
//! wrist distance and local rotation angle, upperArm, lowerArm and hand, over the same
//! frames), below 99% stretch and over all frames; the largest frame-to-frame change of the
//! elbow's swivel about the shoulder-to-wrist line (frames with the elbow at least 1 cm off
//! that line); FABRIK and CCD iterations per arm solve (mean, nearest-rank p95).
//! Acceptance, exit status 1 otherwise: every solver median <= 0.5 mm and max <= 2 mm, and
//! FABRIK and CCD within 1 mm and 2 degrees of twoBone below 99% stretch (beyond it the
//! elbow is ill-conditioned: at 99.8% of an equal-boned arm's length, 0.3 mm of reach moves
//! the elbow 2.4 mm, and the iterative solvers stop within their tolerance of the wrist).

use handrig_support::recordings;

use glam::{Quat, Vec3};
use handrig::humanoid::bones::{Finger, Side};
use handrig::ik::ArmSolver;
use handrig::math::robust_mean;
use handrig::mediapipe::{CameraMapping, FrameInput, HandObservation, WristObservation, MAX_HANDS};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Method {
    Aligned,
    Plain,
    Late,
}

impl Method {
    const ALL: [Method; 3] = [Method::Aligned, Method::Plain, Method::Late];
    fn label(self) -> &'static str {
        match self {
            Method::Aligned => "(a) aligned, lag-free",
            Method::Plain => "(b) no alignment",
            Method::Late => "(c) one frame late (V1)",
        }
    }
}

struct Stats {
    reachable: usize,
    total: usize,
    median: f32,
    p95: f32,
    max: f32,
}

fn stats(errors: &mut [f32], total: usize) -> Stats {
    errors.sort_by(f32::total_cmp);
    let q = |p: f32| {
        if errors.is_empty() {
            f32::NAN
        } else {
            // Nearest-rank percentile.
            let k = ((p * errors.len() as f32).ceil() as usize).clamp(1, errors.len());
            errors[k - 1]
        }
    };
    Stats {
        reachable: errors.len(),
        total,
        median: if errors.is_empty() {
            f32::NAN
        } else if errors.len() % 2 == 1 {
            errors[errors.len() / 2]
        } else {
            0.5 * (errors[errors.len() / 2 - 1] + errors[errors.len() / 2])
        },
        p95: q(0.95),
        max: errors.last().copied().unwrap_or(f32::NAN),
    }
}

/// Kinect point (mirrored recording frame) to a right-handed frame facing +Z, left = +X.
fn kinect_to_avatar(j: [f32; 4]) -> Vec3 {
    Vec3::new(-j[0], j[1], j[2])
}

/// Mean rest arm length (upper + lower) of the avatar's two arms.
fn avatar_arm(skel: &Skeleton) -> f32 {
    handrig::humanoid::measure::avatar_arm_length(skel)
}

/// Wrist-to-index-distal length over arm length: how big the avatar's hand is.
fn hand_to_arm(skel: &Skeleton) -> f32 {
    let side = Side::Right;
    let d = skel.rest_world(side.finger(Finger::Index)[2]).unwrap()
        - skel.rest_world(side.hand()).unwrap();
    d.length() / avatar_arm(skel)
}

struct Session {
    /// Per frame: Kinect shoulder and wrist (avatar axes), `[left, right]`.
    shoulder: Vec<[Vec3; 2]>,
    wrist: Vec<[Vec3; 2]>,
    /// Robust user arm length (m).
    user_arm: f32,
    hands: Vec<FrameInput>,
}

fn load_session() -> Session {
    let kinect = recordings::kinect();
    let idx = |n: &str| {
        kinect
            .joint(n)
            .unwrap_or_else(|| panic!("joint {n} missing"))
    };
    let names = [
        ("SHOULDER_LEFT", "ELBOW_LEFT", "WRIST_LEFT"),
        ("SHOULDER_RIGHT", "ELBOW_RIGHT", "WRIST_RIGHT"),
    ];
    let ids: Vec<[usize; 3]> = names
        .iter()
        .map(|(s, e, w)| [idx(s), idx(e), idx(w)])
        .collect();
    let mut shoulder = Vec::new();
    let mut wrist = Vec::new();
    let mut lengths = Vec::new();
    for f in &kinect.frames {
        let mut sh = [Vec3::ZERO; 2];
        let mut wr = [Vec3::ZERO; 2];
        for (k, [s, e, w]) in ids.iter().enumerate() {
            sh[k] = kinect_to_avatar(f[*s]);
            wr[k] = kinect_to_avatar(f[*w]);
            let el = kinect_to_avatar(f[*e]);
            lengths.push((el - sh[k]).length() + (wr[k] - el).length());
        }
        shoulder.push(sh);
        wrist.push(wr);
    }
    let mut scratch = vec![0.0; lengths.len()];
    let user_arm = robust_mean(&lengths, &mut scratch).expect("arm samples");

    let video = recordings::hand_video();
    assert!(
        video.len() >= kinect.frames.len(),
        "hand video shorter than the Kinect session"
    );
    let hands = video[..kinect.frames.len()]
        .iter()
        .enumerate()
        .map(|(i, hands)| {
            let mut f = recordings::frame_of(&hands[..hands.len().min(MAX_HANDS)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f
        })
        .collect();
    Session {
        shoulder,
        wrist,
        user_arm,
        hands,
    }
}

/// The hand the rig drives `side` with (same rule as the rig: highest score among hands at
/// or above the minimum score that map to that side).
fn driving_hand(
    f: &FrameInput,
    side: Side,
    cam: CameraMapping,
    min_score: f32,
) -> Option<&HandObservation> {
    f.hands()
        .iter()
        .filter(|h| h.score >= min_score && cam.avatar_side(h.handedness) == side)
        .max_by(|a, b| a.score.total_cmp(&b.score))
}

/// Drives a fresh rig with `options` over the session for one avatar side with `method`'s
/// wrist input, calling `visit(frame index, rig, output, target DIP)` after each solved frame
/// the driving hand aligned (frames with a held hand have no report and are skipped; their
/// count is returned). The target DIP is computed here, independently of the rig.
fn drive(
    skel: &Skeleton,
    session: &Session,
    side: Side,
    method: Method,
    mut options: RigOptions,
    mut visit: impl FnMut(usize, &Rig, &SolveOutput, Vec3),
) -> usize {
    options.mirror = side == Side::Left;
    options.alignment.enabled = method == Method::Aligned;
    // Alignment alone: self-contact's body colliders would move targets that come near the
    // avatar's body (`eval/rust/eval_contact.rs` measures contact).
    options.contact.enabled = false;
    let cam = options.camera();
    let min_score = options.min_hand_score;
    let mut rig = Rig::new(skel.clone(), options).expect("rig");
    let mut out = SolveOutput::default();
    let scale = avatar_arm(skel) / session.user_arm;
    let avatar_shoulder = skel.rest_world(side.arm()[1]).unwrap();
    let hand = side.hand();
    let distal = side.finger(Finger::Index)[2];
    // Seed V1 reads the bone transforms before this frame's update (rest pose before the
    // first solve; frame 0 is not scored for this method, see below).
    let mut late_vector = skel.rest_world(distal).unwrap() - skel.rest_world(hand).unwrap();
    let mut held = 0;
    for (i, frame) in session.hands.iter().enumerate() {
        let k = side.index();
        let pose_wrist = avatar_shoulder + scale * (session.wrist[i][k] - session.shoulder[i][k]);
        let Some(h) = driving_hand(frame, side, cam, min_score) else {
            continue;
        };
        let target_dip = pose_wrist + cam.to_avatar(h.world[7] - h.world[0]);
        let ik_wrist = match method {
            Method::Late => target_dip - late_vector,
            _ => pose_wrist,
        };
        let mut input = *frame;
        input.wrists = [None, None];
        input.wrists[k] = Some(WristObservation {
            position: skel.version().position_to_internal(ik_wrist),
            rotation: None,
        });
        rig.solve(&input, &mut out).expect("solve");
        // Compared with the skeleton (internal frame) below.
        out.turn_to_internal_frame(rig.skeleton().version());
        // No report: the hand solver held last frame's hand (degenerate landmarks), so
        // nothing was aligned this frame; not scored.
        let Some(report) = out.alignment[k] else {
            held += 1;
            continue;
        };
        if method == Method::Aligned {
            assert!(
                (report.target_dip - target_dip).length() < 1e-5,
                "frame {i}: rig target DIP differs from the independent one"
            );
        }
        late_vector = out.world.position[distal.index()] - out.world.position[hand.index()];
        visit(i, &rig, &out, target_dip);
    }
    held
}

/// Runs one method over the session for one avatar side; returns the errors (m) of the
/// frames whose IK target was reachable, and the frame count.
fn run(skel: &Skeleton, session: &Session, side: Side, method: Method) -> (Vec<f32>, usize) {
    let distal = side.finger(Finger::Index)[2];
    let mut errors = Vec::new();
    let mut total = 0;
    // The wrist limits off: they turn the hand of this mismatched pairing (the hand video on
    // the Kinect forearm, 97% of frames beyond the wrist's range) by up to 100 degrees, which
    // moves the fingertip of the unaligned methods far from where they put it
    // (`eval/rust/eval_wrist.rs` measures the limits, and alignment under them).
    let mut options = RigOptions::per_frame();
    options.arm.wrist_limits = false;
    let held = drive(
        skel,
        session,
        side,
        method,
        options,
        |i, _, out, target_dip| {
            if method == Method::Late && i == 0 {
                // No previous frame yet: frame 0 only primes the late vector (a live app has
                // been running before; the rest-pose vector would be a start-up artefact).
                return;
            }
            total += 1;
            if out.alignment[side.index()].is_some_and(|r| r.reachable) {
                errors.push((out.world.position[distal.index()] - target_dip).length());
            }
        },
    );
    if held > 0 {
        println!(
            "  {} {}: {held} frames with a held hand (not scored)",
            side.as_str(),
            method.label()
        );
    }
    (errors, total)
}

/// One solved frame of an arm, for comparing solvers and measuring the elbow's swivel.
#[derive(Clone, Copy)]
struct ArmFrame {
    /// Frame index in its recording (clips numbered apart so they never look consecutive).
    frame: usize,
    /// Index distal to target DIP (m) when the IK target was reachable.
    error: Option<f32>,
    upper_joint: Vec3,
    elbow: Vec3,
    wrist: Vec3,
    /// Local rotations of shoulder, upperArm, lowerArm, hand.
    local: [Quat; 4],
    /// FABRIK / CCD iterations of this frame's arm solve.
    iterations: Option<u32>,
}

fn arm_frame(frame: usize, rig: &Rig, out: &SolveOutput, side: Side, target_dip: Vec3) -> ArmFrame {
    let [sh, up, low, hand] = side.arm();
    let distal = side.finger(Finger::Index)[2];
    let report = out.alignment[side.index()];
    ArmFrame {
        frame,
        error: report
            .filter(|r| r.reachable)
            .map(|_| (out.world.position[distal.index()] - target_dip).length()),
        upper_joint: out.world.position[up.index()],
        elbow: out.world.position[low.index()],
        wrist: out.world.position[hand.index()],
        local: [sh, up, low, hand].map(|b| out.local[b.index()]),
        iterations: rig.arms().last_report(side).map(|r| r.iterations),
    }
}

/// The arm options with the shoulder option and the wrist limits off: the plain two-bone arm
/// every solver shares, for comparing them given the same pole. (The wrist limits turn the
/// hand against the forearm each solver ends on and solve again for the moved wrist, so with
/// them the solvers' small differences of elbow swivel come back as different targets.)
fn without_shoulder(solver: ArmSolver) -> RigOptions {
    let mut o = RigOptions {
        arm_solver: solver,
        ..RigOptions::per_frame()
    };
    o.arm.shoulder_angle = 0.0;
    o.arm.wrist_limits = false;
    o
}

/// Largest frame-to-frame change (radians) of the elbow's swivel about the upper-arm-joint-to-
/// wrist line, over consecutive frames with a bent arm (elbow at least 1 cm off that line: a
/// straight arm has no swivel).
fn largest_swivel_change(frames: &[ArmFrame]) -> f32 {
    let mut worst = 0.0f32;
    for w in frames.windows(2) {
        let [a, b] = [w[0], w[1]];
        if b.frame != a.frame + 1 {
            continue;
        }
        let bend = |f: ArmFrame| {
            let axis = (f.wrist - f.upper_joint).normalize();
            let v = f.elbow - f.upper_joint;
            (v - axis * axis.dot(v), axis)
        };
        let ((pa, _), (pb, axis)) = (bend(a), bend(b));
        if pa.length() < 0.01 || pb.length() < 0.01 {
            continue;
        }
        let pa = (pa - axis * axis.dot(pa)).normalize();
        let pb = pb.normalize();
        worst = worst.max(axis.dot(pa.cross(pb)).atan2(pa.dot(pb)).abs());
    }
    worst
}

/// Angle (radians) between rotations, accurate near 0 (q and -q equal).
fn rotation_angle(a: Quat, b: Quat) -> f32 {
    let d = a * b.conjugate();
    2.0 * d.xyz().length().atan2(d.w.abs())
}

/// Reach (upper arm joint to wrist) as a fraction of the arm's length above which the elbow's
/// position is too ill-conditioned to compare solvers by: at 99.8% of the length a 0.3 mm
/// difference in the wrist's reach moves the elbow of an equal-boned arm by 2.4 mm.
const STRETCHED: f32 = 0.99;

/// Largest elbow and wrist distance (m) and local rotation angle (radians; upperArm,
/// lowerArm, hand) between frames of the same index in `a` and `b`: over the frames with the
/// arm below [`STRETCHED`], and over all frames.
fn disagreement(a: &[ArmFrame], b: &[ArmFrame]) -> [(f32, f32); 2] {
    let mut worst = [(0.0f32, 0.0f32); 2];
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.frame, y.frame);
        let dist = (x.elbow - y.elbow)
            .length()
            .max((x.wrist - y.wrist).length());
        let angle = (1..4)
            .map(|k| rotation_angle(x.local[k], y.local[k]))
            .fold(0.0f32, f32::max);
        let length = (y.elbow - y.upper_joint).length() + (y.wrist - y.elbow).length();
        let stretched = (y.wrist - y.upper_joint).length() > STRETCHED * length;
        for (k, w) in worst.iter_mut().enumerate() {
            if k == 1 || !stretched {
                *w = (w.0.max(dist), w.1.max(angle));
            }
        }
    }
    worst
}

/// Mean and nearest-rank p95 of the iteration counts, `None` for the analytic solver.
fn iteration_stats(frames: &[ArmFrame]) -> Option<(f32, u32)> {
    let mut it: Vec<u32> = frames.iter().filter_map(|f| f.iterations).collect();
    if it.is_empty() {
        return None;
    }
    it.sort_unstable();
    let mean = it.iter().sum::<u32>() as f32 / it.len() as f32;
    let k = ((0.95 * it.len() as f32).ceil() as usize).clamp(1, it.len());
    Some((mean, it[k - 1]))
}

/// One row of the arm solver table.
struct SolverRow {
    data: &'static str,
    avatar: String,
    side: Side,
    solver: ArmSolver,
    stats: Stats,
    /// Against twoBone, shoulder option off: largest distance (m) and angle (radians), below
    /// [`STRETCHED`] and over all frames.
    agreement: [(f32, f32); 2],
    swivel: f32,
    iterations: Option<(f32, u32)>,
}

/// The arm solver rows for one data set: `frames(options)` solves the whole data set for one
/// avatar side with `options` and returns its arm frames and frame count.
fn solver_rows(
    data: &'static str,
    avatar: &str,
    side: Side,
    mut frames: impl FnMut(RigOptions) -> (Vec<ArmFrame>, usize),
) -> Vec<SolverRow> {
    let (reference, _) = frames(without_shoulder(ArmSolver::TwoBone));
    ArmSolver::ALL
        .iter()
        .map(|&solver| {
            let (plain, _) = frames(without_shoulder(solver));
            let (solved, total) = frames(RigOptions {
                arm_solver: solver,
                ..RigOptions::per_frame()
            });
            let mut errors: Vec<f32> = solved.iter().filter_map(|f| f.error).collect();
            SolverRow {
                data,
                avatar: avatar.to_string(),
                side,
                solver,
                stats: stats(&mut errors, total),
                agreement: disagreement(&plain, &reference),
                swivel: largest_swivel_change(&solved),
                iterations: iteration_stats(&solved),
            }
        })
        .collect()
}

/// Kinect wrists + hand video (`wrists` input, aligned) for one avatar side.
fn kinect_frames(
    skel: &Skeleton,
    session: &Session,
    side: Side,
    options: RigOptions,
) -> (Vec<ArmFrame>, usize) {
    let mut frames = Vec::new();
    drive(
        skel,
        session,
        side,
        Method::Aligned,
        options,
        |i, rig, out, target_dip| {
            frames.push(arm_frame(i, rig, out, side, target_dip));
        },
    );
    let n = frames.len();
    (frames, n)
}

/// The ASL clips (pose + hands input; a fresh rig per clip: tracking restarts at each) for
/// one avatar side. The hands drive the avatar side MediaPipe's labels map them to (the
/// un-mirrored signer's right hand drives the avatar's right).
fn asl_frames(
    skel: &Skeleton,
    clips: &[Vec<FrameInput>],
    side: Side,
    options: RigOptions,
) -> (Vec<ArmFrame>, usize) {
    let mut frames = Vec::new();
    let mut total = 0;
    let mut options = options;
    options.contact.enabled = false;
    for (c, clip) in clips.iter().enumerate() {
        let mut rig = Rig::new(skel.clone(), options).expect("rig");
        let mut out = SolveOutput::default();
        for (i, f) in clip.iter().enumerate() {
            rig.solve(f, &mut out).expect("solve");
            // Compared with the skeleton (internal frame) below.
            out.turn_to_internal_frame(rig.skeleton().version());
            if let Some(report) = out.alignment[side.index()] {
                total += 1;
                frames.push(arm_frame(
                    c * 100_000 + i,
                    &rig,
                    &out,
                    side,
                    report.target_dip,
                ));
            }
        }
    }
    (frames, total)
}

fn main() {
    let session = load_session();
    let avatars = [
        ("debug-robot.vrm", recordings::ROBOT),
        ("human-proportions-vrm1.vrm", recordings::FIXTURE_VRM1),
    ];
    println!(
        "Kinect session: {} frames paired with the hand video; user arm (robust mean) {:.3} m",
        session.hands.len(),
        session.user_arm
    );
    let mut pass = true;
    let mut rows = Vec::new();
    for (name, path) in &avatars {
        let skel = recordings::vrm(path);
        println!(
            "{name}: arm {:.3} m, wrist-to-index-distal / arm {:.3}, body scale {:.3}",
            avatar_arm(&skel),
            hand_to_arm(&skel),
            avatar_arm(&skel) / session.user_arm
        );
        for side in [Side::Right, Side::Left] {
            for method in Method::ALL {
                let (mut errors, total) = run(&skel, &session, side, method);
                let s = stats(&mut errors, total);
                if method == Method::Aligned && !(s.median <= 0.0005 && s.max <= 0.002) {
                    pass = false;
                }
                rows.push((name.to_string(), side, method, s));
            }
        }
    }
    println!();
    println!("| avatar | side | method | reachable | median mm | p95 mm | max mm |");
    println!("| --- | --- | --- | --- | ---: | ---: | ---: |");
    for (name, side, method, s) in &rows {
        println!(
            "| {name} | {} | {} | {}/{} | {:.4} | {:.4} | {:.4} |",
            side.as_str(),
            method.label(),
            s.reachable,
            s.total,
            s.median * 1000.0,
            s.p95 * 1000.0,
            s.max * 1000.0
        );
    }
    // Every arm solver, on the Kinect session (wrists input) and the ASL clips (pose input),
    // on every avatar including the VRM 0.x fixture.
    let clips: Vec<Vec<FrameInput>> = recordings::ASL.iter().map(|p| recordings::asl(p)).collect();
    let mut solver_table = Vec::new();
    for (name, path) in avatars
        .iter()
        .chain([("vrm0-fingers.vrm", recordings::FIXTURE_VRM0)].iter())
    {
        let skel = recordings::vrm(path);
        for side in [Side::Right, Side::Left] {
            solver_table.extend(solver_rows("kinect wrists", name, side, |o| {
                kinect_frames(&skel, &session, side, o)
            }));
        }
        // The signers use their right hand (avatar right, un-mirrored).
        solver_table.extend(solver_rows("asl pose", name, Side::Right, |o| {
            asl_frames(&skel, &clips, Side::Right, o)
        }));
    }
    println!();
    println!("Arm solvers (aligned, default options). \"vs twoBone\": largest elbow or wrist distance and local rotation angle from the analytic solver given the same pole (shoulder option off for both), over the frames with the arm below {:.0}% of its length (the elbow is ill-conditioned beyond), then over all frames.", STRETCHED * 100.0);
    println!();
    println!("| data | avatar | side | armSolver | reachable | median mm | p95 mm | max mm | vs twoBone mm, deg | (all frames) | largest swivel step deg | iterations mean / p95 |");
    println!("| --- | --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in &solver_table {
        let s = &r.stats;
        let [below, all] = r.agreement;
        if !(s.median <= 0.0005 && s.max <= 0.002) || below.0 > 0.001 || below.1 > 2f32.to_radians()
        {
            pass = false;
        }
        println!(
            "| {} | {} | {} | {} | {}/{} | {:.4} | {:.4} | {:.4} | {:.4}, {:.3} | {:.4}, {:.3} | {:.2} | {} |",
            r.data,
            r.avatar,
            r.side.as_str(),
            r.solver.as_str(),
            s.reachable,
            s.total,
            s.median * 1000.0,
            s.p95 * 1000.0,
            s.max * 1000.0,
            below.0 * 1000.0,
            below.1.to_degrees(),
            all.0 * 1000.0,
            all.1.to_degrees(),
            r.swivel.to_degrees(),
            r.iterations
                .map_or("-".to_string(), |(m, p)| format!("{m:.1} / {p}")),
        );
    }
    println!();
    if pass {
        println!("PASS: (a) and every arm solver: median <= 0.5 mm and max <= 2 mm on every avatar and side; FABRIK and CCD within 1 mm and 2 degrees of twoBone below {:.0}% stretch", STRETCHED * 100.0);
    } else {
        println!("FAIL: (a) or an arm solver exceeds median 0.5 mm or max 2 mm, or FABRIK/CCD differ from twoBone by more than 1 mm or 2 degrees");
        std::process::exit(1);
    }
}
