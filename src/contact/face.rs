//! Face frames and the anchor warp: where on the user's face a finger is, and where that
//! place is on the avatar's face.
//!
//! A face frame is an origin (between the eyes, on the face's surface), a rotation (its axes
//! are the face's left, up and forward: +X, +Y, +Z of the avatar frame when the head is at
//! rest) and a size, the **head breadth** (ear to ear). Points in a face frame are given in
//! head breadths ("local" coordinates), so a finger two centimeters in front of a small
//! face and one in front of a big face have about the same local coordinates.
//!
//! The user's frame comes from tracking ([`UserFace::from_pose`] for MediaPipe pose face
//! landmarks, [`UserFace::from_tracker`] for a body tracker's head joints); the avatar's
//! from its rig ([`AvatarFace::from_rig`]). Each has the eight [`FaceAnchor`]s in local
//! coordinates. [`warp`] carries a local point from the user's face to the avatar's:
//! each anchor's displacement (avatar anchor minus user anchor) is interpolated by inverse
//! distance weighting (Shepard, power 2), so a point on a user anchor lands exactly on the
//! matching avatar anchor, and points between anchors move with their neighbours.
//!
//! ## The canonical face
//! Where nothing better is known, anchors come from one average adult face,
//! [`CANONICAL_ANCHORS`], in head breadths relative to the point between the eyes
//! ([`HEAD_BREADTH`] = 0.145 m, bitragion breadth). Rounded adult averages from
//! craniofacial anthropometry (Farkas, *Anthropometry of the Head and Face*, 1994): eyes
//! 63 mm apart; nose tip 45 mm below the eyes and 25 mm in front of them; mouth 70 mm below,
//! 12 mm in front; chin (its front) 105 mm below, level with the eyes' surface; cheeks 48 mm
//! to the side, 40 mm below, 10 mm behind; ears (tragion) at the head's breadth, 20 mm
//! below and 85 mm behind; forehead 45 mm above, 5 mm in front.

use glam::{Mat3, Quat, Vec3};

use crate::humanoid::bones::{HumanBone, Side};
use crate::humanoid::skeleton::{Skeleton, VrmVersion};
use crate::input::mediapipe::{pose_landmark as pl, CameraMapping, PoseObservation, TrackerFace};
use crate::math::clamp;
use crate::names::named_enum;

/// Number of face anchors.
pub const ANCHORS: usize = FaceAnchor::COUNT;

named_enum! {
    /// The named places of a face that contact maps between user and avatar (JS:
    /// `contact.faceAnchors` keys, `result.alignment.<side>.contact.anchor`). Left and right are
    /// the avatar's (VRM 1.0: its left is +X).
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
    pub enum FaceAnchor {
        /// `"nose"`: the tip of the nose.
        Nose = "nose",
        /// `"chin"`: the front of the chin.
        Chin = "chin",
        /// `"mouth"`: the middle of the lips.
        Mouth = "mouth",
        /// `"leftCheek"`.
        LeftCheek = "leftCheek",
        /// `"rightCheek"`.
        RightCheek = "rightCheek",
        /// `"leftEar"`: the ear opening (tragion).
        LeftEar = "leftEar",
        /// `"rightEar"`.
        RightEar = "rightEar",
        /// `"forehead"`: its middle, above the eyebrows.
        Forehead = "forehead",
    }
}

/// Head breadth (ear to ear, bitragion) of the canonical face, meters: the unit of local
/// face coordinates for it.
pub const HEAD_BREADTH: f32 = 0.145;

const fn canon(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x / HEAD_BREADTH, y / HEAD_BREADTH, z / HEAD_BREADTH)
}

/// The canonical adult face's anchors (see the module docs), local coordinates: head
/// breadths from the point between the eyes, +X the face's left, +Y up, +Z forward.
pub const CANONICAL_ANCHORS: [Vec3; ANCHORS] = [
    canon(0.0, -0.045, 0.025),
    canon(0.0, -0.105, 0.0),
    canon(0.0, -0.070, 0.012),
    canon(0.048, -0.040, -0.010),
    canon(-0.048, -0.040, -0.010),
    canon(0.0725, -0.020, -0.085),
    canon(-0.0725, -0.020, -0.085),
    canon(0.0, 0.045, 0.005),
];

/// The canonical eyes (centers of the eyes' visible surface), `[left, right]`, local.
pub const CANONICAL_EYES: [Vec3; 2] = [canon(0.0315, 0.0, 0.0), canon(-0.0315, 0.0, 0.0)];

/// Eyeball radius over head breadth: an eye bone sits at the eyeball's center, this far
/// behind the eye's surface (12 mm on the canonical face).
pub const EYEBALL: f32 = 0.012 / HEAD_BREADTH;

/// Head breadth over arm length (upper + lower arm, 0.54 m on an average adult), for avatars
/// whose head size nothing else tells.
pub const HEAD_PER_ARM: f32 = HEAD_BREADTH / 0.54;

/// The point between the eyes (on the eyes' surface) relative to the head bone at rest, head
/// breadths: 65 mm above and 92 mm in front of the head joint (top of the neck), as on the
/// human-proportioned fixture (eye bones 80 mm in front, plus an eyeball radius); used for
/// avatars with neither eye bones nor a look-at offset.
pub const EYES_FROM_HEAD: Vec3 = canon(0.0, 0.065, 0.092);

/// A face's frame: origin between the eyes on the face's surface, rotation (face left, up,
/// forward as +X, +Y, +Z) and size (head breadth, meters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceFrame {
    /// The point between the eyes, world.
    pub origin: Vec3,
    /// World rotation of the face's axes.
    pub rotation: Quat,
    /// Head breadth, meters.
    pub size: f32,
}

impl FaceFrame {
    /// A world point in local coordinates (head breadths, face axes).
    #[inline]
    #[must_use]
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.rotation.inverse() * (p - self.origin) / self.size
    }

    /// A local point in world coordinates.
    #[inline]
    #[must_use]
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.origin + self.rotation * (local * self.size)
    }
}

/// Face points in one space, sides by the avatar's sides (`[left, right]`): what a user face
/// is built from.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FacePoints {
    /// Tip of the nose.
    pub nose: Option<Vec3>,
    /// Eye centers.
    pub eyes: [Option<Vec3>; 2],
    /// Ears.
    pub ears: [Option<Vec3>; 2],
    /// Middle of the mouth.
    pub mouth: Option<Vec3>,
}

/// The user's face: frame and anchors (local coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UserFace {
    /// The face frame, in the space its points were given in.
    pub frame: FaceFrame,
    /// The anchors, local: measured where tracking sees the place (nose, mouth, ears), the
    /// canonical face's elsewhere.
    pub anchors: [Vec3; ANCHORS],
}

/// Smallest head breadth taken as a face (meters, or the tracker's unit): below it the
/// points are collapsed.
const MIN_SIZE: f32 = 1e-3;

impl UserFace {
    /// Builds the face frame from tracked points: a similarity fit of the canonical face
    /// ([`CANONICAL_EYES`], nose, mouth and ears of [`CANONICAL_ANCHORS`]) to the given
    /// points.
    ///
    /// * Lateral axis and size: from the ears and the eyes (each pair's left-minus-right
    ///   vector over its canonical length; both pairs summed when both are given).
    /// * The turn about that axis (nodding): the least-squares angle (2D Procrustes) between
    ///   the given points and their canonical places, both about their centroids, in the
    ///   plane across the lateral axis. Every point counts, so one point off the average face
    ///   (a long nose, a receding mouth) tilts the frame little.
    /// * Origin: the least-squares translation (mean of `p - R * size * canonical(p)`).
    /// * Anchors: nose, mouth and ears where given (measured), the canonical face's elsewhere.
    ///
    /// `None` without a lateral pair (both eyes or both ears) and a third point off the
    /// lateral line, or for collapsed points.
    #[must_use]
    pub fn from_points(p: &FacePoints) -> Option<UserFace> {
        let canon_ears = [
            CANONICAL_ANCHORS[FaceAnchor::LeftEar.index()],
            CANONICAL_ANCHORS[FaceAnchor::RightEar.index()],
        ];
        // (measured, canonical) pairs of every given point.
        let given = [
            (p.eyes[0], CANONICAL_EYES[0]),
            (p.eyes[1], CANONICAL_EYES[1]),
            (p.ears[0], canon_ears[0]),
            (p.ears[1], canon_ears[1]),
            (p.nose, CANONICAL_ANCHORS[FaceAnchor::Nose.index()]),
            (p.mouth, CANONICAL_ANCHORS[FaceAnchor::Mouth.index()]),
        ];
        let mut lateral = Vec3::ZERO;
        let mut lengths = 0.0;
        for pair in [[0, 1], [2, 3]] {
            if let (Some(l), Some(r)) = (given[pair[0]].0, given[pair[1]].0) {
                lateral += l - r;
                lengths += (given[pair[0]].1 - given[pair[1]].1).length();
            }
        }
        if lengths == 0.0 {
            return None;
        }
        let size = lateral.length() / lengths;
        if !(size.is_finite() && size > MIN_SIZE) {
            return None;
        }
        let x = lateral / lateral.length();
        let (mut mean, mut canon_mean, mut n) = (Vec3::ZERO, Vec3::ZERO, 0.0);
        for (m, c) in given {
            if let Some(m) = m {
                mean += m;
                canon_mean += c;
                n += 1.0;
            }
        }
        mean /= n;
        canon_mean /= n;
        // Any unit u across x, v = x cross u; Y = cos(t) u + sin(t) v, Z = x cross Y; the
        // angle t maximizing sum m . (c.y Y + c.z Z) is atan2(b, a).
        let u = x.any_orthonormal_vector();
        let v = x.cross(u);
        let (mut a, mut b) = (0.0f32, 0.0f32);
        for (m, c) in given {
            let Some(m) = m else { continue };
            let (m, c) = (m - mean, c - canon_mean);
            let (mu, mv) = (m.dot(u), m.dot(v));
            a += c.y * mu + c.z * mv;
            b += c.y * mv - c.z * mu;
        }
        if a.hypot(b).is_nan() || a.hypot(b) <= 1e-12 {
            return None;
        }
        let t = b.atan2(a);
        let y = t.cos() * u + t.sin() * v;
        let z = x.cross(y);
        let rotation = Quat::from_mat3(&Mat3::from_cols(x, y, z)).normalize();
        let frame = FaceFrame {
            origin: mean - rotation * (canon_mean * size),
            rotation,
            size,
        };
        let mut anchors = CANONICAL_ANCHORS;
        let mut measured = |a: FaceAnchor, point: Option<Vec3>| {
            if let Some(point) = point {
                anchors[a.index()] = frame.to_local(point);
            }
        };
        measured(FaceAnchor::Nose, p.nose);
        measured(FaceAnchor::Mouth, p.mouth);
        measured(FaceAnchor::LeftEar, p.ears[0]);
        measured(FaceAnchor::RightEar, p.ears[1]);
        let ok = frame.origin.is_finite() && anchors.iter().all(|a| a.is_finite());
        ok.then_some(UserFace { frame, anchors })
    }

    /// The user's face from MediaPipe pose world landmarks (user space: the landmarks in the
    /// avatar's axes, meters, origin between the hips; see [`CameraMapping::to_avatar`]).
    /// Sides follow the camera mapping like the arms do (with `mirror` the user's left eye is
    /// the avatar's right). Landmarks below `min_visibility` are not used; mouth from the
    /// midpoint of both corners.
    #[must_use]
    pub fn from_pose(
        pose: &PoseObservation,
        camera: CameraMapping,
        min_visibility: f32,
    ) -> Option<UserFace> {
        let at = |k: usize| {
            (pose.visibility[k] >= min_visibility).then(|| camera.to_avatar(pose.world[k]))
        };
        let pair = |left: usize, right: usize| {
            Side::BOTH.map(|side| match camera.pose_side_for(side) {
                Side::Left => at(left),
                Side::Right => at(right),
            })
        };
        let mouth = at(pl::MOUTH_LEFT)
            .zip(at(pl::MOUTH_RIGHT))
            .map(|(a, b)| 0.5 * (a + b));
        UserFace::from_points(&FacePoints {
            nose: at(pl::NOSE),
            eyes: pair(pl::LEFT_EYE, pl::RIGHT_EYE),
            ears: pair(pl::LEFT_EAR, pl::RIGHT_EAR),
            mouth,
        })
    }

    /// The user's face from a body tracker's face points (`frame.face`, the model's own
    /// frame), in the internal frame.
    #[must_use]
    pub fn from_tracker(face: &TrackerFace, version: VrmVersion) -> Option<UserFace> {
        let c = |p: Option<Vec3>| p.map(|p| version.position_to_internal(p));
        UserFace::from_points(&FacePoints {
            nose: c(face.nose),
            eyes: face.eyes.map(c),
            ears: face.ears.map(c),
            mouth: c(face.mouth),
        })
    }
}

/// The image-to-space map of a MediaPipe pose's face: MediaPipe's world landmarks (camera
/// axes, meters) against its image landmarks (normalized: x of the width, y of the height),
/// fitted per axis over the visible face points (nose, eyes, ears, mouth corners):
/// `world.x = ax image.x + bx`, `world.y = ay image.y + by`. Under weak perspective it carries
/// an image point at the face's depth into the pose's space (the per-axis scales absorb the
/// image's aspect).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageFit {
    /// Scale and offset of x.
    pub ax: f32,
    /// Offset of x.
    pub bx: f32,
    /// Scale of y.
    pub ay: f32,
    /// Offset of y.
    pub by: f32,
}

impl ImageFit {
    /// Fits the map to the pose's visible face points; `None` with fewer than three or
    /// without spread on an axis.
    #[must_use]
    pub fn from_pose(
        pose: &PoseObservation,
        image: &[Vec3; crate::input::mediapipe::POSE_LANDMARKS],
        min_visibility: f32,
    ) -> Option<ImageFit> {
        let face = [
            pl::NOSE,
            pl::LEFT_EYE,
            pl::RIGHT_EYE,
            pl::LEFT_EAR,
            pl::RIGHT_EAR,
            pl::MOUTH_LEFT,
            pl::MOUTH_RIGHT,
        ];
        let (mut n, mut mw, mut mi) = (0.0f32, Vec3::ZERO, Vec3::ZERO);
        for k in face {
            if pose.visibility[k] >= min_visibility {
                n += 1.0;
                mw += pose.world[k];
                mi += image[k];
            }
        }
        if n < 3.0 {
            return None;
        }
        mw /= n;
        mi /= n;
        let (mut cx, mut vx, mut cy, mut vy) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        for k in face {
            if pose.visibility[k] >= min_visibility {
                let (w, i) = (pose.world[k] - mw, image[k] - mi);
                cx += w.x * i.x;
                vx += i.x * i.x;
                cy += w.y * i.y;
                vy += i.y * i.y;
            }
        }
        if vx.is_nan() || vy.is_nan() || vx < 1e-8 || vy < 1e-8 {
            return None;
        }
        let (ax, ay) = (cx / vx, cy / vy);
        let fit = ImageFit {
            ax,
            bx: mw.x - ax * mi.x,
            ay,
            by: mw.y - ay * mi.y,
        };
        [fit.ax, fit.bx, fit.ay, fit.by]
            .iter()
            .all(|v| v.is_finite())
            .then_some(fit)
    }

    /// The camera-axes x and y of an image point at the face's depth.
    #[inline]
    #[must_use]
    pub fn apply(&self, image: Vec3) -> (f32, f32) {
        (self.ax * image.x + self.bx, self.ay * image.y + self.by)
    }
}

/// The user's fingertip as face contact measures it with MediaPipe pose input, in the pose's
/// space (avatar axes): across the camera, from the image when `image_tip` and `fit` are
/// given (where the image shows the finger on the face), else as tracked; along the camera,
/// the depth of the face anchor nearest across the camera plus `depth_trust` times the
/// tracked depth difference (monocular depth of a hand at the face is off by 15 to 35 cm on
/// the sign-language clips: the image is right about where on the face, the depth is not).
/// With `depth_trust` 1 and no image this is `tip`.
#[must_use]
pub fn pose_tip(
    face: &UserFace,
    tip: Vec3,
    image_tip: Option<Vec3>,
    fit: Option<&ImageFit>,
    camera: CameraMapping,
    depth_trust: f32,
) -> Vec3 {
    let anchors = camera_anchors(face, camera);
    pose_tip_at(&anchors, tip, image_tip, fit, camera, depth_trust)
}

/// The face's anchors in camera axes, as [`pose_tip_at`] takes them: once a frame for every
/// part of a hand.
#[must_use]
pub fn camera_anchors(face: &UserFace, camera: CameraMapping) -> [Vec3; ANCHORS] {
    face.anchors
        .map(|a| camera.to_avatar(face.frame.to_world(a)))
}

/// [`pose_tip`] with the face's anchors already in camera axes ([`camera_anchors`]).
#[must_use]
pub fn pose_tip_at(
    anchors: &[Vec3; ANCHORS],
    tip: Vec3,
    image_tip: Option<Vec3>,
    fit: Option<&ImageFit>,
    camera: CameraMapping,
    depth_trust: f32,
) -> Vec3 {
    // `to_avatar` is its own inverse: camera axes and back.
    let c = camera.to_avatar(tip);
    let (x, y) = match (image_tip, fit) {
        (Some(i), Some(f)) => f.apply(i),
        _ => (c.x, c.y),
    };
    let mut nearest = (f32::INFINITY, c.z);
    for w in anchors {
        let d2 = (w.x - x) * (w.x - x) + (w.y - y) * (w.y - y);
        if d2 < nearest.0 {
            nearest = (d2, w.z);
        }
    }
    let z = nearest.1 + depth_trust * (c.z - nearest.1);
    let p = camera.to_avatar(Vec3::new(x, y, z));
    if p.is_finite() {
        p
    } else {
        tip
    }
}

/// The avatar's face, in the head bone's frame: fixed at construction, placed every frame by
/// the head bone's world position and rotation (forward kinematics), so it follows the head
/// when the head moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AvatarFace {
    /// The point between the eyes relative to the head bone (head rest axes = the model's
    /// axes in the internal frame), meters.
    pub origin: Vec3,
    /// Head breadth, meters.
    pub size: f32,
    /// The anchors relative to the head bone (head rest axes), meters.
    pub anchors: [Vec3; ANCHORS],
    /// Which anchors the app gave (`contact.faceAnchors`); the others are derived.
    pub given: [bool; ANCHORS],
}

impl AvatarFace {
    /// The avatar's face from its rig, with the app's anchors where given (`given[i]`:
    /// relative to the head bone, the internal frame's axes). Documented defaults:
    ///
    /// * Breadth (ear to ear): with both eye bones, eye distance / (63 mm / 145 mm);
    ///   otherwise the body estimate, arm length (upper + lower) x [`HEAD_PER_ARM`]; kept
    ///   within 0.5 to 5 times the body estimate.
    /// * Height scale: the eyes' height above the head bone over the canonical 65 mm (per
    ///   145 mm of breadth), kept within 0.5 to 2 times the breadth; the breadth when the
    ///   eyes' height is unknown. Stylized heads are often wider than they are tall between
    ///   the eyes and the chin: the canonical face is stretched by the breadth across and by
    ///   the height scale up, down and in depth.
    /// * Origin (between the eyes, on the face's surface): the eye bones' midpoint moved
    ///   forward by an eyeball radius ([`EYEBALL`] x height scale); else the look-at point
    ///   (`VRMC_vrm.lookAt.offsetFromHeadBone`, VRM 0.x `firstPersonBoneOffset`; offsets
    ///   under 1 mm are taken as unset), moved forward to [`EYES_FROM_HEAD`]'s depth when it
    ///   lies less than a third of that in front of the head bone (look-at points usually
    ///   sit on the head's center line); else [`EYES_FROM_HEAD`].
    /// * Anchors: the canonical face ([`CANONICAL_ANCHORS`]) placed on that origin, so
    ///   stretched; the frame's size is the geometric mean of breadth and height scale.
    #[must_use]
    pub fn from_rig(skeleton: &Skeleton, given: &[Option<Vec3>; ANCHORS]) -> AvatarFace {
        let head = skeleton.rest_world(HumanBone::Head).unwrap_or(Vec3::ZERO);
        let arm = crate::humanoid::measure::avatar_arm_length(skeleton);
        let body = if arm.is_finite() && arm > 1e-4 {
            arm * HEAD_PER_ARM
        } else {
            HEAD_BREADTH
        };
        let eyes = skeleton
            .rest_world(HumanBone::LeftEye)
            .zip(skeleton.rest_world(HumanBone::RightEye))
            .filter(|(l, r)| (*l - *r).length() > 1e-4);
        let look_at = skeleton.look_at_offset().filter(|o| o.length() > 1e-3);
        let canon_eye_breadth = (CANONICAL_EYES[0] - CANONICAL_EYES[1]).length();
        let breadth = clamp(
            eyes.map_or(body, |(l, r)| (l - r).length() / canon_eye_breadth),
            0.5 * body,
            5.0 * body,
        );
        // The eyes' center relative to the head bone, if known.
        let eye_center = eyes.map(|(l, r)| 0.5 * (l + r) - head).or(look_at);
        let height = clamp(
            eye_center.map_or(breadth, |e| e.y / EYES_FROM_HEAD.y),
            0.5 * breadth,
            2.0 * breadth,
        );
        let origin = match (eyes, look_at) {
            (Some((l, r)), _) => 0.5 * (l + r) - head + Vec3::Z * (EYEBALL * height),
            (None, Some(o)) => {
                let depth = EYES_FROM_HEAD.z * height;
                if o.z < depth / 3.0 {
                    Vec3::new(o.x, o.y, depth)
                } else {
                    o
                }
            }
            (None, None) => Vec3::new(0.0, EYES_FROM_HEAD.y * height, EYES_FROM_HEAD.z * height),
        };
        let stretch = Vec3::new(breadth, height, height);
        let mut anchors = [Vec3::ZERO; ANCHORS];
        let mut flags = [false; ANCHORS];
        for (i, a) in anchors.iter_mut().enumerate() {
            *a = match given[i] {
                Some(p) => {
                    flags[i] = true;
                    p
                }
                None => origin + CANONICAL_ANCHORS[i] * stretch,
            };
        }
        AvatarFace {
            origin,
            size: (breadth * height).sqrt(),
            anchors,
            given: flags,
        }
    }

    /// The face frame with the head bone at `head_position` and world rotation `head_rotation`.
    #[inline]
    #[must_use]
    pub fn frame(&self, head_position: Vec3, head_rotation: Quat) -> FaceFrame {
        FaceFrame {
            origin: head_position + head_rotation * self.origin,
            rotation: head_rotation,
            size: self.size,
        }
    }

    /// Anchor `a` in the world with the head bone posed so.
    #[inline]
    #[must_use]
    pub fn anchor_world(&self, a: FaceAnchor, head_position: Vec3, head_rotation: Quat) -> Vec3 {
        head_position + head_rotation * self.anchors[a.index()]
    }

    /// The anchors in local face coordinates (head breadths from the origin).
    #[must_use]
    pub fn local_anchors(&self) -> [Vec3; ANCHORS] {
        self.anchors.map(|a| (a - self.origin) / self.size)
    }
}

/// The anchor nearest `local` and its distance (local units, head breadths).
#[must_use]
pub fn nearest(local: Vec3, anchors: &[Vec3; ANCHORS]) -> (FaceAnchor, f32) {
    let mut best = (FaceAnchor::Nose, f32::INFINITY);
    for a in FaceAnchor::ALL {
        let d = (local - anchors[a.index()]).length();
        if d < best.1 {
            best = (a, d);
        }
    }
    best
}

/// Carries a local point from the user's face (`user` anchors) onto the avatar's (`avatar`
/// anchors): `local + sum_i w_i (avatar_i - user_i)` with inverse-distance weights
/// `w_i = d_i^-2 / sum_j d_j^-2` (Shepard). On a user anchor the result is exactly the
/// avatar anchor; near one it moves like the point does (the weights' gradient vanishes at
/// the anchors). Allocates nothing.
#[must_use]
pub fn warp(local: Vec3, user: &[Vec3; ANCHORS], avatar: &[Vec3; ANCHORS]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let mut total = 0.0;
    for i in 0..ANCHORS {
        let d2 = (local - user[i]).length_squared();
        if d2 < 1e-12 {
            return local + (avatar[i] - user[i]);
        }
        let w = 1.0 / d2;
        sum += w * (avatar[i] - user[i]);
        total += w;
    }
    local + sum / total
}

/// The contact blend for a distance `d` to the nearest anchor (head breadths) and a radius
/// `radius`: 1 up to half the radius, 0 from the radius on, a smoothstep between (slope at
/// most 3 / radius).
#[inline]
#[must_use]
pub fn blend(d: f32, radius: f32) -> f32 {
    let t = ((d - 0.5 * radius) / (0.5 * radius)).clamp(0.0, 1.0);
    if t.is_nan() {
        return 0.0;
    }
    1.0 - t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn canonical_points(frame: &FaceFrame) -> FacePoints {
        let w = |c: Vec3| Some(frame.to_world(c));
        FacePoints {
            nose: w(CANONICAL_ANCHORS[0]),
            eyes: CANONICAL_EYES.map(w),
            ears: [w(CANONICAL_ANCHORS[5]), w(CANONICAL_ANCHORS[6])],
            mouth: w(CANONICAL_ANCHORS[2]),
        }
    }

    #[test]
    fn a_canonical_face_gives_back_its_frame() {
        let frame = FaceFrame {
            origin: Vec3::new(0.1, 1.6, 0.2),
            rotation: Quat::from_rotation_y(0.6) * Quat::from_rotation_x(-0.3),
            size: 0.16,
        };
        let mut p = canonical_points(&frame);
        let f = UserFace::from_points(&p).unwrap();
        assert!((f.frame.origin - frame.origin).length() < 1e-5);
        assert!(f.frame.rotation.dot(frame.rotation).abs() > 1.0 - 1e-6);
        assert!((f.frame.size - frame.size).abs() < 1e-5);
        for (a, c) in f.anchors.iter().zip(CANONICAL_ANCHORS) {
            assert!((*a - c).length() < 1e-4, "{a} vs {c}");
        }
        // Eyes only (no ears) and the nose only (no mouth): the same frame.
        p.ears = [None, None];
        p.mouth = None;
        let g = UserFace::from_points(&p).unwrap();
        assert!((g.frame.origin - frame.origin).length() < 1e-5);
        assert!(g.frame.rotation.dot(frame.rotation).abs() > 1.0 - 1e-6);
        // Nothing vertical: no frame.
        p.nose = None;
        assert!(UserFace::from_points(&p).is_none());
    }

    #[test]
    fn pose_tip_keeps_the_image_place_and_scales_the_depth() {
        let frame = FaceFrame {
            origin: Vec3::new(0.0, 0.6, 0.1),
            rotation: Quat::IDENTITY,
            size: 0.145,
        };
        let face = UserFace::from_points(&canonical_points(&frame)).unwrap();
        let camera = CameraMapping::default();
        // 30 cm in front of the mouth (toward the camera: +Z in avatar axes).
        let mouth = frame.to_world(CANONICAL_ANCHORS[FaceAnchor::Mouth.index()]);
        let tip = mouth + Vec3::new(0.0, 0.0, 0.3);
        assert!((pose_tip(&face, tip, None, None, camera, 1.0) - tip).length() < 1e-6);
        let p = pose_tip(&face, tip, None, None, camera, 0.1);
        assert!(
            (p - (mouth + Vec3::new(0.0, 0.0, 0.03))).length() < 1e-5,
            "{p}"
        );
        // The image puts the finger 1 cm left of where the world landmarks do.
        let fit = ImageFit {
            ax: 1.0,
            bx: 0.0,
            ay: -1.0,
            by: 0.0,
        };
        let image = Vec3::new(tip.x + 0.01, tip.y, 0.0);
        let q = pose_tip(&face, tip, Some(image), Some(&fit), camera, 1.0);
        assert!(
            (q - (tip + Vec3::new(0.01, 0.0, 0.0))).length() < 1e-5,
            "{q}"
        );
    }

    #[test]
    fn warp_is_exact_on_anchors_and_the_blend_is_compact() {
        let user = CANONICAL_ANCHORS;
        let avatar = CANONICAL_ANCHORS.map(|a| a * 0.8 + Vec3::new(0.0, 0.05, -0.1));
        for i in 0..ANCHORS {
            assert!((warp(user[i], &user, &avatar) - avatar[i]).length() < 1e-6);
            assert!(
                (warp(user[i] + Vec3::splat(1e-4), &user, &avatar) - avatar[i]).length() < 1e-3
            );
        }
        assert_eq!(blend(0.0, 0.5), 1.0);
        assert_eq!(blend(0.25, 0.5), 1.0);
        assert_eq!(blend(0.5, 0.5), 0.0);
        assert_eq!(blend(1.5, 0.5), 0.0);
        assert!((blend(0.375, 0.5) - 0.5).abs() < 1e-6);
        assert_eq!(blend(f32::NAN, 0.5), 0.0);
    }
}
