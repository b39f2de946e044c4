//! Per-frame cost of `Rig::solve` on the real hand recording and the shared robot avatar, and
//! of its stages on their own.
//!
//! `cargo bench --bench solve` prints the time per frame for: hands only (hand + fingers),
//! hands + `wrists` (adds fingertip alignment and arm IK), and hands + pose landmarks (adds
//! body mapping and calibration); then per stage: one hand's solve (analytic), fingertip
//! alignment (the wrist target from this frame's finger FK), one arm's IK (two-bone), and the
//! flat layout's decode + encode. Native figures are a lower bound for wasm.

use handrig_support::recordings;

use criterion::{criterion_group, criterion_main, Criterion};
use handrig::{FrameInput, Rig, RigOptions, SolveOutput};
use recordings::ArmInput;

fn bench(c: &mut Criterion) {
    let skeleton = recordings::vrm(recordings::ROBOT);
    // The first hand of every frame (labelled "Left": the subject's right hand).
    let hands: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| h.world)
        .collect();
    let pose = recordings::plausible_pose();

    let mut group = c.benchmark_group("solve per frame (robot, real hand recording)");
    for (name, arm) in [
        ("hands", ArmInput::None),
        ("hands+wrists", ArmInput::Wrist),
        ("hands+pose", ArmInput::Pose),
    ] {
        let mut rig = Rig::new(skeleton.clone(), RigOptions::default()).expect("rig");
        let mut out = SolveOutput::default();
        let mut frame = FrameInput::default();
        let mut i = 0usize;
        group.bench_function(name, |b| {
            b.iter(|| {
                recordings::fill_frame(&mut frame, hands[i % hands.len()], 0.95, arm, &pose);
                i += 1;
                rig.solve(&frame, &mut out).expect("solve");
            })
        });
    }
    group.finish();

    // The stages on their own, on the same frames (right side).
    let side = handrig::Side::Right;
    let camera = handrig::CameraMapping::default();
    let landmarks: Vec<[glam::Vec3; 21]> = hands
        .iter()
        .map(|w| w.map(|p| camera.to_avatar(p)))
        .collect();
    let mut stages = c.benchmark_group("stages (robot, real hand recording)");
    let mut solver = handrig::hand::HandSolver::new(&skeleton, Default::default()).expect("hands");
    let mut local = [glam::Quat::IDENTITY; handrig::BONE_COUNT];
    let mut i = 0usize;
    stages.bench_function("hand solve (analytic, one hand)", |b| {
        b.iter(|| {
            i += 1;
            solver.solve(&skeleton, side, &landmarks[i % landmarks.len()], &mut local)
        })
    });
    let hand_rotation = solver
        .solve(&skeleton, side, &landmarks[100], &mut local)
        .expect("a solved hand");
    let options = handrig::align::AlignmentOptions::default();
    let part = handrig::align::AlignedPart::choose(&skeleton, side, options.finger);
    stages.bench_function("fingertip alignment", |b| {
        b.iter(|| {
            handrig::align::wrist_target(
                &skeleton,
                side,
                &options,
                part,
                &handrig::align::UserHand {
                    wrist: recordings::RIGHT_WRIST,
                    landmarks: &landmarks[100],
                    scale: 1.0,
                },
                hand_rotation,
                &local,
            )
        })
    });
    let mut arms =
        handrig::ik::ArmSolverState::new(&skeleton, handrig::ik::ArmSolver::TwoBone).expect("arms");
    let mut world = handrig::WorldPose::default();
    skeleton.forward(&local, &mut world);
    stages.bench_function("arm IK (two-bone, one arm)", |b| {
        b.iter(|| {
            let to = handrig::ik::ArmTarget {
                target: recordings::RIGHT_WRIST,
                hand_rotation: Some(hand_rotation),
                pole: None,
                finger: None,
            };
            arms.solve(side, &to, &mut local, &world)
        })
    });
    let mut rig = Rig::new(skeleton.clone(), RigOptions::default()).expect("rig");
    let mut out = SolveOutput::default();
    let mut frame = FrameInput::default();
    recordings::fill_frame(&mut frame, hands[100], 0.95, ArmInput::Pose, &pose);
    rig.solve(&frame, &mut out).expect("solve");
    let mut input = vec![0.0f32; handrig::flat::input::LEN];
    let mut output = vec![0.0f32; handrig::flat::output::LEN];
    let mut decoded = FrameInput::default();
    stages.bench_function("flat layout: decode input + encode output", |b| {
        b.iter(|| {
            handrig::flat::write_input(&frame, &mut input);
            handrig::flat::read_input(&input, 0.0, &mut decoded).expect("decode");
            handrig::flat::write_output(&rig, &out, &mut output);
        })
    });
    stages.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
