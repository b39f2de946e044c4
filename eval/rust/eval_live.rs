//! Live-tracking figures on the real recordings (issue 13): jitter of finger and arm bones raw
//! vs One Euro filtered and the filter's lag, the tuning sweep behind the defaults, a 1 s
//! dropout with and without easing, and handedness from the pose.
//!
//! `cargo run --release --example eval_live [-- --sweep]`
//!
//! Data: the hand video `../shared/data/hands/right-hand-video-mediapipe.json` (621 frames at
//! 30 fps, finger bones) and the four ASL clips `../shared/data/asl/*.json` (250 frames, pose
//! and hands of one person: arm bones through the pose wrists, finger bones), on the robot.
//! Jitter = mean angular acceleration of a bone's local rotation (rad/s^2); lag = the frame
//! shift that best matches the filtered angle series to the raw one.

use handrig_support::motion;
use handrig_support::recordings;

use glam::Quat;
use handrig::filter::{DropoutOptions, FilterOptions};
use handrig::humanoid::bones::Finger;
use handrig::mediapipe::{FrameInput, Handedness};
use handrig::pipeline::{HandUse, HandednessPolicy};
use handrig::{HumanBone, Rig, RigOptions, Side, SolveOutput};
use motion::{jitter, lag_frames as lag, largest_step};

fn finger_bones(side: Side) -> Vec<HumanBone> {
    Finger::ALL.iter().flat_map(|f| side.finger(*f)).collect()
}

fn arm_bones() -> Vec<HumanBone> {
    Side::BOTH
        .iter()
        .flat_map(|s| [s.arm()[1], s.arm()[2]])
        .collect()
}

/// Local rotations of `bones` per frame.
fn run(frames: &[FrameInput], options: RigOptions, bones: &[HumanBone]) -> Vec<Vec<Quat>> {
    let mut rig = Rig::new(recordings::vrm(recordings::ROBOT), options).unwrap();
    let mut out = SolveOutput::default();
    frames
        .iter()
        .map(|f| {
            rig.solve(f, &mut out).unwrap();
            bones.iter().map(|b| out.local[b.index()]).collect()
        })
        .collect()
}

fn filtered(min_cutoff: f32, beta: f32) -> RigOptions {
    RigOptions {
        filter: FilterOptions {
            enabled: true,
            min_cutoff,
            beta,
            d_cutoff: 1.0,
        },
        ..RigOptions::per_frame()
    }
}

fn hand_video() -> Vec<FrameInput> {
    recordings::hand_video_first()
        .iter()
        .enumerate()
        .map(|(i, h)| {
            let mut f = recordings::frame_of(&[*h]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            f
        })
        .collect()
}

fn main() {
    let sweep = std::env::args().any(|a| a == "--sweep");
    let video = hand_video();
    let asl: Vec<Vec<FrameInput>> = recordings::ASL.iter().map(|c| recordings::asl(c)).collect();
    let fingers = finger_bones(Side::Right);
    let arms = arm_bones();

    // Jitter and lag, raw vs the defaults.
    let d = FilterOptions::default();
    println!(
        "## Jitter (mean angular acceleration, rad/s^2) and lag, raw vs filtered (minCutoff {}, beta {}, dCutoff {})\n",
        d.min_cutoff, d.beta, d.d_cutoff
    );
    println!("| data | bones | raw | filtered | filtered / raw | lag (frames) |");
    println!("| --- | --- | ---: | ---: | ---: | ---: |");
    let row =
        |name: &str, bones_name: &str, frames: &[FrameInput], bones: &[HumanBone], fps: f32| {
            let raw = run(frames, RigOptions::per_frame(), bones);
            let f = run(frames, filtered(d.min_cutoff, d.beta), bones);
            let (jr, jf) = (jitter(&raw, fps), jitter(&f, fps));
            println!(
                "| {name} | {bones_name} | {jr:.0} | {jf:.0} | {:.2} | {} |",
                jf / jr,
                lag(&raw, &f)
            );
        };
    row(
        "hand video (621 frames)",
        "right fingers",
        &video,
        &fingers,
        30.0,
    );
    let all: Vec<FrameInput> = asl.iter().flatten().copied().collect();
    // The ASL clips are filmed separately: solve each clip on its own rig, then concatenate.
    let per_clip = |options: RigOptions, bones: &[HumanBone]| -> Vec<Vec<Quat>> {
        asl.iter().flat_map(|c| run(c, options, bones)).collect()
    };
    for (bones_name, bones) in [("upper and lower arms", &arms), ("right fingers", &fingers)] {
        let raw = per_clip(RigOptions::per_frame(), bones);
        let f = per_clip(filtered(d.min_cutoff, d.beta), bones);
        let (jr, jf) = (jitter(&raw, 30.0), jitter(&f, 30.0));
        println!(
            "| ASL clips ({} frames) | {bones_name} | {jr:.0} | {jf:.0} | {:.2} | {} |",
            all.len(),
            jf / jr,
            lag(&raw, &f)
        );
    }

    if sweep {
        println!(
            "\n## Tuning sweep: filtered / raw jitter and lag, hand video fingers | ASL arms\n"
        );
        println!("| minCutoff | beta | fingers jitter | fingers lag | arms jitter | arms lag |");
        println!("| ---: | ---: | ---: | ---: | ---: | ---: |");
        let raw_f = run(&video, RigOptions::per_frame(), &fingers);
        let raw_a = per_clip(RigOptions::per_frame(), &arms);
        for min_cutoff in [0.5, 1.0, 1.5, 2.0, 3.0] {
            for beta in [0.0, 0.5, 2.0, 5.0, 20.0] {
                let f = run(&video, filtered(min_cutoff, beta), &fingers);
                let a = per_clip(filtered(min_cutoff, beta), &arms);
                println!(
                    "| {min_cutoff} | {beta} | {:.2} | {} | {:.2} | {} |",
                    jitter(&f, 30.0) / jitter(&raw_f, 30.0),
                    lag(&raw_f, &f),
                    jitter(&a, 30.0) / jitter(&raw_a, 30.0),
                    lag(&raw_a, &a)
                );
            }
        }
    }

    // A 1 s dropout in the hand video.
    let mut dropped = video.clone();
    for f in &mut dropped[300..330] {
        f.hand_count = 0;
    }
    let mut bones = vec![HumanBone::RightHand];
    bones.extend(&fingers);
    let largest = |rot: &[Vec<Quat>]| largest_step(&rot[299..340]).to_degrees();
    let easing = RigOptions {
        dropout: DropoutOptions::default(),
        ..RigOptions::per_frame()
    };
    println!("\n## Dropout: the hand removed for 1 s (frames 300-329 of the hand video)\n");
    println!(
        "largest frame-to-frame rotation of a right hand bone, frames 299-339: {:.1} deg snapping \
         (dropout off), {:.1} deg easing (hold {} ms, out {} ms, in {} ms); {:.1} deg on the same \
         frames without the dropout",
        largest(&run(&dropped, RigOptions::per_frame(), &bones)),
        largest(&run(&dropped, easing, &bones)),
        easing.dropout.hold_ms,
        easing.dropout.fade_out_ms,
        easing.dropout.fade_in_ms,
        largest(&run(&video, RigOptions::per_frame(), &bones)),
    );

    // Handedness from the pose.
    let flip = |h: Handedness| match h {
        Handedness::Left => Handedness::Right,
        Handedness::Right => Handedness::Left,
    };
    println!("\n## Handedness on the ASL clips (pose and hands of the same person)\n");
    println!(
        "| labels | handedness | hands driven to the side the pose gives | reassigned | ignored |"
    );
    println!("| --- | --- | ---: | ---: | ---: |");
    for (labels, swap) in [("as recorded", false), ("all swapped", true)] {
        for policy in [
            HandednessPolicy::Reassign,
            HandednessPolicy::Drop,
            HandednessPolicy::Trust,
        ] {
            let (mut n, mut right, mut reassigned, mut ignored) = (0, 0, 0, 0);
            for clip in &asl {
                let mut reference =
                    Rig::new(recordings::vrm(recordings::ROBOT), RigOptions::per_frame()).unwrap();
                let mut rig = Rig::new(
                    recordings::vrm(recordings::ROBOT),
                    RigOptions {
                        handedness: policy,
                        ..RigOptions::per_frame()
                    },
                )
                .unwrap();
                let (mut a, mut b) = (SolveOutput::default(), SolveOutput::default());
                for f in clip {
                    reference.solve(f, &mut a).unwrap();
                    let mut g = *f;
                    if swap {
                        for h in g.hands.iter_mut().take(f.hand_count) {
                            h.handedness = flip(h.handedness);
                        }
                    }
                    rig.solve(&g, &mut b).unwrap();
                    for k in 0..f.hand_count {
                        if !matches!(a.hand_use[k], HandUse::Drove(_)) {
                            continue;
                        }
                        n += 1;
                        right += usize::from(b.hand_use[k] == a.hand_use[k]);
                        ignored += usize::from(!matches!(b.hand_use[k], HandUse::Drove(_)));
                    }
                    reassigned += b.hands.iter().flatten().filter(|h| h.reassigned).count();
                }
            }
            println!(
                "| {labels} | {} | {right}/{n} | {reassigned} | {ignored} |",
                policy.as_str()
            );
        }
    }
}
