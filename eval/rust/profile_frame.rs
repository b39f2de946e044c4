//! Native profile driver: the speed eval's full frames (the four ASL clips, the robot, default
//! options) solved in a loop, each clip with its own timestamps as `eval/speed.mjs` replays
//! them. Prints microseconds per frame.
//!
//! ```text
//! cargo run --release --example profile_frame [-- SECONDS]      (default 3 s)
//! cargo run --release --example profile_frame -- --passes N      (N passes over the 250 frames)
//! HANDRIG_OPTIONS='{"contact":{"enabled":false}}' cargo run ...    (options as the JS API takes them)
//! HANDRIG_AVATAR=tests/fixtures/avatars/woman-vrm1.vrm cargo run ...  (another avatar: a
//!                                     generated one times self-contact on its skin)
//! HANDRIG_FRAMES=eval/frames/hands-near-face.json cargo run ...  (other full frames, in the
//!                                     ASL clips' format: e.g. where self-contact engages;
//!                                     or a hands-only recording, e.g.
//!                                     ../shared/data/hands/right-hand-video-mediapipe.json,
//!                                     `eval/speed.mjs`'s "one hand" frames)
//! HANDRIG_DIGEST=1 cargo run ... -- --passes 1   (also prints a digest of every output of
//!                                     every frame: two builds with the same digest gave
//!                                     bit-identical outputs on these frames)
//! ```
//!
//! Under `perf record` for a profile; `--passes` under `valgrind --tool=callgrind` for an
//! instruction count that does not depend on how busy the machine is.
use handrig::{FrameInput, Rig, RigOptions, SolveOutput};
use handrig_support::recordings;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (secs, passes) = match args.as_slice() {
        [flag, n] if flag == "--passes" => (f64::INFINITY, n.parse().expect("--passes N")),
        [s] => (s.parse().expect("SECONDS"), usize::MAX),
        _ => (3.0, usize::MAX),
    };
    let skeleton = recordings::vrm(
        &std::env::var("HANDRIG_AVATAR").unwrap_or_else(|_| recordings::ROBOT.to_string()),
    );
    let frames: Vec<FrameInput> = match std::env::var("HANDRIG_FRAMES") {
        Ok(file) => recordings::read_asl(std::path::Path::new(&file))
            .unwrap_or_else(|e| panic!("HANDRIG_FRAMES: {e}")),
        Err(_) => recordings::ASL
            .iter()
            .flat_map(|c| recordings::asl(c))
            .collect(),
    };
    let options: RigOptions = match std::env::var("HANDRIG_OPTIONS") {
        Ok(json) => RigOptions::from_json(&json).expect("HANDRIG_OPTIONS: rig options as JSON"),
        Err(_) => RigOptions::default(),
    };
    let mut rig = Rig::new(skeleton, options).expect("rig");
    let mut out = SolveOutput::default();
    let start = std::time::Instant::now();
    let mut n = 0usize;
    let mut pass = 0;
    let digest = std::env::var("HANDRIG_DIGEST").is_ok();
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    while pass < passes && start.elapsed().as_secs_f64() < secs {
        for f in &frames {
            rig.solve(f, &mut out).expect("solve");
            if digest {
                // Debug prints each float's shortest round-trip form: equal text, equal bits.
                std::hash::Hash::hash(&format!("{out:?}"), &mut hasher);
            }
            n += 1;
        }
        pass += 1;
    }
    if digest {
        println!("digest {:016x}", std::hash::Hasher::finish(&hasher));
    }
    println!(
        "{:.2} us per frame over {n} frames",
        start.elapsed().as_secs_f64() * 1e6 / n as f64
    );
}
