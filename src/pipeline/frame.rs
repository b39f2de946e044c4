//! What one frame's stages share: the [`Context`] they read (the avatar, the options, this
//! frame's input and time) and the [`Frame`] they fill in order (this frame's observed inputs
//! and the values one stage hands the next). Neither carries history: each stage keeps its own.

use glam::{Quat, Vec3};

use crate::align::AlignedPart;
use crate::body::ArmAnchor;
use crate::contact::HandPoints;
use crate::humanoid::bones::BONE_COUNT;
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::{CameraMapping, FrameInput, PoseObservation, HAND_LANDMARKS};
use crate::options::RigOptions;
use crate::torso::BodyObservation;

use super::output::{HandCheck, HandResolved};

/// What every stage of a frame reads and none writes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Context<'a> {
    /// The avatar.
    pub(super) skeleton: &'a Skeleton,
    /// The options in force.
    pub(super) options: &'a RigOptions,
    /// What carries each side's aligned point on this avatar (`[left, right]`).
    pub(super) aligned_parts: &'a [AlignedPart; 2],
    /// The bones the rig drives ([`super::Rig::drives`]).
    pub(super) driven: &'a [bool; BONE_COUNT],
    /// This frame's input (validated).
    pub(super) input: &'a FrameInput,
    /// How MediaPipe's camera axes map onto the avatar.
    pub(super) camera: CameraMapping,
    /// This frame's time (`input.time_ms`).
    pub(super) now_ms: f64,
    /// Seconds since the frame before, `None` on a session's first frame.
    pub(super) dt: Option<f32>,
}

/// The hand picked for a side by the select stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Pick {
    pub(super) index: usize,
    pub(super) reassigned: bool,
    /// What the selection resolved for this side this frame.
    pub(super) resolved: HandResolved,
    /// Image distance from the hand's wrist to this side's pose wrist, when known.
    pub(super) distance: Option<f32>,
    pub(super) score: f32,
}

/// Where an arm reaches this frame (the observe stage's wrist source).
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

/// What a side's arm does this frame, decided by the targets stage before any IK.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Plan {
    /// Nothing drives the arm.
    Rest,
    /// Hands only: the arm rests (`arm.idle`), the hand takes this world rotation.
    HandOnly(Quat),
    /// The arm reaches `target` (the hand with `hand_rotation`, when known).
    Reach {
        target: Vec3,
        hand_rotation: Option<Quat>,
        pole: Option<Vec3>,
        /// `hand_rotation` is a lost hand's as shown last frame: the arm reaches with it, the
        /// hand bone is left to the easing (held, then eased to rest).
        carried: bool,
    },
}

/// This frame's values, each written by one stage before later ones read it (per side,
/// `[left, right]`). Preallocated in the [`super::Rig`]: nothing in it allocates.
#[derive(Clone, Debug)]
pub(super) struct Frame {
    /// The tracked hand driving each side (select).
    pub(super) picks: [Option<Pick>; 2],
    /// This frame's pose, filtered (observe).
    pub(super) pose: Option<PoseObservation>,
    /// This frame's body-tracker joints, filtered for `torso: "pose"` (observe).
    pub(super) body: Option<BodyObservation>,
    /// The torso's rotation of each shoulder bone: what a lost arm's shoulder eases back to
    /// (torso, read by ease).
    pub(super) shoulder_base: [Quat; 2],
    /// Where each side's pose arm is placed (posed upper-arm joint, torso turn; torso).
    pub(super) anchors: [Option<ArmAnchor>; 2],
    /// The turn from the user's upper-torso frame (on the pose) to the avatar's, when measured
    /// (not with `torso: "off"`): applied to the pose-driven arm and hand (torso).
    pub(super) turn: Option<Quat>,
    /// Each side's hand landmarks in the avatar frame, filtered (observe; a held hand's are
    /// replaced by the last solved hand's in the hands stage).
    pub(super) landmarks: [[Vec3; HAND_LANDMARKS]; 2],
    /// The hand checks' verdict (observe).
    pub(super) check: [HandCheck; 2],
    /// Whether `landmarks` place the side's fingertip for alignment and contact (hands): a
    /// hand solved this frame, or one held by the checks with the last solved hand's
    /// landmarks; not a degenerate hand held by the solver.
    pub(super) placed: [bool; 2],
    /// The hand's world rotation when solved or held (hands).
    pub(super) hand_rotation: [Option<Quat>; 2],
    /// Where each arm reaches from (observe, after the torso).
    pub(super) sources: [Option<WristSource>; 2],
    /// What each arm does (targets; moved by contact).
    pub(super) plans: [Plan; 2],
    /// Whether alignment and contact placed the fingers as the easing will show them,
    /// blending in after a loss (targets, read by contact and ease).
    pub(super) fingers_blending: [bool; 2],
    /// The hand's contact points, for a hand placed this frame with contact on (contact,
    /// read by reach).
    pub(super) points: [Option<HandPoints>; 2],
    /// The contact points of a hand not seen this frame, as last seen and turned to its
    /// rotation now, with contact on (contact, read by reach and limit: what keeps it out of
    /// the body).
    pub(super) held: [Option<HandPoints>; 2],
    /// Whether the easing or the turn limit changed what each side shows (ease, limit; read
    /// by report).
    pub(super) eased: [bool; 2],
}

impl Default for Frame {
    fn default() -> Self {
        Frame {
            picks: [None; 2],
            pose: None,
            body: None,
            shoulder_base: [Quat::IDENTITY; 2],
            anchors: [None; 2],
            turn: None,
            landmarks: [[Vec3::ZERO; HAND_LANDMARKS]; 2],
            check: [HandCheck::Good; 2],
            placed: [false; 2],
            hand_rotation: [None; 2],
            sources: [None; 2],
            plans: [Plan::Rest; 2],
            fingers_blending: [false; 2],
            points: [None; 2],
            held: [None; 2],
            eased: [false; 2],
        }
    }
}
