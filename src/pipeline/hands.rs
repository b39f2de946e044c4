//! Stages 4 and 5, per side: **hand** (the hand's landmarks mapped to the avatar frame and
//! filtered, then hand orientation and finger rotations, [`crate::hand`]) and **wrist source**
//! (the wrist from `wrists`, filtered, or from the pose mapped relative to the torso,
//! [`crate::body`], with the elbow as pole).

use glam::{Quat, Vec3};

use crate::hand::flip::{chirality, image_agreement, MIRRORED};
use crate::hand::{HandStatus, HandStrategy};
use crate::humanoid::bones::Side;
use crate::input::hand_wrist::{elbow_hint, wrist_offset};
use crate::mediapipe::{FrameInput, HandObservation, HAND_LANDMARKS};

use super::select::Pick;
use super::{Rig, SolveOutput, TrackedHand};

/// Where an arm reaches this frame, from [`Rig::wrist_source`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct WristSource {
    /// The wrist (internal frame).
    pub(super) position: Vec3,
    /// The hand's world rotation from the tracker, if given.
    pub(super) rotation: Option<Quat>,
    /// Scale from the user's hand to the avatar's (body scale for pose input, 1 for trackers).
    pub(super) scale: f32,
    /// Where the elbow should point (pose elbow), if known.
    pub(super) pole: Option<Vec3>,
}

/// Frames a mirrored hand is held before the rig takes the tracked hand again (re-acquires):
/// a flip of MediaPipe's lasts one to three frames on the ASL clips; a hand mirrored for
/// longer is more likely a wrong label or a real pose the checks misread.
pub(super) const MAX_HELD_FRAMES: u8 = 3;

/// Raw thumb-index tip distance (m) at and below which [`keep_pinch`] restores the raw
/// relation of the two tips fully: the pinch frames of the evals (`examples/eval_fingers.rs`).
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

/// What the rig's hand checks (pipeline stage 4) made of a side's hand this frame (see
/// [`crate::hand::flip`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HandCheck {
    /// The world landmarks pass the checks (or there was nothing to check).
    #[default]
    Good,
    /// The world landmarks were mirrored (fingers bending backwards) or their knuckle line
    /// crossed the image's: the side's last solved hand was held (or, after
    /// `MAX_HELD_FRAMES` (3) held frames, the tracked hand taken as it is).
    Mirrored,
}

impl HandCheck {
    /// Whether the rig holds the side's last solved hand this frame.
    #[must_use]
    pub fn holds(self) -> bool {
        self == HandCheck::Mirrored
    }
}

/// [`TrackedHand::confidence`]: the handedness score times how the hand was solved.
fn confidence(check: HandCheck, status: HandStatus, score: f32) -> f32 {
    let how = match (status, check) {
        (HandStatus::Solved, HandCheck::Good) => 1.0,
        (HandStatus::Held, _) | (HandStatus::Solved, HandCheck::Mirrored) => 0.3,
        (HandStatus::Skipped | HandStatus::NotSolved, _) => 0.0,
    };
    how * score.clamp(0.0, 1.0)
}

/// Per side, what the hand checks carry between frames.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct FlipState {
    /// Consecutive frames held.
    pub(super) held: u8,
    /// The landmarks of the last hand solved on this side (avatar frame, filtered): what a
    /// held hand's later stages (alignment, contact) read instead of the rejected ones.
    pub(super) last: Option<[Vec3; HAND_LANDMARKS]>,
}

impl Rig {
    /// The hand checks (see [`crate::hand::flip`]) on this frame's mapped landmarks
    /// (`scratch.landmarks`): a world hand that is mirrored ([`chirality`] below
    /// [`MIRRORED`]) or whose knuckle line points against the image's ([`image_agreement`]
    /// negative) is held; at most [`MAX_HELD_FRAMES`] in a row are held, then the tracked hand
    /// is taken as it is (re-acquired).
    fn check_hand(&mut self, side: Side, h: &HandObservation) -> HandCheck {
        let state = &mut self.flips[side.index()];
        let mut check = HandCheck::Good;
        let mirrored = chirality(side, &self.scratch.landmarks).is_some_and(|c| c < MIRRORED);
        let crossed = h
            .image
            .and_then(|im| image_agreement(&h.world, &im))
            .is_some_and(|a| a < 0.0);
        if mirrored || crossed {
            check = HandCheck::Mirrored;
        }
        if check.holds() && state.held >= MAX_HELD_FRAMES {
            // Re-acquire: the tracked hand as it is.
            check = HandCheck::Good;
        }
        state.held = if check.holds() { state.held + 1 } else { 0 };
        check
    }

    /// Stage 4: the side's hand (landmarks to the avatar frame, filtered, solved). Returns the
    /// hand's world rotation when solved or held.
    pub(super) fn solve_hand(
        &mut self,
        side: Side,
        frame: &FrameInput,
        pick: Option<Pick>,
        dt: Option<f32>,
        out: &mut SolveOutput,
    ) -> Option<Quat> {
        self.scratch.placed[side.index()] = false;
        let pick = pick?;
        let h = &frame.hands()[pick.index];
        let camera = self.options.camera();
        // A hand whose arm the pose places (no tracker wrist) turns with the arm: the user's
        // hand keeps its pose relative to the torso, like the arm (see `torso_stage`).
        let turn = match (
            frame.wrists[side.index()],
            &self.scratch.pose,
            self.scratch.turn,
        ) {
            (None, Some(_), Some(turn)) => turn,
            _ => Quat::IDENTITY,
        };
        for (dst, src) in self.scratch.landmarks.iter_mut().zip(h.world.iter()) {
            *dst = turn * camera.to_avatar(*src);
        }
        let verdict = self.check_hand(side, h);
        let hand_rotation = if verdict.holds() {
            // The rejected landmarks would place the fingertip (alignment, contact) where the
            // mirrored hand has it: the held hand is placed by its own, the last solved.
            if let Some(last) = self.flips[side.index()].last {
                self.scratch.landmarks = last;
                self.scratch.placed[side.index()] = true;
            }
            self.hands.hold(&self.skeleton, side, &mut out.local)
        } else {
            if self.options.filter.enabled {
                let o = self.options.filter.one_euro();
                let raw = self.scratch.landmarks;
                self.hand_filters[side.index()].apply(
                    &mut self.scratch.landmarks,
                    frame.time_ms,
                    dt,
                    &o,
                );
                if self.hands.strategy() == HandStrategy::Retarget {
                    keep_pinch(&raw, &mut self.scratch.landmarks);
                }
            }
            self.hands.solve(
                &self.skeleton,
                side,
                &self.scratch.landmarks,
                &mut out.local,
            )
        };
        let status = self.hands.report(side).status;
        // (A hand held above always has `last`: it was set by the solve the hand solver holds.)
        if status == HandStatus::Solved {
            self.flips[side.index()].last = Some(self.scratch.landmarks);
            self.scratch.placed[side.index()] = true;
        }
        out.hands[side.index()] = Some(TrackedHand {
            status,
            confidence: confidence(verdict, status, h.score),
            score: h.score,
            index: pick.index,
            reassigned: pick.reassigned,
            resolved: pick.resolved,
            check: verdict,
        });
        if hand_rotation.is_some() {
            for b in crate::humanoid::bones::Finger::ALL
                .iter()
                .flat_map(|f| side.finger(*f))
                .chain([side.hand()])
            {
                out.solved[b.index()] = self.skeleton.has(b);
            }
        }
        hand_rotation
    }

    /// Stage 5: where the side's wrist is this frame: a tracker wrist (filtered) or the pose
    /// wrist mapped onto the avatar relative to the torso (the stage 3 anchor), with the pose
    /// elbow as pole; with no pose, the hand's wrist from its image (`options.handsOnly`).
    pub(super) fn wrist_source(
        &mut self,
        side: Side,
        frame: &FrameInput,
        pick: Option<Pick>,
        dt: Option<f32>,
    ) -> Option<WristSource> {
        let version = self.skeleton.version();
        if let Some(w) = frame.wrists[side.index()] {
            let mut position = [version.position_to_internal(w.position)];
            let mut rotation = w.rotation.map(|q| version.rotation_to_internal(q));
            if self.options.filter.enabled {
                let o = self.options.filter.one_euro();
                let f = &mut self.wrist_filters[side.index()];
                f.position.apply(&mut position, frame.time_ms, dt, &o);
                rotation = rotation.map(|q| f.rotation.filter(q, dt.unwrap_or(0.0), &o));
            }
            return Some(WristSource {
                position: position[0],
                rotation,
                scale: 1.0,
                pole: None,
            });
        }
        let anchor = self.scratch.anchors[side.index()]?;
        let Some(pose) = self.scratch.pose.as_ref() else {
            // No pose: from the hand's image position and size (`crate::input::hand_wrist`).
            let (o, h) = (&self.options, frame.hands().get(pick?.index)?);
            let mut p = [wrist_offset(
                h,
                side,
                o.camera(),
                &o.hands_only,
                frame.image_aspect,
            )?];
            if o.filter.enabled {
                let f = &mut self.wrist_filters[side.index()].position;
                f.apply(&mut p, frame.time_ms, dt, &o.filter.one_euro());
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
        let mapped = self
            .body
            .map_arm_from(side, pose, self.options.camera(), anchor)?;
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
