//! The per-frame pipeline: MediaPipe frame in, normalized-bone rotations, IK targets and
//! alignment reports out.
//!
//! [`Rig::solve`] runs named stages, each feature in one of them, each stage in its own file
//! (`select.rs`, `observe.rs`, `torso.rs`, `hands.rs`, `targets.rs`, `touch.rs`, `reach.rs`,
//! `ease.rs`, `report.rs`; the outputs in `output.rs`):
//!
//! 1. **select hands** (`Rig::select_hands`): which tracked hand drives each avatar side;
//!    low scores ignored, labels that contradict the pose wrists reassigned
//!    (`options.handedness`), labels that jump sides between frames relabelled, two hands on
//!    one side resolved; reported per side (`TrackedHand::resolved`).
//! 2. **pose** (`Rig::observe_pose`): the pose landmarks, One Euro filtered
//!    ([`crate::filter`]), feed body-scale calibration ([`crate::body`]).
//! 3. **torso** (`Rig::torso_stage`): the torso bones from the app (`frame.torso`) or tracked
//!    from `body` joints or the pose, eased over tracking loss ([`crate::torso`]); the user's
//!    upper-torso frame measured on the pose; forward kinematics of the posed torso places
//!    each arm's anchor (its upper-arm joint and torso frame);
//! 4. per side, **hand** (`Rig::solve_hand`): the hand's landmarks mapped to the avatar frame
//!    and filtered, then hand orientation and finger rotations ([`crate::hand`]);
//! 5. per side, **wrist source** (`Rig::wrist_source`): the wrist from `wrists` (filtered) or
//!    from the pose mapped relative to the torso ([`crate::body`]), with the elbow as pole;
//! 6. **targets** (`Rig::plan_target` per side, then `Rig::contact_targets` for both
//!    sides together): the wrist IK target by fingertip alignment ([`crate::align`]) from
//!    forward kinematics of *this* frame's hand as stage 8 will show it (fingers returning
//!    after a loss blend in: `Rig::fingers_blend`), then moved for self-contact
//!    ([`crate::contact`]: a finger on the face lands on the avatar's face where the posed
//!    torso put it, touching hands stay touching, hands stay out of the body; the correction
//!    changes by at most `contact.maxSpeed`), then a hand lost while it touches the other is
//!    held against it (`touch.rs`); both sides' targets exist before any IK;
//! 7. per side, **IK** (`Rig::reach_target`): the arm solver ([`crate::ik`]) reaches the
//!    target from the posed torso;
//! 8. **ease** (`Rig::ease`): groups whose tracking was lost hold, then ease to rest (a
//!    shoulder to the torso's rotation of it); returning ones blend in
//!    ([`crate::filter::dropout`]), but a hand returning into a touch, or to an arm the pose
//!    placed, shows its hand bone's solve at once (its fingers blend in as stage 6 placed them);
//!    rotations keep their hemisphere;
//!    8b. **turn limit** (`Rig::limit_turns`, `limit.rs`): an arm turning faster than
//!    `arm.maxTurnSpeed` is slowed to it, its four bones by the same fraction;
//! 9. **report** (`Rig::report`): forward kinematics of the whole avatar, its fingertips,
//!    the retargeting reports.
//!
//! [`Rig::reset`] clears the history of every stage.

mod ease;
mod hands;
mod limit;
mod observe;
mod output;
mod reach;
mod report;
mod select;
mod targets;
mod torso;
mod touch;

use glam::{Quat, Vec3};

use crate::body::{ArmAnchor, BodyMapper};
use crate::contact::ContactSolver;
use crate::error::Result;
use crate::filter::{Clock, OneEuroQuat, PointFilters, Presence};
use crate::hand::HandSolver;
use crate::humanoid::bones::{HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::Skeleton;
use crate::ik::ArmSolverState;
use crate::input::validate::validate_frame;
use crate::mediapipe::{FrameInput, PoseObservation, HAND_LANDMARKS, MAX_HANDS, POSE_LANDMARKS};
pub use crate::options::{HandednessPolicy, RigOptions};
use crate::torso::{TorsoSolver, TorsoSource, BODY_JOINT_COUNT, TORSO_BONES};

pub use crate::input::validate::COORDINATE_LIMIT;
pub use hands::HandCheck;
pub use output::{HandResolved, HandUse, IkTarget, SolveOutput, TrackedHand};
pub use select::{CONTRADICTION_RATIO, DISTINCT_HANDS, MAX_JUMP_FRAMES};

use targets::Plan;

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
    /// What carries each side's aligned point (`[left, right]`), chosen from the bones the
    /// avatar has ([`crate::align::AlignedPart::choose`]).
    aligned_parts: [crate::align::AlignedPart; 2],
    driven: [bool; BONE_COUNT],
    clock: Clock,
    /// Landmark filters per avatar side, the pose's, and the tracker wrists'.
    hand_filters: [PointFilters<HAND_LANDMARKS>; 2],
    pose_filters: PointFilters<POSE_LANDMARKS>,
    wrist_filters: [WristFilter; 2],
    /// Presence of each side's hand and arm ([`Group`]), for the dropout easing.
    presence: [[Presence; 3]; 2],
    /// The rotations shown last frame, and the anchors of running blends.
    shown: [Quat; BONE_COUNT],
    anchor: [Quat; BONE_COUNT],
    /// The torso stage: the avatar's torso, the shrug's neutral, the torso's easing.
    torso: TorsoSolver,
    /// Filters of the body-tracker joints.
    body_filters: PointFilters<BODY_JOINT_COUNT>,
    /// The arm solver's turn of each shoulder on top of `shoulder_base`, as shown last frame,
    /// and the anchor of its running blend.
    shoulder_turn_shown: [Quat; 2],
    shoulder_turn_anchor: [Quat; 2],
    /// The hand checks' history per side (`hands.rs`).
    flips: [hands::FlipState; 2],
    /// The hand selection's history (`select.rs`).
    selection: select::SelectState,
    /// The contact corrections' history (their rate limit).
    contact_rate: crate::contact::ContactRate,
    /// Each side's touch with the other hand, for holding a lost hand against it (`touch.rs`).
    touch: [touch::TouchHold; 2],
    /// Each side's arm as shown last frame, for the turn limit (`limit.rs`).
    turn_limit: [limit::TurnLimit; 2],
    /// What each side's lost hand leaves to its arm (`targets.rs`).
    lost_hand: [targets::LostHand; 2],
    /// This frame's values passed from stage to stage (not history; see [`Scratch`]).
    scratch: Scratch,
}

/// This frame's values carried from one stage to the next: each is written by an earlier
/// stage of [`Rig::solve`] before a later one reads it, so none is history. Preallocated
/// storage held by the [`Rig`] (fixed-size: no allocation per frame).
#[derive(Clone, Debug)]
struct Scratch {
    /// This frame's hand landmarks of the side being solved, in the avatar frame, filtered
    /// (stage 4, read by stage 6).
    landmarks: [Vec3; HAND_LANDMARKS],
    /// Whether each side's `landmarks` place its fingertip for alignment and contact (stage 4,
    /// read by stage 6): a hand solved this frame, or one held by the hand checks with the
    /// last solved hand's landmarks; not a degenerate hand held by the solver.
    placed: [bool; 2],
    /// Whether each side's fingertip alignment and contact points used the fingers as the
    /// easing will show them, blending in after a loss (stage 6, read by stage 8).
    fingers_blending: [bool; 2],
    /// This frame's pose, filtered (stage 2).
    pose: Option<PoseObservation>,
    /// This frame's torso rotation of each shoulder bone (`[left, right]`): what an arm's
    /// shoulder eases back to when the arm is lost (stage 3, read by stage 8).
    shoulder_base: [Quat; 2],
    /// Where each side's pose arm is placed this frame (posed upper-arm joint, torso turn;
    /// stage 3).
    anchors: [Option<ArmAnchor>; 2],
    /// This frame's turn from the user's upper-torso frame (on the pose) to the avatar's,
    /// when measured (not with `torso: "off"`): applied to the whole pose-driven arm and hand
    /// (stage 3).
    turn: Option<Quat>,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch {
            landmarks: [Vec3::ZERO; HAND_LANDMARKS],
            placed: [false; 2],
            fingers_blending: [false; 2],
            pose: None,
            shoulder_base: [Quat::IDENTITY; 2],
            anchors: [None, None],
            turn: None,
        }
    }
}

/// Filters of one side's tracker wrist (position and rotation).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
struct WristFilter {
    position: PointFilters<1>,
    rotation: OneEuroQuat,
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
            let fingers = crate::humanoid::bones::Finger::ALL
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
        let aligned_parts = Side::BOTH.map(|side| {
            crate::align::AlignedPart::choose(&skeleton, side, options.alignment.finger)
        });
        Ok(Rig {
            skeleton,
            options,
            hands,
            body,
            arms,
            contact,
            aligned_parts,
            driven,
            clock: Clock::default(),
            hand_filters: [PointFilters::default(); 2],
            pose_filters: PointFilters::default(),
            wrist_filters: [WristFilter::default(); 2],
            presence: [[Presence::default(); 3]; 2],
            shown: [Quat::IDENTITY; BONE_COUNT],
            anchor: [Quat::IDENTITY; BONE_COUNT],
            torso,
            body_filters: PointFilters::default(),
            shoulder_turn_shown: [Quat::IDENTITY; 2],
            shoulder_turn_anchor: [Quat::IDENTITY; 2],
            flips: [hands::FlipState::default(); 2],
            selection: select::SelectState::default(),
            contact_rate: crate::contact::ContactRate::default(),
            touch: [touch::TouchHold::default(); 2],
            turn_limit: [limit::TurnLimit::default(); 2],
            lost_hand: [targets::LostHand::default(); 2],
            scratch: Scratch::default(),
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
        self.flips = [hands::FlipState::default(); 2];
        self.selection = select::SelectState::default();
        self.contact_rate = crate::contact::ContactRate::default();
        self.touch = [touch::TouchHold::default(); 2];
        self.turn_limit = [limit::TurnLimit::default(); 2];
        self.lost_hand = [targets::LostHand::default(); 2];
        self.scratch.pose = None;
        self.scratch.anchors = [None, None];
        self.scratch.turn = None;
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

    /// How many frames the turn limit (`arm.maxTurnSpeed`) slowed `side`'s arm since the rig
    /// was made or last reset (a new session, a seek or a long gap also resets it).
    #[must_use]
    pub fn turns_limited(&self, side: Side) -> u32 {
        self.turn_limit[side.index()].limited()
    }

    /// The arm solvers (which method, last iteration counts).
    #[must_use]
    pub fn arms(&self) -> &ArmSolverState {
        &self.arms
    }

    /// Restarts body-scale calibration (and the torso's neutral shoulder height).
    /// What carries `side`'s aligned point on this avatar: `alignment.finger`'s distal bone, or
    /// what stands in for it when the avatar lacks it ([`crate::align::AlignedPart::choose`]).
    #[must_use]
    pub fn aligned_part(&self, side: Side) -> crate::align::AlignedPart {
        self.aligned_parts[side.index()]
    }

    /// A message naming, per side, what the avatar lacks for `alignment.finger` and what
    /// alignment and contact use instead; `None` when both sides have the finger's distal
    /// bone. Built at setup (the npm package prints it once per rig with `console.warn`).
    #[must_use]
    pub fn alignment_warning(&self) -> Option<String> {
        if !self.options.alignment.enabled && !self.options.contact.enabled {
            return None;
        }
        let configured = self.options.alignment.finger;
        let parts: Vec<String> = Side::BOTH
            .into_iter()
            .filter(|s| !self.aligned_parts[s.index()].is_configured(configured))
            .map(|side| {
                let part = self.aligned_parts[side.index()];
                let wanted = side.finger(configured)[2];
                let using = match part {
                    crate::align::AlignedPart::Palm => format!(
                        "the palm (the front of {}, no finger bones)",
                        side.hand().as_str()
                    ),
                    crate::align::AlignedPart::Finger { finger, depth } => {
                        let bone = part.bone(side).as_str();
                        if depth == 2 {
                            format!("the {} finger ({bone})", finger.as_str())
                        } else {
                            format!(
                                "the {} finger's {bone} with its tip extrapolated",
                                finger.as_str()
                            )
                        }
                    }
                };
                format!("{wanted} is missing, {using} is used instead")
            })
            .collect();
        (!parts.is_empty()).then(|| {
            format!(
                "handrig: fingertip alignment and self-contact (alignment.finger \"{}\"): {}.",
                configured.as_str(),
                parts.join("; ")
            )
        })
    }

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
        self.scratch.shoulder_base[side.index()]
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

    /// Solves one frame into `out`, in the model's own frame (the report stage turns a VRM 0.x
    /// model's output; [`SolveOutput::turn_to_internal_frame`] turns it back for use with the
    /// [`Skeleton`]'s internal-frame kinematics). Allocates nothing.
    ///
    /// # Errors
    /// Invalid input (non-finite numbers, and points beyond [`COORDINATE_LIMIT`], are rejected
    /// before any state changes). Degenerate hands are not errors: that hand is skipped and
    /// its previous rotations are kept.
    pub fn solve(&mut self, frame: &FrameInput, out: &mut SolveOutput) -> Result<()> {
        validate_frame(frame)?;
        self.solve_valid(frame, out);
        Ok(())
    }

    /// [`Rig::solve`] on a frame already checked by [`crate::input::validate`] (the flat
    /// decoder runs the same check, so the wasm path does not check a frame twice).
    pub(crate) fn solve_valid(&mut self, frame: &FrameInput, out: &mut SolveOutput) {
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
        self.observe_pose(frame, dt);
        // The torso (from the app or tracking), and its forward kinematics: the world pose the
        // arms hang from, once per frame (arms and hands do not move it).
        self.torso_stage(frame, camera, dt, out);
        let mut plans = [Plan::Rest; 2];
        for side in Side::BOTH {
            let hand_rotation = self.solve_hand(side, frame, picks[side.index()], dt, out);
            let source = self.wrist_source(side, frame, picks[side.index()], dt);
            plans[side.index()] = self.plan_target(side, frame, hand_rotation, source, out);
        }
        self.contact_targets(frame, dt, &mut plans, out);
        for side in Side::BOTH {
            self.reach_target(side, plans[side.index()], out);
        }
        self.remember_offsets(out);
        let eased = self.ease(frame.time_ms, out);
        let slowed = self.limit_turns(dt, out);
        self.report([0, 1].map(|s| eased[s] || slowed[s]), out);
    }

    /// Converts a rotation from the internal frame (the [`Skeleton`]'s, the contact model's,
    /// [`Rig::shoulder_base`]) to the model's own frame (VRM 0.x: negate x and z). [`Rig::solve`]
    /// output is already in the model's frame.
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
