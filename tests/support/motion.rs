//! Motion metrics over per-frame rotation series, shared by the live-tracking tests and
//! `eval/rust/eval_live.rs`: jitter (angular acceleration), lag between two series, and the
//! largest frame-to-frame step.

use glam::Quat;

/// Mean angular acceleration (rad/s^2) over the bones (columns) and frames (rows) of `rot`,
/// sampled at `fps`.
pub fn jitter(rot: &[Vec<Quat>], fps: f32) -> f32 {
    let dt = 1.0 / fps;
    let (mut sum, mut n) = (0.0, 0);
    for w in rot.windows(3) {
        for ((a, b), c) in w[0].iter().zip(&w[1]).zip(&w[2]) {
            let v1 = (a.inverse() * *b).to_scaled_axis() / dt;
            let v2 = (b.inverse() * *c).to_scaled_axis() / dt;
            sum += ((v2 - v1) / dt).length();
            n += 1;
        }
    }
    sum / n.max(1) as f32
}

/// Frames by which `filtered` trails `raw`: the shift (0..=8) that best matches their
/// per-frame rotation angles, summed over bones.
pub fn lag_frames(raw: &[Vec<Quat>], filtered: &[Vec<Quat>]) -> usize {
    let angle = |q: &Quat| q.angle_between(Quat::IDENTITY);
    let err = |s: usize| -> f32 {
        (10 + s..raw.len())
            .map(|i| {
                filtered[i]
                    .iter()
                    .zip(&raw[i - s])
                    .map(|(f, r)| (angle(f) - angle(r)).powi(2))
                    .sum::<f32>()
            })
            .sum()
    };
    (0..=8)
        .min_by(|a, b| err(*a).total_cmp(&err(*b)))
        .unwrap_or(0)
}

/// Largest frame-to-frame rotation change (rad) of any bone in `rot`.
pub fn largest_step(rot: &[Vec<Quat>]) -> f32 {
    rot.windows(2)
        .flat_map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| a.angle_between(*b)))
        .fold(0.0, f32::max)
}

/// Drives `rig` over `frames` and returns, per avatar side (`[left, right]`), the largest turn
/// (radians) of the world rotation of its upper arm, forearm or hand between two consecutive
/// frames whose arm was solved in both, and the frame it came on (what a viewer sees jump).
/// `each` sees every frame's output.
pub fn largest_arm_turns(
    rig: &mut handrig::Rig,
    frames: &[handrig::FrameInput],
    mut each: impl FnMut(usize, &handrig::SolveOutput),
) -> [(f32, usize); 2] {
    use handrig::Side;
    let mut out = handrig::SolveOutput::default();
    let mut last: [Option<[Quat; 3]>; 2] = [None, None];
    let mut worst = [(0.0_f32, 0); 2];
    for (i, f) in frames.iter().enumerate() {
        rig.solve(f, &mut out).expect("solve");
        each(i, &out);
        for side in Side::BOTH {
            let s = side.index();
            let [_, upper, lower, hand] = side.arm();
            let now = out.solved[upper.index()]
                .then(|| [upper, lower, hand].map(|b| out.world.rotation[b.index()]));
            if let (Some(a), Some(b)) = (last[s], now) {
                let turn = (0..3).map(|k| a[k].angle_between(b[k])).fold(0.0, f32::max);
                if turn > worst[s].0 {
                    worst[s] = (turn, i);
                }
            }
            last[s] = now;
        }
    }
    worst
}
