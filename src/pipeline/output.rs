//! What [`Rig::solve`](super::Rig::solve) produces: [`SolveOutput`] and the types it reports.

use glam::{Quat, Vec3};

use crate::align::AlignmentReport;
use crate::contact::ContactReport;
use crate::hand::{HandStatus, RetargetReport};
use crate::humanoid::bones::{Side, BONE_COUNT};
use crate::humanoid::skeleton::{VrmVersion, WorldPose};
use crate::input::mediapipe::MAX_HANDS;

/// What the rig's hand checks (the observe stage, [`super::Rig::solve`]) made of a side's hand this frame (see
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

/// A wrist IK target in the model's own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkTarget {
    /// Where the avatar's hand bone (wrist joint) should be.
    pub position: Vec3,
    /// World rotation the avatar's normalized hand bone should have.
    pub rotation: Quat,
}

/// Everything one `solve` produces, in the model's own frame (a VRM 0.x avatar's rotations and
/// positions as three-vrm's normalized bones of that model take them, the same numbers the JS
/// API returns; [`SolveOutput::turn_to_internal_frame`] turns them into handrig's internal frame).
/// Fixed-size: reused frame to frame without allocation.
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
    /// in the model's frame, every strategy: the distal bone extended by the anatomical
    /// ratio of [`crate::align::tip_offset`] (the point `alignment.point: "tip"` aligns).
    /// `None` where the avatar lacks that finger's distal bone.
    pub fingertips: [[Option<Vec3>; 5]; 2],
    /// What `handStrategy: "retarget"` did per side this frame (`None` for other strategies
    /// and for sides not freshly solved); targets are world positions in the model's frame,
    /// like [`SolveOutput::fingertips`].
    pub retarget: [Option<RetargetReport>; 2],
    /// What became of each input hand (in the frame's order; `Unused` past its count).
    pub hand_use: [HandUse; MAX_HANDS],
    /// What self-contact did per side (`[left, right]`): `Some` for every side with a wrist
    /// IK target while `contact.enabled`.
    pub contact: [Option<ContactReport>; 2],
    /// The face's expressions, look-at and head (issue 50).
    pub face: FaceReport,
    // Legs (issue 51).
    /// The hips' translation from their rest position (m; `legs.moveHips`): what an app adds
    /// to the normalized hips' rest position. The bones' world positions (`world`) are those
    /// of the hips at rest; add this to place them in the room.
    pub hips_offset: Vec3,
    /// Whether each foot (`[left, right]`) is planted: on the floor, bearing weight, locked
    /// where it was put down (`legs.plant`).
    pub planted: [bool; 2],
}

/// What the face stage gave this frame ([`crate::face`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceReport {
    /// 0 no face, 1 tracked this frame, 2 lost and easing out.
    pub state: u8,
    /// The VRM 1.0 presets ([`crate::face::PRESETS`] order), 0..1.
    pub presets: [f32; crate::face::PRESET_COUNT],
    /// The 52 ARKit weights ([`crate::face::ARKIT`] order, the avatar's sides), 0..1.
    pub arkit: [f32; crate::face::SHAPES],
    /// Look-at yaw and pitch in degrees (three-vrm's `VRMLookAt`: yaw > 0 toward the avatar's
    /// left, pitch > 0 down).
    pub look_at: [f32; 2],
    /// Whether the face turned the neck and head this frame (they are then reported driven).
    pub head: bool,
}

impl Default for FaceReport {
    fn default() -> Self {
        FaceReport {
            state: 0,
            presets: [0.0; crate::face::PRESET_COUNT],
            arkit: [0.0; crate::face::SHAPES],
            look_at: [0.0; 2],
            head: false,
        }
    }
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

/// What the hand selection resolved on an avatar side this frame (see
/// `src/pipeline/select.rs`): the first that applies, in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum HandResolved {
    /// Nothing: the hand's label, alone on its side, agreed with the pose and the last frame.
    #[default]
    None,
    /// Its label contradicted the pose wrists and it was reassigned to this side
    /// (`handedness: "reassign"`).
    Swapped,
    /// No pose witness: it landed where this side's hand was the frame before, with the
    /// other side's label (a label flip), and was relabelled to this side (at most
    /// `MAX_JUMP_FRAMES` in a row).
    Jumped,
    /// Two hands claimed this side: this one kept it (nearer the pose wrist, or last frame's
    /// hand, or the higher score; the other is `HandUse::Duplicate`), or, with `reassigned`,
    /// it is the second, distinct hand, moved here from a side it lost (no pose witness).
    Duplicate,
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
    /// Whether it drives the side its label does not give (contradicted by the pose, a label
    /// that jumped, or a distinct duplicate moved to a free side; see `resolved`).
    pub reassigned: bool,
    /// What the hand selection resolved on this side this frame.
    pub resolved: HandResolved,
    /// What the hand checks made of it (good, or mirrored and held).
    pub check: HandCheck,
    /// How far an app can trust this side's hand this frame, 0 to 1: the handedness score
    /// times 1 for a hand that passed the checks, 0.3 for a held hand (mirrored, or
    /// degenerate this frame), 0 when skipped.
    /// For fading a hand in and out.
    pub confidence: f32,
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
            face: FaceReport::default(),
            hips_offset: Vec3::ZERO,
            planted: [false; 2],
        }
    }
}

impl SolveOutput {
    /// Turns every rotation, position and direction of this output from handrig's internal
    /// (+Z-facing) frame into the model's own frame: for VRM 0.x the 180 degree turn about Y
    /// (positions `(-x, y, -z)`, rotations conjugated); for VRM 1.0 nothing changes. The report
    /// stage runs it last, so every caller (native Rust, the flat path, JS) gets the model's
    /// frame. Allocates nothing.
    pub(crate) fn turn_to_model_frame(&mut self, version: VrmVersion) {
        self.turn(version);
    }

    /// The inverse of the report stage's conversion: this output back in handrig's internal
    /// (+Z-facing) frame, the frame of [`crate::Skeleton`]'s forward kinematics and of the
    /// rig's contact model, for Rust code that combines the two. (The turn is its own
    /// inverse.) Allocates nothing.
    pub fn turn_to_internal_frame(&mut self, version: VrmVersion) {
        self.turn(version);
    }

    fn turn(&mut self, version: VrmVersion) {
        if version == VrmVersion::V1 {
            return;
        }
        let p = |v: Vec3| version.position_to_internal(v);
        let q = |r: Quat| version.rotation_to_internal(r);
        for r in self.local.iter_mut().chain(self.world.rotation.iter_mut()) {
            *r = q(*r);
        }
        for v in &mut self.world.position {
            *v = p(*v);
        }
        for t in self.ik_targets.iter_mut().flatten() {
            t.position = p(t.position);
            t.rotation = q(t.rotation);
        }
        for a in self.alignment.iter_mut().flatten() {
            a.target_dip = p(a.target_dip);
            a.ik_wrist = p(a.ik_wrist);
            a.pose_wrist = p(a.pose_wrist);
            a.avatar_offset = p(a.avatar_offset);
        }
        self.hips_offset = p(self.hips_offset);
        for tip in self.fingertips.iter_mut().flatten().flatten() {
            *tip = p(*tip);
        }
        for r in self.retarget.iter_mut().flatten() {
            for t in r.targets.iter_mut().flatten() {
                *t = p(*t);
            }
        }
        for c in self.contact.iter_mut().flatten() {
            for m in [&mut c.hand_meet, &mut c.face_meet].into_iter().flatten() {
                *m = p(*m);
            }
        }
    }
}
