//! `Rig::solve` must not allocate: it runs every frame inside a browser tab. A counting global
//! allocator checks it on the real hand recording, with wrists and pose input, for every hand
//! strategy (one test: the counter is global, parallel tests would count each other).
// Native only: reads ../shared from disk (and uses proptest, not built for wasm32).
#![cfg(not(target_arch = "wasm32"))]

#[path = "support/recordings.rs"]
mod recordings;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use handrig::hand::HandStrategy;
use handrig::{FrameInput, HumanBone, Rig, RigOptions, SolveOutput};
use recordings::ArmInput;

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

#[test]
fn solve_allocates_nothing_per_frame() {
    // The first hand of every frame (labelled "Left": the subject's right hand).
    let hands: Vec<_> = recordings::hand_video_first()
        .iter()
        .map(|h| h.world)
        .collect();
    for strategy in [HandStrategy::Analytic, HandStrategy::Retarget] {
        let options = RigOptions {
            hand_strategy: strategy,
            ..RigOptions::default()
        };
        let rig = Rig::new(recordings::vrm(recordings::ROBOT), options).unwrap();
        count_allocations(rig, &hands, strategy);
    }
}

fn count_allocations(mut rig: Rig, hands: &[[glam::Vec3; 21]], strategy: HandStrategy) {
    let mut out = SolveOutput::default();
    let mut frame = FrameInput::default();
    let pose = recordings::plausible_pose();

    let mut run = |rig: &mut Rig, i: usize, mode: usize| {
        let arm = ArmInput::ALL[mode];
        recordings::fill_frame(&mut frame, hands[i % hands.len()], 0.9, arm, &pose);
        frame.time_ms = i as f64 * 33.3;
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
        "Rig::solve ({strategy:?}) allocated {} times over {} frames",
        after - before,
        hands.len()
    );
    // The frames were really solved (the count is not vacuous).
    assert!(out.solved[HumanBone::RightIndexDistal.index()]);
    assert_eq!(
        out.retarget[1].is_some(),
        strategy == HandStrategy::Retarget,
        "{strategy:?}"
    );
}
