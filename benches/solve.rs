//! Per-frame cost of `Rig::solve` on the real hand recording and the shared robot avatar.
//!
//! `cargo bench --bench solve` prints the time per frame for: hands only (hand + fingers),
//! hands + `wrists` (adds fingertip alignment and arm IK), and hands + pose landmarks (adds
//! body mapping and calibration). The browser budget is a few hundred microseconds per frame
//! at 60 fps alongside rendering; these native figures are a lower bound for wasm.

#[path = "../tests/support/recordings.rs"]
mod recordings;

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
}

criterion_group!(benches, bench);
criterion_main!(benches);
