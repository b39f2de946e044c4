//! Self-contact retargeting: a finger on the user's face lands on the avatar's face, touching
//! hands stay touching, and hands stay out of the avatar's body.
//!
//! Fingertip alignment ([`crate::align`]) fixes the hand's length; seed 000 names the other
//! cause of broken self-touch: "the distance from the neck to the front of the face", which
//! is smaller on avatars (and face sizes differ). Plain alignment carries the user's finger
//! relative to the shoulder; a finger on the user's nose then ends in front of, or inside,
//! the avatar's face. Here the finger is carried relative to the **face** instead when it is
//! near it:
//!
//! 1. **Face** ([`face`]): the user's fingertip (the aligned finger's tip: contact happens at
//!    the tip, whatever `alignment.point` is; on an avatar without that finger's distal bone,
//!    what stands in for it: [`crate::align::AlignedPart`]) in the user's face frame, in head
//!    breadths; the nearest face anchor at distance `e`; the tip warped onto the avatar's face
//!    frame ([`face::warp`]: exact on the anchors). The avatar's fingertip target is
//!    `plain + w (warped - plain)` with `w = contact.weight x blend(e, contact.radius)`
//!    ([`face::blend`]: 1 within half the radius, 0 beyond it, smoothstep between), and the
//!    hand (IK wrist and target DIP) moves by the same translation. The user's face frame is
//!    built in the same space as the finger: pose face landmarks for pose wrists, the
//!    tracker's face points (`frame.face`) for tracker wrists.
//! 2. **Hands** ([`hands`]): both sides' targets together, after the face step.
//! 3. **Body** ([`colliders`]): each hand pushed out of the torso, neck and head colliders,
//!    times `1 - w` of its face contact (a finger on the face wins).
//!
//! Every step is continuous in the input and leaves the plain alignment target untouched
//! beyond the radius. Nothing here keeps state between frames, and nothing allocates.
//!
//! ## Continuity bound
//! Along a finger path, the target moves at most `1 + 3 g + 3 D / (r h)` times as far as the
//! finger: the plain target moves with the finger (1), the warped one with the avatar's
//! face size over the user's (`g`) times the warp's stretch (at most about 3: the anchor
//! interpolation's gradient), and the blend adds its largest slope (3 / (r h): from 1 to 0
//! over half the radius `r h` in meters) times the largest distance `D` between the warped
//! and the plain target. `tests/it/contact.rs` checks it on approach paths to every anchor (the
//! largest step measured is 0.8 of the bound).
//!
//! ## The avatar's head
//! Face anchors and colliders are read from forward kinematics of the frame's rotations (the
//! head and torso as they will be shown). Until the torso moves the head, the avatar's face
//! stays at rest while the user's may turn: the mapping is relative to each face, so a finger
//! on the user's turned cheek still lands on the avatar's cheek, but the hand keeps the
//! user's world orientation and may then come at the avatar's face from an odd side.
//!
//! The avatar's face and colliders are attached to the head (and torso) bones and placed from
//! forward kinematics of the frame's rotations, so they follow the head once it moves.

pub mod chest;
pub mod colliders;
pub mod face;
pub mod hands;
pub mod skin;

use glam::Vec3;

use crate::humanoid::bones::{Finger, HumanBone, Side};
use crate::humanoid::skeleton::{Skeleton, WorldPose};
use crate::input::mediapipe::CameraMapping;

pub use colliders::{BodyColliders, Shape};
pub use face::{AvatarFace, FaceAnchor, FaceFrame, FacePoints, ImageFit, UserFace, ANCHORS};
pub use hands::{HandPoints, Source, POINTS};

/// Largest coordinate accepted in `contact.faceAnchors` (meters from the head bone).
pub const MAX_ANCHOR_OFFSET: f32 = 10.0;

/// Face anchors an app gives (JS: `contact.faceAnchors = { nose: [x, y, z], ... }`): meters,
/// relative to the head bone at rest, in the model's own axes (VRM 0.x: its -Z-facing frame),
/// e.g. found by raycasting the avatar's mesh. Each optional; missing ones are derived.
///
/// Read from JSON as an object whose keys are [`FaceAnchor`] names and whose values are
/// `[x, y, z]` (or `null`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FaceAnchorsOption {
    points: [Option<[f32; 3]>; ANCHORS],
}

impl FaceAnchorsOption {
    /// No anchor given.
    pub const NONE: FaceAnchorsOption = FaceAnchorsOption {
        points: [None; ANCHORS],
    };

    /// From the points in [`FaceAnchor::ALL`] order (model axes).
    #[must_use]
    pub const fn from_array(points: [Option<[f32; 3]>; ANCHORS]) -> Self {
        FaceAnchorsOption { points }
    }

    /// The points in [`FaceAnchor::ALL`] order (model axes).
    #[must_use]
    pub const fn to_array(&self) -> [Option<[f32; 3]>; ANCHORS] {
        self.points
    }

    /// The given anchor, as written (model axes).
    #[must_use]
    pub fn get(&self, a: FaceAnchor) -> Option<Vec3> {
        self.points[a.index()].map(Vec3::from_array)
    }

    /// Sets an anchor (model axes).
    pub fn set(&mut self, a: FaceAnchor, v: Option<Vec3>) {
        self.points[a.index()] = v.map(|v| v.to_array());
    }
}

/// Self-contact options (JS: `options.contact`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// Turn self-contact retargeting on (default) or off (plain alignment targets).
    pub enabled: bool,
    /// Blend radius in head breadths (the user's ear-to-ear distance, ~0.145 m): full
    /// contact mapping within half of it, none beyond it. Default 0.5. Range 0.05..=3.
    pub radius: f32,
    /// 0..1 scale of the contact blend (0: plain alignment). Default 1.
    pub weight: f32,
    /// Hand-to-hand contact (touching hands stay touching). Default `true`.
    pub hands: bool,
    /// Face anchors of the avatar given by the app; missing ones derived from the rig
    /// (`null` in JSON: none given).
    pub face_anchors: FaceAnchorsOption,
    /// Body colliders push hands out of the avatar's torso, neck and head. Default `true`.
    pub colliders: bool,
    /// Torso capsule radius (m); unset: derived from the shoulders; 0: no torso collider.
    pub torso_radius: Option<f32>,
    /// Head sphere radius (m); unset: half the head breadth; 0: no head collider.
    pub head_radius: Option<f32>,
    /// With MediaPipe pose input, how much the tracked depth between the fingertip and the
    /// face counts (see [`face::pose_tip`]); 1 = as tracked. Tracker input always uses its
    /// depth. Default 0.1.
    pub depth_trust: f32,
    /// How fast the contact correction of a wrist target (face, chest, other hand; not the
    /// push out of the body) may change, m/s; 0: no limit. Default 6 (0.2 m a frame at 30 fps).
    pub max_speed: f32,
}

/// Largest `contact.torsoRadius` / `contact.headRadius` (m).
pub const MAX_COLLIDER_RADIUS: f32 = 2.0;

/// How far (m) a hand that touches nothing keeps its skin from the body's (head, neck,
/// torso) on an avatar with a skin: a touch is a gap of 2 cm or less in the measures
/// (`eval/skin-contact.mjs`), and a hand the user holds off the body, placed where the user's
/// is, met an avatar whose body is wider or whose arms are shorter than the user's within
/// that (false touches: 14-21% of the untouched hand-frames with contact off, on the figure
/// of primitives and the voxel figure up to 86%). 2 cm plus the radial maps' bin error (a
/// 1 cm row, half a 7.5 degree sector). Set from the measure's definition, not tuned.
pub const CLEARANCE: f32 = 0.025;

/// The share of a full chest landing below which none is made: the chest blend (the cue
/// held, times what the face blend leaves) is mapped from `[CHEST_FLOOR, 1]` onto `[0, 1]`,
/// so it stays continuous and still reaches full weight. A landing on the chest is the
/// costliest query of a frame (about 45k instructions on the skinned woman, twice a face
/// landing: the hand carried across the torso and settled there), and on frames of hands at
/// the face it was made for blends of a few thousandths (6 of the 12 hand-frames with a chest
/// blend in `eval/frames/hands-near-face.json` were under 0.05: a hand's shift of a
/// millimeter or less). Chosen for cost, not tuned on the contact figures.
pub const CHEST_FLOOR: f32 = 0.05;

/// What contact did for one side this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactReport {
    /// The face anchor nearest the user's fingertip (`None`: no face known for this side's
    /// source, or no hand).
    pub anchor: Option<FaceAnchor>,
    /// The face blend applied, 0..1 (0: plain alignment).
    pub weight: f32,
    /// Distance (m) from the avatar's fingertip (the aligned finger, after IK) to the
    /// avatar's `anchor`; NaN when unknown.
    pub distance: f32,
    /// The hand-to-hand blend applied, 0..1.
    pub hand_weight: f32,
    /// With hand-to-hand contact, where this hand meets the other, relative to its wrist
    /// target (world axes; see [`hands::HandContact::meet`]).
    pub hand_meet: Option<Vec3>,
    /// With face contact judged by the hand part nearest the face (rigs with a skin), the
    /// touching point relative to the wrist target (world axes): the avatar's parts weighted
    /// as their translations are; `None`: the aligned fingertip.
    pub face_meet: Option<Vec3>,
    /// How far the body colliders pushed the hand (m).
    pub push: f32,
    /// The chest blend applied, 0..1 (a hand resting on the torso: [`chest`]).
    pub chest_weight: f32,
}

impl Default for ContactReport {
    fn default() -> Self {
        ContactReport {
            anchor: None,
            weight: 0.0,
            distance: f32::NAN,
            hand_weight: 0.0,
            hand_meet: None,
            face_meet: None,
            push: 0.0,
            chest_weight: 0.0,
        }
    }
}

/// One side's wrist target and contact points, as the rig's target stage hands them over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideTarget {
    /// The wrist IK target; contact moves it.
    pub wrist: Vec3,
    /// The hand's points (a hand solved this frame), for every kind of contact.
    pub hand: Option<HandPoints>,
    /// A hand not seen this frame (held by the solver, or lost and carried by its arm): its
    /// points as last seen, turned to the rotation it is shown with, which only keep the whole
    /// hand out of the body. With neither, only the wrist is pushed.
    pub held: Option<HandPoints>,
}

impl SideTarget {
    /// The points that keep the hand out of the body: this frame's, else the held ones.
    #[must_use]
    pub fn body_points(&self) -> Option<&HandPoints> {
        self.hand.as_ref().or(self.held.as_ref())
    }
}

/// The user's face per source, built once per frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct UserFaces {
    /// From pose landmarks (user space), for pose wrists.
    pub pose: Option<UserFace>,
    /// From the tracker's face points (internal frame), for tracker wrists.
    pub tracker: Option<UserFace>,
    /// The pose's image-to-space map, when the pose's image landmarks are given.
    pub pose_image: Option<ImageFit>,
    /// How MediaPipe input maps onto the avatar (for the pose's camera axes).
    pub camera: CameraMapping,
    /// The user's torso in the image (pose image shoulders and hips), for chest contact.
    pub torso_image: Option<chest::TorsoImage>,
    /// With both hands' image landmarks: the smallest image distance between the two hands'
    /// landmarks over the larger hand's image palm length (wrist to middle knuckle); under
    /// about 0.3 the hands touch (docs/how-it-works/contact.md).
    pub hands_apart: Option<f32>,
}

impl UserFaces {
    /// The face matching a wrist source.
    #[must_use]
    pub fn for_source(&self, source: Source) -> Option<&UserFace> {
        match source {
            Source::Pose => self.pose.as_ref(),
            Source::Tracker => self.tracker.as_ref(),
        }
    }
}

/// The avatar's side of contact: its face and body colliders, derived once from the rig and
/// the options.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSolver {
    options: ContactOptions,
    face: AvatarFace,
    colliders: BodyColliders,
    /// The body learned from the avatar's skin, when the rig has one ([`skin`]): replaces
    /// the colliders and lands touching hands on the skin.
    surface: Option<skin::BodySurface>,
}

impl ContactSolver {
    /// The avatar's face ([`AvatarFace::from_rig`], with `options.faceAnchors`) and body
    /// colliders ([`BodyColliders::from_rig`]). `options` should have passed
    /// [`crate::RigOptions::validate`].
    #[must_use]
    pub fn new(skeleton: &Skeleton, options: &ContactOptions) -> Self {
        let version = skeleton.version();
        let given = FaceAnchor::ALL.map(|a| {
            options
                .face_anchors
                .get(a)
                .map(|p| version.position_to_internal(p))
        });
        let mut face = AvatarFace::from_rig(skeleton, &given);
        let surface = skeleton
            .skin()
            .and_then(|mesh| skin::BodySurface::new(skeleton, mesh));
        if let Some(surface) = &surface {
            if surface.maps[skin::HEAD_MAP].is_some() {
                for a in FaceAnchor::ALL {
                    if !face.given[a.index()] {
                        let side = match a {
                            FaceAnchor::LeftEar => 1.0,
                            FaceAnchor::RightEar => -1.0,
                            _ => 0.0,
                        };
                        face.anchors[a.index()] = surface.onto_face(face.anchors[a.index()], side);
                    }
                }
            }
        }
        let colliders =
            BodyColliders::from_rig(skeleton, &face, options.torso_radius, options.head_radius);
        ContactSolver {
            options: *options,
            face,
            colliders,
            surface,
        }
    }

    /// The body learned from the avatar's skin, if the rig has one.
    #[must_use]
    pub fn surface(&self) -> Option<&skin::BodySurface> {
        self.surface.as_ref()
    }

    /// The avatar's face (head-bone relative, internal frame).
    #[must_use]
    pub fn face(&self) -> &AvatarFace {
        &self.face
    }

    /// The avatar's body colliders.
    #[must_use]
    pub fn colliders(&self) -> &BodyColliders {
        &self.colliders
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &ContactOptions {
        &self.options
    }

    /// Anchor `a` of the avatar posed as `world` (internal frame).
    #[must_use]
    pub fn anchor_world(&self, a: FaceAnchor, world: &WorldPose) -> Vec3 {
        let h = HumanBone::Head.index();
        self.face
            .anchor_world(a, world.position[h], world.rotation[h])
    }

    /// Contact on the avatar's skin ([`skin`]), after the face and hands steps: a hand the
    /// image shows resting on the torso lands on the chest ([`chest`]); a hand in face contact
    /// settles onto the head's skin (its nearest point resting on it: moved in when above, out
    /// when inside); hands the image shows touching are closed onto each other
    /// ([`hands::image_touch`]); the corrections are rate-limited (`rate`, against the targets
    /// at `start`); then every hand is pushed out of the body, and one that touches nothing is kept
    /// [`CLEARANCE`] clear of it. Allocates nothing.
    fn on_skin(
        &self,
        faces: &UserFaces,
        world: &WorldPose,
        targets: &mut [Option<SideTarget>; 2],
        reports: &mut [Option<ContactReport>; 2],
        start: &[Option<Vec3>; 2],
        rate: &mut ContactRate,
    ) {
        let Some(surface) = &self.surface else { return };
        let o = &self.options;
        let mut spheres = [[(Vec3::ZERO, 0.0); skin::HAND_SPHERES]; 2];
        let mut count = [0; 2];
        for side in Side::BOTH {
            if let Some(t) = &targets[side.index()] {
                count[side.index()] =
                    skin::hand_spheres(surface, side, t, &mut spheres[side.index()]);
            }
        }
        let cues = [0, 1].map(|k| targets[k].and_then(|t| t.hand).and_then(|h| h.cue));
        for ((target, report), side) in targets.iter_mut().zip(reports.iter_mut()).zip(Side::BOTH) {
            let Some(t) = target.as_mut() else {
                rate.hold_chest(side.index(), None);
                continue;
            };
            let points = &spheres[side.index()][..count[side.index()]];
            let face = report.as_ref().map_or(0.0, |r| r.weight);
            if let (Some(torso), Some(hand), Some(cue)) =
                (&faces.torso_image, &t.hand, &cues[side.index()])
            {
                let (w, u, v) = chest::weight(torso, cue, cues[1 - side.index()].as_ref());
                let w = rate.hold_chest(side.index(), Some(w));
                let w = o.weight * (w * (1.0 - face) - CHEST_FLOOR).max(0.0) / (1.0 - CHEST_FLOOR);
                if w > 0.0 {
                    if let Some(shift) =
                        self.chest_shift(faces.camera, world, t.wrist, hand, points, [u, v])
                    {
                        t.wrist += w * shift;
                    }
                }
                if let Some(r) = report.as_mut() {
                    r.chest_weight = w;
                }
            } else {
                rate.hold_chest(side.index(), None);
            }
            if face > 0.0 {
                let mut only = [false; skin::MAP_BONES.len()];
                only[skin::HEAD_MAP] = true;
                // Landing is complete from a blend of 2/3 on: a finger that the blend brought
                // most of the way rests on the skin rather than hovering a centimeter or two off.
                let land = (1.5 * face).min(1.0);
                // The wrist's and the palm centre's balls (the first two, with the palm's
                // half-thickness) grown by how far the palm's skin reaches past such balls
                // (`BodySurface::hand_excess`, the avatar's own measure) times how far the
                // palm stands edge-on to the head (the sine between the palm's normal and the
                // direction from the head bone to the wrist): the palm's outline reaches past
                // its balls within the palm's plane, not through its faces. Settled as balls,
                // a palm turned edge-on with its wrist ball resting on the skin left the voxel
                // figure's box palm 15.5 mm inside its box head (`brother`, frame 27); grown
                // whatever the palm's turn, a palm facing the mouth was held off it (`eat`),
                // and grown fingertips held the touching finger off the face.
                let s = side.index();
                let head = (t.wrist - world.position[HumanBone::Head.index()]).normalize_or_zero();
                // The palm's normal (a missing knuckle: none, and no growth).
                let edge = t.hand.as_ref().map_or(0.0, |h| {
                    let [i, l] = [Finger::Index, Finger::Little]
                        .map(|f| h.joints[3 * f.index()].unwrap_or(Vec3::ZERO));
                    i.cross(l).normalize_or_zero().cross(head).length()
                });
                let mut balls = [(Vec3::ZERO, 0.0); skin::HAND_SPHERES];
                for (k, (b, p)) in balls.iter_mut().zip(points).enumerate() {
                    *b = *p;
                    if k < 2 && p.1 == surface.palm_half[s] {
                        b.1 += edge * surface.hand_excess[s][0];
                    }
                }
                t.wrist += land * surface.settle(t.wrist, &balls[..points.len()], world, only);
            }
        }
        if o.hands {
            if let ([Some(l), Some(r)], Some(apart)) = (&mut *targets, faces.hands_apart) {
                let w = o.weight * (1.0 - chest::smooth(0.3, 0.5, apart));
                if w > 0.0 {
                    let (shift, pair) = skin::close_meeting(
                        l.wrist,
                        &spheres[0][..count[0]],
                        r.wrist,
                        &spheres[1][..count[1]],
                    );
                    l.wrist += 0.5 * w * shift;
                    r.wrist -= 0.5 * w * shift;
                    // Where they meet (between the pair that set the line, as far along it as
                    // their radii; relative to each wrist as moved): the point the wrist limits
                    // turn each hand about (`pipeline::reach`). Without it they turned the
                    // hands about the aligned fingertips and took them apart again (`again`:
                    // 3 cm between the skins of clapping hands; 0-3 mm without the limits).
                    let meet = pair.map(|(i, j)| {
                        let ((a, ra), (b, rb)) = (spheres[0][i], spheres[1][j]);
                        let (a, b) = (l.wrist + a, r.wrist + b);
                        a.lerp(b, ra / (ra + rb))
                    });
                    for (rep, wrist) in reports.iter_mut().zip([l.wrist, r.wrist]) {
                        if let Some(rep) = rep {
                            rep.hand_weight = rep.hand_weight.max(w);
                            if rep.hand_meet.is_none() {
                                rep.hand_meet = meet.map(|m| m - wrist);
                            }
                        }
                    }
                }
            }
        }
        rate.limit(start, targets);
        if o.colliders {
            for ((target, report), side) in
                targets.iter_mut().zip(reports.iter_mut()).zip(Side::BOTH)
            {
                let Some(t) = target.as_mut() else { continue };
                // Out of the body; then a hand the user is not touching anything with keeps
                // clear of it (its balls grown by CLEARANCE, lifted out along one line), the
                // clearance fading out as any touch blend comes in.
                let touch = report
                    .as_ref()
                    .map_or(0.0, |r| r.weight.max(r.chest_weight).max(r.hand_weight));
                let fade = crate::math::clamp(1.0 - touch, 0.0, 1.0);
                let own = &spheres[side.index()][..count[side.index()]];
                let mut push = surface.push(t.wrist, own, world);
                if fade > 0.0 {
                    // Each ball grown by the clearance and by how far the hand's skin reaches
                    // past balls of its kind (a palm ball has the palm's half-thickness; on a
                    // hand whose two radii are equal every ball takes the palm's excess, the
                    // larger so far on every avatar measured).
                    let s = side.index();
                    let [palm_excess, finger_excess] = surface.hand_excess[s];
                    let mut balls = [(Vec3::ZERO, 0.0); skin::HAND_SPHERES];
                    for (b, (p, m)) in balls.iter_mut().zip(own) {
                        let excess = if *m == surface.palm_half[s] {
                            palm_excess
                        } else {
                            finger_excess
                        };
                        *b = (*p, m + (CLEARANCE + excess) * fade);
                    }
                    push += surface.lift_out(t.wrist + push, &balls[..own.len()], world);
                }
                t.wrist += push;
                if let Some(r) = report.as_mut() {
                    r.push = push.length();
                }
            }
        }
    }

    /// The translation that puts a hand resting on the user's torso at `[u, v]` on the
    /// avatar's: its palm center carried to the same place across the avatar's torso (upper-arm
    /// joints for the shoulders, upper-leg joints for the hips), then settled onto the torso's
    /// skin. `None` without those joints or without a skin.
    fn chest_shift(
        &self,
        camera: CameraMapping,
        world: &WorldPose,
        wrist: Vec3,
        hand: &HandPoints,
        points: &[(Vec3, f32)],
        [u, v]: [f32; 2],
    ) -> Option<Vec3> {
        let surface = self.surface.as_ref()?;
        use crate::humanoid::bones::Side as S;
        let avatar_of = |pose: S| {
            if camera.pose_side_for(S::Left) == pose {
                S::Left
            } else {
                S::Right
            }
        };
        let (l, r) = (avatar_of(S::Left), avatar_of(S::Right));
        let at = |b: HumanBone| world.position[b.index()];
        let leg = |s: S| match s {
            S::Left => HumanBone::LeftUpperLeg,
            S::Right => HumanBone::RightUpperLeg,
        };
        let (hips_l, hips_r) = (leg(l), leg(r));
        let (sl, sr) = (at(l.arm()[1]), at(r.arm()[1]));
        let mid = 0.5 * (sl + sr);
        let hips = 0.5 * (at(hips_l) + at(hips_r));
        let place = mid + (sl - sr) * u + (hips - mid) * v;
        let palm = wrist + hand.avatar[0]?;
        let c = HumanBone::Chest.index();
        let forward = (world.rotation[c] * Vec3::Z).normalize_or(Vec3::Z);
        let mut shift = place - palm;
        shift -= forward * shift.dot(forward);
        // Onto the torso's skin, then out of the head and neck along one line where they are
        // in the way: a large head's lower front hangs over the upper chest (the chibi's),
        // and settling against all maps stopped the hand under the chin, 8-12 cm off the
        // chest; settled on the torso alone, a curved hand at the collar stayed in the chin
        // (74 mm on the man, `hungry`: the push alone did not get it out).
        let mut torso = [true; skin::MAP_BONES.len()];
        torso[skin::HEAD_MAP] = false;
        torso[skin::NECK_MAP] = false;
        let settle = surface.settle(wrist + shift, points, world, torso);
        let lift = surface.lift_out(wrist + shift + settle, points, world);
        let total = shift + settle + lift;
        total.is_finite().then_some(total)
    }

    /// The avatar's anchors and colliders with the avatar at rest (internal frame): for
    /// drawing them, and for apps checking the derived defaults.
    #[must_use]
    pub fn rest_model(&self, skeleton: &Skeleton) -> ([Vec3; ANCHORS], [Option<Shape>; 3]) {
        let mut world = WorldPose::default();
        skeleton.forward(
            &[glam::Quat::IDENTITY; crate::humanoid::bones::BONE_COUNT],
            &mut world,
        );
        (
            FaceAnchor::ALL.map(|a| self.anchor_world(a, &world)),
            self.colliders.shapes(&world),
        )
    }

    /// Face contact judged by the hand part nearest the face (rigs with a skin, whose hands
    /// have their finger joints): every finger landmark ([`hands::PARTS`]) with an avatar
    /// match is placed in the user's face frame as the aligned fingertip is (with pose input
    /// through [`face::pose_tip`]), its nearest anchor at distance `e_k` gives its blend
    /// `b_k` ([`face::blend`]), and its translation `d_k` puts the avatar's part on the warped
    /// point ([`face::warp`]). The hand moves by `w` times the mean of the `d_k` weighted by
    /// `b_k / e_k^2` (inverse distance, as [`hands::solve`]: continuous as parts come and go;
    /// a part exactly on an anchor decides), `w = contact.weight x max b_k`. So a fist whose
    /// knuckles rest on the forehead, its curled fingertips away from it, lands its
    /// knuckles. Returns the nearest part's anchor, `w`, the translation and the touching
    /// point (the parts' mean with the same weights, relative to the wrist); `None` when no
    /// part has an avatar match.
    fn face_by_parts(
        &self,
        hand: &HandPoints,
        touch: Finger,
        wrist: Vec3,
        user: &UserFace,
        faces: &UserFaces,
        (avatar_frame, avatar_local): (&FaceFrame, &[Vec3; ANCHORS]),
    ) -> Option<(FaceAnchor, f32, Vec3, Option<Vec3>)> {
        let o = &self.options;
        let mut nearest: Option<(FaceAnchor, f32)> = None;
        let mut beta = 0.0f32;
        let (mut sum, mut meet, mut total) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
        let mut exact: Option<(Vec3, Vec3)> = None;
        let seen = match hand.source {
            Source::Pose => face::camera_anchors(user, faces.camera),
            Source::Tracker => [Vec3::ZERO; ANCHORS],
        };
        // One loop over the parts (finger-major, base to tip), not a nested one: LLVM keeps
        // it rolled (the nested one cost 0.7 KiB of wasm, gzipped).
        for p in 0..hands::PARTS {
            let (finger, k) = (Finger::ALL[p / 4], p % 4);
            let f = finger.index();
            let avatar = if k == 3 {
                hand.avatar[1 + f]
            } else {
                hand.joints[3 * f + k]
            };
            let Some(avatar) = avatar else { continue };
            let part = hand.user_parts[4 * f + k];
            let user_point = match hand.source {
                Source::Pose => face::pose_tip_at(
                    &seen,
                    part,
                    hand.image_parts.map(|i| i[4 * f + k]),
                    faces.pose_image.as_ref(),
                    faces.camera,
                    o.depth_trust,
                ),
                Source::Tracker => part,
            };
            let local = user.frame.to_local(user_point);
            let (anchor, e) = face::nearest(local, &user.anchors);
            if nearest.is_none_or(|(_, best)| e < best) {
                nearest = Some((anchor, e));
            }
            let radius = if finger == touch && k == 3 {
                o.radius
            } else {
                PART_RADIUS * o.radius
            };
            let b = face::blend(e, radius);
            if b <= 0.0 {
                continue;
            }
            beta = beta.max(b);
            let warped = face::warp(local, &user.anchors, avatar_local);
            let d = avatar_frame.to_world(warped) - (wrist + avatar);
            if !d.is_finite() {
                continue;
            }
            if e < 1e-6 {
                exact.get_or_insert((d, avatar));
                continue;
            }
            let w = b / (e * e);
            sum += w * d;
            meet += w * avatar;
            total += w;
        }
        let (anchor, _) = nearest?;
        let w = o.weight * beta;
        let (delta, meet) = match exact {
            Some((d, m)) => (w * d, Some(m)),
            None if total > 0.0 => (w * (sum / total), Some(meet / total)),
            None => (Vec3::ZERO, None),
        };
        Some((anchor, w, delta, meet))
    }

    /// Moves both sides' wrist targets for contact (face, then hands, then body), filling
    /// `reports` for every side with a target. `world` is the avatar posed by this frame's
    /// rotations before the arms' IK (the head and torso as they will be shown); `fingers`
    /// per side (`[left, right]`) the finger whose tip slot makes face contact: the aligned
    /// finger, or what stands in for it ([`crate::align::AlignedPart::touch_finger`]).
    /// `rate` carries the corrections from frame to frame: each side's correction (face,
    /// chest, hands; not the push out of the body) changes by at most its step from last
    /// frame's ([`ContactRate::begin`], `contact.maxSpeed`). Allocates nothing.
    pub fn solve(
        &self,
        fingers: [Finger; 2],
        faces: &UserFaces,
        world: &WorldPose,
        targets: &mut [Option<SideTarget>; 2],
        reports: &mut [Option<ContactReport>; 2],
        rate: &mut ContactRate,
    ) {
        let o = &self.options;
        let start = targets.map(|t| t.map(|t| t.wrist));
        let h = HumanBone::Head.index();
        let avatar_frame = self.face.frame(world.position[h], world.rotation[h]);
        let avatar_local = self.face.local_anchors();
        for ((target, report), finger) in targets.iter_mut().zip(reports.iter_mut()).zip(fingers) {
            let tip = 1 + finger.index();
            let Some(t) = target.as_mut() else {
                *report = None;
                continue;
            };
            let mut r = ContactReport::default();
            let by_parts = self.surface.is_some()
                && t.hand.is_some_and(|h| h.joints.iter().any(Option::is_some));
            if let (true, Some(hand)) = (by_parts, &t.hand) {
                if let Some(user) = faces.for_source(hand.source) {
                    if let Some((anchor, w, delta, meet)) = self.face_by_parts(
                        hand,
                        finger,
                        t.wrist,
                        user,
                        faces,
                        (&avatar_frame, &avatar_local),
                    ) {
                        r.anchor = Some(anchor);
                        r.weight = w;
                        r.face_meet = meet;
                        if w > 0.0 && delta.is_finite() {
                            t.wrist += delta;
                        }
                    }
                }
            } else if let Some(hand) = &t.hand {
                if let (Some(user), Some(avatar_tip)) =
                    (faces.for_source(hand.source), hand.avatar[tip])
                {
                    let user_tip = match hand.source {
                        Source::Pose => face::pose_tip(
                            user,
                            hand.user[tip],
                            hand.image_tip,
                            faces.pose_image.as_ref(),
                            faces.camera,
                            o.depth_trust,
                        ),
                        Source::Tracker => hand.user[tip],
                    };
                    let local = user.frame.to_local(user_tip);
                    let (anchor, e) = face::nearest(local, &user.anchors);
                    let w = o.weight * face::blend(e, o.radius);
                    r.anchor = Some(anchor);
                    r.weight = w;
                    if w > 0.0 {
                        let warped = face::warp(local, &user.anchors, &avatar_local);
                        let target_tip = avatar_frame.to_world(warped);
                        let plain_tip = t.wrist + avatar_tip;
                        let delta = w * (target_tip - plain_tip);
                        if delta.is_finite() {
                            t.wrist += delta;
                        }
                    }
                }
            }
            *report = Some(r);
        }

        if o.hands {
            if let [Some(l), Some(r)] = targets {
                if let (Some(lh), Some(rh)) = (&l.hand, &r.hand) {
                    let unit = faces
                        .for_source(lh.source)
                        .map_or(PALMS_PER_HEAD * 0.5 * (lh.user_palm + rh.user_palm), |f| {
                            f.frame.size
                        });
                    if let Some(touch) =
                        hands::solve(lh, l.wrist, rh, r.wrist, unit, o.radius, o.weight)
                    {
                        l.wrist += touch.shift[0];
                        r.wrist += touch.shift[1];
                        for (rep, meet) in reports.iter_mut().zip(touch.meet) {
                            if let Some(rep) = rep {
                                rep.hand_weight = touch.weight;
                                rep.hand_meet = Some(meet);
                            }
                        }
                    }
                }
            }
        }

        if self.surface.is_some() {
            self.on_skin(faces, world, targets, reports, &start, rate);
        } else {
            rate.limit(&start, targets);
        }
        if self.surface.is_none() && o.colliders {
            let shapes = self.colliders.shapes(world);
            for ((target, report), finger) in
                targets.iter_mut().zip(reports.iter_mut()).zip(fingers)
            {
                let Some(t) = target.as_mut() else { continue };
                let tip = 1 + finger.index();
                let c = &self.colliders;
                let mut points = [(t.wrist, c.hand_margin); 3];
                let mut n = 1;
                if let Some(hand) = t.body_points() {
                    for (k, margin) in [(0, c.hand_margin), (tip, c.tip_margin)] {
                        if let Some(a) = hand.avatar[k] {
                            points[n] = (t.wrist + a, margin);
                            n += 1;
                        }
                    }
                }
                // A finger on the face wins over the colliders: the push fades out as the
                // face contact fades in (the hand's orientation comes from the user's, so
                // while the avatar's head does not turn as the user's does, a hand touching
                // the chin from below may graze the neck).
                let face = report.as_ref().map_or(0.0, |r| r.weight);
                let push = (1.0 - face) * self.colliders.push(&shapes, &points[..n]);
                t.wrist += push;
                if let Some(r) = report.as_mut() {
                    r.push = push.length();
                }
            }
        }
    }
}

/// How fast the contact correction of a wrist target (face, chest and hands; not the push
/// out of the body) may change: the history carried between frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactRate {
    /// Each side's correction last frame (`[left, right]`; zero: none, or no hand).
    shift: [Vec3; 2],
    /// Largest change of a correction this frame (m; infinite: no limit).
    step: f32,
    /// Each side's chest cue as held last frame (see [`CHEST_RELEASE`]).
    chest: [f32; 2],
    /// Seconds since the last frame (0: the first of a session).
    dt: f32,
}

/// Seconds a hand on the chest takes to let go when the chest cue drops (from full weight
/// to none): the cue, read from one image, flickers for a frame or two while a hand moves on
/// the chest (`hungry`'s curved hand sliding down: on the long-armed avatar the hand jumped
/// 10 cm off and back between frames, and the turn limit, slowing those jumps, took it through
/// the chest). A cue that comes back within it finds the hand still there; one that stays
/// away lets go over 6 frames at 30 fps.
pub const CHEST_RELEASE: f32 = 0.2;

impl Default for ContactRate {
    fn default() -> Self {
        ContactRate {
            shift: [Vec3::ZERO; 2],
            step: f32::INFINITY,
            chest: [0.0; 2],
            dt: 0.0,
        }
    }
}

impl ContactRate {
    /// Starts a frame `dt` seconds after the last (`None`: first of a session) with corrections
    /// changing at most `speed` m/s.
    pub fn begin(&mut self, dt: Option<f32>, speed: f32) {
        match dt {
            Some(dt) if speed > 0.0 => self.step = speed * dt,
            Some(_) => self.step = f32::INFINITY,
            None => *self = ContactRate::default(),
        }
        if let Some(dt) = dt {
            self.dt = crate::math::clamp(dt, 0.0, 1.0);
        }
    }

    /// Forgets last frame's corrections (a frame without any target).
    pub fn forget(&mut self) {
        self.shift = [Vec3::ZERO; 2];
        self.chest = [0.0; 2];
    }

    /// Side `k`'s chest cue `w` this frame, held against last frame's (falling by at most
    /// `dt / CHEST_RELEASE`); `None`: no cue (no hand or no torso), which lets go at once.
    fn hold_chest(&mut self, k: usize, w: Option<f32>) -> f32 {
        let held = match w {
            Some(w) => w.max(self.chest[k] - self.dt / CHEST_RELEASE),
            None => 0.0,
        };
        let held = if held.is_finite() { held.max(0.0) } else { 0.0 };
        self.chest[k] = held;
        held
    }

    /// Limits each side's correction (`targets` against `start`) to `step` from last frame's.
    fn limit(&mut self, start: &[Option<Vec3>; 2], targets: &mut [Option<SideTarget>; 2]) {
        for k in 0..2 {
            let (Some(s), Some(t)) = (start[k], targets[k].as_mut()) else {
                self.shift[k] = Vec3::ZERO;
                continue;
            };
            let shift = t.wrist - s;
            let change = shift - self.shift[k];
            let len = change.length();
            let kept = if len > self.step {
                self.shift[k] + change * (self.step / len)
            } else {
                shift
            };
            if kept.is_finite() {
                t.wrist = s + kept;
                self.shift[k] = kept;
            }
        }
    }
}

/// The blend radius of the hand's other parts (every finger landmark but the aligned
/// fingertip) over `contact.radius`, for face contact by the hand part nearest the face.
pub const PART_RADIUS: f32 = 0.6;

/// Head breadth over palm length on an adult (0.145 m / 0.09 m): the unit of the hand contact
/// radius when no user face is known.
pub const PALMS_PER_HEAD: f32 = HEAD_BREADTH_M / 0.09;
const HEAD_BREADTH_M: f32 = face::HEAD_BREADTH;
