//! `Rig::solve` must not allocate: it runs every frame inside a browser tab. A counting global
//! allocator checks it on the real hand recording, with wrists and pose input.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use handrig::mediapipe::{
    HandObservation, Handedness, PoseObservation, WristObservation, HAND_LANDMARKS, POSE_LANDMARKS,
};
use handrig::{FrameInput, HumanBone, Rig, RigOptions, Skeleton, SolveOutput, VrmVersion};

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
    match handrig::vrm::load_skeleton(&robot) {
        Ok(s) => s,
        // Until the VRM reader is in, an equivalent hand-built skeleton.
        Err(_) => {
            let mut bones = vec![
                (HumanBone::Hips, Vec3::new(0.0, 0.75, 0.0)),
                (HumanBone::Spine, Vec3::new(0.0, 1.0, 0.0)),
                (HumanBone::Head, Vec3::new(0.0, 1.56, 0.0)),
            ];
            for (s, side) in [(1.0f32, handrig::Side::Left), (-1.0, handrig::Side::Right)] {
                let [_, ua, la, h] = side.arm();
                bones.push((ua, Vec3::new(0.125 * s, 1.5, 0.0)));
                bones.push((la, Vec3::new(0.375 * s, 1.5, 0.0)));
                bones.push((h, Vec3::new(0.625 * s, 1.5, 0.0)));
                for (k, f) in handrig::Finger::ALL.iter().enumerate() {
                    let z = 0.05 - 0.025 * k as f32;
                    for (j, b) in side.finger(*f).iter().enumerate() {
                        bones.push((*b, Vec3::new((0.75 + 0.03 * j as f32) * s, 1.5, z)));
                    }
                }
            }
            let legs = [
                (HumanBone::LeftUpperLeg, 0.1),
                (HumanBone::LeftLowerLeg, 0.1),
                (HumanBone::LeftFoot, 0.1),
                (HumanBone::RightUpperLeg, -0.1),
                (HumanBone::RightLowerLeg, -0.1),
                (HumanBone::RightFoot, -0.1),
            ];
            for (i, (b, x)) in legs.iter().enumerate() {
                bones.push((*b, Vec3::new(*x, 0.7 - 0.3 * (i % 3) as f32, 0.0)));
            }
            Skeleton::new(&bones, VrmVersion::V1).unwrap()
        }
    }
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
