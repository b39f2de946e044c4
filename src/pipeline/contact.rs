//! The **contact** stage, for both sides together: each hand's contact points built from the
//! frame (the user's hand placed on the user's wrist, the avatar's by forward kinematics of
//! this frame's hand), then the wrist targets moved for self-contact ([`crate::contact`]: a
//! finger on the face lands on the avatar's face where the posed torso put it, touching hands
//! stay touching, hands stay out of the body; the correction changes by at most
//! `contact.maxSpeed`), then a hand lost while it touches the other held against it
//! ([`super::touch`]). A hand not seen this frame (held or lost) keeps the contact points it
//! was last seen with, turned to its rotation, which keep its palm and fingertips out of the
//! body.

use glam::{Quat, Vec3};

use crate::align;
use crate::contact::skin::{self, BodySurface};
use crate::contact::ContactOptions;
use crate::contact::{
    ContactRate, ContactSolver, HandPoints, SideTarget, Source, UserFace, UserFaces,
};
use crate::humanoid::bones::{Finger, Side, BONE_COUNT};
use crate::humanoid::skeleton::{Skeleton, WorldPose};
use crate::input::mediapipe::pose_landmark;

use super::ease::Ease;
use super::frame::{Context, Frame, Plan};
use super::output::SolveOutput;
use super::touch::{self, TouchHold};

/// The contact stage: the avatar's side of self-contact, the corrections' rate limit, each
/// side's contact points as last seen, and each side's touch with the other hand.
#[derive(Clone, Debug)]
pub(super) struct Contact {
    solver: ContactSolver,
    rate: ContactRate,
    /// The last freshly placed frame's contact points and the hand rotation they were placed
    /// with, for the body push while the hand is not seen.
    last_points: [Option<(HandPoints, Quat)>; 2],
    touch: [TouchHold; 2],
}

impl Contact {
    pub(super) fn new(skeleton: &Skeleton, options: &ContactOptions) -> Self {
        Contact {
            solver: ContactSolver::new(skeleton, options),
            rate: ContactRate::default(),
            last_points: [None; 2],
            touch: [TouchHold::default(); 2],
        }
    }

    /// The avatar's side of self-contact.
    pub(super) fn solver(&self) -> &ContactSolver {
        &self.solver
    }

    /// Whether `side`'s lost hand is held against the other this frame.
    pub(super) fn touch_held(&self, side: Side) -> bool {
        self.touch[side.index()].held()
    }

    /// Forgets the history.
    pub(super) fn restart(&mut self) {
        self.rate = ContactRate::default();
        self.last_points = [None; 2];
        self.touch = [TouchHold::default(); 2];
    }

    /// Each side's contact points into `f.points` (a hand placed this frame), and those of a
    /// hand not seen, as last seen and turned to its rotation now, into `f.held` (both cleared
    /// by the caller). Written in place: an array of two `Option<HandPoints>` is 1.9 KB, and
    /// returning it cost a copy a frame.
    fn points(&mut self, cx: &Context, ease: &Ease, f: &mut Frame, out: &SolveOutput) {
        for side in Side::BOTH {
            let s = side.index();
            match f.plans[s] {
                Plan::Reach {
                    hand_rotation: Some(hand_rot),
                    ..
                } => {
                    if f.placed[s] {
                        // The fingers as the targets stage placed them (blending in after a
                        // loss: as the easing will show them).
                        let blend = ease
                            .fingers_blend(cx, side)
                            .filter(|_| f.fingers_blending[s]);
                        let mut copy = None;
                        let local = ease.fingers_as_shown(cx, side, blend, &out.local, &mut copy);
                        let hand = out.hands[s].map(|h| h.index);
                        let points = self.hand_points(cx, side, f, hand, hand_rot, local);
                        self.last_points[s] = points.map(|p| (p, hand_rot));
                        f.points[s] = points;
                    } else if let Some((p, q)) = &self.last_points[s] {
                        f.held[s] = Some(p.turned(hand_rot * q.conjugate()));
                    }
                }
                Plan::Reach { .. } => {}
                // Nothing places the arm: what was seen is forgotten.
                Plan::Rest | Plan::HandOnly(_) => self.last_points[s] = None,
            }
        }
    }

    /// The hand's contact points ([`HandPoints`]): the user's from this side's landmarks
    /// placed on the user's wrist (the tracker wrist, or the pose wrist landmark in user
    /// space, whichever the observe stage used), the avatar's from forward kinematics of
    /// this frame's hand rotation and finger rotations.
    #[inline(never)]
    fn hand_points(
        &self,
        cx: &Context,
        side: Side,
        f: &Frame,
        out_hand: Option<usize>,
        hand_rotation: Quat,
        local: &[Quat; BONE_COUNT],
    ) -> Option<HandPoints> {
        use crate::input::mediapipe::hand_landmark as hl;
        let (frame, camera, skeleton) = (cx.input, cx.camera, cx.skeleton);
        let source = f.sources[side.index()]?;
        let (kind, wrist) = if frame.wrists[side.index()].is_some() {
            (Source::Tracker, source.position)
        } else {
            let k = match camera.pose_side_for(side) {
                Side::Left => pose_landmark::LEFT_WRIST,
                Side::Right => pose_landmark::RIGHT_WRIST,
            };
            (Source::Pose, camera.to_avatar(f.pose.as_ref()?.world[k]))
        };
        let lm = &f.landmarks[side.index()];
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
            if skeleton.has(proximal) {
                sum += skeleton.rest_local(proximal);
                n += 1.0;
            }
        }
        avatar[0] = Some(if n > 1.0 {
            hand_rotation * (sum / n)
        } else {
            hand_rotation * (0.8 * align::palm_front(skeleton, side))
        });
        let tip_options = align::AlignmentOptions {
            point: align::AlignPoint::Tip,
            ..cx.options.alignment
        };
        for finger in Finger::ALL {
            let k = 1 + finger.index();
            user[k] = wrist + lm[finger.landmarks()[3]] - lm[hl::WRIST];
            avatar[k] = match align::AlignedPart::depth(skeleton, side, finger) {
                Some(2) | None => align::avatar_offset(
                    skeleton,
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
                    skeleton,
                    side,
                    align::AlignedPart::Finger { finger, depth },
                    align::AlignPoint::Tip,
                    hand_rotation,
                    local,
                )),
            };
        }
        // Without fingers, the palm's front stands in for the aligned finger's tip.
        let part = cx.aligned_parts[side.index()];
        let touch = part.touch_finger(cx.options.alignment.finger);
        if part == align::AlignedPart::Palm {
            avatar[1 + touch.index()] = Some(align::part_offset(
                skeleton,
                side,
                part,
                align::AlignPoint::Tip,
                hand_rotation,
                local,
            ));
        }
        // Every finger joint, for keeping the whole hand out of the body, and what the image
        // says about the hand for chest contact: both used only with a skin.
        let on_skin = self.solver.surface().is_some();
        let mut joints = [None; 15];
        for finger in Finger::ALL.into_iter().filter(|_| on_skin) {
            let mut at = Vec3::ZERO;
            let mut rotation = hand_rotation;
            for (k, b) in side.finger(finger).into_iter().enumerate() {
                if skeleton.has(b) {
                    at += rotation * skeleton.rest_local(b);
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
            .and_then(|i| Some((i, frame.hands().get(i)?)))
            .and_then(|(i, h)| {
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
                    crate::input::mediapipe::Handedness::Left => 1.0,
                    crate::input::mediapipe::Handedness::Right => -1.0,
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
                    // Image landmarks made into pseudo-world ones have no metric size.
                    scale: if frame.world_from_image[i] {
                        0.0
                    } else {
                        crate::contact::chest::hand_scale(&img, &h.world, frame.image_aspect)
                    },
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
            avatar_palm: if skeleton.has(middle) {
                skeleton.rest_local(middle).length()
            } else {
                crate::humanoid::measure::avatar_palm_length(skeleton)
            },
        })
    }

    /// Self-contact for both sides together ([`crate::contact`]): each side's contact points
    /// from the frame (`f.points`), then the targets (`f.plans`) move so that a finger on the
    /// user's face lands on the avatar's, touching hands stay touching, and hands stay out of
    /// the avatar's body; then a lost hand touching the other is held against it
    /// ([`super::touch`]). Reads the head and torso where they will be shown from the torso
    /// stage's forward kinematics (`out.world`; nothing between moves them: the hands and
    /// arms are below).
    pub(super) fn run(&mut self, cx: &Context, ease: &Ease, f: &mut Frame, out: &mut SolveOutput) {
        f.points = [None; 2];
        f.held = [None; 2];
        if !cx.options.contact.enabled {
            return;
        }
        let (frame, options, skeleton) = (cx.input, cx.options, cx.skeleton);
        self.points(cx, ease, f, out);
        self.rate.begin(cx.dt, options.contact.max_speed);
        // Filled in place, each side's points copied only when there are some (a
        // `SideTarget` holds two `Option<HandPoints>`, 1.9 KB: built by value and moved, the
        // array cost a dozen copies of 1.9 KB a frame).
        let mut targets: [Option<SideTarget>; 2] = [None, None];
        for (s, slot) in targets.iter_mut().enumerate() {
            if let Plan::Reach { target, .. } = f.plans[s] {
                let t = slot.insert(SideTarget {
                    wrist: target,
                    hand: None,
                    held: None,
                });
                if let Some(p) = &f.points[s] {
                    t.hand = Some(*p);
                }
                if let Some(p) = &f.held[s] {
                    t.held = Some(*p);
                }
            }
        }
        if targets[0].is_none() && targets[1].is_none() {
            self.rate.forget();
            return;
        }
        let needs = |source: Source| {
            targets
                .iter()
                .flatten()
                .any(|t| t.hand.is_some_and(|h| h.source == source))
        };
        let on_skin = self.solver.surface().is_some();
        let faces = UserFaces {
            pose: if needs(Source::Pose) {
                f.pose.as_ref().and_then(|p| {
                    UserFace::from_pose(p, cx.camera, options.calibration.min_visibility)
                })
            } else {
                None
            },
            pose_image: match (&f.pose, &frame.pose_image) {
                (Some(pose), Some(image)) if needs(Source::Pose) => {
                    crate::contact::ImageFit::from_pose(
                        pose,
                        image,
                        options.calibration.min_visibility,
                    )
                }
                _ => None,
            },
            camera: cx.camera,
            torso_image: match (&f.pose, &frame.pose_image) {
                (Some(pose), Some(image)) if on_skin && needs(Source::Pose) => {
                    let seen = [11, 12, 23, 24]
                        .iter()
                        .all(|&k| pose.visibility[k] >= options.calibration.min_visibility);
                    seen.then(|| crate::contact::chest::TorsoImage {
                        shoulders: [image[11], image[12]],
                        hips: [image[23], image[24]],
                        scale: crate::contact::chest::torso_scale(
                            [image[11], image[12]],
                            [pose.world[11], pose.world[12]],
                            frame.image_aspect,
                        ),
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
                    .and_then(|face| UserFace::from_tracker(face, skeleton.version()))
            } else {
                None
            },
        };
        // Each side's touching finger (the aligned part's; the palm stands in the configured
        // finger's slot): the same on both sides unless the avatar's hands differ.
        let fingers = Side::BOTH
            .map(|side| cx.aligned_parts[side.index()].touch_finger(options.alignment.finger));
        self.solver.solve(
            fingers,
            &faces,
            &out.world,
            &mut targets,
            &mut out.contact,
            &mut self.rate,
        );
        for (s, (plan, t)) in f.plans.iter_mut().zip(&targets).enumerate() {
            if let (Plan::Reach { target, .. }, Some(t)) = (plan, t) {
                let delta = t.wrist - *target;
                *target = t.wrist;
                if let Some(a) = out.alignment[s].as_mut() {
                    a.target_dip += delta;
                    a.ik_wrist += delta;
                }
            }
        }
        touch::hold(&mut self.touch, ease.shown(), cx.now_ms, f, out);
    }
}

/// A side's hand as self-contact keeps it out of the body: the avatar's skin and the hand's
/// contact balls as the contact stage placed them (centers relative to the wrist, world axes,
/// for a hand with world rotation `rotation`: the plan's). For what moves the hand after the
/// contact stage (the wrist limits in the reach, the turn limit) and must not take it into
/// the body.
pub(super) struct HandBody<'a> {
    pub(super) surface: &'a BodySurface,
    pub(super) balls: [(Vec3, f32); skin::HAND_SPHERES],
    pub(super) count: usize,
    pub(super) rotation: Quat,
}

impl<'a> HandBody<'a> {
    /// The side's hand this frame; `None` without a skin, with contact or its push out of the
    /// body off, or when the arm reaches no target.
    pub(super) fn of(
        cx: &Context,
        contact: &'a ContactSolver,
        f: &Frame,
        side: Side,
    ) -> Option<HandBody<'a>> {
        let o = &cx.options.contact;
        let surface = contact.surface().filter(|_| o.enabled && o.colliders)?;
        let s = side.index();
        let Plan::Reach { hand_rotation, .. } = f.plans[s] else {
            return None;
        };
        // A hand not seen is pushed with 7 of its balls (`skin::hand_spheres`); it is checked
        // here with all it was last seen with: between those 7 its knuckles sank up to 18 mm.
        // (The points are read where they are: a copy of them cost more than the balls.)
        let body = f.points[s].as_ref().or(f.held[s].as_ref());
        let mut balls = [(Vec3::ZERO, 0.0); skin::HAND_SPHERES];
        let count = skin::hand_spheres_of(surface, side, body, body.is_some(), &mut balls);
        Some(HandBody {
            surface,
            balls,
            count,
            rotation: hand_rotation.unwrap_or(Quat::IDENTITY),
        })
    }

    /// The balls of the hand turned by `turn` (world) from the plan's rotation.
    pub(super) fn turned(&self, turn: Quat) -> [(Vec3, f32); skin::HAND_SPHERES] {
        let mut balls = self.balls;
        for b in &mut balls[..self.count] {
            b.0 = turn * b.0;
        }
        balls
    }

    /// The translation that takes the hand, its wrist at `wrist` with world rotation
    /// `rotation`, out of the body as the contact stage's push does ([`BodySurface::push`]);
    /// zero for a hand out of it.
    pub(super) fn push(&self, wrist: Vec3, rotation: Quat, world: &WorldPose) -> Vec3 {
        let balls = self.turned(rotation * self.rotation.conjugate());
        self.surface.push(wrist, &balls[..self.count], world)
    }
}
