//! Hand solving: the hand (wrist) world rotation and the 15 finger rotations of one hand from
//! MediaPipe's 21 world landmarks, through an anatomical hand model with joint limits.
//!
//! ## Palm frame
//!
//! [`palm_frame`]: forward `f` = wrist to middle MCP, radial `r` = little MCP to index MCP made
//! perpendicular to `f`, palmar normal `n` (`r x f` on a right hand, `f x r` on a left hand: a
//! left hand is the mirror image of a right one). The avatar's rest palm frame is the same
//! construction on the rest positions of `hand`, `indexProximal`, `littleProximal` and
//! `middleProximal` (substitutes when some are missing: the other proximals, the arm direction,
//! palm-down as VRM's T-pose prescribes). The hand's world rotation maps the rest palm frame
//! onto the tracked one, so "direction in the palm frame" means the same on both.
//!
//! ## Finger model
//!
//! Each finger is a 2-DOF base joint and two hinge joints, each hinge with a small sideways
//! deviation (the play the collateral ligaments allow, [`Dof::Deviation1`] and
//! [`Dof::Deviation2`]; see `chain` for the math). All angles are
//! measured on the tracked hand (so the limits in [`limits`] are anatomical), expressed in the
//! palm frame:
//!
//! * Index to little: the base is the MCP, in spherical coordinates about the palmar normal:
//!   flexion = elevation of the proximal phalanx out of the palm plane, abduction = its
//!   longitude relative to the wrist-to-MCP line (radial +). PIP and DIP bend in the vertical
//!   plane through the proximal phalanx. The ring and little rays measure about their own
//!   palmar normal (the plane of wrist, neighbouring MCP and own MCP), which carries the palm's
//!   cupping at CMC IV/V; index and middle use the palm's.
//! * Thumb: the base is the CMC, in spherical coordinates about the index metacarpal line
//!   (wrist to index MCP): abduction = angle between the two metacarpals, opposition = rotation
//!   about the index metacarpal from the palm plane (radial side) toward palmar. MCP and IP
//!   bend along the carried "east" direction: palmar when the thumb lies in the palm plane,
//!   across the palm in opposition (Kapandji's cone of opposition).
//!
//! The base angles are a least-squares fit to the whole finger (the hinge plane that best
//! explains all three segments, the middle and distal ones weighted half as much as the
//! proximal, `HINGE_FIT_WEIGHT`), then clamped to the limits; the hinge angles are the
//! segments' angles in that plane, clamped. Each hinge segment's deviation is
//! its angle out of its joint's flexion plane (toward the hinge axis as a right hand has it,
//! so mirror images report the same angles: on index to little the radial side), clamped;
//! the distal hinge is measured in the middle phalanx's own frame, so PIP deviation carries
//! into the DIP's plane as it does on a hand.
//!
//! ## Avatar rotations
//!
//! The clamped model gives every user joint position along the finger; each bone the avatar
//! has points along the span from its joint to the next bone it has (or the tip), so a
//! missing intermediate makes the proximal cover MCP to DIP. The first bone (parent: the hand)
//! gets the rotation taking its rest direction and rest hinge axis to the target direction
//! and the tracked hinge axis (no other twist); the others turn about their rest hinge axis,
//! after a tilt about `dir x hinge` toward the hinge axis by their deviation. Rest directions
//! and hinge axes come from the avatar's own rest pose, so bent, rotated or unevenly spaced
//! rest fingers work: a straight rest finger gets the anatomical hinge axis of its rest
//! direction, a finger resting bent (rigged thumbs usually are) hinges in the plane it is
//! bent in. A distal bone's rest direction continues its parent's (avatars
//! have no tip bone).
//!
//! Finger rotations do not depend on the avatar's proportions: the avatar's bones take the
//! tracked directions in the palm frame; lengths only matter where a missing bone makes one
//! bone cover several phalanges (the span direction uses the tracked phalanx lengths).
use glam::{Mat3, Quat, Vec3};

use crate::error::Result;
use crate::humanoid::bones::{Finger, HumanBone, Side, BONE_COUNT};
use crate::humanoid::skeleton::Skeleton;
use crate::input::mediapipe::HAND_LANDMARKS;

mod chain;
pub mod flip;
pub mod limits;
mod palm;
mod report;
mod rest;
pub mod retarget;

pub use limits::{Dof, JointRange, DOF_COUNT, LIMITS};
pub use palm::palm_frame;
pub use report::{HandReport, HandStatus, HandStrategy};
pub use retarget::{RetargetOptions, RetargetReport};

use palm::*;
use rest::*;

use crate::math::{clamp_angle, wrap};
use chain::{bend, hinge_angle, Kind, Targets};

/// Slack before a clamped angle counts as a limit being active.
const LIMIT_SLACK: f32 = 1e-4;
/// Sine below which a phalanx counts as lying in its bone's flexion plane (a pure hinge turn).
const SIDE_EPSILON: f32 = 1e-6;
/// Weight of the middle and distal phalanges, against the proximal's 1, in the fit of a
/// finger's base angles. With 1 (all three alike, before the hinges could deviate) the
/// proximal bone was off by a median 3-6 degrees wherever MediaPipe's finger is not planar;
/// 0 (the proximal alone) leaves the plane to one noisy segment. 0.5: finger bone p95 on the
/// shared recordings 14.1 -> 11.5 degrees, every clip better, less jitter on the hand video
/// (1.63 -> 1.55 degrees per bone-frame; 1.47 before the hinges could deviate); 0.35-0.5
/// measure alike (`eval_fingers`).
const HINGE_FIT_WEIGHT: f32 = 0.5;
/// Previous output of one side, rewritten when a frame is degenerate.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Held {
    rotation: Quat,
    local: [Quat; 15],
}

/// Per-avatar hand solver: rest data precomputed in [`HandSolver::new`], per-side state for
/// holding the last good solve. [`HandSolver::solve`] allocates nothing.
#[derive(Clone, Debug)]
pub struct HandSolver {
    strategy: HandStrategy,
    rest: [Option<SideRest>; 2],
    held: [Option<Held>; 2],
    report: [HandReport; 2],
    /// The retargeting's avatar hands (every strategy: [`HandSolver::avatar_angles`]).
    models: [Option<retarget::HandModel>; 2],
    retarget: [retarget::SideState; 2],
    retarget_options: RetargetOptions,
}

impl HandSolver {
    /// Prepares the solver from the avatar's rest finger layout (directions, hinge axes, palm
    /// frame per side). A side whose palm cannot be defined is never solved.
    ///
    /// # Errors
    /// None currently; the `Result` leaves room for strategies that need more of the rig.
    pub fn new(skeleton: &Skeleton, strategy: HandStrategy) -> Result<Self> {
        let rest = Side::BOTH.map(|side| side_rest(skeleton, side));
        let models = Side::BOTH.map(|side| {
            rest[side.index()]
                .as_ref()
                .and_then(|r| retarget::HandModel::new(skeleton, side, r))
        });
        Ok(HandSolver {
            strategy,
            rest,
            held: [None, None],
            report: [HandReport::default(); 2],
            models,
            retarget: [retarget::SideState::default(); 2],
            retarget_options: RetargetOptions::default(),
        })
    }

    /// Sets the retargeting's weights and stopping rule.
    ///
    /// # Errors
    /// Options failing [`RetargetOptions::is_valid`] (named `options.retarget`).
    pub fn set_retarget_options(&mut self, options: RetargetOptions) -> Result<()> {
        if !options.is_valid() {
            return Err(crate::error::Error::invalid(
                "options.retarget",
                "weights must be finite and non-negative, the temporal weight positive",
            ));
        }
        self.retarget_options = options;
        Ok(())
    }

    /// Forgets every side's history: held rotations, reports, the retargeting's previous
    /// solution and automatic scale (a calibrated or preset hand scale stays).
    pub fn reset(&mut self) {
        self.held = [None, None];
        self.report = [HandReport::default(); 2];
        for state in &mut self.retarget {
            state.reset();
        }
    }

    /// The strategy in use.
    #[must_use]
    pub fn strategy(&self) -> HandStrategy {
        self.strategy
    }

    /// What the retargeting did in the last solve of `side`: `Some` only when that solve
    /// was fresh ([`HandStatus::Solved`]) with [`HandStrategy::Retarget`]. Targets are
    /// relative to the hand joint, in the hand bone's frame.
    #[must_use]
    pub fn retarget_report(&self, side: Side) -> Option<&RetargetReport> {
        self.retarget[side.index()].report.as_ref()
    }

    /// The hand scale (avatar / user) the retargeting uses on `side`: the calibrated or
    /// preset one, else the automatic one; `None` before the first frame.
    #[must_use]
    pub fn hand_scale(&self, side: Side) -> Option<f32> {
        self.retarget[side.index()].scale()
    }

    /// Presets the hand scale of `side` (`None`: back to automatic). Non-finite or
    /// non-positive values count as `None`.
    pub fn set_hand_scale(&mut self, side: Side, scale: Option<f32>) {
        self.retarget[side.index()].set_scale(scale);
    }

    /// Calibrates the hand scale of `side` from the last hand solved there, which should be
    /// an open, flat hand (the seed's bounding-box scale, see [`retarget`]). Returns the new
    /// scale, or `None` (nothing changed) when no hand was solved yet, its fingers are not
    /// straight, or the avatar has no retargetable fingers.
    pub fn calibrate_hand_scale(&mut self, side: Side) -> Option<f32> {
        let model = self.models[side.index()].as_ref()?;
        self.retarget[side.index()].calibrate(model)
    }

    /// The anatomical angles, radians, `[finger] -> [base0, base1, hinge1, hinge2]` ([`Dof`]
    /// order), of the avatar's fingers as posed by `local`, measured on the avatar's rest
    /// palm the way the analytic solver measures the tracked hand: what the retargeting
    /// keeps within [`LIMITS`]. `None` for fingers without a distal bone.
    #[must_use]
    pub fn avatar_angles(&self, side: Side, local: &[Quat; BONE_COUNT]) -> [Option<[f32; 4]>; 5] {
        let Some(model) = self.models[side.index()].as_ref() else {
            return [None; 5];
        };
        let mut fingers = [Quat::IDENTITY; 15];
        for finger in Finger::ALL {
            for (slot, bone) in side.finger(finger).into_iter().enumerate() {
                fingers[finger.index() * 3 + slot] = local[bone.index()];
            }
        }
        retarget::measure(model, &fingers)
    }

    /// The report of the last solve of `side`.
    #[must_use]
    pub fn report(&self, side: Side) -> &HandReport {
        &self.report[side.index()]
    }

    /// The rest direction the solver uses for a finger bone (unit, internal frame; a bone
    /// without a child continues its parent's direction). `None` for non-finger or absent
    /// bones, or when the side's palm is undefined.
    #[must_use]
    pub fn rest_direction(&self, bone: HumanBone) -> Option<Vec3> {
        self.bone_rest(bone).map(|b| b.dir)
    }

    /// The rest hinge (flexion) axis of a finger bone: hinge bones turn only about this axis
    /// (in their parent's frame); a positive angle flexes. Same `None` cases as
    /// [`HandSolver::rest_direction`].
    #[must_use]
    pub fn rest_hinge_axis(&self, bone: HumanBone) -> Option<Vec3> {
        self.bone_rest(bone).map(|b| b.hinge)
    }

    /// The avatar's rest palm frame of `side`, columns `(forward, radial, palmar)`.
    #[must_use]
    pub fn rest_palm_frame(&self, side: Side) -> Option<Mat3> {
        self.rest[side.index()].map(|r| r.frame)
    }

    fn bone_rest(&self, bone: HumanBone) -> Option<BoneRest> {
        let side = bone.side()?;
        let rest = self.rest[side.index()].as_ref()?;
        rest.fingers
            .iter()
            .flat_map(|f| f.bones.iter().flatten())
            .find(|b| b.bone == bone)
            .copied()
    }

    /// Solves one hand. `landmarks`: MediaPipe's 21 world landmarks already in the avatar's
    /// internal frame with the chirality of `side` (meters; only directions matter). Writes
    /// the local rotations of this side's finger bones the avatar has into `local` and
    /// returns the hand's world rotation (internal frame).
    ///
    /// A degenerate hand (coincident points, collinear palm) writes the previous solve's
    /// finger rotations again and returns its hand rotation ([`HandStatus::Held`]); with no
    /// previous solve it writes nothing and returns `None`. Never produces NaN; allocates
    /// nothing.
    pub fn solve(
        &mut self,
        skeleton: &Skeleton,
        side: Side,
        landmarks: &[Vec3; HAND_LANDMARKS],
        local: &mut [Quat; BONE_COUNT],
    ) -> Option<Quat> {
        let s = side.index();
        let mut scratch = [Quat::IDENTITY; 15];
        let mut report = HandReport::default();
        let mut hand = [Vec3::ZERO; HAND_LANDMARKS];
        let fresh = self.rest[s].as_ref().and_then(|rest| {
            solve_side(rest, side, landmarks, &mut scratch, &mut report, &mut hand)
        });
        self.retarget[s].report = None;
        match fresh {
            Some(rotation) => {
                if let Some(model) = &self.models[s] {
                    self.retarget[s].observe(model, &hand);
                    if self.strategy == HandStrategy::Retarget {
                        retarget::solve(
                            model,
                            &self.retarget_options,
                            &mut self.retarget[s],
                            &hand,
                            &report,
                            &mut scratch,
                        );
                    }
                }
                write_fingers(skeleton, side, &scratch, local);
                report.status = HandStatus::Solved;
                self.report[s] = report;
                self.held[s] = Some(Held {
                    rotation,
                    local: scratch,
                });
                Some(rotation)
            }
            None => self.hold(skeleton, side, local),
        }
    }

    /// Writes `side`'s last solved rotations again (status `Held`) and returns its hand
    /// rotation; `None` (status `Skipped`) when nothing was solved yet. What [`HandSolver::solve`]
    /// does with a degenerate hand, and the rig with a hand its checks reject.
    pub fn hold(
        &mut self,
        skeleton: &Skeleton,
        side: Side,
        local: &mut [Quat; BONE_COUNT],
    ) -> Option<Quat> {
        let s = side.index();
        self.retarget[s].report = None;
        match self.held[s] {
            Some(h) => {
                write_fingers(skeleton, side, &h.local, local);
                self.report[s].status = HandStatus::Held;
                Some(h.rotation)
            }
            None => {
                self.report[s] = HandReport {
                    status: HandStatus::Skipped,
                    ..HandReport::default()
                };
                None
            }
        }
    }
}

fn write_fingers(
    skeleton: &Skeleton,
    side: Side,
    src: &[Quat; 15],
    local: &mut [Quat; BONE_COUNT],
) {
    for finger in Finger::ALL {
        for (slot, bone) in side.finger(finger).into_iter().enumerate() {
            if skeleton.has(bone) {
                local[bone.index()] = src[finger.index() * 3 + slot];
            }
        }
    }
}

/// The rotation about the unit `axis` by `atan2(y, x)`, without trigonometry: the half-angle
/// quaternion is `(axis y, r + x)` normalized, `r = |(x, y)|` (exact for every angle; at a
/// half turn, `r + x = 0`, it is `(axis, 0)` signed like `y`). Identity for `x = y = 0`, NaN
/// for NaN.
fn hinge_rotation(axis: Vec3, x: f32, y: f32) -> Quat {
    // x and y are components of a unit vector: no overflow to guard against.
    let r = (x * x + y * y).sqrt();
    if r.is_nan() {
        // Like atan2: the caller's finiteness check rejects the finger.
        return Quat::NAN;
    }
    if r <= 0.0 {
        return Quat::IDENTITY;
    }
    let w = r + x;
    if w <= r * 1e-12 {
        let a = axis * 1.0_f32.copysign(y);
        return Quat::from_xyzw(a.x, a.y, a.z, 0.0);
    }
    let v = axis * y;
    Quat::from_xyzw(v.x, v.y, v.z, w).normalize()
}

/// Solves one side into `out` (15 finger locals, `finger * 3 + slot`) and `report`; returns
/// the hand world rotation, or `None` if degenerate (then `out` is unusable).
fn solve_side(
    rest: &SideRest,
    side: Side,
    lm: &[Vec3; HAND_LANDMARKS],
    out: &mut [Quat; 15],
    report: &mut HandReport,
    hand: &mut [Vec3; HAND_LANDMARKS],
) -> Option<Quat> {
    let obs = rest.palm.observed(side, lm)?;
    let rotation = Quat::from_mat3(&(obs * rest.frame.transpose())).normalize();
    if !rotation.is_finite() {
        return None;
    }
    // Everything below in the avatar's rest axes (the hand's local frame), wrist at origin.
    let to_rest = rotation.inverse();
    let p: [Vec3; HAND_LANDMARKS] = core::array::from_fn(|k| to_rest * (lm[k] - lm[0]));
    let (f, r, n) = (rest.frame.x_axis, rest.frame.y_axis, rest.frame.z_axis);

    for finger in Finger::ALL {
        solve_finger(rest, finger, &p, (f, r, n), out, report)?;
    }
    *hand = p;
    Some(rotation)
}

/// Sine and cosine of a deviation as clamped (`clamped`): from the sine it was measured as
/// (`sine`, of the angle `measured`) when the limit left it alone.
#[inline]
fn deviation(clamped: f32, measured: f32, sine: f32) -> (f32, f32) {
    if clamped == measured {
        (sine, (1.0 - sine * sine).sqrt())
    } else {
        clamped.sin_cos()
    }
}

#[inline(never)] // See `chain::cost`: faster in wasm out of line.
fn solve_finger(
    rest: &SideRest,
    finger: Finger,
    p: &[Vec3; HAND_LANDMARKS],
    (f, r, n): (Vec3, Vec3, Vec3),
    out: &mut [Quat; 15],
    report: &mut HandReport,
) -> Option<()> {
    let fi = finger.index();
    let lims = LIMITS[fi];
    let lm = finger.landmarks();
    let base_pos = p[lm[0]];
    let metacarpal = base_pos.try_normalize().unwrap_or(f);

    // The pole of the base joint; for ring and little the cupped local palmar normal.
    let mut cupping = 0.0;
    let pole = match finger {
        Finger::Thumb => p[MCP[0]].try_normalize().unwrap_or(f),
        Finger::Ring | Finger::Little => {
            let (a, b) = if finger == Finger::Ring {
                (p[MCP[1]], p[MCP[2]])
            } else {
                (p[MCP[2]], p[MCP[3]])
            };
            match local_pole(Vec3::ZERO, a, b, n) {
                Some(pole) => {
                    let tilt = pole.dot(n).clamp(-1.0, 1.0).acos();
                    let (_, hi) = lims[Dof::Cupping.index()].radians();
                    cupping = tilt.min(hi);
                    if tilt > hi + LIMIT_SLACK {
                        report.limited[fi][Dof::Cupping.index()] = true;
                        let side_dir = (pole - pole.dot(n) * n)
                            .try_normalize()
                            .unwrap_or(Vec3::ZERO);
                        (n * hi.cos() + side_dir * hi.sin()).normalize()
                    } else {
                        pole
                    }
                }
                None => n,
            }
        }
        _ => n,
    };
    let (kind, basis) = basis_for(finger, f, r, n, pole);

    // The user's segments.
    let mut len = [0.0_f32; 3];
    let mut targets = Targets {
        dir: [metacarpal; 3],
        weight: [0.0; 3],
        lon_prior: basis.longitude(metacarpal),
    };
    let mut prev = metacarpal;
    for k in 0..3 {
        let v = p[lm[k + 1]] - p[lm[k]];
        len[k] = v.length();
        if len[k] > MIN_LENGTH {
            targets.dir[k] = v / len[k];
            targets.weight[k] = 1.0;
        } else {
            targets.dir[k] = prev;
        }
        prev = targets.dir[k];
    }
    let known: f32 = len.iter().filter(|l| **l > MIN_LENGTH).sum();
    let count = len.iter().filter(|l| **l > MIN_LENGTH).count();
    let nominal = if count > 0 { known / count as f32 } else { 1.0 };
    for l in &mut len {
        if *l <= MIN_LENGTH {
            *l = nominal;
        }
    }

    // Fit, canonicalize into anatomical angles, clamp.
    // The base fit leans on the proximal phalanx: the hinges' deviation takes up what the
    // middle and distal phalanges have out of the plane.
    let mut fit_targets = targets;
    fit_targets.weight[1] *= HINGE_FIT_WEIGHT;
    fit_targets.weight[2] *= HINGE_FIT_WEIGHT;
    let (lon, colat) = chain::fit(&basis, kind, &fit_targets);
    let mut colat = wrap(colat);
    let mut lon = lon;
    let (a0, a1) = match kind {
        Kind::Finger => {
            let mut dl = wrap(lon - targets.lon_prior);
            if dl.abs() > core::f32::consts::FRAC_PI_2 {
                dl = wrap(dl + core::f32::consts::PI);
                colat = -colat;
            }
            (core::f32::consts::FRAC_PI_2 - colat, dl)
        }
        Kind::Thumb => {
            if colat < 0.0 {
                colat = -colat;
                lon += core::f32::consts::PI;
            }
            let center = 60f32.to_radians();
            (colat, wrap(lon - center) + center)
        }
    };
    let mut clamp = |dof: Dof, v: f32| -> f32 {
        let (lo, hi) = lims[dof.index()].radians();
        let c = clamp_angle(v, lo, hi);
        if (c - v).abs() > LIMIT_SLACK {
            report.limited[fi][dof.index()] = true;
        }
        report.angles[fi][dof.index()] = c;
        c
    };
    let a0 = clamp(Dof::Base0, a0);
    let a1 = clamp(Dof::Base1, a1);
    (lon, colat) = match kind {
        Kind::Finger => (targets.lon_prior + a1, core::f32::consts::FRAC_PI_2 - a0),
        Kind::Thumb => (a1, a0),
    };
    let frame = basis.frame(kind, lon, colat);
    let (d, flex) = (frame.dir, frame.flex);
    let hinge = frame.hinge.try_normalize()?;
    let abs1 = if targets.weight[1] > 0.0 {
        hinge_angle(d, flex, targets.dir[1])
    } else {
        0.0
    };
    let h1 = clamp(Dof::Hinge1, wrap(abs1));
    // Sideways deviation: a hinge segment's angle out of its joint's flexion plane, toward
    // the hinge axis as the right hand has it (on a finger the radial side), so that mirror
    // images report the same angles: the palm frame is left-handed on a right hand. The
    // middle phalanx deviates about its joint's dorsopalmar axis and carries the next joint
    // with it, so the distal joint's angles are measured in the middle phalanx's frame.
    let side = if f.cross(r).dot(n) < 0.0 {
        hinge
    } else {
        -hinge
    };
    // Each turn's sine and cosine once, for both vectors of the pair it turns; a deviation
    // within its limits has its sine already (the dot product it was measured from).
    let (s1, c1) = h1.sin_cos();
    let (bent, flex1) = (c1 * d + s1 * flex, c1 * flex - s1 * d);
    let sin_v1 = if targets.weight[1] > 0.0 {
        targets.dir[1].dot(side).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let v1 = sin_v1.asin();
    let (sv1, cv1) = deviation(clamp(Dof::Deviation1, v1), v1, sin_v1);
    let (middle, side1) = (cv1 * bent + sv1 * side, cv1 * side - sv1 * bent);
    let (h2, sin_v2) = if targets.weight[2] > 0.0 {
        let t = targets.dir[2];
        (hinge_angle(middle, flex1, t), t.dot(side1).clamp(-1.0, 1.0))
    } else {
        (0.0, 0.0)
    };
    let h2 = clamp(Dof::Hinge2, wrap(h2));
    let v2 = sin_v2.asin();
    let (sv2, cv2) = deviation(clamp(Dof::Deviation2, v2), v2, sin_v2);
    report.angles[fi][Dof::Cupping.index()] = cupping;

    // The clamped user finger: joint positions relative to its base joint.
    let seg = [d, middle, cv2 * bend(middle, flex1, h2) + sv2 * side1];
    let mut joint = [Vec3::ZERO; 4];
    for k in 0..3 {
        joint[k + 1] = joint[k] + len[k] * seg[k];
    }

    // The avatar's bones along it.
    let fr = &rest.fingers[fi];
    let mut chain_rot = Quat::IDENTITY;
    for i in 0..fr.count {
        let b = fr.bones[i]?;
        let end = if i + 1 < fr.count {
            fr.bones[i + 1]?.slot
        } else {
            3
        };
        let span = (joint[end] - joint[b.slot])
            .try_normalize()
            .unwrap_or(seg[b.slot]);
        let q = if i == 0 {
            frame_rotation(b.dir, b.hinge, span, hinge)?
        } else {
            // Bend about the rest hinge, after tilting out of the flexion plane toward it:
            // R_hinge(theta) R_side(phi) dir = cos phi (cos theta dir + sin theta flex)
            //   + sin phi hinge, with R_side about dir x hinge.
            let w = chain_rot.inverse() * span;
            let bent = hinge_rotation(b.hinge, w.dot(b.dir), w.dot(b.flex));
            let tilt = w.dot(b.hinge).clamp(-1.0, 1.0);
            if tilt.abs() > SIDE_EPSILON {
                // dir x hinge = -flex (rest axes are orthonormal).
                bent * hinge_rotation(-b.flex, (1.0 - tilt * tilt).sqrt(), tilt)
            } else {
                bent
            }
        };
        chain_rot = (chain_rot * q).normalize();
        out[fi * 3 + b.slot] = q;
    }
    out[fi * 3..fi * 3 + 3]
        .iter()
        .all(|q| q.is_finite())
        .then_some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hinge_rotation_turns_by_atan2_without_trigonometry() {
        let axis = Vec3::new(1.0, 2.0, -0.5).normalize();
        for k in -400..=400 {
            let a = k as f32 * (core::f32::consts::PI / 400.0);
            for r in [1e-3_f32, 0.7, 1.0] {
                let (x, y) = (r * a.cos(), r * a.sin());
                let q = hinge_rotation(axis, x, y);
                let want = Quat::from_axis_angle(axis, y.atan2(x));
                assert!(q.dot(want).abs() > 1.0 - 1e-6, "angle {a}: {q} vs {want}");
            }
        }
        // A half turn either way, and no direction at all.
        let half = Quat::from_axis_angle(axis, core::f32::consts::PI);
        assert!(hinge_rotation(axis, -1.0, 0.0).dot(half).abs() > 1.0 - 1e-6);
        assert!(hinge_rotation(axis, -1.0, -0.0).dot(half).abs() > 1.0 - 1e-6);
        assert_eq!(hinge_rotation(axis, 0.0, 0.0), Quat::IDENTITY);
        assert!(hinge_rotation(axis, f32::NAN, 1.0).is_nan());
    }

    #[test]
    fn palm_frame_is_right_handed_per_side_and_rejects_degenerate() {
        // A right hand palm-down with fingers along -X (the debug robot's rest).
        let w = Vec3::ZERO;
        let (i, l, m) = (
            Vec3::new(-0.1, 0.0, 0.02),
            Vec3::new(-0.1, 0.0, -0.05),
            Vec3::new(-0.1, 0.0, 0.0),
        );
        let fr = palm_frame(Side::Right, w, i, l, m).unwrap();
        assert!(fr.z_axis.abs_diff_eq(Vec3::NEG_Y, 1e-6), "{}", fr.z_axis);
        let mirror = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
        let fl = palm_frame(Side::Left, w, mirror(i), mirror(l), mirror(m)).unwrap();
        assert!(fl.z_axis.abs_diff_eq(Vec3::NEG_Y, 1e-6), "{}", fl.z_axis);
        // Mirror images: (f, r, n) is left-handed on a right hand, right-handed on a left.
        assert!((fr.determinant() + 1.0).abs() < 1e-5);
        assert!((fl.determinant() - 1.0).abs() < 1e-5);
        assert!(palm_frame(Side::Right, w, w, w, w).is_none());
        // Collinear palm.
        let c = |x: f32| Vec3::new(x, 0.0, 0.0);
        assert!(palm_frame(Side::Right, w, c(0.1), c(0.3), c(0.2)).is_none());
    }
}
