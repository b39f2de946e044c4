//! Duplicate hands and swapped labels (issue 27, `src/pipeline/select.rs`): what the hand
//! selection resolves per side (`TrackedHand::resolved`) on the real ASL clips and the hand
//! video, counted, and on frames built from them where the clips have no case of a kind (a
//! label that jumps sides between frames without a pose; two distinct hands of one label
//! without a pose). `cargo test --test it dups -- --nocapture` prints the counts.

use crate::support::recordings;

use handrig::mediapipe::{FrameInput, Handedness};
use handrig::pipeline::{HandResolved, HandUse, HandednessPolicy, MAX_JUMP_FRAMES};
use handrig::{Rig, RigOptions, Side, SolveOutput};

fn rig(options: RigOptions) -> Rig {
    Rig::new(recordings::vrm(recordings::ROBOT), options).unwrap()
}

fn flip(h: Handedness) -> Handedness {
    match h {
        Handedness::Left => Handedness::Right,
        Handedness::Right => Handedness::Left,
    }
}

/// Per frame, per side (`[left, right]`), what was resolved (`None`: no hand on the side).
fn resolved(frames: &[FrameInput], options: RigOptions) -> Vec<[Option<HandResolved>; 2]> {
    let mut rig = rig(options);
    let mut out = SolveOutput::default();
    frames
        .iter()
        .map(|f| {
            rig.solve(f, &mut out).unwrap();
            out.hands.map(|h| h.map(|h| h.resolved))
        })
        .collect()
}

/// `(clip, frame, side)` of every side-frame whose resolution is `kind`.
fn where_resolved(
    clip: &str,
    got: &[[Option<HandResolved>; 2]],
    kind: HandResolved,
) -> Vec<(String, usize, Side)> {
    let name = clip.rsplit('/').next().unwrap().trim_end_matches(".json");
    let mut v = Vec::new();
    for (i, sides) in got.iter().enumerate() {
        for side in Side::BOTH {
            if sides[side.index()] == Some(kind) {
                v.push((name.to_string(), i, side));
            }
        }
    }
    v
}

/// The shared clips, every default: the labels the pose contradicts are swapped, two hands of
/// one label near one pose wrist are a duplicate (one kept), nothing jumps (the pose is
/// always there to witness). Known answers from the recordings' own labels and pose wrists.
#[test]
fn the_asl_clips_resolve_swaps_and_duplicates() {
    let mut all = [Vec::new(), Vec::new(), Vec::new()];
    for clip in recordings::ASL.iter().chain(&recordings::ASL_MORE) {
        let frames = recordings::asl(clip);
        let got = resolved(&frames, RigOptions::default());
        for (k, kind) in [
            HandResolved::Swapped,
            HandResolved::Jumped,
            HandResolved::Duplicate,
        ]
        .into_iter()
        .enumerate()
        {
            all[k].extend(where_resolved(clip, &got, kind));
        }
    }
    let [swapped, jumped, duplicate] = all;
    println!("ASL (6 clips): swapped {}: {swapped:?}", swapped.len());
    println!(
        "ASL: jumped {}; duplicate {}: {duplicate:?}",
        jumped.len(),
        duplicate.len()
    );
    let has = |v: &[(String, usize, Side)], clip: &str, frame: usize, side: Side| {
        v.iter()
            .any(|(c, f, s)| c == clip && *f == frame && *s == side)
    };
    // `thanks` 10: two "Right" hands, one at the signer's right pose wrist.
    assert!(has(&swapped, "thanks", 10, Side::Right), "{swapped:?}");
    // `again` 9: a lone "Left" at the signer's left pose wrist.
    assert!(has(&swapped, "again", 9, Side::Left), "{swapped:?}");
    // `brother` 55: two "Right" hands both nearest the signer's left pose wrist.
    assert!(has(&duplicate, "brother", 55, Side::Left), "{duplicate:?}");
    assert_eq!(swapped.len(), 13);
    assert_eq!(duplicate.len(), 3);
    assert!(
        jumped.is_empty(),
        "with a pose the pose decides: {jumped:?}"
    );
}

/// The hand video (hand only, no pose) has four frames with MediaPipe's one hand found twice:
/// the hand nearer where the side's hand was the frame before keeps the side (not the higher
/// score), the other is dropped (it is the same hand, not moved to the free side).
#[test]
fn the_hand_video_duplicates_keep_the_continuous_hand() {
    let frames = recordings::hand_video_frames();
    let mut r = rig(RigOptions::default());
    let mut out = SolveOutput::default();
    let mut dups = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        r.solve(f, &mut out).unwrap();
        if f.hand_count < 2 {
            assert_ne!(
                out.hands[Side::Right.index()].map(|h| h.resolved),
                Some(HandResolved::Duplicate)
            );
            continue;
        }
        dups.push(i);
        let kept = out.hands[Side::Right.index()].expect("the right side keeps a hand");
        assert_eq!(kept.resolved, HandResolved::Duplicate, "frame {i}");
        assert!(!kept.reassigned);
        assert!(
            out.hands[Side::Left.index()].is_none(),
            "frame {i}: one hand found twice"
        );
        assert_eq!(out.hand_use[1 - kept.index], HandUse::Duplicate);
        // Kept: the one whose image wrist is nearer the previous frame's.
        let before = frames[i - 1].hands()[0].image.unwrap()[0].truncate();
        let d = |k: usize| (f.hands()[k].image.unwrap()[0].truncate() - before).length();
        assert!(d(kept.index) < d(1 - kept.index), "frame {i}");
    }
    println!("hand video: duplicates at {dups:?}");
    assert_eq!(dups, vec![559, 561, 563, 566]);
    // At 563 and 566 the higher score is the other, displaced hand: continuity decides.
    assert!(
        [563, 566]
            .iter()
            .all(|&i| frames[i].hands[0].score > frames[i].hands[1].score),
        "the frames where score and continuity disagree"
    );
}

/// No clip has a label that jumps sides without a pose: built from the hand video (one hand,
/// the signer's right, no pose) with its label flipped for a few frames. The flipped hand
/// stays where the right side's hand was, so it keeps driving the right side ("jumped"), for at
/// most `MAX_JUMP_FRAMES` frames; then the label is believed. `handedness: "trust"` follows
/// the label at once.
#[test]
fn a_label_that_jumps_sides_without_a_pose_is_relabelled() {
    let mut frames: Vec<FrameInput> = recordings::hand_video_frames()[..60].to_vec();
    let flipped = |frames: &mut [FrameInput], range: std::ops::Range<usize>| {
        for f in &mut frames[range] {
            f.hands[0].handedness = flip(f.hands[0].handedness);
        }
    };
    flipped(&mut frames, 20..22);
    flipped(&mut frames, 40..46);
    let got = resolved(&frames, RigOptions::default());
    let trust = resolved(
        &frames,
        RigOptions {
            handedness: HandednessPolicy::Trust,
            ..RigOptions::default()
        },
    );
    let right = |k: HandResolved| [None, Some(k)];
    for (i, got) in got.iter().enumerate() {
        let want = match i {
            20 | 21 => right(HandResolved::Jumped),
            40..=42 => right(HandResolved::Jumped),
            43..=45 => [Some(HandResolved::None), None],
            // The label's return is a jump too, from where the left side's hand just was.
            46..=48 => [Some(HandResolved::Jumped), None],
            _ => right(HandResolved::None),
        };
        assert_eq!(*got, want, "frame {i}");
    }
    assert_eq!(MAX_JUMP_FRAMES, 3);
    assert_eq!(trust[20], [Some(HandResolved::None), None]);
    assert_eq!(trust[40], [Some(HandResolved::None), None]);

    // A hand far from where the other side's was is not a jump: the left hand appearing
    // across the image from the right one.
    let mut apart = frames[..21].to_vec();
    for p in apart[20].hands[0].image.as_mut().unwrap() {
        p.x = 1.0 - p.x;
    }
    let got = resolved(&apart, RigOptions::default());
    let right_x = frames[19].hands[0].image.unwrap()[0].x;
    assert!((apart[20].hands[0].image.unwrap()[0].x - right_x).abs() > 0.1);
    assert_eq!(got[20], [Some(HandResolved::None), None]);
}

/// No clip has two distinct hands of one label without a pose: the ASL frames with two hands,
/// both given one label and the pose removed. Each hand goes to the side the pose gave it in
/// the real frame (the second to the free side, by the image's left-right order on a first
/// frame, by the previous frame's hands after one), reported "duplicate" (or "jumped" when
/// continuity already moved the second hand).
#[test]
fn two_distinct_hands_of_one_label_without_a_pose_take_both_sides() {
    let (mut total, mut right_sides, mut by_jump) = (0, 0, 0);
    for clip in recordings::ASL.iter().chain(&recordings::ASL_MORE) {
        let frames = recordings::asl(clip);
        let mut reference = rig(RigOptions::default());
        let mut blind_rig = rig(RigOptions::default());
        let mut out = SolveOutput::default();
        for f in &frames {
            reference.solve(f, &mut out).unwrap();
            let want: Vec<HandUse> = out.hand_use[..f.hand_count].to_vec();
            let mut blind = *f;
            blind.pose = None;
            blind.pose_image = None;
            if f.hand_count == 2 && want.iter().all(|u| matches!(u, HandUse::Drove(_))) {
                blind.hands[1].handedness = blind.hands[0].handedness;
            }
            blind_rig.solve(&blind, &mut out).unwrap();
            if f.hand_count != 2 || !want.iter().all(|u| matches!(u, HandUse::Drove(_))) {
                continue;
            }
            total += 1;
            let got = &out.hand_use[..2];
            if got == want.as_slice() {
                right_sides += 1;
                // The second hand moved by the duplicate rule (both sides "duplicate"), or
                // already by continuity (it landed where the other side's hand was the frame
                // before: "jumped", and the first is then alone on its side).
                let [a, b] = [0, 1].map(|s| out.hands[s].unwrap());
                let (moved, kept) = if a.reassigned { (a, b) } else { (b, a) };
                match moved.resolved {
                    HandResolved::Duplicate => assert_eq!(kept.resolved, HandResolved::Duplicate),
                    HandResolved::Jumped => {
                        by_jump += 1;
                        assert_eq!(kept.resolved, HandResolved::None);
                    }
                    other => panic!("{other:?}"),
                }
                assert_eq!(
                    out.hands.iter().flatten().filter(|h| h.reassigned).count(),
                    1
                );
            }
        }
    }
    println!(
        "two hands of one label, no pose: {right_sides}/{total} on the pose's sides \
         ({by_jump} moved by continuity, the rest by the duplicate rule)"
    );
    assert!(total > 50, "{total}");
    assert!(
        right_sides as f32 >= 0.95 * total as f32,
        "{right_sides}/{total}"
    );
}

/// The selection carries nothing across a new session: after a reset, a flipped label is
/// believed (no previous frame to witness a jump).
#[test]
fn reset_forgets_where_the_hands_were() {
    let frames = recordings::hand_video_frames();
    let mut r = rig(RigOptions::default());
    let mut out = SolveOutput::default();
    for f in &frames[..10] {
        r.solve(f, &mut out).unwrap();
    }
    let mut next = frames[10];
    next.hands[0].handedness = flip(next.hands[0].handedness);
    let mut kept = r.clone();
    kept.solve(&next, &mut out).unwrap();
    assert_eq!(
        out.hands[Side::Right.index()].map(|h| h.resolved),
        Some(HandResolved::Jumped)
    );
    r.reset();
    r.solve(&next, &mut out).unwrap();
    assert!(out.hands[Side::Right.index()].is_none());
    assert_eq!(
        out.hands[Side::Left.index()].map(|h| h.resolved),
        Some(HandResolved::None)
    );
}
