//! Native profile driver: the speed eval's full frames (ASL clips, robot, defaults) solved in a
//! loop, each clip with its own timestamps as `eval/speed.mjs` replays them. `cargo run --release --example profile_frame [-- SECONDS]`; under `perf record` for a
//! profile. Prints microseconds per frame.
#[path = "../tests/support/recordings.rs"]
mod recordings;
use handrig::{FrameInput, Rig, RigOptions, SolveOutput};
fn main() {
    let secs: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3.0);
    let skeleton = recordings::vrm(recordings::ROBOT);
    let frames: Vec<FrameInput> = recordings::ASL
        .iter()
        .flat_map(|c| recordings::asl(c))
        .collect();
    let mut rig = Rig::new(skeleton, RigOptions::default()).expect("rig");
    let mut out = SolveOutput::default();
    let start = std::time::Instant::now();
    let mut n = 0usize;
    while start.elapsed().as_secs_f64() < secs {
        for f in &frames {
            rig.solve(f, &mut out).expect("solve");
            n += 1;
        }
    }

    println!(
        "{:.2} us per frame over {n} frames",
        start.elapsed().as_secs_f64() * 1e6 / n as f64
    );
}
