//! The upper body: hips, spine, chest, upperChest, neck, head and the shoulders, from the app
//! or from tracking, so that every arm target is placed and reached from the torso the avatar
//! is actually drawn with.
//!
//! ## Sources (`options.torso`, [`TorsoSource`])
//! * `"frame"` (default): the app's torso. `frame.torso` gives normalized-bone local rotations
//!   (model frame) for any of [`TORSO_BONES`]; a bone left out is at rest. handrig does not
//!   write these bones (they are not in `result.bones`: the app drives them), but forward
//!   kinematics, fingertip alignment and arm IK work from them. Without `frame.torso` this is
//!   the rest torso, as before the torso existed: apps that move the avatar's body with their
//!   own solver and never tell handrig keep working unchanged (their arms are still measured
//!   relative to the user's torso, see [`crate::body`]).
//! * `"pose"`: handrig tracks the torso from the frame's `body` joints (a body tracker with
//!   spine joints, [`BodyObservation`]) or, without them, from the MediaPipe `pose` world
//!   landmarks, and drives the torso bones (they are in `result.bones`). A bone given in
//!   `frame.torso` still wins over the tracked one (an app that animates the hips itself).
//! * `"off"`: the rest torso whatever the frame says, and pose arms mapped in world axes
//!   (handrig before the torso existed).
//!
//! ## Measuring the user's torso ([`measure`])
//! Everything is measured on points in the avatar frame with avatar sides ([`TorsoPoints`]):
//! * **Hips**: the yaw of the hip line (left hip joint minus right hip joint) about +Y. Hip
//!   pitch and roll are not measured (two points cannot tell them from a lean).
//! * **Upper torso** (the shoulder girdle): `x` along the shoulder line (left shoulder minus
//!   right shoulder, exact), `up` the line from the hip center to the shoulder center made
//!   perpendicular to `x`, `z = x × up`. Without a hip center, `up` is the world's +Y: twist
//!   and side bend are measured, a forward lean is not.
//! * **Head**: `x` along the ear line (the eye line without both ears), forward from the ears
//!   to the eyes (the nose without eyes) made perpendicular to `x`, then turned by the
//!   neutral pitch of that line on an upright head: [`EYE_PITCH`] (ear to eye, up) or
//!   [`NOSE_PITCH`] (ear to nose, down).
//! * **Shrug**: the height of the shoulder line above the hip center along `up`, against its
//!   neutral height (the robust mean of the first `calibration.frames` measurements, like the
//!   body scale), as an elevation angle of a clavicle proportioned like the avatar's shoulder
//!   bone. Both shoulders shrug together: a shoulder line that tilts reads as a side bend.
//!
//! ## Onto the avatar
//! The avatar's own rest frames are read from its skeleton (hip line from the upper legs,
//! shoulder line from the upper arms, up from the hips to the shoulders; the head faces +Z),
//! so a user standing like the avatar's rest pose gives the rest pose. Then:
//! * `hips` = the hip yaw (the whole avatar turns with the user's hips);
//! * `spine`, `chest`, `upperChest` (those the avatar has, below its shoulders) share equally
//!   the rotation from the hips to the upper torso (lean, side bend, twist): each takes the
//!   same rotation about the same axis, so the upper torso's world rotation is exactly the
//!   user's;
//! * `neck` and `head` share the head's rotation relative to the upper torso the same way,
//!   so the head's world rotation is exactly the user's;
//! * `leftShoulder`, `rightShoulder` rotate up (or down) about the forward axis by the shrug.
//!
//! ## Anatomical limits ([`TorsoLimits`])
//! The spine's share (relative to the hips) and the head's (relative to the upper torso) are
//! split into a swing and a twist about +Y; the swing's forward/backward and sideways parts
//! and the twist are clamped to the normal active ranges of motion of the thoracolumbar and
//! cervical spine (American Academy of Orthopaedic Surgeons, *Joint Motion: Method of
//! Measuring and Recording*, 1965: thoracolumbar flexion 80°, extension 25°, lateral flexion
//! 35°, rotation 45°; cervical flexion 45°, extension 45°, lateral flexion 45°, rotation 60°);
//! shoulder girdle elevation 30° and depression 10° (sternoclavicular motion, ibid.); hips
//! yaw ±80° (beyond it the user's back is to the camera and MediaPipe's sides swap).
//!
//! ## Missing or poor input (decided behaviour)
//! Three groups come and go with tracking and are eased like hands and arms
//! ([`crate::filter::dropout`]): the hips (both hips seen), the spine with the shoulders
//! (both shoulders seen) and the neck with the head (a face frame measured). A lost group
//! holds its last rotations, then eases to rest; a returning one blends in. Landmarks below
//! `calibration.minVisibility` (pose visibility, body-joint confidence) are not seen.
//! Degenerate geometry (shoulders closer than 8 cm, hips closer than 4 cm, a face line
//! shorter than 2 cm, a forward line along the face line) counts as not seen. Nothing here
//! produces NaN: every direction is checked before it is normalized.

use core::f32::consts::PI;

use glam::{Mat3, Quat, Vec3};

use crate::filter::{DropoutOptions, Presence};
use crate::humanoid::bones::{HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::{Skeleton, VrmVersion};
use crate::input::mediapipe::{pose_landmark as pl, CameraMapping, PoseObservation};
use crate::math::clamp;
use crate::math::{insert_sorted, robust_mean_sorted};

/// Where the torso comes from (JS: `options.torso`). See the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TorsoSource {
    /// `"off"`: the rest torso; `frame.torso` and the pose's torso are ignored.
    Off,
    /// `"frame"` (default): the app's `frame.torso` (rest where not given); not driven.
    Frame,
    /// `"pose"`: tracked from `body` joints or the MediaPipe pose; driven.
    Pose,
}

impl TorsoSource {
    /// Every value, in the order the option lists them.
    pub const ALL: [TorsoSource; 3] = [TorsoSource::Off, TorsoSource::Frame, TorsoSource::Pose];

    /// The JS value.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            TorsoSource::Off => "off",
            TorsoSource::Frame => "frame",
            TorsoSource::Pose => "pose",
        }
    }
}

pub use crate::input::torso::{
    BodyJoint, BodyObservation, TorsoRotations, BODY_JOINT_COUNT, TORSO_BONES, TORSO_BONE_COUNT,
};

/// The slot of `bone` in [`TORSO_BONES`], if it is a torso bone.
#[must_use]
pub fn torso_slot(bone: HumanBone) -> Option<usize> {
    TORSO_BONES.iter().position(|b| *b == bone)
}

/// Ear-to-eye pitch (radians, up) of an upright head: the median over the four shared ASL
/// clips' MediaPipe pose landmarks (11.4 to 12.7 degrees per clip, signers facing the
/// camera), in line with anthropometry (the Frankfort plane through the ear canal passes
/// below the eyes).
pub const EYE_PITCH: f32 = 12.0 * PI / 180.0;
/// Ear-to-nose-tip pitch (radians, negative: down) of an upright head, from the same clips
/// (-4.5 to -6.6 degrees per clip); used only when the eyes are not seen.
pub const NOSE_PITCH: f32 = -5.0 * PI / 180.0;

/// Shortest shoulder line (m) taken as a measurement.
pub const MIN_SHOULDER_WIDTH: f32 = 0.08;
/// Shortest hip line (m) taken as a measurement.
pub const MIN_HIP_WIDTH: f32 = 0.04;
/// Shortest ear or eye line (m) taken as a measurement.
pub const MIN_FACE_WIDTH: f32 = 0.02;

/// The anatomical limits of [`crate::torso`] (radians). See the module docs for the sources.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsoLimits {
    /// Spine relative to the hips: forward lean (flexion).
    pub spine_flexion: f32,
    /// Backward lean (extension).
    pub spine_extension: f32,
    /// Side bend, either side.
    pub spine_lateral: f32,
    /// Twist about the spine, either side.
    pub spine_twist: f32,
    /// Head relative to the upper torso: looking down (flexion).
    pub head_flexion: f32,
    /// Looking up (extension).
    pub head_extension: f32,
    /// Tilt toward a shoulder, either side.
    pub head_lateral: f32,
    /// Turn, either side.
    pub head_twist: f32,
    /// Shoulder elevation (shrug).
    pub shoulder_elevation: f32,
    /// Shoulder depression.
    pub shoulder_depression: f32,
    /// Hips yaw, either side.
    pub hips_yaw: f32,
}

/// The limits handrig applies.
pub const LIMITS: TorsoLimits = {
    const D: f32 = PI / 180.0;
    TorsoLimits {
        spine_flexion: 80.0 * D,
        spine_extension: 25.0 * D,
        spine_lateral: 35.0 * D,
        spine_twist: 45.0 * D,
        head_flexion: 45.0 * D,
        head_extension: 45.0 * D,
        head_lateral: 45.0 * D,
        head_twist: 60.0 * D,
        shoulder_elevation: 30.0 * D,
        shoulder_depression: 10.0 * D,
        hips_yaw: 80.0 * D,
    }
};

/// Torso landmarks in handrig's internal frame with the avatar's sides (`[left, right]`):
/// what [`measure`] reads. `None` = not seen.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TorsoPoints {
    /// The hip center.
    pub pelvis: Option<Vec3>,
    /// The hip joints.
    pub hip: [Option<Vec3>; 2],
    /// The shoulder (upper arm) joints.
    pub shoulder: [Option<Vec3>; 2],
    /// The eyes.
    pub eye: [Option<Vec3>; 2],
    /// The ears.
    pub ear: [Option<Vec3>; 2],
    /// The nose tip.
    pub nose: Option<Vec3>,
}

impl TorsoPoints {
    /// From MediaPipe pose world landmarks: hips 23/24, shoulders 11/12, eyes 2/5, ears 7/8,
    /// nose 0, each side through `camera` (the avatar side's landmarks are the user side
    /// [`CameraMapping::pose_side_for`] says, reflected when it flips x). The hip center is
    /// the midpoint of the hips whatever their visibility: it is MediaPipe's world origin,
    /// estimated even out of view.
    #[must_use]
    pub fn from_pose(pose: &PoseObservation, camera: CameraMapping, min_visibility: f32) -> Self {
        let seen = |k: usize| {
            // NaN visibility compares false: not seen.
            (pose.visibility[k] >= min_visibility).then(|| camera.to_avatar(pose.world[k]))
        };
        let mut p = TorsoPoints {
            pelvis: Some(
                camera.to_avatar(0.5 * (pose.world[pl::LEFT_HIP] + pose.world[pl::RIGHT_HIP])),
            ),
            nose: seen(pl::NOSE),
            ..TorsoPoints::default()
        };
        for side in Side::BOTH {
            let s = side.index();
            let user_left = camera.pose_side_for(side) == Side::Left;
            let pick = |left: usize, right: usize| if user_left { left } else { right };
            p.hip[s] = seen(pick(pl::LEFT_HIP, pl::RIGHT_HIP));
            p.shoulder[s] = seen(pick(pl::LEFT_SHOULDER, pl::RIGHT_SHOULDER));
            p.eye[s] = seen(pick(pl::LEFT_EYE, pl::RIGHT_EYE));
            p.ear[s] = seen(pick(pl::LEFT_EAR, pl::RIGHT_EAR));
        }
        p
    }

    /// From body-tracker joints in the model's own frame (converted to the internal frame
    /// for VRM 0.x models).
    #[must_use]
    pub fn from_body(body: &BodyObservation, version: VrmVersion, min_visibility: f32) -> Self {
        let seen = |j: BodyJoint| {
            let k = j.index();
            (body.confidence[k] >= min_visibility && body.confidence[k] > 0.0)
                .then(|| version.position_to_internal(body.position[k]))
        };
        TorsoPoints {
            pelvis: seen(BodyJoint::Hips),
            hip: [
                seen(BodyJoint::LeftUpperLeg),
                seen(BodyJoint::RightUpperLeg),
            ],
            shoulder: [
                seen(BodyJoint::LeftUpperArm),
                seen(BodyJoint::RightUpperArm),
            ],
            eye: [seen(BodyJoint::LeftEye), seen(BodyJoint::RightEye)],
            ear: [seen(BodyJoint::LeftEar), seen(BodyJoint::RightEar)],
            nose: seen(BodyJoint::Nose),
        }
    }
}

/// What [`measure`] reads from [`TorsoPoints`] (internal frame). `None` = not measured.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TorsoMeasure {
    /// The hip line's yaw about +Y (radians; 0 = along +X, the avatar's left).
    pub hips_yaw: Option<f32>,
    /// The upper torso's frame: its columns are the shoulder line, up and forward.
    pub upper: Option<Quat>,
    /// Height (m) of the shoulder line above the hip center along the upper frame's up.
    pub height: Option<f32>,
    /// Half the shoulder line's length (m; 0 when not measured).
    pub half_width: f32,
    /// The head's frame (columns: the ear line, up, forward), neutral pitch removed.
    pub head: Option<Quat>,
}

/// The rotation whose columns are `x` (normalized) and `up_hint` made perpendicular to it
/// (and their cross product). `None` when either is too short or they are nearly parallel.
fn frame_x_up(x: Vec3, up_hint: Vec3) -> Option<Quat> {
    let x = x.try_normalize()?;
    let len = up_hint.length();
    let up = up_hint - x * x.dot(up_hint);
    // At least ~12 degrees between the two lines.
    if !(len > 0.0 && up.length() >= 0.2 * len) {
        return None;
    }
    let up = up.normalize();
    quat_from_axes(x, up, x.cross(up))
}

/// The rotation whose columns are `x` (normalized), `forward_hint` made perpendicular to it
/// (as z) and `z × x` (as y).
fn frame_x_forward(x: Vec3, forward_hint: Vec3) -> Option<Quat> {
    let x = x.try_normalize()?;
    let len = forward_hint.length();
    let z = forward_hint - x * x.dot(forward_hint);
    if !(len > 0.0 && z.length() >= 0.2 * len) {
        return None;
    }
    let z = z.normalize();
    quat_from_axes(x, z.cross(x), z)
}

fn quat_from_axes(x: Vec3, y: Vec3, z: Vec3) -> Option<Quat> {
    let q = Quat::from_mat3(&Mat3::from_cols(x, y, z)).normalize();
    q.is_finite().then_some(q)
}

fn both(p: [Option<Vec3>; 2]) -> Option<(Vec3, Vec3)> {
    p[0].zip(p[1])
}

/// Measures the user's torso from `p` (see the module docs). Allocates nothing.
#[must_use]
pub fn measure(p: &TorsoPoints) -> TorsoMeasure {
    let mut m = TorsoMeasure::default();
    if let Some((l, r)) = both(p.hip) {
        let d = Vec3::new(l.x - r.x, 0.0, l.z - r.z);
        if d.length() >= MIN_HIP_WIDTH {
            m.hips_yaw = Some((-d.z).atan2(d.x));
        }
    }
    if let Some((l, r)) = both(p.shoulder) {
        let x = l - r;
        if x.length() >= MIN_SHOULDER_WIDTH {
            let mid = 0.5 * (l + r);
            let from_hips = p
                .pelvis
                .and_then(|c| frame_x_up(x, mid - c).map(|u| (u, mid - c)));
            let upper = from_hips.map(|(u, _)| u).or_else(|| frame_x_up(x, Vec3::Y));
            if let Some(u) = upper {
                m.upper = Some(u);
                m.half_width = 0.5 * x.length();
                m.height = from_hips.map(|(u, chord)| chord.dot(u * Vec3::Y));
            }
        }
    }
    m.head = measure_head(p);
    m
}

fn measure_head(p: &TorsoPoints) -> Option<Quat> {
    let ears = both(p.ear).filter(|(l, r)| (*l - *r).length() >= MIN_FACE_WIDTH);
    let eyes = both(p.eye).filter(|(l, r)| (*l - *r).length() >= MIN_FACE_WIDTH);
    let x = ears.or(eyes).map(|(l, r)| l - r)?;
    // Ear to eye on each side where both are seen.
    let mut forward = Vec3::ZERO;
    let mut pairs = 0;
    for s in 0..2 {
        if let (Some(ear), Some(eye)) = (p.ear[s], p.eye[s]) {
            forward += eye - ear;
            pairs += 1;
        }
    }
    let (forward, pitch) = if pairs > 0 {
        (forward, EYE_PITCH)
    } else {
        let (nose, (l, r)) = p.nose.zip(ears)?;
        (nose - 0.5 * (l + r), NOSE_PITCH)
    };
    let raw = frame_x_forward(x, forward)?;
    Some((raw * Quat::from_rotation_x(pitch)).normalize())
}

/// Clamps `q` (a rotation of a chain whose rest direction is +Y) to a swing box and a twist:
/// forward swing (rotation about +X) in `-back..=forward`, sideways (about +Z) within
/// `±lateral`, twist about +Y within `±twist`.
#[must_use]
pub fn clamp_swing_twist(q: Quat, forward: f32, back: f32, lateral: f32, twist: f32) -> Quat {
    let (swing, tw) = crate::math::swing_twist(q, Vec3::Y);
    let s = swing.to_scaled_axis();
    let s = Vec3::new(
        clamp(s.x, -back, forward),
        0.0,
        clamp(s.z, -lateral, lateral),
    );
    let t = clamp(crate::math::twist_angle(tw, Vec3::Y), -twist, twist);
    let out = Quat::from_scaled_axis(s) * Quat::from_rotation_y(t);
    if out.is_finite() {
        out.normalize()
    } else {
        Quat::IDENTITY
    }
}

/// `q` to the power `1 / n` (the same axis, `1 / n` of the angle): `n` bones each taking it
/// compose to `q`.
fn share(q: Quat, n: usize) -> Quat {
    if n <= 1 {
        return q;
    }
    let q = if q.w < 0.0 { -q } else { q };
    let s = q.to_scaled_axis() / n as f32;
    let r = Quat::from_scaled_axis(s);
    if r.is_finite() {
        r.normalize()
    } else {
        Quat::IDENTITY
    }
}

/// The avatar's torso: which bones share what, and its rest frames.
#[derive(Clone, Copy, Debug, PartialEq)]
struct AvatarTorso {
    /// Spine bones that share the bend (present, parent-first), `spine_count` valid.
    spine: [HumanBone; 3],
    spine_count: usize,
    /// Neck and head (present), `head_count` valid.
    head: [HumanBone; 2],
    head_count: usize,
    /// The bone the arms hang from (the shoulders' or upper arms' effective parent).
    top: HumanBone,
    /// The rest upper-torso frame (as [`TorsoMeasure::upper`] of the rest pose).
    rest_upper: Quat,
    /// The rest hip line's yaw.
    rest_hips_yaw: f32,
    /// Per side: the shoulder bone's raising axis (its parent's frame) and its lever (shoulder
    /// joint to upper arm joint) over half the rest shoulder width, when it has one.
    shrug: [Option<(Vec3, f32)>; 2],
}

impl AvatarTorso {
    fn new(skeleton: &Skeleton) -> Self {
        let rest = |b: HumanBone| skeleton.rest_world(b).unwrap_or(Vec3::ZERO);
        // The arms' parent: the left shoulder's effective parent, else the upper arm's.
        let arm_root = if skeleton.has(HumanBone::LeftShoulder) {
            HumanBone::LeftShoulder
        } else {
            HumanBone::LeftUpperArm
        };
        let top = skeleton.parent(arm_root).unwrap_or(HumanBone::Spine);
        let mut spine = [HumanBone::Spine; 3];
        let mut spine_count = 0;
        // Walk from the top down to the hips, collecting spine bones (then reverse).
        let mut b = Some(top);
        while let Some(bone) = b {
            if matches!(
                bone,
                HumanBone::Spine | HumanBone::Chest | HumanBone::UpperChest
            ) && spine_count < 3
            {
                spine[spine_count] = bone;
                spine_count += 1;
            }
            b = skeleton.parent(bone);
        }
        spine[..spine_count].reverse();
        let mut head = [HumanBone::Head; 2];
        let mut head_count = 0;
        for bone in [HumanBone::Neck, HumanBone::Head] {
            if skeleton.has(bone) {
                head[head_count] = bone;
                head_count += 1;
            }
        }
        let [l, r] = [HumanBone::LeftUpperArm, HumanBone::RightUpperArm].map(rest);
        let shoulder_line = l - r;
        let rest_upper = frame_x_up(shoulder_line, 0.5 * (l + r) - rest(HumanBone::Hips))
            .or_else(|| frame_x_up(shoulder_line, Vec3::Y))
            .unwrap_or(Quat::IDENTITY);
        let hips = rest(HumanBone::LeftUpperLeg) - rest(HumanBone::RightUpperLeg);
        let rest_hips_yaw = if Vec3::new(hips.x, 0.0, hips.z).length() > 1e-6 {
            (-hips.z).atan2(hips.x)
        } else {
            0.0
        };
        let half_width = 0.5 * shoulder_line.length();
        let shrug = Side::BOTH.map(|side| {
            let [shoulder, upper, ..] = side.arm();
            if !skeleton.has(shoulder) || half_width <= 1e-6 {
                return None;
            }
            let offset = skeleton.rest_local(upper);
            let axis = offset.cross(Vec3::Y).try_normalize()?;
            let lever = offset.length() / half_width;
            (lever > 1e-3 && axis.is_finite()).then_some((axis, lever))
        });
        AvatarTorso {
            spine,
            spine_count,
            head,
            head_count,
            top,
            rest_upper,
            rest_hips_yaw,
            shrug,
        }
    }
}

/// The neutral height of the shoulder line above the hips (shrug reference), calibrated
/// like the body scale. Fixed storage: observing allocates nothing.
#[derive(Clone, Debug)]
struct Neutral {
    /// Ascending ([`crate::math::insert_sorted`]), `count` valid.
    samples: [f32; crate::body::MAX_CALIBRATION_FRAMES],
    count: usize,
    frames: usize,
    value: Option<f32>,
}

impl Neutral {
    fn new(frames: usize) -> Self {
        Neutral {
            samples: [0.0; crate::body::MAX_CALIBRATION_FRAMES],
            count: 0,
            frames: frames.clamp(1, crate::body::MAX_CALIBRATION_FRAMES),
            value: None,
        }
    }

    fn observe(&mut self, height: f32) {
        if self.count >= self.frames || !height.is_finite() {
            return;
        }
        insert_sorted(&mut self.samples, self.count, height);
        self.count += 1;
        self.value = robust_mean_sorted(&self.samples[..self.count]);
    }

    fn reset(&mut self) {
        self.count = 0;
        self.value = None;
    }
}

/// The bone groups of the torso that come and go with tracking.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TorsoGroup {
    Hips = 0,
    Spine = 1,
    Head = 2,
}

/// The torso stage of [`crate::Rig`]: the avatar's torso geometry, the neutral shrug
/// height, and the easing state of the tracked torso. One per rig; allocates nothing per
/// frame.
#[derive(Clone, Debug)]
pub struct TorsoSolver {
    avatar: AvatarTorso,
    neutral: Neutral,
    presence: [Presence; 3],
    shown: [Quat; TORSO_BONE_COUNT],
    anchor: [Quat; TORSO_BONE_COUNT],
}

impl TorsoSolver {
    /// A solver for `skeleton`; the shrug's neutral height averages `calibration_frames`
    /// measurements (clamped to 1..=300).
    #[must_use]
    pub fn new(skeleton: &Skeleton, calibration_frames: usize) -> Self {
        TorsoSolver {
            avatar: AvatarTorso::new(skeleton),
            neutral: Neutral::new(calibration_frames),
            presence: [Presence::default(); 3],
            shown: [Quat::IDENTITY; TORSO_BONE_COUNT],
            anchor: [Quat::IDENTITY; TORSO_BONE_COUNT],
        }
    }

    /// The bone the arms hang from (upperChest on a full rig): its world rotation times
    /// [`TorsoSolver::rest_upper`] is the avatar's upper-torso frame.
    #[must_use]
    pub fn top(&self) -> HumanBone {
        self.avatar.top
    }

    /// The avatar's rest upper-torso frame (columns: its shoulder line, up, forward).
    #[must_use]
    pub fn rest_upper(&self) -> Quat {
        self.avatar.rest_upper
    }

    /// The shrug's neutral height (m above the hip center), once measured.
    #[must_use]
    pub fn neutral_height(&self) -> Option<f32> {
        self.neutral.value
    }

    /// Forgets the easing history (a new session).
    pub fn restart(&mut self) {
        self.presence = [Presence::default(); 3];
        self.shown = [Quat::IDENTITY; TORSO_BONE_COUNT];
        self.anchor = [Quat::IDENTITY; TORSO_BONE_COUNT];
    }

    /// Restarts the shrug's neutral-height calibration.
    pub fn reset_calibration(&mut self) {
        self.neutral.reset();
    }

    /// Tracks the torso from `m` into `local` (internal frame): every torso bone the avatar
    /// has gets its eased rotation (rest when never tracked), and `solved` marks the groups
    /// measured this frame. `now_ms` and `timing` drive the easing. Allocates nothing.
    pub fn track(
        &mut self,
        skeleton: &Skeleton,
        m: &TorsoMeasure,
        now_ms: f64,
        timing: &DropoutOptions,
        local: &mut [Quat; BONE_COUNT],
        solved: &mut [bool; BONE_COUNT],
    ) {
        let a = self.avatar;
        let l = LIMITS;
        if let Some(h) = m.height {
            if m.upper.is_some() {
                self.neutral.observe(h);
            }
        }

        // Hips: the yaw relative to the avatar's rest hip line.
        let hips_target = m.hips_yaw.map(|yaw| {
            let d = clamp(wrap_angle(yaw - a.rest_hips_yaw), -l.hips_yaw, l.hips_yaw);
            Quat::from_rotation_y(d)
        });
        self.blend(
            TorsoGroup::Hips,
            &[(HumanBone::Hips, hips_target.unwrap_or(Quat::IDENTITY))],
            hips_target.is_some(),
            now_ms,
            timing,
        );
        let hips = self.shown[slot(HumanBone::Hips)];
        local[HumanBone::Hips.index()] = hips;

        // Spine: the upper frame relative to the (shown) hips, shared by the spine bones.
        let spine_live = m.upper.is_some();
        let spine_share = m.upper.map_or(Quat::IDENTITY, |u| {
            let world = (u * a.rest_upper.conjugate()).normalize();
            let rel = (hips.conjugate() * world).normalize();
            let rel = clamp_swing_twist(
                rel,
                l.spine_flexion,
                l.spine_extension,
                l.spine_lateral,
                l.spine_twist,
            );
            share(rel, a.spine_count)
        });
        let shrug = match (m.height, self.neutral.value, m.upper) {
            (Some(h), Some(n), Some(_)) if m.half_width > 0.0 => h - n,
            _ => 0.0,
        };
        let mut spine_targets = [(HumanBone::Spine, Quat::IDENTITY); 5];
        let mut n = 0;
        for &bone in &a.spine[..a.spine_count] {
            spine_targets[n] = (bone, spine_share);
            n += 1;
        }
        for side in Side::BOTH {
            if let Some((axis, lever)) = a.shrug[side.index()] {
                let s = (shrug / (m.half_width * lever)).clamp(-1.0, 1.0);
                let angle = clamp(
                    if s.is_finite() { s.asin() } else { 0.0 },
                    -l.shoulder_depression,
                    l.shoulder_elevation,
                );
                spine_targets[n] = (side.arm()[0], Quat::from_axis_angle(axis, angle));
                n += 1;
            }
        }
        self.blend(
            TorsoGroup::Spine,
            &spine_targets[..n],
            spine_live,
            now_ms,
            timing,
        );
        for (bone, _) in &spine_targets[..n] {
            local[bone.index()] = self.shown[slot(*bone)];
        }

        // Head: relative to the avatar's upper torso as shown, shared by neck and head.
        let head_live = m.head.is_some();
        let head_share = m.head.map_or(Quat::IDENTITY, |h| {
            let parent = skeleton
                .parent(a.head[0])
                .map_or(Quat::IDENTITY, |p| chain_rotation(skeleton, local, p));
            let rel = (parent.conjugate() * h).normalize();
            let rel = clamp_swing_twist(
                rel,
                l.head_flexion,
                l.head_extension,
                l.head_lateral,
                l.head_twist,
            );
            share(rel, a.head_count)
        });
        let mut head_targets = [(HumanBone::Head, Quat::IDENTITY); 2];
        for (k, &bone) in a.head[..a.head_count].iter().enumerate() {
            head_targets[k] = (bone, head_share);
        }
        self.blend(
            TorsoGroup::Head,
            &head_targets[..a.head_count],
            head_live,
            now_ms,
            timing,
        );
        for (bone, _) in &head_targets[..a.head_count] {
            local[bone.index()] = self.shown[slot(*bone)];
        }

        for (bone, live) in [
            (HumanBone::Hips, hips_target.is_some()),
            (HumanBone::Spine, spine_live),
            (HumanBone::Chest, spine_live),
            (HumanBone::UpperChest, spine_live),
            (HumanBone::LeftShoulder, spine_live),
            (HumanBone::RightShoulder, spine_live),
            (HumanBone::Neck, head_live),
            (HumanBone::Head, head_live),
        ] {
            solved[bone.index()] = live && skeleton.has(bone);
        }
    }

    /// Eases one group toward `targets` (or rest when not `live`) into `shown`.
    fn blend(
        &mut self,
        group: TorsoGroup,
        targets: &[(HumanBone, Quat)],
        live: bool,
        now_ms: f64,
        timing: &DropoutOptions,
    ) {
        let blend = self.presence[group as usize].update(now_ms, live, timing);
        for &(bone, target) in targets {
            let i = slot(bone);
            let q = blend.show(target, &mut self.anchor[i], self.shown[i]);
            self.shown[i] = if q.is_finite() { q } else { Quat::IDENTITY };
        }
    }
}

fn slot(bone: HumanBone) -> usize {
    torso_slot(bone).unwrap_or(0)
}

/// Wraps an angle to `(-pi, pi]`.
fn wrap_angle(a: f32) -> f32 {
    let a = (a + PI).rem_euclid(2.0 * PI) - PI;
    if a <= -PI {
        a + 2.0 * PI
    } else {
        a
    }
}

/// World rotation of `bone` from local rotations (product along its effective parents).
#[must_use]
pub fn chain_rotation(skeleton: &Skeleton, local: &[Quat; BONE_COUNT], bone: HumanBone) -> Quat {
    let mut chain = [HumanBone::Hips; 8];
    let mut n = 0;
    let mut b = Some(bone);
    while let Some(p) = b {
        if n < chain.len() {
            chain[n] = p;
            n += 1;
        }
        b = skeleton.parent(p);
    }
    chain[..n]
        .iter()
        .rev()
        .fold(Quat::IDENTITY, |q, l| q * local[l.index()])
        .normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deg(d: f32) -> f32 {
        d * PI / 180.0
    }

    #[test]
    fn an_upright_user_facing_the_camera_measures_identity() {
        let p = TorsoPoints {
            pelvis: Some(Vec3::ZERO),
            hip: [
                Some(Vec3::new(0.1, 0.0, 0.0)),
                Some(Vec3::new(-0.1, 0.0, 0.0)),
            ],
            shoulder: [
                Some(Vec3::new(0.18, 0.5, 0.0)),
                Some(Vec3::new(-0.18, 0.5, 0.0)),
            ],
            ear: [
                Some(Vec3::new(0.07, 0.65, 0.0)),
                Some(Vec3::new(-0.07, 0.65, 0.0)),
            ],
            eye: [
                Some(Vec3::new(0.03, 0.65 + 0.08 * EYE_PITCH.tan(), 0.08)),
                Some(Vec3::new(-0.03, 0.65 + 0.08 * EYE_PITCH.tan(), 0.08)),
            ],
            nose: None,
        };
        let m = measure(&p);
        assert!(m.hips_yaw.unwrap().abs() < 1e-6);
        assert!(m.upper.unwrap().angle_between(Quat::IDENTITY) < 1e-5);
        assert!(m.head.unwrap().angle_between(Quat::IDENTITY) < 1e-5);
        assert!((m.height.unwrap() - 0.5).abs() < 1e-6);
        assert!((m.half_width - 0.18).abs() < 1e-6);
    }

    #[test]
    fn a_turned_leaning_user_measures_the_rotation() {
        let r = Quat::from_rotation_y(deg(30.0)) * Quat::from_rotation_x(deg(20.0));
        let p = TorsoPoints {
            pelvis: Some(Vec3::ZERO),
            shoulder: [
                Some(r * Vec3::new(0.18, 0.5, 0.0)),
                Some(r * Vec3::new(-0.18, 0.5, 0.0)),
            ],
            ..TorsoPoints::default()
        };
        let m = measure(&p);
        assert!(m.upper.unwrap().angle_between(r) < 1e-5, "{:?}", m.upper);
        assert_eq!(m.hips_yaw, None);
        assert_eq!(m.head, None);
        // Without the hip center, the lean is not measured, the turn is.
        let m = measure(&TorsoPoints { pelvis: None, ..p });
        let want = Quat::from_rotation_y(deg(30.0));
        assert!(m.upper.unwrap().angle_between(want) < 1e-5);
        assert_eq!(m.height, None);
    }

    #[test]
    fn degenerate_points_measure_nothing_and_never_nan() {
        let same = Some(Vec3::new(0.1, 0.5, 0.0));
        let p = TorsoPoints {
            pelvis: Some(Vec3::new(0.1, 0.5, 0.0)),
            hip: [same, same],
            shoulder: [same, same],
            ear: [same, same],
            eye: [same, same],
            nose: same,
        };
        assert_eq!(measure(&p), TorsoMeasure::default());
        // Shoulders straight above each other: no frame.
        let p = TorsoPoints {
            shoulder: [
                Some(Vec3::new(0.0, 0.7, 0.0)),
                Some(Vec3::new(0.0, 0.3, 0.0)),
            ],
            pelvis: Some(Vec3::ZERO),
            ..TorsoPoints::default()
        };
        assert_eq!(measure(&p).upper, None);
        let nan = Some(Vec3::NAN);
        let p = TorsoPoints {
            pelvis: nan,
            hip: [nan, nan],
            shoulder: [nan, nan],
            ear: [nan, nan],
            eye: [nan, nan],
            nose: nan,
        };
        let m = measure(&p);
        assert!(m.upper.is_none() && m.head.is_none() && m.hips_yaw.is_none());
    }

    #[test]
    fn clamping_keeps_rotations_within_the_box() {
        let q = Quat::from_rotation_x(deg(100.0));
        let c = clamp_swing_twist(q, deg(80.0), deg(25.0), deg(35.0), deg(45.0));
        assert!((c.angle_between(Quat::IDENTITY) - deg(80.0)).abs() < 1e-4);
        let q = Quat::from_rotation_x(deg(-40.0));
        let c = clamp_swing_twist(q, deg(80.0), deg(25.0), deg(35.0), deg(45.0));
        assert!((c.angle_between(Quat::from_rotation_x(deg(-25.0)))) < 1e-4);
        let q = Quat::from_rotation_y(deg(90.0)) * Quat::from_rotation_z(deg(10.0));
        let c = clamp_swing_twist(q, deg(80.0), deg(25.0), deg(35.0), deg(45.0));
        let (_, t) = crate::math::swing_twist(c, Vec3::Y);
        assert!((crate::math::twist_angle(t, Vec3::Y).abs() - deg(45.0)).abs() < 1e-4);
        // Within the box: unchanged.
        let q = Quat::from_rotation_z(deg(15.0)) * Quat::from_rotation_y(deg(30.0));
        let c = clamp_swing_twist(q, deg(80.0), deg(25.0), deg(35.0), deg(45.0));
        assert!(c.angle_between(q) < 1e-4);
    }

    #[test]
    fn shares_compose_to_the_whole() {
        let q = Quat::from_rotation_y(0.5) * Quat::from_rotation_x(0.3);
        for n in 1..=3 {
            let s = share(q, n);
            let mut p = Quat::IDENTITY;
            for _ in 0..n {
                p *= s;
            }
            assert!(p.angle_between(q) < 1e-5, "n = {n}");
        }
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-5);
        assert!((wrap_angle(-0.5) + 0.5).abs() < 1e-6);
    }
}
