//! Optimization-based hand retargeting (seed 003, section 3.1): `handStrategy: "retarget"`.
//!
//! Copying joint angles (the [`HandStrategy::Analytic`](super::HandStrategy) strategy, the
//! seed's "naive" one) puts the avatar's fingers in the user's shape, but the avatar's hand
//! has other proportions, so pinches open and contacts miss. Here the avatar's finger angles
//! are instead chosen so that its fingertips land where the user's are.
//!
//! ## Hands
//!
//! * The **intermediate hand** is the avatar's own hand: its bone lengths and rest
//!   directions, and the analytic solver's joint model (per finger a 2-DOF base joint in
//!   spherical coordinates about its pole, two hinges; see `super::chain`) with the
//!   anatomical limits of [`super::limits`]. Four parameters per finger, in
//!   [`Dof`](super::Dof) order: MCP flexion and abduction (thumb: CMC abduction and
//!   opposition), PIP and DIP flexion (thumb: MCP and IP), measured on the avatar's rest palm
//!   as the analytic solver measures them on the tracked palm; the avatar bones take them the
//!   way the analytic solver poses them (a twist-free base rotation, hinges about the rest
//!   hinge axes). The palm is rigid (avatar palms have no cupping joint).
//! * The **tracked hand** is MediaPipe's 21 world landmarks, turned into the avatar's hand
//!   frame by the analytic solver's palm rotation and uniformly scaled by `s` (below), the
//!   wrist on the avatar's hand joint.
//!
//! ## Objective (seed eq. 1)
//!
//! ```text
//! E(q) = 1/2 sum_k w_k |x_k(q) - t_k|^2 + 1/2 w_p |(x_thumb - x_index) - (t_thumb - t_index)|^2
//!      + 1/2 w_s sum_fingers (DIP - 2/3 PIP)^2 + 1/2 w_t |q - q_previous|^2
//! subject to the joint limits (box constraints on q)
//! ```
//!
//! `x_k(q)` are avatar points by forward kinematics relative to the hand joint. Features
//! (diagonal `W`, [`RetargetOptions`]):
//!
//! * the five fingertips, targets `t = s p_tip` (`p` the user's landmarks relative to the
//!   wrist), thumb and index weighted double for pinching as the seed does. The avatar
//!   fingertip is the model of [`crate::align::tip_offset`] (the distal bone extended by an
//!   anatomical ratio), the point `alignment.point: "tip"` aligns;
//! * with a low weight, the two joints between base and tip, their targets hung back from
//!   the fingertip target along the user's phalanx directions with the avatar's phalanx
//!   lengths: the user's finger shape near the tip, at the avatar's size. (The user's own
//!   joint positions, scaled, cannot all be reached together with the tip when the avatar's
//!   proportions differ; chasing them made fingers jump between poses on the debug robot.)
//! * the pinch: the thumb tip relative to the index tip, weighted up smoothly as the user's
//!   scaled tips come within [`RetargetOptions::pinch_distance`], so a pinch closes on the
//!   avatar even where its thumb cannot reach the absolute target (the seed's "very accurate
//!   pinching").
//!
//! Regularization: the spatial term keeps the distal joint near two thirds of the proximal
//! interphalangeal flexion (Rijpkema & Girard, "Computer animation of knowledge-based human
//! grasping", SIGGRAPH 1991), smoothing what the features leave open; the temporal term
//! pulls toward the previous frame's solution, weaker the faster the finger's target moves
//! (tracking noise is smoothed, real motion followed; see
//! [`RetargetOptions::temporal_weight`]).
//!
//! ## Solve
//!
//! Fingers share no parameters, and only thumb and index share a feature (the pinch), so
//! `J'WJ + d2R` is block diagonal: the whole-hand Gauss-Newton step is exactly one step per
//! block, four parameters per finger (eight for thumb and index while the pinch feature
//! counts). Each block is solved by [`crate::solve::least_squares`] (box constraints by an
//! active set, Cholesky and Schur-complement multipliers); the reported iterations are the
//! most any block needed, what a whole-hand solve with a common stopping rule runs. A block
//! starts from the previous frame's solution or from this frame's analytic solution (clamped
//! to the limits), whichever costs less, with straight hinges nudged 2 degrees into flexion
//! (a straight finger whose target is a little nearer is a saddle with zero gradient). The
//! Jacobian is analytic: a base angle turns everything distal about
//! `Basis::turn_axes`, a hinge about its world axis, `d/dphi (I + phi skew(k)) R0 =
//! skew(k) R0`.
//!
//! ## Scale
//!
//! Both ways compare hand *lengths* (wrist to the tip of the middle finger, the
//! anthropometric hand size), which decide whether the avatar's fingers can reach the scaled
//! targets:
//!
//! * **Calibrated** (the seed's): the user shows an open, flat hand and the app calls
//!   [`crate::Rig::calibrate_hand_scale`]; `s` = the ratio of the lengths of the hands'
//!   bounding boxes along the palm's forward axis (the avatar's box from its rest hand
//!   including fingertips). The box's width is left out: it measures finger spread and where
//!   the thumb rests, which differ between a user's open hand and an avatar's rest pose (the
//!   debug robot's thumb splays at 45 degrees: its box diagonal scaled the user's hand 12%
//!   past its fingers' reach: median fingertip error 9.9 mm instead of 2.5 mm on the shared
//!   video). Refused when
//!   the fingers are not straight (see [`OPEN_HAND_STRAIGHTNESS`]).
//! * **Automatic** (no calibration): from lengths that do not change with the pose: the
//!   wrist-to-knuckle palm length plus the three phalanx lengths of the middle finger
//!   (wrist to fingertip along the ray; all rays summed if the avatar lacks a complete middle
//!   finger), times [`OPEN_EXTENT`] (a path is longer than the open hand's straight extent
//!   the calibration measures), averaged over frames ([`SCALE_FRAMES`]). Palm lengths alone
//!   would match palms, not hands: an avatar whose palm is long for its fingers (the debug
//!   robot: 12.5 cm palm, 8.4 cm fingers) would get the user's fingers scaled out of its
//!   reach (scale 1.31 instead of 1.05, median fingertip error 18 mm on the shared video).
use glam::{Mat3, Quat, Vec3};

mod options;

pub use options::{
    RetargetOptions, RetargetReport, DAMPING, OPEN_EXTENT, OPEN_HAND_STRAIGHTNESS, SCALE_FRAMES,
};

use super::chain::{Basis, Kind};
use super::limits::LIMITS;
use super::palm::orthonormal_frame;
use super::report::HandReport;
use super::rest::SideRest;
use crate::align::tip_offset;
use crate::humanoid::bones::{Finger, Side};
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::HAND_LANDMARKS;
use crate::math::wrap;
use crate::solve::least_squares::{minimize, Model, Objective};

/// Smallest hinge flexion (radians, 2 degrees) a Gauss-Newton start gets.
const START_FLEXION: f32 = 2.0 * core::f32::consts::PI / 180.0;
/// The DIP flexion that the spatial term prefers, as a fraction of PIP flexion.
const DIP_PER_PIP: f32 = 2.0 / 3.0;

/// One avatar bone of a finger chain.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Link {
    /// Anatomical slot (0 base, 1, 2).
    slot: usize,
    /// Rest offset from the previous link's joint (zero for the first).
    offset: Vec3,
    /// Rest direction (unit).
    dir: Vec3,
    /// Rest hinge axis (unit; links after the first turn about it).
    hinge: Vec3,
    /// Rest bend from the previous link's direction about `hinge` (radians): the bone's
    /// rotation is the anatomical hinge angle minus this.
    beta: f32,
}

/// The avatar's finger as the retargeting sees it: rest geometry in the hand's rest axes,
/// relative to the hand joint.
#[derive(Clone, Copy, Debug, PartialEq)]
struct FingerModel {
    finger: Finger,
    kind: Kind,
    basis: Basis,
    /// Fingers: longitude of the wrist-to-knuckle line (abduction is measured from it).
    lon_prior: f32,
    /// Rest position of the first bone's joint.
    base: Vec3,
    /// Transpose of the first bone's rest frame `(dir, hinge, dir x hinge)`: its rotation is
    /// the posed frame times this (the analytic solver's twist-free base rotation).
    rest_inv: Mat3,
    links: [Link; 3],
    count: usize,
    /// The fingertip relative to the distal bone's joint, in its frame.
    tip: Vec3,
    /// The link that carries each hinge parameter (index 0: PIP / thumb MCP, 1: DIP / IP;
    /// `None` when the avatar has no bone between, see [`FingerModel::hinge_sum`]).
    carrier: [Option<usize>; 2],
    lower: [f32; 4],
    upper: [f32; 4],
}

/// Posed points of one finger, indexed by slot (0..3 joints; 3 the tip), and their
/// derivatives with respect to the four parameters.
struct Posed {
    points: [Vec3; 4],
    jacobian: [[Vec3; 4]; 4],
}

impl FingerModel {
    fn new(skeleton: &Skeleton, side: Side, rest: &SideRest, finger: Finger) -> Option<Self> {
        let fr = &rest.fingers[finger.index()];
        let hand = skeleton.rest_world(side.hand())?;
        let bones = side.finger(finger);
        // The fingertip model needs the distal bone, the last link.
        let last = fr.bones[fr.count.checked_sub(1)?]?;
        if last.slot != 2 {
            return None;
        }
        let tip = tip_offset(skeleton, side, finger)?;
        let first = fr.bones[0]?;
        let base = skeleton.rest_world(bones[first.slot])? - hand;
        let mut links = [Link {
            slot: 0,
            offset: Vec3::ZERO,
            dir: Vec3::X,
            hinge: Vec3::Y,
            beta: 0.0,
        }; 3];
        for (i, link) in links.iter_mut().enumerate().take(fr.count) {
            let b = fr.bones[i]?;
            let (offset, beta) = if i == 0 {
                (Vec3::ZERO, 0.0)
            } else {
                let prev = fr.bones[i - 1]?;
                (
                    skeleton.rest_local(bones[b.slot]),
                    b.dir.dot(prev.flex).atan2(b.dir.dot(prev.dir)),
                )
            };
            *link = Link {
                slot: b.slot,
                offset,
                dir: b.dir,
                hinge: b.hinge,
                beta,
            };
        }
        let carrier = core::array::from_fn(|h| {
            (1..fr.count).find(|&i| links[i - 1].slot <= h && h < links[i].slot)
        });
        let lims = LIMITS[finger.index()];
        let lower = core::array::from_fn(|k| lims[k].radians().0);
        let upper = core::array::from_fn(|k| lims[k].radians().1);
        Some(FingerModel {
            finger,
            kind: fr.kind,
            basis: fr.basis,
            lon_prior: fr.lon_prior,
            base,
            rest_inv: orthonormal_frame(first.dir, first.hinge)?.transpose(),
            links,
            count: fr.count,
            tip,
            carrier,
            lower,
            upper,
        })
    }

    /// `q` moved into the limits.
    fn clamp(&self, q: [f32; 4]) -> [f32; 4] {
        core::array::from_fn(|k| q[k].max(self.lower[k]).min(self.upper[k]))
    }

    /// Rest length of the avatar's segment from the joint at `slot` to the next joint
    /// (slot 2: to the fingertip); 0 when the joint is absent.
    fn segment(&self, slot: usize) -> f32 {
        let i = self.links[..self.count].iter().position(|l| l.slot == slot);
        match i {
            Some(i) if i + 1 < self.count => self.links[i + 1].offset.length(),
            Some(_) => self.tip.length(),
            None => 0.0,
        }
    }

    /// Longitude and colatitude of the base direction from the two base parameters.
    #[inline]
    fn spherical(&self, q: &[f32; 4]) -> (f32, f32) {
        match self.kind {
            Kind::Finger => (self.lon_prior + q[1], core::f32::consts::FRAC_PI_2 - q[0]),
            Kind::Thumb => (q[1], q[0]),
        }
    }

    /// The two base parameters of a posed base bone with direction `dir` and hinge axis
    /// `hinge` (inverse of [`FingerModel::spherical`], in the limits' turn). The longitude is
    /// read from the hinge (the frame's `east` direction), so it stays defined when the bone
    /// points along the pole, and the colatitude is signed (fingers flexed past the pole).
    fn base_params(&self, dir: Vec3, hinge: Vec3) -> (f32, f32) {
        let b = &self.basis;
        let east = match self.kind {
            // hinge = dir x north = -east on a right-handed basis.
            Kind::Finger => -b.x.cross(b.y).dot(b.z).signum() * hinge,
            // hinge = dir x east.
            Kind::Thumb => hinge.cross(dir),
        };
        let lon = (-east.dot(b.x)).atan2(east.dot(b.y));
        let g = lon.cos() * b.x + lon.sin() * b.y;
        let colat = dir.dot(g).atan2(dir.dot(b.z));
        match self.kind {
            Kind::Finger => (
                core::f32::consts::FRAC_PI_2 - colat,
                wrap(lon - self.lon_prior),
            ),
            Kind::Thumb => {
                let center = 0.5 * (self.lower[1] + self.upper[1]);
                (colat, wrap(lon - center) + center)
            }
        }
    }

    /// The twist-free base rotation for the base parameters (`lon`, `colat`).
    #[inline]
    fn base_rotation(&self, lon: f32, colat: f32) -> Mat3 {
        let frame = self.basis.frame(self.kind, lon, colat);
        Mat3::from_cols(frame.dir, frame.hinge, frame.dir.cross(frame.hinge)) * self.rest_inv
    }

    /// Forward kinematics and, with `jacobian`, its derivatives (tangent-space rotation
    /// derivatives; zero otherwise).
    fn pose(&self, q: &[f32; 4], jacobian: bool) -> Posed {
        let (lon, colat) = self.spherical(q);
        let mut rot = self.base_rotation(lon, colat);
        let mut posed = Posed {
            points: [self.base; 4],
            jacobian: [[Vec3::ZERO; 4]; 4],
        };
        // Per link: its joint (the pivot) and its world hinge axis.
        let mut pivot = [self.base; 3];
        let mut axis = [Vec3::ZERO; 3];
        let mut pos = self.base;
        for i in 1..self.count {
            let l = &self.links[i];
            pos += rot * l.offset;
            axis[i] = rot * l.hinge;
            pivot[i] = pos;
            rot *= Mat3::from_axis_angle(l.hinge, self.hinge_sum(q, i) - l.beta);
            posed.points[l.slot] = pos;
        }
        posed.points[3] = pos + rot * self.tip;
        if !jacobian {
            return posed;
        }
        let (turn_lon, turn_colat) = self.basis.turn_axes(lon);
        let base_axes = match self.kind {
            Kind::Finger => [-turn_colat, turn_lon],
            Kind::Thumb => [turn_colat, turn_lon],
        };
        for s in self.links[0].slot + 1..4 {
            let p = posed.points[s];
            let column = &mut posed.jacobian[s];
            column[0] = base_axes[0].cross(p - self.base);
            column[1] = base_axes[1].cross(p - self.base);
            for (h, carrier) in self.carrier.iter().enumerate() {
                if let Some(i) = *carrier {
                    if s > self.links[i].slot {
                        column[2 + h] = axis[i].cross(p - pivot[i]);
                    }
                }
            }
        }
        posed
    }

    /// The anatomical hinge angles link `i` carries (those of the slots since the previous
    /// link: a missing intermediate bone's angle is carried by the distal bone).
    #[inline]
    fn hinge_sum(&self, q: &[f32; 4], i: usize) -> f32 {
        (self.links[i - 1].slot + 1..=self.links[i].slot)
            .map(|k| q[1 + k])
            .sum()
    }

    /// Writes the links' local rotations at `q` into `out` (15 finger locals,
    /// `finger * 3 + slot`).
    fn write(&self, q: &[f32; 4], out: &mut [Quat; 15]) {
        let fi = self.finger.index();
        let (lon, colat) = self.spherical(q);
        let base = Quat::from_mat3(&self.base_rotation(lon, colat)).normalize();
        out[fi * 3 + self.links[0].slot] = base;
        for i in 1..self.count {
            let l = &self.links[i];
            out[fi * 3 + l.slot] = Quat::from_axis_angle(l.hinge, self.hinge_sum(q, i) - l.beta);
        }
    }

    /// The anatomical angles of this finger as posed by `local` (15 finger locals):
    /// measured geometrically from the posed bone directions, the inverse of the
    /// parametrization. A missing bone's hinge angle is reported on the next bone.
    fn measure(&self, local: &[Quat; 15]) -> [f32; 4] {
        let fi = self.finger.index();
        let r0 = local[fi * 3 + self.links[0].slot];
        let dir0 = r0 * self.links[0].dir;
        let (a0, a1) = self.base_params(dir0, r0 * self.links[0].hinge);
        let mut angles = [a0, a1, 0.0, 0.0];
        let mut rot = r0;
        let (mut prev_dir, mut prev_flex) =
            (dir0, rot * self.links[0].hinge.cross(self.links[0].dir));
        for l in &self.links[1..self.count] {
            rot *= local[fi * 3 + l.slot];
            let dir = rot * l.dir;
            angles[1 + l.slot] = dir.dot(prev_flex).atan2(dir.dot(prev_dir));
            prev_dir = dir;
            prev_flex = rot * l.hinge.cross(l.dir);
        }
        angles
    }
}

/// One finger's objective for [`minimize`].
#[derive(Clone, Copy)]
struct FingerProblem<'a> {
    model: &'a FingerModel,
    /// Targets by slot (1, 2 joints; 3 the tip).
    targets: [Vec3; 4],
    /// Feature weights by slot (0 for the base and absent joints).
    weights: [f32; 4],
    previous: [f32; 4],
    spatial: f32,
    temporal: f32,
}

impl FingerProblem<'_> {
    /// The cost of this finger's terms at `q[offset..offset + 4]`, and with `model` their
    /// Gauss-Newton model added into it; also the posed fingertip and its Jacobian (zero
    /// without `model`).
    fn accumulate<const N: usize>(
        &self,
        q: &[f32; N],
        offset: usize,
        mut model: Option<&mut Model<N>>,
    ) -> (f32, Vec3, [Vec3; 4]) {
        let own: [f32; 4] = core::array::from_fn(|k| q[offset + k]);
        let posed = self.model.pose(&own, model.is_some());
        let mut cost = 0.0;
        let mut columns = [Vec3::ZERO; N];
        for s in 1..4 {
            if self.weights[s] > 0.0 {
                let e = posed.points[s] - self.targets[s];
                cost += match model.as_deref_mut() {
                    Some(m) => {
                        columns[offset..offset + 4].copy_from_slice(&posed.jacobian[s]);
                        m.add_point(self.weights[s], e, &columns)
                    }
                    None => 0.5 * self.weights[s] * e.length_squared(),
                };
            }
        }
        if self.model.kind == Kind::Finger {
            let e = own[3] - DIP_PER_PIP * own[2];
            cost += match model.as_deref_mut() {
                Some(m) => {
                    let mut row = [0.0; N];
                    row[offset + 2] = -DIP_PER_PIP;
                    row[offset + 3] = 1.0;
                    m.add_scalar(self.spatial, e, &row)
                }
                None => 0.5 * self.spatial * e * e,
            };
        }
        for (k, (q, previous)) in own.iter().zip(self.previous).enumerate() {
            let e = q - previous;
            cost += match model.as_deref_mut() {
                Some(m) => m.add_coordinate(self.temporal, offset + k, e),
                None => 0.5 * self.temporal * e * e,
            };
        }
        (cost, posed.points[3], posed.jacobian[3])
    }
}

impl Objective<4> for FingerProblem<'_> {
    fn evaluate(&mut self, q: &[f32; 4], model: Option<&mut Model<4>>) -> f32 {
        self.accumulate(q, 0, model).0
    }
}

/// Thumb and index together with the pinch feature: the thumb tip relative to the index
/// tip, matched to the user's (weight `weight`).
struct PinchProblem<'a, 'b> {
    thumb: &'b FingerProblem<'a>,
    index: &'b FingerProblem<'a>,
    weight: f32,
    /// The user's thumb tip minus index tip, scaled.
    target: Vec3,
}

impl Objective<8> for PinchProblem<'_, '_> {
    fn evaluate(&mut self, q: &[f32; 8], mut model: Option<&mut Model<8>>) -> f32 {
        let (c_thumb, thumb, j_thumb) = self.thumb.accumulate(q, 0, model.as_deref_mut());
        let (c_index, index, j_index) = self.index.accumulate(q, 4, model.as_deref_mut());
        let e = thumb - index - self.target;
        let pinch = match model {
            Some(m) => {
                let columns: [Vec3; 8] =
                    core::array::from_fn(|k| if k < 4 { j_thumb[k] } else { -j_index[k - 4] });
                m.add_point(self.weight, e, &columns)
            }
            None => 0.5 * self.weight * e.length_squared(),
        };
        c_thumb + c_index + pinch
    }
}

/// The avatar's hand for retargeting: the fingers that have a distal bone, and the sizes
/// the scale compares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct HandModel {
    fingers: [Option<FingerModel>; 5],
    /// Wrist-to-fingertip length along the rays the automatic scale compares, index to
    /// little (0: not compared).
    rays: [f32; 4],
    /// Rest palm frame, columns `(forward, radial, palmar)`.
    palm: Mat3,
    /// Length of the rest hand's bounding box along the palm's forward axis.
    open_length: f32,
}

impl HandModel {
    pub(super) fn new(skeleton: &Skeleton, side: Side, rest: &SideRest) -> Option<Self> {
        let fingers = Finger::ALL.map(|f| FingerModel::new(skeleton, side, rest, f));
        if fingers.iter().all(Option::is_none) {
            return None;
        }
        let mut rays = [0.0; 4];
        let mut lo = Vec3::ZERO;
        let mut hi = Vec3::ZERO;
        let palm = rest.frame;
        for m in fingers.iter().flatten() {
            let posed = m.pose(&m.rest_params(), false);
            let fi = m.finger.index();
            if fi > 0 && m.links[0].slot == 0 {
                rays[fi - 1] = m.base.length()
                    + (1..4)
                        .map(|s| (posed.points[s] - posed.points[s - 1]).length())
                        .sum::<f32>();
            }
            for p in &posed.points {
                let v = palm.transpose() * *p;
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        // The middle finger's ray when the avatar has it complete, else every complete ray.
        if rays[1] > 0.0 {
            rays = [0.0, rays[1], 0.0, 0.0];
        }
        Some(HandModel {
            fingers,
            rays,
            palm,
            open_length: hi.x - lo.x,
        })
    }

    /// The automatic scale of one frame: avatar ray length over the user's (`None` when
    /// the user's hand is degenerate).
    fn stable_scale(&self, p: &[Vec3; HAND_LANDMARKS]) -> Option<f32> {
        let (mut avatar, mut user) = (0.0, 0.0);
        for (i, finger) in Finger::ALL[1..].iter().enumerate() {
            if self.rays[i] <= 0.0 {
                continue;
            }
            let ids = finger.landmarks();
            avatar += self.rays[i];
            user += p[ids[0]].length()
                + (1..4)
                    .map(|k| (p[ids[k]] - p[ids[k - 1]]).length())
                    .sum::<f32>();
        }
        let s = OPEN_EXTENT * avatar / user;
        (user > 1e-4 && s.is_finite() && s > 0.0).then_some(s)
    }

    /// The calibrated scale from an open, flat hand `p` (see the module docs); `None` when
    /// the fingers are not straight or the hand is degenerate.
    fn open_hand_scale(&self, p: &[Vec3; HAND_LANDMARKS]) -> Option<f32> {
        for finger in &Finger::ALL[1..] {
            let ids = finger.landmarks();
            let path: f32 = (1..4).map(|k| (p[ids[k]] - p[ids[k - 1]]).length()).sum();
            let straight = (p[ids[3]] - p[ids[0]]).length();
            if !(path > 1e-4 && straight >= OPEN_HAND_STRAIGHTNESS * path) {
                return None;
            }
        }
        let mut lo = Vec3::ZERO;
        let mut hi = Vec3::ZERO;
        for q in p {
            let v = self.palm.transpose() * *q;
            lo = lo.min(v);
            hi = hi.max(v);
        }
        let s = self.open_length / (hi.x - lo.x);
        (s.is_finite() && s > 0.0).then_some(s)
    }
}

impl FingerModel {
    /// The parameters of the avatar's rest finger (the base as it rests, hinges at their
    /// rest bends).
    fn rest_params(&self) -> [f32; 4] {
        let (a0, a1) = self.base_params(self.links[0].dir, self.links[0].hinge);
        let mut q = [a0, a1, 0.0, 0.0];
        for i in 1..self.count {
            q[self.links[i].slot + 1] = self.links[i].beta;
        }
        q
    }
}

/// Retargeting state of one side: the previous solution, the scale, the last tracked hand
/// (for calibration) and the last report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct SideState {
    previous: Option<[[f32; 4]; 5]>,
    /// The previous frame's fingertip targets (with `previous`).
    previous_targets: [Vec3; 5],
    /// Running mean of the automatic scale and how many frames it holds.
    auto_scale: f32,
    auto_frames: u32,
    /// Calibrated or preset scale (overrides the automatic one).
    fixed_scale: Option<f32>,
    /// The last solved frame's landmarks in the hand frame, relative to the wrist.
    last_hand: Option<[Vec3; HAND_LANDMARKS]>,
    pub(super) report: Option<RetargetReport>,
}

impl SideState {
    /// The scale in force (`None` before any frame without a fixed scale).
    pub(super) fn scale(&self) -> Option<f32> {
        self.fixed_scale
            .or((self.auto_frames > 0).then_some(self.auto_scale))
    }

    /// Sets (or with `None` clears) a fixed scale.
    pub(super) fn set_scale(&mut self, scale: Option<f32>) {
        self.fixed_scale = scale.filter(|s| s.is_finite() && *s > 0.0);
    }

    /// Takes in a solved frame's hand (`p`: landmarks in the hand frame relative to the
    /// wrist): updates the automatic scale and keeps the hand for calibration. Every strategy
    /// does this, so the scale is known when the strategy changes and calibration works.
    pub(super) fn observe(&mut self, model: &HandModel, p: &[Vec3; HAND_LANDMARKS]) {
        if let Some(s) = model.stable_scale(p) {
            self.auto_frames = (self.auto_frames + 1).min(SCALE_FRAMES);
            self.auto_scale += (s - self.auto_scale) / self.auto_frames as f32;
        }
        self.last_hand = Some(*p);
    }

    /// Calibrates from the last solved frame (an open hand); returns the new scale.
    pub(super) fn calibrate(&mut self, model: &HandModel) -> Option<f32> {
        let s = model.open_hand_scale(self.last_hand.as_ref()?)?;
        self.fixed_scale = Some(s);
        Some(s)
    }

    /// Forgets the previous solution and the automatic scale (not a fixed scale).
    pub(super) fn reset(&mut self) {
        *self = SideState {
            fixed_scale: self.fixed_scale,
            ..SideState::default()
        };
    }
}

/// Retargets one hand. `p`: the tracked landmarks in the hand frame relative to the wrist
/// (the analytic solver's palm rotation undone), already given to [`SideState::observe`];
/// `analytic`: the analytic solve of this frame (its angles are a first guess). Overwrites
/// the retargeted fingers' locals in `out` (the others keep the analytic rotations) and
/// leaves the report in `state`.
/// Allocates nothing; a finger whose solve is not finite keeps its analytic rotations.
pub(super) fn solve(
    model: &HandModel,
    options: &RetargetOptions,
    state: &mut SideState,
    p: &[Vec3; HAND_LANDMARKS],
    analytic: &HandReport,
    out: &mut [Quat; 15],
) {
    let scale = state.scale().unwrap_or(1.0);
    let mut problems = model.fingers.each_ref().map(|m| {
        m.as_ref().map(|m| FingerProblem {
            model: m,
            targets: [Vec3::ZERO; 4],
            weights: [0.0; 4],
            previous: [0.0; 4],
            spatial: options.spatial_weight,
            temporal: options.temporal_weight,
        })
    });
    // Per finger: targets, weights and the starting point.
    let mut start = [[0.0_f32; 4]; 5];
    for problem in problems.iter_mut().flatten() {
        let m = problem.model;
        let fi = m.finger.index();
        let ids = m.finger.landmarks();
        // The fingertip target, and the joints hung back from it along the user's phalanx
        // directions with the avatar's phalanx lengths (the user's finger shape near the
        // tip, at the avatar's size).
        problem.targets[3] = scale * p[ids[3]];
        problem.weights[3] = options.tip_weights[fi];
        for s in (1..3).rev() {
            let user = (p[ids[s + 1]] - p[ids[s]]).normalize_or_zero();
            problem.targets[s] = problem.targets[s + 1] - m.segment(s) * user;
            if m.segment(s) > 0.0 {
                problem.weights[s] = options.joint_weight;
            }
        }
        let guess = m.clamp(core::array::from_fn(|k| analytic.angles[fi][k]));
        start[fi] = guess;
        problem.previous = guess;
        problem.temporal = DAMPING;
        if let Some(previous) = state.previous {
            problem.temporal = options.temporal_weight;
            let previous = m.clamp(previous[fi]);
            problem.previous = previous;
            let v = (problem.targets[3] - state.previous_targets[fi]).length();
            problem.temporal /= 1.0 + (v / options.temporal_speed).powi(2);
            if problem.evaluate(&previous, None) < problem.evaluate(&guess, None) {
                start[fi] = previous;
            }
        }
        // A straight finger whose target lies a little nearer along its own axis is a saddle
        // of the fingertip distance: every rotation moves the tip sideways, the gradient
        // vanishes and Gauss-Newton would stay. Start straight hinges slightly flexed, the
        // way fingers bend (the objective is unchanged).
        for (q, hi) in start[fi].iter_mut().zip(m.upper).skip(2) {
            if q.abs() < START_FLEXION {
                *q = START_FLEXION.min(hi);
            }
        }
    }
    let mut solution = start;
    let mut iterations = 0;
    let [thumb, index, rest @ ..] = &mut problems;
    // Thumb and index: one problem while the user's tips are close enough for the pinch
    // feature to count.
    let mut pinched = false;
    if let (Some(thumb), Some(index)) = (thumb.as_mut(), index.as_mut()) {
        let target = thumb.targets[3] - index.targets[3];
        let weight = options.pinch_weight * pinch_ramp(target.length(), options.pinch_distance);
        if weight > 0.0 {
            pinched = true;
            let mut q: [f32; 8] = core::array::from_fn(|k| start[k / 4][k % 4]);
            let lower = core::array::from_fn(|k| [thumb.model, index.model][k / 4].lower[k % 4]);
            let upper = core::array::from_fn(|k| [thumb.model, index.model][k / 4].upper[k % 4]);
            let mut pinch = PinchProblem {
                thumb,
                index,
                weight,
                target,
            };
            let result = minimize(&mut pinch, &mut q, &lower, &upper, &options.settings);
            iterations = iterations.max(result.iterations);
            for k in 0..8 {
                solution[k / 4][k % 4] = q[k];
            }
        }
    }
    let singles = [thumb, index]
        .into_iter()
        .filter(|_| !pinched)
        .chain(rest.iter_mut());
    for problem in singles.flatten() {
        let fi = problem.model.finger.index();
        let m = problem.model;
        let result = minimize(
            problem,
            &mut solution[fi],
            &m.lower,
            &m.upper,
            &options.settings,
        );
        iterations = iterations.max(result.iterations);
    }

    let mut report = RetargetReport {
        targets: [None; 5],
        scale,
        iterations,
        residual: 0.0,
    };
    let (mut err, mut weight) = (0.0, 0.0);
    let mut previous = state.previous.unwrap_or(start);
    for problem in problems.iter().flatten() {
        let m = problem.model;
        let fi = m.finger.index();
        let q = solution[fi];
        let posed = m.pose(&q, false);
        if !(q.iter().all(|v| v.is_finite()) && posed.points[3].is_finite()) {
            continue;
        }
        m.write(&q, out);
        previous[fi] = q;
        state.previous_targets[fi] = problem.targets[3];
        report.targets[fi] = Some(problem.targets[3]);
        let w = options.tip_weights[fi];
        err += w * (posed.points[3] - problem.targets[3]).length_squared();
        weight += w;
    }
    report.residual = if weight > 0.0 {
        (err / weight).sqrt()
    } else {
        0.0
    };
    state.previous = Some(previous);
    state.report = Some(report);
}

/// Weight of the pinch feature as a fraction of its full weight, for the user's scaled
/// thumb-index tip distance `d`: 1 below `full / 2`, 0 beyond `full`, smooth in between.
fn pinch_ramp(d: f32, full: f32) -> f32 {
    let t = ((full - d) / (0.5 * full)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Anatomical angles `[finger] -> [base0, base1, hinge1, hinge2]` (radians, [`super::Dof`] order)
/// of the retargeting model's fingers as posed by the 15 finger locals of one side.
pub(super) fn measure(model: &HandModel, local: &[Quat; 15]) -> [Option<[f32; 4]>; 5] {
    model.fingers.map(|m| m.map(|m| m.measure(local)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::humanoid::skeleton::VrmVersion;

    /// A T-pose body (VRM 1.0 frame) with a right hand whose fingers rest spread and bent
    /// (from 3 to 11 degrees a joint) in their anatomical planes, and a thumb forward and
    /// palmar.
    fn skeleton() -> Skeleton {
        let mut bones = crate::humanoid::skeleton::test_body();
        let hand = Vec3::new(-0.7, 1.4, 0.0); // test_body's right hand
        let side = Side::Right;
        for (f, z, bend) in [
            (Finger::Index, 0.025_f32, 0.05_f32),
            (Finger::Middle, 0.0, 0.1),
            (Finger::Ring, -0.02, 0.15),
            (Finger::Little, -0.038, 0.2),
        ] {
            let mut p = hand + Vec3::new(-0.09, 0.0, z);
            let mut d = Vec3::new(-1.0, 0.0, 0.1 * z / 0.025).normalize();
            for (bone, len) in side.finger(f).into_iter().zip([0.045, 0.027, 0.0]) {
                bones.push((bone, p));
                // Bent in the finger's vertical plane (palm down: toward -Y).
                d = (Quat::from_axis_angle(Vec3::Y.cross(d).normalize(), bend) * d).normalize();
                p += d * len;
            }
        }
        let t = Vec3::new(-0.6, -0.4, 0.6).normalize();
        let t0 = hand + Vec3::new(-0.02, -0.01, 0.02);
        for (bone, k) in side
            .finger(Finger::Thumb)
            .into_iter()
            .zip([0.0, 0.04, 0.07])
        {
            bones.push((bone, t0 + t * k));
        }
        Skeleton::new(&bones, VrmVersion::V1).unwrap()
    }

    fn model() -> HandModel {
        let skel = skeleton();
        let rest = super::super::side_rest(&skel, Side::Right).unwrap();
        HandModel::new(&skel, Side::Right, &rest).unwrap()
    }

    /// Parameter sets inside the limits for every finger.
    fn samples(m: &FingerModel) -> [[f32; 4]; 4] {
        let at =
            |t: [f32; 4]| core::array::from_fn(|k| m.lower[k] + t[k] * (m.upper[k] - m.lower[k]));
        [
            at([0.3, 0.5, 0.2, 0.4]),
            at([0.7, 0.2, 0.6, 0.5]),
            at([0.5, 0.8, 0.9, 0.1]),
            at([0.15, 0.4, 0.05, 0.3]),
        ]
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let model = model();
        for m in model.fingers.iter().flatten() {
            for q in samples(m) {
                let posed = m.pose(&q, true);
                for k in 0..4 {
                    let h = 1e-3;
                    let (mut up, mut down) = (q, q);
                    up[k] += h;
                    down[k] -= h;
                    let (a, b) = (m.pose(&up, false), m.pose(&down, false));
                    for s in 1..4 {
                        let fd = (a.points[s] - b.points[s]) / (2.0 * h);
                        let e = (fd - posed.jacobian[s][k]).length();
                        assert!(e < 2e-4, "{:?} point {s} param {k}: {e}", m.finger);
                    }
                }
            }
        }
    }

    #[test]
    fn measuring_a_posed_finger_gives_back_its_parameters() {
        let model = model();
        for m in model.fingers.iter().flatten() {
            for q in samples(m) {
                let mut local = [Quat::IDENTITY; 15];
                m.write(&q, &mut local);
                let got = m.measure(&local);
                for k in 0..4 {
                    assert!(
                        (got[k] - q[k]).abs() < 1e-4,
                        "{:?} param {k}: {} vs {}",
                        m.finger,
                        got[k],
                        q[k]
                    );
                }
            }
            // The rest parameters pose the rest finger. (A rest finger bent out of its
            // anatomical plane would come back turned about its base direction: the
            // twist-free base rotation takes its rest hinge to the anatomical one.)
            let posed = m.pose(&m.rest_params(), false);
            let mut joint = m.base;
            for l in &m.links[1..m.count] {
                joint += l.offset;
                let e = (posed.points[l.slot] - joint).length();
                assert!(e < 1e-5, "{:?} joint {}: {e}", m.finger, l.slot);
            }
            let e = (posed.points[3] - joint - m.tip).length();
            assert!(e < 1e-5, "{:?} tip: {e}", m.finger);
        }
    }

    #[test]
    fn pinch_ramp_is_smooth_and_bounded() {
        assert_eq!(pinch_ramp(0.0, 0.04), 1.0);
        assert_eq!(pinch_ramp(0.02, 0.04), 1.0);
        assert_eq!(pinch_ramp(0.04, 0.04), 0.0);
        assert_eq!(pinch_ramp(1.0, 0.04), 0.0);
        let mid = pinch_ramp(0.03, 0.04);
        assert!((mid - 0.5).abs() < 1e-6, "{mid}");
    }
}
