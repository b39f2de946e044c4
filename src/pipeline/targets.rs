//! Stage 6, **targets**: per side the wrist IK target by fingertip alignment
//! ([`crate::align`]) from forward kinematics of *this* frame's hand, then for both sides
//! together moved for self-contact ([`crate::contact`]: a finger on the face lands on the
//! avatar's face where the posed torso put it, touching hands stay touching, hands stay out of
//! the body); both sides' targets exist before any IK.
//!
//! A hand lost while the wrist source still places the arm ([`LostHand`]) leaves the arm what
//! it had: the aligned target's offset from the wrist source, and the hand's world rotation as
//! shown, which keeps the forearm's share of the twist. Both are held and eased out with the
//! dropout timings (`options.dropout`), as the lost hand's own rotation is (the easing stage
//! holds the hand bone, then eases it to rest). Its contact points as last seen keep the held
//! hand's palm and fingertips out of the body (`Plan::Reach::held`). So a hand MediaPipe drops
//! for a frame neither turns the forearm by its whole twist share nor jumps to the bare wrist
//! (`tests/it/hand_loss.rs`). A hand solved again is aligned in that frame: its hand bone shows
//! the solve at once (`ease.rs`), its fingers blend in.

use glam::{Quat, Vec3};

use crate::align;
use crate::contact::{HandPoints, SideTarget, Source, UserFace, UserFaces};
use crate::filter::{DropoutOptions, Presence};
use crate::humanoid::bones::{Finger, Side, BONE_COUNT};
use crate::mediapipe::{pose_landmark, FrameInput};

use super::hands::WristSource;
use super::{Rig, SolveOutput};

/// What a side's arm does this frame, decided by [`Rig::plan_target`] before any IK. Two per
/// frame on the stack: the size difference between variants does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Plan {
    /// Nothing drives the arm.
    Rest,
    /// Hands only: the arm stays at rest, the hand takes this world rotation.
    HandOnly(Quat),
    /// The arm reaches `target` (the hand with `hand_rotation`, when known).
    Reach {
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        /// The hand's contact points (a hand solved this frame, contact on).
        points: Option<HandPoints>,
        /// `hand_rotation` is a lost hand's as shown last frame ([`LostHand`]): the arm
        /// reaches with it, the hand bone is left to the easing (held, then eased to rest).
        carried: bool,
        /// A hand not seen this frame (held or lost): its contact points as last seen, turned
        /// to `hand_rotation`, which keep it out of the body ([`crate::contact::SideTarget`]).
        held: Option<HandPoints>,
    },
}

/// What a side's lost hand leaves to its arm (history; see the module docs): the fingertip
/// alignment's offset from the wrist source and the hand's world rotation as shown, held and
/// then eased out with the dropout timings.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct LostHand {
    /// The last aligned frame's wrist target (after contact) minus the wrist source's
    /// position.
    offset: Vec3,
    /// This frame's wrist source position.
    wrist: Vec3,
    /// The hand present (live) or lost, and since when: the hold and the fade.
    presence: Presence,
    /// The hand's world rotation shown last frame (internal frame), when the arm was solved
    /// in it (written by the report stage).
    pub(super) shown: Option<Quat>,
    /// The last freshly solved frame's contact points and the hand rotation they were placed
    /// with (contact on), for the body push while the hand is not seen.
    points: Option<(HandPoints, Quat)>,
}

impl LostHand {
    /// Advances to `now_ms` with the hand `present` or not: how far a lost hand's carry has
    /// eased out (0 while present or holding, 1 once gone).
    fn update(&mut self, now_ms: f64, present: bool, timing: &DropoutOptions) -> f32 {
        let blend = self.presence.update(now_ms, present, timing);
        if present {
            0.0
        } else {
            blend.weight
        }
    }
}

impl Rig {
    /// After the IK (stage 7): each aligned side's wrist target as reached (contact and the
    /// wrist limits applied) as an offset from its wrist source, for when the hand is lost
    /// ([`LostHand`]).
    pub(super) fn remember_offsets(&mut self, out: &SolveOutput) {
        for side in Side::BOTH {
            let s = side.index();
            if let (Some(t), true) = (out.ik_targets[s], out.alignment[s].is_some()) {
                let lost = &mut self.lost_hand[s];
                lost.offset = t.position - lost.wrist;
            }
        }
    }

    /// Stage 6a: the side's wrist IK target by fingertip alignment from this frame's hand
    /// (no IK yet), and the hand's contact points while its landmarks are at hand.
    // Out of line: LLVM inlined it once per side, 0.8 KiB of .wasm (docs/measurements.md).
    #[inline(never)]
    pub(super) fn plan_target(
        &mut self,
        side: Side,
        frame: &FrameInput,
        hand_rotation: Option<Quat>,
        source: Option<WristSource>,
        out: &mut SolveOutput,
    ) -> Plan {
        self.scratch.fingers_blending[side.index()] = false;
        let timing = self.options.dropout.effective();
        let present = hand_rotation.or(source.and_then(|s| s.rotation));
        let lost = &mut self.lost_hand[side.index()];
        let gone = lost.update(frame.time_ms, present.is_some(), &timing);
        let Some(source) = source else {
            // Nothing places the arm: a hand alone keeps it at rest and takes the solved world
            // rotation.
            *lost = LostHand::default();
            return present.map_or(Plan::Rest, Plan::HandOnly);
        };
        lost.wrist = source.position;
        if gone >= 1.0 {
            // Eased out: a hand held by the solver on its first frame back starts from the
            // bare wrist, not from an offset of long ago.
            lost.offset = Vec3::ZERO;
        }
        let carried = source.position + lost.offset * (1.0 - gone);
        // A lost hand: the arm keeps the hand's rotation as shown (the forearm keeps its share
        // of the twist) until the hand has eased to rest, and then reaches the wrist.
        let Some(hand_rot) = present.or(lost.shown.filter(|_| gone < 1.0)) else {
            return Plan::Reach {
                target: carried,
                hand_rotation: None,
                pole: source.pole,
                points: None,
                carried: false,
                held: None,
            };
        };

        // A hand held by the solver (degenerate landmarks this frame) keeps its rotations but
        // its landmarks cannot place the fingertip: align freshly solved hands, and hands the
        // checks held with the landmarks they were solved from (`hands.rs`).
        let fresh = self.scratch.placed[side.index()];
        // The fingers as shown: a returning hand's blend in (stage 8), so that the fingertip
        // shown lands on the user's (a copy of the rotations, on the stack, only then).
        let blend = self.fingers_blend(side, frame.time_ms).filter(|_| fresh);
        self.scratch.fingers_blending[side.index()] = blend.is_some();
        let mut shown_local;
        let local = match blend {
            Some(b) => {
                shown_local = out.local;
                self.show_fingers(side, b, &mut shown_local);
                &shown_local
            }
            None => &out.local,
        };
        let target = if fresh {
            let a = align::wrist_target(
                &self.skeleton,
                side,
                &self.options.alignment,
                self.aligned_parts[side.index()],
                source.position,
                &self.scratch.landmarks,
                source.scale,
                hand_rot,
                local,
            );
            out.alignment[side.index()] = Some(a);
            a.ik_wrist
        } else {
            carried
        };
        let hand_index = out.hands[side.index()].map(|h| h.index);
        let points = (fresh && self.options.contact.enabled)
            .then(|| self.hand_points(side, frame, hand_index, &source, hand_rot, local))
            .flatten();
        let lost = &mut self.lost_hand[side.index()];
        let held = if fresh {
            lost.points = points.map(|p| (p, hand_rot));
            None
        } else {
            lost.points.map(|(p, q)| p.turned(hand_rot * q.conjugate()))
        };
        Plan::Reach {
            target,
            hand_rotation: Some(hand_rot),
            pole: source.pole,
            points,
            carried: present.is_none(),
            held,
        }
    }

    /// The hand's contact points ([`HandPoints`]): the user's from this side's landmarks
    /// placed on the user's wrist (the tracker wrist, or the pose wrist landmark in user
    /// space, whichever [`Rig::wrist_source`] used), the avatar's from forward kinematics of
    /// this frame's hand rotation and finger rotations.
    pub(super) fn hand_points(
        &self,
        side: Side,
        frame: &FrameInput,
        out_hand: Option<usize>,
        source: &WristSource,
        hand_rotation: Quat,
        local: &[Quat; BONE_COUNT],
    ) -> Option<HandPoints> {
        use crate::mediapipe::hand_landmark as hl;
        let camera = self.options.camera();
        let (kind, wrist) = if frame.wrists[side.index()].is_some() {
            (Source::Tracker, source.position)
        } else {
            let k = match camera.pose_side_for(side) {
                Side::Left => pose_landmark::LEFT_WRIST,
                Side::Right => pose_landmark::RIGHT_WRIST,
            };
            (
                Source::Pose,
                camera.to_avatar(self.scratch.pose.as_ref()?.world[k]),
            )
        };
        let lm = &self.scratch.landmarks;
        let palm_center = (lm[hl::WRIST]
            + lm[hl::INDEX_MCP]
            + lm[hl::MIDDLE_MCP]
            + lm[hl::RING_MCP]
            + lm[hl::PINKY_MCP])
            / 5.0;
        let mut user = [Vec3::ZERO; crate::contact::POINTS];
        user[0] = wrist + palm_center - lm[hl::WRIST];
        let mut avatar = [None; crate::contact::POINTS];
        // The avatar's palm center: its hand joint and the proximal joints it has; without
        // any, four fifths of the way to its palm front (as the user's: the wrist and four
        // knuckles).
        let mut sum = Vec3::ZERO;
        let mut n = 1.0;
        for f in [Finger::Index, Finger::Middle, Finger::Ring, Finger::Little] {
            let proximal = side.finger(f)[0];
            if self.skeleton.has(proximal) {
                sum += self.skeleton.rest_local(proximal);
                n += 1.0;
            }
        }
        avatar[0] = Some(if n > 1.0 {
            hand_rotation * (sum / n)
        } else {
            hand_rotation * (0.8 * align::palm_front(&self.skeleton, side))
        });
        let tip_options = align::AlignmentOptions {
            point: align::AlignPoint::Tip,
            ..self.options.alignment
        };
        for finger in Finger::ALL {
            let k = 1 + finger.index();
            user[k] = wrist + lm[finger.landmarks()[3]] - lm[hl::WRIST];
            avatar[k] = match align::AlignedPart::depth(&self.skeleton, side, finger) {
                Some(2) | None => align::avatar_offset(
                    &self.skeleton,
                    side,
                    &align::AlignmentOptions {
                        finger,
                        ..tip_options
                    },
                    hand_rotation,
                    local,
                ),
                // A finger without its distal bone: its tip extrapolated.
                Some(depth) => Some(align::part_offset(
                    &self.skeleton,
                    side,
                    align::AlignedPart::Finger { finger, depth },
                    align::AlignPoint::Tip,
                    hand_rotation,
                    local,
                )),
            };
        }
        // Without fingers, the palm's front stands in for the aligned finger's tip.
        let part = self.aligned_parts[side.index()];
        let touch = part.touch_finger(self.options.alignment.finger);
        if part == align::AlignedPart::Palm {
            avatar[1 + touch.index()] = Some(align::part_offset(
                &self.skeleton,
                side,
                part,
                align::AlignPoint::Tip,
                hand_rotation,
                local,
            ));
        }
        // Every finger joint, for keeping the whole hand out of the body, and what the image
        // says about the hand for chest contact: both used only with a skin.
        let on_skin = self.contact.surface().is_some();
        let mut joints = [None; 15];
        for finger in Finger::ALL.into_iter().filter(|_| on_skin) {
            let mut at = Vec3::ZERO;
            let mut rotation = hand_rotation;
            for (k, b) in side.finger(finger).into_iter().enumerate() {
                if self.skeleton.has(b) {
                    at += rotation * self.skeleton.rest_local(b);
                    joints[3 * finger.index() + k] = Some(at);
                    rotation *= local[b.index()];
                }
            }
        }
        let middle = side.finger(Finger::Middle)[0];
        let image = out_hand
            .and_then(|i| frame.hands().get(i))
            .and_then(|h| h.image);
        let image_tip = image.map(|img| img[touch.landmarks()[3]]);
        // The finger landmarks for face contact by the hand part nearest the face: skin only.
        let mut user_parts = [Vec3::ZERO; crate::contact::hands::PARTS];
        if on_skin {
            for (k, p) in user_parts.iter_mut().enumerate() {
                *p = wrist + lm[1 + k] - lm[hl::WRIST];
            }
        }
        let image_parts = image
            .filter(|_| on_skin)
            .map(|img| core::array::from_fn(|k| img[1 + k]));
        let cue = out_hand
            .filter(|_| on_skin)
            .and_then(|i| frame.hands().get(i))
            .and_then(|h| {
                let img = h.image?;
                let palm = (img[hl::WRIST]
                    + img[hl::INDEX_MCP]
                    + img[hl::MIDDLE_MCP]
                    + img[hl::RING_MCP]
                    + img[hl::PINKY_MCP])
                    / 5.0;
                let a = (img[hl::INDEX_MCP] - img[hl::WRIST]).truncate();
                let b = (img[hl::PINKY_MCP] - img[hl::WRIST]).truncate();
                let sine = a.perp_dot(b) / (a.length() * b.length()).max(1e-9);
                let sign = match h.handedness {
                    crate::mediapipe::Handedness::Left => 1.0,
                    crate::mediapipe::Handedness::Right => -1.0,
                };
                let palm_length = (lm[hl::MIDDLE_MCP] - lm[hl::WRIST]).length().max(1e-6);
                let extension = [hl::INDEX_TIP, 12, 16, 20]
                    .iter()
                    .map(|&k| (lm[k] - lm[hl::WRIST]).length())
                    .sum::<f32>()
                    / (4.0 * palm_length);
                Some(crate::contact::chest::HandCue {
                    palm,
                    facing: sign * sine,
                    extension,
                })
            });
        Some(HandPoints {
            cue,
            image_tip,
            user_parts,
            image_parts,
            source: kind,
            user,
            avatar,
            joints,
            user_palm: (lm[hl::MIDDLE_MCP] - lm[hl::WRIST]).length(),
            avatar_palm: if self.skeleton.has(middle) {
                self.skeleton.rest_local(middle).length()
            } else {
                crate::humanoid::measure::avatar_palm_length(&self.skeleton)
            },
        })
    }

    /// Stage 6b: self-contact for both sides together ([`crate::contact`]): the targets move
    /// so that a finger on the user's face lands on the avatar's, touching hands stay
    /// touching, and hands stay out of the avatar's body. Reads the head and torso where they
    /// will be shown from the torso stage's forward kinematics (`out.world`; nothing between
    /// moves them: the hands and arms are below).
    pub(super) fn contact_targets(
        &mut self,
        frame: &FrameInput,
        dt: Option<f32>,
        plans: &mut [Plan; 2],
        out: &mut SolveOutput,
    ) {
        if !self.options.contact.enabled {
            return;
        }
        self.contact_rate.begin(dt, self.options.contact.max_speed);
        let mut targets: [Option<SideTarget>; 2] = plans.map(|p| match p {
            Plan::Reach {
                target,
                points,
                held,
                ..
            } => Some(SideTarget {
                wrist: target,
                hand: points,
                held,
            }),
            _ => None,
        });
        if targets.iter().all(Option::is_none) {
            self.contact_rate.forget();
            return;
        }
        let needs = |source: Source| {
            targets
                .iter()
                .flatten()
                .any(|t| t.hand.is_some_and(|h| h.source == source))
        };
        let on_skin = self.contact.surface().is_some();
        let faces = UserFaces {
            pose: if needs(Source::Pose) {
                self.scratch.pose.as_ref().and_then(|p| {
                    UserFace::from_pose(
                        p,
                        self.options.camera(),
                        self.options.calibration.min_visibility,
                    )
                })
            } else {
                None
            },
            pose_image: match (&self.scratch.pose, &frame.pose_image) {
                (Some(pose), Some(image)) if needs(Source::Pose) => {
                    crate::contact::ImageFit::from_pose(
                        pose,
                        image,
                        self.options.calibration.min_visibility,
                    )
                }
                _ => None,
            },
            camera: self.options.camera(),
            torso_image: match (&self.scratch.pose, &frame.pose_image) {
                (Some(pose), Some(image)) if on_skin && needs(Source::Pose) => {
                    let seen = [11, 12, 23, 24]
                        .iter()
                        .all(|&k| pose.visibility[k] >= self.options.calibration.min_visibility);
                    seen.then(|| crate::contact::chest::TorsoImage {
                        shoulders: [image[11], image[12]],
                        hips: [image[23], image[24]],
                    })
                }
                _ => None,
            },
            hands_apart: if on_skin {
                let image = |side: Side| {
                    out.hands[side.index()]
                        .and_then(|h| frame.hands().get(h.index))
                        .and_then(|h| h.image)
                };
                match (image(Side::Left), image(Side::Right)) {
                    (Some(a), Some(b)) => crate::contact::hands::image_apart(&a, &b),
                    _ => None,
                }
            } else {
                None
            },
            tracker: if needs(Source::Tracker) {
                frame
                    .face
                    .as_ref()
                    .and_then(|f| UserFace::from_tracker(f, self.skeleton.version()))
            } else {
                None
            },
        };
        // Each side's touching finger (the aligned part's; the palm stands in the configured
        // finger's slot): the same on both sides unless the avatar's hands differ.
        let fingers = Side::BOTH.map(|side| {
            self.aligned_parts[side.index()].touch_finger(self.options.alignment.finger)
        });
        self.contact.solve(
            fingers,
            &faces,
            &out.world,
            &mut targets,
            &mut out.contact,
            &mut self.contact_rate,
        );
        for (s, (plan, t)) in plans.iter_mut().zip(targets).enumerate() {
            if let (Plan::Reach { target, .. }, Some(t)) = (plan, t) {
                let delta = t.wrist - *target;
                *target = t.wrist;
                if let Some(a) = out.alignment[s].as_mut() {
                    a.target_dip += delta;
                    a.ik_wrist += delta;
                }
            }
        }
        self.touch_hold(frame.time_ms, plans, out);
    }
}
