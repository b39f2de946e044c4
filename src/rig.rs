//! The per-frame pipeline: MediaPipe frame in, normalized-bone rotations, IK targets and
//! alignment reports out.
//!
//! [`Rig::solve`] runs named stages, each feature in one of them:
//!
//! 1. **select hands** ([`Rig::select_hands`]): which tracked hand drives each avatar side;
//!    low scores ignored, labels that contradict the pose wrists reassigned
//!    (`options.handedness`), two hands on one side resolved.
//! 2. **pose** ([`Rig::observe_pose`]): the pose landmarks, One Euro filtered
//!    ([`crate::filter`]), feed body-scale calibration ([`crate::body`]).
//! 3. **torso** ([`Rig::torso_stage`]): the torso bones from the app (`frame.torso`) or tracked
//!    from `body` joints or the pose, eased over tracking loss ([`crate::torso`]); the user's
//!    upper-torso frame measured on the pose; forward kinematics of the posed torso places
//!    each arm's anchor (its upper-arm joint and torso frame);
//! 4. per side, **hand** ([`Rig::solve_hand`]): the hand's landmarks mapped to the avatar frame
//!    and filtered, then hand orientation and finger rotations ([`crate::hand`]);
//! 5. per side, **wrist source** ([`Rig::wrist_source`]): the wrist from `wrists` (filtered) or
//!    from the pose mapped relative to the torso ([`crate::body`]), with the elbow as pole;
//! 6. **targets** ([`Rig::plan_target`] per side, then [`Rig::contact_targets`] for both
//!    sides together): the wrist IK target by fingertip alignment ([`crate::align`]) from
//!    forward kinematics of *this* frame's hand, then moved for self-contact
//!    ([`crate::contact`]: a finger on the face lands on the avatar's face where the posed
//!    torso put it, touching hands stay touching, hands stay out of the body); both sides'
//!    targets exist before any IK;
//! 7. per side, **IK** ([`Rig::reach_target`]): the arm solver ([`crate::ik`]) reaches the
//!    target from the posed torso;
//! 8. **ease** ([`Rig::ease`]): groups whose tracking was lost hold, then ease to rest (a
//!    shoulder to the torso's rotation of it); returning ones blend in
//!    ([`crate::filter::dropout`]); rotations keep their hemisphere;
//! 9. **report** ([`Rig::report`]): forward kinematics of the whole avatar, its fingertips,
//!    the retargeting reports.
//!
//! [`Rig::reset`] clears the history of every stage.

use glam::{Quat, Vec3};

use crate::align::{self, AlignmentReport};
use crate::body::{ArmAnchor, BodyMapper};
use crate::bones::Finger;
use crate::bones::{HumanBone, Side, BONE_COUNT};
use crate::contact::{
    ContactReport, ContactSolver, HandPoints, SideTarget, Source, UserFace, UserFaces,
};
use crate::error::Result;
use crate::filter::{Clock, OneEuroQuat, PointFilters, Presence};
use crate::hand::{HandSolver, HandStatus, RetargetReport};
use crate::ik::ArmSolverState;
use crate::mediapipe::{
    hand_landmark, pose_landmark, CameraMapping, FrameInput, PoseObservation, TrackerFace,
    HAND_LANDMARKS, MAX_HANDS, POSE_LANDMARKS,
};
pub use crate::options::{HandednessPolicy, RigOptions};
use crate::skeleton::{Skeleton, WorldPose};
use crate::torso::{
    self, BodyJoint, TorsoPoints, TorsoSolver, TorsoSource, BODY_JOINT_COUNT, TORSO_BONES,
};

/// A hand's label contradicts the pose when its wrist is nearer the other side's pose wrist
/// than this fraction of its distance to its own side's (in the image).
pub const CONTRADICTION_RATIO: f32 = 0.5;

/// A wrist IK target in the internal frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkTarget {
    /// Where the avatar's hand bone (wrist joint) should be.
    pub position: Vec3,
    /// World rotation the avatar's normalized hand bone should have.
    pub rotation: Quat,
}

/// Everything one `solve` produces, in handrig's internal frame. Fixed-size: reused frame to
/// frame without allocation.
#[derive(Clone, Debug, PartialEq)]
pub struct SolveOutput {
    /// Local rotation of every normalized bone (identity where nothing was solved).
    pub local: [Quat; BONE_COUNT],
    /// Which bones were solved this frame (only these are reported).
    pub solved: [bool; BONE_COUNT],
    /// Forward kinematics of `local`.
    pub world: WorldPose,
    /// Wrist IK targets per side (`[left, right]`), when a pose wrist was known.
    pub ik_targets: [Option<IkTarget>; 2],
    /// Fingertip-alignment reports per side.
    pub alignment: [Option<AlignmentReport>; 2],
    /// The tracked hand that drove each side this frame, if any.
    pub hands: [Option<TrackedHand>; 2],
    /// The avatar's fingertips per side (`[left, right]`), thumb to little, world positions
    /// in the internal frame, every strategy: the distal bone extended by the anatomical
    /// ratio of [`crate::align::tip_offset`] (the point `alignment.point: "tip"` aligns).
    /// `None` where the avatar lacks that finger's distal bone.
    pub fingertips: [[Option<Vec3>; 5]; 2],
    /// What `handStrategy: "retarget"` did per side this frame (`None` for other strategies
    /// and for sides not freshly solved); targets are world positions in the internal frame,
    /// like [`SolveOutput::fingertips`].
    pub retarget: [Option<RetargetReport>; 2],
    /// What became of each input hand (in the frame's order; `Unused` past its count).
    pub hand_use: [HandUse; MAX_HANDS],
    /// What self-contact did per side (`[left, right]`): `Some` for every side with a wrist
    /// IK target while `contact.enabled`.
    pub contact: [Option<ContactReport>; 2],
}

/// What the rig did with one tracked hand of the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HandUse {
    /// No such hand in the frame.
    #[default]
    Unused,
    /// It drove this avatar side (see [`TrackedHand::reassigned`]).
    Drove(Side),
    /// Ignored: its score is below `minHandScore`.
    LowScore,
    /// Ignored: another hand drove its side (higher score, or nearer that side's pose wrist).
    Duplicate,
    /// Ignored: its label contradicts the pose (`handedness: "drop"`).
    Contradicted,
}

/// Which tracked hand drove an avatar side, and whether its rotations are fresh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackedHand {
    /// [`HandStatus::Solved`] (from this frame), [`HandStatus::Held`] (this frame's hand was
    /// degenerate; the previous rotations were kept) or [`HandStatus::Skipped`] (degenerate
    /// with nothing to keep, or the avatar has no usable palm).
    pub status: HandStatus,
    /// Its handedness score.
    pub score: f32,
    /// Its index in the frame's hands.
    pub index: usize,
    /// Whether its label contradicted the pose and it was reassigned to this side.
    pub reassigned: bool,
}

impl Default for SolveOutput {
    fn default() -> Self {
        SolveOutput {
            local: [Quat::IDENTITY; BONE_COUNT],
            solved: [false; BONE_COUNT],
            world: WorldPose::default(),
            ik_targets: [None, None],
            alignment: [None, None],
            hands: [None, None],
            hand_use: [HandUse::Unused; MAX_HANDS],
            fingertips: [[None; 5]; 2],
            retarget: [None, None],
            contact: [None, None],
        }
    }
}

/// The solver for one avatar: owns the skeleton, the options and every buffer, so
/// [`Rig::solve`] allocates nothing.
#[derive(Clone, Debug)]
pub struct Rig {
    skeleton: Skeleton,
    options: RigOptions,
    hands: HandSolver,
    body: BodyMapper,
    arms: ArmSolverState,
    contact: ContactSolver,
    landmarks: [Vec3; HAND_LANDMARKS],
    driven: [bool; BONE_COUNT],
    clock: Clock,
    /// Landmark filters per avatar side, the pose's, and the tracker wrists'.
    hand_filters: [PointFilters<HAND_LANDMARKS>; 2],
    pose_filters: PointFilters<POSE_LANDMARKS>,
    wrist_filters: [WristFilter; 2],
    /// This frame's pose, filtered.
    pose: Option<PoseObservation>,
    /// Presence of each side's hand and arm ([`Group`]), for the dropout easing.
    presence: [[Presence; 3]; 2],
    /// The rotations shown last frame, and the anchors of running blends.
    shown: [Quat; BONE_COUNT],
    anchor: [Quat; BONE_COUNT],
    /// The torso stage: the avatar's torso, the shrug's neutral, the torso's easing.
    torso: TorsoSolver,
    /// Filters of the body-tracker joints.
    body_filters: PointFilters<BODY_JOINT_COUNT>,
    /// This frame's torso rotation of each shoulder bone (`[left, right]`): what an arm's
    /// shoulder eases back to when the arm is lost.
    shoulder_base: [Quat; 2],
    /// The arm solver's turn of each shoulder on top of `shoulder_base`, as shown last frame,
    /// and the anchor of its running blend.
    shoulder_turn_shown: [Quat; 2],
    shoulder_turn_anchor: [Quat; 2],
    /// Where each side's pose arm is placed this frame (posed upper-arm joint, torso turn).
    anchors: [Option<ArmAnchor>; 2],
    /// This frame's turn from the user's upper-torso frame (on the pose) to the avatar's,
    /// when measured (not with `torso: "off"`): applied to the whole pose-driven arm and hand.
    turn: Option<Quat>,
}

/// The bone groups that come and go with tracking, per side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Group {
    /// The fingers: tracked with a hand.
    Fingers = 0,
    /// The hand bone: tracked with a hand, or a tracker wrist's rotation.
    Hand = 1,
    /// The shoulder, upper and lower arm: tracked with a wrist (tracker or pose).
    Arm = 2,
}

/// Filters of one side's tracker wrist (position and rotation).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct WristFilter {
    position: PointFilters<1>,
    rotation: OneEuroQuat,
}

/// The hand picked for a side by [`Rig::select_hands`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pick {
    index: usize,
    reassigned: bool,
    /// Image distance from the hand's wrist to this side's pose wrist, when known.
    distance: Option<f32>,
    score: f32,
}

/// Where an arm reaches this frame, from [`Rig::wrist_source`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct WristSource {
    /// The wrist (internal frame).
    position: Vec3,
    /// The hand's world rotation from the tracker, if given.
    rotation: Option<Quat>,
    /// Scale from the user's hand to the avatar's (body scale for pose input, 1 for trackers).
    scale: f32,
    /// Where the elbow should point (pose elbow), if known.
    pole: Option<Vec3>,
}

/// What a side's arm does this frame, decided by [`Rig::plan_target`] before any IK. Two per
/// frame on the stack: the size difference between variants does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
enum Plan {
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
    },
}

impl Rig {
    /// Creates a rig for `skeleton`.
    ///
    /// # Errors
    /// Options out of range (field named in the message).
    pub fn new(skeleton: Skeleton, options: RigOptions) -> Result<Self> {
        options.validate()?;
        let mut hands = HandSolver::new(&skeleton, options.hand_strategy)?;
        hands.set_retarget_options(options.retarget)?;
        let contact = ContactSolver::new(&skeleton, &options.contact);
        let body = BodyMapper::new(&skeleton, &options.calibration);
        let arms = ArmSolverState::with_options(&skeleton, options.arm_solver, &options.arm)?;
        let mut driven = [false; BONE_COUNT];
        for side in Side::BOTH {
            let [shoulder, upper, lower, hand] = side.arm();
            let fingers = crate::bones::Finger::ALL
                .iter()
                .flat_map(|f| side.finger(*f));
            for b in [upper, lower, hand].into_iter().chain(fingers) {
                driven[b.index()] = skeleton.has(b);
            }
            // The shoulder when the arm option may turn it on far reaches, or the torso
            // shrugs it.
            driven[shoulder.index()] = skeleton.has(shoulder)
                && (arms.moves_shoulder(side) || options.torso == TorsoSource::Pose);
        }
        if options.torso == TorsoSource::Pose {
            for b in TORSO_BONES {
                driven[b.index()] = skeleton.has(b);
            }
        }
        let torso = TorsoSolver::new(&skeleton, options.calibration.frames);
        Ok(Rig {
            skeleton,
            options,
            hands,
            body,
            arms,
            contact,
            landmarks: [Vec3::ZERO; HAND_LANDMARKS],
            driven,
            clock: Clock::default(),
            hand_filters: [PointFilters::default(); 2],
            pose_filters: PointFilters::default(),
            wrist_filters: [WristFilter::default(); 2],
            pose: None,
            presence: [[Presence::default(); 3]; 2],
            shown: [Quat::IDENTITY; BONE_COUNT],
            anchor: [Quat::IDENTITY; BONE_COUNT],
            torso,
            body_filters: PointFilters::default(),
            shoulder_base: [Quat::IDENTITY; 2],
            shoulder_turn_shown: [Quat::IDENTITY; 2],
            shoulder_turn_anchor: [Quat::IDENTITY; 2],
            anchors: [None, None],
            turn: None,
        })
    }

    /// Whether the rig drives `bone`: it writes the bone's rotation every frame (solved, held
    /// or back at rest), so an app applies it every frame. The hand, finger and arm bones the
    /// avatar has (the shoulders when the arm option may turn them); with `torso: "pose"` also
    /// the torso bones (hips, spine, chest, upperChest, neck, head, shoulders) it has; other
    /// bones are left to the app.
    #[inline]
    #[must_use]
    pub fn drives(&self, bone: HumanBone) -> bool {
        self.driven[bone.index()]
    }

    /// Forgets everything carried between frames (filters, dropout holds and blends, held
    /// hands, the elbow swivel, body-scale calibration): the next frame solves as if it were
    /// the first.
    pub fn reset(&mut self) {
        self.body.reset();
        self.torso.reset_calibration();
        self.restart_history();
    }

    /// The per-frame history of the filters and the easing (not calibration).
    fn restart_history(&mut self) {
        self.clock.reset();
        self.new_session();
    }

    /// Everything carried from one frame to the next, but the clock (which already holds the
    /// new session's first time) and calibration: a frame after a seek or a long gap solves
    /// exactly as the first frame of a new rig.
    fn new_session(&mut self) {
        self.hands.reset();
        self.arms.reset();
        self.hand_filters = [PointFilters::default(); 2];
        self.pose_filters.reset();
        self.wrist_filters = [WristFilter::default(); 2];
        self.presence = [[Presence::default(); 3]; 2];
        self.shown = [Quat::IDENTITY; BONE_COUNT];
        self.torso.restart();
        self.body_filters.reset();
        self.shoulder_turn_shown = [Quat::IDENTITY; 2];
        self.shoulder_turn_anchor = [Quat::IDENTITY; 2];
        self.pose = None;
        self.anchors = [None, None];
        self.turn = None;
    }

    /// The avatar's skeleton.
    #[must_use]
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The options in force.
    #[must_use]
    pub fn options(&self) -> &RigOptions {
        &self.options
    }

    /// Body-scale calibration state.
    #[must_use]
    pub fn body(&self) -> &BodyMapper {
        &self.body
    }

    /// The arm solvers (which method, last iteration counts).
    #[must_use]
    pub fn arms(&self) -> &ArmSolverState {
        &self.arms
    }

    /// Restarts body-scale calibration (and the torso's neutral shoulder height).
    /// The avatar's side of self-contact: its face (anchors) and body colliders.
    #[must_use]
    pub fn contact(&self) -> &ContactSolver {
        &self.contact
    }

    /// Restarts body-scale calibration (and the torso's neutral shoulder height).
    pub fn reset_calibration(&mut self) {
        self.body.reset();
        self.torso.reset_calibration();
    }

    /// The torso stage (the avatar's torso bone the arms hang from, the shrug's neutral).
    #[must_use]
    pub fn torso(&self) -> &TorsoSolver {
        &self.torso
    }

    /// The torso's rotation of `side`'s shoulder bone in the last solve (internal frame): the
    /// shrug (`torso: "pose"`) or the app's rotation of it, before the arm solver's turn on
    /// far reaches. What a lost arm's shoulder eases back to.
    #[must_use]
    pub fn shoulder_base(&self, side: Side) -> Quat {
        self.shoulder_base[side.index()]
    }

    /// Calibrates the hand scale of `handStrategy: "retarget"` (avatar hand over user hand)
    /// on each side from the last hand solved there, which should be an open, flat hand
    /// (the seed's bounding-box scale; see [`crate::hand::retarget`]). Until then, or after
    /// a refused calibration, the scale comes from the hand's stable lengths. Returns the new
    /// scale per side (`[left, right]`), `None` where nothing changed (no hand solved yet,
    /// fingers not straight, or no retargetable fingers). Any strategy may calibrate.
    pub fn calibrate_hand_scale(&mut self) -> [Option<f32>; 2] {
        Side::BOTH.map(|side| self.hands.calibrate_hand_scale(side))
    }

    /// Solves one frame into `out` (internal frame; see [`Rig::export_rotation`] and
    /// [`Rig::export_position`] for the model frame). Allocates nothing.
    ///
    /// # Errors
    /// Invalid input (non-finite numbers, and points beyond [`COORDINATE_LIMIT`], are rejected
    /// before any state changes). Degenerate hands are not errors: that hand is skipped and
    /// its previous rotations are kept.
    pub fn solve(&mut self, frame: &FrameInput, out: &mut SolveOutput) -> Result<()> {
        validate_frame(frame)?;
        let camera = self.options.camera();
        let dt = self.clock.advance(frame.time_ms);
        if dt.is_none() {
            // A new session (first frame, time going back, a long gap): no blending across,
            // and no continuity either (the forearm's twist branch, the elbow swivel and the
            // IK warm start are carried from the frame before, which is not this one's past).
            self.new_session();
        }
        out.solved = [false; BONE_COUNT];
        out.ik_targets = [None, None];
        out.alignment = [None, None];
        out.hands = [None, None];
        out.hand_use = [HandUse::Unused; MAX_HANDS];
        out.retarget = [None, None];
        out.contact = [None, None];
        // Everything not solved this frame goes back to rest (then the easing stage decides).
        out.local = [Quat::IDENTITY; BONE_COUNT];

        let picks = self.select_hands(frame, camera, out);
        self.observe_pose(frame, camera, dt);
        // The torso (from the app or tracking), and its forward kinematics: the world pose the
        // arms hang from, once per frame (arms and hands do not move it).
        self.torso_stage(frame, camera, dt, out);
        let mut plans = [Plan::Rest; 2];
        for side in Side::BOTH {
            let hand_rotation = self.solve_hand(side, frame, picks[side.index()], dt, out);
            let source = self.wrist_source(side, frame, dt);
            plans[side.index()] = self.plan_target(side, frame, hand_rotation, source, out);
        }
        self.contact_targets(frame, &mut plans, out);
        for side in Side::BOTH {
            self.reach_target(side, plans[side.index()], out);
        }
        let eased = self.ease(frame.time_ms, out);
        self.report(eased, out);
        Ok(())
    }

    /// Stage 9: forward kinematics of what is shown, the avatar's fingertips, and the
    /// retargeting reports placed on the avatar. `eased[side]`: the easing blended that side's
    /// arm, hand or fingers away from what was solved, so its alignment error (measured on the
    /// solve) is measured again on what is shown.
    fn report(&self, eased: [bool; 2], out: &mut SolveOutput) {
        // The torso stage posed the body, which nothing has turned since (the later stages turn
        // the arms, hands and fingers, the easing also the shoulders): the arms from their roots.
        for side in Side::BOTH {
            self.skeleton.forward_arm(side, &out.local, &mut out.world);
        }
        for side in Side::BOTH {
            let s = side.index();
            if let (true, Some(report)) = (eased[s], out.alignment[s].as_mut()) {
                let hand = side.hand().index();
                report.error = align::avatar_offset(
                    &self.skeleton,
                    side,
                    &self.options.alignment,
                    out.world.rotation[hand],
                    &out.local,
                )
                .map_or(f32::NAN, |a| {
                    (out.world.position[hand] + a - report.target_dip).length()
                });
            }
            for finger in Finger::ALL {
                out.fingertips[s][finger.index()] =
                    align::fingertip(&self.skeleton, &out.world, side, finger);
            }
            let fresh = out.hands[s].is_some_and(|h| h.status == HandStatus::Solved);
            if let (true, Some(report)) = (fresh, self.hands.retarget_report(side)) {
                let hand = side.hand().index();
                let (p, q) = (out.world.position[hand], out.world.rotation[hand]);
                out.retarget[s] = Some(RetargetReport {
                    targets: report.targets.map(|t| t.map(|t| p + q * t)),
                    ..*report
                });
            }
        }
    }

    /// Stage 1: which tracked hand drives each side (`[left, right]`), recording what became
    /// of every hand in `out.hand_use`.
    fn select_hands(
        &self,
        frame: &FrameInput,
        camera: CameraMapping,
        out: &mut SolveOutput,
    ) -> [Option<Pick>; 2] {
        // The pose wrists in the image, per avatar side, when both are visible.
        let pose_wrists = match (&frame.pose, &frame.pose_image) {
            (Some(pose), Some(image)) if self.options.handedness != HandednessPolicy::Trust => {
                let at = |side: Side| {
                    let k = match camera.pose_side_for(side) {
                        Side::Left => pose_landmark::LEFT_WRIST,
                        Side::Right => pose_landmark::RIGHT_WRIST,
                    };
                    (pose.visibility[k] >= self.options.calibration.min_visibility)
                        .then(|| image[k].truncate())
                };
                at(Side::Left).zip(at(Side::Right)).map(|(l, r)| [l, r])
            }
            _ => None,
        };
        let mut picks: [Option<Pick>; 2] = [None, None];
        for (index, h) in frame.hands().iter().enumerate() {
            if h.score < self.options.min_hand_score {
                out.hand_use[index] = HandUse::LowScore;
                continue;
            }
            let mut side = camera.avatar_side(h.handedness);
            let mut reassigned = false;
            let wrist = h.image.map(|img| img[hand_landmark::WRIST].truncate());
            let distance_to = |side: Side| {
                pose_wrists
                    .zip(wrist)
                    .map(|(pw, w)| (w - pw[side.index()]).length())
            };
            if let (Some(own), Some(other)) = (distance_to(side), distance_to(side.opposite())) {
                if other < CONTRADICTION_RATIO * own {
                    match self.options.handedness {
                        HandednessPolicy::Reassign => {
                            side = side.opposite();
                            reassigned = true;
                        }
                        HandednessPolicy::Drop => {
                            out.hand_use[index] = HandUse::Contradicted;
                            continue;
                        }
                        HandednessPolicy::Trust => {}
                    }
                }
            }
            let pick = Pick {
                index,
                reassigned,
                distance: distance_to(side),
                score: h.score,
            };
            let slot = &mut picks[side.index()];
            let loser = match *slot {
                None => {
                    *slot = Some(pick);
                    None
                }
                Some(current) => {
                    // Nearer the side's pose wrist wins when known, else the higher score.
                    let better = match (pick.distance, current.distance) {
                        (Some(a), Some(b)) => a < b,
                        _ => pick.score > current.score,
                    };
                    if better {
                        *slot = Some(pick);
                        Some(current.index)
                    } else {
                        Some(index)
                    }
                }
            };
            if let Some(l) = loser {
                out.hand_use[l] = HandUse::Duplicate;
            }
        }
        for side in Side::BOTH {
            if let Some(p) = picks[side.index()] {
                out.hand_use[p.index] = HandUse::Drove(side);
            }
        }
        picks
    }

    /// Stage 2: this frame's pose, filtered, observed for body-scale calibration.
    fn observe_pose(&mut self, frame: &FrameInput, camera: CameraMapping, dt: Option<f32>) {
        self.pose = frame.pose;
        if let Some(pose) = self.pose.as_mut() {
            if self.options.filter.enabled {
                let o = self.options.filter.one_euro();
                // Only the landmarks the rig reads: the pose's hands and legs are not used.
                self.pose_filters.apply_to(
                    &mut pose.world,
                    &pose_landmark::READ,
                    frame.time_ms,
                    dt,
                    &o,
                );
            }
            self.body.observe(&self.skeleton, pose, camera);
        }
    }

    /// Stage 3: the torso bones into `out.local` (see [`crate::torso`]): the app's
    /// (`frame.torso`), tracked (`torso: "pose"`, from `body` joints or the pose) with the
    /// app's bones winning, or rest (`"off"`). Then each arm's anchor for the pose mapping:
    /// the posed upper-arm joint, and the turn from the user's upper-torso frame (measured on
    /// the pose) to the avatar's.
    fn torso_stage(
        &mut self,
        frame: &FrameInput,
        camera: CameraMapping,
        dt: Option<f32>,
        out: &mut SolveOutput,
    ) {
        let source = self.options.torso;
        let min_visibility = self.options.calibration.min_visibility;
        let version = self.skeleton.version();
        // The user's torso on the pose (also what the pose arms are measured against).
        let pose_measure = match (source, &self.pose) {
            (TorsoSource::Off, _) | (_, None) => None,
            (_, Some(pose)) => Some(torso::measure(&TorsoPoints::from_pose(
                pose,
                camera,
                min_visibility,
            ))),
        };
        if source == TorsoSource::Pose {
            let measure = match frame.body {
                Some(mut body) => {
                    if self.options.filter.enabled {
                        let o = self.options.filter.one_euro();
                        self.body_filters
                            .apply(&mut body.position, frame.time_ms, dt, &o);
                    }
                    torso::measure(&TorsoPoints::from_body(&body, version, min_visibility))
                }
                None => pose_measure.unwrap_or_default(),
            };
            let timing = self.options.dropout.effective();
            self.torso.track(
                &self.skeleton,
                &measure,
                frame.time_ms,
                &timing,
                &mut out.local,
                &mut out.solved,
            );
        }
        if source != TorsoSource::Off {
            // The app's bones (in "pose" mode they win over the tracked ones).
            for (bone, q) in TORSO_BONES.iter().zip(frame.torso.iter()) {
                if let Some(q) = q {
                    out.local[bone.index()] = version.rotation_to_internal(*q).normalize();
                    out.solved[bone.index()] = self.skeleton.has(*bone);
                }
            }
        }
        for side in Side::BOTH {
            self.shoulder_base[side.index()] = out.local[side.arm()[0].index()];
        }
        // Anchors: forward kinematics of the torso alone (arms at rest). The fingers are posed
        // with their arm (`align::alignment_error`, the contact stage) or in the report.
        self.skeleton.forward_body(&out.local, &mut out.world);
        let top = self.torso.top();
        let avatar_frame = out.world.rotation[top.index()] * self.torso.rest_upper();
        self.turn = pose_measure
            .and_then(|m| m.upper)
            .map(|user| (avatar_frame * user.conjugate()).normalize())
            .filter(|q| q.is_finite());
        for side in Side::BOTH {
            let upper = side.arm()[1];
            self.anchors[side.index()] = self.skeleton.has(upper).then(|| ArmAnchor {
                shoulder: out.world.position[upper.index()],
                rotation: self.turn.unwrap_or(Quat::IDENTITY),
            });
        }
    }

    /// Stage 4: the side's hand (landmarks to the avatar frame, filtered, solved). Returns the
    /// hand's world rotation when solved or held.
    fn solve_hand(
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
        let turn = match (frame.wrists[side.index()], &self.pose, self.turn) {
            (None, Some(_), Some(turn)) => turn,
            _ => Quat::IDENTITY,
        };
        for (dst, src) in self.landmarks.iter_mut().zip(h.world.iter()) {
            *dst = turn * camera.to_avatar(*src);
        }
        if self.options.filter.enabled {
            let o = self.options.filter.one_euro();
            self.hand_filters[side.index()].apply(&mut self.landmarks, frame.time_ms, dt, &o);
        }
        let hand_rotation = self
            .hands
            .solve(&self.skeleton, side, &self.landmarks, &mut out.local);
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
    fn wrist_source(
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
        let pose = self.pose.as_ref()?;
        let anchor = self.anchors[side.index()]?;
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

    /// Stage 6a: the side's wrist IK target by fingertip alignment from this frame's hand
    /// (no IK yet), and the hand's contact points while its landmarks are at hand.
    fn plan_target(
        &mut self,
        side: Side,
        frame: &FrameInput,
        hand_rotation: Option<Quat>,
        source: Option<WristSource>,
        out: &mut SolveOutput,
    ) -> Plan {
        let Some(hand_rot) = hand_rotation.or(source.and_then(|s| s.rotation)) else {
            // No hand and no wrist rotation: with a wrist the arm can still reach it.
            return match source {
                Some(s) => Plan::Reach {
                    target: s.position,
                    hand_rotation: None,
                    pole: s.pole,
                    points: None,
                },
                None => Plan::Rest,
            };
        };

        let Some(source) = source else {
            // Hands only: the arm stays at rest and the hand takes the solved world rotation.
            return Plan::HandOnly(hand_rot);
        };

        // A held hand (degenerate landmarks this frame) keeps its rotations but its
        // landmarks cannot place the fingertip: align only freshly solved hands.
        let fresh = out.hands[side.index()].is_some_and(|h| h.status == HandStatus::Solved);
        let target = if fresh {
            let a = align::wrist_target(
                &self.skeleton,
                side,
                &self.options.alignment,
                source.position,
                &self.landmarks,
                source.scale,
                hand_rot,
                &out.local,
            );
            out.alignment[side.index()] = Some(a);
            a.ik_wrist
        } else {
            source.position
        };
        let hand_index = out.hands[side.index()].map(|h| h.index);
        let points = (fresh && self.options.contact.enabled)
            .then(|| self.hand_points(side, frame, hand_index, &source, hand_rot, &out.local))
            .flatten();
        Plan::Reach {
            target,
            hand_rotation: Some(hand_rot),
            pole: source.pole,
            points,
        }
    }

    /// The hand's contact points ([`HandPoints`]): the user's from this side's landmarks
    /// placed on the user's wrist (the tracker wrist, or the pose wrist landmark in user
    /// space, whichever [`Rig::wrist_source`] used), the avatar's from forward kinematics of
    /// this frame's hand rotation and finger rotations.
    fn hand_points(
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
            (Source::Pose, camera.to_avatar(self.pose.as_ref()?.world[k]))
        };
        let lm = &self.landmarks;
        let palm_center = (lm[hl::WRIST]
            + lm[hl::INDEX_MCP]
            + lm[hl::MIDDLE_MCP]
            + lm[hl::RING_MCP]
            + lm[hl::PINKY_MCP])
            / 5.0;
        let mut user = [Vec3::ZERO; crate::contact::POINTS];
        user[0] = wrist + palm_center - lm[hl::WRIST];
        let mut avatar = [None; crate::contact::POINTS];
        // The avatar's palm center: its hand joint and the proximal joints it has.
        let mut sum = Vec3::ZERO;
        let mut n = 1.0;
        for f in [Finger::Index, Finger::Middle, Finger::Ring, Finger::Little] {
            let proximal = side.finger(f)[0];
            if self.skeleton.has(proximal) {
                sum += self.skeleton.rest_local(proximal);
                n += 1.0;
            }
        }
        avatar[0] = Some(hand_rotation * (sum / n));
        let tip_options = align::AlignmentOptions {
            point: align::AlignPoint::Tip,
            ..self.options.alignment
        };
        for finger in Finger::ALL {
            let k = 1 + finger.index();
            user[k] = wrist + lm[finger.landmarks()[3]] - lm[hl::WRIST];
            avatar[k] = align::avatar_offset(
                &self.skeleton,
                side,
                &align::AlignmentOptions {
                    finger,
                    ..tip_options
                },
                hand_rotation,
                local,
            );
        }
        let middle = side.finger(Finger::Middle)[0];
        let image_tip = out_hand
            .and_then(|i| frame.hands().get(i))
            .and_then(|h| h.image)
            .map(|img| img[self.options.alignment.finger.landmarks()[3]]);
        Some(HandPoints {
            image_tip,
            source: kind,
            user,
            avatar,
            user_palm: (lm[hl::MIDDLE_MCP] - lm[hl::WRIST]).length(),
            avatar_palm: if self.skeleton.has(middle) {
                self.skeleton.rest_local(middle).length()
            } else {
                crate::contact::colliders::avatar_palm_length(&self.skeleton)
            },
        })
    }

    /// Stage 6b: self-contact for both sides together ([`crate::contact`]): the targets move
    /// so that a finger on the user's face lands on the avatar's, touching hands stay
    /// touching, and hands stay out of the avatar's body. Reads the head and torso where they
    /// will be shown from the torso stage's forward kinematics (`out.world`; nothing between
    /// moves them: the hands and arms are below).
    fn contact_targets(
        &mut self,
        frame: &FrameInput,
        plans: &mut [Plan; 2],
        out: &mut SolveOutput,
    ) {
        if !self.options.contact.enabled {
            return;
        }
        let mut targets: [Option<SideTarget>; 2] = plans.map(|p| match p {
            Plan::Reach { target, points, .. } => Some(SideTarget {
                wrist: target,
                hand: points,
            }),
            _ => None,
        });
        if targets.iter().all(Option::is_none) {
            return;
        }
        let needs = |source: Source| {
            targets
                .iter()
                .flatten()
                .any(|t| t.hand.is_some_and(|h| h.source == source))
        };
        let faces = UserFaces {
            pose: if needs(Source::Pose) {
                self.pose.as_ref().and_then(|p| {
                    UserFace::from_pose(
                        p,
                        self.options.camera(),
                        self.options.calibration.min_visibility,
                    )
                })
            } else {
                None
            },
            pose_image: match (&self.pose, &frame.pose_image) {
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
            tracker: if needs(Source::Tracker) {
                frame
                    .face
                    .as_ref()
                    .and_then(|f| UserFace::from_tracker(f, self.skeleton.version()))
            } else {
                None
            },
        };
        self.contact.solve(
            self.options.alignment.finger,
            &faces,
            &out.world,
            &mut targets,
            &mut out.contact,
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
    }

    /// Stage 7: the arm reaching the side's target, and the reports that need the result.
    fn reach_target(&mut self, side: Side, plan: Plan, out: &mut SolveOutput) {
        let (target, hand_rot, pole, points) = match plan {
            Plan::Rest => return,
            Plan::HandOnly(q) => {
                set_hand_world_rotation(&self.skeleton, side, q, out);
                return;
            }
            Plan::Reach {
                target,
                hand_rotation: None,
                pole,
                ..
            } => {
                self.reach(side, target, None, pole, None, out);
                return;
            }
            Plan::Reach {
                target,
                hand_rotation: Some(q),
                pole,
                points,
            } => (target, q, pole, points),
        };
        out.ik_targets[side.index()] = Some(IkTarget {
            position: target,
            rotation: hand_rot,
        });
        // The aligned finger point (CCD's first-priority effector; the wrist limits turn the
        // hand about it). With `alignment.weight` w the IK wrist moves by w times the avatar
        // offset, so the point that stays put is w of the way along it.
        let weight = self.options.alignment.effective_weight();
        let finger = out.alignment[side.index()]
            .filter(|a| a.aligned && weight > 0.0)
            .map(|a| a.avatar_offset * weight);
        // In contact, the touching point is what must stay put, so the wrist limits turn the
        // hand about it (as far as the blends go): the point touching the other hand, then a
        // fingertip on the face (which wins).
        let finger = match (out.contact[side.index()], points) {
            (Some(c), Some(p)) => {
                let mut pivot = finger;
                let mut toward = |point: Option<Vec3>, weight: f32| {
                    if let Some(point) = point.filter(|_| weight > 0.0) {
                        pivot = Some(pivot.unwrap_or(Vec3::ZERO).lerp(point, weight));
                    }
                };
                toward(c.hand_meet, c.hand_weight);
                let tip = 1 + self.options.alignment.finger.index();
                toward(p.avatar[tip], c.weight);
                pivot
            }
            _ => finger,
        };
        let reach = self.reach(side, target, Some(hand_rot), pole, finger, out);
        if let Some(limited) = reach.wrist {
            // The wrist limits turned the hand: report the target and rotation reached.
            let turn = limited.hand_rotation * hand_rot.conjugate();
            if let Some(t) = out.ik_targets[side.index()].as_mut() {
                t.position = limited.target;
                t.rotation = limited.hand_rotation;
            }
            if let Some(report) = out.alignment[side.index()].as_mut() {
                report.ik_wrist = limited.target;
                report.avatar_offset = turn * report.avatar_offset;
            }
        }
        if let Some(report) = out.alignment[side.index()].as_mut() {
            report.reachable = reach.reachable;
            report.error = align::alignment_error(
                &self.skeleton,
                side,
                &self.options.alignment,
                report,
                &out.local,
                &mut out.world,
            );
        }
        if let Some(c) = out.contact[side.index()].as_mut() {
            if let Some(anchor) = c.anchor {
                // Forward kinematics of the arm just solved (alignment_error ran it when
                // there was a report; run it here otherwise).
                if out.alignment[side.index()].is_none() {
                    self.skeleton.forward_arm(side, &out.local, &mut out.world);
                }
                c.distance = align::fingertip(
                    &self.skeleton,
                    &out.world,
                    side,
                    self.options.alignment.finger,
                )
                .map_or(f32::NAN, |tip| {
                    (tip - self.contact.anchor_world(anchor, &out.world)).length()
                });
            }
        }
    }

    /// Stage 8: hold and ease the groups whose tracking was lost, blend in the returning ones
    /// (see [`crate::filter::dropout`]), and keep every driven rotation in the hemisphere of
    /// last frame's (so that apps interpolating output never go the long way round). Returns,
    /// per side, whether anything shown differs from what was solved (a blend under way).
    fn ease(&mut self, now_ms: f64, out: &mut SolveOutput) -> [bool; 2] {
        let timing = self.options.dropout.effective();
        let mut eased = [false; 2];
        for side in Side::BOTH {
            let [shoulder, upper, lower, hand] = side.arm();
            let live_fingers = out.hands[side.index()]
                .is_some_and(|h| matches!(h.status, HandStatus::Solved | HandStatus::Held));
            // The hand bone is also driven by a tracker wrist's rotation without a hand.
            let groups = [
                (Group::Fingers, live_fingers),
                (Group::Hand, out.solved[hand.index()]),
                (Group::Arm, out.solved[upper.index()]),
            ];
            for (group, live) in groups {
                let blend =
                    self.presence[side.index()][group as usize].update(now_ms, live, &timing);
                eased[side.index()] |= !(blend.is_exact() && blend.to_solved);
                let mut apply = |b: HumanBone| {
                    let i = b.index();
                    if !self.driven[i] {
                        return;
                    }
                    let q = blend.show(out.local[i], &mut self.anchor[i], self.shown[i]);
                    out.local[i] = q;
                    self.shown[i] = q;
                };
                match group {
                    Group::Fingers => {
                        for f in crate::bones::Finger::ALL {
                            side.finger(f).into_iter().for_each(&mut apply);
                        }
                    }
                    Group::Hand => apply(hand),
                    Group::Arm => {
                        [upper, lower].into_iter().for_each(apply);
                        if self.arms.moves_shoulder(side) && self.skeleton.has(shoulder) {
                            self.ease_shoulder(side, blend, out);
                        }
                    }
                }
            }
        }
        eased
    }

    /// Eases the arm's share of a shoulder: the turn the arm solver put on top of the torso's
    /// rotation of the bone (`shoulder_base`), so that a lost arm's shoulder goes back to the
    /// torso's (shrug, or the app's) while the torso keeps moving.
    fn ease_shoulder(&mut self, side: Side, blend: crate::filter::Blend, out: &mut SolveOutput) {
        let s = side.index();
        let i = side.arm()[0].index();
        let base = self.shoulder_base[s];
        if blend.capture {
            self.shoulder_turn_anchor[s] = self.shoulder_turn_shown[s];
        }
        let target = if blend.to_solved {
            (base.conjugate() * out.local[i]).normalize()
        } else {
            Quat::IDENTITY
        };
        let turn = if blend.is_exact() {
            target
        } else if blend.weight <= 0.0 {
            self.shoulder_turn_anchor[s]
        } else {
            nlerp(self.shoulder_turn_anchor[s], target, blend.weight)
        };
        let turn = if turn.dot(self.shoulder_turn_shown[s]) < 0.0 {
            -turn
        } else {
            turn
        };
        self.shoulder_turn_shown[s] = turn;
        let q = (base * turn).normalize();
        let q = if q.dot(self.shown[i]) < 0.0 { -q } else { q };
        out.local[i] = q;
        self.shown[i] = q;
    }

    #[allow(clippy::too_many_arguments)]
    fn reach(
        &mut self,
        side: Side,
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        finger: Option<Vec3>,
        out: &mut SolveOutput,
    ) -> crate::ik::ArmReach {
        // `out.world` holds the arm's parent chain (posed once per frame in `solve`; neither
        // side's arm moves it).
        let reach = self.arms.solve(
            side,
            target,
            hand_rotation,
            pole,
            finger,
            &mut out.local,
            &out.world,
        );
        for b in side.arm() {
            if b != side.arm()[0] || self.arms.moves_shoulder(side) {
                out.solved[b.index()] |= self.skeleton.has(b);
            }
        }
        reach
    }

    /// Converts a rotation from the internal frame to the model's own frame (VRM 0.x: negate
    /// x and z).
    #[inline]
    #[must_use]
    pub fn export_rotation(&self, q: Quat) -> Quat {
        self.skeleton.version().rotation_to_internal(q)
    }

    /// Converts a position from the internal frame to the model's own frame.
    #[inline]
    #[must_use]
    pub fn export_position(&self, p: Vec3) -> Vec3 {
        self.skeleton.version().position_to_internal(p)
    }
}

/// Normalized linear interpolation from `a` to `b` (the short way): for easing it looks like a
/// slerp, and costs no trigonometry (software `acos`/`sin` are slow in wasm).
pub(crate) fn nlerp(a: Quat, b: Quat, t: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    (a * (1.0 - t) + b * t).normalize()
}

/// Sets the hand's local rotation so its world rotation is `hand_world`, given the arm's
/// current local rotations.
fn set_hand_world_rotation(
    skeleton: &Skeleton,
    side: Side,
    hand_world: Quat,
    out: &mut SolveOutput,
) {
    let hand = side.hand();
    let mut parent_world = Quat::IDENTITY;
    let mut chain = [HumanBone::Hips; 8];
    let mut n = 0;
    let mut b = skeleton.parent(hand);
    while let Some(p) = b {
        if n < chain.len() {
            chain[n] = p;
            n += 1;
        }
        b = skeleton.parent(p);
    }
    for link in chain[..n].iter().rev() {
        parent_world *= out.local[link.index()];
    }
    out.local[hand.index()] = (parent_world.inverse() * hand_world).normalize();
}

/// Largest magnitude of any coordinate of a frame's points: meters for world points, wrists,
/// body joints and face points, image units for image landmarks. A body is not 1 km across, and
/// far larger (finite) numbers overflow the solvers' squares into infinities.
pub const COORDINATE_LIMIT: f32 = 1000.0;

/// What is wrong with a point of a frame, if anything.
pub(crate) fn point_problem(p: Vec3) -> Option<&'static str> {
    // One test for the common case: NaN fails every comparison, infinities the bound.
    let a = p.abs();
    if a.x <= COORDINATE_LIMIT && a.y <= COORDINATE_LIMIT && a.z <= COORDINATE_LIMIT {
        None
    } else if !p.is_finite() {
        Some("must be three finite numbers")
    } else {
        Some("must be three numbers within -1000..1000 (meters; image landmarks in image units)")
    }
}

/// The first point of `points` with a problem: its index and the problem.
fn points_problem(points: &[Vec3]) -> Option<(usize, &'static str)> {
    // A pass without branches first (every frame's ~150 points; NaN fails the comparisons).
    let within = points.iter().fold(true, |ok, p| {
        let a = p.abs();
        ok & (a.x <= COORDINATE_LIMIT) & (a.y <= COORDINATE_LIMIT) & (a.z <= COORDINATE_LIMIT)
    });
    if within {
        return None;
    }
    points
        .iter()
        .enumerate()
        .find_map(|(k, p)| point_problem(*p).map(|e| (k, e)))
}

fn validate_frame(frame: &FrameInput) -> Result<()> {
    if !frame.time_ms.is_finite() {
        return Err(crate::Error::invalid(
            "frame.timeMs",
            "must be a finite number",
        ));
    }
    for (i, h) in frame.hands().iter().enumerate() {
        if let Some((k, e)) = points_problem(&h.world) {
            return Err(crate::Error::invalid(
                format!("frame.hands[{i}].worldLandmarks[{k}]"),
                e,
            ));
        }
        if let Some((k, e)) = h.image.as_ref().and_then(|p| points_problem(p)) {
            return Err(crate::Error::invalid(
                format!("frame.hands[{i}].landmarks[{k}]"),
                e,
            ));
        }
        if !(0.0..=1.0).contains(&h.score) {
            return Err(crate::Error::invalid(
                format!("frame.hands[{i}].score"),
                "must be a number in 0..1",
            ));
        }
    }
    if let Some(p) = &frame.pose {
        if let Some((k, e)) = points_problem(&p.world) {
            return Err(crate::Error::invalid(
                format!("frame.pose.worldLandmarks[{k}]"),
                e,
            ));
        }
    }
    if let Some((k, e)) = frame.pose_image.as_ref().and_then(|p| points_problem(p)) {
        return Err(crate::Error::invalid(
            format!("frame.pose.landmarks[{k}]"),
            e,
        ));
    }
    for side in Side::BOTH {
        if let Some(w) = &frame.wrists[side.index()] {
            if let Some(e) = point_problem(w.position) {
                return Err(crate::Error::invalid(
                    format!("frame.wrists.{}.position", side.as_str()),
                    e,
                ));
            }
            if let Some(q) = w.rotation {
                if !q.is_finite() || (q.length() - 1.0).abs() > 1e-2 {
                    return Err(crate::Error::invalid(
                        format!("frame.wrists.{}.rotation", side.as_str()),
                        "must be a unit quaternion [x, y, z, w]",
                    ));
                }
            }
        }
    }
    for (bone, q) in TORSO_BONES.iter().zip(frame.torso.iter()) {
        if let Some(q) = q {
            if !q.is_finite() || (q.length() - 1.0).abs() > 1e-2 {
                return Err(crate::Error::invalid(
                    format!("frame.torso.{bone}"),
                    "must be a unit quaternion [x, y, z, w]",
                ));
            }
        }
    }
    if let Some(body) = &frame.body {
        for j in BodyJoint::ALL {
            let k = j.index();
            if let Some(e) = point_problem(body.position[k]) {
                return Err(crate::Error::invalid(
                    format!("frame.body.{}", j.as_str()),
                    e,
                ));
            }
            if !(0.0..=1.0).contains(&body.confidence[k]) {
                return Err(crate::Error::invalid(
                    format!("frame.body.{}.confidence", j.as_str()),
                    "must be a number in 0..1",
                ));
            }
        }
    }
    if let Some(face) = &frame.face {
        for k in 0..TrackerFace::POINTS {
            if let Some(e) = face.point(k).and_then(point_problem) {
                return Err(crate::Error::invalid(
                    format!("frame.face.{}", TrackerFace::NAMES[k]),
                    e,
                ));
            }
        }
    }
    let _ = hand_landmark::WRIST;
    Ok(())
}
