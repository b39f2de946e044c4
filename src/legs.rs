//! Legs from the pose's lower body (MediaPipe pose landmarks 23-32): each leg solved by the
//! analytic two-bone IK of the arms ([`crate::ik::TwoBoneIk`]) on the user's hip-to-ankle
//! vector scaled to the avatar's leg, the knee's pole from the tracked knee, the foot turned
//! along the tracked heel-to-toe line; then the joint limits: the knee a hinge that never
//! bends backwards, the hip and ankle within the normal ranges of motion.
//!
//! The ranges (degrees) are the American Academy of Orthopaedic Surgeons' normal values
//! (Greene & Heckman, *The Clinical Measurement of Joint Motion*, AAOS 1994; the 1965 AAOS
//! *Joint Motion: Method of Measuring and Recording* gives the same): hip flexion 120,
//! extension 30, abduction 45, adduction 30, internal and external rotation 45; ankle
//! plantarflexion 50. The knee's flexion is limited to 150 rather than the AAOS' active 135,
//! and the ankle's dorsiflexion to 40 rather than its active 20: a deep squat, heels down,
//! reaches about 150-165 at the knee and about 40 at the ankle under the body's weight
//! (Hemmerich et al. 2006, *Hip, knee, and ankle kinematics of high range of motion activities
//! of daily living*, J Orthop Res 24:770); at 20 a squatting avatar rose onto its toes. The foot's turn about the shin (MediaPipe gives one toe point, so the forefoot's
//! own adduction and the subtalar inversion are not seen apart) is limited to 20 either way.
//! See `docs/how-it-works/legs.md`.

use core::f32::consts::PI;

use glam::{Mat3, Quat, Vec3};

use crate::humanoid::bones::{HumanBone, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::ik::{ArmChain, ArmGoal, ArmIk, ArmPose, TwoBoneIk, TwoBoneOptions};
use crate::kinematics::swing;

/// Options of the legs (JS: `options.legs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegOptions {
    /// Solve the legs from the pose's lower body. Default `true`.
    pub enabled: bool,
    /// A leg is tracked when its hip, knee and ankle have at least this visibility and lie
    /// inside the image (when the pose's image landmarks are given). Default 0.5.
    pub min_visibility: f32,
    /// The hips move with the user (root motion): up and down so the lower foot stands on the
    /// floor, sideways and toward the camera from the pose's image. `false` keeps the hips
    /// where they rest (the feet may then float or sink). Default `true`.
    pub move_hips: bool,
    /// A foot on the floor stays where it was planted while it bears weight. Default `true`.
    pub plant: bool,
    /// Where legs that are not seen rest. Default [`LegRest::Standing`].
    pub rest: LegRest,
}

/// Where legs that are not seen rest (JS: `options.legs.rest`): a head-and-shoulders webcam
/// sees none.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LegRest {
    /// `"standing"`: the avatar's rest pose (legs straight, feet on the floor).
    #[default]
    Standing,
    /// `"seated"`: hips and knees bent [`SEATED_BEND`] (the thighs forward, the shins down,
    /// the feet flat), the hips where they rest: sitting on a chair at the hips' height.
    Seated,
}

/// The seated rest's hip flexion and knee flexion (radians): a chair's right angles.
pub const SEATED_BEND: f32 = PI / 2.0;

/// The avatar's soles: the floor's height and, per foot, the heel and ball points under the
/// foot joint and the toes joint, as offsets from the foot joint at rest (world axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Soles {
    /// The floor's height (m): `y = 0` when the lowest foot or toes joint is within 15 cm
    /// above it (VRM avatars stand on the origin), else that joint's height.
    pub floor: f32,
    /// `[left, right]` of `[heel, ball]`, from the foot joint.
    pub points: [[Vec3; 2]; 2],
}

impl Soles {
    /// The soles of `skeleton` at rest (`None` without both feet).
    #[must_use]
    pub fn new(skeleton: &Skeleton) -> Option<Self> {
        let rest = |b: HumanBone| skeleton.rest_world(b);
        let mut lowest = f32::INFINITY;
        for side in Side::BOTH {
            let [_, _, foot, toes] = leg_bones(side);
            lowest = lowest.min(rest(foot)?.y);
            lowest = lowest.min(rest(toes).map_or(f32::INFINITY, |p| p.y));
        }
        let floor = lowest.min(0.0).max(lowest - 0.15);
        let points = Side::BOTH.map(|side| {
            let [upper, _, foot, toes] = leg_bones(side);
            let at = rest(foot).unwrap_or_default();
            let down = floor - at.y;
            // Without toes: the ball a fifth of the leg's length ahead of the heel.
            let ball = rest(toes)
                .map_or(Vec3::Z * 0.2 * (rest(upper).unwrap_or(at).y - at.y), |t| {
                    t - at
                });
            [Vec3::new(0.0, down, 0.0), Vec3::new(ball.x, down, ball.z)]
        });
        Some(Soles { floor, points })
    }

    /// The lower of `side`'s heel and ball for the foot joint at `at` turned by `rotation`.
    #[must_use]
    pub fn lowest(&self, side: Side, at: Vec3, rotation: Quat) -> Vec3 {
        let [heel, ball] = self.points[side.index()].map(|p| at + rotation * p);
        if heel.y <= ball.y {
            heel
        } else {
            ball
        }
    }
}

const DEG: f32 = PI / 180.0;
/// Hip: flexion, extension, abduction, adduction, rotation either way (AAOS).
const HIP_FLEXION: f32 = 120.0 * DEG;
const HIP_EXTENSION: f32 = 30.0 * DEG;
const HIP_ABDUCTION: f32 = 45.0 * DEG;
const HIP_ADDUCTION: f32 = 30.0 * DEG;
const HIP_ROTATION: f32 = 45.0 * DEG;
/// Knee flexion (deep squat, Hemmerich et al. 2006); never below 0 (a hinge).
pub const KNEE_FLEXION: f32 = 150.0 * DEG;
/// Ankle: dorsiflexion (toes up; weight-bearing, Hemmerich et al. 2006), plantarflexion (toes
/// down), turn about the shin.
const ANKLE_DORSIFLEXION: f32 = 40.0 * DEG;
const ANKLE_PLANTARFLEXION: f32 = 50.0 * DEG;
const FOOT_TURN: f32 = 20.0 * DEG;
/// The knee's collinear cone ([`TwoBoneOptions::collinear_cone`], the arms' 10 degrees):
/// a tracked knee within this of the hip-ankle line (the knee bent less than about twice
/// it) only slowly turns the leg's bend plane from where it was, as the leg moves. A nearly
/// straight leg's knee lies a few cm off the line, on the side MediaPipe's noise puts it:
/// with 10 degrees the bend plane (the thigh's twist) followed that noise (the real walking
/// video: a thigh twisted 93 degrees between frames, the knee bent 7).
const KNEE_CONE: f32 = 20.0 * DEG;

/// The leg bones of `side`: `[upperLeg, lowerLeg, foot, toes]`.
#[must_use]
pub const fn leg_bones(side: Side) -> [HumanBone; 4] {
    match side {
        Side::Left => [
            HumanBone::LeftUpperLeg,
            HumanBone::LeftLowerLeg,
            HumanBone::LeftFoot,
            HumanBone::LeftToes,
        ],
        Side::Right => [
            HumanBone::RightUpperLeg,
            HumanBone::RightLowerLeg,
            HumanBone::RightFoot,
            HumanBone::RightToes,
        ],
    }
}

/// The subject's pose landmarks of one leg: `[hip, knee, ankle, heel, foot index]`.
#[must_use]
pub const fn leg_landmarks(user: Side) -> [usize; 5] {
    let o = user.index();
    [23 + o, 25 + o, 27 + o, 29 + o, 31 + o]
}

/// One of the avatar's legs as the two-bone solver sees it (thigh, shin; the foot is its
/// "hand"), with its rest axes.
#[derive(Clone, Debug)]
pub struct Leg {
    chain: ArmChain,
    ik: TwoBoneIk,
    /// The thigh's rest direction (unit, hip to knee) and its hinge axis (unit, +X made
    /// perpendicular to it): the rest frame the hinge is built on.
    thigh: Vec3,
    hinge: Vec3,
    /// The shin's rest direction (unit, knee to ankle, in the thigh's frame).
    shin: Vec3,
    /// +X for the left leg, -X for the right: abduction's direction.
    outward: Vec3,
}

/// Where a tracked leg puts the avatar's, world (internal frame, avatar axes), scaled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegTarget {
    /// The avatar's hip joint (upperLeg).
    pub hip: Vec3,
    /// The tracked knee (the pole).
    pub knee: Vec3,
    /// The tracked ankle (the IK target).
    pub ankle: Vec3,
    /// The tracked heel-to-toe direction, when both are seen.
    pub foot: Option<Vec3>,
}

/// A solved leg: local rotations `[upperLeg, lowerLeg, foot]` and the joints placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegPose {
    /// Local rotations of upperLeg, lowerLeg, foot.
    pub local: [Quat; 3],
    /// The knee angle (radians, 0 straight, positive bent: never negative).
    pub knee_angle: f32,
}

impl Leg {
    /// `side`'s leg of `skeleton`; `None` when it lacks upperLeg, lowerLeg or foot.
    #[must_use]
    pub fn new(skeleton: &Skeleton, side: Side) -> Option<Self> {
        let [upper, lower, foot, _] = leg_bones(side);
        if ![upper, lower, foot].iter().all(|b| skeleton.has(*b)) {
            return None;
        }
        let chain = ArmChain {
            side,
            bones: [upper, lower, foot],
            parent: skeleton.parent(upper),
            upper: skeleton.rest_local(lower),
            lower: skeleton.rest_local(foot),
            // The knee's fallback side: forward.
            outward: Vec3::Z,
            shoulder: None,
            shoulder_offset: Vec3::ZERO,
            wrist: None,
        };
        let thigh = chain.upper.try_normalize()?;
        let hinge = (Vec3::X - thigh * thigh.x).try_normalize()?;
        let ik = TwoBoneIk::new(TwoBoneOptions {
            default_pole: Vec3::Z,
            collinear_cone: KNEE_CONE,
        })
        .ok()?;
        let outward = if side == Side::Left {
            Vec3::X
        } else {
            Vec3::NEG_X
        };
        Some(Leg {
            shin: chain.lower.try_normalize()?,
            chain,
            ik,
            thigh,
            hinge,
            outward,
        })
    }

    /// The leg's length (thigh plus shin, m).
    #[must_use]
    pub fn length(&self) -> f32 {
        self.chain.upper.length() + self.chain.lower.length()
    }

    /// The thigh's and the shin's lengths (m).
    #[must_use]
    pub fn lengths(&self) -> (f32, f32) {
        (self.chain.upper.length(), self.chain.lower.length())
    }

    /// The rest pose's local rotations `[upperLeg, lowerLeg, foot, toes]` for `rest` (in the
    /// hips' frame): identity standing; seated, the thigh turned from its rest direction to
    /// the hips' forward and the shin to straight down (hip and knee at [`SEATED_BEND`] on a
    /// straight rest leg), the foot as the shin turns it (flat).
    #[must_use]
    pub fn rest_pose(&self, rest: LegRest) -> [Quat; 4] {
        match rest {
            LegRest::Standing => [Quat::IDENTITY; 4],
            LegRest::Seated => {
                let (sin, cos) = SEATED_BEND.sin_cos();
                let thigh = Quat::from_rotation_arc(self.thigh, Vec3::new(0.0, -cos, sin));
                let shin = Quat::from_rotation_arc(self.shin, thigh.conjugate() * Vec3::NEG_Y);
                [thigh, shin, Quat::IDENTITY, Quat::IDENTITY]
            }
        }
    }

    /// Forgets the knee's swivel memory.
    pub fn reset(&mut self) {
        self.ik.reset();
    }

    /// Solves the leg toward `t` with the hips' world rotation `hips`.
    pub fn solve(&mut self, hips: Quat, t: &LegTarget) -> LegPose {
        let forward = hips * Vec3::Z;
        // The knee's pole, in front of the hip-ankle line: a knee tracked behind it is
        // reflected forward (a knee does not bend backwards).
        let line = (t.ankle - t.hip).normalize_or(hips * self.thigh);
        let off = t.knee - t.hip;
        let side = off - line * line.dot(off);
        let back = side.dot(forward).min(0.0);
        let pole = t.knee - 2.0 * back * forward;
        let goal = ArmGoal {
            shoulder: t.hip,
            parent_rotation: hips,
            target: t.ankle,
            hand_rotation: None,
            pole: Some(pole),
            shoulder_root: None,
            finger: None,
        };
        let mut pose = ArmPose::default();
        self.ik.solve(&self.chain, &goal, &mut pose);
        // The hinge: the thigh turned so that its rest hinge axis is the bend plane's normal,
        // the shin turned about that axis only, by a flexion within [0, KNEE_FLEXION].
        let u = (pose.elbow - t.hip).normalize_or(hips * self.thigh);
        let v = (pose.wrist - pose.elbow).normalize_or(u);
        let h = u.cross(v) + 0.05 * (hips * Vec3::X);
        let h = (h - u * u.dot(h)).normalize_or(hips * self.hinge);
        let frame = |d: Vec3, x: Vec3| Quat::from_mat3(&Mat3::from_cols(x, d, x.cross(d)));
        let world = frame(u, h) * frame(self.thigh, self.hinge).conjugate();
        let upper = self.limit_hip((hips.conjugate() * world).normalize());
        let knee_angle = u.angle_between(v).clamp(0.0, KNEE_FLEXION);
        // The shin along the thigh's axis bent about the hinge (an avatar whose rest knee is
        // not straight is measured from straight).
        let shin = Quat::from_axis_angle(self.hinge, knee_angle) * self.thigh;
        let lower = swing(self.shin, shin, self.hinge);
        let foot = t.foot.map_or(Quat::IDENTITY, |d| {
            let shin = hips * upper * lower;
            limit_foot(shin.conjugate() * d)
        });
        LegPose {
            local: [upper, lower, foot],
            knee_angle,
        }
    }

    /// The hip's ranges on the thigh's local rotation `q` (in the hips' frame): its direction
    /// within flexion/extension and abduction/adduction, its twist within the rotations.
    fn limit_hip(&self, q: Quat) -> Quat {
        let d = q * self.thigh;
        let flex = d.z.atan2(-d.y);
        let abd = d.dot(self.outward).clamp(-1.0, 1.0).asin();
        let (f, a) = (
            flex.clamp(-HIP_EXTENSION, HIP_FLEXION),
            abd.clamp(-HIP_ADDUCTION, HIP_ABDUCTION),
        );
        let mut q = q;
        if f != flex || a != abd {
            let to = self.outward * a.sin() + a.cos() * Vec3::new(0.0, -f.cos(), f.sin());
            q = swing(d, to, self.hinge) * q;
        }
        // Swing-twist about the thigh's rest axis: q = swing * twist.
        let axis = Vec3::new(q.x, q.y, q.z).dot(self.thigh);
        let angle = 2.0 * axis.atan2(q.w);
        let angle = if angle > PI {
            angle - 2.0 * PI
        } else if angle < -PI {
            angle + 2.0 * PI
        } else {
            angle
        };
        let limited = angle.clamp(-HIP_ROTATION, HIP_ROTATION);
        if limited != angle {
            let twist = Quat::from_axis_angle(self.thigh, angle);
            q = q * twist.conjugate() * Quat::from_axis_angle(self.thigh, limited);
        }
        q.normalize()
    }
}

/// The foot's local rotation (in the shin's frame) turning its rest heel-to-toe direction
/// (+Z: the foot flat, the shin upright) onto `d` (in the shin's frame), pitch and turn
/// within the ankle's ranges.
fn limit_foot(d: Vec3) -> Quat {
    let Some(d) = d.try_normalize() else {
        return Quat::IDENTITY;
    };
    // Pitch: positive toes down (plantarflexion).
    let pitch = (-d.y)
        .atan2(d.x.hypot(d.z))
        .clamp(-ANKLE_DORSIFLEXION, ANKLE_PLANTARFLEXION);
    let turn = d.x.atan2(d.z).clamp(-FOOT_TURN, FOOT_TURN);
    let to = Vec3::new(
        pitch.cos() * turn.sin(),
        -pitch.sin(),
        pitch.cos() * turn.cos(),
    );
    swing(Vec3::Z, to, Vec3::X)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::humanoid::skeleton::VrmVersion;

    /// A T-pose body (VRM 1.0 frame), legs straight down.
    fn skeleton() -> Skeleton {
        let bones = crate::humanoid::skeleton::test_body();
        Skeleton::new(&bones, VrmVersion::V1).unwrap()
    }

    fn rest_leg() -> (Leg, Vec3) {
        let skeleton = skeleton();
        let hip = skeleton.rest_world(HumanBone::LeftUpperLeg).unwrap();
        (Leg::new(&skeleton, Side::Left).unwrap(), hip)
    }

    #[test]
    fn a_knee_tracked_behind_the_leg_still_bends_forward() {
        let (mut leg, hip) = rest_leg();
        let l = leg.length();
        // Ankle 70% of the leg below the hip; knee tracked behind (backwards) and in front.
        for knee_z in [-0.15, 0.15] {
            let t = LegTarget {
                hip,
                knee: hip + Vec3::new(0.0, -0.35 * l, knee_z * l),
                ankle: hip + Vec3::new(0.0, -0.7 * l, 0.0),
                foot: None,
            };
            let p = leg.solve(Quat::IDENTITY, &t);
            assert!(p.knee_angle > 0.5, "knee bent: {}", p.knee_angle);
            // The shin's rotation is about +X by a positive angle: the shin goes back.
            let shin = p.local[0] * p.local[1] * Vec3::NEG_Y;
            let thigh = p.local[0] * Vec3::NEG_Y;
            assert!(thigh.z > 0.1 && shin.z < thigh.z, "{thigh} {shin}");
            let (axis, angle) = p.local[1].to_axis_angle();
            assert!(axis.x * angle > 0.0);
        }
    }

    #[test]
    fn the_ankle_reaches_a_reachable_target_and_limits_hold() {
        let (mut leg, hip) = rest_leg();
        let l = leg.length();
        let ankle = hip + Vec3::new(0.05, -0.8 * l, 0.1);
        let t = LegTarget {
            hip,
            knee: hip + Vec3::new(0.03, -0.4 * l, 0.2),
            ankle,
            foot: Some(Vec3::new(0.0, 0.9, 1.0)),
        };
        let p = leg.solve(Quat::IDENTITY, &t);
        let skeleton = skeleton();
        let k = hip + p.local[0] * skeleton.rest_local(HumanBone::LeftLowerLeg);
        let a = k + p.local[0] * p.local[1] * skeleton.rest_local(HumanBone::LeftFoot);
        assert!((a - ankle).length() < 0.01, "{a} {ankle}");
        // Toes 42 degrees up, limited to the 40 degrees of dorsiflexion (shin nearly upright).
        let toe = p.local[0] * p.local[1] * p.local[2] * Vec3::Z;
        let shin = p.local[0] * p.local[1];
        let local = shin.conjugate() * toe;
        assert!(
            (local.y.asin() - ANKLE_DORSIFLEXION).abs() < 1e-3,
            "{local}"
        );
        // A thigh kicked 170 degrees forward stops at the hip's 120.
        let t = LegTarget {
            hip,
            knee: hip + Vec3::new(0.0, 0.3 * l, 0.3 * l),
            ankle: hip + Vec3::new(0.0, 0.9 * l, 0.1 * l),
            foot: None,
        };
        let p = leg.solve(Quat::IDENTITY, &t);
        let d = p.local[0] * leg.thigh;
        assert!(d.z.atan2(-d.y) <= HIP_FLEXION + 1e-3);
    }
}
