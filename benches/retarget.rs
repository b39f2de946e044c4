//! Per-hand cost of the hand strategies (issue 11): `HandSolver::solve` of one hand on the
//! real hand recording, per avatar, for `"analytic"` and `"retarget"` (which runs the
//! analytic solve first, then the fingertip fit).
//!
//! `cargo bench --bench retarget`. The target is at most 20 microseconds per hand natively
//! for `"retarget"`; the seed reports 5 ms per frame for its implementation.

use handrig_support::recordings;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Quat;
use handrig::hand::{HandSolver, HandStrategy};
use handrig::mediapipe::CameraMapping;
use handrig::{Side, BONE_COUNT};

fn bench(c: &mut Criterion) {
    let camera = CameraMapping::default();
    // The subject's right hand in the avatar frame, every frame in order (the temporal term
    // and warm starts see the real sequence).
    let hands: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| h.world.map(|p| camera.to_avatar(p)))
        .collect();
    let mut group = c.benchmark_group("hand solve per hand (real recording)");
    for (avatar, path) in [
        ("robot", recordings::ROBOT),
        ("human", recordings::FIXTURE_VRM1),
        ("vrm0", recordings::FIXTURE_VRM0),
    ] {
        let skeleton = recordings::vrm(path);
        for (name, strategy) in [
            ("analytic", HandStrategy::Analytic),
            ("retarget", HandStrategy::Retarget),
        ] {
            let mut solver = HandSolver::new(&skeleton, strategy).expect("solver");
            let mut local = [Quat::IDENTITY; BONE_COUNT];
            let mut i = 0usize;
            group.bench_function(format!("{name}/{avatar}"), |b| {
                b.iter(|| {
                    let lm = &hands[i % hands.len()];
                    i += 1;
                    solver.solve(&skeleton, Side::Right, lm, &mut local)
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
