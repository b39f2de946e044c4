//! Mirrored MediaPipe hands (issue 27): the rig's hand checks on the real ASL clips and on
//! real frames mirrored on purpose. `cargo run --release --example eval_turns` measures the
//! effect on whole clips.

use crate::support::recordings;

use glam::Quat;
use handrig::hand::flip::{chirality, image_agreement, MIRRORED};
use handrig::hand::HandStatus;
use handrig::mediapipe::{CameraMapping, FrameInput};
use handrig::rig::HandCheck;
use handrig::{Rig, RigOptions, Side, SolveOutput};

const PLEASE: &str = "../shared/data/asl/please.json";

/// The rig's check and status of `side` on every frame of `frames`.
fn checks(frames: &[FrameInput], side: Side) -> Vec<Option<(HandCheck, HandStatus)>> {
    let mut rig = Rig::new(recordings::vrm(recordings::ROBOT), RigOptions::default()).unwrap();
    let mut out = SolveOutput::default();
    frames
        .iter()
        .map(|f| {
            rig.solve(f, &mut out).unwrap();
            out.hands[side.index()].map(|t| (t.check, t.status))
        })
        .collect()
}

#[test]
fn the_world_landmarks_of_please_are_right_handed_but_for_the_flips() {
    // `please` frame 16: the signer's right hand flat on the chest, its world landmarks
    // with the knuckles swapped across the palm (the palm normal turns 103 degrees and back).
    let frames = recordings::asl(PLEASE);
    let camera = CameraMapping::default();
    let mut mirrored = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        for h in f.hands() {
            let side = camera.avatar_side(h.handedness);
            let world = h.world.map(|p| camera.to_avatar(p));
            let c = chirality(side, &world).unwrap();
            let a = image_agreement(&h.world, &h.image.unwrap()).unwrap_or(1.0);
            if c < MIRRORED || a < 0.0 {
                mirrored.push((i, side));
            }
        }
    }
    // Frame 2 (the hand leaving the hip, knuckle line crossed) and frame 16.
    assert_eq!(mirrored, vec![(2, Side::Right), (16, Side::Right)]);
}

#[test]
fn a_flipped_frame_of_a_real_clip_is_solved_from_the_image() {
    let frames = recordings::asl(PLEASE);
    let got = checks(&frames, Side::Right);
    assert_eq!(got[16], Some((HandCheck::FromImage, HandStatus::Solved)));
    assert_eq!(got[15], Some((HandCheck::Good, HandStatus::Solved)));
    assert_eq!(got[17], Some((HandCheck::Good, HandStatus::Solved)));
    // The confidence: the handedness score times 1 for a good hand, 0.6 from the image.
    let mut rig = Rig::new(recordings::vrm(recordings::ROBOT), RigOptions::default()).unwrap();
    let mut out = SolveOutput::default();
    for (i, f) in frames.iter().enumerate().take(18) {
        rig.solve(f, &mut out).unwrap();
        let t = out.hands[Side::Right.index()];
        if let Some(t) = t.filter(|_| i >= 15) {
            let score = f.hands()[t.index].score;
            let want = if i == 16 { 0.6 * score } else { score };
            assert!(
                (t.confidence - want).abs() < 1e-6,
                "frame {i}: {}",
                t.confidence
            );
        }
    }
}

/// `frame` with the world depth of the hand driving the avatar's right side mirrored about
/// its wrist, with or without its image landmarks.
fn mirrored(frame: &FrameInput, keep_image: bool) -> FrameInput {
    let mut f = *frame;
    let camera = CameraMapping::default();
    let n = f.hand_count;
    let h = f.hands[..n]
        .iter_mut()
        .find(|h| camera.avatar_side(h.handedness) == Side::Right)
        .expect("a right hand");
    let w = h.world[0];
    for p in &mut h.world {
        p.z = 2.0 * w.z - p.z;
    }
    if !keep_image {
        h.image = None;
    }
    f
}

#[test]
fn a_mirrored_hand_is_undone_from_the_image_or_held() {
    let frames = recordings::asl(PLEASE);
    // Frames 20-30: the signer's right hand on the chest, bent enough to tell.
    let side = Side::Right;
    let hand = side.hand().index();
    let solve = |edit: &dyn Fn(usize, &FrameInput) -> FrameInput| {
        let mut rig = Rig::new(recordings::vrm(recordings::ROBOT), RigOptions::default()).unwrap();
        let mut out = SolveOutput::default();
        let mut res = Vec::new();
        for (i, f) in frames.iter().enumerate().take(31) {
            rig.solve(&edit(i, f), &mut out).unwrap();
            res.push((out.hands[side.index()], out.world.rotation[hand]));
        }
        res
    };
    let clean = solve(&|_, f| *f);
    // Frame 25 mirrored, image landmarks kept: solved from the image, close to the clean hand.
    let from_image = solve(&|i, f| if i == 25 { mirrored(f, true) } else { *f });
    let t = from_image[25].0.unwrap();
    assert_eq!(
        (t.check, t.status),
        (HandCheck::FromImage, HandStatus::Solved)
    );
    let turn = |a: Quat, b: Quat| a.angle_between(b).to_degrees();
    let d = turn(from_image[25].1, clean[25].1);
    assert!(
        d < 30.0,
        "solved from the image: {d} degrees from the clean hand"
    );
    // Without image landmarks: held (the rotation of frame 24 again), for at most 3 frames.
    let held = solve(&|i, f| {
        if (25..=29).contains(&i) {
            mirrored(f, false)
        } else {
            *f
        }
    });
    for (i, (t, _)) in held.iter().enumerate().skip(25).take(5) {
        let t = t.unwrap();
        if t.status == HandStatus::Held {
            let score = frames[i].hands()[t.index].score;
            assert!((t.confidence - 0.3 * score).abs() < 1e-6, "frame {i}");
        }
        let want = if i <= 27 {
            (HandCheck::Mirrored, HandStatus::Held)
        } else if i == 28 {
            // Re-acquired after 3 held frames.
            (HandCheck::Good, HandStatus::Solved)
        } else {
            (HandCheck::Mirrored, HandStatus::Held)
        };
        assert_eq!((t.check, t.status), want, "frame {i}");
    }
}
