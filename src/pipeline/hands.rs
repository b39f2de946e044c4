//! Stages 4 and 5, per side: **hand** (the hand's landmarks mapped to the avatar frame and
//! filtered, then hand orientation and finger rotations, [`crate::hand`]) and **wrist source**
//! (the wrist from `wrists`, filtered, or from the pose mapped relative to the torso,
//! [`crate::body`], with the elbow as pole).

use glam::{Quat, Vec3};

use crate::bones::Side;
use crate::hand::flip::{chirality, image_agreement, image_hand, MIRRORED};
use crate::hand::HandStatus;
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

/// What the checks of [`Rig::check_hand`] made of a side's hand this frame (see
/// [`crate::hand::flip`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HandCheck {
    /// The world landmarks pass the checks (or there was nothing to check).
    #[default]
    Good,
    /// The world landmarks were mirrored (fingers bending backwards) or their knuckle line
    /// crossed the image's; the image landmarks, made metric, were solved instead.
    FromImage,
    /// Mirrored with no usable image landmarks (absent, or mirrored too): the side's last
    /// solved hand was held.
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
        (HandStatus::Solved, HandCheck::FromImage) => 0.6,
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
}

impl Rig {
    /// The hand checks (see [`crate::hand::flip`]) on this frame's mapped landmarks
    /// (`scratch.landmarks`, replaced by the image's hand when that is the better witness):
    /// a world hand that is mirrored ([`chirality`] below [`MIRRORED`]) or whose knuckle line
    /// points against the image's ([`image_agreement`] negative) is replaced by the image
    /// landmarks when those have the right chirality, else held; at most [`MAX_HELD_FRAMES`]
    /// in a row are held, then the tracked hand is taken as it is (re-acquired).
    fn check_hand(&mut self, side: Side, h: &HandObservation, turn: Quat) -> HandCheck {
        let camera = self.options.camera();
        let state = &mut self.flips[side.index()];
        let mut check = HandCheck::Good;
        let mirrored = chirality(side, &self.scratch.landmarks).is_some_and(|c| c < MIRRORED);
        let crossed = h
            .image
            .and_then(|im| image_agreement(&h.world, &im))
            .is_some_and(|a| a < 0.0);
        if mirrored || crossed {
            check = HandCheck::Mirrored;
            let mut raw = [Vec3::ZERO; HAND_LANDMARKS];
            if let Some(im) = &h.image {
                if image_hand(&h.world, im, &mut raw) {
                    let mut mapped = [Vec3::ZERO; HAND_LANDMARKS];
                    for (dst, src) in mapped.iter_mut().zip(raw.iter()) {
                        *dst = turn * camera.to_avatar(*src);
                    }
                    if chirality(side, &mapped).is_some_and(|c| c >= MIRRORED) {
                        self.scratch.landmarks = mapped;
                        check = HandCheck::FromImage;
                    }
                }
            }
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
        let verdict = self.check_hand(side, h, turn);
        let hand_rotation = if verdict.holds() {
            self.hands.hold(&self.skeleton, side, &mut out.local)
        } else {
            if self.options.filter.enabled {
                let o = self.options.filter.one_euro();
                self.hand_filters[side.index()].apply(
                    &mut self.scratch.landmarks,
                    frame.time_ms,
                    dt,
                    &o,
                );
            }
            self.hands.solve(
                &self.skeleton,
                side,
                &self.scratch.landmarks,
                &mut out.local,
            )
        };
        let status = self.hands.report(side).status;
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
            for b in crate::bones::Finger::ALL
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
    /// elbow as pole.
    pub(super) fn wrist_source(
        &mut self,
        side: Side,
        frame: &FrameInput,
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
        let pose = self.scratch.pose.as_ref()?;
        let anchor = self.scratch.anchors[side.index()]?;
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
