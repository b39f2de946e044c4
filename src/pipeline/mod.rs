//! The per-frame pipeline: MediaPipe frame in, normalized-bone rotations, IK targets and
//! alignment reports out.
//!
//! A [`Rig`] holds the avatar, the options and one value per stage; each stage is a type in its
//! own file that keeps its own history, and a frame runs them in this order
//! ([`Rig::solve`]), handing values on in a `Frame` (what every stage reads and none
//! writes is the `Context`, both in `frame.rs`):
//!
//! 1. **select** (`select.rs`): which tracked hand drives each avatar side; low scores
//!    ignored, labels that contradict the pose wrists reassigned (`options.handedness`),
//!    labels that jump sides between frames relabelled, two hands on one side resolved.
//! 2. **observe**, the body (`observe.rs`): the pose and the body tracker's joints, One Euro
//!    filtered ([`crate::filter`]); body-scale calibration ([`crate::body`]).
//! 3. **torso** (`torso.rs`): the torso bones from the app (`frame.torso`) or tracked from
//!    `body` joints or the pose, eased over tracking loss ([`crate::torso`]); forward
//!    kinematics of the posed torso places each arm's anchor.
//!    Then **legs** (`legs.rs`, issue 51): each leg from the pose's lower body when seen
//!    ([`crate::legs`]), eased to rest when not; the hips' offset and the planted feet.
//! 4. per side: **observe**, the hand and wrist (`observe.rs`): the hand's landmarks mapped to
//!    the avatar frame (turned with the torso when the pose places the arm), checked for
//!    MediaPipe's depth flips, filtered; the wrist from a tracker (filtered) or the pose
//!    (mapped relative to the torso's anchor); then **hands** (`hands.rs`): hand orientation
//!    and finger rotations ([`crate::hand`]); then **targets** (`targets.rs`): the wrist IK
//!    target by fingertip alignment ([`crate::align`]) of the hand as the easing will show
//!    it, or what a lost hand leaves its arm.
//! 5. **contact** (`contact.rs`, both sides together): each hand's contact points, the
//!    targets moved for self-contact ([`crate::contact`]), a lost hand touching the other
//!    held against it (`touch.rs`).
//! 6. per side, **reach** (`reach.rs`): the arm solver ([`crate::ik`]) reaches the target
//!    from the posed torso.
//! 7. **ease** (`ease.rs`): groups whose tracking was lost hold, then ease to rest; returning
//!    ones blend in ([`crate::filter::dropout`]); then the **turn limit** (`limit.rs`): an arm
//!    turning faster than `arm.maxTurnSpeed` is slowed to it.
//! 8. **report** (`report.rs`): forward kinematics of the whole avatar, its fingertips, the
//!    retargeting reports, the output in the model's own frame.
//!
//! [`Rig::reset`] clears the history of every stage.

mod contact;
mod ease;
mod face;
mod frame;
mod hands;
mod legs;
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

use crate::align::AlignedPart;
use crate::body::BodyMapper;
use crate::contact::ContactSolver;
use crate::error::Result;
use crate::filter::Clock;
use crate::humanoid::bones::{Finger, HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::Skeleton;
use crate::ik::ArmSolverState;
use crate::input::mediapipe::FrameInput;
use crate::input::validate::validate_frame;
pub use crate::options::{HandednessPolicy, RigOptions};
use crate::torso::{TorsoSolver, TorsoSource, TORSO_BONES};

pub use crate::input::validate::COORDINATE_LIMIT;
pub use output::{HandCheck, HandResolved, HandUse, IkTarget, SolveOutput, TrackedHand};
pub use select::{CONTRADICTION_RATIO, DISTINCT_HANDS, MAX_JUMP_FRAMES};

use frame::{Context, Frame};

/// The solver for one avatar: owns the skeleton, the options, each stage's history and this
/// frame's values, so [`Rig::solve`] allocates nothing.
#[derive(Clone, Debug)]
pub struct Rig {
    skeleton: Skeleton,
    options: RigOptions,
    /// What carries each side's aligned point (`[left, right]`), chosen from the bones the
    /// avatar has ([`AlignedPart::choose`]).
    aligned_parts: [AlignedPart; 2],
    driven: [bool; BONE_COUNT],
    clock: Clock,
    /// This frame's values, handed from stage to stage (not history).
    frame: Frame,
    // The stages, in the order a frame runs them.
    select: select::Select,
    observe: observe::Observe,
    torso: torso::Torso,
    hands: hands::Hands,
    targets: targets::Targets,
    contact: contact::Contact,
    reach: reach::Reach,
    ease: ease::Ease,
    limit: limit::Limit,
    // The face (issue 50), after the torso.
    face: face::FaceStage,
    // Legs (issue 51).
    legs: legs::Legs,
}

impl Rig {
    /// Creates a rig for `skeleton`.
    ///
    /// # Errors
    /// Options out of range (field named in the message).
    pub fn new(skeleton: Skeleton, options: RigOptions) -> Result<Self> {
        options.validate()?;
        let hands = hands::Hands::new(&skeleton, &options)?;
        let contact = contact::Contact::new(&skeleton, &options.contact);
        let observe = observe::Observe::new(&skeleton, &options.calibration);
        let reach = reach::Reach::new(&skeleton, &options)?;
        let mut driven = [false; BONE_COUNT];
        for side in Side::BOTH {
            let [shoulder, upper, lower, hand] = side.arm();
            let fingers = Finger::ALL.iter().flat_map(|f| side.finger(*f));
            for b in [upper, lower, hand].into_iter().chain(fingers) {
                driven[b.index()] = skeleton.has(b);
            }
            // The shoulder when the arm option may turn it on far reaches, or the torso
            // shrugs it.
            driven[shoulder.index()] = skeleton.has(shoulder)
                && (reach.arms.moves_shoulder(side) || options.torso == TorsoSource::Pose);
        }
        if options.torso == TorsoSource::Pose {
            for b in TORSO_BONES {
                driven[b.index()] = skeleton.has(b);
            }
        }
        // Legs (issue 51): the leg bones the avatar has, when legs are on.
        for side in Side::BOTH {
            for b in crate::legs::leg_bones(side) {
                driven[b.index()] |= options.legs.enabled && skeleton.has(b);
            }
        }
        let legs = legs::Legs::new(&skeleton);
        let torso = torso::Torso::new(&skeleton, options.calibration.frames);
        let aligned_parts =
            Side::BOTH.map(|side| AlignedPart::choose(&skeleton, side, options.alignment.finger));
        Ok(Rig {
            skeleton,
            options,
            aligned_parts,
            driven,
            clock: Clock::default(),
            frame: Frame::default(),
            select: select::Select::default(),
            observe,
            torso,
            hands,
            targets: targets::Targets::default(),
            contact,
            reach,
            ease: ease::Ease::default(),
            limit: limit::Limit::default(),
            face: face::FaceStage::default(),
            legs,
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
        self.reset_calibration();
        self.clock.reset();
        self.new_session();
    }

    /// Everything carried from one frame to the next, but the clock (which already holds the
    /// new session's first time) and calibration: a frame after a seek or a long gap solves
    /// exactly as the first frame of a new rig.
    fn new_session(&mut self) {
        self.select = select::Select::default();
        self.observe.restart();
        self.torso.solver.restart();
        self.hands.restart();
        self.targets.restart();
        self.contact.restart();
        self.reach.arms.reset();
        self.ease.restart();
        self.limit.restart();
        self.face.restart();
        self.legs.restart();
        let f = &mut self.frame;
        f.pose = None;
        f.anchors = [None, None];
        f.turn = None;
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
        self.observe.body()
    }

    /// How many frames the turn limit (`arm.maxTurnSpeed`) slowed `side`'s arm since the rig
    /// was made or last reset (a new session, a seek or a long gap also resets it).
    #[must_use]
    pub fn turns_limited(&self, side: Side) -> u32 {
        self.limit.limited(side)
    }

    /// The arm solvers (which method, last iteration counts).
    #[must_use]
    pub fn arms(&self) -> &ArmSolverState {
        &self.reach.arms
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
        self.contact.solver()
    }

    /// Restarts body-scale calibration (and the torso's neutral shoulder height).
    pub fn reset_calibration(&mut self) {
        self.observe.reset_calibration();
        self.torso.solver.reset_calibration();
    }

    /// Starts the neutral face's calibration again (`face.calibrationTime` seconds of face
    /// frames from the next one): call it while the user holds a neutral face.
    pub fn calibrate_face(&mut self) {
        self.face.face.calibrate();
    }

    /// The torso stage (the avatar's torso bone the arms hang from, the shrug's neutral).
    #[must_use]
    pub fn torso(&self) -> &TorsoSolver {
        &self.torso.solver
    }

    /// The torso's rotation of `side`'s shoulder bone in the last solve (internal frame): the
    /// shrug (`torso: "pose"`) or the app's rotation of it, before the arm solver's turn on
    /// far reaches. What a lost arm's shoulder eases back to.
    #[must_use]
    pub fn shoulder_base(&self, side: Side) -> Quat {
        self.frame.shoulder_base[side.index()]
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
    pub(crate) fn solve_valid(&mut self, input: &FrameInput, out: &mut SolveOutput) {
        let dt = self.clock.advance(input.time_ms);
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
        out.hand_use = [crate::pipeline::HandUse::Unused; crate::input::mediapipe::MAX_HANDS];
        out.retarget = [None, None];
        out.contact = [None, None];
        out.hips_offset = Vec3::ZERO;
        out.planted = [false; 2];
        // Everything not solved this frame goes back to rest (then the easing stage decides).
        out.local = [Quat::IDENTITY; BONE_COUNT];

        let cx = Context {
            skeleton: &self.skeleton,
            options: &self.options,
            aligned_parts: &self.aligned_parts,
            driven: &self.driven,
            input,
            camera: self.options.camera(),
            now_ms: input.time_ms,
            dt,
        };
        let f = &mut self.frame;
        self.select.run(&cx, f, out);
        self.observe.body_inputs(&cx, f);
        // The torso and its forward kinematics: the world pose the arms hang from, once per
        // frame (arms and hands do not move it).
        self.torso.run(&cx, f, out);
        // The face: expressions, look-at, the head over the posed torso (issue 50).
        self.face.run(&cx, f, out);
        // Legs (issue 51): from the posed hips.
        self.legs.run(&cx, f, out);
        for side in Side::BOTH {
            self.observe.hand(&cx, side, f);
            self.hands.run(&cx, side, f, out);
            self.observe.wrist(&cx, side, f);
            self.targets.plan(&cx, &self.ease, side, f, out);
        }
        self.contact.run(&cx, &self.ease, f, out);
        for side in Side::BOTH {
            self.reach.run(&cx, self.contact.solver(), side, f, out);
        }
        self.targets.remember_offsets(out);
        let moves_shoulder = Side::BOTH.map(|side| self.reach.arms.moves_shoulder(side));
        let touch_held = Side::BOTH.map(|side| self.contact.touch_held(side));
        let eased = self.ease.run(&cx, moves_shoulder, touch_held, f, out);
        let slowed = self
            .limit
            .run(&cx, self.contact.solver(), f, self.ease.shown_mut(), out);
        f.eased = [0, 1].map(|s| eased[s] || slowed[s]);
        report::Report::run(&cx, &self.hands, &mut self.targets, f.eased, out);
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
