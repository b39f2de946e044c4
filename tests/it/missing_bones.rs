//! Avatars without the aligned finger's distal bone (partial finger rigs), without the index
//! finger, without any finger bone: alignment and self-contact use what the avatar has
//! ([`AlignedPart::choose`]), report it, and stay on.
//!
//! The avatars are the human-proportioned fixtures, the robot and the generated adult and
//! child (VRM 1.0 and 0.x) with bones removed; the data the shared hand video (with the Kinect
//! wrists) and the sign-language clips. Full avatars are checked by the golden test (their
//! outputs do not move).

use glam::{Quat, Vec3};
use handrig::align::{self, AlignPoint, AlignedPart};
use handrig::humanoid::bones::{Finger, HumanBone, Side, BONE_COUNT};
use handrig::{flat, FrameInput, Rig, RigOptions, Skeleton, SolveOutput};

use crate::support::kinect_wrists;
use crate::support::recordings;
use crate::support::stats;

/// The `p`-th percentile (0..1) of `v`.
fn percentile(v: &mut [f32], p: f32) -> f32 {
    v.sort_by(f32::total_cmp);
    stats::percentile(v, 100.0 * p)
}

const GENERATED: [&str; 4] = [
    "tests/fixtures/avatars/woman-vrm1.vrm",
    "tests/fixtures/avatars/man-vrm0.vrm",
    "tests/fixtures/avatars/child-vrm1.vrm",
    "tests/fixtures/avatars/child-vrm0.vrm",
];

/// The avatars the tests cut bones from.
fn avatars() -> Vec<(&'static str, Skeleton)> {
    [
        recordings::FIXTURE_VRM1,
        recordings::FIXTURE_VRM0,
        recordings::ROBOT,
    ]
    .into_iter()
    .chain(GENERATED)
    .map(|p| (p, recordings::vrm(p)))
    .collect()
}

/// `skel` without the bones `drop` says to drop (rest positions and look-at kept).
fn without(skel: &Skeleton, drop: impl Fn(HumanBone) -> bool) -> Skeleton {
    let version = skel.version();
    let bones: Vec<(HumanBone, Vec3)> = skel
        .bones()
        .filter(|b| !drop(*b))
        .map(|b| {
            let p = skel.rest_world(b).expect("present");
            (b, version.position_to_internal(p))
        })
        .collect();
    Skeleton::new(&bones, version)
        .expect("skeleton")
        .with_look_at_offset(skel.look_at_offset())
}

fn fingers_of(side: Side) -> impl Iterator<Item = HumanBone> {
    Finger::ALL.into_iter().flat_map(move |f| side.finger(f))
}

/// The three cuts of the issue, on both sides: `(name, cut skeleton, expected part)`.
fn cuts(skel: &Skeleton) -> Vec<(&'static str, Skeleton, AlignedPart)> {
    let index = |s: Side| s.finger(Finger::Index);
    vec![
        (
            "no indexDistal",
            without(skel, |b| Side::BOTH.iter().any(|s| b == index(*s)[2])),
            AlignedPart::Finger {
                finger: Finger::Index,
                depth: 1,
            },
        ),
        (
            "no index finger",
            without(skel, |b| Side::BOTH.iter().any(|s| index(*s).contains(&b))),
            AlignedPart::Finger {
                finger: Finger::Middle,
                depth: 2,
            },
        ),
        (
            "no fingers",
            without(skel, |b| {
                Side::BOTH.iter().any(|s| fingers_of(*s).any(|f| f == b))
            }),
            AlignedPart::Palm,
        ),
    ]
}

#[test]
fn the_stand_in_follows_the_rule_and_is_named() {
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let rig = Rig::new(skel.clone(), RigOptions::default()).expect("rig");
    for side in Side::BOTH {
        assert!(rig.aligned_part(side).is_configured(Finger::Index));
    }
    assert_eq!(rig.alignment_warning(), None, "full avatar");
    for (name, cut, want) in cuts(&skel) {
        let rig = Rig::new(cut, RigOptions::default()).expect("rig");
        for side in Side::BOTH {
            assert_eq!(rig.aligned_part(side), want, "{name} {side:?}");
        }
        let w = rig.alignment_warning().expect("a warning");
        let missing = Side::Right.finger(Finger::Index)[2].as_str();
        let used = want.bone(Side::Right).as_str();
        assert!(
            w.contains(missing) && w.contains(used),
            "{name}: {w} names neither {missing} nor {used}"
        );
    }
    // Only the right index intermediate and distal gone: the right side takes its index
    // proximal, the left is untouched.
    let cut = without(&skel, |b| {
        b == HumanBone::RightIndexDistal || b == HumanBone::RightIndexIntermediate
    });
    let rig = Rig::new(cut.clone(), RigOptions::default()).expect("rig");
    assert_eq!(
        rig.aligned_part(Side::Right),
        AlignedPart::Finger {
            finger: Finger::Index,
            depth: 0
        }
    );
    assert!(rig.aligned_part(Side::Left).is_configured(Finger::Index));
    assert!(!rig.alignment_warning().expect("warning").contains("left"));
    // The configured thumb missing entirely: the index (first in the order) stands in; the
    // middle finger configured, without its distal: its intermediate.
    let no_thumb = without(&skel, |b| {
        Side::BOTH
            .iter()
            .any(|s| s.finger(Finger::Thumb).contains(&b))
    });
    let thumb = RigOptions::from_json(r#"{ "alignment": { "finger": "thumb" } }"#).unwrap();
    let rig = Rig::new(no_thumb, thumb).expect("rig");
    assert_eq!(
        rig.aligned_part(Side::Left),
        AlignedPart::Finger {
            finger: Finger::Index,
            depth: 2
        }
    );
    // Alignment and contact both off: nothing to warn about.
    let off = RigOptions::from_json(
        r#"{ "alignment": { "enabled": false }, "contact": { "enabled": false } }"#,
    )
    .unwrap();
    let rig = Rig::new(cut, off).expect("rig");
    assert_eq!(rig.alignment_warning(), None);
}

/// The extrapolated point against the real one: on full avatars, with this frame's finger
/// rotations from the hand video, the index DIP and tip extrapolated from the intermediate
/// (depth 1) and proximal (depth 0) bones against forward kinematics through the distal bone,
/// in percent of the wrist-to-fingertip length (the avatars' hands differ 2.5x in size).
#[test]
fn extrapolated_fingertips_are_near_the_real_ones() {
    let video = recordings::hand_video();
    for (path, skel) in avatars() {
        let mut rig = Rig::new(skel.clone(), RigOptions::default()).expect("rig");
        let mut out = SolveOutput::default();
        let side = Side::Right;
        let mut errors = [[Vec::new(), Vec::new()], [Vec::new(), Vec::new()]];
        let reach = {
            let local = [Quat::IDENTITY; BONE_COUNT];
            let full = AlignedPart::Finger {
                finger: Finger::Index,
                depth: 2,
            };
            align::part_offset(&skel, side, full, AlignPoint::Tip, Quat::IDENTITY, &local).length()
        };
        for (i, hands) in video.iter().enumerate() {
            let mut f =
                recordings::frame_of(&hands[..hands.len().min(handrig::mediapipe::MAX_HANDS)]);
            f.time_ms = i as f64 * 1000.0 / 30.0;
            if rig.solve(&f, &mut out).is_err() || out.hands[side.index()].is_none() {
                continue;
            }
            let local = &out.local;
            for (k, point) in [AlignPoint::Dip, AlignPoint::Tip].into_iter().enumerate() {
                let at = |depth| {
                    let part = AlignedPart::Finger {
                        finger: Finger::Index,
                        depth,
                    };
                    align::part_offset(&skel, side, part, point, Quat::IDENTITY, local)
                };
                let real = at(2);
                for depth in [0, 1] {
                    errors[k][depth].push(100.0 * (at(depth) - real).length() / reach);
                }
            }
        }
        assert!(
            errors[0][0].len() > 500,
            "{path}: {} frames",
            errors[0][0].len()
        );
        for (k, point) in ["DIP", "tip"].iter().enumerate() {
            for depth in [1, 0] {
                let e = &mut errors[k][depth];
                let (median, p95) = (percentile(e, 0.5), percentile(e, 0.95));
                println!(
                    "{path}: index {point} from depth {depth}: median {median:.1}%, p95 {p95:.1}% of \
                     wrist-to-tip {:.0} mm",
                    reach * 1e3
                );
                // From the intermediate the DIP is exact but for the avatar's phalanx
                // proportions (0 on the fixtures built to the table, 5.6-6.5% elsewhere); the
                // tip also misses the DIP's curl. From the proximal both the PIP's and the
                // DIP's curl are missing (straight extrapolation): a curled finger's point is
                // far off, and the generated hands' wrist-to-knuckle proportions differ most.
                let bound = match (depth, k) {
                    (1, 0) => 8.0,
                    (1, _) => 13.0,
                    _ => 30.0,
                };
                assert!(
                    median < bound,
                    "{path}: {point} from depth {depth}: median {median:.1}% >= {bound}%"
                );
            }
        }
    }
}

/// Solves `frames` on a rig for `skel` and returns every frame's output.
fn run(skel: &Skeleton, options: &str, frames: &[FrameInput]) -> (Rig, Vec<SolveOutput>) {
    let mut rig = Rig::new(skel.clone(), RigOptions::from_json(options).unwrap()).expect("rig");
    let mut outs = Vec::with_capacity(frames.len());
    for f in frames {
        let mut out = SolveOutput::default();
        rig.solve(f, &mut out).expect("solve");
        outs.push(out);
    }
    (rig, outs)
}

#[test]
fn alignment_puts_the_stand_in_on_the_users_point() {
    let clips: Vec<(&str, Vec<FrameInput>)> = vec![
        ("eat", recordings::asl(recordings::ASL[0])),
        ("sister", recordings::asl(recordings::ASL[3])),
    ];
    let mut flat_out = vec![0.0f32; flat::output::LEN];
    for (path, skel) in avatars().into_iter().take(4) {
        let mut data = clips.clone();
        data.push((
            "hand video + kinect",
            kinect_wrists::paired_frames(&skel, Side::Right),
        ));
        for (cut_name, cut, want) in cuts(&skel) {
            let mut errors = Vec::new();
            let (mut reports, mut unreachable) = (0, 0);
            for (clip, frames) in &data {
                let (rig, outs) = run(&cut, r#"{ "contact": { "enabled": false } }"#, frames);
                for out in &outs {
                    for side in Side::BOTH {
                        let Some(a) = out.alignment[side.index()] else {
                            continue;
                        };
                        reports += 1;
                        assert!(a.aligned, "{path} {cut_name} {clip}: not aligned");
                        assert_eq!(a.part, want, "{path} {cut_name} {clip}");
                        if a.reachable {
                            errors.push(a.error * 1e3);
                        } else {
                            unreachable += 1;
                        }
                    }
                    // The flat output names the bone standing in.
                    flat::write_output(&rig, out, &mut flat_out);
                    for side in Side::BOTH {
                        let at = flat::output::SIDES + side.index() * flat::output::SIDE_STRIDE;
                        if flat_out[at + flat::output::side::ALIGNMENT_PRESENT] == 1.0 {
                            assert_eq!(
                                flat_out[at + flat::output::side::ALIGNED_BONE],
                                1.0 + want.bone(side).index() as f32
                            );
                        }
                    }
                }
            }
            assert!(reports > 100, "{path} {cut_name}: {reports} reports");
            let median = percentile(&mut errors, 0.5);
            let p95 = percentile(&mut errors, 0.95);
            println!(
                "{path} / {cut_name}: {reports} aligned hand-frames ({unreachable} unreachable), \
                 error median {median:.3} mm, p95 {p95:.2} mm"
            );
            assert!(
                median <= 0.5,
                "{path} {cut_name}: median alignment error {median:.3} mm"
            );
        }
    }
}

/// Face-touch frames of `eat` (the signer's fingertips at the mouth): the side-frames where
/// the full avatar's contact blends the signing hand toward the face (contact weight > 0,
/// as `eval/rust/eval_contact.rs` counts them). On the cut avatars contact touches in them too.
#[test]
fn contact_touches_in_the_face_touch_frames() {
    let frames = recordings::asl(recordings::ASL[0]);
    for (path, skel) in avatars().into_iter().take(4) {
        let (_, full) = run(&skel, "{}", &frames);
        let touches: Vec<(usize, Side)> = full
            .iter()
            .enumerate()
            .flat_map(|(i, out)| {
                Side::BOTH.into_iter().filter_map(move |s| {
                    out.contact[s.index()]
                        .is_some_and(|c| c.weight > 0.0)
                        .then_some((i, s))
                })
            })
            .collect();
        assert!(
            touches.len() >= 10,
            "{path}: {} touch frames",
            touches.len()
        );
        for (cut_name, cut, _) in cuts(&skel) {
            let (_, outs) = run(&cut, "{}", &frames);
            let mut touching = 0;
            let mut distances = Vec::new();
            for &(i, s) in &touches {
                let Some(c) = outs[i].contact[s.index()] else {
                    continue;
                };
                if c.weight > 0.0 {
                    touching += 1;
                    if c.distance.is_finite() {
                        distances.push(c.distance * 1e3);
                    }
                }
            }
            let full_d: Vec<f32> = touches
                .iter()
                .filter_map(|&(i, s)| full[i].contact[s.index()].map(|c| c.distance * 1e3))
                .collect();
            let median = percentile(&mut distances.clone(), 0.5);
            println!(
                "{path} / {cut_name}: contact in {touching} of {} face-touch side-frames; \
                 touching point to anchor median {median:.1} mm (full avatar {:.1} mm)",
                touches.len(),
                percentile(&mut full_d.clone(), 0.5)
            );
            assert!(
                touching * 10 >= touches.len() * 8,
                "{path} {cut_name}: contact in {touching} of {} face-touch frames",
                touches.len()
            );
            assert_eq!(
                distances.len(),
                touching,
                "{path} {cut_name}: distance unknown"
            );
        }
    }
}

/// A real avatar without finger bones (the shared odd-armature VRM 0.x, 17 bones): its palm
/// stands in, alignment is exact and contact touches in `eat`'s face-touch frames (those of
/// the human-proportioned fixture: the user's side decides them).
#[test]
fn an_avatar_without_finger_bones_aligns_and_touches_with_its_palm() {
    let odd = recordings::vrm("../shared/avatars/odd-armature-vrm0.vrm");
    assert!(Finger::ALL
        .iter()
        .all(|f| Side::Right.finger(*f).iter().all(|b| !odd.has(*b))));
    let frames = recordings::asl(recordings::ASL[0]);
    let (rig, outs) = run(&odd, "{}", &frames);
    for side in Side::BOTH {
        assert_eq!(rig.aligned_part(side), AlignedPart::Palm);
    }
    let (_, full) = run(&recordings::vrm(recordings::FIXTURE_VRM1), "{}", &frames);
    let mut errors = Vec::new();
    let (mut reports, mut touches, mut touching) = (0, 0, 0);
    for (out, reference) in outs.iter().zip(&full) {
        for side in Side::BOTH {
            let s = side.index();
            if let Some(a) = out.alignment[s] {
                assert!(a.aligned);
                reports += 1;
                if a.reachable {
                    errors.push(a.error * 1e3);
                }
            }
            if reference.contact[s].is_some_and(|c| c.weight > 0.0) {
                touches += 1;
                touching += usize::from(out.contact[s].is_some_and(|c| c.weight > 0.0));
            }
        }
    }
    let median = percentile(&mut errors, 0.5);
    println!(
        "odd-armature-vrm0: {reports} aligned hand-frames, {} reachable, error median \
         {median:.3} mm; contact in {touching} of {touches} face-touch side-frames",
        errors.len()
    );
    assert!(
        errors.len() >= 20,
        "{} reachable aligned frames",
        errors.len()
    );
    assert!(median <= 0.5, "median {median:.3} mm");
    assert!(
        touches >= 10 && touching == touches,
        "{touching} of {touches}"
    );
}
