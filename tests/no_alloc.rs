//! `Rig::solve` must not allocate: it runs every frame inside a browser tab. A counting global
//! allocator checks it on the real hand recording, with wrists and pose input.
// Native only: reads ../shared from disk (and uses proptest, not built for wasm32).
#![cfg(not(target_arch = "wasm32"))]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use handrig::mediapipe::{
    HandObservation, Handedness, PoseObservation, WristObservation, HAND_LANDMARKS, POSE_LANDMARKS,
};
use handrig::{FrameInput, HumanBone, Rig, RigOptions, Skeleton, SolveOutput};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn skeleton() -> Skeleton {
    let robot = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/avatars/debug-robot.vrm"
    ))
    .expect("shared avatar");
    handrig::vrm::load_skeleton(&robot).expect("robot loads")
}

fn hand_frames() -> Vec<[Vec3; HAND_LANDMARKS]> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/hands/right-hand-video-mediapipe.json"
    ))
    .expect("shared recording");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v.as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let w = &f["hands"][0]["worldLandmarks"];
            std::array::from_fn(|i| {
                let p = &w[i];
                Vec3::new(
                    p[0].as_f64().unwrap() as f32,
                    p[1].as_f64().unwrap() as f32,
                    p[2].as_f64().unwrap() as f32,
                )
            })
        })
        .collect()
}

#[test]
fn solve_allocates_nothing_per_frame() {
    let hands = hand_frames();
    let mut rig = Rig::new(skeleton(), RigOptions::default()).unwrap();
    let mut out = SolveOutput::default();
    let mut frame = FrameInput::default();
    let mut pose = PoseObservation {
        world: [Vec3::ZERO; POSE_LANDMARKS],
        visibility: [1.0; POSE_LANDMARKS],
    };
    // A plausible MediaPipe pose (camera axes: y down, z away): shoulders, elbows, wrists.
    pose.world[11] = Vec3::new(0.18, -0.45, 0.0);
    pose.world[12] = Vec3::new(-0.18, -0.45, 0.0);
    pose.world[13] = Vec3::new(0.25, -0.2, -0.05);
    pose.world[14] = Vec3::new(-0.25, -0.2, -0.05);
    pose.world[15] = Vec3::new(0.2, -0.3, -0.25);
    pose.world[16] = Vec3::new(-0.2, -0.3, -0.25);

    let mut run = |rig: &mut Rig, i: usize, mode: usize| {
        frame.clear();
        frame.time_ms = i as f64 * 33.3;
        frame.hands[0] = HandObservation {
            handedness: Handedness::Left,
            score: 0.9,
            world: hands[i % hands.len()],
            image: None,
        };
        frame.hand_count = 1;
        match mode {
            0 => {}
            1 => {
                frame.wrists[1] = Some(WristObservation {
                    position: Vec3::new(-0.45, 1.3, 0.2),
                    rotation: None,
                })
            }
            _ => frame.pose = Some(pose),
        }
        rig.solve(&frame, &mut out).unwrap();
    };
    // The counter sees allocations at all.
    let probe_before = ALLOCATIONS.load(Ordering::SeqCst);
    let probe = std::hint::black_box(vec![0u8; 64]);
    assert!(ALLOCATIONS.load(Ordering::SeqCst) > probe_before && probe.len() == 64);
    drop(probe);
    // Warm up every path once, then count.
    for mode in 0..3 {
        run(&mut rig, 0, mode);
    }
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    for i in 0..hands.len() {
        run(&mut rig, i, i % 3);
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert_eq!(
        after - before,
        0,
        "Rig::solve allocated {} times over {} frames",
        after - before,
        hands.len()
    );
    // The frames were really solved (the count is not vacuous).
    assert!(out.solved[HumanBone::RightIndexDistal.index()]);
}
