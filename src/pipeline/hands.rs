//! Stages 4 and 5, per side: **hand** (the hand's landmarks mapped to the avatar frame and
//! filtered, then hand orientation and finger rotations, [`crate::hand`]) and **wrist source**
//! (the wrist from `wrists`, filtered, or from the pose mapped relative to the torso,
//! [`crate::body`], with the elbow as pole).

use glam::{Quat, Vec3};

use crate::bones::Side;
use crate::mediapipe::FrameInput;

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

impl Rig {
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
        if self.options.filter.enabled {
            let o = self.options.filter.one_euro();
            self.hand_filters[side.index()].apply(
                &mut self.scratch.landmarks,
                frame.time_ms,
                dt,
                &o,
            );
        }
        let hand_rotation = self.hands.solve(
            &self.skeleton,
            side,
            &self.scratch.landmarks,
            &mut out.local,
        );
        out.hands[side.index()] = Some(TrackedHand {
            status: self.hands.report(side).status,
            score: h.score,
            index: pick.index,
            reassigned: pick.reassigned,
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
