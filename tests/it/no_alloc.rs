//! `Rig::solve` must not allocate: it runs every frame inside a browser tab. A counting global
//! allocator checks it on the real hand recording, with wrists and pose input (the wrist
//! limits' search included), for every arm solver and hand strategy, through the flat layout;
//! the torso paths on the real ASL clips; and `ChainSolver::solve` / `solve_into` for both
//! methods. Allocations are counted per thread, so the tests can run in parallel.
// Native only: reads ../shared from disk (and uses proptest, not built for wasm32).

use crate::support::recordings;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use glam::{Quat, Vec3};
use handrig::flat;
use handrig::hand::HandStrategy;
use handrig::ik::{ArmSolver, ChainMethod, ChainSolver, ChainSolverOptions};
use handrig::kinematics::JointLimit;
use handrig::torso::{BodyObservation, TorsoSource};
use handrig::{FrameInput, HumanBone, Rig, RigOptions, Side, SolveOutput};
use recordings::ArmInput;

struct Counting;

thread_local! {
    // `const` initialisation: no lazy setup (which could itself allocate) on first use.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
    // Bytes this thread holds (allocated minus freed by it) and the most it held since
    // `reset_peak`: the fuzzers' bound on memory per case (issue 49).
    static LIVE: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the slot is gone while a thread shuts down; those allocations do not matter.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

fn held(delta: isize) {
    let _ = LIVE.try_with(|l| {
        let now = l.get() + delta;
        l.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

/// Starts measuring this thread's peak memory from what it holds now.
pub(crate) fn reset_peak() {
    let now = LIVE.with(Cell::get);
    PEAK.with(|p| p.set(now));
}

/// The most bytes this thread held beyond what it held at `reset_peak`.
pub(crate) fn peak_since_reset(at_reset: isize) -> usize {
    usize::try_from(PEAK.with(Cell::get) - at_reset).unwrap_or(0)
}

/// Bytes this thread holds now (allocated minus freed by it).
pub(crate) fn live_bytes() -> isize {
    LIVE.with(Cell::get)
}

/// Allocations made by this thread so far.
fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        held(layout.size() as isize);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        held(-(layout.size() as isize));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        held(new_size as isize - layout.size() as isize);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The counter sees allocations at all (the counts below are not vacuous).
fn check_counter() {
    let before = allocations();
    let probe = std::hint::black_box(vec![0u8; 64]);
    assert!(allocations() > before && probe.len() == 64);
}

#[test]
fn solve_allocates_nothing_per_frame() {
    // The first hand of every frame (labelled "Left": the subject's right hand).
    let hands: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| h.world)
        .collect();
    check_counter();
    let cases = ArmSolver::ALL
        .map(|s| (s, HandStrategy::Analytic))
        .into_iter()
        .chain([(ArmSolver::TwoBone, HandStrategy::Retarget)]);
    for (solver, strategy) in cases {
        let options = RigOptions {
            arm_solver: solver,
            hand_strategy: strategy,
            ..RigOptions::default()
        };
        let mut rig = Rig::new(recordings::vrm(recordings::ROBOT), options).unwrap();
        let mut out = SolveOutput::default();
        let mut frame = FrameInput::default();
        let mut decoded = FrameInput::default();
        let pose = recordings::plausible_pose();
        let mut input = vec![0.0f32; flat::input::LEN];
        let mut output = vec![0.0f32; flat::output::LEN];

        // Through the flat layout, as the npm package does: encode, decode, solve, write out.
        // Frames the wrist limits changed (their search re-solves the arm).
        let mut limited = 0;
        let mut run = |rig: &mut Rig, i: usize, mode: usize| {
            let arm = ArmInput::ALL[mode];
            recordings::fill_frame(&mut frame, hands[i % hands.len()], 0.9, arm, &pose);
            frame.time_ms = i as f64 * 33.3;
            flat::write_input(&frame, &mut input);
            flat::read_input(&input, frame.time_ms, &mut decoded).unwrap();
            rig.solve(&decoded, &mut out).unwrap();
            flat::write_output(rig, &out, &mut output);
            limited +=
                usize::from(arm != ArmInput::None && rig.arms().last_wrist(Side::Right).is_some());
        };
        // Warm up every path once, then count.
        for mode in 0..3 {
            run(&mut rig, 0, mode);
        }
        let before = allocations();
        for i in 0..hands.len() {
            run(&mut rig, i, i % 3);
        }
        let after = allocations();
        assert_eq!(
            after - before,
            0,
            "Rig::solve ({solver:?}, {strategy:?}) allocated {} times over {} frames",
            after - before,
            hands.len()
        );
        // The frames were really solved (the count is not vacuous), the wrist limits included.
        assert!(limited > 10, "{solver:?}: {limited} frames limited");
        assert!(out.solved[HumanBone::RightIndexDistal.index()]);
        assert!(out.solved[HumanBone::RightLowerArm.index()]);
        assert_eq!(
            out.retarget[1].is_some(),
            strategy == HandStrategy::Retarget,
            "{strategy:?}"
        );
    }
}

/// The torso paths: `torso: "pose"` from the real ASL clips' pose (hips, shoulders, face),
/// from body-tracker joints, with the app's bones winning, and with the shoulders lost
/// (hold, ease); `torso: "frame"` with the app's torso; every frame through the flat layout.
#[test]
fn torso_paths_allocate_nothing() {
    check_counter();
    let clip = recordings::asl(recordings::ASL[2]);
    for source in [TorsoSource::Pose, TorsoSource::Frame] {
        let options = RigOptions {
            torso: source,
            ..RigOptions::default()
        };
        let mut rig = Rig::new(recordings::vrm(recordings::FIXTURE_VRM1), options).unwrap();
        let mut out = SolveOutput::default();
        let mut frame = FrameInput::default();
        let mut decoded = FrameInput::default();
        let mut input = vec![0.0f32; flat::input::LEN];
        let mut output = vec![0.0f32; flat::output::LEN];
        let mut run = |rig: &mut Rig, out: &mut SolveOutput, i: usize| {
            frame = clip[i % clip.len()];
            frame.time_ms = i as f64 * 33.3;
            match i % 4 {
                // Body joints from the pose's own points (avatar axes, 1 m up).
                1 => {
                    let pose = frame.pose.expect("every ASL frame has a pose");
                    let mut body = BodyObservation::default();
                    for (j, k) in [
                        (0, 23),
                        (1, 23),
                        (2, 24),
                        (3, 11),
                        (4, 12),
                        (5, 0),
                        (6, 2),
                        (7, 5),
                        (8, 7),
                        (9, 8),
                    ] {
                        let p = pose.world[k];
                        body.position[j] = Vec3::new(p.x, 1.0 - p.y, -p.z);
                        body.confidence[j] = pose.visibility[k];
                    }
                    frame.body = Some(body);
                }
                // The app's spine and head win.
                2 => {
                    frame.torso[1] = Some(Quat::from_rotation_x(0.2));
                    frame.torso[5] = Some(Quat::from_rotation_y(-0.3));
                }
                // Shoulders lost: held, then eased.
                3 => {
                    if let Some(p) = frame.pose.as_mut() {
                        p.visibility[11] = 0.0;
                    }
                }
                _ => {}
            }
            flat::write_input(&frame, &mut input);
            flat::read_input(&input, frame.time_ms, &mut decoded).unwrap();
            rig.solve(&decoded, out).unwrap();
            flat::write_output(rig, out, &mut output);
        };
        for i in 0..8 {
            run(&mut rig, &mut out, i);
        }
        let before = allocations();
        for i in 0..=4 * clip.len() {
            run(&mut rig, &mut out, i);
        }
        let after = allocations();
        assert_eq!(
            after - before,
            0,
            "{source:?}: {} allocations",
            after - before
        );
        // The counted frames were really solved (tracked in "pose"; the app's spine, i % 4 == 2).
        let tracked = out.solved[HumanBone::Spine.index()];
        run(&mut rig, &mut out, 2);
        assert!(
            (tracked || source == TorsoSource::Frame) && out.solved[HumanBone::Spine.index()],
            "{source:?}: the torso was solved"
        );
    }
}

#[test]
fn chain_solves_allocate_nothing() {
    check_counter();
    let joints: Vec<Vec3> = (0..8)
        .map(|k| Vec3::new(0.0, 0.1 * k as f32, 0.02 * (k % 2) as f32))
        .collect();
    let hinge = JointLimit::Hinge {
        axis: Vec3::X,
        min: -1.0,
        max: 1.0,
    };
    let cone = JointLimit::Cone { max_angle: 0.6 };
    let constraints = vec![
        Some(cone),
        None,
        Some(hinge),
        Some(cone),
        None,
        Some(hinge),
        None,
    ];
    for method in [ChainMethod::Fabrik, ChainMethod::Ccd] {
        for limits in [Vec::new(), constraints.clone()] {
            let mut solver = ChainSolver::new(&ChainSolverOptions {
                method,
                joints: joints.clone(),
                constraints: limits,
                ..ChainSolverOptions::default()
            })
            .unwrap();
            let mut out_joints = vec![0.0f32; 3 * 8];
            let mut out_rotations = vec![0.0f32; 4 * 7];
            let before = allocations();
            let mut iterations = 0;
            for i in 0..500 {
                let a = i as f32 * 0.05;
                let target = Vec3::new(0.3 * a.cos(), 0.4 + 0.2 * a.sin(), 0.3 * a.sin());
                let pole = (i % 3 != 0).then_some(Vec3::new(0.0, 0.3, -1.0));
                if i % 2 == 0 {
                    iterations += solver.solve(target, pole).unwrap().status.iterations;
                } else {
                    let status = solver
                        .solve_into(target, pole, &mut out_joints, &mut out_rotations)
                        .unwrap();
                    iterations += status.iterations;
                }
            }
            // Out of reach and at the root: the other paths.
            solver.solve(Vec3::splat(10.0), None).unwrap();
            solver.solve(Vec3::ZERO, Some(Vec3::Y)).unwrap();
            let after = allocations();
            assert_eq!(
                after - before,
                0,
                "{method:?}: {} allocations",
                after - before
            );
            assert!(iterations > 0 && out_joints.iter().any(|x| *x != 0.0));
        }
    }
}

/// Self-contact allocates nothing either: both hands on the face and on each other, with
/// tracker wrists and face points, and with pose input carrying face landmarks.
#[test]
fn contact_allocates_nothing() {
    use handrig::contact::face::{CANONICAL_ANCHORS, CANONICAL_EYES};
    use handrig::humanoid::bones::Side;
    use handrig::mediapipe::{pose_landmark as pl, Handedness, TrackerFace, WristObservation};

    let hands: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| h.world)
        .collect();
    check_counter();
    let skel = recordings::vrm(recordings::ROBOT);
    let mut rig = Rig::new(skel.clone(), RigOptions::default()).unwrap();
    // A user face (canonical, 0.15 m) 5 cm in front of the avatar's, in the avatar's frame.
    let origin = skel.rest_world(HumanBone::Head).unwrap()
        + rig.contact().face().origin
        + Vec3::new(0.0, 0.0, 0.05);
    let at = |c: Vec3| origin + c * 0.15;
    let face = TrackerFace {
        nose: Some(at(CANONICAL_ANCHORS[0])),
        eyes: CANONICAL_EYES.map(|e| Some(at(e))),
        ears: [
            Some(at(CANONICAL_ANCHORS[5])),
            Some(at(CANONICAL_ANCHORS[6])),
        ],
        mouth: Some(at(CANONICAL_ANCHORS[2])),
    };
    let nose = at(CANONICAL_ANCHORS[0]);
    // The same user as MediaPipe pose landmarks (user space 1 m below, camera axes).
    let mut pose = recordings::plausible_pose();
    let cam = |p: Vec3| {
        let p = p - Vec3::new(0.0, 1.0, 0.0);
        Vec3::new(p.x, -p.y, -p.z)
    };
    for (k, p) in [
        (pl::NOSE, face.nose),
        (pl::LEFT_EYE, face.eyes[0]),
        (pl::RIGHT_EYE, face.eyes[1]),
        (pl::LEFT_EAR, face.ears[0]),
        (pl::RIGHT_EAR, face.ears[1]),
        (pl::MOUTH_LEFT, face.mouth),
        (pl::MOUTH_RIGHT, face.mouth),
    ] {
        pose.world[k] = cam(p.unwrap());
    }
    let mut out = SolveOutput::default();
    let mut frame = FrameInput::default();
    let mut decoded = FrameInput::default();
    let mut input = vec![0.0f32; flat::input::LEN];
    let mut output = vec![0.0f32; flat::output::LEN];
    let mut face_contact = 0;
    let mut hand_contact = 0;
    let mut run = |rig: &mut Rig, i: usize, pose_input: bool| {
        let right = hands[i % hands.len()];
        let left = right.map(|p| Vec3::new(-p.x, p.y, p.z));
        frame.clear();
        frame.time_ms = i as f64 * 33.3;
        frame.hands[0] = recordings::hand(Handedness::Left, 0.9, right);
        frame.hands[1] = recordings::hand(Handedness::Right, 0.9, left);
        frame.hand_count = 2;
        // Camera axes to the avatar's: (x, -y, -z); the right index tip on the nose, the left
        // index tip on the right one.
        let tip = |lm: &[Vec3; 21]| {
            let d = lm[8] - lm[0];
            Vec3::new(d.x, -d.y, -d.z)
        };
        let wr = nose - tip(&right);
        let wl = nose - tip(&left);
        if pose_input {
            let mut p = pose;
            p.world[pl::RIGHT_WRIST] = cam(wr);
            p.world[pl::LEFT_WRIST] = cam(wl);
            frame.pose = Some(p);
        } else {
            for (side, w) in [(Side::Right, wr), (Side::Left, wl)] {
                frame.wrists[side.index()] = Some(WristObservation {
                    position: w,
                    rotation: None,
                });
            }
            frame.face = Some(face);
        }
        flat::write_input(&frame, &mut input);
        flat::read_input(&input, frame.time_ms, &mut decoded).unwrap();
        rig.solve(&decoded, &mut out).unwrap();
        flat::write_output(rig, &out, &mut output);
        for c in out.contact.iter().flatten() {
            face_contact += usize::from(c.weight > 0.5);
            hand_contact += usize::from(c.hand_weight > 0.5);
        }
    };
    for mode in [false, true] {
        run(&mut rig, 0, mode);
    }
    let before = allocations();
    for i in 0..hands.len() {
        run(&mut rig, i, i % 2 == 0);
    }
    let after = allocations();
    assert_eq!(
        after - before,
        0,
        "contact allocated {} times",
        after - before
    );
    // Not vacuous: face and hand contact were active in most frames.
    assert!(
        face_contact > hands.len(),
        "face contact in {face_contact} side-frames"
    );
    assert!(
        hand_contact > hands.len(),
        "hand contact in {hand_contact} side-frames"
    );
}

/// Contact on the skin (a generated body read with its skin): the face landing, the chest from
/// the image, the hands closing and the push allocate nothing per frame, on every shared ASL
/// clip (each path is checked to have run).
#[test]
fn skin_contact_allocates_nothing() {
    check_counter();
    let skel = recordings::vrm("tests/fixtures/avatars/woman-vrm1.vrm");
    let mut rig = Rig::new(skel, RigOptions::default()).unwrap();
    assert!(
        rig.contact().surface().is_some(),
        "the generated body has a skin"
    );
    let mut out = SolveOutput::default();
    let (mut face, mut chest, mut hands) = (0, 0, 0);
    for clip in recordings::ASL.iter().chain(recordings::ASL_MORE.iter()) {
        let frames = recordings::asl(clip);
        rig.reset();
        // The first frame may set up (history); every later one allocates nothing.
        rig.solve(&frames[0], &mut out).unwrap();
        for f in &frames[1..] {
            let before = allocations();
            rig.solve(f, &mut out).unwrap();
            assert_eq!(allocations(), before, "{clip}: a frame allocated");
            for c in out.contact.iter().flatten() {
                face += usize::from(c.weight > 0.5);
                chest += usize::from(c.chest_weight > 0.5);
                hands += usize::from(c.hand_weight > 0.5);
            }
        }
    }
    assert!(
        face > 20 && chest > 20 && hands > 20,
        "paths run: face {face}, chest {chest}, hands {hands}"
    );
}
