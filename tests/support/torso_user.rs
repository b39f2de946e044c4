//! Synthetic users posed by a known torso pose, for known-answer tests and the torso eval:
//! MediaPipe pose world landmarks (and the same body as body-tracker joints) of a user whose
//! hips turn, whose upper body pivots rigidly about the hip center (lean, turn, side bend),
//! whose shoulders shrug and whose head turns about the neck base, with both arms held in
//! the upper body's frame.
//!
//! The user's frame: +Y up, +Z toward the camera, the user's left at +X, origin at the hip
//! center (MediaPipe's world origin). The head's landmarks are placed with the neutral ear-to-
//! eye and ear-to-nose pitches handrig documents (`handrig::torso::EYE_PITCH`,
//! `NOSE_PITCH`): the test checks the frames, sharing, limits and mappings, not those
//! anthropometric constants (the eval reads them on the real recordings).

use core::f32::consts::PI;

use glam::{Quat, Vec3};
use handrig::mediapipe::{PoseObservation, POSE_LANDMARKS};
use handrig::torso::{BodyJoint, BodyObservation, EYE_PITCH, NOSE_PITCH};

/// Degrees to radians.
pub fn deg(d: f32) -> f32 {
    d * PI / 180.0
}

/// A known torso pose (user frame).
#[derive(Clone, Copy, Debug)]
pub struct TorsoPose {
    pub name: &'static str,
    /// Hips yaw about +Y (radians).
    pub hips_yaw: f32,
    /// The upper body relative to the hips, pivoting at the hip center.
    pub spine: Quat,
    /// The head relative to the upper body, pivoting at the neck base.
    pub head: Quat,
    /// Both shoulders raised by this much (m) in the upper body's frame.
    pub shrug: f32,
}

impl TorsoPose {
    /// At rest: standing upright, facing the camera.
    pub const REST: TorsoPose = TorsoPose {
        name: "rest",
        hips_yaw: 0.0,
        spine: Quat::IDENTITY,
        head: Quat::IDENTITY,
        shrug: 0.0,
    };

    /// The hips' world rotation.
    pub fn hips(&self) -> Quat {
        Quat::from_rotation_y(self.hips_yaw)
    }

    /// The upper torso's world rotation (its frame: shoulder line, up, forward).
    pub fn upper(&self) -> Quat {
        self.hips() * self.spine
    }

    /// The head's world rotation.
    pub fn head_world(&self) -> Quat {
        self.upper() * self.head
    }
}

/// The acceptance poses: lean forward 20 degrees, turn 30, side bend 15, their combinations,
/// plus turned hips, a turned and nodding head, and a shrug.
pub fn poses() -> Vec<TorsoPose> {
    let lean = Quat::from_rotation_x(deg(20.0));
    let turn = Quat::from_rotation_y(deg(30.0));
    let bend = Quat::from_rotation_z(deg(15.0));
    let p = |name, spine: Quat| TorsoPose {
        name,
        spine,
        ..TorsoPose::REST
    };
    vec![
        TorsoPose::REST,
        p("lean forward 20", lean),
        p("turn 30", turn),
        p("side bend 15", bend),
        p("lean 20 + turn 30", turn * lean),
        p("turn 30 + bend 15", turn * bend),
        p("lean 20 + bend 15", lean * bend),
        p("lean 20 + turn 30 + bend 15", turn * lean * bend),
        p(
            "turn -30 + bend -15",
            Quat::from_rotation_y(deg(-30.0)) * bend.inverse(),
        ),
        TorsoPose {
            name: "hips 25 + lean 20",
            hips_yaw: deg(25.0),
            ..p("", lean)
        },
        TorsoPose {
            name: "head turn 40 + nod 15, lean 20",
            head: Quat::from_rotation_y(deg(40.0)) * Quat::from_rotation_x(deg(15.0)),
            ..p("", lean)
        },
        TorsoPose {
            name: "head tilt 20, turn 30",
            head: Quat::from_rotation_z(deg(20.0)),
            ..p("", turn)
        },
    ]
}

/// The user's body at rest (user frame, meters): an adult of MediaPipe's proportions.
pub const HIP_HALF: f32 = 0.09;
pub const SHOULDER_HALF: f32 = 0.18;
pub const SHOULDER_HEIGHT: f32 = 0.50;
/// The neck base: the head's pivot.
pub const NECK: Vec3 = Vec3::new(0.0, 0.55, -0.01);
/// The ears' midpoint relative to the neck base.
pub const EAR_MID: Vec3 = Vec3::new(0.0, 0.11, 0.0);
pub const EAR_HALF: f32 = 0.075;
pub const EYE_HALF: f32 = 0.032;
/// Ear-to-eye and ear-to-nose distances (m).
pub const EYE_REACH: f32 = 0.085;
pub const NOSE_REACH: f32 = 0.105;

/// One arm held in the upper body's frame: elbow and wrist relative to the shoulder.
#[derive(Clone, Copy, Debug)]
pub struct ArmPose {
    pub elbow: Vec3,
    pub wrist: Vec3,
}

/// Arms for frame `k` of a clip: the user's left hand near the chin, the right in front of
/// the chest, each moving a little from frame to frame (within 75% of a 0.52 m arm, so
/// the avatar's shoulder option stays still).
pub fn arms(k: usize) -> [ArmPose; 2] {
    let t = k as f32 * 0.4;
    let wobble = Vec3::new(
        0.02 * t.sin(),
        0.02 * (1.3 * t).cos(),
        0.015 * (0.7 * t).sin(),
    );
    [
        ArmPose {
            elbow: Vec3::new(0.05, -0.24, 0.10),
            wrist: Vec3::new(-0.08, 0.02, 0.26) + wobble,
        },
        ArmPose {
            elbow: Vec3::new(-0.04, -0.25, 0.08),
            wrist: Vec3::new(0.10, -0.12, 0.28) - wobble,
        },
    ]
}

/// Named points of the posed user (user frame), `[left, right]` for pairs.
#[derive(Clone, Copy, Debug)]
pub struct UserPoints {
    pub hip: [Vec3; 2],
    pub shoulder: [Vec3; 2],
    pub elbow: [Vec3; 2],
    pub wrist: [Vec3; 2],
    pub ear: [Vec3; 2],
    pub eye: [Vec3; 2],
    pub nose: Vec3,
}

/// The posed user.
pub fn points(pose: &TorsoPose, arms: &[ArmPose; 2]) -> UserPoints {
    let hips = pose.hips();
    let upper = pose.upper();
    let sx = [1.0, -1.0];
    let hip = sx.map(|s| hips * Vec3::new(s * HIP_HALF, 0.0, 0.0));
    let shoulder_rest = sx.map(|s| Vec3::new(s * SHOULDER_HALF, SHOULDER_HEIGHT + pose.shrug, 0.0));
    let shoulder = shoulder_rest.map(|p| upper * p);
    let elbow = [0, 1].map(|i| upper * (shoulder_rest[i] + arms[i].elbow));
    let wrist = [0, 1].map(|i| upper * (shoulder_rest[i] + arms[i].wrist));
    let head_point = |p: Vec3| upper * (NECK + pose.head * p);
    let ear = sx.map(|s| head_point(EAR_MID + Vec3::new(s * EAR_HALF, 0.0, 0.0)));
    let eye_dir = Vec3::new(0.0, EYE_PITCH.sin(), EYE_PITCH.cos());
    let eye =
        sx.map(|s| head_point(EAR_MID + EYE_REACH * eye_dir + Vec3::new(s * EYE_HALF, 0.0, 0.0)));
    let nose_dir = Vec3::new(0.0, NOSE_PITCH.sin(), NOSE_PITCH.cos());
    let nose = head_point(EAR_MID + NOSE_REACH * nose_dir);
    UserPoints {
        hip,
        shoulder,
        elbow,
        wrist,
        ear,
        eye,
        nose,
    }
}

/// User frame to MediaPipe's camera axes for an un-mirrored image: `(x, -y, -z)`.
pub fn to_camera(p: Vec3) -> Vec3 {
    Vec3::new(p.x, -p.y, -p.z)
}

/// A rotation of the user's frame as it acts on MediaPipe's camera axes (`(x, -y, -z)` is a
/// half turn about +X): for turning hand landmarks with the body.
pub fn camera_rotation(q: Quat) -> Quat {
    Quat::from_xyzw(q.x, -q.y, -q.z, q.w)
}

/// MediaPipe pose world landmarks of the posed user (every landmark fully visible; the
/// mouth, fingers and legs placed plausibly, handrig does not read them).
pub fn pose_landmarks(u: &UserPoints) -> PoseObservation {
    let mut w = [Vec3::ZERO; POSE_LANDMARKS];
    w[0] = u.nose;
    // Eyes: inner, center, outer per side (1-3 left, 4-6 right).
    for (s, base) in [(0usize, 1usize), (1, 4)] {
        let toward_nose = (u.nose - u.eye[s]) * 0.15;
        w[base] = u.eye[s] + toward_nose;
        w[base + 1] = u.eye[s];
        w[base + 2] = u.eye[s] - toward_nose;
    }
    w[7] = u.ear[0];
    w[8] = u.ear[1];
    w[9] = u.nose + Vec3::new(0.02, -0.03, 0.0);
    w[10] = u.nose + Vec3::new(-0.02, -0.03, 0.0);
    w[11] = u.shoulder[0];
    w[12] = u.shoulder[1];
    w[13] = u.elbow[0];
    w[14] = u.elbow[1];
    w[15] = u.wrist[0];
    w[16] = u.wrist[1];
    for (k, s) in [(17, 0), (18, 1), (19, 0), (20, 1), (21, 0), (22, 1)] {
        let forearm = (u.wrist[s] - u.elbow[s]).normalize_or_zero();
        w[k] = u.wrist[s] + 0.07 * forearm;
    }
    w[23] = u.hip[0];
    w[24] = u.hip[1];
    for (k, s, drop) in [
        (25, 0, 0.45),
        (26, 1, 0.45),
        (27, 0, 0.85),
        (28, 1, 0.85),
        (29, 0, 0.9),
        (30, 1, 0.9),
        (31, 0, 0.92),
        (32, 1, 0.92),
    ] {
        w[k] = u.hip[s] - Vec3::new(0.0, drop, 0.0);
    }
    PoseObservation {
        world: w.map(to_camera),
        visibility: [1.0; POSE_LANDMARKS],
    }
}

/// The same user as body-tracker joints in an avatar-like frame (what an app converting its
/// tracker's joints passes): the user frame moved up by `hip_height`, confidence 1.
pub fn body_joints(u: &UserPoints, hip_height: f32) -> BodyObservation {
    let up = Vec3::new(0.0, hip_height, 0.0);
    let mut b = BodyObservation::default();
    let mut put = |j: BodyJoint, p: Vec3| {
        b.position[j.index()] = p + up;
        b.confidence[j.index()] = 1.0;
    };
    put(BodyJoint::Hips, 0.5 * (u.hip[0] + u.hip[1]));
    put(BodyJoint::LeftUpperLeg, u.hip[0]);
    put(BodyJoint::RightUpperLeg, u.hip[1]);
    put(BodyJoint::LeftUpperArm, u.shoulder[0]);
    put(BodyJoint::RightUpperArm, u.shoulder[1]);
    put(BodyJoint::Nose, u.nose);
    put(BodyJoint::LeftEye, u.eye[0]);
    put(BodyJoint::RightEye, u.eye[1]);
    put(BodyJoint::LeftEar, u.ear[0]);
    put(BodyJoint::RightEar, u.ear[1]);
    b
}

/// A rotation of the user seen in a mirror (x reflected): what `mirror: true` shows.
pub fn mirrored(q: Quat) -> Quat {
    Quat::from_xyzw(q.x, -q.y, -q.z, q.w)
}
