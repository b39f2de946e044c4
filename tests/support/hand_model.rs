//! A synthetic hand for known-answer tests of `handrig::hand`: avatars with configurable rest
//! hands, and a landmark hand posed by anatomical joint angles.
//!
//! The joint-angle conventions are the ones documented in `src/hand/mod.rs`, written here
//! independently (cumulative elevations in a vertical plane for fingers, rotations about the
//! index metacarpal line for the thumb) so the tests check the solver against the
//! definitions, not against its own code.

use super::rigs;

use glam::{Quat, Vec3};
use handrig::{Finger, HumanBone, Side, Skeleton, VrmVersion};

/// Anatomical angles of one hand, radians, `[finger][dof]` in `Finger::ALL` order:
/// fingers `[MCP flexion, MCP abduction, PIP, DIP]`, thumb `[CMC abduction, CMC opposition,
/// MCP, IP]`.
pub type Angles = [[f32; 4]; 5];

/// Rest layout of one hand in the avatar's left-hand coordinates (fingers along +X, palm down,
/// thumb toward +Z), relative to the hand joint; the right hand is its mirror image.
#[derive(Clone, Debug)]
pub struct HandLayout {
    /// `[finger][slot]` joint offsets from the hand joint: thumb metacarpal/proximal/distal,
    /// other fingers proximal/intermediate/distal.
    pub joints: [[Vec3; 3]; 5],
}

impl HandLayout {
    /// A typical VRM 1.0 T-pose hand: straight fingers along +X, thumb in the palm plane at 45
    /// degrees, about 19 cm wrist to middle fingertip.
    pub fn standard() -> Self {
        let finger = |z: f32, start: f32, lens: [f32; 2]| {
            let p = Vec3::new(start, 0.0, z);
            [p, p + Vec3::X * lens[0], p + Vec3::X * (lens[0] + lens[1])]
        };
        let t = Vec3::new(1.0, 0.0, 1.0).normalize();
        let t0 = Vec3::new(0.025, -0.005, 0.02);
        HandLayout {
            joints: [
                [t0, t0 + t * 0.045, t0 + t * 0.08],
                finger(0.025, 0.09, [0.045, 0.027]),
                finger(0.0, 0.095, [0.05, 0.03]),
                finger(-0.02, 0.09, [0.047, 0.029]),
                finger(-0.038, 0.08, [0.036, 0.022]),
            ],
        }
    }

    /// The whole hand turned by `q` about the hand joint (rest fingers not along an axis).
    pub fn rotated(mut self, q: Quat) -> Self {
        for f in &mut self.joints {
            for j in f.iter_mut() {
                *j = q * *j;
            }
        }
        self
    }

    /// Rest fingers curled by `curl` radians at each finger joint and spread: each finger's
    /// distal joints turned about its proximal joint (Blender-style relaxed rest hands).
    pub fn relaxed(mut self, curl: f32, spread: [f32; 4]) -> Self {
        for (i, f) in self.joints.iter_mut().enumerate().skip(1) {
            let base = f[0];
            let turn = Quat::from_rotation_y(spread[i - 1]);
            // Curling about +Z bends +X toward -Y (palmar on this palm-down hand).
            let mut rel = [f[1] - f[0], f[2] - f[1]];
            rel[0] = Quat::from_rotation_z(-curl) * (turn * rel[0]);
            rel[1] = Quat::from_rotation_z(-2.0 * curl) * (turn * rel[1]);
            f[1] = base + rel[0];
            f[2] = f[1] + rel[1];
        }
        self
    }

    /// The thumb resting bent by `angle` at MCP and IP, in a plane turned `tilt` about the
    /// metacarpal away from the palm-normal plane (riggers often model thumbs bent).
    pub fn bent_thumb(mut self, angle: f32, tilt: f32) -> Self {
        let [t0, t1, t2] = self.joints[0];
        let d = (t1 - t0).normalize();
        let axis = Quat::from_axis_angle(d, tilt) * d.cross(Vec3::NEG_Y).normalize();
        let r1 = Quat::from_axis_angle(axis, angle) * (t2 - t1);
        self.joints[0][2] = t1 + r1;
        self
    }

    /// A VRM 0.x style thumb pointing forward and down out of the palm plane.
    pub fn drooping_thumb(mut self) -> Self {
        let t = Vec3::new(0.6, -0.55, 0.6).normalize();
        let t0 = self.joints[0][0];
        self.joints[0] = [t0, t0 + t * 0.045, t0 + t * 0.08];
        self
    }
}

/// A humanoid avatar (VRM 1.0 frame) with `layout` on both hands, minus `missing` bones.
pub fn avatar(layout: &HandLayout, missing: &[HumanBone]) -> Skeleton {
    let torso = [
        (HumanBone::Hips, 0.95),
        (HumanBone::Spine, 1.05),
        (HumanBone::Chest, 1.2),
        (HumanBone::UpperChest, 1.3),
        (HumanBone::Neck, 1.45),
        (HumanBone::Head, 1.55),
    ];
    let legs = rigs::Legs {
        x: 0.1,
        heights: [0.9, 0.5, 0.08],
    };
    let side = Side::Left;
    let hand = Vec3::new(0.6, 1.4, 0.0);
    let arm = side.arm();
    let mut left = vec![
        (arm[0], Vec3::new(0.05, 1.38, 0.0)),
        (arm[1], Vec3::new(0.15, 1.4, 0.0)),
        (arm[2], Vec3::new(0.38, 1.4, 0.0)),
        (arm[3], hand),
    ];
    for finger in Finger::ALL {
        for (slot, bone) in side.finger(finger).into_iter().enumerate() {
            left.push((bone, hand + layout.joints[finger.index()][slot]));
        }
    }
    let mut bones = rigs::t_pose(&torso, legs, &left);
    bones.retain(|(b, _)| !missing.contains(b));
    rigs::skeleton(&bones, VrmVersion::V1)
}

/// A landmark hand built on an avatar's rest hand (all finger bones required), posed by
/// anatomical angles.
#[derive(Clone, Debug)]
pub struct HandModel {
    pub side: Side,
    /// Wrist.
    pub wrist: Vec3,
    /// Rest positions of each finger's `[base, joint1, joint2, tip]` (MediaPipe order).
    pub rest: [[Vec3; 4]; 5],
    /// Segment lengths `[finger][segment]`.
    pub lengths: [[f32; 3]; 5],
}

impl HandModel {
    /// The rest hand of `side` of `skeleton`; tips continue the distal bones by 0.8 of the
    /// previous segment.
    pub fn from_skeleton(skeleton: &Skeleton, side: Side) -> Self {
        let wrist = skeleton.rest_world(side.hand()).expect("hand");
        let mut rest = [[Vec3::ZERO; 4]; 5];
        let mut lengths = [[0.0; 3]; 5];
        for finger in Finger::ALL {
            let j: Vec<Vec3> = side
                .finger(finger)
                .iter()
                .map(|b| {
                    skeleton
                        .rest_world(*b)
                        .expect("model needs every finger bone")
                })
                .collect();
            let tip = j[2] + (j[2] - j[1]) * 0.8;
            let r = [j[0], j[1], j[2], tip];
            rest[finger.index()] = r;
            for k in 0..3 {
                lengths[finger.index()][k] = (r[k + 1] - r[k]).length();
            }
        }
        HandModel {
            side,
            wrist,
            rest,
            lengths,
        }
    }

    /// Palm axes `(forward, radial, palmar)` of the rest hand.
    pub fn palm(&self) -> (Vec3, Vec3, Vec3) {
        let idx = |f: Finger| self.rest[f.index()][0];
        let f = (idx(Finger::Middle) - self.wrist).normalize();
        let a = idx(Finger::Index) - idx(Finger::Little);
        let r = (a - a.dot(f) * f).normalize();
        let n = match self.side {
            Side::Right => r.cross(f),
            Side::Left => f.cross(r),
        };
        (f, r, n)
    }

    /// The base joint's pole for `finger`: palmar normal (ring and little: of their own
    /// wrist-neighbour-MCP triangle), thumb: the index metacarpal line.
    pub fn pole(&self, finger: Finger) -> Vec3 {
        let (_, _, n) = self.palm();
        let mcp = |f: Finger| self.rest[f.index()][0] - self.wrist;
        let local = |a: Vec3, b: Vec3| {
            let c = a.cross(b).normalize();
            if c.dot(n) < 0.0 {
                -c
            } else {
                c
            }
        };
        match finger {
            Finger::Thumb => mcp(Finger::Index).normalize(),
            Finger::Ring => local(mcp(Finger::Middle), mcp(Finger::Ring)),
            Finger::Little => local(mcp(Finger::Ring), mcp(Finger::Little)),
            _ => n,
        }
    }

    /// Unit segment directions of `finger` posed by `a` (its four angles).
    pub fn segments(&self, finger: Finger, a: [f32; 4]) -> [Vec3; 3] {
        let (f, r, n) = self.palm();
        let z = self.pole(finger);
        if finger == Finger::Thumb {
            let x = (r - r.dot(z) * z).normalize();
            let y = (n - n.dot(z) * z - n.dot(x) * x).normalize();
            let [gamma, omega, mcp, ip] = a;
            let d = gamma.sin() * (omega.cos() * x + omega.sin() * y) + gamma.cos() * z;
            let east = -omega.sin() * x + omega.cos() * y;
            let axis = d.cross(east).normalize();
            [
                d,
                Quat::from_axis_angle(axis, mcp) * d,
                Quat::from_axis_angle(axis, mcp + ip) * d,
            ]
        } else {
            let x = (f - f.dot(z) * z).normalize();
            let y = (r - r.dot(z) * z - r.dot(x) * x).normalize();
            let m = self.rest[finger.index()][0] - self.wrist;
            let lon0 = m.dot(y).atan2(m.dot(x));
            let [flex, abd, pip, dip] = a;
            let lon = lon0 + abd;
            let g = lon.cos() * x + lon.sin() * y;
            let el = [flex, flex + pip, flex + pip + dip];
            el.map(|e| e.cos() * g + e.sin() * z)
        }
    }

    /// The hinge axis of `finger` posed by `a` (up to sign).
    pub fn hinge_axis(&self, finger: Finger, a: [f32; 4]) -> Vec3 {
        let s = self.segments(finger, [a[0], a[1], 0.5, 0.0]);
        s[0].cross(s[1]).normalize()
    }

    /// The 21 landmarks of the posed hand in the rest hand's frame, each segment's length
    /// scaled by `stretch[finger][segment]`.
    pub fn landmarks(&self, angles: &Angles, stretch: &[[f32; 3]; 5]) -> [Vec3; 21] {
        let mut out = [Vec3::ZERO; 21];
        out[0] = self.wrist;
        for finger in Finger::ALL {
            let i = finger.index();
            let ids = finger.landmarks();
            let seg = self.segments(finger, angles[i]);
            let mut p = self.rest[i][0];
            out[ids[0]] = p;
            for k in 0..3 {
                p += seg[k] * self.lengths[i][k] * stretch[i][k];
                out[ids[k + 1]] = p;
            }
        }
        out
    }
}

/// `points` moved rigidly (turned by `q` about the first point, scaled by `s` about it,
/// then translated by `t`).
pub fn place(points: &[Vec3; 21], q: Quat, s: f32, t: Vec3) -> [Vec3; 21] {
    let o = points[0];
    points.map(|p| o + t + q * ((p - o) * s))
}

/// All-ones stretch.
pub const NO_STRETCH: [[f32; 3]; 5] = [[1.0; 3]; 5];

/// Degrees to radians for an angle table.
pub fn deg(a: [[f32; 4]; 5]) -> Angles {
    a.map(|f| f.map(f32::to_radians))
}

/// Hand-picked poses inside the limits (degrees): flat, fist, pinch, spread, hook.
pub fn poses() -> Vec<(&'static str, Angles)> {
    vec![
        (
            "flat",
            deg([
                [30.0, 0.0, 0.0, 0.0],
                [0.0; 4],
                [0.0; 4],
                [0.0; 4],
                [0.0; 4],
            ]),
        ),
        (
            "fist",
            deg([
                [25.0, 110.0, 45.0, 30.0],
                [80.0, -5.0, 95.0, 60.0],
                [84.0, 0.0, 100.0, 65.0],
                [87.0, 3.0, 100.0, 60.0],
                [95.0, 8.0, 95.0, 55.0],
            ]),
        ),
        (
            "pinch",
            deg([
                [35.0, 80.0, 20.0, 15.0],
                [40.0, -8.0, 50.0, 20.0],
                [20.0, 0.0, 30.0, 10.0],
                [15.0, 2.0, 20.0, 10.0],
                [10.0, 5.0, 15.0, 5.0],
            ]),
        ),
        (
            "spread",
            deg([
                [60.0, 5.0, -10.0, -20.0],
                [-20.0, 25.0, -5.0, -15.0],
                [-15.0, 10.0, 0.0, -10.0],
                [-10.0, -15.0, 0.0, -5.0],
                [-30.0, -25.0, 5.0, 0.0],
            ]),
        ),
        (
            "hook",
            deg([
                [15.0, -20.0, -10.0, 60.0],
                [0.0, 0.0, 100.0, 80.0],
                [-5.0, 5.0, 105.0, 85.0],
                [10.0, -5.0, 90.0, 70.0],
                [20.0, 0.0, 80.0, 60.0],
            ]),
        ),
    ]
}

/// The pose of [`poses`] called `name`.
pub fn pose(name: &str) -> Angles {
    poses()
        .into_iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no pose {name}"))
        .1
}
