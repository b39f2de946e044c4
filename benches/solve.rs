//! Per-frame cost of `Rig::solve` on the real hand recording and the shared robot avatar.
//!
//! `cargo bench --bench solve` prints the time per frame for: hands only (hand + fingers),
//! hands + `wrists` (adds fingertip alignment and arm IK), and hands + pose landmarks (adds
//! body mapping and calibration). The browser budget is a few hundred microseconds per frame
//! at 60 fps alongside rendering; these native figures are a lower bound for wasm.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use handrig::mediapipe::{
    HandObservation, Handedness, PoseObservation, WristObservation, HAND_LANDMARKS, POSE_LANDMARKS,
};
use handrig::{FrameInput, Rig, RigOptions, SolveOutput};

fn hand_frames() -> Vec<[Vec3; HAND_LANDMARKS]> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/hands/right-hand-video-mediapipe.json"
    ))
    .expect("shared recording at ../shared");
    let v: serde_json::Value = serde_json::from_str(&text).expect("recording JSON");
    v.as_array()
        .expect("array of frames")
        .iter()
        .map(|f| {
            let w = &f["hands"][0]["worldLandmarks"];
            std::array::from_fn(|i| {
                let c = |k: usize| w[i][k].as_f64().unwrap_or(0.0) as f32;
                Vec3::new(c(0), c(1), c(2))
            })
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let robot = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/avatars/debug-robot.vrm"
    ))
    .expect("shared avatar at ../shared");
    let skeleton = handrig::vrm::load_skeleton(&robot).expect("robot loads");
    let hands = hand_frames();
    let mut pose = PoseObservation {
        world: [Vec3::ZERO; POSE_LANDMARKS],
        visibility: [1.0; POSE_LANDMARKS],
    };
    pose.world[11] = Vec3::new(0.18, -0.45, 0.0);
    pose.world[12] = Vec3::new(-0.18, -0.45, 0.0);
    pose.world[13] = Vec3::new(0.25, -0.2, -0.05);
    pose.world[14] = Vec3::new(-0.25, -0.2, -0.05);
    pose.world[15] = Vec3::new(0.2, -0.3, -0.25);
    pose.world[16] = Vec3::new(-0.2, -0.3, -0.25);

    let mut group = c.benchmark_group("solve per frame (robot, real hand recording)");
    for (name, mode) in [("hands", 0), ("hands+wrists", 1), ("hands+pose", 2)] {
        let mut rig = Rig::new(skeleton.clone(), RigOptions::default()).expect("rig");
        let mut out = SolveOutput::default();
        let mut frame = FrameInput::default();
        let mut i = 0usize;
        group.bench_function(name, |b| {
            b.iter(|| {
                frame.clear();
                frame.hands[0] = HandObservation {
                    handedness: Handedness::Left,
                    score: 0.95,
                    world: hands[i % hands.len()],
                    image: None,
                };
                frame.hand_count = 1;
                match mode {
                    1 => {
                        frame.wrists[1] = Some(WristObservation {
                            position: Vec3::new(-0.45, 1.3, 0.2),
                            rotation: None,
                        })
                    }
                    2 => frame.pose = Some(pose),
                    _ => {}
                }
                i += 1;
                rig.solve(&frame, &mut out).expect("solve");
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
