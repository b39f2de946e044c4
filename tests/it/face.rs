//! The face (issue 50) through the whole pipeline on the human VRM 1.0 fixture: perfect sync
//! passes weights through (smoothing off), mirrored to the avatar's sides; presets move; a
//! blink closes at once and opens speed-limited; mouth shapes sum to at most 1; the head
//! follows the matrix (mirror-aware) and drives the neck and head only with a face; a lost
//! face eases out; a row-major matrix is refused by name.

use crate::support::recordings;

use glam::{Mat4, Quat};
use handrig::face::{FaceObservation, ARKIT, PRESETS, SHAPES};
use handrig::humanoid::bones::HumanBone as B;
use handrig::{flat, FrameInput, Rig, RigOptions, SolveOutput};

fn shape(name: &str) -> usize {
    ARKIT.iter().position(|n| *n == name).expect(name)
}

fn preset(out: &SolveOutput, name: &str) -> f32 {
    out.face.presets[PRESETS.iter().position(|n| *n == name).expect(name)]
}

fn matrix(q: Quat) -> [f32; 16] {
    Mat4::from_rotation_translation(q, glam::Vec3::new(0.0, 0.0, -40.0)).to_cols_array()
}

fn frame(t: f64, shapes: [f32; SHAPES], m: Option<[f32; 16]>) -> FrameInput {
    FrameInput {
        time_ms: t,
        face_tracking: Some(FaceObservation {
            shapes: Some(shapes),
            matrix: m,
            mesh: None,
        }),
        ..FrameInput::default()
    }
}

fn rig(o: RigOptions) -> Rig {
    Rig::new(recordings::vrm(recordings::FIXTURE_VRM1), o).expect("rig")
}

#[test]
fn perfect_sync_passes_weights_through_mirrored_and_presets_move() {
    let mut w = [0.0; SHAPES];
    for (k, v) in w.iter_mut().enumerate() {
        *v = (k as f32 * 0.37).fract() * 0.5;
    }
    let mut opts = RigOptions::per_frame();
    opts.face.calibration_time = 0.0;
    // Mirrored input, no mirror: MediaPipe's "Left" (the face's left in the flipped image, the
    // user's right) is the avatar's right.
    opts.input_mirrored = true;
    let mut r = rig(opts);
    let mut out = SolveOutput::default();
    r.solve(&frame(0.0, [0.0; SHAPES], None), &mut out).unwrap();
    r.solve(&frame(33.0, w, None), &mut out).unwrap();
    for (k, name) in ARKIT.iter().enumerate() {
        let partner = if let Some(base) = name.strip_suffix("Left") {
            shape(&format!("{base}Right"))
        } else if let Some(base) = name.strip_suffix("Right") {
            shape(&format!("{base}Left"))
        } else {
            k
        };
        assert!(
            (out.face.arkit[k] - w[partner]).abs() < 0.05,
            "{name}: {} vs {}",
            out.face.arkit[k],
            w[partner]
        );
    }
    // Un-mirrored input: the names are the avatar's sides.
    opts.input_mirrored = false;
    let mut r = rig(opts);
    r.solve(&frame(0.0, [0.0; SHAPES], None), &mut out).unwrap();
    r.solve(&frame(33.0, w, None), &mut out).unwrap();
    for k in 0..SHAPES {
        assert!((out.face.arkit[k] - w[k]).abs() < 0.05, "{}", ARKIT[k]);
    }
    let mut open = [0.0; SHAPES];
    open[shape("jawOpen")] = 0.6;
    open[shape("mouthSmileLeft")] = 0.7;
    open[shape("mouthSmileRight")] = 0.7;
    r.solve(&frame(66.0, open, None), &mut out).unwrap();
    assert!(preset(&out, "aa") > 0.5, "aa {}", preset(&out, "aa"));
    assert!(
        preset(&out, "happy") > 0.5,
        "happy {}",
        preset(&out, "happy")
    );
    let mouth: f32 = ["aa", "ih", "ou", "ee", "oh"]
        .iter()
        .map(|n| preset(&out, n))
        .sum();
    assert!(mouth <= 1.0 + 1e-6, "mouth shapes sum to {mouth}");
}

#[test]
fn a_blink_closes_at_once_opens_limited_and_looking_down_is_not_one() {
    let mut o = RigOptions::default();
    o.face.calibration_time = 0.0;
    let mut r = rig(o);
    let mut out = SolveOutput::default();
    let mut t = 0.0;
    let mut step = |w: [f32; SHAPES], out: &mut SolveOutput| {
        r.solve(&frame(t, w, None), out).unwrap();
        t += 1000.0 / 30.0;
    };
    for _ in 0..5 {
        step([0.0; SHAPES], &mut out);
    }
    let mut closed = [0.0; SHAPES];
    closed[shape("eyeBlinkLeft")] = 0.9;
    closed[shape("eyeBlinkRight")] = 0.9;
    step(closed, &mut out);
    assert!(
        preset(&out, "blink") > 0.99,
        "closed at once: {}",
        preset(&out, "blink")
    );
    step([0.0; SHAPES], &mut out);
    let first = preset(&out, "blink");
    assert!(first > 0.5 && first < 0.9, "opens limited (0.1 s): {first}");
    step([0.0; SHAPES], &mut out);
    step([0.0; SHAPES], &mut out);
    step([0.0; SHAPES], &mut out);
    assert!(preset(&out, "blink") == 0.0, "open after 0.13 s");
    // Looking down lowers MediaPipe's lids: `eyeBlink` 0.3 with `eyeLookDown` 0.6 (the shared
    // clips' downcast eyes, `please` and `thanks`: medians 0.31 and 0.24 with 0.60) is no blink.
    let mut down = [0.0; SHAPES];
    for n in ["eyeBlinkLeft", "eyeBlinkRight"] {
        down[shape(n)] = 0.3;
    }
    for n in ["eyeLookDownLeft", "eyeLookDownRight"] {
        down[shape(n)] = 0.6;
    }
    step(down, &mut out);
    assert_eq!(preset(&out, "blink"), 0.0);
    // A blink raises `eyeLookDown` too (0.7 on the shared clips' one blink and the bench's
    // rendered ones, `eyeBlink` 0.5-0.7): closed all the same.
    let mut shut = down;
    for n in ["eyeBlinkLeft", "eyeBlinkRight"] {
        shut[shape(n)] = 0.65;
    }
    for n in ["eyeLookDownLeft", "eyeLookDownRight"] {
        shut[shape(n)] = 0.7;
    }
    step(shut, &mut out);
    assert!(
        preset(&out, "blink") >= 0.5,
        "a blink with the eyes' look-down: {}",
        preset(&out, "blink")
    );
    for _ in 0..4 {
        step(down, &mut out);
    }
    assert_eq!(preset(&out, "blink"), 0.0, "open again, eyes down");
    assert!(
        out.face.look_at[1] > 5.0,
        "pitch (smoothed) {}",
        out.face.look_at[1]
    );
    // One eye: blinkLeft, the avatar's left.
    let mut wink = [0.0; SHAPES];
    wink[shape("eyeBlinkLeft")] = 0.9;
    step(wink, &mut out);
    assert!(preset(&out, "blinkLeft") > 0.99 && preset(&out, "blinkRight") == 0.0);
}

#[test]
fn a_blink_while_calibrating_does_not_raise_the_neutral_face() {
    // The neutral face is calibrated over the first 2 s (the default): a user who blinks in
    // them (two blinks of 5 frames at 30 fps, 170 ms each) must see later blinks as one who did
    // not. With the mean as the neutral, the blinks raised it (`eyeBlink` 0.05 -> 0.15). The
    // user who did not blinks as often in the next 2 s, so that both rigs have learned the
    // same closed level (`BOTH_CLOSED`) from two blinks.
    let blinks_after = |blink_while_calibrating: bool| {
        let mut r = rig(RigOptions::default());
        let mut out = SolveOutput::default();
        let eyes = |blink: f32, down: f32| {
            let mut w = [0.0; SHAPES];
            for n in ["eyeBlinkLeft", "eyeBlinkRight"] {
                w[shape(n)] = blink;
            }
            for n in ["eyeLookDownLeft", "eyeLookDownRight"] {
                w[shape(n)] = down;
            }
            w
        };
        for i in 0..120 {
            let t = f64::from(i) * 1000.0 / 30.0;
            let blinking = (i % 30) >= 15 && (i % 30) < 20;
            let shut = blinking && (i < 60) == blink_while_calibrating;
            let w = if shut {
                eyes(0.65, 0.7)
            } else {
                eyes(0.04 + 0.002 * (i % 10) as f32, 0.2)
            };
            r.solve(&frame(t, w, None), &mut out).unwrap();
        }
        // Then open, then a blink as MediaPipe scores the bench's man's.
        r.solve(&frame(4100.0, eyes(0.05, 0.2), None), &mut out)
            .unwrap();
        r.solve(&frame(4133.0, eyes(0.5, 0.66), None), &mut out)
            .unwrap();
        preset(&out, "blink")
    };
    let (clean, blinked) = (blinks_after(false), blinks_after(true));
    assert!(clean > 0.2, "the later blink shows: {clean}");
    assert!(
        (clean - blinked).abs() < 0.02,
        "the later blink {blinked} with blinks while calibrating, {clean} without"
    );
}

#[test]
fn the_head_follows_the_matrix_mirror_aware_and_only_with_a_face() {
    let yaw = Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-0.2);
    for mirror in [false, true] {
        let mut o = RigOptions::per_frame();
        o.mirror = mirror;
        o.face.neck_share = 0.3;
        let mut r = rig(o);
        let mut out = SolveOutput::default();
        let mut buf = vec![0.0; flat::output::LEN];
        r.solve(&FrameInput::default(), &mut out).unwrap();
        flat::write_output(&r, &out, &mut buf);
        assert_eq!(
            buf[flat::output::BONE_FLAGS + B::Head.index()],
            0.0,
            "no face, head not driven"
        );
        r.solve(&frame(33.0, [0.0; SHAPES], Some(matrix(yaw))), &mut out)
            .unwrap();
        let head = out.world.rotation[B::Head.index()];
        let want = if mirror {
            Quat::from_xyzw(yaw.x, -yaw.y, -yaw.z, yaw.w)
        } else {
            yaw
        };
        assert!(
            head.angle_between(want) < 0.01,
            "mirror {mirror}: {head:?} vs {want:?}"
        );
        let neck = out.local[B::Neck.index()];
        assert!(
            (neck.angle_between(Quat::IDENTITY) - 0.3 * want.angle_between(Quat::IDENTITY)).abs()
                < 0.01
        );
        flat::write_output(&r, &out, &mut buf);
        assert_eq!(buf[flat::output::BONE_FLAGS + B::Head.index()], 1.0);
        assert_eq!(buf[flat::output::FACE_STATE], 1.0);
    }
}

#[test]
fn a_lost_face_holds_then_eases_out() {
    let mut o = RigOptions::default();
    o.face.calibration_time = 0.0;
    let mut r = rig(o);
    let mut out = SolveOutput::default();
    let mut open = [0.0; SHAPES];
    open[shape("jawOpen")] = 0.8;
    r.solve(&frame(0.0, [0.0; SHAPES], None), &mut out).unwrap();
    for k in 1..10 {
        r.solve(
            &frame(
                f64::from(k) * 33.0,
                open,
                Some(matrix(Quat::from_rotation_y(0.3))),
            ),
            &mut out,
        )
        .unwrap();
    }
    let aa = preset(&out, "aa");
    assert!(aa > 0.5);
    let lost = |t: f64| FrameInput {
        time_ms: t,
        ..FrameInput::default()
    };
    r.solve(&lost(400.0), &mut out).unwrap();
    assert_eq!(out.face.state, 2);
    assert_eq!(preset(&out, "aa"), aa, "held");
    r.solve(&lost(900.0), &mut out).unwrap();
    assert!(
        preset(&out, "aa") < aa && preset(&out, "aa") > 0.0,
        "easing"
    );
    r.solve(&lost(1300.0), &mut out).unwrap();
    assert_eq!(out.face.state, 0);
    assert_eq!(preset(&out, "aa"), 0.0);
    assert!(!out.face.head);
}

#[test]
fn a_row_major_matrix_and_bad_scores_are_named() {
    let mut r = rig(RigOptions::default());
    let mut out = SolveOutput::default();
    let m = Mat4::from_rotation_translation(Quat::IDENTITY, glam::Vec3::new(1.0, 2.0, -40.0))
        .transpose();
    let e = r
        .solve(
            &frame(0.0, [0.0; SHAPES], Some(m.to_cols_array())),
            &mut out,
        )
        .unwrap_err();
    assert!(
        e.to_string().contains("facialTransformationMatrixes")
            && e.to_string().contains("column-major"),
        "{e}"
    );
    let mut w = [0.0; SHAPES];
    w[shape("jawOpen")] = 2.0;
    let e = r.solve(&frame(0.0, w, None), &mut out).unwrap_err();
    assert!(e.to_string().contains("faceBlendshapes"), "{e}");
    // The rig stays usable.
    r.solve(&frame(33.0, [0.0; SHAPES], None), &mut out)
        .unwrap();
}

#[test]
fn both_eyes_close_on_less_than_one_and_learn_the_users_closed_level() {
    // The bench's hooded man: open eyes `eyeBlink` 0.03 (`eyeLookDown` 0.07), closed eyes 0.55
    // with `eyeLookDown` 0.68, which one eye's ramp reads as 0.43 of a blink.
    let mut r = rig(RigOptions::default());
    let mut out = SolveOutput::default();
    let eyes = |left: f32, right: f32, down: f32| {
        let mut w = [0.0; SHAPES];
        w[shape("eyeBlinkLeft")] = left;
        w[shape("eyeBlinkRight")] = right;
        for n in ["eyeLookDownLeft", "eyeLookDownRight"] {
            w[shape(n)] = down;
        }
        w
    };
    let mut t = 0.0;
    let mut step = |w: [f32; SHAPES], out: &mut SolveOutput| {
        r.solve(&frame(t, w, None), out).unwrap();
        t += 1000.0 / 30.0;
    };
    for _ in 0..70 {
        step(eyes(0.03, 0.03, 0.07), &mut out);
    }
    let mut blink = |out: &mut SolveOutput| {
        step(eyes(0.55, 0.55, 0.68), out);
        let closed = preset(out, "blink");
        for _ in 0..4 {
            step(eyes(0.55, 0.55, 0.68), out);
        }
        for _ in 0..20 {
            step(eyes(0.03, 0.03, 0.07), out);
        }
        assert_eq!(preset(out, "blink"), 0.0, "open again");
        closed
    };
    let first = blink(&mut out);
    assert!(first >= 0.5, "both eyes closed: {first}");
    let mut later = first;
    for _ in 0..3 {
        later = blink(&mut out);
    }
    assert!(
        later > first + 0.05,
        "closer once this user's blinks are learned: {first} -> {later}"
    );
    // One eye alone at the same score is no blink (a wink: that eye alone).
    step(eyes(0.55, 0.03, 0.68), &mut out);
    assert!(preset(&out, "blink") == 0.0 && preset(&out, "blinkRight") == 0.0);
    for _ in 0..10 {
        step(eyes(0.03, 0.03, 0.07), &mut out);
    }
    // A wink as the bench's woman's scores: one eye 0.45, the other open.
    step(eyes(0.45, 0.02, 0.4), &mut out);
    assert!(
        preset(&out, "blinkLeft") >= 0.5 && preset(&out, "blink") == 0.0,
        "a wink: blinkLeft {}, blink {}",
        preset(&out, "blinkLeft"),
        preset(&out, "blink")
    );
}

/// Blendshape weights with both eyes' `eyeBlink` at `b` and their `eyeLookDown` at `down`.
fn both_eyes(b: f32, down: f32) -> [f32; SHAPES] {
    let mut w = [0.0; SHAPES];
    w[shape("eyeBlinkLeft")] = b;
    w[shape("eyeBlinkRight")] = b;
    for n in ["eyeLookDownLeft", "eyeLookDownRight"] {
        w[shape(n)] = down;
    }
    w
}

/// A rig (defaults) fed face frames of both eyes, 30 fps, after 70 frames of open eyes (its
/// neutral face).
struct BlinkRun {
    rig: Rig,
    out: SolveOutput,
    t: f64,
}

impl BlinkRun {
    fn calibrated() -> Self {
        let mut run = BlinkRun {
            rig: rig(RigOptions::default()),
            out: SolveOutput::default(),
            t: 0.0,
        };
        for _ in 0..70 {
            run.eyes(0.03, 0.07);
        }
        run
    }

    /// One frame of [`both_eyes`]`(b, down)`: the `blink` shown.
    fn eyes(&mut self, b: f32, down: f32) -> f32 {
        self.step(both_eyes(b, down));
        preset(&self.out, "blink")
    }

    /// One frame (30 fps) of these weights.
    fn step(&mut self, w: [f32; SHAPES]) {
        self.rig
            .solve(&frame(self.t, w, None), &mut self.out)
            .unwrap();
        self.t += 1000.0 / 30.0;
    }
}

#[test]
fn a_held_blink_does_not_follow_its_readings_noise() {
    // The bench's hooded man again (see above): once his closed level is learned, a held blink
    // whose reading wanders by a frame's noise (`eyeBlink` 0.54-0.56) stays shown closed
    // (`BLINK_HOLD`), and still closes at once and opens limited.
    let mut run = BlinkRun::calibrated();
    for _ in 0..4 {
        for _ in 0..5 {
            run.eyes(0.55, 0.68);
        }
        for _ in 0..20 {
            run.eyes(0.03, 0.07);
        }
    }
    let first = run.eyes(0.55, 0.68);
    assert!(first >= 0.8, "closes at once: {first}");
    // The hold from its second frame (the first reads without the hold).
    let mut shown = run.eyes(0.55, 0.68);
    let mut largest: f32 = 0.0;
    for b in [0.54, 0.56, 0.55, 0.54, 0.56, 0.55, 0.54, 0.56] {
        let now = run.eyes(b, 0.68);
        largest = largest.max((now - shown).abs());
        shown = now;
    }
    assert!(
        largest <= 0.02,
        "a held blink moves {largest} a frame (shown {shown})"
    );
    let opening = run.eyes(0.03, 0.07);
    assert!(
        opening > 0.5 && opening < shown,
        "opens limited: {shown} -> {opening}"
    );
    for _ in 0..3 {
        run.eyes(0.03, 0.07);
    }
    assert_eq!(preset(&run.out, "blink"), 0.0, "open again");
}

#[test]
fn a_held_half_read_wink_stays_still_and_a_blink_still_closes_at_once() {
    // The bench child's held left wink (face-wink, frames 21-28): `eyeBlinkLeft` 0.42-0.44
    // moving about 0.01 a frame, the other eye 0.01, both eyes' `eyeLookDown` 0.47. Half read
    // by the wink's ramp (three times as steep as a reading), it followed that noise 0.03-0.06
    // a frame; a fall that small is smoothed now (`BLINK_STILL`): at most 0.02 a frame, and the
    // wink still read.
    let mut run = BlinkRun::calibrated();
    let left = |run: &BlinkRun| preset(&run.out, "blink") + preset(&run.out, "blinkLeft");
    let wink = |l: f32| {
        let mut w = both_eyes(0.01, 0.47);
        w[shape("eyeBlinkLeft")] = l;
        w
    };
    for l in [0.2, 0.35, 0.42, 0.43] {
        run.step(wink(l));
    }
    let mut shown = left(&run);
    assert!((0.5..0.9).contains(&shown), "half read: {shown}");
    let (mut largest, mut least): (f32, f32) = (0.0, 1.0);
    for l in [
        0.422, 0.417, 0.435, 0.424, 0.43, 0.425, 0.432, 0.429, 0.417, 0.435,
    ] {
        run.step(wink(l));
        let now = left(&run);
        largest = largest.max((now - shown).abs());
        least = least.min(now);
        shown = now;
    }
    assert!(largest <= 0.02, "a held wink moves {largest} a frame");
    assert!(least >= 0.5, "the wink still read: {least}");
    assert_eq!(
        preset(&run.out, "blinkRight") + preset(&run.out, "blink"),
        0.0
    );
    // It opens as before (limited), to 0.
    run.eyes(0.03, 0.07);
    let opening = left(&run);
    assert!(opening < shown - 0.2, "opens: {shown} -> {opening}");
    for _ in 0..3 {
        run.eyes(0.03, 0.07);
    }
    assert_eq!(left(&run), 0.0, "open again");
    // A blink closes at once (its first frame) and opens limited as before.
    for _ in 0..20 {
        run.eyes(0.03, 0.07);
    }
    let first = run.eyes(0.6, 0.7);
    assert!(first >= 0.8, "closes at once: {first}");
    run.eyes(0.6, 0.7);
    let opening = run.eyes(0.03, 0.07);
    assert!(opening > 0.5 && opening < 0.9, "opens limited: {opening}");
    for _ in 0..3 {
        run.eyes(0.03, 0.07);
    }
    assert_eq!(preset(&run.out, "blink"), 0.0, "open again");
}

#[test]
fn a_long_squint_does_not_teach_the_closed_level() {
    // Both eyes held half shut for 30 s (a squint, a long laugh: both eyes read 0.36, which the
    // both-eyes ramp shows as 0.7 closed) are no blinks: the user's closed level learns only
    // from closures that ended within a blink's length (`BLINK_LEARN_MS`). Learned from them,
    // it would sink to its floor (0.35), and a later look-down whose smaller eye reads 0.27
    // would show as a blink (0.6).
    let mut run = BlinkRun::calibrated();
    let look_down = |run: &mut BlinkRun| {
        let mut most: f32 = 0.0;
        for _ in 0..10 {
            most = most.max(run.eyes(0.43, 0.6));
        }
        for _ in 0..10 {
            run.eyes(0.03, 0.07);
        }
        most
    };
    let before = look_down(&mut run);
    assert!(before < 0.5, "looking down is no blink: {before}");
    let mut squint: f32 = 1.0;
    for _ in 0..900 {
        squint = squint.min(run.eyes(0.379, 0.07));
    }
    assert!(squint > 0.5, "the squint shows half shut: {squint}");
    for _ in 0..10 {
        run.eyes(0.03, 0.07);
    }
    let after = look_down(&mut run);
    assert!(after < 0.5, "looking down after a long squint: {after}");
}

/// A talking mouth: the jaw held open 3 frames then shut shows `aa` at most 0.1 two frames
/// after the shut (the bench's talking clip; with the face's filter it still showed 0.3-0.7),
/// and opens to at least 0.3 within two frames; a brow raised and dropped the same way is
/// still smoothed (the mouth's faster filter is the jaw's and mouth's weights only).
#[test]
fn a_talking_mouth_shuts_within_two_frames_and_the_brows_stay_smoothed() {
    let mut run = BlinkRun::calibrated();
    let mut shut = [0.0; SHAPES];
    shut[shape("jawOpen")] = 0.02;
    for _ in 0..10 {
        run.step(shut);
    }
    let mut open = shut;
    open[shape("jawOpen")] = 0.7;
    open[shape("browInnerUp")] = 0.7;
    let mut seen = Vec::new();
    for _ in 0..3 {
        run.step(open);
        seen.push((
            preset(&run.out, "aa"),
            run.out.face.arkit[shape("browInnerUp")],
        ));
    }
    assert!(seen[1].0 >= 0.3, "aa opens within two frames: {seen:?}");
    for _ in 0..2 {
        run.step(shut);
        seen.push((
            preset(&run.out, "aa"),
            run.out.face.arkit[shape("browInnerUp")],
        ));
    }
    let (aa, brow) = seen[4];
    assert!(aa <= 0.1, "aa two frames after the shut: {seen:?}");
    assert!(brow > 0.1, "the brow still smoothed: {seen:?}");
}
