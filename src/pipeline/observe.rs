//! The **observe** stage: this frame's tracked inputs mapped from MediaPipe's camera axes (or
//! the model's frame) into the avatar's, checked, and One Euro filtered ([`crate::filter`]).
//! It runs at two points of a frame: the pose and the body-tracker joints before the torso
//! stage (which measures the user's torso on them), the hands and wrists after it (a hand
//! whose arm the pose places is observed turned with the torso, and the pose wrist is placed
//! relative to the posed torso). It also feeds body-scale calibration ([`crate::body`]).

use glam::{Quat, Vec3};

use crate::body::BodyMapper;
use crate::body::CalibrationOptions;
use crate::filter::{OneEuroQuat, PointFilters};
use crate::hand::flip::{chirality, image_agreement, MIRRORED};
use crate::hand::HandStrategy;
use crate::humanoid::bones::Side;
use crate::humanoid::skeleton::Skeleton;
use crate::input::hand_wrist::{elbow_hint, wrist_offset};
use crate::input::mediapipe::{pose_landmark, HAND_LANDMARKS, POSE_LANDMARKS};
use crate::torso::{TorsoSource, BODY_JOINT_COUNT};

use super::frame::{Context, Frame, WristSource};
use super::output::HandCheck;

/// Frames a mirrored hand is held before the rig takes the tracked hand again (re-acquires):
/// a flip of MediaPipe's lasts one to three frames on the ASL clips; a hand mirrored for
/// longer is more likely a wrong label or a real pose the checks misread.
pub(super) const MAX_HELD_FRAMES: u8 = 3;

/// Raw thumb-index tip distance (m) at and below which [`keep_pinch`] restores the raw
/// relation of the two tips fully: the pinch frames of the evals (`eval/rust/eval_fingers.rs`).
const PINCH_FULL: f32 = 0.02;
/// Raw thumb-index tip distance (m) from which the filtered tips are left alone: where the
/// retargeting's pinch feature fades in (4 cm of scaled distance, `src/hand/retarget.rs`).
const PINCH_NONE: f32 = 0.04;
/// MediaPipe's thumb and index fingertip landmarks.
const THUMB_TIP: usize = 4;
const INDEX_TIP: usize = 8;

/// A pinch survives the One Euro filter (`handStrategy: "retarget"`). The filter smooths every
/// landmark on its own, so a pinch that closes for one to three frames (most do on the hand
/// video: the tips 40-50 mm apart, 15-19 mm for a frame, apart again) reaches the solver
/// half-closed, and the avatar's tips stay 8-28 mm further apart than the user's, scaled
/// (`cargo run --release --example eval_fingers`). Where the raw tips are close, the filtered
/// thumb and index tips are moved apart or together symmetrically so that their difference is
/// the raw one's: fully at [`PINCH_FULL`] and below, blending out (smoothstep) to
/// [`PINCH_NONE`]. Everything else stays filtered; far from a pinch nothing changes.
fn keep_pinch(raw: &[Vec3; HAND_LANDMARKS], filtered: &mut [Vec3; HAND_LANDMARKS]) {
    let raw_gap = raw[THUMB_TIP] - raw[INDEX_TIP];
    let d = raw_gap.length();
    if !d.is_finite() || d >= PINCH_NONE {
        return;
    }
    let t = ((PINCH_NONE - d) / (PINCH_NONE - PINCH_FULL)).clamp(0.0, 1.0);
    let w = t * t * (3.0 - 2.0 * t);
    let half = 0.5 * w * (raw_gap - (filtered[THUMB_TIP] - filtered[INDEX_TIP]));
    filtered[THUMB_TIP] += half;
    filtered[INDEX_TIP] -= half;
}

/// Filters of one side's tracker wrist (position and rotation).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct WristFilter {
    position: PointFilters<1>,
    rotation: OneEuroQuat,
}

/// The observe stage: every landmark filter, the hand checks' count of held frames, and
/// body-scale calibration.
#[derive(Clone, Debug)]
pub(super) struct Observe {
    body: BodyMapper,
    pose_filters: PointFilters<POSE_LANDMARKS>,
    body_filters: PointFilters<BODY_JOINT_COUNT>,
    hand_filters: [PointFilters<HAND_LANDMARKS>; 2],
    wrist_filters: [WristFilter; 2],
    /// Consecutive frames each side's hand was held by the checks.
    held: [u8; 2],
}

impl Observe {
    pub(super) fn new(skeleton: &Skeleton, calibration: &CalibrationOptions) -> Self {
        Observe {
            body: BodyMapper::new(skeleton, calibration),
            pose_filters: PointFilters::default(),
            body_filters: PointFilters::default(),
            hand_filters: [PointFilters::default(); 2],
            wrist_filters: [WristFilter::default(); 2],
            held: [0; 2],
        }
    }

    /// Body-scale calibration state.
    pub(super) fn body(&self) -> &BodyMapper {
        &self.body
    }

    /// Restarts body-scale calibration.
    pub(super) fn reset_calibration(&mut self) {
        self.body.reset();
    }

    /// Forgets the filters' and the checks' history (not calibration).
    pub(super) fn restart(&mut self) {
        self.pose_filters.reset();
        self.body_filters.reset();
        self.hand_filters = [PointFilters::default(); 2];
        self.wrist_filters = [WristFilter::default(); 2];
        self.held = [0; 2];
    }

    /// Before the torso: this frame's pose, filtered, observed for body-scale calibration
    /// (`f.pose`), and the body tracker's joints, filtered when the torso follows them
    /// (`f.body`).
    pub(super) fn body_inputs(&mut self, cx: &Context, f: &mut Frame) {
        let filter = cx
            .options
            .filter
            .enabled
            .then(|| cx.options.filter.one_euro());
        f.pose = cx.input.pose;
        if let Some(pose) = f.pose.as_mut() {
            if let Some(o) = &filter {
                // Only the landmarks the rig reads: the pose's hands are not used, nor its
                // legs with `legs.enabled` off.
                let read: &[usize] = if cx.options.legs.enabled {
                    &pose_landmark::READ_WITH_LEGS
                } else {
                    &pose_landmark::READ
                };
                self.pose_filters
                    .apply_to(&mut pose.world, read, cx.now_ms, cx.dt, o);
            }
            self.body.observe(pose);
        }
        f.body = cx.input.body;
        if let (Some(body), Some(o), TorsoSource::Pose) =
            (f.body.as_mut(), &filter, cx.options.torso)
        {
            self.body_filters
                .apply(&mut body.position, cx.now_ms, cx.dt, o);
        }
    }

    /// After the torso, per side: the picked hand's world landmarks mapped to the avatar
    /// frame (turned with the torso when the pose places its arm) into `f.landmarks`, checked
    /// (`f.check`: see [`Observe::check`]), and filtered unless the check holds the hand.
    pub(super) fn hand(&mut self, cx: &Context, side: Side, f: &mut Frame) {
        let s = side.index();
        let Some(pick) = f.picks[s] else { return };
        let h = &cx.input.hands()[pick.index];
        // A hand whose arm the pose places (no tracker wrist) turns with the arm: the user's
        // hand keeps its pose relative to the torso, like the arm (see the torso stage).
        let turn = match (cx.input.wrists[s], &f.pose, f.turn) {
            (None, Some(_), Some(turn)) => turn,
            _ => Quat::IDENTITY,
        };
        let landmarks = &mut f.landmarks[s];
        for (dst, src) in landmarks.iter_mut().zip(h.world.iter()) {
            *dst = turn * cx.camera.to_avatar(*src);
        }
        let mirrored = chirality(side, landmarks).is_some_and(|c| c < MIRRORED);
        let crossed = h
            .image
            .and_then(|im| image_agreement(&h.world, &im))
            .is_some_and(|a| a < 0.0);
        f.check[s] = self.check(side, mirrored || crossed);
        if !f.check[s].holds() && cx.options.filter.enabled {
            let o = cx.options.filter.one_euro();
            let raw = *landmarks;
            self.hand_filters[s].apply(landmarks, cx.now_ms, cx.dt, &o);
            if cx.options.hand_strategy == HandStrategy::Retarget {
                keep_pinch(&raw, landmarks);
            }
        }
    }

    /// The hand checks (see [`crate::hand::flip`]): a world hand that is mirrored
    /// ([`chirality`] below [`MIRRORED`]) or whose knuckle line points against the image's
    /// ([`image_agreement`] negative) is held; at most [`MAX_HELD_FRAMES`] in a row are held,
    /// then the tracked hand is taken as it is (re-acquired).
    fn check(&mut self, side: Side, suspect: bool) -> HandCheck {
        let held = &mut self.held[side.index()];
        let mut check = if suspect {
            HandCheck::Mirrored
        } else {
            HandCheck::Good
        };
        if check.holds() && *held >= MAX_HELD_FRAMES {
            // Re-acquire: the tracked hand as it is.
            check = HandCheck::Good;
        }
        *held = if check.holds() { *held + 1 } else { 0 };
        check
    }

    /// After the torso, per side: where the wrist is this frame (`f.sources`): a tracker wrist
    /// (filtered) or the pose wrist mapped onto the avatar relative to the torso (the torso
    /// stage's anchor), with the pose elbow as pole; with no pose, the picked hand's wrist from
    /// its image position and size (`options.handsOnly`, [`crate::input::hand_wrist`]).
    pub(super) fn wrist(&mut self, cx: &Context, side: Side, f: &mut Frame) {
        f.sources[side.index()] = self.wrist_source(cx, side, f);
    }

    fn wrist_source(&mut self, cx: &Context, side: Side, f: &Frame) -> Option<WristSource> {
        let version = cx.skeleton.version();
        if let Some(w) = cx.input.wrists[side.index()] {
            let mut position = [version.position_to_internal(w.position)];
            let mut rotation = w.rotation.map(|q| version.rotation_to_internal(q));
            if cx.options.filter.enabled {
                let o = cx.options.filter.one_euro();
                let filters = &mut self.wrist_filters[side.index()];
                filters.position.apply(&mut position, cx.now_ms, cx.dt, &o);
                rotation = rotation.map(|q| filters.rotation.filter(q, cx.dt.unwrap_or(0.0), &o));
            }
            return Some(WristSource {
                position: position[0],
                rotation,
                scale: 1.0,
                pole: None,
            });
        }
        let anchor = f.anchors[side.index()]?;
        let Some(pose) = f.pose.as_ref() else {
            // No pose: from the hand's image position and size.
            let (o, input) = (cx.options, cx.input);
            let h = input.hands().get(f.picks[side.index()]?.index)?;
            let mut p = [wrist_offset(
                h,
                side,
                cx.camera,
                &o.hands_only,
                input.image_aspect,
            )?];
            if o.filter.enabled {
                let filter = &mut self.wrist_filters[side.index()].position;
                filter.apply(&mut p, cx.now_ms, cx.dt, &o.filter.one_euro());
            }
            let scale = self.body.scale();
            let at = |p: Vec3| anchor.shoulder + scale * (anchor.rotation * p);
            return Some(WristSource {
                position: at(p[0]),
                rotation: None,
                scale,
                pole: Some(at(elbow_hint(side))),
            });
        };
        let mapped = self.body.map_arm_from(side, pose, cx.camera, anchor)?;
        Some(WristSource {
            position: mapped.wrist,
            rotation: None,
            scale: self.body.scale(),
            pole: mapped.elbow,
        })
    }
}

#[cfg(test)]
mod pinch_tests {
    use super::*;

    fn hand(thumb: Vec3, index: Vec3) -> [Vec3; HAND_LANDMARKS] {
        let mut p = core::array::from_fn(|i| Vec3::new(i as f32 * 0.01, 0.02, -0.01));
        p[THUMB_TIP] = thumb;
        p[INDEX_TIP] = index;
        p
    }

    #[test]
    fn a_raw_pinch_gap_is_restored_and_far_tips_are_left_alone() {
        // Raw tips 1 cm apart; the filter left them 4 cm apart: the gap becomes the raw one,
        // about the filtered midpoint; nothing else moves.
        let raw = hand(Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.01, 0.0, 0.0));
        let mut f = hand(Vec3::new(-0.01, 0.001, 0.0), Vec3::new(0.03, 0.001, 0.0));
        let before = f;
        keep_pinch(&raw, &mut f);
        assert!((f[THUMB_TIP] - f[INDEX_TIP] - (raw[THUMB_TIP] - raw[INDEX_TIP])).length() < 1e-6);
        let mid = |p: &[Vec3; HAND_LANDMARKS]| 0.5 * (p[THUMB_TIP] + p[INDEX_TIP]);
        assert!((mid(&f) - mid(&before)).length() < 1e-6);
        for i in (0..HAND_LANDMARKS).filter(|i| *i != THUMB_TIP && *i != INDEX_TIP) {
            assert_eq!(f[i], before[i]);
        }
        // Halfway through the blend (3 cm raw gap): half the correction.
        let raw = hand(Vec3::ZERO, Vec3::new(0.03, 0.0, 0.0));
        let mut f = hand(Vec3::ZERO, Vec3::new(0.05, 0.0, 0.0));
        keep_pinch(&raw, &mut f);
        assert!(((f[INDEX_TIP] - f[THUMB_TIP]).x - 0.04).abs() < 1e-6);
        // Raw tips 4 cm or more apart (or not finite): untouched.
        for raw in [
            hand(Vec3::ZERO, Vec3::new(0.04, 0.0, 0.0)),
            hand(Vec3::NAN, Vec3::ZERO),
        ] {
            let mut f = hand(Vec3::ZERO, Vec3::new(0.09, 0.0, 0.0));
            let before = f;
            keep_pinch(&raw, &mut f);
            assert_eq!(f, before);
        }
    }
}
