//! The torso (issue 12) through the whole pipeline, on synthetic users posed by a known torso
//! (lean forward 20 degrees, turn 30, side bend 15, combinations, turned hips and head, a
//! shrug; both hands) and on the three real avatars: the tracked torso is recovered, the
//! app's torso is used as given, fingertip alignment lands on target DIPs computed here from
//! the known pose, a lean is not read as a reach, lost landmarks hold then ease to rest,
//! limits hold.
// Native only: reads ../shared from disk.

use crate::support::recordings;
use crate::support::torso_user;

use glam::{Quat, Vec3};
use handrig::humanoid::bones::{Finger, HumanBone as B, Side};
use handrig::mediapipe::{
    pose_landmark as pl, CameraMapping, FrameInput, HandObservation, Handedness, WristObservation,
    HAND_LANDMARKS,
};
use handrig::torso::{chain_rotation, TorsoSource, LIMITS, TORSO_BONES};
use handrig::{Rig, RigOptions, Skeleton, SolveOutput, BONE_COUNT};
use torso_user::{deg, TorsoPose};

const AVATARS: [&str; 3] = [
    recordings::ROBOT,
    recordings::FIXTURE_VRM1,
    recordings::FIXTURE_VRM0,
];

/// Per-frame options with `torso` and `mirror`, and self-contact off: these tests measure
/// plain fingertip alignment (contact moves targets near the face and body; with a posed
/// torso it is tested in `tests/it/contact.rs`).
fn options(torso: TorsoSource, mirror: bool) -> RigOptions {
    let mut options = RigOptions {
        torso,
        mirror,
        ..RigOptions::per_frame()
    };
    options.contact.enabled = false;
    options
}

/// The two hands of frame `k`: the recorded right hand (labelled "Left", un-mirrored) and its
/// mirror image as the left hand (labelled "Right").
fn hands(video: &[HandObservation], k: usize) -> [HandObservation; 2] {
    let right = video[k % video.len()];
    let mut left = right;
    left.handedness = Handedness::Right;
    left.world = right.world.map(|p| Vec3::new(-p.x, p.y, p.z));
    left.image = None;
    let mut right = right;
    right.image = None;
    right.score = 0.95;
    left.score = 0.95;
    [right, left]
}

/// The frame of synthetic user `pose` at step `k`: its pose landmarks and both hands (turned
/// with the upper body, like the arms).
fn user_frame(pose: &TorsoPose, k: usize, video: &[HandObservation]) -> FrameInput {
    let u = torso_user::points(pose, &torso_user::arms(k));
    let turn = torso_user::camera_rotation(pose.upper());
    let mut hands = hands(video, k);
    for h in &mut hands {
        h.world = h.world.map(|p| turn * p);
    }
    let mut f = recordings::frame_of(&hands);
    f.pose = Some(torso_user::pose_landmarks(&u));
    f.time_ms = k as f64 * 1000.0 / 30.0;
    f
}

/// The avatar's upper-torso frame in a solved pose (the bone the arms hang from, times its
/// rest frame).
fn avatar_upper(rig: &Rig, out: &SolveOutput) -> Quat {
    out.world.rotation[rig.torso().top().index()] * rig.torso().rest_upper()
}

/// The truth as the avatar should show it: the user's rotation, reflected with `mirror`.
fn shown(q: Quat, mirror: bool) -> Quat {
    if mirror {
        torso_user::mirrored(q)
    } else {
        q
    }
}

/// Distance from the avatar's index distal (forward kinematics of `local`) on `side` to the
/// target DIP of the hand that drove it, computed here from the user: `anchor + s * turn *
/// (user DIP - user shoulder)`, with the anchor the avatar's upper-arm joint posed by the
/// torso alone (`local` with the arm and hand bones at rest) and `turn` from the user's
/// upper-torso frame `user_upper` to the avatar's `avatar_upper`.
#[allow(clippy::too_many_arguments)]
fn dip_error(
    skel: &Skeleton,
    local: &[Quat; BONE_COUNT],
    side: Side,
    frame: &FrameInput,
    hand_index: usize,
    camera: CameraMapping,
    scale: f32,
    turn: Quat,
) -> f32 {
    let mut torso_only = *local;
    let [_, upper, lower, hand] = side.arm();
    for b in [upper, lower, hand]
        .into_iter()
        .chain(Finger::ALL.iter().flat_map(|f| side.finger(*f)))
    {
        torso_only[b.index()] = Quat::IDENTITY;
    }
    let mut world = handrig::WorldPose::default();
    skel.forward(&torso_only, &mut world);
    let anchor = world.position[upper.index()];
    let pose = frame.pose.as_ref().unwrap();
    let (sh, wr) = match camera.pose_side_for(side) {
        Side::Left => (pl::LEFT_SHOULDER, pl::LEFT_WRIST),
        Side::Right => (pl::RIGHT_SHOULDER, pl::RIGHT_WRIST),
    };
    let h = &frame.hands[hand_index].world;
    let user = camera.to_avatar(pose.world[wr] - pose.world[sh]) + camera.to_avatar(h[7] - h[0]);
    let target = anchor + scale * (turn * user);
    skel.forward(local, &mut world);
    (world.position[side.finger(Finger::Index)[2].index()] - target).length()
}

/// Angle (degrees) between rotations, accurate near 0 (q and -q equal).
fn angle_deg(a: Quat, b: Quat) -> f32 {
    let d = a * b.conjugate();
    (2.0 * d.xyz().length().atan2(d.w.abs())).to_degrees()
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

/// The tracked torso (`torso: "pose"`, from the MediaPipe pose) is the user's (within 0.01
/// degrees; the acceptance is 3): the avatar's
/// upper torso and head take the user's world rotations and the hips its yaw, on every
/// avatar, mirrored or not; fingertip alignment of both hands lands on the target DIPs
/// computed from the known pose.
#[test]
fn tracked_torso_is_the_users_and_both_hands_align() {
    let video = recordings::hand_video_first();
    for path in AVATARS {
        let skel = recordings::vrm(path);
        for mirror in [false, true] {
            let mut errors = Vec::new();
            for pose in torso_user::poses() {
                let mut rig = Rig::new(skel.clone(), options(TorsoSource::Pose, mirror)).unwrap();
                let mut out = SolveOutput::default();
                let cam = rig.options().camera();
                for k in 0..8 {
                    let f = user_frame(&pose, k, &video);
                    rig.solve(&f, &mut out).unwrap();
                    out.turn_to_internal_frame(rig.skeleton().version());
                    let what = format!("{path} mirror {mirror} {} frame {k}", pose.name);
                    let upper = avatar_upper(&rig, &out);
                    let want = shown(pose.upper(), mirror);
                    assert!(
                        angle_deg(upper, want) < 0.01,
                        "{what}: upper torso {}",
                        angle_deg(upper, want)
                    );
                    let head = out.world.rotation[B::Head.index()];
                    let want = shown(pose.head_world(), mirror);
                    assert!(
                        angle_deg(head, want) < 0.01,
                        "{what}: head {}",
                        angle_deg(head, want)
                    );
                    let hips = out.local[B::Hips.index()];
                    let want = shown(pose.hips(), mirror);
                    assert!(
                        angle_deg(hips, want) < 0.01,
                        "{what}: hips {}",
                        angle_deg(hips, want)
                    );
                    for side in Side::BOTH {
                        let a = out.alignment[side.index()].expect("aligned");
                        assert!(a.reachable, "{what} {side:?}");
                        let index = out.hands[side.index()].unwrap().index;
                        let turn = upper * shown(pose.upper(), mirror).inverse();
                        let e = dip_error(
                            &skel,
                            &out.local,
                            side,
                            &f,
                            index,
                            cam,
                            rig.body().scale(),
                            turn,
                        );
                        errors.push(e);
                        assert!(e < 2e-3, "{what} {side:?}: {e} m");
                        assert!(
                            (e - a.error).abs() < 1e-4,
                            "{what}: the rig reports {} m",
                            a.error
                        );
                    }
                }
            }
            let m = median(errors);
            assert!(m < 5e-4, "{path} mirror {mirror}: median {m} m");
        }
    }
}

/// Body-tracker joints (`frame.body`, model frame) give the same torso as the pose.
#[test]
fn body_joints_give_the_same_torso() {
    for path in AVATARS {
        let skel = recordings::vrm(path);
        let version = skel.version();
        for pose in torso_user::poses() {
            let mut rig = Rig::new(skel.clone(), options(TorsoSource::Pose, false)).unwrap();
            let mut out = SolveOutput::default();
            let u = torso_user::points(&pose, &torso_user::arms(0));
            let mut body = torso_user::body_joints(&u, 0.95);
            // The model's own frame: VRM 0.x models face -Z.
            body.position = body.position.map(|p| version.position_to_internal(p));
            let f = FrameInput {
                body: Some(body),
                ..FrameInput::default()
            };
            rig.solve(&f, &mut out).unwrap();
            out.turn_to_internal_frame(rig.skeleton().version());
            let upper = avatar_upper(&rig, &out);
            let a = angle_deg(upper, pose.upper());
            assert!(a < 0.01, "{path} {}: {a}", pose.name);
            let head = out.world.rotation[B::Head.index()];
            assert!(
                angle_deg(head, pose.head_world()) < 0.01,
                "{path} {}",
                pose.name
            );
            // Output in the model's own frame, like every other bone.
            let q = version.rotation_to_internal(out.local[B::Hips.index()]);
            let want = version.rotation_to_internal(pose.hips());
            assert!(angle_deg(q, want) < 0.01, "{path} {}", pose.name);
        }
    }
}

/// The app's torso (`frame.torso`, default `torso: "frame"`): forward kinematics of the app's
/// torso plus handrig's arms and fingers puts the index distal on the target DIP, with
/// tracker wrists (the seed formula) and with pose input (the arm placed relative to the
/// torso); handrig does not report the torso bones.
#[test]
fn the_apps_torso_is_used_as_given() {
    let video = recordings::hand_video_first();
    for path in AVATARS {
        let skel = recordings::vrm(path);
        let version = skel.version();
        let mut tracker_errors = Vec::new();
        let mut pose_errors = Vec::new();
        for pose in torso_user::poses() {
            // The app turns its hips, bends its spine bone, turns its head bone.
            let mut app = [Quat::IDENTITY; BONE_COUNT];
            app[B::Hips.index()] = pose.hips();
            app[B::Spine.index()] = pose.spine;
            app[B::Head.index()] = pose.head;
            let mut given = [None; 8];
            for (slot, b) in TORSO_BONES.iter().enumerate() {
                if app[b.index()] != Quat::IDENTITY {
                    given[slot] = Some(version.rotation_to_internal(app[b.index()]));
                }
            }
            let mut world = handrig::WorldPose::default();
            skel.forward(&app, &mut world);
            let mut rig = Rig::new(skel.clone(), options(TorsoSource::Frame, false)).unwrap();
            for b in TORSO_BONES {
                // Shoulders: driven only for the arm option's turn on far reaches.
                let arm = b.side().is_some_and(|s| rig.arms().moves_shoulder(s));
                assert_eq!(rig.drives(b), arm, "{b}: the app drives it");
            }
            let mut out = SolveOutput::default();
            for k in 0..6 {
                // Tracker wrists in front of the posed shoulders (model frame).
                let mut f = recordings::frame_of(&hands(&video, k));
                f.torso = given;
                f.time_ms = k as f64 * 33.0;
                let upper_rot = world.rotation[rig.torso().top().index()];
                for side in Side::BOTH {
                    let s = if side == Side::Left { 1.0 } else { -1.0 };
                    let shoulder = world.position[side.arm()[1].index()];
                    let reach = Vec3::new(-0.12 * s, -0.15, 0.25 + 0.01 * k as f32);
                    f.wrists[side.index()] = Some(WristObservation {
                        position: version.position_to_internal(shoulder + upper_rot * reach),
                        rotation: None,
                    });
                }
                rig.solve(&f, &mut out).unwrap();
                out.turn_to_internal_frame(rig.skeleton().version());
                let mut shown = out.local;
                for b in TORSO_BONES {
                    shown[b.index()] = app[b.index()];
                }
                let mut posed = handrig::WorldPose::default();
                skel.forward(&shown, &mut posed);
                for side in Side::BOTH {
                    let a = out.alignment[side.index()].unwrap();
                    assert!(a.reachable);
                    let index = out.hands[side.index()].unwrap().index;
                    let h = &f.hands[index].world;
                    let cam = rig.options().camera();
                    let wrist =
                        version.position_to_internal(f.wrists[side.index()].unwrap().position);
                    let target = wrist + cam.to_avatar(h[7] - h[0]);
                    let tip = posed.position[side.finger(Finger::Index)[2].index()];
                    tracker_errors.push((tip - target).length());
                }
                // The flat output: torso bones flagged "not driven", identity.
                let mut buf = vec![0.0; handrig::flat::output::LEN];
                handrig::flat::write_output(&rig, &out, &mut buf);
                for b in TORSO_BONES.into_iter().filter(|b| !rig.drives(*b)) {
                    assert_eq!(
                        buf[handrig::flat::output::BONE_FLAGS + b.index()],
                        0.0,
                        "{b}"
                    );
                }

                // Pose input: the arm placed relative to the app's torso.
                let mut f = user_frame(&pose, k, &video);
                f.torso = given;
                rig.solve(&f, &mut out).unwrap();
                out.turn_to_internal_frame(rig.skeleton().version());
                let avatar_frame =
                    world.rotation[rig.torso().top().index()] * rig.torso().rest_upper();
                let turn = avatar_frame * pose.upper().inverse();
                let cam = rig.options().camera();
                for side in Side::BOTH {
                    let index = out.hands[side.index()].unwrap().index;
                    let mut local = out.local;
                    for b in TORSO_BONES {
                        local[b.index()] = app[b.index()];
                    }
                    let e = dip_error(
                        &skel,
                        &local,
                        side,
                        &f,
                        index,
                        cam,
                        rig.body().scale(),
                        turn,
                    );
                    pose_errors.push(e);
                    assert!(e < 2e-3, "{path} {} {side:?}: {e} m", pose.name);
                }
            }
        }
        let (m, max) = (
            median(tracker_errors.clone()),
            tracker_errors.iter().copied().fold(0.0, f32::max),
        );
        assert!(
            m < 5e-4 && max < 2e-3,
            "{path}: tracker wrists median {m} max {max}"
        );
        let m = median(pose_errors);
        assert!(m < 5e-4, "{path}: pose median {m}");
    }
}

/// A lean or a turn of the whole upper body, arms held still relative to it, is not read as a
/// reach: with the avatar's torso at rest (`"frame"` without `frame.torso`) the arm's local
/// rotations stay those of the upright user; with `"off"` (world axes, as before the torso)
/// they change.
#[test]
fn a_lean_is_not_read_as_a_reach() {
    let video = recordings::hand_video_first();
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let arm_rotations = |source: TorsoSource, pose: &TorsoPose| {
        let mut opts = options(source, false);
        opts.calibration.body_scale = Some(1.0);
        let mut rig = Rig::new(skel.clone(), opts).unwrap();
        let mut out = SolveOutput::default();
        rig.solve(&user_frame(pose, 3, &video), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let [_, upper, lower, hand] = Side::Right.arm();
        [upper, lower, hand].map(|b| out.local[b.index()])
    };
    let upright = arm_rotations(TorsoSource::Frame, &TorsoPose::REST);
    for pose in torso_user::poses()
        .into_iter()
        .filter(|p| p.head == Quat::IDENTITY)
    {
        let leaning = arm_rotations(TorsoSource::Frame, &pose);
        for (a, b) in upright.iter().zip(&leaning) {
            assert!(
                angle_deg(*a, *b) < 0.01,
                "{}: {}",
                pose.name,
                angle_deg(*a, *b)
            );
        }
        if pose.upper().angle_between(Quat::IDENTITY) > deg(10.0) {
            let off = arm_rotations(TorsoSource::Off, &pose);
            let moved = upright
                .iter()
                .zip(&off)
                .map(|(a, b)| angle_deg(*a, *b))
                .fold(0.0, f32::max);
            assert!(
                moved > 5.0,
                "{}: \"off\" reads it as a reach ({moved} deg)",
                pose.name
            );
        }
    }
}

/// Calibration of the body scale from a leaning, turned user equals the upright user's (arm
/// lengths are measured, not positions).
#[test]
fn body_scale_is_the_same_whatever_the_torso() {
    let video = recordings::hand_video_first();
    let skel = recordings::vrm(recordings::ROBOT);
    let scale = |pose: &TorsoPose| {
        let mut rig = Rig::new(skel.clone(), options(TorsoSource::Pose, false)).unwrap();
        let mut out = SolveOutput::default();
        for k in 0..30 {
            rig.solve(&user_frame(pose, k, &video), &mut out).unwrap();
            out.turn_to_internal_frame(rig.skeleton().version());
        }
        rig.body().scale()
    };
    let upright = scale(&TorsoPose::REST);
    for pose in torso_user::poses() {
        let s = scale(&pose);
        assert!(
            (s - upright).abs() < 1e-4 * upright,
            "{}: {s} vs {upright}",
            pose.name
        );
    }
}

/// A shrug (both shoulders 3 cm up, after a neutral calibration) raises both of the avatar's
/// upper-arm joints by the same proportion of its shoulder bone, within the elevation limit.
#[test]
fn a_shrug_raises_the_shoulders() {
    let video = recordings::hand_video_first();
    let skel = recordings::vrm(recordings::FIXTURE_VRM1);
    let mut opts = options(TorsoSource::Pose, false);
    opts.calibration.frames = 5;
    let mut rig = Rig::new(skel.clone(), opts).unwrap();
    let mut out = SolveOutput::default();
    for k in 0..5 {
        rig.solve(&user_frame(&TorsoPose::REST, k, &video), &mut out)
            .unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        for side in Side::BOTH {
            let q = out.local[side.arm()[0].index()];
            assert!(angle_deg(q, Quat::IDENTITY) < 1e-3, "calibrating: no shrug");
        }
    }
    let neutral = rig.torso().neutral_height().unwrap();
    assert!(
        (neutral - torso_user::SHOULDER_HEIGHT).abs() < 1e-4,
        "{neutral}"
    );
    let rest_y = |side: Side| skel.rest_world(side.arm()[1]).unwrap().y;
    for (shrug, lean) in [(0.03, 0.0), (0.03, 20.0), (-0.01, 0.0), (0.2, 0.0)] {
        let pose = TorsoPose {
            shrug,
            spine: Quat::from_rotation_x(deg(lean)),
            ..TorsoPose::REST
        };
        rig.solve(&user_frame(&pose, 6, &video), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let mut lifts = [0.0; 2];
        for side in Side::BOTH {
            let [shoulder, upper, ..] = side.arm();
            let angle = out.local[shoulder.index()].angle_between(Quat::IDENTITY);
            let lever = skel.rest_local(upper).length();
            let half = 0.5
                * (skel.rest_world(B::LeftUpperArm).unwrap()
                    - skel.rest_world(B::RightUpperArm).unwrap())
                .length();
            let want = (shrug / (torso_user::SHOULDER_HALF * lever / half))
                .clamp(-1.0, 1.0)
                .asin()
                .clamp(-LIMITS.shoulder_depression, LIMITS.shoulder_elevation);
            assert!(
                (angle - want.abs()).abs() < 1e-3,
                "shrug {shrug}: {angle} vs {want}"
            );
            lifts[side.index()] = if lean == 0.0 {
                out.world.position[upper.index()].y - rest_y(side)
            } else {
                0.0
            };
        }
        if lean == 0.0 {
            assert!(
                (lifts[0] - lifts[1]).abs() < 1e-5,
                "both sides alike: {lifts:?}"
            );
            assert!(lifts[0].signum() == shrug.signum(), "{shrug}: {lifts:?}");
        }
    }
}

/// Lost torso landmarks: the torso holds its last rotations, then eases to rest; the head,
/// with its own landmarks, keeps following; nothing is NaN. A returning torso blends in.
#[test]
fn lost_landmarks_hold_then_ease_to_rest() {
    let video = recordings::hand_video_first();
    let skel = recordings::vrm(recordings::ROBOT);
    let mut rig = Rig::new(
        skel.clone(),
        RigOptions {
            torso: TorsoSource::Pose,
            filter: handrig::filter::FilterOptions {
                enabled: false,
                ..Default::default()
            },
            ..RigOptions::default()
        },
    )
    .unwrap();
    let d = rig.options().dropout;
    let mut out = SolveOutput::default();
    let pose = torso_user::poses()[7];
    let mut f = user_frame(&pose, 0, &video);
    f.time_ms = 0.0;
    rig.solve(&f, &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    let tracked = out.local[B::Spine.index()];
    assert!(angle_deg(tracked, Quat::IDENTITY) > 5.0);
    // The shoulders vanish (visibility 0): spine and shoulders are no longer measured.
    let lost = |t: f64| {
        let mut f = user_frame(&pose, 0, &video);
        let p = f.pose.as_mut().unwrap();
        p.visibility[pl::LEFT_SHOULDER] = 0.0;
        p.visibility[pl::RIGHT_SHOULDER] = 0.1;
        f.time_ms = t;
        f
    };
    let mut t = 33.0;
    while t < f64::from(d.hold_ms) {
        rig.solve(&lost(t), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        assert_eq!(out.local[B::Spine.index()], tracked, "held at {t} ms");
        assert!(!out.solved[B::Spine.index()] && rig.drives(B::Spine));
        t += 33.0;
    }
    let mut last = 0.0;
    while t < f64::from(d.hold_ms + d.fade_out_ms) + 100.0 {
        rig.solve(&lost(t), &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        for q in out.local.iter().chain(out.world.rotation.iter()) {
            assert!(q.is_finite());
        }
        let a = angle_deg(out.local[B::Spine.index()], tracked);
        assert!(
            a + 1e-4 >= last,
            "easing away monotonically: {a} after {last}"
        );
        last = a;
        // The head keeps its world rotation (its landmarks are still there).
        let head = out.world.rotation[B::Head.index()];
        assert!(
            angle_deg(head, pose.head_world()) < 0.5,
            "head at {t}: {}",
            angle_deg(head, pose.head_world())
        );
        t += 33.0;
    }
    for b in [B::Spine, B::Chest, B::UpperChest, B::LeftShoulder] {
        assert!(
            angle_deg(out.local[b.index()], Quat::IDENTITY) < 1e-3,
            "{b} at rest"
        );
    }
    // Back: blends in from rest, then shows the tracked torso.
    let mut f = user_frame(&pose, 0, &video);
    f.time_ms = t;
    rig.solve(&f, &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    assert!(angle_deg(out.local[B::Spine.index()], Quat::IDENTITY) < 1e-3);
    f.time_ms = t + f64::from(d.fade_in_ms) + 1.0;
    rig.solve(&f, &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    assert!(angle_deg(out.local[B::Spine.index()], tracked) < 1e-3);
}

/// Poses beyond the anatomical ranges are clamped to them; odd input never gives NaN.
#[test]
fn limits_hold_and_odd_input_is_finite() {
    let video = recordings::hand_video_first();
    for path in AVATARS {
        let skel = recordings::vrm(path);
        let mut rig = Rig::new(skel.clone(), options(TorsoSource::Pose, false)).unwrap();
        let mut out = SolveOutput::default();
        let extreme = [
            Quat::from_rotation_x(deg(120.0)),
            Quat::from_rotation_x(deg(-60.0)),
            Quat::from_rotation_z(deg(70.0)),
            Quat::from_rotation_y(deg(100.0)),
        ];
        for spine in extreme {
            let pose = TorsoPose {
                name: "extreme",
                spine,
                head: Quat::from_rotation_y(deg(95.0)) * Quat::from_rotation_x(deg(70.0)),
                ..TorsoPose::REST
            };
            rig.solve(&user_frame(&pose, 1, &video), &mut out).unwrap();
            out.turn_to_internal_frame(rig.skeleton().version());
            let hips = out.local[B::Hips.index()];
            let rel = (hips.inverse() * out.world.rotation[rig.torso().top().index()]).normalize();
            let (swing, twist) = handrig::math::swing_twist(rel, Vec3::Y);
            let s = swing.to_scaled_axis();
            let t = handrig::math::twist_angle(twist, Vec3::Y);
            let eps = 1e-3;
            assert!(
                s.x <= LIMITS.spine_flexion + eps && s.x >= -LIMITS.spine_extension - eps,
                "{path}: {s}"
            );
            assert!(
                s.z.abs() <= LIMITS.spine_lateral + eps && t.abs() <= LIMITS.spine_twist + eps,
                "{path}: {s} {t}"
            );
            let parent =
                out.world.rotation[skel.parent(B::Neck).unwrap_or(rig.torso().top()).index()];
            let head = (parent.inverse() * out.world.rotation[B::Head.index()]).normalize();
            let (swing, twist) = handrig::math::swing_twist(head, Vec3::Y);
            let s = swing.to_scaled_axis();
            let t = handrig::math::twist_angle(twist, Vec3::Y);
            assert!(
                s.x.abs() <= LIMITS.head_flexion + eps && s.z.abs() <= LIMITS.head_lateral + eps,
                "{path}: head {s}"
            );
            assert!(t.abs() <= LIMITS.head_twist + eps, "{path}: head twist {t}");
        }
        // Collapsed and far-away landmarks: finite output, torso at rest or held.
        let mut f = user_frame(&TorsoPose::REST, 2, &video);
        let p = f.pose.as_mut().unwrap();
        p.world = [Vec3::new(0.1, -0.5, 0.0); 33];
        rig.solve(&f, &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        let mut f = user_frame(&TorsoPose::REST, 3, &video);
        f.pose.as_mut().unwrap().world[11] = Vec3::splat(1e30);
        let e = rig.solve(&f, &mut out).unwrap_err().to_string();
        assert!(e.starts_with("frame.pose.worldLandmarks[11]:"), "{e}");
        // Within the coordinate limit but beyond a body's reach: pixels for meters (issue 30).
        f.pose.as_mut().unwrap().world[11] = Vec3::splat(handrig::COORDINATE_LIMIT);
        let e = rig.solve(&f, &mut out).unwrap_err().to_string();
        assert!(e.contains("more than 4 m from the hips"), "{e}");
        // Far, but within reach: finite output.
        f.pose.as_mut().unwrap().world[11] = Vec3::splat(2.3);
        rig.solve(&f, &mut out).unwrap();
        out.turn_to_internal_frame(rig.skeleton().version());
        for q in out.local.iter().chain(out.world.rotation.iter()) {
            assert!(q.is_finite(), "{path}");
        }
        for p in &out.world.position {
            assert!(p.is_finite(), "{path}");
        }
        let _ = chain_rotation(&skel, &out.local, B::Head);
    }
}

/// Bad torso and body input is an error naming the field, and the rig keeps working.
#[test]
fn bad_torso_input_is_an_error_naming_the_field() {
    let skel = recordings::vrm(recordings::ROBOT);
    let mut rig = Rig::new(skel, options(TorsoSource::Pose, false)).unwrap();
    let mut out = SolveOutput::default();
    let mut f = FrameInput::default();
    f.torso[4] = Some(Quat::from_xyzw(0.0, 0.0, 0.0, 2.0));
    let e = rig.solve(&f, &mut out).unwrap_err();
    assert_eq!(
        e.to_string(),
        "frame.torso.neck: must be a unit quaternion [x, y, z, w]"
    );
    let mut f = FrameInput::default();
    let mut body = handrig::torso::BodyObservation::default();
    body.position[9] = Vec3::new(f32::NAN, 0.0, 0.0);
    f.body = Some(body);
    let e = rig.solve(&f, &mut out).unwrap_err();
    assert_eq!(
        e.to_string(),
        "frame.body.rightEar: must be three finite numbers"
    );
    body.position[9] = Vec3::ZERO;
    body.confidence[0] = -0.5;
    f.body = Some(body);
    let e = rig.solve(&f, &mut out).unwrap_err();
    assert_eq!(
        e.to_string(),
        "frame.body.hips.confidence: must be a number in 0..1"
    );
    rig.solve(&FrameInput::default(), &mut out).unwrap();
    out.turn_to_internal_frame(rig.skeleton().version());
    let _ = HAND_LANDMARKS;
}
